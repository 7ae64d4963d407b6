#!/usr/bin/env bash
# Interruptions beyond checkpoint_resume.sh's (docs/reliability.md, "Faults tried"): SIGTERM in
# the pre-relaxation and in a volume correction's relaxation resumes to the same bits (on the
# run's two threads, which the checkpoint keeps); a
# checkpoint of another build, and one with valid checksums but hostile contents, are refused
# with exit 2 naming the problem, changing nothing; kill -9 while the outputs are written leaves
# no report.json and nothing partial under a final name, and --resume then completes the folder
# to the uninterrupted run's bits; a second SIGTERM while the first one's checkpoint is being
# written exits at once (143) writing nothing more, and the next run removes its temporary.
set -u
bin="$1"
support="$(cd "$(dirname "$0")/../support" && pwd)"  # report_keys.py: the timing keys
export CMCSURF_BIN="$bin"  # report_keys.py reads the timing keys from its `schema --json`
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
fail=0

# Compares a resumed folder with the uninterrupted one: report (timings aside), file list,
# every field value and the mesh.
same() {
  PYTHONPATH="$support" python3 - "$1" "$2" <<'PY' || fail=1
import json, os, sys
from report_keys import differing_keys
a, b = (json.load(open(f"{d}/report.json")) for d in sys.argv[1:3])
diff = differing_keys(a, b)
assert not diff, f"{sys.argv[2]}: resumed report differs in {diff}"
assert b["resumed_from_step"] > 0, b.get("resumed_from_step")
assert b["threads"] == a["threads"], (a["threads"], b["threads"])
files = [sorted(os.listdir(d)) for d in sys.argv[1:3]]
assert files[0] == files[1], f"the folders hold {files[0]} and {files[1]}"
PY
  cmp -s <(grep -av seconds "$1/field.vti") <(grep -av seconds "$2/field.vti") ||
    { echo "FAIL: $2/field.vti differs from $1's"; fail=1; }
  for m in "$1"/surface.*; do  # the mesh, and its report less the timings
    [ -e "$m" ] || continue
    cmp -s <(grep -av seconds "$m") <(grep -av seconds "$2/$(basename "$m")") ||
      { echo "FAIL: $2/$(basename "$m") differs"; fail=1; }
  done
}

# Rewrites bytes inside checkpoint.bin's CBOR header and fixes its CRC-32: valid checksums,
# other contents. $1: file, $2: python expression mapping the header bytes `h` to new bytes of
# the same length.
patch_header() {
  python3 - "$1" "$2" <<'PY'
import re, struct, sys, zlib
path, expr = sys.argv[1:3]
b = bytearray(open(path, "rb").read())
n = struct.unpack_from("<Q", b, 16)[0]
h = bytes(b[24:24 + n])
new = eval(expr)
assert len(new) == len(h) and new != h, "the edit found nothing to change"
b[24:24 + n] = new
struct.pack_into("<I", b, 12, zlib.crc32(new))
open(path, "wb").write(b)
PY
}

refused() {  # $1: folder, $2: pattern the message must hold
  local before; before=$(md5sum "$1"/* | md5sum)
  "$bin" run --resume "$1" 2>"$work/err"
  local rc=$?
  [ $rc = 2 ] && grep -q -- "$2" "$work/err" ||
    { echo "FAIL: $1: exit $rc, no '$2' in:"; cat "$work/err"; fail=1; }
  [ "$before" = "$(md5sum "$1"/* | md5sum)" ] ||
    { echo "FAIL: a refused resume changed $1"; fail=1; }
}

# --- Stages: 40 pre-relaxation steps so that a signal can land in them (16^3, 1 s a run).
# Two threads, which the bare --resume must take from the checkpoint (OpenMP's sums round
# differently on another count); passive waiting, as ctest runs two tests at once.
export OMP_WAIT_POLICY=PASSIVE
args=(run --paper --surface P --volume-fraction 0.3 --grid 16 --epsilon 0.04 --tol 1e-8
      --prerelax-steps 40 --prerelax-epsilon-factor 1.5 --threads 2 --no-preview --no-report)
"$bin" "${args[@]}" --quiet --out "$work/whole" || { echo "FAIL: the plain run"; exit 1; }
for stage in prerelax volume; do
  out="$work/$stage"
  "$bin" "${args[@]}" --out "$out" 2>"$out.log" &
  pid=$!
  for _ in $(seq 1 1000); do grep -q "^$stage " "$out.log" && break; sleep 0.005; done
  kill -TERM $pid
  wait $pid
  rc=$?
  [ $rc = 143 ] || { echo "FAIL: SIGTERM in $stage exited $rc"; cat "$out.log"; fail=1; }
  python3 -c "
import json; c = json.load(open('$out/report.json'))['checkpoint']
assert c['stage'] == '$stage' and c['grid'] == 16, c
" || { echo "FAIL: not stopped in $stage"; fail=1; }
  if [ $stage = prerelax ]; then
    # Another build's checkpoint (its commit differs): refused, naming both builds.
    cp -r "$out" "$work/other-build"
    patch_header "$work/other-build/checkpoint.bin" \
      're.sub(rb"\(commit ([^,]+),", lambda m: b"(commit " + b"0" * len(m[1]) + b",", h, count=1)'
    refused "$work/other-build" \
      "written by cmcsurf [0-9.]* (commit 0*, .*; this is cmcsurf [0-9.]* (commit [0-9a-f]"
    # Valid checksums, hostile contents: a parameter out of range; volume iterates in a
    # pre-relaxation (no run reaches that state).
    cp -r "$out" "$work/hostile-params"
    patch_header "$work/hostile-params/checkpoint.bin" \
      're.sub(rb"gepsilon\xfb.{8}", b"gepsilon\xfb" + struct.pack(">d", 2.0), h, count=1,
              flags=re.S)'
    refused "$work/hostile-params" "parameter out of range: --epsilon: got 2"
    cp -r "$out" "$work/hostile-state"
    patch_header "$work/hostile-state/checkpoint.bin" \
      'h.replace(b"rvolume_constrained\xf4", b"rvolume_constrained\xf5")'
    refused "$work/hostile-state" "cannot continue it: volume iterates before the volume stage"
  fi
  "$bin" run --resume "$out" --quiet || { echo "FAIL: resume from $stage"; fail=1; }
  same "$work/whole" "$out"
done

# --- kill -9 while the outputs are written (64^3, 45 steps, an STL mesh after field.vti), then
# --resume from the last periodic checkpoint; and a second signal during a checkpoint (96^3
# with extrapolation: 28 MB, about 50 ms to write). Driven from Python to react within 1 ms.
python3 - "$bin" "$work" <<'PY' || fail=1
import glob, json, os, signal, subprocess, sys, time
bin, work = sys.argv[1:3]
failed = []
def check(ok, what):
    if not ok:
        failed.append(what)
        print("FAIL:", what)
def wait_for(cond, proc, limit=120):
    t0 = time.time()
    while not cond():
        if proc.poll() is not None or time.time() - t0 > limit:
            return False
        time.sleep(0.001)
    return True

args = [bin, "run", "--paper", "--surface", "G", "--grid", "64", "--max-steps", "40",
        "--constrain", "mass", "--mesh", "stl",
        "--no-preview", "--no-report", "--checkpoint-every", "0.2", "--quiet"]
subprocess.run(args + ["--out", f"{work}/out-whole"], check=True)
out = f"{work}/out-killed"
p = subprocess.Popen(args + ["--out", out])
# history.csv is the second output: from then until report.json the outputs are being written.
check(wait_for(lambda: os.path.exists(f"{out}/history.csv"), p), "no history.csv appeared")
p.kill()
p.wait()
names = sorted(os.listdir(out))
check("report.json" not in names, f"kill -9 during the outputs left report.json: {names}")
check("checkpoint.bin" in names, f"the periodic checkpoint is gone: {names}")
if "field.vti" in names:  # only ever complete under its final name
    check(open(f"{out}/field.vti", "rb").read().rstrip().endswith(b"</VTKFile>"),
          "partial field.vti")
r = subprocess.run([bin, "run", "--resume", out], capture_output=True, text=True)
check(r.returncode == 0, f"resume after kill -9 during the outputs: {r.stderr}")
left = [n for n in os.listdir(out) if ".cmcsurf-tmp." in n or n == "checkpoint.bin"]
check(not left, f"left after the resume: {left}")
print("killed while writing:", names)

out = f"{work}/twice"
p = subprocess.Popen([bin, "run", "--paper", "--surface", "G", "--grid", "96", "--extrapolate",
                      "--checkpoint-every", "0.5", "--no-preview", "--no-report", "--quiet",
                      "--out", out])
temporary = lambda: glob.glob(f"{out}/checkpoint.bin.cmcsurf-tmp.*")
# A periodic checkpoint in place and none being written: then the signal's is the next.
check(wait_for(lambda: os.path.exists(f"{out}/checkpoint.bin") and not temporary(), p),
      "no periodic checkpoint")
before = open(f"{out}/checkpoint.bin", "rb").read()
p.send_signal(signal.SIGTERM)
check(wait_for(temporary, p), "the first signal's checkpoint was never being written")
p.send_signal(signal.SIGTERM)
t0 = time.time()
rc = p.wait()
exit_seconds = time.time() - t0
check(rc == 143, f"two SIGTERMs: exit {rc}")
names = sorted(os.listdir(out))
check("report.json" not in names and "history.csv" not in names,
      f"the second signal's exit wrote the graceful stop's files: {names}")
print(f"second SIGTERM: exit {rc} after {exit_seconds:.3f} s; left {names}")
if temporary():  # it came while the temporary was open: the last checkpoint is unchanged
    check(open(f"{out}/checkpoint.bin", "rb").read() == before, "checkpoint.bin changed")
    r = subprocess.Popen([bin, "run", "--resume", out], stderr=subprocess.PIPE, text=True)
    line = ""
    for line in r.stderr:
        if line.startswith("resuming"):
            break
    r.kill()
    r.wait()
    check(not temporary(), "the resume kept the interrupted checkpoint's temporary")
    check(line.startswith("resuming"), "the resume did not continue the older checkpoint")
sys.exit(1 if failed else 0)
PY
same "$work/out-whole" "$work/out-killed"

[ $fail = 0 ] && echo "checkpoint_resume_stages: all passed"
exit $fail
