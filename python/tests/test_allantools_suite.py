"""AllanTools' own test suite (tests/ of github.com/aewallin/allantools) with
`allantools` resolving to cubecal: every test that passes with AllanTools
itself must pass with cubecal (scripts/allantools-suite.py runs both).

AllanTools' source is not kept here: ALLANTOOLS_SRC (or CUBECAL_ALLANTOOLS_SRC,
set by ctest from the environment at configure time) names a checkout; without
one the test is skipped and says why.
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "allantools-suite.py")


def _source():
    for src in (os.environ.get("ALLANTOOLS_SRC"), os.environ.get("CUBECAL_ALLANTOOLS_SRC")):
        if src and os.path.isfile(os.path.join(src, "allantools", "allantools.py")) and \
                os.path.isdir(os.path.join(src, "tests")):
            return src
    raise unittest.SkipTest("AllanTools' source is not here: set ALLANTOOLS_SRC to a checkout of "
                            "github.com/aewallin/allantools to run its test suite against cubecal")


class AllanToolsSuite(unittest.TestCase):
    def test_every_test_that_passes_with_allantools_passes_with_cubecal(self):
        src = _source()
        with tempfile.TemporaryDirectory() as work:
            reference = os.path.join(work, "allantools.json")
            run = subprocess.run([sys.executable, SCRIPT, src, "--module", "allantools", "--json", reference],
                                 capture_output=True, text=True)
            self.assertTrue(os.path.isfile(reference), run.stdout[-2000:] + run.stderr[-2000:])
            passing = sum(o in ("passed", "xpassed") for o in json.load(open(reference)).values())
            self.assertGreater(passing, 300, "AllanTools' own run passed too few of its tests to be the measure")
            run = subprocess.run([sys.executable, SCRIPT, src, "--module", "cubecal", "--expect", reference],
                                 capture_output=True, text=True)
            table = run.stdout[run.stdout.rfind("\nfile"):]
            print(table)
            self.assertEqual(run.returncode, 0, table + run.stderr[-3000:])


if __name__ == "__main__":
    unittest.main()
