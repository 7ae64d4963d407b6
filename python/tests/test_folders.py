"""Result.save() writes only into a folder that is new, empty or cmcsurf's, one writer at a
time, and a run that cannot fit in memory is refused before the solve (docs/reliability.md)."""
import fcntl
import json
import subprocess
import sys
import textwrap

import pytest

import cmcsurf


def test_save_refuses_a_foreign_folder_and_changes_nothing(gyroid_result, tmp_path):
    d = tmp_path / "d"
    d.mkdir()
    (d / "report.json").write_text('{"mine":1}')
    (d / "surface.obj").write_text("x")
    with pytest.raises(ValueError, match="not written by cmcsurf.*force"):
        gyroid_result.save(d)
    assert (d / "report.json").read_text() == '{"mine":1}'
    assert sorted(p.name for p in d.iterdir()) == ["report.json", "surface.obj"]
    gyroid_result.save(d, preview=False, report=False, force=True)
    assert json.loads((d / "report.json").read_text())["surface"] == "G"


def test_save_refuses_a_folder_another_process_writes(gyroid_result, tmp_path):
    d = gyroid_result.save(tmp_path / "run", preview=False, report=False)
    with open(d / ".cmcsurf") as held:
        fcntl.flock(held, fcntl.LOCK_EX)  # what a writing cmcsurf holds
        with pytest.raises(RuntimeError, match="another cmcsurf process"):
            gyroid_result.save(d, preview=False, report=False)
    gyroid_result.save(d, preview=False, report=False)  # free again


def test_a_run_too_large_for_the_memory_raises_memory_error():
    # Under a 1.5 GB address-space limit, a 1024^3 run (about 120 GB) is refused at once.
    code = textwrap.dedent("""
        import resource, cmcsurf
        resource.setrlimit(resource.RLIMIT_AS, (1500 << 20, 1500 << 20))
        try:
            cmcsurf.run(surface="G", grid=1024)
        except MemoryError as e:
            print("MemoryError:", e)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60)
    assert "MemoryError: --grid 1024" in out.stdout, out.stdout + out.stderr
    assert "RLIMIT_AS" in out.stdout
