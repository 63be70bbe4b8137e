"""cubecal.ci, AllanTools' allantools.ci on cubecal's library: every function
against AllanTools' own (its public source run here, when ALLANTOOLS_SRC or
CUBECAL_ALLANTOOLS_SRC names a checkout; skipped otherwise) over a grid of
alpha, d, overlapping, modified, m and N and on the Stable32 datasets; the
EDFs and intervals against Stable32's tables (the reference for real data);
and the refusals of bad arguments."""
import contextlib
import gzip
import io
import math
import os
import unittest

import numpy as np

import cubecal
import cubecal.ci as ci
from support import STABLE32, allantools, phase_dat, stable32_table


def relative(a, b):
    a, b = float(a), float(b)
    return abs(a - b) / max(abs(b), 1e-300)


def quiet(f, *args, **kwargs):
    """AllanTools' call with its prints (edf_mtotdev, verbose) swallowed."""
    with contextlib.redirect_stdout(io.StringIO()):
        return f(*args, **kwargs)


def gps_phase():
    with gzip.open(os.path.join(STABLE32, "gps", "gps_1pps_phase_data.txt.gz"), "rt") as f:
        return np.loadtxt(f)


def ocxo_frequency():
    return (np.loadtxt(os.path.join(STABLE32, "ocxo", "ocxo_frequency.txt")) - 1e7) / 1e7


def allantools_ci():
    at = allantools()
    import allantools.ci as at_ci
    return at, at_ci


ALPHAS = (2, 1, 0, -1, -2, -3, -4)
FACTORS = (1, 2, 3, 4, 8, 16, 64, 128)
LENGTHS = (64, 1000, 10000, 100000)


class EdfParity(unittest.TestCase):
    """The EDF functions equal AllanTools' to rounding."""

    @classmethod
    def setUpClass(cls):
        cls.at, cls.ci = allantools_ci()

    def test_edf_greenhall_grid(self):
        compared = unsupported = 0
        for alpha in ALPHAS:
            for d in (1, 2, 3):
                if alpha + 2 * d <= 1:
                    with self.assertRaises(ci.NoEstimateError):
                        ci.edf_greenhall(alpha, d, 4, 1000)
                    continue
                for overlapping in (False, True):
                    for modified in (False, True):
                        for m in FACTORS:
                            for n in LENGTHS:
                                span = m * (d + 1) if modified else 1 + m * d
                                if n < span:
                                    with self.assertRaises(cubecal.UsageError):
                                        ci.edf_greenhall(alpha, d, m, n, overlapping, modified)
                                    continue
                                with self.subTest(alpha=alpha, d=d, overlapping=overlapping, modified=modified,
                                                  m=m, N=n):
                                    mine = ci.edf_greenhall(alpha, d, m, n, overlapping, modified)
                                    try:
                                        theirs = self.ci.edf_greenhall(alpha, d, m, n, overlapping, modified)
                                    except NotImplementedError:
                                        # White PM, unmodified, ceil(r) <= d: the direct sum here.
                                        unsupported += 1
                                        self.assertTrue(alpha == 2 and not modified)
                                        self.assertGreater(mine, 0.0)
                                        continue
                                    except AssertionError:
                                        # AllanTools' greenhall_table2 refuses its own alpha = -4 row.
                                        unsupported += 1
                                        self.assertTrue(alpha == -4 and not modified)
                                        self.assertEqual(ci.greenhall_table2(-4, 3), (1.302, 0.535))
                                        self.assertGreater(mine, 0.0)
                                        continue
                                    self.assertLess(relative(mine, theirs), 1e-11)
                                    compared += 1
        self.assertGreater(compared, 1500)
        self.assertLess(unsupported, 40)

    def test_edf_greenhall_takes_stable32_floats_and_prints_the_case(self):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            mine = ci.edf_greenhall(alpha=0.0, d=2, m=4.0, N=1000, overlapping=True, verbose=True)
            theirs = self.ci.edf_greenhall(alpha=0.0, d=2, m=4.0, N=1000, overlapping=True, verbose=True)
        lines = out.getvalue().splitlines()
        self.assertEqual(lines[0], lines[1])
        self.assertTrue(lines[0].startswith("case 2.1a edf="))
        self.assertLess(relative(mine, theirs), 1e-12)

    def test_greenhall_pieces(self):
        for alpha in ALPHAS:
            for t in (0.0, 0.25, 1.0, -2.5, 7.0):
                self.assertLess(relative(ci.greenhall_sw(t, alpha) + 1e-300, self.ci.greenhall_sw(t, alpha) + 1e-300),
                                1e-13)
                for F in (1, 4, float("inf")) if alpha <= 0 else (1, 4):
                    self.assertLess(abs(ci.greenhall_sx(t, F, alpha) - self.ci.greenhall_sx(t, F, alpha)),
                                    1e-12 * (1 + abs(self.ci.greenhall_sx(t, F, alpha))))
                    # sz is a difference of terms of the size of sw(|t| + 4): rounding on that scale.
                    scale = 1.0 + abs(self.ci.greenhall_sw(abs(t) + 4.0, alpha + 2 if F == float("inf") else alpha))
                    for d in (1, 2, 3):
                        theirs = self.ci.greenhall_sz(t, F, alpha, d)
                        self.assertLess(abs(ci.greenhall_sz(t, F, alpha, d) - theirs), 1e-13 * scale * F ** 2
                                        if F != float("inf") else 1e-13 * scale)
            for d in (1, 2, 3):
                self.assertEqual(ci.greenhall_table1(alpha, d), tuple(self.ci.greenhall_table1(alpha, d)))
                if alpha != -4:  # AllanTools' assertion refuses its own alpha = -4 row
                    self.assertEqual(ci.greenhall_table2(alpha, d), tuple(self.ci.greenhall_table2(alpha, d)))
                if alpha + 2 * d > 1:
                    for (J, M, S, F) in ((3, 10, 1, 4), (12, 50, 4, 1), (24, 300, 8, float("inf"))):
                        if F == float("inf") and alpha > 0:
                            continue
                        theirs = self.ci.greenhall_BasicSum(J, M, S, F, alpha, d)
                        self.assertLess(relative(ci.greenhall_BasicSum(J, M, S, F, alpha, d), theirs), 1e-11)
                    for (m, S, F, N) in ((4, 1, 4, 100), (4, 4, 1, 100), (8, 8, 8, 1000)):
                        theirs = self.ci.edf_greenhall_simple(alpha, d, m, S, F, N)
                        self.assertLess(relative(ci.edf_greenhall_simple(alpha, d, m, S, F, N), theirs), 1e-11)
        for d in (1, 2, 3):
            self.assertEqual(ci.greenhall_table3(1, d), tuple(self.ci.greenhall_table3(1, d)))

    def test_edf_simple_totdev_mtotdev(self):
        for alpha in (2, 1, 0, -1, -2, 5):
            for m in FACTORS:
                for n in (100, 1000, 10000):
                    with self.subTest(alpha=alpha, m=m, N=n):
                        if alpha in (2, 1) and n <= 2 * m:
                            # AllanTools: a negative EDF or the log of a negative number.
                            with self.assertRaises(cubecal.UsageError):
                                ci.edf_simple(n, m, alpha)
                            continue
                        theirs = quiet(self.ci.edf_simple, n, m, alpha)
                        if alpha == -1 and m == 1:
                            # SP 1065 Table 5: 2 (N-2)^2 / (2.3 N - 4.9); AllanTools drops the square.
                            self.assertLess(relative(theirs, 2 * (n - 2) / (2.3 * n - 4.9)), 1e-12)
                            self.assertLess(relative(ci.edf_simple(n, m, alpha), (n - 2) * theirs), 1e-12)
                            continue
                        self.assertLess(relative(ci.edf_simple(n, m, alpha), theirs), 1e-12)
                        if not (alpha == -1 and m == 1):
                            self.assertLess(relative(ci.edf_totdev(n, m, alpha), quiet(self.ci.edf_totdev, n, m, alpha)),
                                            1e-12)
                        if alpha in (2, 1, 0, -1, -2):
                            theirs = quiet(self.ci.edf_mtotdev, n, m, alpha)
                            self.assertLess(abs(ci.edf_mtotdev(n, m, alpha) - theirs), 1e-12 * (1 + abs(theirs)))


class ConfidenceParity(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.at, cls.ci = allantools_ci()

    def test_confidence_interval_grid(self):
        for dev in (1e-12, 0.5, 3.0):
            for edf in (0.7, 1.0, 2.5, 10.0, 123.4, 1e5):
                for c in (ci.ONE_SIGMA_CI, 0.9, 0.95, 0.3, 0.999):
                    lo, hi = ci.confidence_interval(dev, edf, c)
                    lo0, hi0 = self.ci.confidence_interval(dev, edf, c)
                    self.assertIsInstance(lo, np.float64)
                    self.assertLess(relative(lo, lo0), 1e-10, (dev, edf, c))
                    self.assertLess(relative(hi, hi0), 1e-10, (dev, edf, c))
        self.assertEqual(ci.ONE_SIGMA_CI, self.ci.ONE_SIGMA_CI)
        # Arrays (AllanTools takes an array of devs with one edf; cubecal
        # also an edf per dev): each element as its own call.
        devs, edfs = np.array([1.0, 2.0, 3.0]), np.array([5.0, 50.0, 500.0])
        lo, hi = ci.confidence_interval(devs, 20.0)
        lo0, hi0 = self.ci.confidence_interval(devs, 20.0)
        np.testing.assert_allclose(lo, lo0, rtol=1e-10)
        np.testing.assert_allclose(hi, hi0, rtol=1e-10)
        lo, hi = ci.confidence_interval(devs, edfs)
        for k in range(3):
            self.assertEqual((lo[k], hi[k]), ci.confidence_interval(devs[k], edfs[k]))

    def test_noise_id_pieces(self):
        rng = np.random.default_rng(34)
        series = {"white PM": rng.standard_normal(3000), "white FM": np.cumsum(rng.standard_normal(3000)),
                  "PHASE.DAT": phase_dat()}
        for name, x in series.items():
            with self.subTest(series=name):
                self.assertLess(abs(ci.lag1_acf(x) - self.ci.lag1_acf(x)), 1e-12)
                for deg in (0, 1, 2, 3):
                    r, r0 = ci.detrend(x, deg), self.ci.detrend(x, deg)
                    self.assertLess(np.max(np.abs(r - r0)), 1e-9 * np.max(np.abs(x)))
                for af in (1, 2, 5, 16):
                    self.assertLess(relative(ci.b1(x, af, 1.0), self.ci.b1(x, af, 1.0)), 1e-10)
                    self.assertLess(relative(ci.rn(x, af, 1.0), self.ci.rn(x, af, 1.0)), 1e-10)
        for n in (10, 100, 1000):
            for b in range(0, -6, -1):
                self.assertEqual(ci.b_to_mu(b), self.ci.b_to_mu(b))
                self.assertLess(relative(ci.b1_theory(n, ci.b_to_mu(b)), self.ci.b1_theory(n, self.ci.b_to_mu(b))),
                                1e-13)
                if b > -5:
                    self.assertLess(relative(ci.b1_boundary(b, n), self.ci.b1_boundary(b, n)), 1e-13)
        for af in (1, 2, 10, 1000):
            for b in (0, -1, -2, -3, -4):
                self.assertLess(relative(ci.rn_theory(af, b), self.ci.rn_theory(af, b)), 1e-13)
                self.assertLess(relative(ci.rn_boundary(af, b), self.ci.rn_boundary(af, b)), 1e-13)

    def test_autocorr_noise_id_on_real_data(self):
        cases = [("PHASE.DAT", phase_dat(), "phase"), ("gps", gps_phase(), "phase"),
                 ("ocxo", ocxo_frequency(), "freq")]
        compared = 0
        for name, x, dtype in cases:
            for af in (1, 2, 4, 8, 16, 32, 64, 128, 512):
                for dmin, dmax in ((0, 2), (0, 3), (1, 2), (2, 2)):
                    with self.subTest(data=name, af=af, dmin=dmin, dmax=dmax):
                        try:
                            theirs = quiet(self.ci.autocorr_noise_id, x, af, data_type=dtype, dmin=dmin, dmax=dmax)
                        except NotImplementedError:
                            with self.assertRaises(NotImplementedError):
                                ci.autocorr_noise_id(x, af, data_type=dtype, dmin=dmin, dmax=dmax)
                            continue
                        mine = ci.autocorr_noise_id(x, af, data_type=dtype, dmin=dmin, dmax=dmax)
                        self.assertEqual((mine[0], mine[2]), (theirs[0], theirs[2]))
                        self.assertLess(abs(mine[1] - theirs[1]), 1e-8)
                        self.assertLess(abs(mine[3] - theirs[3]), 1e-8)
                        compared += 1
        self.assertGreater(compared, 60)

    def test_confidence_interval_noise_id_on_real_data(self):
        x = phase_dat()
        for dev_type in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev"):
            for af in (1, 4, 16):
                with self.subTest(dev_type=dev_type, af=af):
                    lo, hi = ci.confidence_interval_noiseID(x, 1.0, af, dev_type=dev_type)
                    lo0, hi0 = self.ci.confidence_interval_noiseID(x, 1.0, af, dev_type=dev_type)
                    self.assertLess(relative(lo, lo0), 1e-10)
                    self.assertLess(relative(hi, hi0), 1e-10)


# (table, d, overlapping, modified) of Stable32's deviations.
GREENHALL_TABLES = {"adev": (2, False, False), "oadev": (2, True, False), "mdev": (2, True, True),
                    "tdev": (2, True, True), "hdev": (3, False, False), "ohdev": (3, True, False)}


# The tables' "Confidence Factor" (0.683, not erf(1/sqrt(2)) = 0.6827).
STABLE32_CI = 0.683


class Stable32Intervals(unittest.TestCase):
    """The EDFs with Stable32's noise types give Stable32's intervals within
    1e-3 relative, the bar of tests/test_stable32.cpp (the bounds from the
    table's rounded sigma at its confidence factor 0.683: with exact
    chi-squared quantiles the rows differ from the printed bounds by up to
    3e-4, more than the five printed digits explain)."""

    def check(self, path, n_phase, edf_of):
        rows = stable32_table(path)
        self.assertGreater(len(rows), 3)
        for r in rows:
            with self.subTest(table=os.path.basename(path), af=r["af"]):
                edf = edf_of(r)
                lo, hi = cubecal.confidence_interval(r["sigma"], edf, STABLE32_CI)
                self.assertLess(relative(lo, r["lo"]), 1e-3)
                self.assertLess(relative(hi, r["hi"]), 1e-3)

    def test_greenhall_deviations(self):
        sets = [("ocxo", "{}_octave.txt", len(ocxo_frequency()) + 1), ("phasedat", "phase_dat_{}_octave.txt", 1001),
                ("cs5071a", "{}_decade.txt", None)]
        for folder, pattern, n_phase in sets:
            if n_phase is None:
                with gzip.open(os.path.join(STABLE32, folder, "5071A_phase.txt.gz"), "rt") as f:
                    n_phase = len(np.loadtxt(f))
            for name, (d, overlapping, modified) in GREENHALL_TABLES.items():
                self.check(os.path.join(STABLE32, folder, pattern.format(name)), n_phase,
                           lambda r: cubecal.edf_greenhall(r["alpha"], d, r["af"], n_phase, overlapping, modified))

    def test_totdev(self):
        # White, flicker and random-walk FM rows: SP 1065's b N/m - c, as
        # Stable32. (Flicker PM rows: AllanTools' edf_totdev gives
        # edf_simple, Stable32 two more; see the differences page.)
        path = os.path.join(STABLE32, "ocxo", "totdev_octave.txt")
        n_phase = len(ocxo_frequency()) + 1
        rows = [r for r in stable32_table(path) if r["alpha"] in (0, -1, -2)]
        self.assertGreater(len(rows), 8)
        for r in rows:
            lo, hi = cubecal.confidence_interval(r["sigma"], cubecal.edf_totdev(n_phase, r["af"], r["alpha"]),
                                                 STABLE32_CI)
            self.assertLess(relative(lo, r["lo"]), 1e-3, r)
            self.assertLess(relative(hi, r["hi"]), 1e-3, r)
        # Flicker PM: AllanTools' edf_simple; the library's TOTDEV EDF (what
        # cubecal.dev uses) is Stable32's, two more.
        flicker = [r for r in stable32_table(path) if r["alpha"] == 1]
        self.assertGreater(len(flicker), 1)
        for r in flicker:
            self.assertEqual(cubecal.edf_totdev(n_phase, r["af"], 1), ci.edf_simple(n_phase, r["af"], 1))
            self.assertAlmostEqual(cubecal._cubecal._ci_edf_totvar(1, r["af"], n_phase) - ci.edf_simple(n_phase, r["af"], 1),
                                   2.0, places=9)


class Closed(unittest.TestCase):
    """Results that do not need AllanTools: closed forms and the module's shape."""

    def test_submodule_and_top_level_names(self):
        import importlib
        self.assertIs(importlib.import_module("cubecal.ci"), ci)
        for name in ("edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev", "confidence_interval",
                     "autocorr_noise_id", "confidence_interval_noiseID"):
            self.assertIs(getattr(cubecal, name), getattr(ci, name))
        for name in ci.__all__:
            self.assertTrue(hasattr(ci, name), name)
            f = getattr(ci, name)
            if callable(f) and not isinstance(f, type):
                self.assertIn("Returns", f.__doc__, name)

    def test_interval_closed_form(self):
        # edf = 2: chi2 quantiles are -2 ln(1 - p).
        lo, hi = ci.confidence_interval(1.0, 2.0, 0.9)
        self.assertAlmostEqual(lo, math.sqrt(2.0 / (-2.0 * math.log(0.05))), places=13)
        self.assertAlmostEqual(hi, math.sqrt(2.0 / (-2.0 * math.log(0.95))), places=13)
        # ci and 1 - ci are the same interval, as in AllanTools.
        self.assertEqual(ci.confidence_interval(1.0, 7.0, 0.1), ci.confidence_interval(1.0, 7.0, 0.9))

    def test_white_pm_edf_closed_form(self):
        # Greenhall case 4.2, non-overlapping ADEV: M / (35/18 - 1/M), M = 1 + floor((N - 1 - 2m)/m).
        m, n = 4, 1001
        M = 1 + (n - 1 - 2 * m) // m
        self.assertAlmostEqual(ci.edf_greenhall(2, 2, m, n) / (M / (35.0 / 18.0 - 1.0 / M)), 1.0, places=13)

    def test_noise_id_of_power_law_noise(self):
        rng = np.random.default_rng(7)
        self.assertEqual(ci.autocorr_noise_id(rng.standard_normal(5000), 4)[0], 2)
        self.assertEqual(ci.autocorr_noise_id(np.cumsum(rng.standard_normal(5000)), 4)[0], 0)
        self.assertEqual(ci.autocorr_noise_id(rng.standard_normal(5000), 4, data_type="freq")[0], 0)
        self.assertEqual(ci.autocorr_noise_id(np.cumsum(np.cumsum(rng.standard_normal(5000))), 4)[0], -2)
        # An (N, 1) column as AllanTools takes it.
        x = rng.standard_normal(500)
        self.assertEqual(ci.autocorr_noise_id(x[:, None], 2), ci.autocorr_noise_id(list(x), 2))

    def test_rn_theory_and_b1_theory(self):
        self.assertEqual(ci.rn_theory(8, 0), 1.0 / 8)
        self.assertEqual(ci.rn_theory(8, -2), 1.0)
        self.assertEqual(ci.b1_theory(20, -1), 1.0)
        self.assertEqual(ci.b1_theory(20, 1), 10.0)
        self.assertEqual([ci.b_to_mu(b) for b in range(0, -7, -1)], [-2, -2, -1, 0, 1, 2, 3])


class BadArguments(unittest.TestCase):
    def refused(self, option, f, *args, error=None, **kwargs):
        with self.assertRaises(error or cubecal.UsageError) as c:
            f(*args, **kwargs)
        self.assertIsInstance(c.exception, cubecal.Error)
        self.assertEqual(c.exception.option, option)
        self.assertIn(option, str(c.exception).split(":")[0])
        self.assertEqual(len(str(c.exception).splitlines()), 1)
        return c.exception

    def test_edf(self):
        self.refused("alpha", ci.edf_greenhall, 3, 2, 4, 100)
        self.refused("alpha", ci.edf_greenhall, 0.5, 2, 4, 100)
        self.refused("d", ci.edf_greenhall, 0, 4, 4, 100)
        self.refused("m", ci.edf_greenhall, 0, 2, 0, 100)
        self.refused("m", ci.edf_greenhall, 0, 2, 2.5, 100)
        self.refused("N", ci.edf_greenhall, 0, 2, 64, 100)
        self.refused("overlapping", ci.edf_greenhall, 0, 2, 4, 100, overlapping="yes")
        e = self.refused("alpha", ci.edf_greenhall, -2, 1, 4, 100, error=ci.NoEstimateError)
        self.assertIsInstance(e, NotImplementedError)
        self.refused("N", ci.edf_simple, 10, 8, 2)
        self.refused("m", ci.edf_simple, 100, -1, 0)
        self.refused("alpha", ci.edf_mtotdev, 100, 4, -3)
        self.refused("alpha", ci.greenhall_table3, 0, 2)
        self.refused("F", ci.greenhall_sx, 0.0, -1.0, 0)
        self.refused("F", ci.greenhall_sz, 0.0, float("inf"), 1, 2)

    def test_intervals(self):
        self.refused("edf", ci.confidence_interval, 1.0, 0.0)
        self.refused("edf", ci.confidence_interval, 1.0, float("nan"))
        self.refused("dev", ci.confidence_interval, -1.0, 5.0)
        self.refused("ci", ci.confidence_interval, 1.0, 5.0, 1.5)
        self.refused("ci", ci.confidence_interval, 1.0, 5.0, 0.0)
        self.refused("edf", ci.confidence_interval, [1.0, 2.0], [1.0, 2.0, 3.0])
        e = self.refused("dev_type", ci.confidence_interval_noiseID, phase_dat(), 1.0, 2, dev_type="totdev",
                         error=ci.NoEstimateError)
        self.assertIsInstance(e, NotImplementedError)

    def test_noise_id(self):
        x = np.random.default_rng(1).standard_normal(100)
        e = self.refused("af", ci.autocorr_noise_id, x, 10, error=ci.NoEstimateError)
        self.assertIsInstance(e, NotImplementedError)
        self.assertIn("30", str(e))
        self.refused("data_type", ci.autocorr_noise_id, x, 1, data_type="phaze")
        self.refused("af", ci.autocorr_noise_id, x, 0)
        self.refused("dmax", ci.autocorr_noise_id, x, 1, dmax=-1)
        self.refused("x", ci.autocorr_noise_id, np.append(x, np.nan), 1)
        self.refused("x", ci.autocorr_noise_id, np.ones((10, 2)), 1)
        self.refused("x", ci.lag1_acf, np.ones(10))
        self.refused("x", ci.lag1_acf, "abc")
        self.refused("deg", ci.detrend, x, 9)
        self.refused("af", ci.b1, x, 50, 1.0)
        self.refused("af", ci.rn, x, 40, 1.0)
        self.refused("rate", ci.rn, x, 2, 0.0)
        self.refused("x", ci.rn, np.arange(100.0), 2, 1.0)
        self.refused("b", ci.b_to_mu, 1)
        self.refused("b", ci.rn_theory, 4, 2)
        self.refused("af", ci.rn_theory, 0, 0)
        self.refused("mu", ci.b1_theory, 10, -3)


if __name__ == "__main__":
    unittest.main()
