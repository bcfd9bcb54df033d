#!/usr/bin/env bash
# SIGTERM or SIGINT to `report` or `export` while its Python script runs (issue 27): the signal
# goes on to the script, clothbench waits for the script to end (a second signal orphans
# nothing) and exits 143 for TERM, 130 for INT. A stand-in script (CLOTHBENCH_PYTHON) records
# the signals it gets and takes a moment to clean up, so the order of events can be checked.
# Usage: signals.sh CLOTHBENCH WORK_DIR
set -u
clothbench=$1 work=$2
source "$(dirname "$0")/expect.sh"
cat >"$work/fake-python" <<'SH'
#!/usr/bin/env bash
# stands in for python3: records each signal, ends 0.5 s after the first (its cleanup)
log=$CLOTHBENCH_SIGNAL_LOG
echo started >"$log"
got=""
trap 'echo "got TERM" >>"$log"; got=TERM' TERM
trap 'echo "got INT" >>"$log"; got=INT' INT
for _ in $(seq 300); do
  [ -n "$got" ] && { sleep 0.5; echo "cleaned up" >>"$log"; exit 1; }
  sleep 0.1
done
echo "never signalled" >>"$log"
SH
chmod +x "$work/fake-python"

# one command under a signal: send SIGNAL COUNT times, expect the status, the script told and
# finished before clothbench ended
try() {
  local cmd=$1 sig=$2 count=$3 want=$4 log=$work/$1-$2-$3.log
  CLOTHBENCH_PYTHON=$work/fake-python CLOTHBENCH_SIGNAL_LOG=$log \
    "$clothbench" "$cmd" "$work" --format obj >/dev/null 2>"$work/stderr" &
  local pid=$!
  for _ in $(seq 50); do [ -s "$log" ] && break; sleep 0.1; done
  for _ in $(seq "$count"); do kill "-$sig" "$pid"; sleep 0.1; done
  wait "$pid"
  local status=$?
  [ "$status" -eq "$want" ] || fail "$cmd, $count x SIG$sig: exit $status, expected $want"
  grep -q "got $sig" "$log" || fail "$cmd, SIG$sig: the script never got the signal: $(cat "$log")"
  grep -q "cleaned up" "$log" ||
    fail "$cmd, $count x SIG$sig: clothbench ended before its script: $(cat "$log")"
}
try report TERM 1 143
try report INT 1 130
try export TERM 2 143
try export INT 2 130

[ "$failures" -eq 0 ] || exit 1
echo "report and export pass SIGTERM and SIGINT on, wait for their script, and exit 143 or 130"
