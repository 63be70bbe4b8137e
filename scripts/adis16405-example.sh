#!/usr/bin/env bash
# Regenerates the numbers of docs/adis16405.md: `cubecal analyze` on the six
# real ADIS16405 static runs in ../shared/data/imu/adis16405, one table row per
# run and axis. Usage: scripts/adis16405-example.sh [build/bin/cubecal] [OUTDIR]
set -euo pipefail
CUBECAL=${1:-build/bin/cubecal}
OUT=${2:-adis16405-out}
DATA=$(cd "${CUBECAL_SHARED_DATA:-$(dirname "$0")/../../shared/data}/imu/adis16405" && pwd)
PY=/usr/bin/python3
mkdir -p "$OUT"
# Two runs at a time (JOBS=N for more); each analysis is mostly one thread.
export CUBECAL DATA OUT
printf '%s\n' 1 2 3 4 5 6 | xargs -P "${JOBS:-2}" -I{} sh -c \
  '"$CUBECAL" analyze "$DATA/run{}.csv.gz" --unit deg/s,deg/s,deg/s,g,g,g --model-lsb 20,20,20,300.3,300.3,300.3 \
    --out "$OUT/run{}" --force > "$OUT/run{}.txt"'
"$PY" - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
# As the console prints a term: 4 digits, the sigma to 2, the unit ("—": none).
def f(q, unit=""):
    return "—" if q["value"] is None else f"{q['value']:.4g} ± {q['sigma']:.2g}" + (f" {unit}" if unit else "")
print("| run | axis | N | B | T [s] | K | model sigma_n, sigma_mu | Gauss-Markov sigma_b, T_c |")
print("|---|---|---|---|---|---|---|---|")
for run in range(1, 7):
    j = json.load(open(f"{out}/run{run}/analysis.json"))
    for c in j["channels"]:
        n = c["noise"]
        m = c["model"]
        gm = m.get("gauss_markov")
        model = "—" if m["sigma_n"] is None else f"{m['sigma_n']:.3g}, {m['sigma_mu']:.2g}"
        gms = "—" if not gm else f"{gm['sigma']:.2g}, {gm['tau_s']:.3g} s"
        print(f"| {run} | {c['name']} | {f(n['arw'], n['arw']['unit'])} | "
              f"{f(n['bias_instability'], n['bias_instability']['unit'])} | {'—' if n['time_constant_s'] is None else format(n['time_constant_s'], '.3g')} | {f(n['rate_random_walk'])} | {model} | {gms} |")
PY
