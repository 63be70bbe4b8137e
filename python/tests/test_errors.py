"""Errors reach Python as the documented exceptions, with their places;
long calls let other Python threads run."""
import os
import tempfile
import threading
import unittest

import numpy as np

import cubecal


class Errors(unittest.TestCase):
    def test_input_error_has_the_place(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.csv")
            with open(path, "w") as f:
                f.write("t,gx_dps\n0,1.5\n0.1,abc\n0.2,1.0\n")
            with self.assertRaises(cubecal.InputError) as cm:
                cubecal.read(path)
            e = cm.exception
            self.assertEqual((e.file, e.line, e.column), (path, 3, 5))
            self.assertTrue(str(e).startswith(f"{path}:3:5: "), str(e))
            self.assertIn("abc", e.problem)
            self.assertTrue(e.hint)
            self.assertIsInstance(e, cubecal.Error)
            self.assertIsInstance(e, ValueError)
            with self.assertRaises(cubecal.InputError):
                cubecal.analyze(path, unit="deg/s")

    def test_missing_file(self):
        with self.assertRaises(cubecal.Error):
            cubecal.read("/nonexistent/record.csv")

    def test_usage_errors_name_the_argument(self):
        x = np.zeros(100)
        for call, option in ((lambda: cubecal.dev(x, stat="xdev"), "stat"),
                             (lambda: cubecal.dev(x, taus="weekly"), "taus"),
                             (lambda: cubecal.dev(x, ci=1.5), "ci"),
                             (lambda: cubecal.analyze(x, rate=10.0, unit="furlongs"), "unit"),
                             (lambda: cubecal.simulate("no-such-sensor"), "model")):
            with self.subTest(option=option):
                with self.assertRaises(cubecal.UsageError) as cm:
                    call()
                self.assertEqual(cm.exception.option, option)

    def test_messages_name_python_arguments(self):
        # The library's checks, in Python's words: the argument, never a CLI flag.
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calibrate_mag(np.ones((100, 3)), lsb=0)
        self.assertEqual(cm.exception.option, "lsb")
        self.assertEqual(str(cm.exception), "lsb must be a positive number of counts per unit")
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calibrate_mag(np.ones((100, 3)), field_norm=50.0, field_column=np.ones(100), method="twostep")
        self.assertEqual(cm.exception.option, "field_column")
        self.assertEqual(str(cm.exception), "give either field_norm= or field_column=, not both")

    def test_non_finite_sample(self):
        y = np.ones(1000)
        y[17] = np.nan
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.analyze(y, rate=10.0, unit="deg/s")
        self.assertEqual((cm.exception.line, cm.exception.column), (18, 1))
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.oadev(y)
        self.assertEqual((cm.exception.line, cm.exception.column), (18, 1))

    def test_units_from_names_or_asked(self):
        y = np.random.default_rng(0).normal(size=2000)
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.analyze({"gyro": y}, rate=10.0)
        self.assertIn("gyro", str(cm.exception))
        a = cubecal.analyze({"gx_dps": y}, rate=10.0)
        self.assertEqual(a.channels[0].unit, "deg/s")


class Gil(unittest.TestCase):
    def test_other_threads_run_during_a_long_call(self):
        y = np.random.default_rng(0).normal(size=50_000)
        done = threading.Event()
        ticks = 0

        def work():
            cubecal.oadev(y, data_type="freq", taus="all")
            done.set()

        t = threading.Thread(target=work)
        t.start()
        while not done.is_set():
            ticks += 1
        t.join()
        # With the GIL held for the call this loop could not run meanwhile.
        self.assertGreater(ticks, 10_000)


if __name__ == "__main__":
    unittest.main()
