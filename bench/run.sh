#!/usr/bin/env bash
# make bench: micro-benchmarks, then the end-to-end timing of the issue:
# a 72 h x 10 Hz, 6-channel record through `cubecal dev --stat oadev --taus log:20`.
set -euo pipefail
BUILD=${1:-build}
OUT=${BENCH_OUT:-bench-out}
mkdir -p "$OUT"
echo "== Google Benchmark: OADEV kernel vs streaming read (median of 5)"
"$BUILD/bin/bench_oadev" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_display_aggregates_only=true | grep -E "median|Benchmark|---"

REC="$OUT/imu_72h_10hz_6ch.csv"
if [ ! -s "$REC" ]; then
  echo "== generating $REC"
  "$BUILD/bin/make_record" "$REC" 72 10 6 1
fi
SIZE=$(stat -c %s "$REC")
echo "== end to end: cubecal dev --stat oadev --taus log:20 on 6 channels ($((SIZE / 1000000)) MB)"
times=()
for i in 1 2 3 4 5; do
  s=$(date +%s.%N)
  "$BUILD/bin/cubecal" dev "$REC" --stat oadev --taus log:20 --format json > "$OUT/e2e.json"
  e=$(date +%s.%N)
  times+=("$(echo "$e - $s" | bc -l)")
done
printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {printf "  runs: "; for(i=1;i<=NR;i++) printf "%.3f ", a[i]; printf "\n  median: %.3f s\n", a[int((NR+1)/2)]}'
echo "== reader: Google Benchmark read_table on a 2.59 M-row x 8-column CSV (median of 5)"
"$BUILD/bin/bench_reader" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true --benchmark_display_aggregates_only=true | grep -E "median|Benchmark|---"
echo "== reader in the tool: dev --no-ci on 1 channel, one tau"
times=()
for i in 1 2 3 4 5; do
  s=$(date +%s.%N)
  "$BUILD/bin/cubecal" dev "$REC" --columns c1 --no-ci --taus 1 --format csv > /dev/null
  e=$(date +%s.%N)
  times+=("$(echo "$e - $s" | bc -l)")
done
printf '%s\n' "${times[@]}" | sort -g | awk -v size="$SIZE" '{a[NR]=$1} END {m=a[int((NR+1)/2)]; printf "  median %.3f s -> %.0f MB/s\n", m, size/m/1e6}'

IMU="$OUT/imu_72h_10hz_paper.csv"
if [ ! -s "$IMU" ]; then
  echo "== generating $IMU (gyro + magnetometer + temperature)"
  "$BUILD/bin/make_record" "$IMU" 72 10 imu 1
fi
echo "== end to end: cubecal analyze, 72 h x 10 Hz, 3 gyro + 3 magnetometer + temperature"
times=()
for i in 1 2 3 4 5; do
  s=$(date +%s.%N)
  "$BUILD/bin/cubecal" analyze "$IMU" --columns gx,gy,gz,mx,my,mz --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss \
    --temp-col temp > "$OUT/analyze.txt"
  e=$(date +%s.%N)
  times+=("$(echo "$e - $s" | bc -l)")
done
printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {printf "  runs: "; for(i=1;i<=NR;i++) printf "%.3f ", a[i]; printf "\n  median: %.3f s\n", a[int((NR+1)/2)]}'

echo "== the stage table: each stage of dev and analyze beside this machine's limits, and AllanTools (bench/limits.sh)"
BENCH_OUT="$OUT" bash "$(dirname "$0")/limits.sh" "$BUILD"

BENCH_OUT="$OUT" bash "$(dirname "$0")/memory.sh" "$BUILD"

echo "== temperature stage of analyze: the least-squares passes of one 72 h x 10 Hz channel (min/median/max of 5)"
"$BUILD/bin/bench_temperature" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_display_aggregates_only=true | grep -E "_min|_median|_max|Benchmark|---"

echo "== simulator: Google Benchmark (median of 5; items = axis samples)"
"$BUILD/bin/bench_simulator" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_display_aggregates_only=true | grep -E "median|Benchmark|---"

echo "== dynamic Allan deviation: 72 h x 10 Hz, 1 h windows every 60 s, log:10 (target < 2 s; min/median/max of 5)"
"$BUILD/bin/bench_davar" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_display_aggregates_only=true | grep -E "_min|_median|_max|Benchmark|---"

echo "== GMWM: WN+2*GM+RW on 1e6 samples, the fit (target < 2 s) and 200 bootstrap replicates (target < 30 s); min/median/max of 5"
"$BUILD/bin/bench_gmwm" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_display_aggregates_only=true | grep -E "_min|_median|_max|Benchmark|---"

bash "$(dirname "$0")/stream.sh" "$BUILD"
bash "$(dirname "$0")/stream_formats.sh" "$BUILD"

BENCH_OUT="$OUT" bash "$(dirname "$0")/twin.sh" "$BUILD"

echo "== cubecal demo (72 h simulated in memory, written, analyzed; target < 10 s)"
s=$(date +%s.%N)
"$BUILD/bin/cubecal" demo --out "$OUT/demo" > "$OUT/demo.txt"
e=$(date +%s.%N)
echo "  $(echo "$e - $s" | bc -l | xargs printf '%.2f') s"

if [ -f "$BUILD/python/cubecal/__init__.py" ]; then
  PYTHONPATH="$BUILD/python" BENCH_OUT="$OUT" /usr/bin/python3 "$(dirname "$0")/python_speed.py" "$BUILD" 5
  PYTHONPATH="$BUILD/python" /usr/bin/python3 "$(dirname "$0")/psd_speed.py" 5
fi

echo "== cubecal record: 10 kHz x 10 channels of text from a pipe, CPU of the recorder and of cat (bench/record_throughput.sh)"
bash "$(dirname "$0")/record_throughput.sh" "$BUILD/bin/cubecal" 20 3
