#!/usr/bin/env bash
# Runs the libFuzzer targets, one per core at a time, each for a fixed time, and fails on any finding
# (crash, sanitizer report, timeout of one input, memory above the limit).
#   fuzz/run.sh BUILD_DIR [SECONDS=60] [TARGET...]   (targets: scene_json mgf obj ply solution)
# Corpora start from scenes/ (JSON and MGF), fuzz/seeds/ (OBJ, PLY, a small .ghrs) and every
# regression input in tests/fuzz_regressions/<target>/; findings are kept in BUILD_DIR/fuzz-findings/
# (copy one into tests/fuzz_regressions/<target>/ so the test suite replays it for ever).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
secs=${2:-60}
shift $(( $# >= 2 ? 2 : 1 ))
targets=("$@")
all=(scene_json mgf obj ply solution)
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
findings="$build/fuzz-findings"
mkdir -p "$findings"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One target per core at a time (CI has two): each fuzzer is a single process, so running them side
# by side shortens the whole run (five targets: three rounds instead of five) and no target's own time.
jobs=$(nproc 2>/dev/null || echo 1)
fuzz_one() {
  local t=$1 corpus="$work/$1" log="$work/$1.log" rc execs cov
  mkdir -p "$corpus"
  case $t in
    scene_json) cp "$root"/scenes/*.json "$corpus"/ ;;
    mgf) cp "$root"/scenes/mgf/*.mgf "$corpus"/ ;;
    *) cp "$root"/fuzz/seeds/"$t"/* "$corpus"/ ;;  # obj, ply, solution (names checked below)
  esac
  cp "$root"/tests/fuzz_regressions/"$t"/* "$corpus"/ 2>/dev/null || true
  # Inputs run from a scratch folder: a fuzzed scene may name relative files, which must not exist.
  rc=0
  (cd "$work" && "$build/fuzz/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
     -print_final_stats=1 -artifact_prefix="$findings/$t-" "$corpus") >"$log" 2>&1 || rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -oE '#[0-9]+[[:space:]]+DONE[[:space:]]+cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 | sed 's/.*DONE *//' || true)
  {
    echo "fuzz_$t: exit $rc, $execs executions in ${secs} s ($(( execs / (secs > 0 ? secs : 1) )) per s), ${cov:-cov: ?}"
    [ $rc -eq 0 ] || grep -E "ERROR|SUMMARY|Test unit written|==[0-9]+==" "$log" | head -20 || true
  } >"$work/$t.summary"
  return $rc
}
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "unknown target $t (valid: ${all[*]})" >&2; exit 2; }
done
failed=0
running=0
for t in "${targets[@]}"; do
  if [ $running -ge "$jobs" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ $running -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
for t in "${targets[@]}"; do cat "$work/$t.summary" 2>/dev/null || echo "fuzz_$t: no summary (the script failed)"; done
if [ $failed -ne 0 ]; then
  echo "fuzzing found problems; inputs in $findings" >&2
  exit 1
fi
