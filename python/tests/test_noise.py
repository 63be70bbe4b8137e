"""cubecal.Noise and cubecal.noise (AllanTools' noise_kasdin.Noise and noise
module) on cubecal's Kasdin & Walter generator.

The generator is checked against the exact second moments of Kasdin &
Walter's discrete process, computed here from the filter's taps
(h_0 = 1, h_k = h_{k-1} (k - 1 - b/2) / k): seeded Monte Carlo means within
4.5 standard errors. The closed forms (adev, mdev) are checked against the
same exact moments where they hold. With AllanTools' source at hand
(ALLANTOOLS_SRC), its Noise methods, numpy_psd, scipy_psd and the seeded
timmer_koenig_from_psd give the same numbers, and its generators the same
second moments."""
import importlib
import itertools
import math
import unittest

import numpy as np

import cubecal
from support import allantools
from cubecal import noise

# Standard errors a Monte Carlo mean may be off by (two-sided, p ~ 7e-6).
Z = 4.5


def _allantools():
    peer = allantools()
    importlib.import_module("allantools.noise")  # the submodule, for peer.noise
    return peer



def taps(b, n):
    """Kasdin & Walter's impulse response for phase PSD ~ f^b, n taps."""
    g = np.ones(n)
    for k in range(1, n):
        g[k] = g[k - 1] * (k - 1 - b / 2.0) / k
    return g


def expected_oavar(b, qd, n, m):
    """E of the overlapping Allan variance (tau0 = 1) of n samples of the
    discrete process x_i = sum_k g_k w_{i-k}, var(w) = qd: the mean over
    positions i of E[(x_{i+2m} - 2 x_{i+m} + x_i)^2] / (2 m^2)."""
    g = np.concatenate([taps(b, n), np.zeros(1)])  # g[-1] stands for taps at negative lags: 0
    i = np.arange(n - 2 * m)[:, None]
    j = np.arange(n)[None, :]

    def tap(lag):
        return g[np.where(lag >= 0, lag, -1)]

    c = tap(i + 2 * m - j) - 2.0 * tap(i + m - j) + tap(i - j)
    return qd * np.mean(np.sum(c * c, axis=1)) / (2.0 * m * m)


def oavar(x, m):
    d = x[2 * m:] - 2.0 * x[m:-m] + x[:-2 * m]
    return np.mean(d * d) / (2.0 * m * m)


def assert_mean_within(test, samples, expected, what):
    samples = np.asarray(samples, dtype=float)
    mean = samples.mean()
    se = samples.std(ddof=1) / math.sqrt(samples.size)
    test.assertLess(abs(mean - expected), Z * se, f"{what}: mean {mean:.6g} against {expected:.6g} (se {se:.3g})")


class KasdinWalter(unittest.TestCase):
    """The generator is Kasdin & Walter's process with innovations of variance qd."""

    def test_series_length_and_type(self):
        for nr in (1, 2, 3, 1000, 2 ** 12, 2 ** 12 + 1):
            g = cubecal.Noise(nr=nr, qd=1.0, b=-2)
            self.assertEqual(g.time_series.size, 0)
            self.assertIsNone(g.generateNoise())
            self.assertIsInstance(g.time_series, np.ndarray)
            self.assertEqual(g.time_series.shape, (nr,))
            self.assertEqual(g.time_series.dtype, np.float64)

    def test_first_sample_has_variance_qd(self):
        # x_0 = w_0 for every b: var(x_0) = qd.
        for b in (0, -1, -2, -3, -4, -1.5):
            g = cubecal.Noise(nr=8, qd=4.0, b=b, seed=11)
            first = []
            for _ in range(3000):
                g.generateNoise()
                first.append(g.time_series[0] ** 2)
            assert_mean_within(self, first, 4.0, f"b={b}: x_0^2")

    def test_allan_variance_is_the_discrete_process(self):
        n, qd, runs = 512, 2.5e-3, 400
        for b in (0, -1, -2, -3, -4, -0.5, -2.5):
            g = cubecal.Noise(nr=n, qd=qd, b=b, seed=1000 + int(10 * -b))
            avars = {m: [] for m in (1, 4, 32)}
            for _ in range(runs):
                g.generateNoise()
                for m in avars:
                    avars[m].append(oavar(g.time_series, m))
            for m, values in avars.items():
                with self.subTest(b=b, m=m):
                    assert_mean_within(self, values, expected_oavar(b, qd, n, m), f"b={b} m={m}: AVAR")

    def test_suite_shape_adev_within_ten_percent(self):
        # AllanTools' test_adev_average: 30 series of 2^16, ADEV at one tau
        # within 10 % of the closed form (white and flicker PM, white FM).
        for b, tau in ((0, 1), (0, 30), (-1, 5), (-2, 1), (-2, 20)):
            g = cubecal.Noise(nr=2 ** 16, qd=6e-9, b=b, seed=7)
            devs = []
            for _ in range(30):
                g.generateNoise()
                devs.append(cubecal.adev(g.time_series, taus=[tau], rate=1.0)[1][0])
            self.assertTrue(np.isclose(np.mean(devs), g.adev(tau0=1.0, tau=tau), rtol=0.1, atol=0),
                            f"b={b} tau={tau}: {np.mean(devs)} against {g.adev(tau0=1.0, tau=tau)}")

    def test_seed(self):
        a = cubecal.Noise(nr=100, qd=1.0, b=-1, seed=5)
        b = cubecal.Noise(nr=100, qd=1.0, b=-1, seed=5)
        a.generateNoise()
        b.generateNoise()
        np.testing.assert_array_equal(a.time_series, b.time_series)
        first = a.time_series.copy()
        a.generateNoise()
        self.assertFalse(np.array_equal(first, a.time_series), "successive series of one seed differ")
        c = cubecal.Noise(nr=100, qd=1.0, b=-1, seed=6)
        c.generateNoise()
        self.assertFalse(np.array_equal(first, c.time_series))

    def test_numpy_global_seed(self):
        # Without a seed the series follows NumPy's global generator, as AllanTools'.
        g = cubecal.Noise(nr=64, qd=1.0, b=-2)
        np.random.seed(42)
        g.generateNoise()
        first = g.time_series.copy()
        g.generateNoise()
        self.assertFalse(np.array_equal(first, g.time_series))
        np.random.seed(42)
        g.generateNoise()
        np.testing.assert_array_equal(first, g.time_series)

    def test_set_input_restores_defaults(self):
        g = cubecal.Noise(nr=8, qd=3.0, b=-3)
        g.set_input(nr=16)
        self.assertEqual((g.nr, g.qd, g.b), (16, 1, 0))
        g.generateNoise()
        self.assertEqual(g.time_series.size, 16)


class ClosedForms(unittest.TestCase):
    """adev and mdev against the discrete process where the closed forms hold."""

    def test_white_pm_and_white_fm_are_exact(self):
        n = 256
        for b, m in itertools.product((0, -2), (1, 3, 16)):
            g = cubecal.Noise(nr=n, qd=2e-20, b=b)
            self.assertAlmostEqual(g.adev(1.0, m) ** 2 / expected_oavar(b, 2e-20, n, m), 1.0, places=12)

    def test_random_walk_fm_at_long_tau(self):
        # The discrete AVAR is qd (2 m^2 + 1) / (6 m): the closed form qd m / 3 plus 1 / (2 m^2).
        n = 512
        for m in (1, 8, 32):
            g = cubecal.Noise(nr=n, qd=1.0, b=-4)
            exact = expected_oavar(-4, 1.0, n, m)
            self.assertAlmostEqual(exact, (2.0 * m * m + 1.0) / (6.0 * m), places=9)
            self.assertAlmostEqual(g.adev(1.0, m) ** 2 / exact, 1.0 / (1.0 + 1.0 / (2.0 * m * m)), places=9)

    def test_flicker_within_their_approximation(self):
        # Flicker PM (f_h tau0 = 1/2) and flicker FM (far from the record's start) within 8 %.
        n = 4096
        for b, m in ((-1, 8), (-1, 64), (-3, 8), (-3, 32)):
            g = cubecal.Noise(nr=n, qd=1.0, b=b)
            ratio = g.adev(1.0, m) ** 2 / expected_oavar(b, 1.0, n, m)
            self.assertLess(abs(ratio - 1.0), 0.08, f"b={b} m={m}: closed form / exact = {ratio}")

    def test_exponents_and_levels(self):
        g = cubecal.Noise(qd=1.0)
        for b, ca, cm in ((0, -2, -3), (-1, -2, -2), (-2, -1, -1), (-3, 0, 0), (-4, 1, 1)):
            g.set_input(qd=1.0, b=b)
            self.assertEqual((g.c_avar(), g.c_mvar()), (ca, cm))
            # S_x = g_b f^b and S_y = (2 pi f)^2 S_x: h_a = (2 pi)^2 g_b at tau0 = 1.
            self.assertAlmostEqual(g.frequency_psd_from_qd(1.0), 4.0 * math.pi ** 2 * g.phase_psd_from_qd(1.0))
        g.set_input(b=-2.5)
        self.assertIsNone(g.c_avar())
        np.testing.assert_allclose(cubecal.Noise(b=-2).adev(1.0, np.array([1.0, 4.0])), [1.0, 0.5])


class Generators(unittest.TestCase):
    """white, brown, violet, pink, iterpink: AllanTools' shapes and levels."""

    def test_shapes(self):
        for f in (noise.white, noise.brown, noise.violet, noise.pink):
            for n in (0, 1, 500, 1025):
                x = f(n, seed=3)
                self.assertIsInstance(x, np.ndarray)
                self.assertEqual(x.shape, (n,))
            np.testing.assert_array_equal(f(100, seed=9), f(100, seed=9))
            self.assertFalse(np.array_equal(f(100, seed=9), f(100, seed=10)))

    def test_white_level(self):
        # Variance b0 fs / 2: one-sided PSD b0 up to fs / 2.
        x = noise.white(200000, b0=3.0, fs=8.0, seed=1)
        assert_mean_within(self, x * x, 12.0, "white x^2")
        np.testing.assert_array_equal(noise.white(5, b0=0.0, seed=1), np.zeros(5))

    def test_brown_level(self):
        # Steps of variance 4 pi^2 b_minus2 / (2 fs) (PSD b_minus2 f^-2), from x_0 one step.
        fs, level = 4.0, 0.5
        x = noise.brown(200000, b_minus2=level, fs=fs, seed=2)
        steps = np.diff(np.concatenate(([0.0], x)))
        assert_mean_within(self, steps * steps, 4 * math.pi ** 2 * level / (2 * fs), "brown steps^2")

    def test_violet_level(self):
        # Differences of white noise of variance b2 fs^3 / (2 (2 pi)^2): var 2 s^2, lag-1 covariance -s^2.
        fs, level = 2.0, 3.0
        s2 = level * fs ** 3 / (2 * (2 * math.pi) ** 2)
        x = noise.violet(200000, b2=level, fs=fs, seed=3)
        assert_mean_within(self, x * x, 2 * s2, "violet x^2")
        assert_mean_within(self, x[1:] * x[:-1], -s2, "violet lag-1 product")

    def test_pink_is_one_over_f(self):
        # Mean periodogram times f over a mid band: 1 / ln 2 for f << 1/2.
        n, runs = 4096, 60
        values = []
        for k in range(runs):
            x = noise.pink(n, depth=80, seed=100 + k)
            f, p = noise.numpy_psd(x - x.mean())
            band = (f > 1.0 / 256) & (f < 1.0 / 32)
            values.append(np.mean(p[band] * f[band]))
        assert_mean_within(self, values, 1.0 / math.log(2.0), "pink f S(f)")

    def test_pink_depth(self):
        # 2^depth taps: below f ~ 2^-depth the spectrum is flat.
        x = noise.pink(2 ** 16, depth=4, seed=5)
        f, p = noise.scipy_psd(x, nr_segments=16)
        low = np.mean(p[(f > 0) & (f < 1.0 / 256)])
        mid = np.mean(p[(f > 1.0 / 128) & (f < 1.0 / 64)])
        self.assertLess(abs(low / mid - 1.0), 0.3, "flat below 2^-depth")

    def test_iterpink(self):
        s = noise.iterpink(depth=12, seed=4)
        x = np.fromiter(itertools.islice(s, 10000), dtype=float)
        self.assertIsInstance(next(s), np.floating)
        self.assertEqual(x.size, 10000)
        t = np.fromiter(itertools.islice(noise.iterpink(depth=12, seed=4), 10000), dtype=float)
        np.testing.assert_array_equal(x, t)
        # A run far from the start has the 1/f level.
        values = []
        for _ in range(40):
            y = np.fromiter(itertools.islice(s, 4096), dtype=float)
            f, p = noise.numpy_psd(y - y.mean())
            band = (f > 1.0 / 256) & (f < 1.0 / 32)
            values.append(np.mean(p[band] * f[band]))
        assert_mean_within(self, values, 1.0 / math.log(2.0), "iterpink f S(f)")

    def test_numpy_psd_of_a_sine(self):
        # A sine of amplitude A on a bin: total power A^2 / 2 in one bin of width fs / N.
        fs, n, k, amp = 10.0, 1000, 37, 2.0
        t = np.arange(n) / fs
        f, p = noise.numpy_psd(amp * np.sin(2 * np.pi * k * fs / n * t), f_sample=fs)
        self.assertEqual(f.size, n // 2 + 1)
        self.assertAlmostEqual(f[-1], fs / 2)
        self.assertAlmostEqual(p[k] * fs / n, amp * amp / 2, places=9)
        self.assertLess(np.max(np.delete(p, k)), 1e-18)

    def test_scipy_psd_is_welch(self):
        import scipy.signal
        x = noise.white(1000, seed=8)
        f0, p0 = scipy.signal.welch(x, 5.0, nperseg=250)
        f1, p1 = noise.scipy_psd(x, f_sample=5.0)
        np.testing.assert_allclose(f1, f0, rtol=1e-12)
        np.testing.assert_allclose(p1, p0, rtol=1e-9)

    def test_timmer_koenig_level(self):
        # White FM h0: E[y^2] of y = diff(x) / dt from the synthesis' bins,
        # E|X_k|^2 = S_x(f_k) / 2 (k < n/2, and its mirror; the Nyquist bin's
        # real part: S_x / 4), x = ifft(X) sqrt((n - 1) / dt).
        h0, dt, n = 2e-22, 0.5, 4096
        half = n // 2
        grid = np.linspace(1.0 / ((n - 1) * dt), 1.0 / (2.0 * dt), half + 1)[1:]
        k = np.arange(1, half + 1)
        power = np.where(k == half, 0.25, 1.0) * h0 / (2 * np.pi * grid) ** 2  # both halves: 2 x S_x / 2
        expected = (n - 1) / (n * n * dt ** 3) * np.sum(power * 4.0 * np.sin(np.pi * k / n) ** 2)
        y = [noise.timmer_koenig_from_psd([], [h0], [0.0], n * dt, dt, output="freq", seed=k)[1:] for k in range(50)]
        assert_mean_within(self, [np.mean(v * v) for v in y], expected, "timmer_koenig y^2")
        # About h0 fs / 2 times the finite difference's mean sinc^2 over the band (0.774).
        self.assertAlmostEqual(expected / (h0 / (2 * dt)), 0.774, delta=0.01)
        x = noise.timmer_koenig_from_psd([], [h0], [0.0], n * dt, dt, seed=1)
        self.assertEqual(x.shape, (n,))
        self.assertEqual(noise.timmer_koenig_from_psd([], [h0], [0.0], 5.0, 1.0).shape, (5,))


class BadArguments(unittest.TestCase):
    def check(self, option, call, *args, **kwargs):
        with self.assertRaises(cubecal.UsageError) as c:
            call(*args, **kwargs)
        self.assertIsInstance(c.exception, ValueError)
        self.assertEqual(c.exception.option, option)
        self.assertIn(option, str(c.exception).split(":")[0])
        self.assertNotIn("\n", str(c.exception))

    def test_noise(self):
        self.check("nr", cubecal.Noise(nr=0).generateNoise)
        self.check("nr", cubecal.Noise(nr=2.5).generateNoise)
        self.check("qd", cubecal.Noise(qd=-1).generateNoise)
        self.check("qd", cubecal.Noise(qd=float("nan")).generateNoise)
        self.check("b", cubecal.Noise(b=float("inf")).generateNoise)
        self.check("b", cubecal.Noise(b=-2.5).adev, 1.0, 1.0)
        self.check("b", cubecal.Noise(b=1).mdev_from_qd)
        self.check("qd", cubecal.Noise(qd=-1.0, b=-2).adev, 1.0, 10.0)
        self.check("tau0", cubecal.Noise(b=0).adev_from_qd, tau0=0.0)
        self.check("tau0", cubecal.Noise(b=-3).pdev_from_qd, tau0=float("nan"))
        self.check("seed", cubecal.Noise, seed=-1)

    def test_generators(self):
        self.check("num_points", noise.white, -1)
        self.check("num_points", noise.brown, 2.5)
        self.check("fs", noise.white, 10, fs=0.0)
        self.check("b0", noise.white, 10, b0=-1.0)
        self.check("b_minus2", noise.brown, 10, b_minus2=float("nan"))
        self.check("b2", noise.violet, 10, b2="1")
        self.check("depth", noise.pink, 10, depth=-1)
        self.check("depth", noise.iterpink, depth=1.5)
        self.check("seed", noise.white, 10, seed=-3)

    def test_spectra(self):
        self.check("x", noise.numpy_psd, [1.0, 2.0])
        self.check("x", noise.numpy_psd, [1.0, np.nan, 2.0, 3.0])
        self.check("f_sample", noise.numpy_psd, np.ones(8), f_sample=0.0)
        self.check("nr_segments", noise.scipy_psd, np.ones(8), nr_segments=4)
        self.check("nr_segments", noise.scipy_psd, np.ones(8), nr_segments=0)

    def test_timmer_koenig(self):
        tk = noise.timmer_koenig_from_psd
        self.check("duration", tk, [], [1.0], [0.0], -1.0, 1.0)
        self.check("duration", tk, [], [1.0], [0.0], 3.0, 1.0)
        self.check("alpha", tk, [], [1.0, 2.0], [0.0], 10.0, 1.0)
        self.check("f_nodes", tk, [0.1, 0.2], [1.0, 2.0], [0.0, -1.0], 10.0, 1.0)
        self.check("output", tk, [], [1.0], [0.0], 10.0, 1.0, output="time")


class AllanToolsParity(unittest.TestCase):
    """The same conventions as AllanTools: numbers equal, generators with the same moments."""

    @classmethod
    def setUpClass(cls):
        cls.at = _allantools()

    def test_noise_methods(self):
        for b, qd, tau0, tau in itertools.product((0, -1, -2, -3, -4), (1.0, 3e-15), (1.0, 0.25), (1.0, 7.0)):
            ours, theirs = cubecal.Noise(qd=qd, b=b), self.at.Noise(qd=qd, b=b)
            for name, args in (("phase_psd_from_qd", (tau0,)), ("frequency_psd_from_qd", (tau0,)),
                               ("adev_from_qd", (tau0, tau)), ("mdev_from_qd", (tau0, tau)),
                               ("pdev_from_qd", (tau0, tau)), ("adev", (tau0, tau)), ("mdev", (tau0, tau)),
                               ("c_avar", ()), ("c_mvar", ())):
                with self.subTest(b=b, qd=qd, tau0=tau0, tau=tau, method=name):
                    np.testing.assert_allclose(getattr(ours, name)(*args), getattr(theirs, name)(*args),
                                               rtol=1e-14, atol=0)

    def test_generator_moments(self):
        # Mean overlapping AVAR of AllanTools' and cubecal's series, each within
        # its standard error of the exact expectation.
        n, qd, runs = 256, 1.0, 300
        np.random.seed(2024)
        for b in (0, -1, -2, -3, -4):
            ours, theirs = cubecal.Noise(nr=n, qd=qd, b=b, seed=b + 10), self.at.Noise(nr=n, qd=qd, b=b)
            for m in (1, 8):
                expected = expected_oavar(b, qd, n, m)
                for gen, who in ((ours, "cubecal"), (theirs, "AllanTools")):
                    values = []
                    for _ in range(runs):
                        gen.generateNoise()
                        values.append(oavar(gen.time_series, m))
                    with self.subTest(b=b, m=m, generator=who):
                        assert_mean_within(self, values, expected, f"{who} b={b} m={m}")

    def test_white_brown_violet_moments(self):
        np.random.seed(7)
        n = 100000
        for name, kwargs, stat in (("white", {"b0": 2.0, "fs": 3.0}, lambda x: x * x),
                                   ("brown", {"b_minus2": 0.3, "fs": 2.0}, lambda x: np.diff(x) ** 2),
                                   ("violet", {"b2": 5.0, "fs": 0.5}, lambda x: x * x),
                                   ("violet", {"b2": 5.0, "fs": 0.5}, lambda x: x[1:] * x[:-1])):
            theirs = stat(getattr(self.at.noise, name)(n, **kwargs))
            ours = stat(getattr(noise, name)(n, seed=1, **kwargs))
            se = math.hypot(np.std(theirs) / math.sqrt(theirs.size), np.std(ours) / math.sqrt(ours.size))
            with self.subTest(generator=name):
                self.assertLess(abs(np.mean(ours) - np.mean(theirs)), Z * se)

    def test_psd_functions(self):
        x = np.random.default_rng(3).standard_normal(1001)
        for data in (x, x[:1000]):
            for fs in (1.0, 40.0):
                for f_ours, f_theirs in zip(noise.numpy_psd(data, fs), self.at.noise.numpy_psd(data, fs)):
                    np.testing.assert_allclose(f_ours, f_theirs, rtol=1e-10, atol=0)
                for segments in (4, 3):
                    ours, theirs = noise.scipy_psd(data, fs, segments), self.at.noise.scipy_psd(data, fs, segments)
                    for a, b in zip(ours, theirs):
                        np.testing.assert_allclose(a, b, rtol=1e-9, atol=0)

    def test_timmer_koenig_same_samples(self):
        cases = (([], [1e-22], [0.0], 1024.0, 1.0, "phase"),
                 ([1e-2], [1e-24, 1e-22], [-1.0, 0.0], 2000.0, 0.5, "freq"),
                 ([1e-3, 3e-2], [1e-26, 1e-24, 1e-22], [-2.0, -1.0, 0.0], 4096.0, 1.0, "phase"))
        for nodes, h, alpha, duration, dt, output in cases:
            with self.subTest(nodes=nodes, output=output):
                ours = noise.timmer_koenig_from_psd(nodes, h, alpha, duration, dt, output=output, seed=12)
                theirs = self.at.noise.timmer_koenig_from_psd(nodes, h, alpha, duration, dt, output=output, seed=12)
                np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-12 * np.max(np.abs(theirs)))


if __name__ == "__main__":
    unittest.main()
