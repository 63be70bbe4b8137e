"""The Python examples (examples/python) run and agree with the CLI: the
paper's gyro figure drawn from a simulated record of the paper's experiment
reports the numbers `cubecal analyze` finds on the same record, and the Dask
fleet analysis of the six ADIS16405 runs tabulates exactly what `cubecal
analyze` reports for each run."""
import csv
import importlib.util
import json
import os
import statistics
import subprocess
import sys
import tempfile
import unittest

from support import SHARED, cli, cli_json, relative

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python")
ADIS = os.path.realpath(os.path.join(SHARED, "imu", "adis16405"))
ADIS_RUNS = [f"run{k}.csv.gz" for k in range(1, 7)]
GYRO_COLUMNS = "gyro_x_dps,gyro_y_dps,gyro_z_dps"
# The demo's analysis (src/cli/cmd_demo.cpp), which the figure's script repeats.
DEMO_ANALYZE = ("--unit", "deg/s,deg/s,deg/s,mGauss,mGauss,mGauss", "--temp-col", "temp", "--taus", "log:20",
                "--max-samples", 42000, "--model-lsb", "145.6,145.6,145.6,1.3,1.3,1.3")
# analysis.json's reported terms (noise.reported) under their symbols.
TERMS = {"N": "white_noise", "B": "bias_instability", "K": "rate_random_walk"}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def has(module):
    return importlib.util.find_spec(module) is not None


def run_example(script, *args):
    """Runs an example with this interpreter (its environment: PYTHONPATH
    reaches the module); returns its standard output."""
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *map(str, args)], capture_output=True,
                       text=True, timeout=600)
    if p.returncode != 0:
        raise AssertionError(f"{script} {' '.join(map(str, args))}: exit {p.returncode}:\n{p.stderr}")
    return p.stdout


@unittest.skipUnless(has("matplotlib"), "needs matplotlib (Debian: python3-matplotlib)")
class PaperGyroFigure(unittest.TestCase):
    """paper_gyro_figure.py against `cubecal simulate` + `cubecal analyze`
    with the same seed and options. The CLI's record is the CSV (nine
    significant digits), the script's the simulation in memory: the numbers
    agree to 1e-6 relative, not to the last bit."""

    SEED = 5
    HOURS = 3

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.figure = os.path.join(cls.dir.name, "figure", "gyro.png")
        out = run_example("paper_gyro_figure.py", "--hours", cls.HOURS, "--seed", cls.SEED, "--out", cls.figure,
                          "--json")
        cls.got = json.loads(out.strip().splitlines()[-1])
        record = os.path.join(cls.dir.name, "sport.csv")
        cli("simulate", "--preset", "sport-gyro,sport-mag", "--rate", 10, "--duration", f"{cls.HOURS}h", "--seed",
            cls.SEED, "--temp", "sine:25,5", "--out", record)
        result = os.path.join(cls.dir.name, "cli")
        cli("analyze", record, *DEMO_ANALYZE, "--out", result)
        with open(os.path.join(result, "analysis.json")) as f:
            cls.want = json.load(f)
        with open(os.path.join(result, "adev.csv")) as f:
            cls.adev_csv = list(csv.DictReader(f))

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_writes_a_png(self):
        self.assertEqual(self.got["figure"], os.path.abspath(self.figure))
        with open(self.figure, "rb") as f:
            data = f.read()
        self.assertEqual(data[:8], PNG_MAGIC)
        self.assertGreater(len(data), 20000)  # a drawn figure, not an empty canvas

    def test_the_gyro_axes_of_the_record(self):
        self.assertEqual([c["name"] for c in self.got["channels"]], ["gx", "gy", "gz"])
        self.assertEqual(self.got["samples"], self.want["input"]["samples"])
        self.assertEqual(self.got["samples"], self.HOURS * 3600 * 10)

    def test_read_offs_equal_the_cli(self):
        for got, want in zip(self.got["channels"], self.want["channels"]):
            for symbol, key in TERMS.items():
                with self.subTest(channel=got["name"], term=symbol):
                    w = want["noise"]["reported"][key]
                    self.assertEqual(got[symbol]["source"], w["source"])
                    self.assertEqual(got[symbol]["unit"], w["unit"])
                    self.assertLess(relative(got[symbol]["value"], w["value"]), 1e-6)
                    if w["sigma"] is None:
                        self.assertIsNone(got[symbol]["sigma"])
                    else:
                        self.assertLess(relative(got[symbol]["sigma"], w["sigma"]), 1e-6)
            with self.subTest(channel=got["name"], term="T"):
                self.assertEqual(got["T_s"], want["noise"]["time_constant_s"])

    def test_model_equals_the_cli(self):
        for got, want in zip(self.got["channels"], self.want["channels"]):
            with self.subTest(channel=got["name"]):
                model = want["model"]
                self.assertEqual(got["model_samples"], model["samples"])
                self.assertEqual(got["lsb"], model["lsb"])
                self.assertLess(relative(got["sigma_n"], model["sigma_n"]), 1e-6)
                self.assertLess(relative(got["sigma_mu"], model["sigma_mu"]), 1e-6)
                # The drawn model curve is the CLI's model_dev (avar(RandomWalkModel, m), nine digits).
                rows = [r for r in self.adev_csv if r["channel"] == got["name"]]
                self.assertEqual(len(got["model_tau"]), len(rows))
                self.assertLess(relative(got["model_tau"], [float(r["tau"]) for r in rows]), 1e-8)
                self.assertLess(relative(got["model_dev"], [float(r["model_dev"]) for r in rows]), 1e-6)


def csv_number(text, kind=float):
    return None if text == "" else kind(text)


@unittest.skipUnless(has("dask") and has("distributed"), "needs Dask (Debian: python3-dask, python3-distributed)")
class Fleet(unittest.TestCase):
    """fleet.py on a 2-worker LocalCluster over the six ADIS16405 runs
    (gyro columns) against `cubecal analyze` of each run: every number of the
    table, and each file's analysis.json, equal to the last bit."""

    @classmethod
    def setUpClass(cls):
        if not all(os.path.exists(os.path.join(ADIS, run)) for run in ADIS_RUNS):
            raise unittest.SkipTest(f"no ADIS16405 runs in {ADIS}")
        cls.dir = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.dir.name, "fleet")
        cls.stdout = run_example("fleet.py", ADIS, "--columns", GYRO_COLUMNS, "--unit", "deg/s", "--pattern",
                                 "run*.csv.gz", "--workers", 2, "--out", cls.out)
        with open(os.path.join(cls.out, "fleet.csv"), newline="") as f:
            cls.rows = list(csv.DictReader(f))
        with open(os.path.join(cls.out, "fleet.json")) as f:
            cls.fleet = json.load(f)
        cls.want = {run: cli_json("analyze", os.path.join(ADIS, run), "--columns", GYRO_COLUMNS, "--unit", "deg/s",
                                  "--format", "json") for run in ADIS_RUNS}

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def cli_channel(self, run, name):
        return next(c for c in self.want[run]["channels"] if c["name"] == name)

    def test_one_row_per_file_and_channel(self):
        self.assertEqual([(r["file"], r["channel"]) for r in self.rows],
                         [(run, c) for run in ADIS_RUNS for c in GYRO_COLUMNS.split(",")])
        self.assertIn("6 of 6 files analyzed, 18 rows", self.stdout)

    def test_csv_equals_the_cli(self):
        for row in self.rows:
            with self.subTest(file=row["file"], channel=row["channel"]):
                want = self.want[row["file"]]
                c = self.cli_channel(row["file"], row["channel"])
                self.assertEqual(row["unit"], c["unit"])
                self.assertEqual(int(row["samples"]), want["input"]["samples"])
                self.assertEqual(float(row["rate_hz"]), want["input"]["rate_hz"])
                for symbol, key in TERMS.items():
                    term = c["noise"]["reported"][key]
                    self.assertEqual(csv_number(row[symbol]), term["value"])
                    self.assertEqual(csv_number(row[f"{symbol}_sigma"]), term["sigma"])
                    self.assertEqual(row[f"{symbol}_unit"], term["unit"])
                    self.assertEqual(row[f"{symbol}_source"], term["source"])
                self.assertEqual(csv_number(row["T_s"]), c["noise"]["time_constant_s"])
                self.assertEqual(csv_number(row["sigma_n"]), c["model"]["sigma_n"])
                self.assertEqual(csv_number(row["sigma_mu"]), c["model"]["sigma_mu"])

    def test_json_rows_equal_the_csv(self):
        self.assertEqual(len(self.fleet["rows"]), len(self.rows))
        for got, row in zip(self.fleet["rows"], self.rows):
            for key, text in row.items():
                value = got[key]
                self.assertEqual("" if value is None else str(value), text, key)

    def test_json_holds_each_files_analysis(self):
        files = {f["file"]: f["analysis"] for f in self.fleet["files"]}
        self.assertEqual(sorted(files), ADIS_RUNS)
        for run, analysis in files.items():
            with self.subTest(file=run):
                want = dict(self.want[run])
                got = dict(analysis)
                self.assertTrue(got.pop("command").startswith("cubecal.analyze("))
                want.pop("command")
                self.assertEqual(got, want)

    def test_fleet_statistics(self):
        summary = {(s["channel"], s["term"]): s for s in self.fleet["summary"]}
        for channel in GYRO_COLUMNS.split(","):
            for symbol in ("N", "B"):
                with self.subTest(channel=channel, term=symbol):
                    terms = {run: self.cli_channel(run, channel)["noise"]["reported"][TERMS[symbol]]
                             for run in ADIS_RUNS}
                    values = {run: t["value"] for run, t in terms.items() if not t["upper_bound"]}
                    s = summary[(channel, symbol)]
                    self.assertEqual(s["n"], len(values))
                    self.assertEqual(s["min"], min(values.values()))
                    self.assertEqual(s["max"], max(values.values()))
                    med = statistics.median(values.values())
                    self.assertEqual(s["median"], med)
                    mad = 1.4826 * statistics.median(abs(v - med) for v in values.values())
                    self.assertEqual(s["outliers"], [run for run, v in values.items() if abs(v - med) > 3 * mad])

    def test_summary_page(self):
        with open(os.path.join(self.out, "summary.html"), encoding="utf-8") as f:
            page = f.read()
        self.assertTrue(page.startswith("<!DOCTYPE html>"))
        self.assertNotIn("<script", page)
        self.assertNotIn("src=", page)  # self-contained
        for run in ADIS_RUNS:
            self.assertIn(run, page)
        for channel in GYRO_COLUMNS.split(","):
            self.assertIn(channel, page)
        flagged = sum(len(s["outliers"]) for s in self.fleet["summary"])
        self.assertEqual(page.count('class="out"'), flagged)


if __name__ == "__main__":
    unittest.main()
