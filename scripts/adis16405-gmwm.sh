#!/usr/bin/env bash
# Regenerates the tables of docs/adis16405-gmwm.md: `cubecal model` (GMWM) on
# the six real ADIS16405 static runs in ../shared/data/imu/adis16405, every
# axis, one JSON per run and model, then one table row per run, axis and
# model: each term's quantities with their bootstrap standard deviation, the
# objective, and the scales whose model wavelet variance lies outside the
# measured one's 95 % chi-square interval.
# Usage: scripts/adis16405-gmwm.sh [build/bin/cubecal] [OUTDIR] [BOOTSTRAP] [MODEL ...]
# (defaults: 100 replicates; models WN+RW+2*GM, WN+RW+3*GM, 3*GM and MA1+RW+2*GM). A JSON already in
# OUTDIR is kept, not refitted: remove OUTDIR to fit again.
set -euo pipefail
CUBECAL=${1:-build/bin/cubecal}
OUT=${2:-adis16405-gmwm-out}
B=${3:-100}
shift $(( $# < 3 ? $# : 3 ))
MODELS=("$@")
[ ${#MODELS[@]} -gt 0 ] || MODELS=("WN+RW+2*GM" "WN+RW+3*GM" "3*GM" "MA1+RW+2*GM")
DATA=$(cd "${CUBECAL_SHARED_DATA:-$(dirname "$0")/../../shared/data}/imu/adis16405" && pwd)
PY=/usr/bin/python3
mkdir -p "$OUT"
for model in "${MODELS[@]}"; do
  slug=$(printf '%s' "$model" | tr '+*' 'p_')
  for run in 1 2 3 4 5 6; do
    f="$OUT/run$run-$slug.json"
    [ -s "$f" ] && continue
    "$CUBECAL" model "$DATA/run$run.csv.gz" --model "$model" --unit deg/s,deg/s,deg/s,g,g,g \
      --bootstrap "$B" --format json --out "$f" --force
  done
done
"$PY" - "$OUT" "${MODELS[@]}" <<'PY'
import json, sys
out, models = sys.argv[1], sys.argv[2:]
def q(x, boot):
    d = x["display"]
    s = f" ± {d['sigma']:.2g}" if boot else ""
    return f"{x['name']} {d['value']:.4g}{s} {d['unit']}"
def white(c, dt):
    # The white level the record shows beyond the first scales: WN (or the
    # MA1's N = sigma (1 + theta) sqrt(dt)) plus every Gauss-Markov term of
    # T_c < 10 dt, whose low-frequency density is sigma_b^2 (1 + phi) / (1 - phi)
    # dt; as N in the WN's display unit.
    n2 = 0.0
    for t in c["terms"]:
        if t["term"] in ("WN", "MA1"):
            n2 += t["quantities"][0]["value"] ** 2
        elif t["term"] == "GM" and t["quantities"][1]["value"] < 10 * dt:
            phi = t["parameters"]["phi"]
            n2 += t["quantities"][0]["value"] ** 2 * (1 + phi) / (1 - phi) * dt
    unit, factor = {"deg/s": ("deg/sqrt(h)", 60.0), "g": ("g*sqrt(h)", 1 / 60.0)}.get(c["unit"], (c["unit"] + "*sqrt(s)", 1.0))
    return f"{n2 ** 0.5 * factor:.3g} {unit}"
for model in models:
    slug = model.replace("+", "p").replace("*", "_")
    print(f"\n### {model}\n")
    print("| run | axis | terms (± bootstrap sd) | white level | objective / scales | outside the 95 % interval (tau [s]) |")
    print("|---|---|---|---|---|---|")
    for run in range(1, 7):
        j = json.load(open(f"{out}/run{run}-{slug}.json"))
        for c in j["channels"]:
            wv = c["wavelet_variance"]
            outside = [t for t, lo, hi, m in zip(wv["tau_s"], wv["lo"], wv["hi"], wv["model"]) if not lo <= m <= hi]
            boot = c["replicates"] >= 2
            terms = "; ".join(t["term"] + " " + ", ".join(q(x, boot) for x in t["quantities"]) for t in c["terms"])
            if not boot and j["bootstrap"] > 0:
                terms += f" (no bootstrap: {c['replicates']} of {j['bootstrap']} replicates fitted)"
            where = "none" if not outside else f"{len(outside)}: " + ", ".join(f"{t:g}" for t in outside)
            print(f"| {run} | {c['name']} | {terms} | {white(c, 1 / j['rate_hz'])} | {c['objective']:.4g} / "
                  f"{len(wv['tau_s'])} | {where} |")
PY
