"""Every public call, given what it cannot take, raises a cubecal.Error
subclass that names the keyword at fault in plain words: never pybind11's
signature of a private function, an OverflowError or a plain ValueError, and
never a result with NaN in it. Values the CLI refuses in a file (a rate
outside 1e-9 to 1e9 Hz, subnormal or huge samples, NaN) are refused in an
array with the same rule."""
import math
import os
import tempfile
import unittest

import numpy as np

import cubecal

RNG = np.random.default_rng(3)
Y = RNG.normal(size=600)
XYZ = RNG.normal(size=(200, 3))
TEMP = np.linspace(20.0, 30.0, 600)
FILES = tempfile.TemporaryDirectory()
CSV = os.path.join(FILES.name, "y.csv")
np.savetxt(CSV, Y, header="g", comments="")

STATISTICS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev", "tierms",
              "mtie", "gradev")


def _allantools(name):
    return lambda **kw: getattr(cubecal, name)(**{"data": Y, "rate": 100.0, **kw})


# Each public call with valid arguments; a case replaces one of them.
CALLS = {name: _allantools(name) for name in STATISTICS}
CALLS.update({
    "dev": lambda **kw: cubecal.dev(**{"data": Y, "rate": 100.0, **kw}),
    "analyze": lambda **kw: cubecal.analyze(**{"data": Y, "rate": 100.0, "unit": "deg/s", "composite": False, **kw}),
    "psd": lambda **kw: cubecal.psd(**{"data": Y, "rate": 100.0, **kw}),
    "davar": lambda **kw: cubecal.davar(**{"data": Y, "rate": 100.0, **kw}),
    "model": lambda **kw: cubecal.model(**{"data": Y, "model": "WN", "rate": 100.0, "wic_replicates": 0, **kw}),
    "simulate": lambda **kw: cubecal.simulate(**{"model": "sport-gyro", "rate": 10.0, "duration": 60.0, **kw}),
    "calibrate_mag": lambda **kw: cubecal.calibrate_mag(**{"points": XYZ, **kw}),
    "calibrate_temperature": lambda **kw: cubecal.calibrate_temperature(
        **{"data": Y, "temperature": TEMP, "rate": 10.0, **kw}),
    "calibrate_rate_table": lambda **kw: cubecal.calibrate_rate_table(
        **{"data": np.ones((600, 3)), "rate": 100.0, "reference": np.ones((600, 3)), **kw}),
    "calibrate_multiposition": lambda **kw: cubecal.calibrate_multiposition(**{"acc": XYZ, "rate": 100.0, **kw}),
    "read": lambda **kw: cubecal.read(**{"path": CSV, "rate": 100.0, **kw}),
    "turnon": lambda **kw: cubecal.turnon(**{"runs": [Y, Y + 1.0], "rate": 100.0, "unit": "deg/s", **kw}),
    "compare": lambda **kw: cubecal.compare(**{"runs": [Y, Y + 1.0], "rate": 100.0, "unit": "deg/s", **kw}),
})

PATH_CALLS = ("analyze", "psd", "davar", "model", "calibrate_mag", "calibrate_temperature", "calibrate_rate_table",
              "calibrate_multiposition")
ARRAY_CALLS = (*STATISTICS, "dev", "analyze", "psd", "davar", "model", "calibrate_temperature")

BAD_RATES = (0, 0.0, -100.0, math.nan, math.inf, 1e300, 1e-300, "fast", [100.0])
BAD_DATA = ("hello", None, ["a", "b", "c"], np.array([]), np.ones((2, 2, 2)))
BAD_COUNTS = (-1, 2 ** 70, 1.5, "ten", None, math.nan)
BAD_NUMBERS = ("x", None, math.nan, math.inf, [1.0, 2.0])


def _with(values, index, value):
    v = np.array(values, dtype=np.float64)
    v.flat[index] = value
    return v


def _cases():
    """(call, keyword, value) of every bad argument."""
    cases = []
    for name in CALLS:
        if name not in ("simulate", "turnon", "compare", "read"):
            first = "points" if name == "calibrate_mag" else "acc" if name == "calibrate_multiposition" else "data"
            # A string is a path where the call reads files.
            cases += [(name, first, v) for v in BAD_DATA if not (isinstance(v, str) and name in PATH_CALLS)]
        if name != "calibrate_mag":
            cases += [(name, "rate", v) for v in BAD_RATES]
    for name in STATISTICS:
        cases += [(name, "taus", ["x"]), (name, "taus", "weekly"), (name, "taus", [-1.0]), (name, "taus", "log:0"),
                  (name, "data_type", 3), (name, "data_type", "angle")]
    cases += [("gradev", "ci", v) for v in BAD_NUMBERS] + [("gradev", "noisetype", v) for v in ("zz", 3)]
    counts = {
        "dev": ("threads",), "analyze": ("threads", "temp_order", "cov_samples", "max_samples", "composite_bootstrap"),
        "psd": ("threads", "segment", "bins_per_decade"), "davar": ("threads", "window", "step"),
        "model": ("threads", "bootstrap", "seed", "starts", "wic_replicates"), "simulate": ("seed",),
        "calibrate_mag": ("threads", "skip_rows"), "calibrate_temperature": ("order",),
        "calibrate_multiposition": ("threads", "skip_rows", "window", "interval_samples", "min_intervals"),
        "turnon": ("threads",), "compare": ("threads",), "read": ("threads", "skip_rows", "header_bytes"),
    }
    for name, keywords in counts.items():
        for k in keywords:
            # A window or step may also be a duration: a string is read as one.
            cases += [(name, k, v) for v in BAD_COUNTS if not (k in ("window", "step") and name == "davar"
                                                                and (v is None or isinstance(v, str)))]
    numbers = {
        "dev": ("ci",), "analyze": ("ci", "drift_window"), "psd": ("overlap", "fmin", "fit_min", "fit_max"),
        "davar": ("ci",), "model": ("ci", "efficiency"), "simulate": ("duration",),
        "calibrate_mag": ("lsb", "reject", "field_norm", "noise"),
        "calibrate_rate_table": ("margin", "min_plateau", "ref_tolerance", "window"),
        "calibrate_multiposition": ("g", "init_static", "acc_scale", "gyro_scale"),
        "turnon": ("ci",), "compare": ("ci",),
    }
    for name, keywords in numbers.items():
        for k in keywords:
            cases += [(name, k, v) for v in BAD_NUMBERS if not (v is None and k in ("field_norm", "noise"))]
    cases += [("dev", "alpha", v) for v in ("x", 1.5, 2 ** 70)] + [("davar", "alpha", v) for v in ("x", 1.5)]
    cases += [("dev", "stat", 3), ("dev", "edf", 3), ("dev", "conservative", "maybe"), ("dev", "intervals", 2)]
    cases += [("model", "model", 3), ("model", "bootstrap", -1), ("model", "robust", "yes")]
    cases += [("psd", "window", 3), ("psd", "detrend", None), ("psd", "fit", "no")]
    cases += [("analyze", "psd", "yes"), ("analyze", "temperature", ["a"] * 600), ("analyze", "model_lsb", "x"),
              ("analyze", "unit", 3.5)]
    cases += [("simulate", "rate", v) for v in BAD_RATES if v is not None and v != 0 and v != 0.0]
    cases += [("simulate", "flicker", "x"), ("simulate", "temperature", None), ("simulate", "true_input", 3),
              ("simulate", "bias", 3)]
    cases += [("calibrate_mag", "method", 3), ("calibrate_mag", "allow_partial", "x"), ("calibrate_mag", "unit", 3)]
    cases += [("calibrate_temperature", "temperature", v) for v in ("x", np.ones((600, 2)), ["a"] * 600)]
    cases += [("calibrate_rate_table", "from_signal", "x"), ("calibrate_rate_table", "earth_axis", "x"),
              ("calibrate_rate_table", "schedule", ["a", "b", "c", "d", "e"])]
    cases += [("calibrate_multiposition", "acc_bias", "x"), ("calibrate_multiposition", "use_means", "x")]
    cases += [(name, "runs", v) for name in ("turnon", "compare") for v in ("x", None, 3)]
    cases += [(name, "runs", [["a"] * 600, Y]) for name in ("turnon", "compare")]
    cases += [("read", "path", v) for v in (None, 3, ["a"])] + [("read", "lsb", v) for v in ("x", math.nan, [[1.0]])]
    cases += [("read", "gaps", 3), ("read", "time", 1.5), ("read", "columns", 1.5), ("read", "frame", "x"),
              ("read", "columns", {"a": 1})]
    cases += [("psd", "fit_max", 1.5), ("psd", "fmin", 1e-300), ("analyze", "composite", "WN+FOO"),
              ("analyze", "model_lsb", -1.0), ("simulate", "flicker", 1e300), ("calibrate_mag", "noise", 1e-300),
              ("calibrate_mag", "points", {"a": 1}), ("dev", "names", 3.5), ("dev", "names", ["a", "b"])]
    return cases


def _value_cases():
    """(call, keyword, bad samples, sample index, column): samples the CLI
    refuses in a file, refused as cubecal.InputError at their place."""
    cases = []
    for name in ARRAY_CALLS:
        values = [(math.inf, 7), (-1e200, 9), (1e-310, None)]
        if name != "gradev":  # gradev takes NaN as a missing sample
            values.append((math.nan, 11))
        for bad, index in values:
            if index is None:  # every sample subnormal: refused at the largest
                data, index = Y * 1e-310, int(np.argmax(np.abs(Y)))
            else:
                data = _with(Y, index, bad)
            cases.append((name, "data", data, index, 1))
    for bad, index in ((math.nan, 4), (math.inf, 5), (1e-310, None)):
        points = XYZ * 1e-310 if index is None else _with(XYZ, index * 3 + 1, bad)
        column = 2 if index is not None else int(np.argmax(np.abs(XYZ)) % 3) + 1
        row = index if index is not None else int(np.argmax(np.abs(XYZ)) // 3)
        cases.append(("calibrate_mag", "points", points, row, column))
    return cases


class BadArguments(unittest.TestCase):
    def assert_plain(self, e, keyword):
        text = str(e)
        for private in ("incompatible function arguments", "Invoked with", "_cubecal", "(self:"):
            self.assertNotIn(private, text)
        self.assertNotIn("\n", text)
        if keyword:
            self.assertIn(keyword, text)

    def test_every_bad_argument_is_a_usage_error_naming_its_keyword(self):
        cases = _cases()
        self.assertGreater(len(cases), 300)
        for name, keyword, value in cases:
            with self.subTest(call=name, keyword=keyword, value=repr(value)[:40]):
                with self.assertRaises(cubecal.Error) as cm:
                    CALLS[name](**{keyword: value})
                e = cm.exception
                if isinstance(e, cubecal.UsageError):
                    self.assertEqual(e.option, keyword, str(e))
                    self.assert_plain(e, keyword)
                else:
                    # A record that is empty or has no sample a statistic can use.
                    self.assertIsInstance(e, cubecal.InputError, str(e))
                    self.assert_plain(e, None)

    def test_samples_the_cli_refuses_are_input_errors_at_their_place(self):
        for name, keyword, data, index, column in _value_cases():
            with self.subTest(call=name, value=repr(data.flat[index])):
                with self.assertRaises(cubecal.InputError) as cm:
                    CALLS[name](**{keyword: data})
                e = cm.exception
                self.assertEqual((e.line, e.column), (index + 1, column), str(e))
                self.assertIsInstance(e, cubecal.Error)
                self.assertIsInstance(e, ValueError)
                self.assert_plain(e, None)

    def test_the_issue_cases(self):
        # issue 33, item 10, as filed.
        y = Y
        for rate in (1e300, 1e-300):
            with self.assertRaises(cubecal.UsageError) as cm:
                cubecal.oadev(y, rate=rate)
            self.assertEqual(cm.exception.option, "rate")
            self.assertIn("outside the range 1e-09 to 1e+09 Hz", str(cm.exception))
        with self.assertRaises(cubecal.InputError):
            cubecal.oadev(np.full(100, 1e-310), rate=1.0)
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.oadev("hello", rate=100.0)
        self.assertEqual(cm.exception.option, "data")
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.totdev(np.array([]), rate=1.0)
        self.assertEqual(cm.exception.option, "data")
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.model(y, "WN", rate=100.0, bootstrap=-1)
        self.assertEqual(cm.exception.option, "bootstrap")
        self.assertEqual(str(cm.exception), "bootstrap: a whole number from 0 to 18446744073709551615 is expected, "
                                            "not -1")
        nan = y.copy()
        nan[17] = np.nan
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.oadev(nan, rate=1.0)
        self.assertEqual((cm.exception.line, cm.exception.column), (18, 1))

    def test_the_cli_says_the_same_of_the_rate(self):
        # The rule is the library's: the CLI's --rate and Python's rate= give one message.
        binary = os.environ.get("CUBECAL_BINARY")
        if not binary:
            self.skipTest("CUBECAL_BINARY is not set (run the tests through ctest)")
        import subprocess
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "y.csv")
            np.savetxt(path, Y, header="g", comments="")
            p = subprocess.run([binary, "dev", path, "--rate", "1e300"], capture_output=True, text=True)
            self.assertEqual(p.returncode, 2)
            with self.assertRaises(cubecal.UsageError) as cm:
                cubecal.dev(Y, rate=1e300)
            self.assertIn(str(cm.exception).split(": ", 1)[1], p.stderr)

    def test_messages_are_one_line_without_overflowed_numbers(self):
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.oadev(Y, rate=np.ones((2, 2)))
        self.assertNotIn("\n", str(cm.exception))
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.psd(Y, rate=100.0, fmin=1e-300)
        self.assertNotIn("-9223372036854775808", str(cm.exception))
        self.assertEqual(cm.exception.option, "fmin")

    def test_result_of_an_analysis_writes_only_to_a_path(self):
        a = cubecal.analyze(Y, rate=100.0, unit="deg/s", composite=False)
        for v in (None, 3, ["a"]):
            with self.subTest(directory=v):
                with self.assertRaises(cubecal.UsageError) as cm:
                    a.write(v)
                self.assertEqual(cm.exception.option, "directory")

    def test_a_drift_window_outside_the_record_names_its_keyword(self):
        # 600 samples at 100 Hz: 6 s of record, 0.01 s per sample.
        for window, says in ((1e30, "is longer than the record"), (0.004, "is shorter than one sample")):
            with self.subTest(window=window):
                with self.assertRaises(cubecal.UsageError) as cm:
                    cubecal.analyze(Y, rate=100.0, unit="deg/s", composite=False, drift_window=window)
                self.assertEqual(cm.exception.option, "drift_window")
                self.assertIn(says, str(cm.exception))
                self.assertNotIn("--", str(cm.exception))

    def test_valid_calls_still_work(self):
        # The checks take what they should: NumPy scalars, ints for floats, float taus.
        taus, devs, _, _ = cubecal.oadev(Y, rate=np.float32(100.0), taus=[0.01, 0.02])
        self.assertEqual(len(taus), 2)
        self.assertTrue(np.all(np.isfinite(devs)))
        self.assertEqual(len(cubecal.oadev(Y, rate=100, taus=0.04)[0]), 1)
        r = cubecal.dev(Y.astype(np.float32), rate=np.int64(100), threads=np.int32(1), alpha=np.int64(0))
        self.assertTrue(np.all(np.isfinite(r.dev)))
        self.assertEqual(cubecal.simulate("sport-gyro", rate=10, duration="1m", seed=np.uint64(2 ** 63)).rate_hz, 10.0)


if __name__ == "__main__":
    unittest.main()
