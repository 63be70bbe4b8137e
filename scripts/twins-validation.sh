#!/usr/bin/env bash
# The validation of docs/twins.md: `cubecal analyze` with its default twin and
# `--twin-check K` on the six real ADIS16405 static runs of
# ../shared/data/imu/adis16405 (1e6 samples at 100 Hz each) and the static
# Phidgets and AR.Drone bags of ../shared/data/rosbag; one row per run and
# axis: the selected twin, its twin error on the record's Allan curve
# (largest |sigma_model / sigma - 1|, taus inside the 68.3 % intervals), its
# fidelity on the wavelet variance (scales inside the 95 % intervals), and
# the mean curve of K simulated twins against the record: the worst error to
# 10 s and to 100 s.
# Usage: scripts/twins-validation.sh [build/bin/cubecal] [OUTDIR] [K]
# (defaults: twins-validation-out, K = 4). An analysis already in OUTDIR is
# kept: remove OUTDIR to run again.
set -euo pipefail
CUBECAL=${1:-build/bin/cubecal}
OUT=${2:-twins-validation-out}
K=${3:-4}
DATA=$(cd "${CUBECAL_SHARED_DATA:-$(dirname "$0")/../../shared/data}" && pwd)
PY=/usr/bin/python3
mkdir -p "$OUT"
run() {  # name, then analyze's arguments
  local name=$1
  shift
  [ -s "$OUT/$name/analysis.json" ] && return 0
  "$CUBECAL" analyze "$@" --twin-check "$K" --out "$OUT/$name" --force > "$OUT/$name.txt"
}
for r in 1 2 3 4 5 6; do
  run "adis16405-run$r" "$DATA/imu/adis16405/run$r.csv.gz" --unit deg/s,deg/s,deg/s,g,g,g
done
run phidgets "$DATA/rosbag/ros1/phidgets_imu_upside_down.bag" --topic /imu/data_raw --rate 250
run ardrone "$DATA/rosbag/ros1/ardrone_imu.bag" --topic /ardrone/imu --rate 50
"$PY" - "$OUT" <<'PY'
import json, os, sys
out = sys.argv[1]
print("| record | axis | twin | twin error to 10 s | to 100 s | all taus | taus inside | WV scales inside 95 % | mean of twins: worst to 10 s | to 100 s |")
print("|---|---|---|---|---|---|---|---|---|---|")
for name in sorted(os.listdir(out)):
    f = os.path.join(out, name, "analysis.json")
    if not os.path.isfile(f):
        continue
    a = json.load(open(f))
    checks = {c["name"]: c for c in a.get("twin_check", {}).get("channels", [])}
    for ch in a["channels"]:
        c = ch["model"].get("composite")
        if c is None:
            print(f"| {name} | {ch['name']} | none: {a.get('composite_skipped', '')} | | | | | | | |")
            continue
        e = c["twin_error"]
        fi = c["fidelity"]
        t = checks.get(ch["name"], {})
        print(f"| {name} | {ch['name']} | {c['model']} | {100 * e['max_error_10s']:.1f} % | {100 * e['max_error_100s']:.1f} % "
              f"| {100 * e['max_error']:.1f} % at {e['max_error_tau_s']:.4g} s "
              f"| {e['inside']}/{e['taus']} | {fi['inside_95']}/{fi['scales']} "
              f"| {100 * t.get('max_error_10s', float('nan')):.1f} % | {100 * t.get('max_error_100s', float('nan')):.1f} % |")
PY
