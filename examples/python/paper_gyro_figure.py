#!/usr/bin/env python3
"""The paper's gyro figure from a simulated record of its static experiment.

Simulates the SPORT gyro and magnetometer at 10 Hz under a daily 25 +- 5 degC
swing (as `cubecal demo`), analyzes the record as the demo does (Allan curve on
the log:20 grid, the random-walk model fitted on the first 42000 samples with
the sensors' LSBs) and draws the Allan deviation of the three gyro axes in
deg/h: the measured overlapping ADEV with its 68.3 % confidence band, the
fitted random-walk model (the paper's eq. (1)-(3)) dashed, and the read-off
terms N, B (with the bias-instability time T) and K.

    PYTHONPATH=build/python python3 examples/python/paper_gyro_figure.py --hours 3
    PYTHONPATH=build/python python3 examples/python/paper_gyro_figure.py --hours 72 --out gyro_72h.svg

The model curve is evaluated from the model's parameters in analysis.json
(sigma_n, sigma_mu, lsb) with the exact discrete Allan variance of
docs/formulas/noise-terms.md section 4.2, the formula of the library's
avar(RandomWalkModel, m) and of adev.csv's model_dev column.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)
import numpy as np  # noqa: E402

import cubecal  # noqa: E402

RATE_HZ = 10.0
GYRO = ("gx", "gy", "gz")
# The demo's analysis (src/cli/cmd_demo.cpp): units, grid, model fit window, LSBs.
ANALYZE_OPTIONS = dict(unit=["deg/s"] * 3 + ["mGauss"] * 3, temperature="temp", taus="log:20",
                       max_samples=42000, model_lsb=[145.6] * 3 + [1.3] * 3)
DEG_S_TO_DEG_H = 3600.0
# The reported terms of analysis.json (noise.reported) and their symbols.
TERMS = (("N", "white_noise"), ("B", "bias_instability"), ("K", "rate_random_walk"))


def simulate_and_analyze(hours, seed):
    """The simulated record of the paper's experiment and its Analysis."""
    record = cubecal.simulate(["sport-gyro", "sport-mag"], rate=RATE_HZ, duration=hours * 3600.0, seed=seed,
                              temperature="sine:25,5")
    return cubecal.analyze(record, **ANALYZE_OPTIONS)


def model_adev(model, dt, m):
    """ADEV of the random-walk model at averaging factors m (u, the channel's
    unit): sigma^2(m) = (sigma_n^2 + q^2)/m + (sigma_mu dt)^2 (2 m^2 + 1)/(6 m),
    q^2 = 1/(12 lsb^2) the quantization share (none without an LSB)."""
    m = np.asarray(m, dtype=float)
    q2 = 1.0 / (12.0 * model["lsb"] ** 2) if model["lsb"] > 0 else 0.0
    step = model["sigma_mu"] * dt
    return np.sqrt((model["sigma_n"] ** 2 + q2) / m + step * step * (m / 3.0 + 1.0 / (6.0 * m)))


def channel_summary(channel, dt):
    """The numbers the figure shows for one channel (plain Python data)."""
    noise, model = channel["noise"], channel["model"]
    terms = {}
    for symbol, key in TERMS:
        t = noise["reported"][key]
        terms[symbol] = {"value": t["value"], "sigma": t["sigma"], "unit": t["unit"], "source": t["source"]}
    summary = {"name": channel["name"], "unit": channel["unit"], **terms, "T_s": noise["time_constant_s"],
               "sigma_n": model["sigma_n"], "sigma_mu": model["sigma_mu"], "lsb": model["lsb"],
               "model_samples": model["samples"]}
    if model["sigma_n"] is not None:
        tau = np.asarray(channel["adev"]["tau"])
        summary["model_tau"] = tau.tolist()
        summary["model_dev"] = model_adev(model, dt, np.rint(tau / dt)).tolist()
    return summary


def term_text(symbol, term):
    """'N = 0.269 ± 0.0015 deg/sqrt(h)', '<' for an upper bound, '—' when absent."""
    if term["value"] is None:
        return f"{symbol} —"
    unit = term["unit"].replace("sqrt(h)", "√h")
    if term["source"] == "UPPER BOUND":
        return f"{symbol} < {term['value']:.3g} {unit}"
    return f"{symbol} = {term['value']:.4g} ± {term['sigma']:.2g} {unit}"


def table_cell(term):
    """A term as a 19-character cell of the printed table."""
    if term["value"] is None:
        return f"{'—':>19}"
    if term["source"] == "UPPER BOUND":
        return f"{'< ' + format(term['value'], '.4g'):>19}"
    return f"{term['value']:>9.4g} ± {term['sigma']:<7.2g}"


def draw(channels, summaries, ci, dt, title, path):
    """Writes the figure of the gyro channels (analysis.json's channels and
    their summaries; ci the intervals' confidence, dt the sample period in s)
    to path (PNG, SVG or PDF by its extension)."""
    fig, ax = plt.subplots(figsize=(9, 6.5), layout="constrained")
    lines = []
    for k, (channel, s) in enumerate(zip(channels, summaries)):
        color = f"C{k}"
        a = channel["adev"]
        tau = np.asarray(a["tau"])
        dev, lo, hi = (np.asarray(a[key]) * DEG_S_TO_DEG_H for key in ("dev", "lo", "hi"))
        ax.fill_between(tau, lo, hi, color=color, alpha=0.25, linewidth=0)
        ax.plot(tau, dev, color=color, linewidth=1.4,
                label=f"{s['name']} OADEV ({ci * 100:.1f} % interval)")
        if s["sigma_n"] is not None:
            # Every averaging factor from 1 to the curve's last: a smooth model curve.
            m = np.unique(np.rint(np.geomspace(1, tau[-1] / dt, 400)))
            ax.plot(m * dt, model_adev(channel["model"], dt, m) * DEG_S_TO_DEG_H, color=color, linestyle="--",
                    linewidth=1.2, label=f"{s['name']} random-walk model")
        if s["T_s"] is not None:
            # The minimum of the curve, where B = sigma_min / 0.664 is read.
            minimum = channel["noise"]["curve_minimum"]["tau_s"], channel["noise"]["sigma_min"]["value"]
            ax.plot([minimum[0]], [minimum[1] * DEG_S_TO_DEG_H], marker="o", markersize=7, markerfacecolor="none",
                    markeredgecolor=color, markeredgewidth=1.5, linestyle="none")
        t_text = f" (T = {s['T_s']:.3g} s)" if s["T_s"] is not None else ""
        lines.append(f"{s['name']}:  {term_text('N', s['N'])},  {term_text('B', s['B'])}{t_text},  "
                     f"{term_text('K', s['K'])}")
    model_samples = summaries[0]["model_samples"]
    lines.append(f"model fitted on the first {model_samples} samples ({model_samples * dt:g} s); "
                 "○ = the curve's minimum σ_min (B = σ_min / 0.664, at T)")
    ax.text(0.015, 0.015, "\n".join(lines), transform=ax.transAxes, fontsize=8, va="bottom", ha="left",
            family="DejaVu Sans", bbox=dict(boxstyle="round", facecolor="white", alpha=0.85, edgecolor="0.7"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("averaging time τ [s]")
    ax.set_ylabel("Allan deviation σ(τ) [deg/h]")
    ax.set_title(title)
    ax.grid(True, which="major", alpha=0.5)
    ax.grid(True, which="minor", alpha=0.15)
    ax.legend(fontsize=8, ncol=3, loc="upper left")
    # Room below the curves for the read-offs and above them for the legend.
    bottom, top = ax.get_ylim()
    ax.set_ylim(bottom / 4.0, top * 2.0)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                epilog="Needs the cubecal module (PYTHONPATH=build/python) and matplotlib.")
    p.add_argument("--hours", type=float, default=3.0,
                   help="length of the simulated record in hours (default 3; the paper's experiment: 72)")
    p.add_argument("--seed", type=int, default=1, help="random seed of the simulation (default 1, as the demo)")
    p.add_argument("--out", default="gyro_allan.png",
                   help="figure file; its extension chooses the format: .png, .svg, .pdf (default gyro_allan.png)")
    p.add_argument("--json", action="store_true",
                   help="print one JSON line (the figure's path and, per gyro axis, N, B, K with their sigmas, T, "
                        "the model's sigma_n and sigma_mu and its curve at the measured taus) instead of the table")
    args = p.parse_args(argv)
    if not args.hours > 0:
        p.error("--hours: a positive length")

    analysis = simulate_and_analyze(args.hours, args.seed).to_dict()
    gyro = [c for c in analysis["channels"] if c["name"] in GYRO]
    dt = 1.0 / analysis["input"]["rate_hz"]
    summaries = [channel_summary(c, dt) for c in gyro]
    title = f"SPORT gyro (simulated): {args.hours:g} h at {RATE_HZ:g} Hz, 25 ± 5 °C daily, seed {args.seed}"
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    draw(gyro, summaries, analysis["ci"], dt, title, args.out)

    if args.json:
        print(json.dumps({"figure": os.path.abspath(args.out), "hours": args.hours, "seed": args.seed,
                          "samples": analysis["input"]["samples"], "channels": summaries}))
        return 0
    print(f"{'axis':<4} {'N [deg/√h]':>19} {'B [deg/h]':>19} {'T [s]':>6} {'K [deg/h/√h]':>19} "
          f"{'sigma_n [deg/s]':>16} {'sigma_mu [deg/s/s]':>19}")
    for s in summaries:
        cells = [table_cell(s[symbol]) for symbol in ("N", "B", "K")]
        T, sn, smu = (format(s[key], ".4g") if s[key] is not None else "—" for key in ("T_s", "sigma_n", "sigma_mu"))
        print(f"{s['name']:<4} {cells[0]} {cells[1]} {T:>6} {cells[2]} {sn:>16} {smu:>19}")
    print(f"Figure written to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
