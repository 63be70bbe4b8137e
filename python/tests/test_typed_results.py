"""Typed results: every call that returns a command's document returns it
as typed objects (a class per kind of object, its fields declared with their
units; arrays of numbers NumPy arrays made in the binding), whose to_dict()
equals the command's JSON (`--format json` of the CLI on the same record),
whose repr is a short summary, and whose classes and functions agree with
the package's type stubs (cubecal/*.pyi).

The stub checks are generic: every public name a module of the package
defines appears in the stub beside it (python/cubecal/NAME.pyi) with the
same parameters (names, kinds, defaults), which holds for the stubs of every
module, not only the results'."""
import ast
import inspect
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import cubecal
from cubecal._result import Node, Result
from support import SHARED, cli, cli_json

PACKAGE = os.path.dirname(cubecal.__file__)
SCRIPTS = os.path.join(os.path.dirname(__file__), "..", "..", "scripts")
MAG = os.path.join(SHARED, "mag", "cubesat-adcs", "meas_for_mag_calib.csv")
XSENS = os.path.join(SHARED, "imu", "xsens-multiposition")


def without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


def undeclared(value, where="result"):
    """Places in a result that no class declares: an object left a generic
    Node where its field is not declared Any, or a key no class names."""
    out = []
    if isinstance(value, Result):
        fields = type(value)._fields
        for key, x in value.items():
            spec = fields.get(key)
            if spec is None and not isinstance(value, Node):
                out.append(f"{where}.{key}")
            elif isinstance(x, Node) and (spec is None or spec[0] != "Any"):
                out.append(f"{where}.{key}")
            out += undeclared(x, f"{where}.{key}")
    elif isinstance(value, list):
        for i, x in enumerate(value):
            out += undeclared(x, f"{where}[{i}]")
    return out


def arrays_of(value):
    """The NumPy arrays a result holds."""
    if isinstance(value, Result):
        for x in value.values():
            yield from arrays_of(x)
    elif isinstance(value, list):
        for x in value:
            yield from arrays_of(x)
    elif isinstance(value, np.ndarray):
        yield value


class Documents(unittest.TestCase):
    """Each result type against the CLI's JSON of the same record."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.dir.name, "imu.csv")
        cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "30m", "--seed", 5,
            "--temp", "sine:25,10,3600", "--out", cls.csv)
        cls.runs = []
        for seed in (1, 2):
            path = os.path.join(cls.dir.name, f"run{seed}.csv")
            cli("simulate", "--preset", "sport-gyro", "--rate", 10, "--duration", "10m", "--seed", seed,
                "--out", path)
            cls.runs.append(path)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def check(self, result, want, cls, ignore=()):
        """result is a cls, typed throughout, equal to want but for `ignore`
        (and "invocation", the CLI's command line or the Python call's text)."""
        ignore = ("invocation",) + tuple(ignore)
        self.assertIsInstance(result, cls)
        self.assertEqual(without(result.to_dict(), *ignore), without(want, *ignore))
        self.assertEqual(undeclared(result), [])
        arrays = list(arrays_of(result))
        self.assertTrue(arrays, "a result with arrays of numbers holds them as NumPy arrays")
        for a in arrays:
            self.assertFalse(a.flags.writeable)
        text = repr(result)
        self.assertTrue(text.startswith(cls.__name__ + "("), text)
        self.assertLessEqual(len(text.splitlines()), 8, text)
        self.assertLess(max(len(line) for line in text.splitlines()), 400, text)
        # to_dict() is a copy: changing it leaves the result as it was.
        d = result.to_dict()
        d.clear()
        self.assertEqual(without(result.to_dict(), *ignore), without(want, *ignore))
        # JSON text of to_dict() reads back to the same document.
        self.assertEqual(json.loads(result.to_json()), result.to_dict())

    def test_analyze(self):
        want = cli_json("analyze", self.csv, "--columns", "gx,gy,gz", "--unit", "deg/s", "--temp-col", "temp",
                        "--psd", "--format", "json")
        a = cubecal.analyze(self.csv, columns="gx,gy,gz", unit="deg/s", temperature="temp", psd=True)
        self.check(a, want, cubecal.Analysis, ignore=("command",))
        c = a.channels[0]
        self.assertIsInstance(c.noise.reported.white_noise.value, float)
        self.assertEqual(c.noise.reported.white_noise.unit, "deg/sqrt(h)")
        self.assertEqual(c.adev.tau.dtype, np.float64)
        self.assertEqual(c.adev.af.dtype, np.int64)
        self.assertEqual(c.temperature.coeff_cov.ndim, 2)
        self.assertIs(a["channels"][0], a.channels[0])
        self.assertEqual(type(c.spectral).__name__, "SpectralView")
        self.assertIn("gx", repr(a))
        self.assertIn("deg/sqrt(h)", repr(a))

    def test_model(self):
        want = cli_json("model", self.csv, "--columns", "gx", "--model", "WN+RW,WN+GM", "--wic-replicates", 0,
                        "--bootstrap", 4, "--format", "json")
        m = cubecal.model(self.csv, "WN+RW,WN+GM", columns="gx", wic_replicates=0, bootstrap=4)
        self.check(m, want, cubecal.NoiseModel, ignore=("command",))
        q = m.channels[0].terms[0].quantities[0]
        self.assertIsInstance(q.display.unit, str)
        self.assertEqual(m.channels[0].wavelet_variance.n.dtype, np.int64)

    def test_psd_and_davar(self):
        want = cli_json("psd", self.csv, "--columns", "gx,gy", "--format", "json")
        p = cubecal.psd(self.csv, columns="gx,gy")
        self.check(p, want, cubecal.Spectrum, ignore=("command",))
        self.assertEqual(p.channels[0].frequency_hz.shape, p.channels[0].density.shape)
        want = cli_json("davar", self.csv, "--columns", "gx", "--window", "5m", "--step", "60s", "--format", "json")
        d = cubecal.davar(self.csv, columns="gx", window="5m", step="60s")
        self.check(d, want, cubecal.DynamicAllan, ignore=("command",))
        ch = d.channels[0]
        self.assertEqual(ch.dev.shape, (len(ch.tau), len(ch.t)))

    def test_dev(self):
        rec = cubecal.read(self.csv, columns="gx,gy")
        want = cli_json("dev", self.csv, "--columns", "gx,gy", "--taus", "log:5", "--format", "json")
        r = cubecal.dev(rec, taus="log:5")
        self.assertIsInstance(r, cubecal.DevResult)
        self.assertEqual(without(r.to_dict(), "file"), without(want, "file"))
        self.assertEqual(undeclared(r), [])
        self.assertIn("oadev of gx, gy", repr(r))

    def test_calibrations(self):
        want = cli_json("calibrate", "mag", MAG, "--method", "twostep", "--reject", 2, "--unit", "norm",
                        "--format", "json")
        self.check(cubecal.calibrate_mag(MAG, method="twostep", reject=2, unit="norm"), want, cubecal.MagCalibration,
                   ignore=("invocation",))
        want = cli_json("calibrate", "temperature", self.csv, "--columns", "gx,gy,gz", "--temp-col", "temp",
                        "--order", 2, "--unit", "deg/s", "--format", "json")
        t = cubecal.calibrate_temperature(self.csv, "temp", columns="gx,gy,gz", order=2, unit="deg/s")
        self.check(t, want, cubecal.TemperatureCalibration)
        acc, gyro = os.path.join(XSENS, "xsens_acc.txt"), os.path.join(XSENS, "xsens_gyro.txt")
        want = cli_json("calibrate", "multiposition", acc, gyro, "--acc-columns", "2,3,4", "--time-col", 1, "--g",
                        9.81744, "--init-static", 50, "--acc-bias", 32768, "--gyro-scale", 1.598e-4, "--format", "json")
        r = cubecal.calibrate_multiposition(acc, gyro, acc_columns="2,3,4", time="1", g=9.81744, init_static=50,
                                            acc_bias=32768, gyro_scale=1.598e-4)
        self.check(r, want, cubecal.MultipositionCalibration, ignore=("invocation",))
        self.assertEqual(r.accelerometer.model.T.shape, (3, 3))
        self.assertIsInstance(r.accelerometer.model.misalignment.xy, float)

    def test_rate_table(self):
        sys.path.insert(0, os.path.dirname(__file__))
        from test_calibrate import RATES, rate_table_log
        log = rate_table_log(self.dir.name, "table", RATES, 7)
        want = cli_json("calibrate", "rate-table", log, "--columns", "gx,gy,gz", "--ref-columns", "rx,ry,rz",
                        "--margin", 5, "--min-plateau", 20, "--format", "json")
        r = cubecal.calibrate_rate_table(log, columns="gx,gy,gz", reference="rx,ry,rz", margin=5, min_plateau=20)
        self.check(r, want, cubecal.RateTableCalibration, ignore=("invocation",))
        self.assertEqual(r.A.shape, (3, 3))
        self.assertIn("ppm", repr(r))

    def test_runs(self):
        want = cli_json("turnon", *self.runs, "--columns", "gx,gy,gz", "--unit", "deg/s", "--format", "json")
        r = cubecal.turnon(self.runs, columns="gx,gy,gz", unit="deg/s")
        self.check(r, want, cubecal.TurnOn)
        self.assertEqual(r.runs[0].channels[0].adev.m.dtype, np.int64)
        want = cli_json("compare", *self.runs, "--columns", "gx,gy,gz", "--unit", "deg/s", "--format", "json")
        self.check(cubecal.compare(self.runs, columns="gx,gy,gz", unit="deg/s"), want, cubecal.Comparison)


class Conversion(unittest.TestCase):
    """The binding's arrays and their way back to the JSON's lists."""

    def test_nan_is_none_in_to_dict_and_integers_stay_integers(self):
        y = np.random.default_rng(2).normal(size=3000)
        with tempfile.TemporaryDirectory() as directory:
            path = os.path.join(directory, "gap.csv")
            with open(path, "w") as f:
                f.write("t,gx_dps\n")
                for k, v in enumerate(y):
                    f.write(f"{k / 10:.1f},{'' if 1000 <= k < 1800 else repr(float(v))}\n")
            want = cli_json("davar", path, "--gaps", "skip", "--window", "60s", "--step", "20s", "--format", "json")
            d = cubecal.davar(path, gaps="skip", window="60s", step="20s")
        ch = d.channels[0]
        self.assertTrue(np.isnan(ch.dev).any(), "a window inside the gap has no value")
        doc = d.to_dict()
        self.assertEqual(without(doc, "invocation"), without(want, "invocation"))
        rows = doc["channels"][0]["dev"]
        self.assertTrue(any(v is None for row in rows for v in row))
        self.assertFalse(any(isinstance(v, float) and math.isnan(v) for row in rows for v in row))
        self.assertTrue(all(type(v) is int for v in doc["channels"][0]["m"]))
        self.assertTrue(all(type(v) is float for v in doc["channels"][0]["tau"]))
        self.assertEqual(ch.dev.dtype, np.float64)
        self.assertEqual(ch.dev.shape, (len(ch.tau), len(ch.t)))

    def test_result_is_read_only(self):
        d = cubecal.davar(np.random.default_rng(3).normal(size=2000), rate=10.0)
        with self.assertRaises(AttributeError):
            d.window = None
        with self.assertRaises(ValueError):
            d.channels[0].tau[0] = 1.0

    def test_pickle_and_copy(self):
        import copy
        import pickle
        m = cubecal.model(np.random.default_rng(5).normal(size=5000), "WN+RW", rate=10.0, wic_replicates=0)
        m.channels[0].terms  # wrapped before pickling, or not: the same document
        for other in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m)):
            self.assertIsInstance(other, cubecal.NoiseModel)
            self.assertEqual(other.to_dict(), m.to_dict())
            self.assertEqual(other.channels[0].terms[0].term, "WN")
        r = cubecal.dev(np.random.default_rng(6).normal(size=1000), rate=1.0)
        self.assertEqual(pickle.loads(pickle.dumps(r)).to_dict(), r.to_dict())

    def test_absent_declared_field_is_none_and_unknown_field_raises(self):
        m = cubecal.model(np.random.default_rng(4).normal(size=5000), "WN", rate=10.0, wic_replicates=0)
        self.assertNotIn("fidelity", m.channels[0])
        self.assertIsNone(m.channels[0].fidelity)
        with self.assertRaises(AttributeError):
            m.channels[0].no_such_field

    def test_docstrings_carry_the_fields(self):
        for cls in (cubecal.Analysis, cubecal.NoiseModel, cubecal.Spectrum, cubecal.TurnOn):
            doc = inspect.getdoc(cls)
            self.assertIn("Attributes\n----------", doc)
            for name in cls._fields:
                self.assertIn(f"\n{name} : ", doc, f"{cls.__name__}.{name}")


def stub_functions(tree):
    """{name: ast node} of the top-level functions and classes of a stub."""
    return {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}


def stub_parameters(node):
    """(name, kind, default text) of a stub function's parameters, as
    inspect.Parameter's kinds."""
    a = node.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    for arg, d in zip(positional, defaults):
        kind = "POSITIONAL_ONLY" if arg in a.posonlyargs else "POSITIONAL_OR_KEYWORD"
        out.append((arg.arg, kind, None if d is None else ast.unparse(d)))
    if a.vararg:
        out.append((a.vararg.arg, "VAR_POSITIONAL", None))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, "KEYWORD_ONLY", None if d is None else ast.unparse(d)))
    if a.kwarg:
        out.append((a.kwarg.arg, "VAR_KEYWORD", None))
    return out


def runtime_parameters(function):
    out = []
    for p in inspect.signature(function).parameters.values():
        default = None if p.default is inspect.Parameter.empty else repr(p.default)
        out.append((p.name, p.kind.name, default))
    return out


def same_default(a, b):
    """Default texts equal as values (1e-06 and 1e-6, 'x' and "x")."""
    if a is None or b is None:
        return a is b
    try:
        return ast.literal_eval(a) == ast.literal_eval(b)
    except (ValueError, SyntaxError, TypeError):
        return a == b  # not a literal (np.inf, a call): the same text


class Stubs(unittest.TestCase):
    """The type stubs shipped beside the modules agree with them."""

    def stubs(self):
        names = sorted(f for f in os.listdir(PACKAGE) if f.endswith(".pyi"))
        self.assertTrue(names)
        return names

    def test_every_stub_parses(self):
        for name in self.stubs():
            with open(os.path.join(PACKAGE, name)) as f:
                ast.parse(f.read(), name)

    def test_every_module_with_a_stub_matches_it(self):
        import importlib
        for name in self.stubs():
            module_name = name[:-4]
            module = importlib.import_module("cubecal" + ("" if module_name == "__init__" else "." + module_name))
            with open(os.path.join(PACKAGE, name)) as f:
                stub = stub_functions(ast.parse(f.read(), name))
            # A partial stub (PEP 484: it declares a module-level __getattr__)
            # of a private module must still declare every name the package
            # exports from it; its internal helpers may stay undeclared.
            partial = "__getattr__" in stub and module_name.startswith("_")
            public = getattr(module, "__all__", None)
            for attr, obj in vars(module).items():
                if attr.startswith("_") or (public is not None and attr not in public and
                                            getattr(obj, "__module__", None) != module.__name__):
                    continue
                if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                    continue
                if getattr(obj, "__module__", None) != module.__name__:
                    continue  # imported: its own module's stub has it
                if partial and getattr(cubecal, attr, None) is not obj:
                    continue
                with self.subTest(module=module_name, name=attr):
                    self.assertIn(attr, stub, f"{name} lacks {attr}")
                    if inspect.isfunction(obj):
                        self.check_function(stub[attr], obj, f"{name}: {attr}")
                    else:
                        self.check_class(stub[attr], obj, name)

    def check_function(self, node, function, where):
        self.assertIsInstance(node, ast.FunctionDef, where)
        got, want = stub_parameters(node), runtime_parameters(function)
        self.assertEqual([(n, k) for n, k, _ in got], [(n, k) for n, k, _ in want], where)
        for (n, _, a), (_, _, b) in zip(got, want):
            if a == "...":
                continue  # a stub may leave a default out
            self.assertTrue(same_default(a, b), f"{where}: {n} = {a} in the stub, {b} in the module")

    def check_class(self, node, cls, stub_name):
        self.assertIsInstance(node, ast.ClassDef)
        methods = {n.name: n for n in node.body if isinstance(n, ast.FunctionDef)}
        for attr, member in vars(cls).items():
            if attr.startswith("_") or not inspect.isfunction(member):
                continue
            self.assertIn(attr, methods, f"{stub_name}: {cls.__name__}.{attr}")
            self.check_function(methods[attr], member, f"{stub_name}: {cls.__name__}.{attr}")
        if issubclass(cls, Result):
            fields = {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
            own = {k for k in cls._fields_own if k.isidentifier() and not __import__("keyword").iskeyword(k)}
            own |= set(cls.__dict__.get("__annotations__", {}))
            self.assertEqual(fields, own, f"{stub_name}: {cls.__name__}'s fields")

    def test_result_stubs_are_generated_from_the_specs(self):
        source = os.path.join(os.path.dirname(__file__), "..", "cubecal")
        p = subprocess.run([sys.executable, os.path.join(SCRIPTS, "result-stubs.py"), source, "--check"],
                           capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr + p.stdout)


if __name__ == "__main__":
    unittest.main()
