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
# under_memory_limit <args...>: check_usage <args...> under a 1 GB address-space limit, where
# a memory refusal must happen before any work. A sanitizer build cannot start under the limit
# (AddressSanitizer reserves terabytes of address space): there the check is not made, and says
# so; the Release pass makes it. (A failure inside the subshell sets its own `fail`: its exit
# status carries it out.)
under_memory_limit() {
  if (ulimit -v 1000000 && "$bin" --version >/dev/null 2>&1); then
    (ulimit -v 1000000 && check_usage "$@"; exit "$fail") || fail=1
  else
    echo "note: $bin does not start under ulimit -v (a sanitizer build): memory refusal not checked"
  fi
}
