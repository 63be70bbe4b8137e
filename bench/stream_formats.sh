#!/usr/bin/env bash
# Formats streamed like raw binary (issue 33, item 4): a NumPy .npy of
# NPY_SAMPLES (default 2e8) float64 samples, one column (1.6 GB), and a
# gzip-compressed text record of GZ_LINES (default 2e7) lines "t,gx", each
# through `cubecal dev FILE --rate 100 --stream --memory 256M`: peak RSS (GNU
# time) and samples per second, min/median/max of RUNS runs (default 3), and
# as a share of what this machine does with the same file and no analysis:
# `cat FILE > /dev/null` for the .npy, `gzip -dc FILE > /dev/null` for the
# .gz. The files are written piece by piece (bench/emit_raw behind a header
# written here; awk into gzip -1) into a temporary directory deleted at the
# end.
set -euo pipefail
BUILD=${1:-build}
NPY_SAMPLES=${NPY_SAMPLES:-200000000}
GZ_LINES=${GZ_LINES:-20000000}
RUNS=${RUNS:-3}
MEMORY=${STREAM_MEMORY:-256M}
TIME=/usr/bin/time
TMP=$(mktemp -d "${TMPDIR:-/tmp}/cubecal-stream-formats.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

# The header of a version 1.0 .npy of n float64 samples: the magic, the
# version, the header length, a Python dict padded with spaces to a multiple
# of 64 bytes and ended by a newline.
npy_header() {
  local dict="{'descr': '<f8', 'fortran_order': False, 'shape': ($1,), }"
  local len=$(( (10 + ${#dict} + 1 + 63) / 64 * 64 - 10 ))
  printf '\x93NUMPY\x01\x00'
  printf "\\x$(printf %02x $((len % 256)))\\x$(printf %02x $((len / 256)))"
  printf '%s%*s\n' "$dict" $((len - ${#dict} - 1)) ''
}

# min/median/max of the numbers on standard input.
stats() { sort -g | awk '{a[NR]=$1} END {printf "%.4g/%.4g/%.4g", a[1], a[int((NR+1)/2)], a[NR]}'; }

# label, file, samples, baseline command: RUNS runs of dev --stream and of
# the baseline, the figures on one line each.
measure() {
  local label=$1 file=$2 n=$3 baseline=$4
  local rates=() rss=() base=()
  for _ in $(seq "$RUNS"); do
    $TIME -f "%M %e" -o "$TMP/time.txt" "$BUILD/bin/cubecal" dev "$file" --rate 100 --stream --memory "$MEMORY" \
      --format csv > "$TMP/dev.csv"
    read -r rss_kb secs < "$TMP/time.txt"
    rates+=("$(echo "$n / $secs" | bc -l)")
    rss+=("$(echo "$rss_kb / 1024" | bc -l)")
    $TIME -f "%e" -o "$TMP/time.txt" bash -c "$baseline '$file' > /dev/null"
    base+=("$(echo "$n / $(cat "$TMP/time.txt")" | bc -l)")
  done
  local r b
  r=$(printf '%s\n' "${rates[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  b=$(printf '%s\n' "${base[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  echo "  $label: $n samples, $(du -m "$file" | cut -f1) MB"
  echo "    dev --stream: $(printf '%s\n' "${rates[@]}" | awk '{print $1/1e6}' | stats) M samples/s (min/median/max of $RUNS)," \
    "peak RSS $(printf '%s\n' "${rss[@]}" | stats) MB"
  echo "    $baseline alone: $(printf '%s\n' "${base[@]}" | awk '{print $1/1e6}' | stats) M samples/s;" \
    "dev at $(echo "100 * $r / $b" | bc -l | xargs printf '%.0f') % of it (medians)"
}

echo "== streamed formats: dev FILE --rate 100 --stream --memory $MEMORY (bench/stream_formats.sh)"
NPY="$TMP/walk.npy"
{ npy_header "$NPY_SAMPLES"; "$BUILD/bin/emit_raw" "$NPY_SAMPLES"; } > "$NPY"
measure ".npy float64" "$NPY" "$NPY_SAMPLES" cat
rm -f "$NPY"
GZ="$TMP/gyro.csv.gz"
awk -v n="$GZ_LINES" 'BEGIN { srand(1); print "t,gx"; for (i = 0; i < n; i++) printf "%.2f,%.6f\n", i / 100, rand() - 0.5 }' |
  gzip -1 > "$GZ"
measure "gzip text" "$GZ" "$GZ_LINES" "gzip -dc"
