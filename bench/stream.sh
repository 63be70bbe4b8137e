#!/usr/bin/env bash
# The streaming benchmark of issue 12: a 1 kHz channel of STREAM_DAYS days
# (default 30: 2.592e9 samples) analysed by `cubecal dev - --stream` from a
# pipe, with the peak RSS of the dev process (GNU time) and the throughput:
#  1. simulated: cubecal simulate --format raw --out - (the sport-gyro preset:
#     gx,gy,gz,temp as float64le; dev reads gx);
#  2. replayed: bench/emit_raw (one float64le channel, no generation cost),
#     to see dev's own rate when the simulator is the bottleneck.
# Measured 2026-11-23 on the shared 2-core build machine (load 6-14 from other
# builds): replayed, 30 days (2.592e9 samples): 360 s wall (7.2 M samples/s),
# dev CPU 62.8 s user + 3.0 s sys (39 M samples per CPU second), peak RSS
# 51.8 MB; simulated, 1 day (8.64e7): 22.7 s wall (the simulator bound, 3.8 M
# samples/s), dev CPU 3.0 s, peak RSS 37 MB.
# After the streaming speed-ups (docs/performance.md), STREAM_DAYS=2
# (1.728e8 samples), same machine, lighter load: replayed 3.9 s wall (45 M
# samples/s, emit_raw the bound), dev CPU 1.7 s user + 0.5 s sys (78 M samples
# per CPU second; main 54 M), peak RSS 33 MB (main 51 MB); simulated 19.7 s
# wall (8.8 M samples/s, the simulator bound), dev CPU 4.2 s.
# 30 days replayed after the merge with analyze --stream, the pipe widened to
# 1 MiB, quiet machine: 41.0 s wall (63 M samples/s; emit_raw | cat alone
# moves 90 M samples/s), dev CPU 25.8 s user + 6.2 s sys (81 M samples per
# CPU second), peak RSS 40.4 MB (docs/performance.md).
set -euo pipefail
BUILD=${1:-build}
DAYS=${STREAM_DAYS:-30}
MEMORY=${STREAM_MEMORY:-256M}
N=$(echo "$DAYS * 86400 * 1000" | bc)
TIME=/usr/bin/time
run() {  # label, producer, dev arguments
  local label=$1 producer=$2 args=$3
  local s e
  s=$(date +%s.%N)
  bash -c "$producer" | $TIME -f "%M %e %U %S" -o "$OUT/stream_time.txt" \
    "$BUILD/bin/cubecal" dev - $args --rate 1000 --stream --memory "$MEMORY" --format csv > "$OUT/stream_$label.csv"
  e=$(date +%s.%N)
  read -r rss_kb secs user sys < "$OUT/stream_time.txt"
  echo "$label $N $secs $rss_kb $user $sys" | awk '{printf "  %-9s %.4g samples in %.1f s: %.1f M samples/s (dev CPU %.1f s user + %.1f s sys: %.1f M samples per CPU second), peak RSS %.0f MB\n", $1, $2, $3, $2/$3/1e6, $5, $6, $2/($5+$6)/1e6, $4/1024}'
}
OUT=${BENCH_OUT:-bench-out}
mkdir -p "$OUT"
echo "== streaming: $DAYS days x 1 kHz (${N} samples), dev --stream --memory $MEMORY, oadev octave"
run simulated "'$BUILD/bin/cubecal' simulate --preset sport-gyro --rate 1000 --duration ${DAYS}d --seed 1 --format raw --out - --force 2>/dev/null" \
  "--binary float64le,float64le,float64le,float64le --columns 1"
run replayed "'$BUILD/bin/emit_raw' $N" "--binary float64le"
tail -n 3 "$OUT/stream_replayed.csv"
