# Shared by the command-line tests (sourced): a fresh $work folder, a failure count, and
# expect STATUS COMMAND..., which runs the command with its stdout and stderr kept in $work.
rm -rf "$work"
mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

expect() {
  local want=$1
  shift
  "$@" >"$work/stdout" 2>"$work/stderr"
  local got=$?
  [ "$got" -eq "$want" ] || fail "expected exit $want, got $got: $* ($(head -c 300 "$work/stderr"))"
}
