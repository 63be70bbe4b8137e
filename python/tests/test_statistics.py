"""cubecal.dev and the AllanTools-shaped calls against Stable32's tables, a
closed form, and the CLI's JSON on the same data."""
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import STABLE32, cli_json, phase_dat, relative, stable32_table

STATS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev")


class Stable32Octave(unittest.TestCase):
    """cubecal.dev on PHASE.DAT: AF, n and the noise type exact, sigma to the
    table's five digits, the interval bounds to 1e-3 (Stable32's chi-squared
    quantiles differ in the fourth digit: tests/test_stable32.cpp)."""

    def test_every_statistic(self):
        x = phase_dat()
        for stat in STATS:
            with self.subTest(stat=stat):
                table = stable32_table(os.path.join(STABLE32, "phasedat", f"phase_dat_{stat}_octave.txt"))
                r = cubecal.dev(x, rate=1.0, stat=stat, data_type="phase", taus="octave")
                self.assertEqual(list(r.m), [row["af"] for row in table])
                self.assertEqual(list(r.n), [row["n"] for row in table])
                self.assertLess(relative(r.dev, [row["sigma"] for row in table]), 1e-4)
                alpha = [row["alpha"] for row in table]
                if stat == "totdev":
                    # Stable32's TOTDEV run says white FM at AF 128 and 256
                    # where its own all-tau run (AF 127, 129) and cubecal say
                    # flicker PM: the reference fault of tests/test_stable32.cpp.
                    self.assertEqual(alpha[-2:], [0, 0])
                    alpha[-2:] = [1, 1]
                    table = table[:-2]
                self.assertEqual(list(r.alpha), alpha)
                k = len(table)
                self.assertLess(relative(r.lo[:k], [row["lo"] for row in table]), 1e-3)
                self.assertLess(relative(r.hi[:k], [row["hi"] for row in table]), 1e-3)


class AllanToolsShape(unittest.TestCase):
    """cubecal.oadev & co. return (taus, devs, errs, ns) as AllanTools does; at
    every AF of Stable32's all-tau table, n and sigma agree with it."""

    def test_all_tau_tables(self):
        x = phase_dat()
        for stat in STATS:
            with self.subTest(stat=stat):
                table = stable32_table(os.path.join(STABLE32, "phasedat", f"phase_dat_{stat}.txt"))
                taus, devs, errs, ns = getattr(cubecal, stat)(x, rate=1.0, data_type="phase", taus="all")
                self.assertEqual(ns.dtype, np.float64)
                self.assertTrue(np.all(ns > 1))
                np.testing.assert_allclose(errs, devs / np.sqrt(ns), rtol=1e-15)
                at = {int(round(t)): i for i, t in enumerate(taus)}
                for row in table:
                    i = at[row["af"]]
                    self.assertEqual(ns[i], row["n"], f"{stat} AF {row['af']}")
                    self.assertLess(relative(devs[i], row["sigma"]), 1e-4, f"{stat} AF {row['af']}")

    def test_frequency_data_and_rate(self):
        # pink_frequency: fractional frequency at tau0 = 42 s (Stable32's all-tau table).
        y = np.loadtxt(os.path.join(STABLE32, "pink_frequency", "pink_frequency.txt"))
        table = stable32_table(os.path.join(STABLE32, "pink_frequency", "oadev.txt"))
        taus, devs, errs, ns = cubecal.oadev(y, rate=1 / 42.0, data_type="freq", taus=[r["tau"] for r in table])
        np.testing.assert_allclose(taus, [r["tau"] for r in table], rtol=1e-12)
        self.assertEqual(list(ns), [r["n"] for r in table])
        self.assertLess(relative(devs, [r["sigma"] for r in table]), 1e-4)

    def test_default_grid_is_octave_on_phase_points(self):
        x = phase_dat()  # 1001 points: AllanTools' octave grid is 1..512, kept while n > 1
        taus, devs, errs, ns = cubecal.oadev(x)
        self.assertEqual(list(taus), [1, 2, 4, 8, 16, 32, 64, 128, 256])
        self.assertEqual(list(ns), [1001 - 2 * m for m in [1, 2, 4, 8, 16, 32, 64, 128, 256]])


class ClosedForm(unittest.TestCase):
    def test_white_frequency_noise(self):
        # White FM of sigma s at rate f: AVAR(tau) = s^2 / (tau f) exactly in
        # expectation; every point within its 99 % interval (seeded).
        rng = np.random.default_rng(7)
        s, f = 0.3, 50.0
        y = rng.normal(0.0, s, 200_000)
        r = cubecal.dev(y, rate=f, taus="octave", ci=0.99)
        truth = s / np.sqrt(r.tau * f)
        inside = (r.lo <= truth) & (truth <= r.hi)
        self.assertGreaterEqual(inside.mean(), 0.9, f"{inside.sum()} of {inside.size} intervals hold the truth")
        self.assertTrue(np.all(r.alpha[: len(r.alpha) // 2] == 0), r.alpha)


class SameAsTheCli(unittest.TestCase):
    """cubecal.dev on the record cubecal.read gives equals `cubecal dev --format json`."""

    def test_dev_json(self):
        x = phase_dat()
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "x.csv")
            np.savetxt(path, np.column_stack([np.arange(x.size) * 2.0, x, -0.5 * x]), delimiter=",",
                       header="t,a,b", comments="", fmt="%.17g")
            for stat, taus in (("oadev", "log:10"), ("mdev", "octave"), ("totdev", "decade")):
                with self.subTest(stat=stat):
                    want = cli_json("dev", path, "--stat", stat, "--taus", taus, "--format", "json")
                    rec = cubecal.read(path)
                    self.assertEqual(rec.rate_hz, 0.5)
                    got = cubecal.dev(rec, stat=stat, taus=taus).to_dict()
                    got["file"] = want["file"]
                    self.assertEqual(got, want)


class Gradev(unittest.TestCase):
    """cubecal.gradev (missing samples as NaN) equals `cubecal dev --gaps skip` at the taus both give."""

    def test_same_as_the_cli(self):
        path = os.path.join(os.path.dirname(STABLE32), "allantools", "gradev", "y_gap.dat")
        y = np.loadtxt(path)
        self.assertEqual(int(np.isnan(y).sum()), 200)
        taus, devs, (err_lo, err_hi), ns = cubecal.gradev(y, rate=1.0, data_type="phase", taus="octave", noisetype=None,
                                                  ci=0.683)
        want = cli_json("dev", path, "--type", "phase", "--rate", 1, "--gaps", "skip", "--taus", "octave",
                        "--format", "json")["columns"][0]
        k = len(want["tau"])
        self.assertGreater(len(taus), k)  # AllanTools' octave grid goes further than Stable32's
        np.testing.assert_array_equal(taus[:k], want["tau"])
        np.testing.assert_array_equal(ns[:k], want["n"])
        np.testing.assert_array_equal(devs[:k], want["dev"])
        np.testing.assert_allclose(devs[:k] - err_lo[:k], want["lo"], rtol=1e-12)
        np.testing.assert_allclose(devs[:k] + err_hi[:k], want["hi"], rtol=1e-12)


class Arrays(unittest.TestCase):
    def test_input_untouched_and_dtypes(self):
        x = phase_dat()
        before = x.copy()
        a = cubecal.oadev(x, data_type="phase")
        b = cubecal.oadev(x.astype(np.float32).astype(np.float64), data_type="phase")
        c = cubecal.oadev(list(x), data_type="phase")
        np.testing.assert_array_equal(x, before)
        np.testing.assert_array_equal(a[1], c[1])
        self.assertEqual(len(a[0]), len(b[0]))

    def test_several_channels(self):
        rng = np.random.default_rng(1)
        y = rng.normal(size=(10_000, 3))
        r = cubecal.dev(y, rate=10.0)
        self.assertEqual([c.name for c in r.channels], ["ch1", "ch2", "ch3"])
        for j, c in enumerate(r.channels):
            one = cubecal.dev(np.ascontiguousarray(y[:, j]), rate=10.0)
            np.testing.assert_array_equal(c.dev, one.dev)


if __name__ == "__main__":
    unittest.main()
