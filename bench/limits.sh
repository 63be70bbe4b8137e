#!/usr/bin/env bash
# The stage table (part of `make bench`): bench_limits measures what this
# machine can do at best on the 72 h x 10 Hz, 6-channel record; cubecal dev
# and analyze run with --timings; AllanTools (its public source) runs on the
# same record in the same run. bench/stage_table.py prints the table.
#
#   bash bench/limits.sh [BUILD]     RUNS=5, BENCH_OUT=bench-out
#
# AllanTools' source: ALLANTOOLS_SRC (a checkout of
# github.com/aewallin/allantools), else BENCH_OUT/allantools, cloned there
# when the network allows; without it the table says why it has no peer.
set -euo pipefail
BUILD=${1:-build}
OUT=${BENCH_OUT:-bench-out}
RUNS=${RUNS:-5}
T="$OUT/stages"
rm -rf "$T" && mkdir -p "$T"
REC="$OUT/imu_72h_10hz_6ch.csv"
IMU="$OUT/imu_72h_10hz_paper.csv"
[ -s "$REC" ] || "$BUILD/bin/make_record" "$REC" 72 10 6 1
[ -s "$IMU" ] || "$BUILD/bin/make_record" "$IMU" 72 10 imu 1
cat "$REC" "$IMU" > /dev/null  # both in the page cache

"$BUILD/bin/bench_limits" "$REC" "$RUNS" log:20 > "$T/limits.txt"
IMU_COLUMNS=gx,gy,gz,mx,my,mz
for i in $(seq "$RUNS"); do
  "$BUILD/bin/cubecal" dev "$REC" --taus log:20 --format json --timings > "$T/dev.json" 2> "$T/dev-timings-$i.txt"
  "$BUILD/bin/cubecal" dev "$REC" --taus log:20 --no-ci --format json --timings > /dev/null 2> "$T/devnoci-timings-$i.txt"
  "$BUILD/bin/cubecal" dev "$IMU" --columns "$IMU_COLUMNS" --taus log:20 --format json --timings \
    > /dev/null 2> "$T/devimu-timings-$i.txt"
  "$BUILD/bin/cubecal" analyze "$IMU" --columns "$IMU_COLUMNS" --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss \
    --temp-col temp --timings > /dev/null 2> "$T/analyze-timings-$i.txt"
done

SRC=${ALLANTOOLS_SRC:-$OUT/allantools}
if [ ! -f "$SRC/allantools/allantools.py" ] && [ -z "${ALLANTOOLS_SRC:-}" ]; then
  timeout 60 git clone -q --depth 1 https://github.com/aewallin/allantools "$SRC" > /dev/null 2>&1 || rm -rf "$SRC"
fi
if [ -f "$SRC/allantools/allantools.py" ]; then
  /usr/bin/python3 "$(dirname "$0")/allantools_peer.py" "$SRC" "$REC" "$T/dev.json" "$RUNS" > "$T/allantools.txt" 2>&1 ||
    { echo "AllanTools failed: $(tail -1 "$T/allantools.txt")" > "$T/allantools.txt"; }
else
  echo "no AllanTools source: set ALLANTOOLS_SRC to a checkout of github.com/aewallin/allantools" > "$T/allantools.txt"
fi
/usr/bin/python3 "$(dirname "$0")/stage_table.py" "$T"
