"""The calibrations and the runs commands from Python equal the CLI's JSON
on the same data: cubecal.calibrate_rate_table, calibrate_mag,
calibrate_temperature, calibrate_multiposition, turnon and compare, on a
file and on arrays; data that cannot determine a calibration raise
CalibrationError with its reason, bad arguments UsageError naming the
keyword, bad data InputError.

The comparisons are exact: the arrays are the file's values parsed to the
same doubles (cubecal.read, or numpy.loadtxt of the file's decimal text,
both correctly rounded), so the library computes the same numbers. Only the
keys that name where the data came from differ: "invocation" (the CLI's
command line, the Python call's text here), and for plain arrays the file
name and what depends on its lines. One comparison is to 1e-12 relative,
where it says why: plain arrays at a rate put sample k at k / rate, where the
file's time column has the decimal 274.9 for 274.90000000000003."""
import json
import math
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import SHARED, cli

MAG = os.path.join(SHARED, "mag", "cubesat-adcs", "meas_for_mag_calib.csv")
XSENS = os.path.join(SHARED, "imu", "xsens-multiposition")
MPU = os.path.join(SHARED, "imu", "mpu6050", "example_data_calibration.csv")

# The table's rates (deg/s) over ten 40 s plateaus, as the CLI's report tests run it.
RATES = [(0, 0, 0), (10, 0, 0), (-10, 0, 0), (0, 10, 0), (0, -10, 0), (0, 0, 10), (0, 0, -10), (20, 20, 0),
         (0, -15, 15), (0, 0, 0)]


def without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


def assert_close(test, got, want, rel, where="result"):
    """got and want of the same structure, strings, integers and booleans
    equal, floats within `rel` relative."""
    if isinstance(want, dict):
        test.assertEqual(sorted(got), sorted(want), where)
        for k in want:
            assert_close(test, got[k], want[k], rel, f"{where}.{k}")
    elif isinstance(want, list):
        test.assertEqual(len(got), len(want), where)
        for i, (a, b) in enumerate(zip(got, want)):
            assert_close(test, a, b, rel, f"{where}[{i}]")
    elif isinstance(want, float) and not isinstance(got, bool):
        test.assertIsInstance(got, (float, int), where)
        test.assertLessEqual(abs(got - want), rel * max(abs(got), abs(want)), f"{where}: {got!r} vs {want!r}")
    else:
        test.assertEqual(got, want, where)


def cli_out_json(*args):
    """The CLI run with --format json; its document."""
    return json.loads(cli(*args, "--format", "json"))


def rate_table_log(directory, name, rates, seed):
    """A simulated rate-table run: the sport gyro turned through `rates`
    (40 s each, --true-input), with the table's rates appended as columns
    rx, ry, rz. Returns the path."""
    profile = os.path.join(directory, name + "_profile.csv")
    with open(profile, "w") as f:
        f.write("t,wx,wy,wz\n")
        for k, r in enumerate(rates):
            f.write(f"{40 * k},{r[0]},{r[1]},{r[2]}\n")
    raw = os.path.join(directory, name + "_raw.csv")
    cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", f"{40 * len(rates)}s", "--seed", seed,
        "--true-input", profile, "--out", raw)
    path = os.path.join(directory, name + ".csv")
    with open(raw) as src, open(path, "w") as out:
        out.write(src.readline().rstrip("\n") + ",rx,ry,rz\n")
        for line in src:
            if not line.strip():
                continue
            t = float(line.split(",", 1)[0])
            r = rates[min(len(rates) - 1, int(math.floor(t / 40.0 + 1e-9)))]
            out.write(f"{line.rstrip()},{r[0]:g},{r[1]:g},{r[2]:g}\n")
    return path


class Fixture(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def path(self, name):
        return os.path.join(self.dir.name, name)


class RateTable(Fixture):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.log = rate_table_log(cls.dir.name, "table", RATES, 7)
        cls.schedule = os.path.join(cls.dir.name, "schedule.csv")
        with open(cls.schedule, "w") as f:
            f.write("t_begin,t_end,wx,wy,wz\n")
            for k, r in enumerate(RATES):
                f.write(f"{40 * k},{40 * k + 40},{r[0]},{r[1]},{r[2]}\n")
        cls.want_ref = cli_out_json("calibrate", "rate-table", cls.log, "--columns", "gx,gy,gz", "--ref-columns",
                                    "rx,ry,rz", "--margin", 5, "--min-plateau", 20)
        cls.want_sched = cli_out_json("calibrate", "rate-table", cls.log, "--columns", "gx,gy,gz", "--schedule",
                                      cls.schedule, "--margin", 5, "--min-plateau", 20, "--unit", "deg/s")

    def test_reference_file_equals_cli(self):
        r = cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", reference="rx,ry,rz", margin=5, min_plateau=20)
        self.assertIsInstance(r, cubecal.RateTableCalibration)
        self.assertEqual(without(r.to_dict(), "invocation"), without(self.want_ref, "invocation"))
        self.assertTrue(r.invocation.startswith("cubecal.calibrate_rate_table("), r.invocation)
        self.assertEqual(r.plateau_source, "reference")
        self.assertEqual(r.fit.plateaus, len(r.plateaus))
        self.assertEqual(np.shape(r.A), (3, 3))

    def test_schedule_file_and_rows_equal_cli(self):
        want = without(self.want_sched, "invocation")
        self.assertEqual(want["plateau_source"], "schedule")
        r = cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", schedule=self.schedule, margin=5,
                                         min_plateau=20)
        self.assertEqual(without(r.to_dict(), "invocation"), want)
        rows = np.loadtxt(self.schedule, delimiter=",", skiprows=1)
        r = cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", schedule=rows, margin=5, min_plateau=20)
        self.assertEqual(without(r.to_dict(), "invocation"), want)

    def test_arrays_equal_cli(self):
        # A Record from cubecal.read: the file's values, time stamps and name.
        rec = cubecal.read(self.log, columns="gx,gy,gz", extra="rx,ry,rz")
        r = cubecal.calibrate_rate_table(rec, reference=["rx", "ry", "rz"], margin=5, min_plateau=20)
        self.assertEqual(without(r.to_dict(), "invocation"), without(self.want_ref, "invocation"))
        # Plain arrays: sample k at k / rate, the file's time base but not its
        # decimals (the plateaus' t_end 274.90000000000003 for the file's
        # 274.9): to 1e-12 relative; the calibration itself is exact.
        gyro = np.column_stack([rec["gx"], rec["gy"], rec["gz"]])
        ref = np.column_stack([rec["rx"], rec["ry"], rec["rz"]])
        r = cubecal.calibrate_rate_table(gyro, rate=10.0, reference=ref, margin=5, min_plateau=20)
        self.assertEqual(r.file, "<arrays>")
        got, want = without(r.to_dict(), "invocation", "file"), without(self.want_ref, "invocation", "file")
        assert_close(self, got, want, 1e-12)
        self.assertEqual(without(got, "plateaus"), without(want, "plateaus"))
        rows = np.loadtxt(self.schedule, delimiter=",", skiprows=1)
        r = cubecal.calibrate_rate_table(gyro, rate=10.0, schedule=rows, margin=5, min_plateau=20)
        got, want = without(r.to_dict(), "invocation", "file"), without(self.want_sched, "invocation", "file")
        assert_close(self, got, want, 1e-12)
        self.assertEqual(without(got, "plateaus"), without(want, "plateaus"))

    def test_calibration_errors_have_their_reason(self):
        # Plateaus of 40 s cannot last 100 s.
        cli("calibrate", "rate-table", self.log, "--columns", "gx,gy,gz", "--ref-columns", "rx,ry,rz",
            "--min-plateau", 100, expect=2)
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", reference="rx,ry,rz", min_plateau=100)
        self.assertEqual(cm.exception.reason, "no_plateaus")
        self.assertIsInstance(cm.exception, cubecal.Error)
        # A table turned about x alone cannot determine the other axes.
        x_only = rate_table_log(self.dir.name, "x_only", [(0, 0, 0), (10, 0, 0), (-10, 0, 0), (20, 0, 0),
                                                          (-20, 0, 0), (0, 0, 0)], 3)
        cli("calibrate", "rate-table", x_only, "--columns", "gx,gy,gz", "--ref-columns", "rx,ry,rz", "--margin", 5,
            "--min-plateau", 20, expect=2)
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_rate_table(x_only, columns="gx,gy,gz", reference="rx,ry,rz", margin=5, min_plateau=20)
        self.assertEqual(cm.exception.reason, "degenerate")

    def test_usage_and_input_errors(self):
        rows = np.loadtxt(self.schedule, delimiter=",", skiprows=1)
        for call, option in (
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz"), "reference"),
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", reference="rx,ry,rz",
                                                      schedule=rows), "schedule"),
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy", schedule=rows), "columns"),
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", schedule=rows, unit="rpm"),
                 "unit"),
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", schedule=rows[:, :4]),
                 "schedule"),
                (lambda: cubecal.calibrate_rate_table(self.log, columns="gx,gy,gz", schedule=rows, margin=-1),
                 "margin"),
                (lambda: cubecal.calibrate_rate_table(np.zeros((100, 3)), schedule=rows), "rate")):
            with self.subTest(option=option):
                with self.assertRaises(cubecal.UsageError) as cm:
                    call()
                self.assertEqual(cm.exception.option, option)
        gyro = np.zeros((4000, 3))
        gyro[123, 1] = np.nan
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.calibrate_rate_table(gyro, rate=10.0, schedule=rows)
        self.assertEqual((cm.exception.line, cm.exception.column), (124, 2))
        with self.assertRaises(cubecal.InputError):
            cubecal.calibrate_rate_table(self.path("missing.csv"), columns="gx,gy,gz", schedule=rows)


class Mag(Fixture):
    def test_twostep_file_and_arrays_equal_cli(self):
        want = cli_out_json("calibrate", "mag", MAG, "--method", "twostep", "--reject", 2, "--unit", "norm")
        r = cubecal.calibrate_mag(MAG, method="twostep", reject=2, unit="norm")
        self.assertIsInstance(r, cubecal.MagCalibration)
        self.assertEqual(without(r.to_dict(), "invocation"), without(want, "invocation"))
        self.assertEqual(r.method, "twostep")
        self.assertGreater(want["rejected"], 0)  # the rejected lines are compared below
        # The points as an (n, 3) array: numbered from 1 instead of the file's
        # lines, which start after the header.
        points = np.loadtxt(MAG, delimiter=",", skiprows=1)
        a = cubecal.calibrate_mag(points, method="twostep", reject=2, unit="norm").to_dict()
        self.assertEqual(a["file"], "<arrays>")
        self.assertEqual(a["first_data_line"] + 1, want["first_data_line"])
        self.assertEqual([k + 1 for k in a["rejected_lines"]], want["rejected_lines"])
        self.assertEqual(without(a, "invocation", "file", "first_data_line", "rejected_lines"),
                         without(want, "invocation", "file", "first_data_line", "rejected_lines"))
        # Three arrays, or named columns, are the same points.
        b = cubecal.calibrate_mag(list(points.T), method="twostep", reject=2, unit="norm").to_dict()
        self.assertEqual(without(b, "invocation"), without(a, "invocation"))
        c = cubecal.calibrate_mag({"magx": points[:, 0], "magy": points[:, 1], "magz": points[:, 2]},
                                  method="twostep", reject=2, unit="norm").to_dict()
        self.assertEqual(without(c, "invocation"), without(a, "invocation"))

    def test_ellipsoid_equals_cli_and_poor_coverage_is_a_calibration_error(self):
        want = cli_out_json("calibrate", "mag", MAG, "--allow-partial", "--field-norm", 1)
        r = cubecal.calibrate_mag(MAG, allow_partial=True, field_norm=1)
        self.assertEqual(without(r.to_dict(), "invocation"), without(want, "invocation"))
        self.assertEqual(r.method, "ellipsoid")
        self.assertEqual(r.field_norm_source, "given")
        # The cubesat points cover less than a hemisphere: the ellipsoid is
        # refused without allow_partial, as by the CLI.
        cli("calibrate", "mag", MAG, expect=2)
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_mag(MAG)
        self.assertEqual(cm.exception.reason, "poor_coverage")
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_mag(np.loadtxt(MAG, delimiter=",", skiprows=1))
        self.assertEqual(cm.exception.reason, "poor_coverage")

    def test_usage_errors(self):
        points = np.loadtxt(MAG, delimiter=",", skiprows=1)
        for call, option in (
                (lambda: cubecal.calibrate_mag(points, method="magneto"), "method"),
                (lambda: cubecal.calibrate_mag(points, field_norm=-1), "field_norm"),
                (lambda: cubecal.calibrate_mag(points, method="twostep", noise=0), "noise"),
                (lambda: cubecal.calibrate_mag(points, field_column=np.ones(len(points))), "field_column"),
                (lambda: cubecal.calibrate_mag(points[:, :2]), "points"),
                (lambda: cubecal.calibrate_mag(MAG, columns="magx,magy"), "columns")):
            with self.subTest(option=option):
                with self.assertRaises(cubecal.UsageError) as cm:
                    call()
                self.assertEqual(cm.exception.option, option)


class Temperature(Fixture):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.csv = os.path.join(cls.dir.name, "mag.csv")
        cli("simulate", "--preset", "sport-mag", "--rate", 1, "--duration", "12h", "--temp", "sine:25,10,21600",
            "--seed", 2, "--out", cls.csv)
        cls.want = cli_out_json("calibrate", "temperature", cls.csv, "--columns", "mx,my,mz", "--temp-col", "temp",
                                "--unit", "mGauss", "--order", 2)

    def test_file_equals_cli(self):
        r = cubecal.calibrate_temperature(self.csv, "temp", columns="mx,my,mz", unit="mGauss", order=2)
        self.assertIsInstance(r, cubecal.TemperatureCalibration)
        self.assertEqual(r.to_dict(), self.want)
        self.assertEqual([c.name for c in r.channels], ["mx", "my", "mz"])
        self.assertEqual(r.channels[0].coeff_units, ["mGauss", "mGauss/degC", "mGauss/degC^2"])

    def test_arrays_equal_cli(self):
        # The Record holds the file's values and name: the whole document is the CLI's.
        rec = cubecal.read(self.csv, columns="mx,my,mz", extra="temp")
        r = cubecal.calibrate_temperature(rec, "temp", unit="mGauss", order=2)
        self.assertEqual(r.to_dict(), self.want)
        # Bare arrays, the temperature as an array of its own.
        data = np.column_stack([rec["mx"], rec["my"], rec["mz"]])
        r = cubecal.calibrate_temperature(data, rec["temp"], unit="mGauss", order=2, names=["mx", "my", "mz"])
        self.assertEqual(without(r.to_dict(), "file", "temperature_column"),
                         without(self.want, "file", "temperature_column"))

    def test_constant_temperature_is_a_calibration_error(self):
        y = np.random.default_rng(5).normal(size=(2000, 2))
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_temperature(y, np.full(2000, 25.0), unit="deg/s")
        self.assertEqual(cm.exception.reason, "degenerate")
        self.assertIn("ch1", str(cm.exception))
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calibrate_temperature(y, np.linspace(20, 30, 2000), order=6)
        self.assertEqual(cm.exception.option, "order")
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.calibrate_temperature(y, np.linspace(20, 30, 1999))
        self.assertEqual(cm.exception.option, "temperature")
        with self.assertRaises(cubecal.InputError):
            cubecal.calibrate_temperature(self.csv, "no_such_column", columns="mx")


class Multiposition(Fixture):
    ARGS = dict(g=9.81744, init_static=50, acc_bias=32768, gyro_scale=1.598e-4)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.acc = os.path.join(XSENS, "xsens_acc.txt")
        cls.gyro = os.path.join(XSENS, "xsens_gyro.txt")
        cls.want = cli_out_json("calibrate", "multiposition", cls.acc, cls.gyro, "--acc-columns", "2,3,4",
                                "--time-col", 1, "--g", 9.81744, "--init-static", 50, "--acc-bias", 32768,
                                "--gyro-scale", 1.598e-4)

    def test_files_equal_cli(self):
        r = cubecal.calibrate_multiposition(self.acc, self.gyro, acc_columns="2,3,4", time="1", **self.ARGS)
        self.assertIsInstance(r, cubecal.MultipositionCalibration)
        self.assertEqual(without(r.to_dict(), "invocation"), without(self.want, "invocation"))
        self.assertEqual(r.static_intervals, 38)
        self.assertTrue(r.gyroscope.converged)

    def test_arrays_equal_cli(self):
        a = np.loadtxt(self.acc)
        g = np.loadtxt(self.gyro)
        r = cubecal.calibrate_multiposition(a[:, 1:], g[:, 1:], time=a[:, 0], gyro_time=g[:, 0], **self.ARGS)
        got = r.to_dict()
        self.assertEqual((got["acc_file"], got["gyro_file"]), ("<arrays>", "<gyro arrays>"))
        self.assertEqual(without(got, "invocation", "acc_file", "gyro_file"),
                         without(self.want, "invocation", "acc_file", "gyro_file"))
        # The accelerometer alone is the same accelerometer calibration.
        alone = cubecal.calibrate_multiposition(a[:, 1:], time=a[:, 0], **self.ARGS)
        self.assertIsNone(alone.gyroscope)
        self.assertEqual(alone.to_dict()["accelerometer"], self.want["accelerometer"])

    def test_one_file_with_both_triads_and_too_few_poses(self):
        args = dict(skip_rows=4, acc_columns="ax,ay,az", gyro_columns="gx,gy,gz", rate=100, g=9.81, init_static=30,
                    gyro_scale=1.3323e-4)
        cli_args = ["calibrate", "multiposition", MPU, "--skip-rows", 4, "--acc-columns", "ax,ay,az",
                    "--gyro-columns", "gx,gy,gz", "--rate", 100, "--g", 9.81, "--init-static", 30, "--gyro-scale",
                    1.3323e-4]
        cli(*cli_args, expect=2)
        with self.assertRaises(cubecal.CalibrationError) as cm:
            cubecal.calibrate_multiposition(MPU, **args)
        self.assertEqual(cm.exception.reason, "too_few_intervals")
        want = cli_out_json(*cli_args, "--min-intervals", 10)
        r = cubecal.calibrate_multiposition(MPU, min_intervals=10, **args)
        self.assertEqual(without(r.to_dict(), "invocation"), without(want, "invocation"))
        self.assertEqual(r.gyro_file, MPU)

    def test_usage_and_input_errors(self):
        a = np.loadtxt(self.acc)
        for call, option in (
                (lambda: cubecal.calibrate_multiposition(a[:, 1:]), "rate"),
                (lambda: cubecal.calibrate_multiposition(a[:, 1:], time=a[:, 0], rate=100), "rate"),
                (lambda: cubecal.calibrate_multiposition(a[:, 1:], rate=100, window=5), "window"),
                (lambda: cubecal.calibrate_multiposition(a[:, 1:], rate=100, acc_bias=[1, 2]), "acc_bias"),
                (lambda: cubecal.calibrate_multiposition(self.acc, acc_columns="2,3", time="1"), "acc_columns")):
            with self.subTest(option=option):
                with self.assertRaises(cubecal.UsageError) as cm:
                    call()
                self.assertEqual(cm.exception.option, option)
        # 50 samples taken out: a gap the gyroscope cannot be integrated across.
        t = np.delete(a[:, 0], np.s_[5300:5350])
        with self.assertRaises(cubecal.InputError) as cm:
            cubecal.calibrate_multiposition(np.delete(a[:, 1:], np.s_[5300:5350], axis=0), time=t, **self.ARGS)
        self.assertEqual(cm.exception.line, 5301)
        self.assertIn("gap", cm.exception.problem)


class Runs(Fixture):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.runs = []
        for seed in (1, 2, 3):
            path = os.path.join(cls.dir.name, f"run{seed}.csv")
            cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "10m", "--temp", "const:25",
                "--seed", seed, "--out", path)
            cls.runs.append(path)

    def test_turnon_equals_cli(self):
        want = cli_out_json("turnon", *self.runs, "--columns", "gx,gy,gz", "--unit", "deg/s")
        r = cubecal.turnon(self.runs, columns="gx,gy,gz", unit="deg/s")
        self.assertIsInstance(r, cubecal.TurnOn)
        self.assertEqual(r.to_dict(), want)
        self.assertEqual([c.name for c in r.channels], ["gx", "gy", "gz"])
        # Records read from the files are the same runs.
        records = [cubecal.read(p, columns="gx,gy,gz") for p in self.runs]
        self.assertEqual(cubecal.turnon(records, unit="deg/s").to_dict(), want)
        # Bare arrays: the same numbers, the runs named by their place.
        arrays = [np.column_stack([rec["gx"], rec["gy"], rec["gz"]]) for rec in records]
        got = cubecal.turnon(arrays, rate=10, unit="deg/s", names=["gx", "gy", "gz"]).to_dict()
        self.assertEqual([run["file"] for run in got["runs"]], ["<run 1>", "<run 2>", "<run 3>"])
        for run in got["runs"] + want["runs"]:
            run.pop("file")
        self.assertEqual(got, want)

    def test_compare_equals_cli_with_options_per_run(self):
        want = cli_out_json("compare", self.runs[0], self.runs[1] + ":columns=gx,gy", self.runs[2], "--columns",
                            "gx,gy,gz", "--unit", "deg/s", "--taus", "octave")
        r = cubecal.compare([self.runs[0], (self.runs[1], {"columns": "gx,gy"}), self.runs[2]], columns="gx,gy,gz",
                            unit="deg/s", taus="octave")
        self.assertIsInstance(r, cubecal.Comparison)
        self.assertEqual(r.to_dict(), want)
        self.assertEqual([len(run.channels) for run in r.runs], [3, 2, 3])

    def test_usage_errors(self):
        for call, option in (
                (lambda: cubecal.turnon(self.runs[:1], columns="gx,gy,gz", unit="deg/s"), "runs"),
                (lambda: cubecal.turnon(self.runs, columns="gx,gy,gz"), "unit"),
                (lambda: cubecal.turnon(self.runs, columns="gx,gy,gz", unit="furlongs"), "unit"),
                (lambda: cubecal.turnon([self.runs[0], (self.runs[1], {"unit": "rad/s"})], columns="gx,gy,gz",
                                        unit="deg/s"), "unit"),
                (lambda: cubecal.turnon([self.runs[0], (self.runs[1], {"columns": "gx,gy"})], columns="gx,gy,gz",
                                        unit="deg/s"), "columns"),
                (lambda: cubecal.turnon([np.zeros(100), np.ones(100)], unit="deg/s"), "rate"),
                (lambda: cubecal.compare(self.runs, columns="gx,gy,gz", unit="deg/s", ci=2), "ci")):
            with self.subTest(option=option):
                with self.assertRaises(cubecal.UsageError) as cm:
                    call()
                self.assertEqual(cm.exception.option, option)


if __name__ == "__main__":
    unittest.main()
