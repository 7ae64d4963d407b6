"""Out of memory is a MemoryError, not the end of the interpreter: a failed
allocation on a thread of an OpenMP parallel region called std::terminate."""
import os
import pathlib
import subprocess
import sys
import textwrap

import pytest

resource = pytest.importorskip("resource")

# In a child process: one small run, then save() and run() under address-space limits from
# the process's current size up, 1 MiB apart, until each succeeds. Every tighter limit must
# give MemoryError, and the child must live to print what each try gave.
CHILD = textwrap.dedent(r"""
    import pathlib, resource, sys
    import cmcsurf

    out = pathlib.Path(sys.argv[1])
    result = cmcsurf.run("G", 0.5, 32, 0.05, max_steps=2, threads=2)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)

    def size():
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024

    def tries(name, call):
        got = []
        for mib in range(256):
            resource.setrlimit(resource.RLIMIT_AS, (size() + (mib << 20), hard))
            try:
                call(mib)
                got.append("ok")
            except MemoryError:
                got.append("MemoryError")
            finally:
                resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
            if got[-1] == "ok":
                break
        print(name, " ".join(got), flush=True)

    tries("save", lambda mib: result.save(out / f"save{mib}"))
    tries("run", lambda mib: cmcsurf.run("G", 0.5, 64, 0.05, max_steps=1, threads=2))
""")


def test_out_of_memory_raises_memory_error_and_the_interpreter_lives(tmp_path):
    if os.environ.get("ASAN_OPTIONS") is not None or "asan" in os.environ.get("LD_PRELOAD", ""):
        pytest.skip("AddressSanitizer reserves more address space than any limit here allows")
    env = dict(os.environ, OMP_NUM_THREADS="2")
    child = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path)], capture_output=True,
                           text=True, env=env, timeout=600)
    assert child.returncode == 0, f"the interpreter died ({child.returncode}):\n{child.stderr}"
    lines = dict(line.split(" ", 1) for line in child.stdout.splitlines())
    for name in ("save", "run"):
        outcomes = lines[name].split()
        assert outcomes[-1] == "ok", (name, outcomes)
        # The limit did bite: at least the tightest one failed, each failure a MemoryError.
        assert outcomes[:-1] and set(outcomes[:-1]) == {"MemoryError"}, (name, outcomes)
    # The folder of the save that succeeded is whole.
    saved = sorted(tmp_path.glob("save*"), key=lambda p: int(p.name[4:]))
    assert (saved[-1] / "report.json").is_file()
