#!/usr/bin/env bash
# Peak memory of the in-memory path against the doubles it must hold:
# `dev` and `analyze` on the 72 h x 10 Hz records and `dev` on a 3 h x 1 kHz
# record, peak RSS from /usr/bin/time (max of 3 runs; memory does not depend
# on load), read whole and streamed (--stream). Ratios: to every parsed
# column (time, channels, temperature) and to the channels alone. A command
# that fails stops the script (a failed run's peak says nothing).
set -euo pipefail
shopt -s inherit_errexit
BUILD=${1:-build}
OUT=${BENCH_OUT:-bench-out}
CUBECAL=${CUBECAL:-$BUILD/bin/cubecal}
mkdir -p "$OUT"
REC="$OUT/imu_72h_10hz_6ch.csv"; IMU="$OUT/imu_72h_10hz_paper.csv"; FAST="$OUT/rec_3h_1khz_4ch.csv"
[ -s "$REC" ] || "$BUILD/bin/make_record" "$REC" 72 10 6 1
[ -s "$IMU" ] || "$BUILD/bin/make_record" "$IMU" 72 10 imu 1
[ -s "$FAST" ] || "$BUILD/bin/make_record" "$FAST" 3 1000 4 1

# peak KB of a command (the largest of three runs)
peak() {
  local best=0 kb
  for _ in 1 2 3; do
    if ! kb=$(/usr/bin/time -f "%M" "$@" 2>&1 >/dev/null | tail -1); then
      echo "bench/memory.sh: failed: $*" >&2
      exit 1
    fi
    [ "$kb" -gt "$best" ] && best=$kb
  done
  echo "$best"
}
# row: label file parsed-columns channels command...
row() {
  local label=$1 file=$2 parsed=$3 channels=$4; shift 4
  local rows kb
  rows=$(($(wc -l < "$file") - 1))
  kb=$(peak "$@")
  awk -v l="$label" -v kb="$kb" -v r="$rows" -v p="$parsed" -v c="$channels" 'BEGIN {
    all = r * p * 8 / 1e6; ch = r * c * 8 / 1e6; mb = kb * 1024 / 1e6
    printf "  %-34s %8.0f MB  parsed %6.0f MB (x%.2f)  channels %6.0f MB (x%.2f)\n", l, mb, all, mb / all, ch, mb / ch }'
}
echo "== peak memory (in-memory path; max of 3 runs)"
row "dev 72 h x 10 Hz, 6 ch, log:20" "$REC" 7 6 \
  "$CUBECAL" dev "$REC" --stat oadev --taus log:20 --format json
row "analyze 72 h x 10 Hz, 6 ch" "$REC" 7 6 \
  "$CUBECAL" analyze "$REC" --unit deg/s
row "analyze 72 h, 6 ch + temperature" "$IMU" 8 6 \
  "$CUBECAL" analyze "$IMU" --columns gx,gy,gz,mx,my,mz --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp
row "dev 3 h x 1 kHz, 4 ch, log:20" "$FAST" 5 4 \
  "$CUBECAL" dev "$FAST" --stat oadev --taus log:20 --format json
echo "== peak memory, streamed (--stream: the default window bound, 2^16 at most; and --window 4096)"
row "dev --stream 72 h, 6 ch, log:20" "$REC" 7 6 \
  "$CUBECAL" dev "$REC" --stat oadev --taus log:20 --format json --stream
row "dev --stream --window 4096" "$REC" 7 6 \
  "$CUBECAL" dev "$REC" --stat oadev --taus log:20 --format json --stream --window 4096
row "analyze --stream 72 h, 6 ch" "$REC" 7 6 \
  "$CUBECAL" analyze "$REC" --unit deg/s --stream
row "analyze --stream, 6 ch + temperature" "$IMU" 8 6 \
  "$CUBECAL" analyze "$IMU" --columns gx,gy,gz,mx,my,mz --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp --stream
row "analyze --stream --window 4096, + temp" "$IMU" 8 6 \
  "$CUBECAL" analyze "$IMU" --columns gx,gy,gz,mx,my,mz --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp --stream --window 4096
row "dev --stream 3 h x 1 kHz, 4 ch" "$FAST" 5 4 \
  "$CUBECAL" dev "$FAST" --stat oadev --taus log:20 --format json --stream
