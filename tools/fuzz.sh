#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang-14 with ASan + UBSan) in their own build folder and runs each one.
#   tools/fuzz.sh                 every target for 300 s (the long form; the corpus grows in build-fuzz/corpus)
#   tools/fuzz.sh --ci            every target for VKVO_FUZZ_CI_SECONDS (default 5 s), two at a time
#   tools/fuzz.sh --time 60 npy   one target for 60 s
# Before fuzzing, every target replays the seeds and the kept reproducers (fuzz/regressions/<target>/). Any crash,
# sanitizer report, leak or timeout fails the script; the input that triggered it is left in build-fuzz/findings.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=300
jobs=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --ci) seconds=${VKVO_FUZZ_CI_SECONDS:-5}; jobs=${VKVO_FUZZ_JOBS:-$(nproc)} ;;
    --time) seconds=$2; shift ;;
    --jobs) jobs=$2; shift ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) targets+=("$1") ;;
  esac
  shift
done
[ ${#targets[@]} -gt 0 ] || mapfile -t targets < fuzz/targets.txt

BUILD_DIR=${FUZZ_BUILD_DIR:-build-fuzz}
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S fuzz -B "$BUILD_DIR" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 "${launcher[@]}" >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)"

seeds="$BUILD_DIR/seeds"
rm -rf "$seeds"
"$BUILD_DIR/vkvo_fuzz_seeds" fuzz/seeds "$seeds"

run_target() {
  local target=$1
  local corpus="$BUILD_DIR/corpus/$target" findings="$BUILD_DIR/findings/$target" log="$BUILD_DIR/logs/$target.log"
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  local inputs=("$seeds/$target")
  [ -d "fuzz/regressions/$target" ] && inputs+=("fuzz/regressions/$target")
  # -rss_limit_mb / -malloc_limit_mb: a parser that allocates what a header claims is a finding, not an OOM kill.
  if ! "$BUILD_DIR/vkvo_fuzz_$target" "$corpus" "${inputs[@]}" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$findings/" >"$log" 2>&1; then
    echo "fuzz: $target FAILED (log: $log, reproducer in $findings/)"
    grep -m1 -E "ERROR|runtime error|Assertion" "$log" || tail -n 20 "$log"
    return 1
  fi
  local runs
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n1)
  echo "fuzz: $target ok, ${runs:-?} executions in ${seconds} s, corpus $(find "$corpus" -type f | wc -l) inputs"
}

status=0
pids=()
for target in "${targets[@]}"; do
  run_target "$target" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
[ $status -eq 0 ] && echo "fuzz: all ${#targets[@]} targets clean" || echo "fuzz: findings (see above)"
exit $status
