#!/usr/bin/env bash
# Before/after timing of two builds on the same machine, interleaved so that
# drift in the machine's speed falls on both alike:
#   bash bench/ab.sh OLD_BIN_DIR NEW_BIN_DIR [runs]
# Each run times `dev --stat oadev --taus log:20` on the 6-channel 72 h x 10 Hz
# record and `analyze` with temperature on the 72 h gyro + magnetometer record
# (both made by make_record, as bench/run.sh does), and prints min / median /
# max per build.
set -euo pipefail
OLD=$1; NEW=$2; N=${3:-7}
OUT=${BENCH_OUT:-bench-out}
mkdir -p "$OUT"
REC="$OUT/imu_72h_10hz_6ch.csv"; IMU="$OUT/imu_72h_10hz_paper.csv"
[ -s "$REC" ] || "$NEW/make_record" "$REC" 72 10 6 1
[ -s "$IMU" ] || "$NEW/make_record" "$IMU" 72 10 imu 1
t() { local s e; s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
declare -A R
for _ in $(seq "$N"); do
  for side in OLD NEW; do
    B=${!side}
    R[$side,dev]+="$(t "$B/cubecal" dev "$REC" --stat oadev --taus log:20 --format json) "
    R[$side,analyze]+="$(t "$B/cubecal" analyze "$IMU" --columns gx,gy,gz,mx,my,mz \
      --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp) "
  done
done
for k in dev analyze; do
  for side in OLD NEW; do
    echo "$side $k: $(echo ${R[$side,$k]} | tr ' ' '\n' | sort -g |
      awk '{a[NR]=$1} END {printf "min %.3f median %.3f max %.3f s (n=%d)", a[1], a[int((NR+1)/2)], a[NR], NR}')"
  done
done
