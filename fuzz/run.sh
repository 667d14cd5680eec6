#!/usr/bin/env bash
# Runs the libFuzzer targets, one after another, each for a fixed time, and fails on any finding
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
[ ${#targets[@]} -gt 0 ] || targets=(scene_json mgf obj ply solution)
findings="$build/fuzz-findings"
mkdir -p "$findings"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
for t in "${targets[@]}"; do
  corpus="$work/$t"
  mkdir -p "$corpus"
  case $t in
    scene_json) cp "$root"/scenes/*.json "$corpus"/ ;;
    mgf) cp "$root"/scenes/mgf/*.mgf "$corpus"/ ;;
    obj | ply | solution) cp "$root"/fuzz/seeds/"$t"/* "$corpus"/ ;;
    *) echo "unknown target $t" >&2; exit 2 ;;
  esac
  cp "$root"/tests/fuzz_regressions/"$t"/* "$corpus"/ 2>/dev/null || true
  log="$work/$t.log"
  # Inputs run from a scratch folder: a fuzzed scene may name relative files, which must not exist.
  set +e
  (cd "$work" && "$build/fuzz/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
     -print_final_stats=1 -artifact_prefix="$findings/$t-" "$corpus") >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -oE '#[0-9]+[[:space:]]+DONE[[:space:]]+cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 | sed 's/.*DONE *//')
  echo "fuzz_$t: exit $rc, $execs executions in ${secs} s ($(( execs / (secs > 0 ? secs : 1) )) per s), ${cov:-cov: ?}"
  if [ $rc -ne 0 ]; then
    failed=1
    grep -E "ERROR|SUMMARY|Test unit written|==[0-9]+==" "$log" | head -20 || true
  fi
done
if [ $failed -ne 0 ]; then
  echo "fuzzing found problems; inputs in $findings" >&2
  exit 1
fi
