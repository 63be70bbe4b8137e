"""The wheel (pyproject.toml, setup.py): built, installed into a fresh virtual environment, used.

`python3 -m build --wheel --no-isolation` on the source tree, reusing this build
tree (CUBECAL_CMAKE_BUILD_DIR: its cubecal_python target, no second build of the
library), into a temporary directory; the wheel installed with pip into a fresh
`python3 -m venv --system-site-packages` (numpy from Debian) and imported from
outside the source tree. The source tree gets nothing: no egg-info, dist/ or
setuptools build/ (docs/python-packaging.md).

Environment (python/tests/CMakeLists.txt): CUBECAL_WHEEL_SOURCE (the source
tree), CUBECAL_WHEEL_BUILD (this build tree), CUBECAL_WHEEL_VERSION (CMake's
project version), CUBECAL_PYTHON (the interpreter).
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest
import zipfile
from pathlib import Path

SOURCE = Path(os.environ.get("CUBECAL_WHEEL_SOURCE", Path(__file__).resolve().parents[2])).resolve()
BUILD = Path(os.environ.get("CUBECAL_WHEEL_BUILD", SOURCE / "build")).resolve()
VERSION = os.environ.get("CUBECAL_WHEEL_VERSION", "")
PYTHON = os.environ.get("CUBECAL_PYTHON", "/usr/bin/python3")

# oadev of a seeded frequency series, printed as exact hex floats; run by the
# venv's interpreter and by the build tree's module alike.
COMPUTE = r"""
import json, sys
import numpy as np
import cubecal
y = np.random.default_rng(34).standard_normal(4096)
taus, devs, errs, ns = cubecal.oadev(y, rate=10.0, data_type="freq", taus="octave")
print(json.dumps({"file": cubecal.__file__, "extension": cubecal._cubecal.__file__,
                  "version": cubecal.__version__, "prefix": sys.prefix,
                  "taus": [float(t).hex() for t in taus], "devs": [float(d).hex() for d in devs],
                  "ns": [int(n) for n in ns], "path": sys.path}))
"""


def clean_env(**extra):
    """The environment without the build tree's PYTHONPATH (the test's own), plus extra."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(extra)
    return env


def run(words, **kwargs):
    done = subprocess.run(words, capture_output=True, text=True, **kwargs)
    if done.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, words))} exited {done.returncode}:\n"
                             f"{done.stdout[-4000:]}\n{done.stderr[-4000:]}")
    return done


def source_entries():
    """Every path in the source tree but .git and CMake build trees (a CMakeCache.txt in them)."""
    entries = set()
    for root, dirs, files in os.walk(SOURCE):
        dirs[:] = [d for d in dirs if d != ".git" and not (Path(root, d) / "CMakeCache.txt").exists()]
        for name in dirs + files:
            entries.add(os.path.relpath(os.path.join(root, name), SOURCE))
    return entries


class Wheel(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="cubecal-wheel-")
        tmp = Path(cls.tmp.name)
        cls.before = source_entries()
        run([PYTHON, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(tmp / "dist"), str(SOURCE)],
            cwd=tmp, env=clean_env(CUBECAL_CMAKE_BUILD_DIR=str(BUILD), PYTHONDONTWRITEBYTECODE="1"))
        cls.after = source_entries()
        wheels = sorted((tmp / "dist").glob("cubecal-*.whl"))
        assert len(wheels) == 1, f"expected one wheel in {tmp / 'dist'}, found {wheels}"
        cls.wheel = wheels[0]
        cls.venv = tmp / "venv"
        run([PYTHON, "-m", "venv", "--system-site-packages", str(cls.venv)], cwd=tmp, env=clean_env())
        cls.venv_python = cls.venv / "bin" / "python"
        # --no-index: nothing downloaded; numpy is Debian's, seen through --system-site-packages.
        run([cls.venv_python, "-m", "pip", "install", "--no-index", "--disable-pip-version-check", str(cls.wheel)],
            cwd=tmp, env=clean_env())
        cls.installed = json.loads(run([cls.venv_python, "-c", COMPUTE], cwd=tmp, env=clean_env()).stdout)
        cls.reference = json.loads(run([PYTHON, "-c", COMPUTE], cwd=tmp,
                                       env=clean_env(PYTHONPATH=str(BUILD / "python"))).stdout)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_wheel_name_and_version(self):
        # cubecal-<CMake's project version>-cp3X-cp3X-<platform>.whl: a binary wheel.
        name, version, python_tag, abi_tag, platform = self.wheel.stem.split("-")
        self.assertEqual(name, "cubecal")
        self.assertEqual(version, VERSION)
        self.assertEqual(python_tag, f"cp{sys.version_info.major}{sys.version_info.minor}")
        self.assertNotEqual(platform, "any")
        with zipfile.ZipFile(self.wheel) as whl:
            metadata = whl.read(f"cubecal-{VERSION}.dist-info/METADATA").decode()
        self.assertIn(f"\nVersion: {VERSION}\n", metadata)
        self.assertIn("\nRequires-Dist: numpy", metadata)
        self.assertEqual(self.installed["version"], VERSION)

    def test_wheel_holds_the_package(self):
        # Every .py, .pyi and py.typed of python/cubecal, the extension, and nothing else in cubecal/.
        with zipfile.ZipFile(self.wheel) as whl:
            names = {n for n in whl.namelist() if n.startswith("cubecal/")}
        package = SOURCE / "python" / "cubecal"
        expected = {f"cubecal/{p.name}" for p in package.iterdir()
                    if p.suffix in (".py", ".pyi") or p.name == "py.typed"}
        self.assertIn("cubecal/py.typed", expected)
        self.assertIn("cubecal/__init__.py", expected)
        extensions = sorted(n for n in names if n.startswith("cubecal/_cubecal.") and n.endswith(".so"))
        self.assertEqual(len(extensions), 1, names)
        self.assertEqual(names - set(extensions), expected)

    def test_installed_in_the_venv(self):
        # Imported from the venv (outside the source and build trees), not from PYTHONPATH.
        venv = str(self.venv.resolve())
        for key in ("file", "extension"):
            path = str(Path(self.installed[key]).resolve())
            self.assertTrue(path.startswith(venv + os.sep), f"{key}: {path} not in {venv}")
        self.assertEqual(str(Path(self.installed["prefix"]).resolve()), venv)
        # The stubs (every .pyi of python/cubecal) and the py.typed marker, installed.
        installed = Path(self.installed["file"]).parent
        for stub in [*(SOURCE / "python" / "cubecal").glob("*.pyi"), Path("py.typed")]:
            self.assertTrue((installed / stub.name).is_file(), stub.name)
        for entry in self.installed["path"]:
            self.assertFalse(entry and Path(entry).resolve() in (SOURCE / "python", BUILD / "python"), entry)

    def test_computation_matches_the_build_tree(self):
        self.assertGreater(len(self.installed["devs"]), 5)
        for key in ("taus", "devs", "ns"):
            self.assertEqual(self.installed[key], self.reference[key], key)
        # And the first point is the closed form: at m = 1 the overlapping Allan deviation of
        # frequency data is sqrt(mean(diff(y)^2) / 2).
        import numpy as np
        y = np.random.default_rng(34).standard_normal(4096)
        self.assertAlmostEqual(float.fromhex(self.installed["taus"][0]), 0.1, places=15)
        expected = np.sqrt(0.5 * np.mean(np.diff(y) ** 2))
        self.assertLess(abs(float.fromhex(self.installed["devs"][0]) / expected - 1), 1e-12)

    def test_source_tree_untouched(self):
        # No egg-info, dist/, setuptools build/ or compiled file in the sources.
        self.assertEqual(sorted(self.after - self.before), [])


if __name__ == "__main__":
    unittest.main()
