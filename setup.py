"""The wheel's build: setuptools (pyproject.toml) with a build_ext that drives CMake.

The extension cubecal._cubecal is CMake's target cubecal_python. By default it
is configured with -DCUBECAL_PYTHON_ONLY=ON (the module and the libraries it
links; no command, tests, benchmarks or docs) in build/wheel, a tree this build
owns and reuses from one `pip install .` to the next. Environment:

CUBECAL_CMAKE_BUILD_DIR
    An existing configured CMake build tree (say build/): the wheel takes its
    cubecal_python target, built there if out of date, instead of configuring
    and building its own; setuptools' scratch files go under it too
    (<tree>/wheel-setuptools). How `make test` tests the wheel.
CMAKE_ARGS
    More arguments for the configuration of build/wheel (shell words), e.g.
    "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache".
CMAKE_BUILD_PARALLEL_LEVEL
    Parallel build jobs (default: the number of processors).

setuptools' own files (build/, *.egg-info) go under the CMake tree, never
into the source tree. See docs/python-packaging.md.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent


def project_version():
    """The version of CMakeLists.txt's project(cubecal VERSION x.y.z): one source of truth."""
    text = (SOURCE / "CMakeLists.txt").read_text(encoding="utf-8")
    found = re.search(r"project\(\s*cubecal\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if not found:
        sys.exit(f"setup.py: no 'project(cubecal VERSION x.y.z)' in {SOURCE / 'CMakeLists.txt'}")
    return found.group(1)


def reused_tree():
    """The configured CMake tree CUBECAL_CMAKE_BUILD_DIR names, or None."""
    given = os.environ.get("CUBECAL_CMAKE_BUILD_DIR", "")
    if not given:
        return None
    tree = Path(given).resolve()
    if not (tree / "CMakeCache.txt").is_file():
        sys.exit(f"setup.py: CUBECAL_CMAKE_BUILD_DIR={given} is not a configured CMake build tree "
                 "(no CMakeCache.txt): configure it first (cmake -S . -B build) or unset the variable")
    return tree


def scratch_dir():
    """Where setuptools writes its build/ and egg-info: under the CMake tree, not the sources."""
    tree = reused_tree()
    scratch = tree / "wheel-setuptools" if tree else SOURCE / "build" / "wheel" / "setuptools"
    scratch.mkdir(parents=True, exist_ok=True)
    return scratch


def interpreter():
    """The interpreter the extension is built for: a virtual environment's base python3."""
    return getattr(sys, "_base_executable", None) or sys.executable


def jobs(parallel):
    """Parallel build jobs: build_ext -j, CMAKE_BUILD_PARALLEL_LEVEL, else every processor."""
    if parallel:
        return str(parallel)
    return os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)


class CMakeBuild(build_ext):
    """Builds cubecal._cubecal with CMake and copies it where setuptools packs it."""

    def build_extension(self, ext):
        tree = reused_tree()
        if tree is None:
            tree = SOURCE / "build" / "wheel"
            self.run_command_line([
                "cmake", "-S", str(SOURCE), "-B", str(tree), "-DCMAKE_BUILD_TYPE=Release",
                "-DCUBECAL_PYTHON_ONLY=ON", f"-DCUBECAL_PYTHON={interpreter()}",
                *shlex.split(os.environ.get("CMAKE_ARGS", ""))])
        self.run_command_line(["cmake", "--build", str(tree), "--target", "cubecal_python",
                               "--parallel", jobs(self.parallel)])
        target = Path(self.get_ext_fullpath(ext.name))
        built = tree / "python" / "cubecal" / target.name
        if not built.is_file():
            found = sorted(p.name for p in (tree / "python" / "cubecal").glob("_cubecal*.so"))
            sys.exit(f"setup.py: {built} not found after building cubecal_python in {tree} "
                     f"(found: {', '.join(found) or 'none'}); the tree is configured for another "
                     f"Python than {sys.executable}: configure it with -DCUBECAL_PYTHON={interpreter()}")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)

    @staticmethod
    def run_command_line(words):
        print("setup.py:", shlex.join(words), flush=True)
        subprocess.run(words, check=True)


scratch = scratch_dir()
# setuptools keeps its build/lib from one run to the next: a file since removed
# from python/cubecal would still be packed. Each build starts from none (the
# CMake tree, where the time goes, is kept).
shutil.rmtree(scratch / "build", ignore_errors=True)
setup(
    version=project_version(),
    ext_modules=[Extension("cubecal._cubecal", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(scratch / "build")},
             "egg_info": {"egg_base": str(scratch)}},
)
