#!/usr/bin/env bash
# Whose folder (docs/reliability.md, "Whose folder"): run and sweep write only into a new,
# empty or cmcsurf folder (a foreign one is refused with exit 2 and left as it was, unless
# --force), never into /, one writer at a time (a second is refused at once), only our own
# temporaries are cleared, an unwritable folder is refused before the solve, the printed resume
# command survives a hostile folder name, a resumed sweep never runs a program sweep.json
# names, a sweep's members have one folder each, and a new sweep clears an old one's members.
set -u
bin=$(realpath "$1")
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'kill -9 $(jobs -p) 2>/dev/null; umount "$work/ro" 2>/dev/null; rm -rf "$work"' EXIT
cd "$work" || exit 1
fail=0
quick=(--grid 16 --epsilon 0.04 --quiet --no-preview --no-report)

# A foreign folder: refused, named, and every file in it kept as it was.
mkdir d
echo '{"mine":1}' >d/report.json
echo x >d/surface.obj
echo thesis >d/thesis.tmp.99999.1
"$bin" run --paper --grid 16 --dt-factor 1e300 --out d 2>err
rc=$?
[ "$rc" = 2 ] || { echo "FAIL: a foreign folder: exit $rc, want 2"; cat err; fail=1; }
grep -q "'d'.*not empty.*not written by cmcsurf.*--force" err ||
  { echo "FAIL: the message: $(cat err)"; fail=1; }
[ "$(cat d/report.json)" = '{"mine":1}' ] && [ "$(cat d/surface.obj)" = x ] &&
  [ -e d/thesis.tmp.99999.1 ] && [ ! -e d/.cmcsurf ] ||
  { echo "FAIL: the foreign folder changed: $(ls -a d)"; fail=1; }
"$bin" sweep --paper --surface G --volume-fractions 0.5 "${quick[@]}" --out d 2>err
[ $? = 2 ] && [ "$(cat d/report.json)" = '{"mine":1}' ] ||
  { echo "FAIL: sweep into a foreign folder"; cat err; fail=1; }
# --force: the user said so; files with our output names are replaced, their others stay.
"$bin" run --paper "${quick[@]}" --out d --force 2>err || { echo "FAIL: --force"; cat err; fail=1; }
[ -e d/.cmcsurf ] && [ -e d/thesis.tmp.99999.1 ] && [ ! -e d/surface.obj ] ||
  { echo "FAIL: --force: $(ls -a d)"; fail=1; }

# Our own folder: a rerun replaces our outputs, keeps a user's file that looks like a
# temporary, and removes our own stale temporary.
"$bin" run --paper "${quick[@]}" --out ours || { echo "FAIL: a new folder"; fail=1; }
echo user >ours/thesis.tmp.99999.1
echo partial >ours/field.vti.cmcsurf-tmp.2147483647.0
"$bin" run --paper "${quick[@]}" --surface P --out ours || { echo "FAIL: a rerun"; fail=1; }
[ -e ours/thesis.tmp.99999.1 ] || { echo "FAIL: a user's thesis.tmp.99999.1 was removed"; fail=1; }
[ ! -e ours/field.vti.cmcsurf-tmp.2147483647.0 ] ||
  { echo "FAIL: our stale temporary kept"; fail=1; }
python3 -c "import json; assert json.load(open('ours/report.json'))['surface'] == 'P'" || fail=1
# An empty folder is fine; a file is not a folder.
mkdir empty
"$bin" run --paper "${quick[@]}" --out empty || { echo "FAIL: an empty folder"; fail=1; }
echo x >afile
"$bin" run --paper "${quick[@]}" --out afile 2>err
[ $? = 2 ] && [ "$(cat afile)" = x ] || { echo "FAIL: --out a file"; cat err; fail=1; }

# The root of the file system, even with --force: nothing written there.
"$bin" run --paper "${quick[@]}" --out / --force 2>err
[ $? = 2 ] && grep -q "root of the file system" err || { echo "FAIL: --out /"; cat err; fail=1; }
[ ! -e /.cmcsurf ] || { echo "FAIL: /.cmcsurf written"; fail=1; }

# One writer: a second run into a folder being written is refused at once, naming the folder,
# and the first one's outputs are its own.
"$bin" run --paper --surface G --grid 32 --quiet --no-report --out busy 2>first.err &
first=$!
for _ in $(seq 1 500); do [ -e busy/.cmcsurf ] && break; sleep 0.01; done
start=$(date +%s)
"$bin" run --paper --surface P --grid 32 --quiet --out busy 2>err
rc=$?
[ "$rc" = 1 ] && grep -q "another cmcsurf process.*is writing this folder" err ||
  { echo "FAIL: a second writer: exit $rc"; cat err; fail=1; }
[ $(($(date +%s) - start)) -le 5 ] ||
  { echo "FAIL: the second writer was not refused at once"; fail=1; }
wait $first || { echo "FAIL: the first writer"; cat first.err; fail=1; }
python3 -c "import json; assert json.load(open('busy/report.json'))['surface'] == 'G'" || fail=1
# The same with a lock held by another tool (util-linux flock), and for a sweep.
if command -v flock >/dev/null; then
  flock ours/.cmcsurf sleep 3 &
  sleep 0.3
  "$bin" run --paper "${quick[@]}" --out ours 2>err
  [ $? = 1 ] || { echo "FAIL: a locked folder was written"; fail=1; }
  mkdir -p sw &&
    "$bin" sweep --paper --surface G --volume-fractions 0.5 "${quick[@]}" --out sw >/dev/null 2>&1
  flock sw/.cmcsurf sleep 3 &
  sleep 0.3
  "$bin" sweep --paper --surface G --volume-fractions 0.5 "${quick[@]}" --out sw 2>err
  [ $? = 1 ] && grep -q "another cmcsurf process" err ||
    { echo "FAIL: a locked sweep folder"; cat err; fail=1; }
  flock sw/G_0.50/.cmcsurf sleep 3 &
  sleep 0.3
  "$bin" run --paper "${quick[@]}" --out sw/G_0.50 2>/dev/null
  [ $? = 1 ] || { echo "FAIL: a locked member folder"; fail=1; }
  wait
fi

# A folder that cannot be written is refused before the solve (a read-only tmpfs; root only).
mkdir ro
if mount -t tmpfs -o ro,size=64k tmpfs ro 2>/dev/null; then
  start=$(date +%s)
  "$bin" run --paper --grid 32 --quiet --out ro/run 2>err
  rc=$?
  [ "$rc" = 1 ] && grep -q "ro/run" err || { echo "FAIL: read-only: exit $rc"; cat err; fail=1; }
  [ $(($(date +%s) - start)) -le 5 ] ||
    { echo "FAIL: read-only refused only after the solve"; fail=1; }
  umount ro
else
  echo "note: no read-only tmpfs here; that case is not checked"
fi

# The printed resume command is quoted: pasted into a shell it resumes and runs nothing else.
# --tol 1e-7: the run goes on for 1.5 s after its first relax line in the Release build, time
# enough to stop it there, and the resumed rest takes 7 s under the sanitizers (20 s at 1e-9).
hostile='ck x; touch PWNED #'
"$bin" run --paper --surface P --volume-fraction 0.3 --grid 16 --epsilon 0.04 --tol 1e-7 \
  --no-preview --no-report --out "$hostile" 2>sig.log &
pid=$!
for _ in $(seq 1 1000); do grep -q "^relax " sig.log 2>/dev/null && break; sleep 0.01; done
kill -TERM $pid
wait $pid
line=$(sed -n 's/^resume with: //p' sig.log)
[ -n "$line" ] || { echo "FAIL: no resume line"; cat sig.log; fail=1; }
(eval "$line --quiet" >/dev/null 2>&1)
[ ! -e PWNED ] || { echo "FAIL: the pasted resume command ran 'touch PWNED'"; fail=1; }
[ -e "$hostile/report.json" ] && [ ! -e "$hostile/checkpoint.bin" ] ||
  { echo "FAIL: the pasted resume command did not finish the run: $line"; fail=1; }

# sweep --resume never runs what sweep.json names (outputs.python, outputs.plot_script).
"$bin" sweep --paper --surface G --volume-fractions 0.5 "${quick[@]}" --out sweep1 2>/dev/null ||
  { echo "FAIL: a small sweep"; fail=1; }
printf '#!/bin/sh\ntouch %s/RAN\n' "$work" >evil.sh
chmod +x evil.sh
python3 - sweep1/sweep.json "$work/evil.sh" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["complete"] = False
s["outputs"]["python"] = sys.argv[2]
s["outputs"]["plot_script"] = sys.argv[2]
json.dump(s, open(sys.argv[1], "w"))
PY
"$bin" sweep --resume sweep1 --quiet 2>err
[ ! -e RAN ] || { echo "FAIL: sweep --resume ran the program sweep.json named"; fail=1; }
grep -q "evil" sweep1/sweep.json && { echo "FAIL: sweep.json still names the program"; fail=1; }

# Members with one name are refused (one folder each); a new sweep into an old sweep's folder
# clears the old members it does not have, but keeps a member folder holding a user's file.
"$bin" sweep --paper --surface G,G --volume-fractions 0.5 "${quick[@]}" --out dup 2>err
[ $? = 2 ] && grep -q "two members named 'G_0.50'" err && [ ! -e dup ] ||
  { echo "FAIL: --surface G,G"; cat err; fail=1; }
"$bin" sweep --paper --surface G --volume-fractions 0.5,0.5 "${quick[@]}" --out dup 2>err
[ $? = 2 ] && [ ! -e dup ] || { echo "FAIL: --volume-fractions 0.5,0.5"; cat err; fail=1; }
"$bin" sweep --paper --surface P --volume-fractions 0.4,0.5 "${quick[@]}" --no-plot \
  --out old 2>/dev/null ||
  { echo "FAIL: the old sweep"; fail=1; }
echo mine >old/P_0.40/notes.txt
"$bin" sweep --paper --surface G --volume-fractions 0.5 "${quick[@]}" --no-plot --out old 2>err ||
  { echo "FAIL: the new sweep"; cat err; fail=1; }
[ ! -e old/P_0.50 ] || { echo "FAIL: the old member P_0.50 is still there: $(ls old)"; fail=1; }
[ -e old/P_0.40/notes.txt ] && [ ! -e old/P_0.40/report.json ] ||
  { echo "FAIL: the old member with a user's file: $(ls -a old/P_0.40)"; fail=1; }
grep -q "kept the earlier sweep's member folder .*P_0.40" err ||
  { echo "FAIL: no note naming the kept folder: $(cat err)"; fail=1; }

[ "$fail" = 0 ] && echo "out_folder: all checks passed"
exit "$fail"
