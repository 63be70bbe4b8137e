#!/usr/bin/env bash
# The twin's cost in `analyze` (docs/twins.md, docs/performance.md): the
# 72 h x 10 Hz, 3 gyro + 3 magnetometer + temperature record analyzed with
# the default twin and without it (--composite none, the analysis before the
# twin), interleaved, RUNS each; and one channel of 1e6 samples (2.78 h at
# 100 Hz) the same way. Prints min/median/max of each and the ratios.
# Usage: bench/twin.sh [BUILD]   (RUNS=5, BENCH_OUT=bench-out)
set -euo pipefail
BUILD=${1:-build}
OUT=${BENCH_OUT:-bench-out}
RUNS=${RUNS:-5}
mkdir -p "$OUT"
IMU="$OUT/imu_72h_10hz_paper.csv"
[ -s "$IMU" ] || "$BUILD/bin/make_record" "$IMU" 72 10 imu 1 > /dev/null
ONE="$OUT/one_channel_1e6.csv"
[ -s "$ONE" ] || "$BUILD/bin/make_record" "$ONE" 2.7777777778 100 1 2 > /dev/null
# A real channel of 1e6 samples with a spectral line, when ../shared is beside the checkout.
ADIS="$(dirname "$0")/../../shared/data/imu/adis16405/run1.csv.gz"
REAL="$OUT/adis16405_run1.csv"
cases=(imu one)
if [ -s "$ADIS" ]; then
  [ -s "$REAL" ] || zcat "$ADIS" > "$REAL"
  cases+=(real)
fi
secs() {  # command...: wall seconds
  local s e
  s=$(date +%s.%N)
  "$@" > /dev/null 2>&1
  e=$(date +%s.%N)
  echo "$e - $s" | bc -l
}
stats() {  # label, seconds...
  local label=$1
  shift
  printf '%s\n' "$@" | sort -g | awk -v l="$label" '{a[NR]=$1} END {printf "  %-44s min %.3f  median %.3f  max %.3f s\n", l, a[1], a[int((NR+1)/2)], a[NR]}'
}
for case in "${cases[@]}"; do
  with=() without=()
  for ((i = 0; i < RUNS; i++)); do
    case $case in
      imu) args=("$IMU" --columns gx,gy,gz,mx,my,mz --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp) ;;
      one) args=("$ONE" --unit deg/s) ;;
      real) args=("$REAL" --columns gyro_z_dps --unit deg/s) ;;
    esac
    without+=("$(secs "$BUILD/bin/cubecal" analyze "${args[@]}" --composite none)")
    with+=("$(secs "$BUILD/bin/cubecal" analyze "${args[@]}")")
  done
  case $case in
    imu) echo "== analyze, 72 h x 10 Hz, 6 channels + temperature ($RUNS runs each, interleaved)" ;;
    one) echo "== analyze, one simulated channel of 1e6 samples at 100 Hz ($RUNS runs each, interleaved)" ;;
    real) echo "== analyze, ADIS16405 run 1 gyro z, 1e6 samples at 100 Hz with its 20 Hz line ($RUNS runs each, interleaved)" ;;
  esac
  stats "without the twin (--composite none)" "${without[@]}"
  stats "with the twin (the default)" "${with[@]}"
  mw=$(printf '%s\n' "${with[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  mo=$(printf '%s\n' "${without[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  printf '  median ratio %.2fx, median difference %+.3f s\n' "$(echo "$mw / $mo" | bc -l)" "$(echo "$mw - $mo" | bc -l)"
done
