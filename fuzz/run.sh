#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, in $FUZZ_BUILD) and runs
# each for FUZZ_SECONDS, one after the other:
#   FUZZ_SECONDS=300 bash fuzz/run.sh [target...]     (targets: text_reader gzip analysis_json ros1_bag mcap binary_reader ulog sample_stream
#   recording_manifest line_framer frame_decoder)
# Each starts from its seeds (fuzz/corpus/TARGET, read only) and the inputs it
# found before; new inputs go to $FUZZ_WORK/corpus/TARGET, never into the
# repository. A crash, sanitizer report, leak, timeout or oversized
# allocation stops the run: the reproducer is saved in $FUZZ_WORK/crashes/
# and its path printed, and the script exits 1. FUZZ_SEED fixes libFuzzer's
# random seed (0, the default: a new one each run).
set -euo pipefail
cd "$(dirname "$0")/.."
SECS=${FUZZ_SECONDS:-300}
BUILD=${FUZZ_BUILD:-build-fuzz}
WORK=${FUZZ_WORK:-$BUILD/work}
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(text_reader gzip analysis_json ros1_bag mcap binary_reader ulog sample_stream
  recording_manifest line_framer frame_decoder)

cmake -S . -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCUBECAL_FUZZ=ON -DCUBECAL_WERROR=ON >/dev/null
cmake --build "$BUILD" -j "${JOBS:-$(nproc)}" >/dev/null

status=0
for t in "${TARGETS[@]}"; do
  corpus="$WORK/corpus/$t" crashes="$WORK/crashes/$t" log="$WORK/$t.log"
  mkdir -p "$corpus" "$crashes"
  dict=()
  [ -f "fuzz/$t.dict" ] && dict=(-dict="fuzz/$t.dict")
  # The real bags are seeds too (read only), when the shared data are there.
  seeds=("fuzz/corpus/$t")
  [ $t = ros1_bag ] && [ -d ../shared/data/rosbag/ros1 ] && seeds+=(../shared/data/rosbag/ros1)
  [ $t = mcap ] && [ -d ../shared/data/rosbag/ros2-mcap ] && seeds+=(../shared/data/rosbag/ros2-mcap)
  [ $t = ulog ] && [ -d ../shared/data/px4 ] && seeds+=(../shared/data/px4)
  start=$(date +%s)
  # -malloc_limit_mb: no single allocation of more than 512 MB (an input is a
  # few kB); -timeout: 10 s for one input.
  if ASAN_OPTIONS=detect_leaks=1 "$BUILD/bin/fuzz_$t" "$corpus" "${seeds[@]}" "${dict[@]}" \
      -max_total_time="$SECS" -seed="${FUZZ_SEED:-0}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 \
      -artifact_prefix="$crashes/" -print_final_stats=1 >"$log" 2>&1; then
    result=ok
  else
    result=FAILED
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  echo "fuzz $t: $result, ${execs:-?} executions in $(( $(date +%s) - start )) s," \
    "corpus $(find "$corpus" -type f | wc -l) found + $(find "fuzz/corpus/$t" -type f | wc -l) seeds (log: $log)"
  if [ $result = FAILED ]; then
    grep -E "ERROR|runtime error|finding|SUMMARY" "$log" | head -5 | sed 's/^/  /'
    grep -o "Test unit written to .*" "$log" | sed 's/^Test unit written to /  reproducer: /'
    echo "  replay: $BUILD/bin/fuzz_$t REPRODUCER"
  fi
done
exit $status
