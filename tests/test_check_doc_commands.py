"""scripts/check-doc-commands.py on docs it is given: numbers compared at their
quoted digits, text up to white space, "..." eliding lines, the exit code, the
FILE:LINE of each mismatch, --update rewriting only the marked blocks, and a
block's commands sharing one directory. The program is a stand-in script, so
the rules are tested apart from cubecal's output."""
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "scripts", "check-doc-commands.py")

# Prints what `cubecal` would, per subcommand; `fail` exits 2 with a message.
FAKE = """#!/bin/sh
if [ "$1" = "--help" ]; then printf 'Subcommands:\\n  n    terms\\n  table  a table\\n  write  w\\n  read  r\\n  fail  f\\n'; exit 0; fi
if [ "$2" = "--help" ]; then printf 'Options:\\n  --digits INT   digits\\n'; exit 0; fi
case "$1" in
  n) printf 'N         2.4507 ± 0.013 deg/sqrt(h) (read at 1 s)\\nB  27.89 ± 8.2 deg/h\\nrun1.csv 1e+03\\n' ;;
  table) printf 'af  dev\\n 1  2.92232e-01\\n 2  1.58207e-01\\n 4  1.07797e-01\\n' ;;
  write) echo 3.5 > "$2" ;;
  read) cat "$2" ;;
  fail) echo "cubecal: error: x.csv:3:1: bad" >&2; exit 2 ;;
esac
"""


class CheckDocCommands(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        root = self.tmp.name
        self.root = root
        os.makedirs(os.path.join(root, "docs"))
        os.makedirs(os.path.join(root, "scripts"))
        os.makedirs(os.path.join(root, "data"))
        os.makedirs(os.path.join(root, "build", "bin"))
        self.binary = os.path.join(root, "build", "bin", "cubecal")
        with open(self.binary, "w") as f:
            f.write(FAKE)
        os.chmod(self.binary, 0o755)
        with open(os.path.join(root, "README.md"), "w") as f:
            f.write("# none\n")

    def tearDown(self):
        self.tmp.cleanup()

    def doc(self, text):
        path = os.path.join(self.root, "docs", "x.md")
        with open(path, "w") as f:
            f.write(textwrap.dedent(text))
        return path

    def check(self, *args):
        p = subprocess.run([sys.executable, SCRIPT, "--cubecal", self.binary, "--data",
                            os.path.join(self.root, "data"), *args, self.root],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        return p.returncode, p.stdout + p.stderr

    def test_written_commands_are_checked_against_their_help(self):
        self.doc("""\
            Run `cubecal n --digits 3`, or in a block:

            ```sh
            cubecal table --digits 2 \\
                --colour
            cubecal frob x.csv
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("docs/x.md:4: `cubecal table --digits 2 --colour`: cubecal table takes no --colour", out)
        self.assertIn("docs/x.md:6: `cubecal frob x.csv`: cubecal has no command 'frob'", out)
        self.assertNotIn("--digits", out.replace("--digits 2 --colour", ""))
        self.assertIn("2 written command(s) checked against their --help, 2 wrong", out)

    def test_numbers_match_at_their_quoted_digits(self):
        self.doc("""\
            <!-- doc-test -->
            ```console
            $ cubecal n
            N   2.451 ± 0.013 deg/sqrt(h) (read at 1 s)
            B  28 ± 8 deg/h
            run1.csv 1e+03
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 0, out)
        self.assertIn("1 command(s) run, 6 quoted number(s), 0 failed", out)

    def test_a_drifted_number_fails_with_file_line_and_both_lines(self):
        self.doc("""\
            Text.

            <!-- doc-test -->
            ```console
            $ cubecal n
            N   2.27 ± 0.003 deg/sqrt(h) (read at 1 s)
            ...
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("docs/x.md:6: FAIL: 2.27 (printed 2.4507); 0.003 (printed 0.013)", out)
        self.assertIn("- docs:    N   2.27 ± 0.003 deg/sqrt(h)", out)
        self.assertIn("+ program: N         2.4507 ± 0.013 deg/sqrt(h)", out)

    def test_text_differs_and_missing_or_extra_lines_fail(self):
        self.doc("""\
            <!-- doc-test -->
            ```console
            $ cubecal n
            N   2.451 ± 0.013 deg/h (read at 1 s)
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("docs/x.md:4: FAIL: the text differs", out)
        self.assertIn("the program printed 2 more line(s) than the docs quote", out)

    def test_ellipsis_skips_to_the_next_quoted_line(self):
        self.doc("""\
            <!-- doc-test -->
            ```console
            $ cubecal table
            ...
             4  1.078e-01
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 0, out)

    def test_exit_code_and_stderr(self):
        self.doc("""\
            <!-- doc-test stderr exit=2 -->
            ```console
            $ cubecal fail
            cubecal: error: x.csv:3:1: bad
            ```
            <!-- doc-test -->
            ```console
            $ cubecal fail
            ```
            """)
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("docs/x.md:8: FAIL: `cubecal fail` exited 2, the docs expect 0", out)
        self.assertNotIn("docs/x.md:3: FAIL", out)

    def test_a_blocks_commands_share_a_directory_and_a_hidden_command_checks_a_table(self):
        self.doc("""\
            <!-- doc-test -->
            ```console
            $ cubecal write v.txt
            $ cubecal read v.txt
            3.5
            ```

            <!-- doc-test $ cubecal table | sed 's/^/|/' -->
            |af  dev
            | 1  0.29223
            | 2  1.58e-01
            | 4  1.08e-01
            """)
        code, out = self.check()
        self.assertEqual(code, 0, out)

    def test_slow_and_skip(self):
        self.doc("""\
            <!-- doc-test slow="a long one" -->
            ```console
            $ cubecal fail
            ```
            <!-- doc-test skip="CPU minutes" $ cubecal fail -->
            | x |
            """)
        code, out = self.check()
        self.assertEqual(code, 0, out)
        self.assertIn("slow, run with --slow (a long one)", out)
        self.assertIn("skipped (CPU minutes)", out)
        self.assertEqual(self.check("--slow")[0], 1)

    def test_update_rewrites_the_marked_block_only_keeping_its_digits(self):
        text = """\
            Quoted outside a block: N 2.27 ± 0.003.

            <!-- doc-test -->
            ```console
            $ cubecal table
            af  dev
             1  2.9e-01
             2  1.500e-01
            ...
            ```
            """
        path = self.doc(text)
        code, out = self.check("--update")
        self.assertEqual(code, 1, out)
        with open(path) as f:
            updated = f.read()
        self.assertEqual(updated, textwrap.dedent(text).replace(" 2  1.500e-01", " 2  1.582e-01"))
        self.assertEqual(self.check()[0], 0)


if __name__ == "__main__":
    unittest.main()
