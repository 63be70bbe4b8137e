#!/usr/bin/env bash
# Regenerates the table of docs/twins.md "Exports to simulators": `cubecal
# analyze --for gazebo,rotors,navego,matlab,basilisk` on ADIS16405 run 1 of
# ../shared/data/imu/adis16405, and each projection's twin error from
# analysis.json (estimator_files.simulator_projections): to 10 s / to 100 s /
# every scale, in %, one row per target, one column per axis.
# Usage: scripts/twin-projections.sh [build/bin/cubecal] [OUTDIR]
set -euo pipefail
CUBECAL=${1:-build/bin/cubecal}
OUT=${2:-twin-projections-out}
DATA=$(cd "${CUBECAL_SHARED_DATA:-$(dirname "$0")/../../shared/data}/imu/adis16405" && pwd)
"$CUBECAL" analyze "$DATA/run1.csv.gz" --unit deg/s,deg/s,deg/s,g,g,g --for gazebo,rotors,navego,matlab,basilisk \
  --out "$OUT" --force > /dev/null 2>&1
/usr/bin/python3 - "$OUT/analysis.json" <<'PY'
import json, sys
projections = json.load(open(sys.argv[1]))["estimator_files"]["simulator_projections"]
label = {"matlab": "matlab (R2023b on)", "matlab-pre-R2023b": "matlab (before R2023b)"}
print("| target | gyro x | gyro y | gyro z | acc x | acc y | acc z |")
print("|---|---|---|---|---|---|---|")
rows = {}
for p in projections:
    rows.setdefault(p["target"], []).append(p)
for target, ps in rows.items():
    cells = [f"{100 * p['twin_error_10s']:.0f} / {100 * p['twin_error_100s']:.0f} / {100 * p['twin_error']:.0f}" for p in ps]
    print(f"| {label.get(target, target)} | " + " | ".join(cells) + " |")
PY
