"""cubecal.plan equals `cubecal plan --format json` (its rows), for a
preset, a datasheet, an Analysis, a NoiseModel and their files; unreachable
targets carry their reasons; a bad argument is a UsageError naming its
keyword."""
import json
import math
import os
import tempfile
import unittest

import numpy as np

import cubecal
from support import cli, cli_json


class Plan(unittest.TestCase):
    def test_preset_rows_equal_the_cli(self):
        want = cli_json("plan", "--preset", "sport-gyro", "--target", "B:10%,K:20%", "--duration", "24h",
                        "--format", "json")
        got = cubecal.plan("sport-gyro", target="B:10%,K:20%", duration="24h")
        self.assertIsInstance(got, cubecal.Plan)
        self.assertEqual([r.to_dict() for r in got.rows], want)
        self.assertEqual(got.source, "preset")
        self.assertEqual(got.rate_hz, 10.0)
        self.assertEqual([c.name for c in got.channels], ["gx", "gy", "gz"])
        self.assertEqual(got.duration_s, 86400.0)
        row = got.rows[0]
        self.assertEqual((row.channel, row.term, row.kind), ("gx", "B", "target"))
        self.assertEqual(row.precision, 0.1)
        self.assertLessEqual(row.achieved, 0.1)
        self.assertEqual(row.unit, "deg/h")
        self.assertIsNone(row.reason)
        # A dict of fractions is the same targets.
        same = cubecal.plan("sport-gyro", target={"B": 0.1, "K": 0.2}, duration=86400.0)
        self.assertEqual(same.to_dict()["rows"], got.to_dict()["rows"])

    def test_curves_fall_with_length(self):
        p = cubecal.plan("sport-mag", target="N:1%")
        self.assertFalse(p.defaults)
        self.assertEqual(len(p.curves), 3)
        c = p.curves[0]
        self.assertEqual((c.channel, c.term), ("mx", "N"))
        self.assertIsInstance(c.duration_s, np.ndarray)
        self.assertEqual(c.duration_s.size, 40)
        self.assertTrue(np.all(np.diff(c.duration_s) > 0))
        finite = c.precision[np.isfinite(c.precision)]
        self.assertGreater(finite.size, 10)
        self.assertTrue(np.all(np.diff(finite) <= 1e-4 * finite[:-1]))  # white noise: better with every length
        # The planned length lies on the curve: the precision there is the target or just under it.
        length = p.rows[0].duration_s
        self.assertGreaterEqual(length, c.duration_s[0])
        self.assertLessEqual(length, c.duration_s[-1])
        at = np.interp(np.log(length), np.log(c.duration_s), c.precision)
        self.assertAlmostEqual(at, 0.01, delta=0.002)

    def test_defaults(self):
        p = cubecal.plan("sport-gyro")
        self.assertTrue(p.defaults)
        self.assertEqual([(t.term, t.precision) for t in p.targets], [("B", 0.1), ("N", 0.01), ("K", 0.2), ("T", 0.3)])
        self.assertEqual(p.duration_s, 72 * 3600.0)
        self.assertEqual(len(p.rows), 3 * 8)

    def test_datasheet_and_unreachable_targets(self):
        p = cubecal.plan(datasheet="N=0.15deg/rth", rate=100, target="N:1%,K:20%,T:1%")
        self.assertEqual(p.source, "datasheet")
        n, k, t = p.rows
        self.assertIsNone(n.reason)
        self.assertAlmostEqual(n.value, 0.15, delta=1e-6)  # white noise alone: N exactly
        self.assertEqual(n.unit, "deg/sqrt(h)")
        self.assertEqual(k.reason, "not in model")
        self.assertIsNone(k.duration_s)
        self.assertTrue(k.why)
        self.assertEqual(t.reason, "finer than model")
        self.assertIsNone(t.duration_s)
        self.assertEqual(p.rows[1].to_dict(),
                         cli_json("plan", "--datasheet", "N=0.15deg/rth", "--rate", "100", "--target",
                                  "N:1%,K:20%,T:1%", "--format", "json")[1])

    def test_analysis_and_model_results_and_files(self):
        rec = cubecal.simulate("sport-gyro", duration="1h", seed=2, temperature="const:25")
        a = cubecal.analyze({"gx": rec["gx"]}, rate=10.0, unit="deg/s", composite=False)
        p = cubecal.plan(a, target="N:5%")
        self.assertEqual(p.source, "random-walk")
        self.assertIn("no twin", p.source_note)
        self.assertAlmostEqual(p.rows[0].value, 13.9e-3 * math.sqrt(0.1) * 60.0, delta=0.03)
        m = cubecal.model({"gx": rec["gx"]}, "WN+RW", rate=10.0, unit="deg/s", wic_replicates=0)
        q = cubecal.plan(m, target="N:5%", rate=20.0)
        self.assertEqual((q.source, q.rate_hz), ("model", 20.0))
        self.assertAlmostEqual(q.rows[0].value, p.rows[0].value, delta=0.03)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "model.json")
            with open(path, "w") as f:
                json.dump(m.to_dict(), f)
            from_file = cubecal.plan(path, target="N:5%", rate=20.0)
            self.assertEqual(from_file.to_dict()["rows"], q.to_dict()["rows"])
            self.assertEqual(from_file.to_dict()["rows"],
                             cli_json("plan", "--model", path, "--target", "N:5%", "--rate", "20", "--format", "json"))

    def test_bad_arguments_name_their_keyword(self):
        cases = [
            (dict(), "model"),
            (dict(model="sport-gyro", datasheet="N=0.15deg/rth", rate=100), "model"),
            (dict(model="no-such-sensor"), "model"),
            (dict(model=3), "model"),
            (dict(model="sport-gyro", target="X:10%"), "target"),
            (dict(model="sport-gyro", target="B:0%"), "target"),
            (dict(model="sport-gyro", target="B:100%"), "target"),
            (dict(model="sport-gyro", target={"B": "x"}), "target"),
            (dict(model="sport-gyro", target=3), "target"),
            (dict(datasheet="N=0.15deg/rth"), "rate"),
            (dict(datasheet="N=0.15deg/h", rate=100), "datasheet"),
            (dict(datasheet="N=0.15deg/rth,B=1uT", rate=100), "datasheet"),
            (dict(datasheet=" ", rate=100), "datasheet"),
            (dict(model="sport-gyro", duration="3x"), "duration"),
            (dict(model="sport-gyro", duration=-1.0), "duration"),
            (dict(model="sport-gyro", ci=1.5), "ci"),
            (dict(model="sport-gyro", rate=-1.0), "rate"),
            (dict(model="sport-gyro", taus="sometimes"), "taus"),
        ]
        for kwargs, keyword in cases:
            with self.subTest(**{k: repr(v) for k, v in kwargs.items()}):
                with self.assertRaises(cubecal.UsageError) as cm:
                    cubecal.plan(**kwargs)
                self.assertEqual(cm.exception.option, keyword, str(cm.exception))
                self.assertNotIn("\n", str(cm.exception))
                self.assertNotIn("_cubecal", str(cm.exception))

    def test_the_cli_and_python_refuse_alike(self):
        cli("plan", "--datasheet", "N=0.15deg/h", "--rate", "100", expect=2)
        with self.assertRaises(cubecal.UsageError) as cm:
            cubecal.plan(datasheet="N=0.15deg/h", rate=100)
        self.assertIn("N=0.15deg/h: deg/h is not a unit of N", str(cm.exception))


if __name__ == "__main__":
    unittest.main()
