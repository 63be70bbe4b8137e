#!/usr/bin/env python3
"""Analyze a fleet of sensor logs in parallel with Dask.

Every file of DIRECTORY matching --pattern is one task, `cubecal.analyze(path,
...)` run on a Dask worker; the results are gathered into one table, a row per
file and channel: file, channel, unit, samples, rate_hz, the reported noise
terms N, B, K (value, sigma, unit and source as analysis.json's
noise.reported gives them), the bias-instability time T_s and the paper's
random-walk model (sigma_n, sigma_mu). Written into --out:

  fleet.csv     the table (numbers at full precision: they read back to the same doubles)
  fleet.json    the table and the full analysis.json content of every file
  summary.html  one self-contained page: per channel the min / median / max of N and B
                over the fleet, values further than 3 scaled MADs from the median
                flagged, and the table

    PYTHONPATH=build/python python3 examples/python/fleet.py ../shared/data/imu/adis16405 \\
        --columns gyro_x_dps,gyro_y_dps,gyro_z_dps --unit deg/s --workers 2 --out fleet-out
"""
import argparse
import contextlib
import csv
import html
import importlib.util
import json
import os
import statistics
import sys
from pathlib import Path

from dask.distributed import Client, LocalCluster, as_completed

# The table's columns, in order.
COLUMNS = ("file", "channel", "unit", "samples", "rate_hz",
           "N", "N_sigma", "N_unit", "N_source",
           "B", "B_sigma", "B_unit", "B_source",
           "K", "K_sigma", "K_unit", "K_source",
           "T_s", "sigma_n", "sigma_mu", "sigma_mu_unit", "model_error")
# The terms of analysis.json's noise.reported and their symbols in the table.
TERMS = (("N", "white_noise"), ("B", "bias_instability"), ("K", "rate_random_walk"))
UPPER_BOUND = "UPPER BOUND"
# Outliers: further than this many scaled MADs (1.4826 MAD, the standard
# deviation's estimate for normal data) from the fleet's median.
OUTLIER_MADS = 3.0
MAD_SCALE = 1.4826


def analyze_file(path, options):
    """The task a worker runs: cubecal.analyze on one file. Returns
    {"path", "analysis": analysis.json's content} or {"path", "error"} when
    the file cannot be analyzed (cubecal.Error: bad data or options)."""
    try:
        import cubecal
    except ImportError as e:
        raise RuntimeError(f"a Dask worker cannot import cubecal ({e}): start the workers with the module on "
                           "their PYTHONPATH") from e
    try:
        return {"path": path, "analysis": cubecal.analyze(path, **options).to_dict()}
    except cubecal.Error as e:
        return {"path": path, "error": f"{type(e).__name__}: {e}"}


def rows_of(file, analysis):
    """The table's rows of one analysis: one per channel."""
    rows = []
    for c in analysis["channels"]:
        row = {"file": file, "channel": c["name"], "unit": c["unit"], "samples": analysis["input"]["samples"],
               "rate_hz": analysis["input"]["rate_hz"]}
        for symbol, key in TERMS:
            t = c["noise"]["reported"][key]
            row.update({symbol: t["value"], f"{symbol}_sigma": t["sigma"], f"{symbol}_unit": t["unit"],
                        f"{symbol}_source": t["source"]})
        model = c["model"]
        row.update({"T_s": c["noise"]["time_constant_s"], "sigma_n": model["sigma_n"],
                    "sigma_mu": model["sigma_mu"], "sigma_mu_unit": model.get("sigma_mu_unit"),
                    "model_error": model.get("error")})
        rows.append(row)
    return rows


def csv_value(v):
    """A cell of fleet.csv: empty for a missing value, floats as repr (the
    shortest text that reads back to the same double)."""
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    return str(v)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for row in rows:
            w.writerow([csv_value(row[k]) for k in COLUMNS])


def robust_stats(values):
    """min, median, max and scaled MAD of a list of numbers."""
    med = statistics.median(values)
    mad = MAD_SCALE * statistics.median(abs(v - med) for v in values)
    return {"n": len(values), "min": min(values), "median": med, "max": max(values), "mad": mad}


def is_outlier(value, stats):
    """Further than OUTLIER_MADS scaled MADs from the median (any departure
    when the MAD is zero: most of the fleet agrees exactly)."""
    deviation = abs(value - stats["median"])
    if stats["mad"] == 0.0:
        return deviation > 0.0
    return deviation > OUTLIER_MADS * stats["mad"]


def fleet_statistics(rows):
    """Per channel and term (N, B): the fleet's statistics over the estimates
    (upper bounds and missing values left out) and the outliers' files.
    Returns {(channel, symbol): stats} and the set of (file, channel, symbol)
    flagged."""
    stats, flagged = {}, set()
    for channel in dict.fromkeys(r["channel"] for r in rows):
        for symbol in ("N", "B"):
            own = [r for r in rows if r["channel"] == channel and r[symbol] is not None
                   and r[f"{symbol}_source"] != UPPER_BOUND]
            if not own:
                continue
            s = robust_stats([r[symbol] for r in own])
            s["unit"] = own[0][f"{symbol}_unit"]
            s["outliers"] = [r["file"] for r in own if is_outlier(r[symbol], s)]
            flagged.update((f, channel, symbol) for f in s["outliers"])
            stats[(channel, symbol)] = s
    return stats, flagged


def fmt(v, digits=4):
    """A number for the page (the CSV and JSON keep every digit)."""
    if v is None:
        return "—"
    if isinstance(v, float):
        return format(v, f".{digits}g")
    return html.escape(str(v))


def write_html(path, title, rows, stats, flagged, errors, options):
    """summary.html: self-contained (inline style, no script, no external file)."""
    e = html.escape
    given = ", ".join(f"{k}={v}" for k, v in options.items())
    out = [f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{e(title)}</title>",
           "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;"
           "margin:0.5em 0 1.5em}th,td{border:1px solid #bbb;padding:0.2em 0.5em;text-align:right}"
           "th{background:#eee}td.t{text-align:left}td.out{background:#fcc;font-weight:bold}"
           ".note{color:#555;font-size:0.9em}</style></head><body>",
           f"<h1>{e(title)}</h1>",
           f"<p class=\"note\">{len(set(r['file'] for r in rows))} files analyzed, {len(errors)} failed. "
           f"Options: {e(given)}. N, B, K are analysis.json's reported terms (noise.reported); "
           "&lt; marks an upper bound. Outliers (red): further than "
           f"{OUTLIER_MADS:g} &times; {MAD_SCALE} &times; MAD from the fleet's median of the channel; "
           "upper bounds are left out of the statistics. Full precision in fleet.csv and fleet.json.</p>",
           "<h2>Across the fleet</h2><table><tr><th>channel</th><th>term</th><th>unit</th><th>estimates</th>"
           "<th>min</th><th>median</th><th>max</th><th>scaled MAD</th><th>outliers</th></tr>"]
    for (channel, symbol), s in stats.items():
        out.append(f"<tr><td class=\"t\">{e(channel)}</td><td class=\"t\">{symbol}</td><td class=\"t\">"
                   f"{e(s['unit'])}</td><td>{s['n']}</td><td>{fmt(s['min'])}</td><td>{fmt(s['median'])}</td>"
                   f"<td>{fmt(s['max'])}</td><td>{fmt(s['mad'], 2)}</td><td class=\"t\">"
                   f"{e(', '.join(s['outliers'])) or '—'}</td></tr>")
    out.append("</table><h2>Every file and channel</h2><table><tr>")
    shown = ("file", "channel", "unit", "samples", "rate_hz", "N", "B", "K", "T_s", "sigma_n", "sigma_mu")
    out.extend(f"<th>{k}</th>" for k in shown)
    out.append("</tr>")
    for r in rows:
        cells = []
        for k in shown:
            if k in ("N", "B", "K"):
                value = fmt(r[k])
                if r[f"{k}_source"] == UPPER_BOUND:
                    value = "&lt; " + value
                elif r[f"{k}_sigma"] is not None:
                    value += " ± " + fmt(r[f"{k}_sigma"], 2)
                if r[k] is not None:
                    value += f" {e(r[f'{k}_unit'])}"
                css = "out" if (r["file"], r["channel"], k) in flagged else ""
                cells.append(f"<td class=\"{css}\">{value}</td>")
            elif k in ("file", "channel", "unit"):
                cells.append(f"<td class=\"t\">{e(str(r[k]))}</td>")
            else:
                cells.append(f"<td>{fmt(r[k])}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    if errors:
        out.append("<h2>Files not analyzed</h2><ul>")
        out.extend(f"<li>{e(f)}: {e(msg)}</li>" for f, msg in errors)
        out.append("</ul>")
    out.append("</body></html>\n")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out))


def run(client, paths, options):
    """One task per file on the client's cluster; the results by path, as the
    tasks finish (reported on stderr)."""
    futures = client.map(analyze_file, paths, options=options, pure=False)
    results = {}
    for future in as_completed(futures):
        result = future.result()
        results[result["path"]] = result
        status = result.get("error") or f"{len(result['analysis']['channels'])} channels"
        print(f"  {os.path.basename(result['path'])}: {status}", file=sys.stderr)
    return results


def main(argv=None):
    p = argparse.ArgumentParser(
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="By default a LocalCluster of --workers processes (one thread each) runs the tasks; its workers "
               "inherit PYTHONPATH and import cubecal themselves. With --scheduler, the tasks run on that "
               "cluster's workers: each needs the cubecal module (PYTHONPATH=.../build/python or an installed "
               "package), NumPy, and the files at the same paths (a shared file system).")
    p.add_argument("directory", help="directory of logs")
    p.add_argument("--pattern", default="*.csv*",
                   help="file names to analyze, a glob relative to DIRECTORY ('**/*.csv' descends; default '*.csv*')")
    p.add_argument("--columns", help="columns to analyze, names or 1-based indices (default: as cubecal analyze)")
    p.add_argument("--unit", help="unit of the channels, one for all or a comma list (deg/s, rad/s, g, mGauss, ...;"
                                  " default: from the column names)")
    p.add_argument("--taus", default="log:10", help="tau grid of the Allan curves (default log:10)")
    p.add_argument("--temp-col", help="temperature column: regress each channel on it")
    p.add_argument("--threads", type=int, default=1,
                   help="threads of one analysis (default 1: the workers share the cores)")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="worker processes of the LocalCluster (default: the number of cores)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="a running Dask scheduler (tcp://host:8786) instead of a LocalCluster")
    p.add_argument("--out", default="fleet-out", help="output directory (default fleet-out)")
    args = p.parse_args(argv)
    if args.workers < 1:
        p.error("--workers: at least 1")

    directory = Path(args.directory).resolve()
    if not directory.is_dir():
        p.error(f"{args.directory}: not a directory")
    files = sorted(f for f in directory.glob(args.pattern) if f.is_file())
    if not files:
        p.error(f"no file in {args.directory} matches {args.pattern!r}")
    options = {"unit": args.unit, "columns": args.columns, "taus": args.taus, "temperature": args.temp_col,
               "threads": args.threads}
    options = {k: v for k, v in options.items() if v is not None}

    with contextlib.ExitStack() as stack:
        if args.scheduler:
            client = stack.enter_context(Client(args.scheduler))
            where = args.scheduler
        else:
            if importlib.util.find_spec("cubecal") is None:
                p.error("cannot import cubecal: set PYTHONPATH to the build tree's python directory")
            cluster = stack.enter_context(LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                                       processes=True, dashboard_address=None))
            client = stack.enter_context(Client(cluster))
            where = f"a LocalCluster of {args.workers} workers"
        print(f"Analyzing {len(files)} files on {where}", file=sys.stderr)
        results = run(client, [str(f) for f in files], options)

    rows, analyses, errors = [], [], []
    for f in files:
        name = f.relative_to(directory).as_posix()
        result = results[str(f)]
        if "error" in result:
            errors.append((name, result["error"]))
            analyses.append({"file": name, "error": result["error"]})
        else:
            rows.extend(rows_of(name, result["analysis"]))
            analyses.append({"file": name, "analysis": result["analysis"]})
    stats, flagged = fleet_statistics(rows)

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / "fleet.csv", rows)
    summary = [{"channel": c, "term": s, **v} for (c, s), v in stats.items()]
    with open(out / "fleet.json", "w") as f:
        json.dump({"directory": str(directory), "pattern": args.pattern, "options": options, "columns": COLUMNS,
                   "rows": rows, "summary": summary, "files": analyses}, f, indent=1, allow_nan=False)
        f.write("\n")
    write_html(out / "summary.html", f"cubecal fleet: {directory}", rows, stats, flagged, errors, options)
    for name, message in errors:
        print(f"not analyzed: {name}: {message}", file=sys.stderr)
    print(f"{len(files) - len(errors)} of {len(files)} files analyzed, {len(rows)} rows: "
          f"{out / 'fleet.csv'}, {out / 'fleet.json'}, {out / 'summary.html'}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
