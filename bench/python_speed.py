#!/usr/bin/python3
"""cubecal's AllanTools-shaped calls beside AllanTools itself, in the same run (`make bench`).

    PYTHONPATH=BUILD/python python_speed.py BUILD [RUNS] [--only suite,arrays,oadev] [--budget SECONDS]

suite   the calls of AllanTools' own test suite (the tests/ directory of its
        source), made as the suite makes them: the data as the suite passes
        them (Python lists read line by line, as its testutils.read_datafile
        does, or the arrays a test builds), one call per row of a Stable32
        table with a single tau, short tau lists, taus "all"/"octave"/"decade",
        phase and frequency data, from the 10-point and 1000-point NBS14 sets
        to the 5071A's 556,990 phase points; every deviation the suite calls
        (adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev,
        htotdev, mtie, tierms, gradev; theo1, pdev, gcodev) and its CI and
        noise-ID calls (edf_greenhall, confidence_interval, edf_totdev,
        edf_mtotdev, confidence_interval_noiseID, autocorr_noise_id). A case
        whose functions cubecal does not have is left out and named.
arrays  numpy float64 records of 1e5 and 1e6 samples at octave taus (tierms,
        mtie and gradev at 1e5 only: AllanTools takes 2-13 s for them at 1e6).
oadev   one 72 h x 10 Hz gyro channel (2,592,000 samples, cubecal.simulate,
        seed 1), frequency data, oadev at AllanTools' octave taus and at
        cubecal's log:20 grid, and the same work called from C++
        (bench_deviation_call): the Python call's overhead. RUNS runs each.

A case times the call as a user makes it (list or array in, result out),
cubecal and AllanTools alternately, each at least 3 times and again while the
case has taken less than --budget seconds (3 s; at most 5 x RUNS times), single
threaded on both sides. Per case: min / median / max seconds of one run (all
its calls), the ratio of the medians (AllanTools / cubecal), and the largest
relative difference of the results (taus and ns must be equal; the errors of
the deviations are not compared: cubecal gives dev / sqrt(n) for tierms, where
AllanTools gives zeros, and finite gradev error bars). The suite and arrays
tables are printed and written as markdown to BENCH_OUT/python_speed.md.

AllanTools' source: ALLANTOOLS_SRC (a checkout of github.com/aewallin/allantools,
with its tests/), else BENCH_OUT/allantools (cloned there by bench/limits.sh);
without it only cubecal's side of the oadev part is printed.
"""
import argparse
import contextlib
import datetime
import gzip
import importlib.util
import io
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import cubecal
from bench_timing import span, timed

DEVIATIONS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev")
NBS14_10 = DEVIATIONS + ("mtotdev", "ttotdev", "htotdev")


class Calls:
    """A case's calls, each (name, args, kwargs), made in one run on cubecal or
    allantools; with `caught`, the exception AllanTools' suite catches
    (NotImplementedError where a noise cannot be identified) is a result,
    compared by the built-in class caught."""

    def __init__(self, items, caught=False):
        self.items, self.caught = list(items), caught
        self.needs = sorted({name for name, _, _ in self.items})

    def __call__(self, mod):
        return [self._one(getattr(mod, name), args, kwargs) for name, args, kwargs in self.items]

    def _one(self, function, args, kwargs):
        if not self.caught:
            return function(*args, **kwargs)
        try:
            return function(*args, **kwargs)
        except (NotImplementedError, ValueError, RuntimeError) as e:
            # The built-in class a caller catches: cubecal's NoEstimateError
            # is a NotImplementedError, as AllanTools raises.
            return next(c.__name__ for c in (NotImplementedError, RuntimeError, ValueError) if isinstance(e, c))


class Case:
    """One row of the table: `run` (Calls) on both modules; kind "dev"
    compares (taus, devs, errs, ns) tuples, "num" numbers or tuples of
    numbers (an exception's name compared as a name)."""

    def __init__(self, label, data, run, kind="dev"):
        self.label, self.data, self.run, self.kind = label, data, run, kind
        self.calls, self.needs = len(run.items), run.needs


def each_tau(name, data, rate, taus, **kw):
    """The suite's row-by-row call: one call per tau, taus=[tau]."""
    return Calls((name, (data,), dict(rate=rate, taus=[t], **kw)) for t in taus)


# ---------------------------------------------------------------- input data
def read_values(path):
    """One number per line, '#' lines skipped: a Python list, as the suite reads it."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return [float(line) for line in f if not line.startswith("#")]


def stable32_rows(path, rate):
    """(tau, m, alpha) of each row of a Stable32 result table (7 columns, or
    4 for MTIE/TIE), tau = m / rate as the suite sets it."""
    rows = []
    with open(path) as f:
        for line in f:
            cols = line.split()
            if line.startswith("#") or len(cols) not in (4, 7):
                continue
            m = float(cols[0])
            rows.append((m * (1.0 / rate), m, float(cols[3]) if len(cols) == 7 else None))
    return rows


def test_module(tests, relative):
    """A module of AllanTools' suite, for the data it defines (the NBS14 sets);
    None when it cannot be imported (it imports pytest)."""
    name = "at_" + os.path.basename(relative)[:-3]
    spec = importlib.util.spec_from_file_location(name, os.path.join(tests, relative))
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except ImportError as e:
        print(f"  the cases on {relative} left out: {e}")
        return None
    return module


# ---------------------------------------------------------------- the cases
def small_cases(tests, at):
    """The NBS14 sets (when their modules import), then the functional tests'."""
    n10 = test_module(tests, "nbs14/test_nbs14_10point.py")
    n1k = test_module(tests, "nbs14/test_nbs14_1000point.py")
    if n10 is not None and n1k is not None:
        yield from nbs14_cases(n10, n1k)
    yield from functional_cases(tests)


def nbs14_cases(n10, n1k):
    """The NBS14 sets: 10 points (phase and frequency lists), 1000 points
    (frequency list, phase array from AllanTools' frequency2phase)."""
    yield Case("nbs14 10-point, 10 deviations, phase + freq", "lists of 10 / 9, taus [1, 2]",
               Calls([(f, (n10.nbs14_phase,), dict(rate=1.0, taus=[1, 2])) for f in NBS14_10]
                     + [(f, (n10.nbs14_f,), dict(rate=1.0, data_type="freq", taus=[1, 2])) for f in NBS14_10]))
    yield Case("nbs14 1000-point, 7 deviations, phase + freq", "array / list of 1000, taus [1, 10, 100]",
               Calls([(f, (n1k.pdata,), dict(rate=1.0, taus=[1, 10, 100])) for f in DEVIATIONS]
                     + [(f, (n1k.fdata,), dict(rate=1.0, data_type="freq", taus=[1, 10, 100])) for f in DEVIATIONS]))
    yield Case("nbs14 1000-point theo1, phase + freq", "array / list of 1000, taus [10, 100, 1000]",
               Calls([("theo1", (n1k.pdata,), dict(rate=1.0, taus=[10, 100, 1000])),
                      ("theo1", (n1k.fdata,), dict(rate=1.0, data_type="freq", taus=[10, 100, 1000]))]))
    yield Case("nbs14 1000-point pdev, phase + freq", f"array / list of 1000, {len(n1k.pdev_taus)} taus",
               Calls([("pdev", (n1k.pdata,), dict(rate=1.0, taus=n1k.pdev_taus)),
                      ("pdev", (n1k.fdata,), dict(rate=1.0, data_type="freq", taus=n1k.pdev_taus))]))


def functional_cases(tests):
    """The functional tests' short arrays, gradev's example, gcodev's."""
    rng = np.random.default_rng(1)
    d = rng.random(128)
    yield Case("tau generator: adev, taus [], all, octave, decade, [1..4]", "array of 128",
               Calls([("adev", (d,), dict(taus=[]))]
                     + [("adev", (d,), dict(rate=1.0, taus=t)) for t in ("all", "octave", "decade", [1, 2, 3, 4])]))
    white = rng.standard_normal(500)
    insane = [t for t in np.logspace(0, 4, 4000)]
    yield Case("test_ns: 9 deviations at 4000 taus", "array of 500, list of 4000 taus",
               Calls((f, (white,), dict(rate=1.0, taus=insane)) for f in DEVIATIONS + ("mtie", "tierms")))
    g = os.path.join(tests, "gradev")
    x, y, y_gap = (np.loadtxt(os.path.join(g, f)) for f in ("x.dat", "y.dat", "y_gap.dat"))
    yield Case("gradev, with and without gaps", "arrays of 1000, 1000 taus",
               Calls(("gradev", (v,), dict(data_type="phase", rate=1, taus=x)) for v in (y, y_gap)))
    a, b, c = (rng.standard_normal(100_000) * k for k in (1.0, 5.0, 10.0))
    yield Case("gcodev, three pairs of a three-cornered hat", "arrays of 100000, octave",
               Calls(("gcodev", pair, dict(rate=1, taus="octave")) for pair in ((a - b, c - a), (a - b, b - c),
                                                                                 (c - a, b - c))))


def phasedat_cases(tests, at):
    """PHASE.DAT (1003 phase points, a list), one call per Stable32 row."""
    p = os.path.join(tests, "phasedat")
    phase = read_values(os.path.join(p, "PHASE.DAT"))
    tables = [(f, f"phase_dat_{f}.txt") for f in DEVIATIONS + ("tierms", "mtie")]
    tables += [(f, f"phase_dat_{f}_octave.txt") for f in ("mtotdev", "ttotdev")]
    tables += [("htotdev", "phase_dat_htotdev_octave_nobias.txt"), ("theo1", "phase_dat_theo1_alpha0_decade.txt")]
    for name, table in tables:
        taus = [r[0] for r in stable32_rows(os.path.join(p, table), 1.0)]
        yield Case(f"PHASE.DAT {name}, the rows of {table}", f"list of {len(phase)}, 1 tau per call",
                   each_tau(name, phase, 1.0, taus))
    yield from ci_cases(p, phase, at)


def ci_cases(p, phase, at):
    """test_phasedat_with_ci: the EDFs and intervals at the octave rows, the noise ID."""
    configs = (("adev", 2, False, False), ("oadev", 2, True, False), ("mdev", 2, True, True),
               ("hdev", 3, False, False), ("ohdev", 3, True, False))
    edf_calls, ci_calls = [], []
    for name, d, overlapping, modified in configs:
        for tau, m, _ in stable32_rows(os.path.join(p, f"phase_dat_{name}_octave.txt"), 1.0):
            kw = dict(alpha=0, d=d, m=int(m), N=len(phase), overlapping=overlapping, modified=modified)
            edf_calls.append(("edf_greenhall", (), kw))
            dev = float(getattr(at, name)(phase, rate=1.0, taus=[tau])[1][0])
            ci_calls.append(("confidence_interval", (), dict(dev=dev, edf=at.edf_greenhall(**kw))))
    yield Case("edf_greenhall, PHASE.DAT octave rows of 5 deviations", f"alpha 0, N {len(phase)}",
               Calls(edf_calls), "num")
    yield Case("confidence_interval at those EDFs", "dev, edf", Calls(ci_calls), "num")
    totals = [("edf_totdev", len(phase), r[0])
              for r in stable32_rows(os.path.join(p, "phase_dat_totdev_octave.txt"), 1.0)]
    totals += [("edf_mtotdev", len(phase), r[0])
               for r in stable32_rows(os.path.join(p, "phase_dat_mtotdev_octave.txt"), 1.0)]
    yield Case("edf_totdev, edf_mtotdev, octave rows", f"N {len(phase)}, alpha 0",
               Calls((name, (n, t), dict(alpha=0)) for name, n, t in totals), "num")
    rows = stable32_rows(os.path.join(p, "phase_dat_adev_octave.txt"), 1.0)
    devs = at.adev(phase, taus=[r[0] for r in rows])[1]
    yield Case("confidence_interval_noiseID, adev octave rows", f"list of {len(phase)}",
               Calls((("confidence_interval_noiseID", (phase, float(dev)), dict(af=int(r[1]), dev_type="adev",
                                                                              data_type="phase"))
                      for r, dev in zip(rows, devs)), caught=True), "num")
    afs = [int(r[1]) for r in stable32_rows(os.path.join(p, "phase_dat_oadev_octave.txt"), 1.0)]
    yield Case("autocorr_noise_id, PHASE.DAT, octave AFs", f"list of {len(phase)}",
               Calls((("autocorr_noise_id", (phase,), dict(af=af)) for af in afs), caught=True), "num")


def record_cases(tests, at):
    """The longer records: pink (10,003 freq), OCXO (19,985 freq), the
    53230A TIC (55,698 phase), GPS (241,223 phase), 5071A (556,990 phase)."""
    pink = read_values(os.path.join(tests, "pink_frequency", "pink_frequency.txt"))
    taus = [r[0] for r in stable32_rows(os.path.join(tests, "pink_frequency", "oadev.txt"), 1 / 42.0)]
    yield Case("pink oadev, freq, Stable32 rows", f"list of {len(pink)}, rate 1/42, 1 tau per call",
               each_tau("oadev", pink, 1 / 42.0, taus, data_type="freq"))
    ocxo = at.frequency2fractional(read_values(os.path.join(tests, "ocxo", "ocxo_frequency.txt")), mean_frequency=1.0e7)
    taus = [r[0] for r in stable32_rows(os.path.join(tests, "ocxo", "adev_octave.txt"), 1.0)]
    yield Case("OCXO adev, fractional freq, octave rows", f"array of {len(ocxo)}, 1 tau per call",
               each_tau("adev", ocxo, 1.0, taus, data_type="freq"))
    tic = read_values(os.path.join(tests, "Keysight53230A_ti_noise_floor", "tic_phase.txt"))
    taus = [r[0] for r in stable32_rows(os.path.join(tests, "Keysight53230A_ti_noise_floor", "tic_mdev.txt"), 1.0)]
    yield Case("53230A TIC mdev, Stable32 rows", f"list of {len(tic)}, 1 tau per call",
               each_tau("mdev", tic, 1.0, taus))
    gps = read_values(os.path.join(tests, "gps", "gps_1pps_phase_data.txt.gz"))
    rows = stable32_rows(os.path.join(tests, "gps", "stable32_ADEV_decade.txt"), 1.0)
    yield Case("GPS adev, the decade taus in one call", f"list of {len(gps)}, {len(rows)} taus",
               Calls([("adev", (gps,), dict(rate=1.0, data_type="phase", taus=[r[0] for r in rows]))]))
    yield Case("autocorr_noise_id, GPS, decade AFs", f"list of {len(gps)}",
               Calls((("autocorr_noise_id", (gps,), dict(af=int(r[1]))) for r in rows), caught=True), "num")
    cs = read_values(os.path.join(tests, "Cs5071A", "5071A_phase.txt.gz"))
    for name in DEVIATIONS + ("tierms",):
        yield Case(f"5071A {name}, one decade row (tau 100 s)", f"list of {len(cs)}, taus [100.0]",
                   each_tau(name, cs, 1.0, [100.0]))


def array_cases():
    """numpy float64 records at octave taus: random-walk phase (white FM)
    of 1e5 and 1e6 points, and 1e6 white frequency points."""
    rng = np.random.default_rng(2)
    for n in (100_000, 1_000_000):
        x = np.cumsum(rng.standard_normal(n))
        for name in DEVIATIONS + (("tierms", "mtie", "gradev") if n <= 100_000 else ()):
            yield Case(f"{name}, phase, octave", f"array of {n}", Calls([(name, (x,), dict(rate=1.0, taus="octave"))]))
    y = rng.standard_normal(1_000_000)
    for name in ("adev", "oadev", "mdev"):
        yield Case(f"{name}, freq, octave", "array of 1000000",
                   Calls([(name, (y,), dict(rate=1.0, data_type="freq", taus="octave"))]))


# ---------------------------------------------------------------- timing and checking
def measure(case, modules, runs, budget):
    """Both modules alternately (the order swapped every run): seconds per
    run (sorted), the last results, the error of a module that raised."""
    seconds = {name: [] for name in modules}
    results, errors = {}, {}
    start = time.perf_counter()
    for i in range(runs):
        for name in (list(modules) if i % 2 == 0 else list(reversed(modules))):
            if name in errors:
                continue
            t0 = time.perf_counter()
            try:
                results[name] = case.run(modules[name])
            except Exception as e:  # a call cubecal does not take yet: reported in the row
                errors[name] = f"{type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"[:70]
                continue
            seconds[name].append(time.perf_counter() - t0)
        if i + 1 >= 3 and time.perf_counter() - start > budget:
            break
    return {n: sorted(s) for n, s in seconds.items()}, results, errors


def rel_diff(a, b):
    a, b = np.asarray(a, dtype=np.float64).ravel(), np.asarray(b, dtype=np.float64).ravel()
    if a.shape != b.shape:
        return np.inf
    both_nan = np.isnan(a) & np.isnan(b)
    same = (a == b) | both_nan
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(same, 0.0, np.abs(a - b) / np.abs(b))
    return float(np.max(np.where(np.isnan(d), np.inf, d), initial=0.0))


def check(kind, ours, theirs):
    """The largest relative difference, or what differs."""
    if len(ours) != len(theirs):
        return "other number of results"
    worst, notes = 0.0, set()
    for a, b in zip(ours, theirs):
        if kind == "dev":
            if np.shape(a[0]) != np.shape(b[0]) or not np.allclose(a[0], b[0], rtol=1e-12, atol=0):
                return f"taus differ ({len(a[0])} / {len(b[0])})"
            if not np.array_equal(np.asarray(a[3], dtype=np.float64), np.asarray(b[3], dtype=np.float64)):
                notes.add("ns differ")
            worst = max(worst, rel_diff(a[1], b[1]))
        elif isinstance(a, str) or isinstance(b, str):
            if a != b:
                notes.add(f"{a if isinstance(a, str) else 'a result'} / {b if isinstance(b, str) else 'a result'}")
        else:
            worst = max(worst, rel_diff(a, b))
    text = "0" if worst == 0 else f"{worst:.1e}"
    return "; ".join([text] + sorted(notes))


def seconds_span(s):
    return f"{s[0]:.3g} / {s[len(s) // 2]:.3g} / {s[-1]:.3g}" if s else "-"


def row(case, modules, runs, budget):
    with contextlib.redirect_stdout(io.StringIO()):  # AllanTools prints where it cannot identify a noise
        seconds, results, errors = measure(case, modules, runs, budget)
    cc, at = seconds.get("cubecal", []), seconds.get("allantools", [])
    ratio = f"{at[len(at) // 2] / cc[len(cc) // 2]:.1f}x" if cc and at else "-"
    if errors:
        same = "; ".join(f"{n}: {e}" for n, e in errors.items())
    elif "allantools" in results:
        same = check(case.kind, results["cubecal"], results["allantools"])
    else:
        same = "-"
    return [case.label, case.data, str(case.calls), seconds_span(cc), seconds_span(at), ratio, same, len(cc)]


def agrees(cells):
    """The results agree: no error, equal taus and ns, within 1e-9."""
    try:
        return cells[6] == "-" or float(cells[6]) <= 1e-9
    except ValueError:
        return False


HEADER = ["case", "data", "calls", "cubecal s (min / median / max)", "AllanTools s (min / median / max)",
          "AllanTools / cubecal", "largest rel. diff", "runs"]


def print_row(r):
    print(f"  {r[0][:58]:58s} {r[1][:32]:32s} {r[2]:>5s} {r[3]:31s} {r[4]:31s} {r[5]:>7s}  {r[6]}  ({r[7]})",
          flush=True)


def markdown(title, rows):
    lines = [f"### {title}", "", "| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def compare_parts(parts, src, allantools, runs, budget, out_dir):
    if not parts:
        return
    modules = {"cubecal": cubecal}
    if allantools is not None:
        modules["allantools"] = allantools
    tests = os.path.join(src, "tests")
    load0, start = os.getloadavg()[0], time.perf_counter()
    sections, skipped = [], set()
    for part in parts:
        if part == "suite":
            if allantools is None or not os.path.isdir(tests):
                print(f"== suite shapes: no AllanTools tests/ at {src}: skipped")
                continue
            title = "AllanTools' test suite's calls"
            makers = (small_cases, phasedat_cases, record_cases)
            cases = (c for make in makers for c in make(tests, allantools))
        else:
            title = "numpy float64 arrays, octave taus"
            cases = array_cases()
        print(f"== Python: {title}, cubecal vs AllanTools; seconds per run of a case's calls, "
              f"min / median / max (3 to {runs} runs, about {budget:g} s a case)", flush=True)
        print(f"  {'case':58s} {'data':32s} {'calls':>5s} {'cubecal s':31s} {'AllanTools s':31s} {'ratio':>7s}  "
              "largest rel. diff  (runs)")
        rows = []
        for case in cases:
            missing = [n for n in case.needs if not hasattr(cubecal, n)]
            if missing:
                skipped.update(missing)
                continue
            rows.append(row(case, modules, runs, budget))
            print_row(rows[-1])
        sections.append((title, rows))
    took = time.perf_counter() - start
    differ = [r[0] for _, rows in sections for r in rows if not agrees(r)]
    if differ:
        print(f"  results differ from AllanTools' (see the rows) in: {'; '.join(differ)}")
    if skipped:
        print(f"  not timed, cubecal has no {', '.join(sorted(skipped))}")
    print(f"  (these parts took {took:.0f} s; load average {load0:.1f} at the start, "
          f"{os.getloadavg()[0]:.1f} at the end)")
    if sections and out_dir:
        write_markdown(os.path.join(out_dir, "python_speed.md"), sections, src, allantools, took, load0,
                       sorted(skipped))


def write_markdown(path, sections, src, allantools, took, load0, skipped):
    version = getattr(allantools, "__version__", "?") if allantools else "absent"
    head = [f"Measured {datetime.date.today().isoformat()} by `bench/python_speed.py` (`make bench`): cubecal "
            f"{cubecal.__version__}, AllanTools {version} from {src}, {os.cpu_count()} cores, load average "
            f"{load0:.1f} at the start and {os.getloadavg()[0]:.1f} at the end; these tables took {took:.0f} s. "
            "Seconds per run of a case's calls; the ratio is of the medians; the largest relative difference is "
            "of the deviations (or numbers) returned, with equal taus and ns."]
    if skipped:
        head += ["", f"Not timed (cubecal has no {', '.join(skipped)} in this build)."]
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write("\n".join(head) + "\n\n" + "\n".join(markdown(t, r) for t, r in sections))
    print(f"  table written to {path}")


# ---------------------------------------------------------------- the oadev part
def oadev_part(build, runs, allantools):
    """cubecal.oadev vs allantools.oadev on 2,592,000 samples, and the C++ call."""
    y = cubecal.simulate("sport-gyro", rate=10, duration="72h", seed=1, temperature="const:25")["gx"]
    rate = 10.0
    log20 = cubecal.dev(y, rate=rate, taus="log:20", intervals=False).tau
    print(f"== Python: cubecal.oadev vs allantools.oadev, {y.size} samples, freq data, one thread each, "
          f"min / median / max of {runs}")
    for label, taus in (("octave", "octave"), ("log:20", log20)):
        cc, (t1, d1, _, _) = timed(lambda: cubecal.oadev(y, rate=rate, data_type="freq", taus=taus), runs)
        line = f"  {label:7s} {len(t1):4d} taus  cubecal {span(cc)}"
        if allantools is not None:
            at, (t0, d0, _, _) = timed(lambda: allantools.oadev(y, rate=rate, data_type="freq", taus=taus), runs)
            if not np.array_equal(t0, t1):
                sys.exit(f"allantools and cubecal gave other taus at {label}")
            diff = float(np.max(np.abs(d1 / d0 - 1.0)))
            line += (f"  allantools {span(at)}  ratio {at[len(at) // 2] / cc[len(cc) // 2]:.1f}x  "
                     f"max rel diff {diff:.1e}")
        print(line)
        # The same work from C++: the Python call's overhead is the difference.
        with tempfile.TemporaryDirectory() as d:
            samples, factors = os.path.join(d, "y.f64"), os.path.join(d, "m.txt")
            np.ascontiguousarray(y, dtype=np.float64).tofile(samples)
            np.savetxt(factors, np.round(t1 * rate).astype(np.int64), fmt="%d")
            out = subprocess.run([os.path.join(build, "bin", "bench_deviation_call"), samples, factors, str(rate),
                                  str(runs)], capture_output=True, text=True, check=True).stdout.split()
            cpp = sorted(float(x) for x in out)
            py_median = cc[len(cc) // 2]
            print(f"          C++ call {cpp[0]:.4f} / {cpp[1]:.4f} / {cpp[2]:.4f} s; the Python call adds "
                  f"{(py_median - cpp[1]) * 1e3:.2f} ms ({100 * (py_median / cpp[1] - 1):.1f} %) at the median")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build")
    parser.add_argument("runs", nargs="?", type=int, default=5)
    parser.add_argument("--only", default="suite,arrays,oadev", help="comma-separated parts: suite, arrays, oadev")
    parser.add_argument("--budget", type=float, default=3.0,
                        help="a case runs again while it has taken less than this many seconds (3 runs at least)")
    args = parser.parse_args()
    out_dir = os.environ.get("BENCH_OUT", "bench-out")
    src = os.environ.get("ALLANTOOLS_SRC") or os.path.join(out_dir, "allantools")
    allantools = None
    if os.path.isfile(os.path.join(src, "allantools", "allantools.py")):
        sys.path.insert(0, src)
        import allantools
    parts = [p for p in args.only.split(",") if p]
    unknown = set(parts) - {"suite", "arrays", "oadev"}
    if unknown:
        parser.error(f"--only: unknown part {', '.join(sorted(unknown))} (suite, arrays, oadev)")
    most = 5 * max(args.runs, 1)
    compare_parts([p for p in parts if p != "oadev"], src, allantools, most, args.budget, out_dir)
    if "oadev" in parts:
        oadev_part(args.build, args.runs, allantools)
    if allantools is None:
        print(f"  (no AllanTools source at {src}: set ALLANTOOLS_SRC to a checkout of github.com/aewallin/allantools)")


if __name__ == "__main__":
    main()
