"""The wheel's build backend (pyproject.toml): setuptools' own, found offline.

setuptools.build_meta does the work (setup.py drives CMake). What this adds:
`pip install .` and an isolated `python3 -m build` run the backend in an
environment that hides the interpreter's installed packages and would
download setuptools and wheel into it, which fails offline. The build needs
nothing but what Debian's python3-setuptools and python3-wheel install, so
when the environment has no setuptools, the base interpreter's site
directories are appended to the path (last: whatever the environment holds
comes first) and setuptools is taken from there. Only where the interpreter
has no setuptools either does the backend ask the frontend for
setuptools>=61 and wheel (downloaded as usual). docs/python-packaging.md.
"""
import importlib
import site
import sys

# The version pyproject.toml's [project] table needs (PEP 621 in setuptools).
_SETUPTOOLS_MIN = (61, 0)


def _usable_setuptools():
    """setuptools.build_meta when a setuptools >= 61 with wheel is importable, else None."""
    try:
        build_meta = importlib.import_module("setuptools.build_meta")
        importlib.import_module("wheel")
        version = importlib.import_module("setuptools").__version__
    except ImportError:
        return None
    major_minor = tuple(int(part) for part in version.split(".")[:2] if part.isdigit())
    return build_meta if major_minor >= _SETUPTOOLS_MIN else None


def _backend():
    """setuptools.build_meta from the environment, else from the base interpreter, else None."""
    found = _usable_setuptools()
    if found is not None:
        return found
    known = set(sys.path)
    for directory in site.getsitepackages([sys.base_prefix]):
        if directory not in known:
            site.addsitedir(directory)  # appended, with its .pth files (setuptools' distutils shim)
    for name in [m for m in sys.modules if m == "setuptools" or m.startswith(("setuptools.", "wheel"))]:
        del sys.modules[name]  # an unusable copy found first, if any
    return _usable_setuptools()


def _require():
    backend = _backend()
    if backend is None:
        raise RuntimeError("cubecal_backend: no setuptools>=61 with wheel (Debian: apt install "
                           "python3-setuptools python3-wheel)")
    return backend


def get_requires_for_build_wheel(config_settings=None):
    # Nothing more to install when setuptools and wheel were found (setuptools'
    # own answer, ["wheel"], would have pip download it into its environment).
    return [] if _backend() is not None else ["setuptools>=61", "wheel"]


def get_requires_for_build_sdist(config_settings=None):
    return [] if _backend() is not None else ["setuptools>=61"]


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    return _require().prepare_metadata_for_build_wheel(metadata_directory, config_settings)


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    return _require().build_wheel(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory, config_settings=None):
    return _require().build_sdist(sdist_directory, config_settings)
