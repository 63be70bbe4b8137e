"""AllanTools' API beyond the thirteen deviations (issue 34): the
conversions, the tau bookkeeping, pdev, gcodev, theo1, the per-factor
kernels, mtie_phase_fast, the three-cornered hat, psd2allan and the
piecewise power-law conversions, the ITU masks and the allantools.allantools
submodule, each against AllanTools' own function (its public source, run
here) on the Stable32 records (PHASE.DAT, the ocxo frequency record); and
the arguments as AllanTools takes them: a RuntimeError for rate=0 that is
also a cubecal.UsageError, NaN at the ends of frequency data trimmed, an
(N, 1) column, a list giving the numbers of an array.

AllanTools' source: ALLANTOOLS_SRC (see test_allantools_parity.py); without
it the comparisons are skipped and the argument cases still run."""
import contextlib
import io
import os
import unittest

import numpy as np

import cubecal
from support import STABLE32, allantools, phase_dat




def ocxo_hz():
    return np.loadtxt(os.path.join(STABLE32, "ocxo", "ocxo_frequency.txt"))


def ocxo():
    f = ocxo_hz()
    return (f - 1e7) / 1e7


STATS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev", "tierms",
         "mtie", "pdev", "theo1")
# Names of AllanTools' __all__ that the other branches of issue 34 provide.
OTHER_BRANCHES = {"noise", "Noise", "Dataset", "Plot", "edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev",
                  "confidence_interval", "confidence_interval_noiseID", "autocorr_noise_id"}


class AgainstAllanTools(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.at = allantools()
        cls.phase = phase_dat()
        cls.freq = ocxo()

    def assert_same(self, got, want, rtol=1e-10):
        for g, w in zip(got, want):
            if isinstance(w, list) or isinstance(g, list):
                self.assertEqual(len(g), len(w))
            np.testing.assert_allclose(np.asarray(g, dtype=float), np.asarray(w, dtype=float), rtol=rtol, atol=0)

    def test_conversions(self):
        at = self.at
        for rate in (1.0, 0.37):
            np.testing.assert_allclose(cubecal.frequency2phase(self.freq, rate), at.frequency2phase(self.freq, rate),
                                       rtol=1e-12, atol=1e-300)
            np.testing.assert_allclose(cubecal.phase2frequency(self.phase, rate), at.phase2frequency(self.phase, rate),
                                       rtol=1e-14)
        np.testing.assert_allclose(cubecal.phase2radians(self.phase, 10e6), at.phase2radians(self.phase, 10e6),
                                   rtol=1e-15)
        hz = ocxo_hz()
        for mean in (-1, 1e7):
            got, want = cubecal.frequency2fractional(hz, mean), at.frequency2fractional(hz, mean)
            self.assertIsInstance(got, list)
            np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-22)
        holes = np.array([np.nan, np.nan, 1, 2, 3.4, np.nan, 9, np.nan])
        np.testing.assert_array_equal(cubecal.trim_data(holes), at.trim_data(holes))
        np.testing.assert_array_equal(cubecal.trim_data(self.phase), at.trim_data(self.phase))
        with_nan = np.concatenate(([np.nan, np.nan], self.freq, [np.nan]))
        np.testing.assert_allclose(cubecal.frequency2phase(with_nan, 1.0), at.frequency2phase(with_nan, 1.0),
                                   rtol=1e-12, atol=1e-300)

    def test_tau_generator_and_reduction(self):
        at = self.at
        cases = [dict(taus=t) for t in (None, [], "all", "octave", "decade", "log10", [1, 2, 3.3, 7.5, 1e9, 0.1],
                                        np.array([4.0, 2.0, 4.0]), 16.0)]
        cases += [dict(taus="all", even=True), dict(taus="octave", maximum_m=100.0), dict(taus="all", maximum_m=7)]
        for rate in (1.0, 2.5):
            for kw in cases:
                with self.subTest(rate=rate, **{k: repr(v) for k, v in kw.items()}):
                    with contextlib.redirect_stdout(io.StringIO()):
                        want = at.tau_generator(self.phase, rate, **kw)
                    got = cubecal.tau_generator(self.phase, rate, **kw)
                    np.testing.assert_array_equal(got[0], want[0])
                    np.testing.assert_array_equal(got[1], want[1])
                    np.testing.assert_allclose(got[2], want[2], rtol=1e-15)
        ms = np.arange(1, 1000)
        for k in (1, 2, 5, 10, 100):
            got, want = cubecal.tau_reduction(ms, 2.0, k), at.tau_reduction(ms, 2.0, k)
            np.testing.assert_array_equal(got[0], want[0])
            np.testing.assert_allclose(got[1], want[1], rtol=1e-15)

    def test_remove_small_ns(self):
        rng = np.random.default_rng(4)
        taus, devs, lo, hi = np.arange(1.0, 21.0), rng.random(20), rng.random(20), rng.random(20)
        ns = np.array([50.0, 20, 9, 5, 2, 1, 1, 3, 1, 0, 7, 1, 2, 1, 1, 1, 1, 1, 1, 1])
        for errs in (lo, [lo, hi]):
            got = cubecal.remove_small_ns(taus, devs, errs, ns)
            want = self.at.allantools.remove_small_ns(taus, devs, errs, ns)
            for g, w in zip(got, want):
                np.testing.assert_array_equal(np.asarray(g), np.asarray(w))
        with contextlib.redirect_stdout(io.StringIO()):
            with self.assertRaises(UserWarning):
                self.at.allantools.remove_small_ns(taus, devs, lo, np.ones(20))
        with self.assertRaises(UserWarning):
            cubecal.remove_small_ns(taus, devs, lo, np.ones(20))

    def test_pdev_theo1_and_the_kernels(self):
        at = self.at
        for data, dtype, rate in ((self.phase, "phase", 1.0), (self.freq[:3000], "freq", 2.0)):
            for taus in ("octave", [1.0, 3.0, 10.0, 64.0]):
                with self.subTest(stat="pdev", data_type=dtype, taus=taus):
                    self.assert_same(cubecal.pdev(data, rate, dtype, taus), at.pdev(data, rate, dtype, taus), 1e-9)
        for taus in ("octave", [10, 100, 200]):
            with self.subTest(stat="theo1", taus=taus):
                self.assert_same(cubecal.theo1(self.phase, 1.0, "phase", taus),
                                 at.theo1(self.phase, 1.0, "phase", taus), 1e-9)
        for mj in (1, 2, 5, 33):
            for stride in (1, mj):
                self.assert_same(cubecal.calc_hdev_phase(self.phase, 2.0, mj, stride),
                                 at.calc_hdev_phase(self.phase, 2.0, mj, stride))
                self.assertIsInstance(cubecal.calc_hdev_phase(self.phase, 2.0, mj, stride)[2], int)
        for m in (1, 3, 8):
            self.assert_same(cubecal.calc_mtotdev_phase(self.phase, 1.0, m), at.calc_mtotdev_phase(self.phase, 1.0, m),
                             1e-9)
        y = self.freq[:600]
        for m in (1, 2, 7, 50):
            self.assert_same(cubecal.calc_htotdev_freq(y, m), at.calc_htotdev_freq(y, m), 1e-9)

    def test_gcodev_and_three_cornered_hat(self):
        rng = np.random.default_rng(42)
        a, b, c = rng.normal(size=20000), 5 * rng.normal(size=20000), 10 * rng.normal(size=20000)
        ab, bc, ca = a - b, b - c, c - a
        for taus in ("octave", "decade", [1, 5, 100]):
            self.assert_same(cubecal.gcodev(ab, bc, rate=1.0, taus=taus), self.at.gcodev(ab, bc, rate=1.0, taus=taus))
            other = self.phase + 1e-7 * rng.normal(size=self.phase.size)
            self.assert_same(cubecal.gcodev(self.phase, other, 2.0, "phase", taus),
                             self.at.gcodev(self.phase, other, 2.0, "phase", taus), 1e-9)
            for fn in ("oadev", "mdev"):
                got = cubecal.three_cornered_hat_phase(ab, bc, ca, 1.0, taus, getattr(cubecal, fn))
                want = self.at.three_cornered_hat_phase(ab, bc, ca, 1.0, taus, getattr(self.at, fn))
                self.assertIsInstance(got[2], list)
                self.assert_same(got, want)
        # Clock B's deviation: white phase of amplitude 5, ADEV(1) = sqrt(3) * 5 (independent draws).
        tau, dev, _, _ = cubecal.gcodev(ab, bc, rate=1.0, taus=[1])
        self.assertAlmostEqual(dev[0] / (5 * np.sqrt(3)), 1.0, delta=0.05)

    def test_mtie_phase_fast(self):
        with contextlib.redirect_stdout(io.StringIO()):
            want = self.at.mtie_phase_fast(self.phase[:300])
        got = cubecal.mtie_phase_fast(self.phase[:300], rate=2.0)
        np.testing.assert_allclose(got[1], want[1], rtol=1e-15)
        np.testing.assert_array_equal(got[3], want[3])
        # The taus are the windows' spans, (2^k - 1) / rate (AllanTools gives 2^(k-1) unscaled).
        np.testing.assert_allclose(got[0], (2.0 ** np.arange(1, got[0].size + 1) - 1) / 2.0)
        np.testing.assert_allclose(got[1], cubecal.mtie(self.phase[:256], 2.0, taus=got[0])[1], rtol=1e-15)

    def test_psd_conversions(self):
        f = np.arange(2001.0)
        for s in (1e-24 * np.ones(f.size), 1e-24 * f ** 2, 1e-20 / np.maximum(f, 1.0)):
            for kind in ("adev", "m"):
                for base in (2, 10, 0.5):
                    with self.subTest(kind=kind, base=base):
                        self.assert_same(cubecal.psd2allan(s, f, kind, base), self.at.psd2allan(s, f, kind, base),
                                         1e-9)
        self.assert_same(cubecal.psd2allan(1e-24 * np.ones(300), 0.5), self.at.psd2allan(1e-24 * np.ones(300), 0.5),
                         1e-9)
        taus = np.array([1.0, 10.0, 100.0, 1000.0, 1e4])
        for adev, vartype in (([1e-11, 3e-12, 2e-12, 4e-12, 1e-11], "adev"), ([1e-11, 3e-12, 3e-12], "hdev"),
                              ([1e-11, 3.2e-12], "adev")):
            t = taus[:len(adev)]
            got = cubecal.adev2psd_piecewise_approx(adev, t, vartype)
            want = self.at.adev2psd_piecewise_approx(adev, t, vartype)
            self.assert_same(got, want, 1e-9)
            self.assert_same([cubecal.psd_piecewise_to_adev(got[2], got[3], got[0], taus)],
                             [self.at.psd_piecewise_to_adev(want[2], want[3], want[0], taus)], 1e-9)

    def test_masks(self):
        taus = [0.5, 1, 5, 50, 54.5, 99.9, 100, 250, 273, 500, 999, 1000, 5000, 30e3, 100e3, 300e3, 400e3, 5e5]
        for name in ("prc_tdev", "prc_mtie", "eprtc_tdev", "eprtc_mtie", "prtcA_tdev", "prtcB_tdev", "prtcA_mtie",
                     "prtcB_mtie"):
            want = [getattr(self.at.mask, name)(t) for t in taus]
            self.assertEqual([getattr(cubecal.mask, name)(t) for t in taus], want, name)
            np.testing.assert_array_equal(getattr(cubecal.mask, name)(np.array(taus)), want)

    def test_frequency_data_with_nan_at_their_ends(self):
        y = np.concatenate(([np.nan], self.freq[:4000], [np.nan, np.nan]))
        for stat in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "tierms", "mtie", "pdev", "gradev"):
            for taus in ("octave", [1, 10, 100]):
                with self.subTest(stat=stat, taus=taus), contextlib.redirect_stdout(io.StringIO()):
                    got = getattr(cubecal, stat)(y, 1.0, "freq", taus)
                    want = getattr(self.at, stat)(y, 1.0, "freq", taus)
                    np.testing.assert_array_equal(got[0], want[0])
                    np.testing.assert_array_equal(got[3], want[3])
                    np.testing.assert_allclose(got[1], want[1], rtol=1e-9)

    def test_a_column_gives_what_allantools_gives(self):
        # (AllanTools' totdev and pdev fail on a column of phase; cubecal takes it as every other call.)
        for stat in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev"):
            for data, dtype in ((self.phase, "phase"), (self.freq[:3000], "freq")):
                with self.subTest(stat=stat, data_type=dtype):
                    column = data.reshape(-1, 1)
                    self.assert_same(getattr(cubecal, stat)(column, 1.0, dtype, "octave"),
                                     getattr(self.at, stat)(column, 1.0, dtype, "octave"), 1e-9)

    def test_rate_zero_and_nothing_left_raise_what_allantools_raises(self):
        with self.assertRaises(RuntimeError):
            self.at.oadev(self.phase, rate=0.0)
        with self.assertRaises(RuntimeError):
            cubecal.oadev(self.phase, rate=0.0)
        with contextlib.redirect_stdout(io.StringIO()), self.assertRaises(UserWarning):
            self.at.oadev(self.phase, rate=1.0, taus=[1e6])
        with self.assertRaises(UserWarning):
            cubecal.oadev(self.phase, rate=1.0, taus=[1e6])

    def test_every_name_of_allantools_all(self):
        mine = [n for n in self.at.__all__ if n not in OTHER_BRANCHES]
        for name in mine:
            self.assertTrue(hasattr(cubecal, name), name)
        self.assertEqual(sorted(set(self.at.__all__) - set(cubecal.__all__)), [])
        for name in ("adev", "tau_reduction", "remove_small_ns", "trim_data", "calc_adev_phase", "input_to_phase",
                     "mtie_rolling_window", "psd_piecewise_to_adev"):
            self.assertTrue(hasattr(cubecal.allantools, name), name)
            self.assertTrue(hasattr(self.at.allantools, name), name)


class Arguments(unittest.TestCase):
    """The argument cases without AllanTools."""

    @classmethod
    def setUpClass(cls):
        cls.phase = phase_dat()
        cls.freq = ocxo()

    def test_rate_zero_is_a_runtime_error_and_a_usage_error(self):
        calls = [lambda r: cubecal.oadev(self.phase, rate=r), lambda r: cubecal.pdev(self.phase, rate=r),
                 lambda r: cubecal.gcodev(self.phase, self.phase, rate=r), lambda r: cubecal.tau_generator(self.phase, r),
                 lambda r: cubecal.frequency2phase(self.freq, r), lambda r: cubecal.gradev(self.phase, rate=r),
                 lambda r: cubecal.dev(self.phase, rate=r)]
        for i, call in enumerate(calls):
            for rate in (0, 0.0, -1.0, float("nan")):
                with self.subTest(call=i, rate=rate):
                    with self.assertRaises(RuntimeError) as cm:
                        call(rate)
                    e = cm.exception
                    self.assertIsInstance(e, cubecal.UsageError)
                    self.assertIsInstance(e, cubecal.RateError)
                    self.assertIsInstance(e, ValueError)
                    self.assertEqual(e.option, "rate")
                    self.assertTrue(str(e).startswith("rate"), str(e))
                    self.assertNotIn("\n", str(e))

    def test_nothing_left_is_a_tau_error(self):
        with self.assertRaises(cubecal.TauError) as cm:
            cubecal.oadev(self.phase[:10], rate=1.0, taus=[100.0])
        self.assertIsInstance(cm.exception, cubecal.UsageError)
        self.assertIsInstance(cm.exception, UserWarning)
        self.assertEqual(cm.exception.option, "taus")

    def test_nan_at_the_ends_of_frequency_data_is_trimmed(self):
        y = self.freq[:5000]
        padded = np.concatenate(([np.nan] * 3, y, [np.nan] * 2))
        for stat in STATS + ("gradev",):
            with self.subTest(stat=stat):
                got = getattr(cubecal, stat)(padded, 1.0, "freq", "octave")
                want = getattr(cubecal, stat)(y, 1.0, "freq", "octave")
                for g, w in zip(got, want):
                    np.testing.assert_array_equal(np.asarray(g), np.asarray(w))
        # Inside the record, or in phase data, NaN stays an error at its place.
        inside = y.copy()
        inside[100] = np.nan
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.oadev(inside, 1.0, "freq")
        self.assertEqual(cm.exception.line, 101)
        with self.assertRaises(cubecal.InputError):
            cubecal.oadev(np.concatenate(([np.nan], self.phase)), 1.0, "phase")
        with self.assertRaises(cubecal.UsageError):
            cubecal.oadev(np.full(10, np.nan), 1.0, "freq")

    def test_a_column_is_a_record_and_a_matrix_is_refused(self):
        for stat in STATS + ("gradev",):
            with self.subTest(stat=stat):
                got = getattr(cubecal, stat)(self.phase.reshape(-1, 1), 1.0, "phase", "octave")
                want = getattr(cubecal, stat)(self.phase, 1.0, "phase", "octave")
                for g, w in zip(got, want):
                    np.testing.assert_array_equal(np.asarray(g), np.asarray(w))
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.oadev(np.ones((100, 2)), 1.0)
        self.assertEqual(cm.exception.option, "data")
        self.assertIn("(N, 1)", str(cm.exception))

    def test_a_list_gives_the_numbers_of_an_array(self):
        for stat in STATS + ("gradev",):
            for data, dtype in ((self.phase, "phase"), (self.freq[:3000], "freq")):
                with self.subTest(stat=stat, data_type=dtype):
                    got = getattr(cubecal, stat)(data.tolist(), 1.0, dtype, [1, 2, 10])
                    want = getattr(cubecal, stat)(data, 1.0, dtype, [1, 2, 10])
                    for g, w in zip(got, want):
                        np.testing.assert_array_equal(np.asarray(g), np.asarray(w))

    def test_frequency2phase_integrates_and_phase2frequency_differences(self):
        y = self.freq[:1000]
        x = cubecal.frequency2phase(y, 4.0)
        self.assertEqual(x.shape, (1001,))
        self.assertEqual(x[0], 0.0)
        np.testing.assert_allclose(cubecal.phase2frequency(x, 4.0), y - y.mean(), rtol=1e-9, atol=1e-12 * np.abs(y).max())

    def test_theo1_is_the_library_statistic(self):
        # cubecal's theo1 at even factors is `cubecal dev --stat theo1`'s Theo1 at the same factors.
        t, d, e, n = cubecal.theo1(self.phase, 1.0, "phase", [10, 100, 500])
        r = cubecal.dev(self.phase, rate=1.0, stat="theo1", data_type="phase", taus="all", intervals=False)
        for m, dev, count in zip(t, d, n):
            i = int(np.flatnonzero(r.af == m)[0])
            self.assertAlmostEqual(dev / r.dev[i], 1.0, places=12)
            self.assertEqual(count, r.n[i])
        np.testing.assert_array_equal(n, (self.phase.size - t) * t / 2)

    def test_calc_kernels_refuse_what_cubecal_does_not_compute(self):
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calc_hdev_phase(self.phase, 1.0, 4, 2)
        self.assertEqual(cm.exception.option, "stride")
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calc_mtotdev_phase(self.phase[:20], 1.0, 7)
        self.assertEqual(cm.exception.option, "m")
        self.assertEqual(cubecal.calc_hdev_phase(self.phase[:5], 1.0, 4, 4), (0.0, 0.0, 1))

    def test_masks_at_their_breakpoints(self):
        m = cubecal.mask
        self.assertEqual(m.prc_tdev(99.999), 3e-9)
        self.assertAlmostEqual(m.prc_tdev(500.0), 15e-9, delta=1e-22)
        self.assertEqual(m.prc_tdev(1000.0), 30e-9)
        self.assertAlmostEqual(m.prtcA_mtie(5.0), 0.026375e-6, delta=1e-20)
        self.assertEqual(m.prtcB_mtie(54.5), 0.04e-6)
        self.assertEqual(m.eprtc_mtie(1.0), 4e-9)
        self.assertIsInstance(m.eprtc_tdev(5), float)
        with self.assertRaises(cubecal.UsageError):
            m.prc_tdev("long")

    def test_submodule_is_allantools_allantools(self):
        import cubecal.allantools as at
        self.assertIs(at.oadev, cubecal.oadev)
        self.assertIs(at.tau_reduction, cubecal.tau_reduction)
        self.assertEqual(at.__version__, cubecal.__version__)
        for name in at.__all__:
            self.assertTrue(hasattr(at, name), name)
        # AllanTools' allantools.allantools imports its ci module: at.ci.edf_greenhall works there.
        self.assertIs(at.ci, cubecal.ci)
        self.assertIs(at.ci.edf_greenhall, cubecal.edf_greenhall)


if __name__ == "__main__":
    unittest.main()
