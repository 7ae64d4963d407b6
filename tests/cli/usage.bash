# Sourced by the bad-input CLI tests (not a test itself: CTest registers only *.sh).
# check_usage <out name> <option named in message> <args...>: the command, given
# --out "$work/<out name>", must exit 2, name the option on stderr and write nothing.
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
check_usage() {
  local out="$work/$1" opt="$2"; shift 2
  "$bin" "$@" --out "$out" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  if [ "$rc" -ne 2 ]; then echo "FAIL: '$*' exited $rc, want 2"; cat "$work/stderr"; fail=1; fi
  if ! grep -q -- "$opt" "$work/stderr"; then
    echo "FAIL: '$*' message does not name $opt:"; cat "$work/stderr"; fail=1
  fi
  # Nothing at all under the output name: no file, no report beside it, no temporary.
  if compgen -G "$out*" >/dev/null; then echo "FAIL: '$*' wrote $out*"; fail=1; rm -rf "$out"*; fi
}
