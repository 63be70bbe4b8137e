#!/usr/bin/python3
"""AllanTools' own test suite, run against cubecal: the measure of
`import cubecal as allantools`.

    allantools-suite.py SRC [--module cubecal|allantools] [--json OUT] [--expect FILE] [-k EXPR]

SRC is a checkout of github.com/aewallin/allantools (its tests/ is what
runs; none of it is kept in this repository). With --module cubecal (the
default) every `import allantools`, `import allantools.X` and
`from allantools.X import Y` in the suite resolves to cubecal and
cubecal.X; with --module allantools the suite runs against AllanTools
itself from SRC. The suite runs from a copy of SRC/tests in a temporary
directory (some of its tests write files), with pytest (Debian's
python3-pytest).

Prints one line per test file: tests, passed (pytest's "passed" and
"xpassed"), and the tests that did not pass. --json writes
{nodeid: outcome} for every test. --expect FILE (a --json output of a run
with --module allantools) compares: every test that passed there must pass
here, or the script names it and exits 1.
"""
import argparse
import importlib
import importlib.abc
import importlib.util
import json
import os
import shutil
import sys
import tempfile


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Resolves `allantools` and `allantools.X` to `cubecal` and `cubecal.X`."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "allantools" and not fullname.startswith("allantools."):
            return None
        real = "cubecal" + fullname[len("allantools"):]
        if importlib.util.find_spec(real) is None:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec):
        return importlib.import_module("cubecal" + spec.name[len("allantools"):])

    def exec_module(self, module):
        pass


class _Outcomes:
    """A pytest plugin that keeps each test's outcome."""

    def __init__(self):
        self.outcome = {}

    def pytest_runtest_logreport(self, report):
        nodeid = report.nodeid
        if report.when == "call" or (report.when == "setup" and report.outcome != "passed"):
            if hasattr(report, "wasxfail"):
                outcome = "xpassed" if report.outcome == "passed" else "xfailed"
            else:
                outcome = report.outcome
            if report.when == "setup" and report.outcome == "failed":
                outcome = "error"
            self.outcome[nodeid] = outcome
        elif report.when == "teardown" and report.outcome == "failed":
            self.outcome[nodeid] = "error"


def passed(outcome):
    return outcome in ("passed", "xpassed")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("src", help="a checkout of github.com/aewallin/allantools")
    parser.add_argument("--module", choices=("cubecal", "allantools"), default="cubecal")
    parser.add_argument("--json", help="write {nodeid: outcome} here")
    parser.add_argument("--expect", help="a --json output of AllanTools' own run: its passes must pass here")
    parser.add_argument("-k", dest="keyword", help="pytest's -k expression")
    args = parser.parse_args()

    tests = os.path.join(args.src, "tests")
    if not os.path.isdir(tests):
        sys.exit(f"allantools-suite: {tests} is not a directory: SRC is a checkout of github.com/aewallin/allantools")
    import pytest

    if args.module == "cubecal":
        sys.meta_path.insert(0, _Alias())
        import cubecal  # noqa: F401  (fails here, plainly, when PYTHONPATH misses the module)
    else:
        sys.path.insert(0, os.path.abspath(args.src))

    plugin = _Outcomes()
    with tempfile.TemporaryDirectory(prefix="allantools-suite-") as work:
        copy = os.path.join(work, "tests")
        shutil.copytree(tests, copy)
        here = os.getcwd()
        os.chdir(work)
        try:
            argv = ["-q", "-p", "no:cacheprovider", "-o", "addopts=", "--rootdir", work,
                    "--continue-on-collection-errors", "tests"]
            if args.keyword:
                argv += ["-k", args.keyword]
            pytest.main(argv, plugins=[plugin])
        finally:
            os.chdir(here)

    reference = {}
    if args.expect:
        with open(args.expect) as f:
            reference = json.load(f)
    names = sorted(set(plugin.outcome) | set(reference))
    by_file = {}
    for nodeid in names:
        by_file.setdefault(nodeid.split("::")[0], []).append(nodeid)
    if reference:
        print(f"\n{'file':50} {'tests':>5} {'AllanTools':>10} {args.module:>10}")
    else:
        print(f"\n{'file':50} {'tests':>5} {'passed':>10}")
    for name, ids in by_file.items():
        mine = sum(passed(plugin.outcome.get(n, "missing")) for n in ids)
        theirs = f"{sum(passed(reference.get(n, 'missing')) for n in ids):10d}" if reference else ""
        print(f"{name:50} {len(ids):5d} {theirs} {mine:10d}".replace("  ", " ", 1 if reference else 0))
        for nodeid in ids:
            outcome = plugin.outcome.get(nodeid, "not run (collection error)")
            if not passed(outcome):
                print(f"    {outcome:8} {nodeid.split('::', 1)[-1]}")
    mine = sum(passed(plugin.outcome.get(n, "missing")) for n in names)
    theirs = f"{sum(passed(reference.get(n, 'missing')) for n in names):10d}" if reference else ""
    print(f"{'all':50} {len(names):5d} {theirs} {mine:10d}")

    if args.json:
        with open(args.json, "w") as f:
            json.dump(plugin.outcome, f, indent=1, sort_keys=True)
    lost = [n for n in names if passed(reference.get(n, "missing")) and not passed(plugin.outcome.get(n, "missing"))]
    for nodeid in lost:
        print(f"passes with AllanTools, not with {args.module}: {nodeid} ({plugin.outcome.get(nodeid, 'not run')})")
    if lost:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
