#!/usr/bin/python3
"""The stage table of `make bench` (bench/run.sh writes its inputs in DIR):

    stage_table.py DIR

DIR/limits.txt             bench_limits on the 6-channel record
DIR/dev-timings-*.txt      stderr of `cubecal dev --taus log:20 --timings` on it
DIR/devnoci-timings-*.txt  the same with --no-ci (deviations only, as AllanTools computes)
DIR/devimu-timings-*.txt   the same on the paper's record (6 columns)
DIR/analyze-timings-*.txt  stderr of `cubecal analyze --temp-col temp --timings` on it
DIR/allantools.txt         allantools_peer.py on the 6-channel record (optional)

Every figure is min / median / max over the runs. Thread-seconds (the time
of a stage summed over the threads that ran it) are set against the limit's
wall clock times the threads, since the limits run on all cores too.
"""
import glob
import os
import statistics
import sys

d = sys.argv[1]


def spread(values):
    v = sorted(values)
    return v[0], statistics.median(v), v[-1]


def fmt(s, unit="s"):
    return f"{s[1]:7.3f} {unit} ({s[0]:.3f}-{s[2]:.3f})"


def timings(pattern):
    runs = []
    for path in sorted(glob.glob(os.path.join(d, pattern))):
        stages = {}
        for line in open(path):
            if not line.startswith("cubecal: timing: "):
                continue
            words = line[len("cubecal: timing: "):].split()
            # "noise id" is two words: the value is the first number.
            k = next(i for i, w in enumerate(words) if w.replace(".", "", 1).isdigit())
            stages[" ".join(words[:k])] = float(words[k])
        runs.append(stages)
    if not runs:
        sys.exit(f"stage_table: no {pattern} in {d}")
    names = [n for n in runs[0]]
    return {n: spread([r.get(n, 0.0) for r in runs]) for n in names}, len(runs)


limits, info = {}, {}
for line in open(os.path.join(d, "limits.txt")):
    w = line.split()
    if w[0] == "limit":
        limits[w[1]] = tuple(float(x) for x in w[2:5])
    elif w[0] == "info":
        info[w[1]] = float(w[2])
threads = int(info["threads"])
size = info["bytes"]

dev, runs = timings("dev-timings-*.txt")
devnoci, _ = timings("devnoci-timings-*.txt")
devimu, _ = timings("devimu-timings-*.txt")
analyze, _ = timings("analyze-timings-*.txt")


def times(s, k):
    return tuple(x * k for x in s)


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


print(f"machine: {threads} threads; record {size / 1e6:.0f} MB, {int(info['rows'])} rows x "
      f"{int(info['columns'])} channels, {int(info['taus'])} taus ({info['terms']:.3g} OADEV terms); "
      f"{runs} runs each, min-max in brackets")
print()
print("limits (all cores, wall):")
print(f"  (a)  read the file from the page cache   {fmt(limits['read'])}   {size / limits['read'][1] / 1e9:5.1f} GB/s")
print(f"  (a') the parsed doubles from memory      {fmt(limits['doubles'])}")
print(f"  (b)  parse, fast_float over the bytes    {fmt(limits['parse'])}   {size / limits['parse'][1] / 1e9:5.2f} GB/s")
print(f"  (c)  OADEV, one pass per tau             {fmt(limits['oadev'])}   "
      f"{info['terms'] / limits['oadev'][1] / 1e9:5.2f} G terms/s")
print()
print("cubecal dev --taus log:20, 6 channels, by stage:")
print(f"  {'stage':<12} {'time':<34} {'limit':<34} ratio")
rows = [
    ("read", dev["read"], "wall", limits["parse"], "(b) parse"),
    ("phase+kern.", add(dev["phase"], dev["kernels"]), "thread-s", times(limits["oadev"], threads), "(c) x threads"),
    ("noise id", dev.get("noise id", (0, 0, 0)), "thread-s", None, "share of the total"),
    ("intervals", dev.get("intervals", (0, 0, 0)), "thread-s", None, "share of the total"),
    ("output", dev["output"], "wall", None, "share of the total"),
    ("total", dev["total"], "wall", add(limits["read"], limits["oadev"]), "(a)+(c)"),
]
for name, t, unit, lim, what in rows:
    if lim is not None:
        print(f"  {name:<12} {fmt(t, unit):<34} {fmt(lim):<26} {what:<8} {t[1] / lim[1]:5.2f}x")
    else:
        share = t[1] / (dev["total"][1] * (threads if unit == "thread-s" else 1))
        print(f"  {name:<12} {fmt(t, unit):<34} {what:<35} {100 * share:5.1f}%")
print(f"  parse rate: {size / dev['read'][1] / 1e9:.2f} GB/s (target >= 1)")
print()
print("cubecal analyze --temp-col temp on the paper's record (6 channels + temperature), by stage:")
for name in ["read", "phase", "kernels", "noise id", "intervals", "fits", "drift", "covariance", "temperature",
             "output", "total"]:
    if name in analyze:
        unit = "wall" if name in ("read", "output", "total", "temperature") else "thread-s"
        print(f"  {name:<12} {fmt(analyze[name], unit)}")
print(f"  analyze with temperature / dev of the same 6 columns: {analyze['total'][1]:.3f} s / "
      f"{devimu['total'][1]:.3f} s = {analyze['total'][1] / devimu['total'][1]:.2f}x (target <= 1.5)")

peer = os.path.join(d, "allantools.txt")
print()
if os.path.exists(peer) and any(line.startswith("run ") for line in open(peer)):
    load, oadev, total, diff = [], [], [], ""
    for line in open(peer):
        w = line.split()
        if w[0] == "run":
            load.append(float(w[1]))
            oadev.append(float(w[2]))
            total.append(float(w[1]) + float(w[2]))
        elif w[0] == "max_rel_diff":
            diff = w[1]
    t = spread(total)
    print(f"AllanTools (np.loadtxt + oadev at the same taus, {len(total)} runs): load {fmt(spread(load))}, "
          f"oadev {fmt(spread(oadev))}, total {fmt(t)}; largest relative difference from cubecal {diff}")
    for label, run in (("cubecal dev", dev), ("cubecal dev --no-ci (no intervals, like AllanTools)", devnoci)):
        print(f"  AllanTools / {label}: {t[1] / run['total'][1]:.1f}x median "
              f"({t[0] / run['total'][2]:.1f}x-{t[2] / run['total'][0]:.1f}x) (target >= 25)")
else:
    reason = open(peer).read().strip() if os.path.exists(peer) else "not run"
    print(f"AllanTools: skipped ({reason})")
