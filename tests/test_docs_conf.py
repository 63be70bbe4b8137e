"""The pieces docs/conf.py adds to Sphinx (ctest docs.site_config): the pages
completed at read time and the reading of plain-text docstrings. The whole site
is built and opened in a browser by tests/check_docs_site.py (ctest docs.site)."""
import importlib.util
import os
import tempfile
import types
import unittest

import io

import docutils.core

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
spec = importlib.util.spec_from_file_location("cubecal_docs_conf", os.path.join(ROOT, "docs", "conf.py"))
conf = importlib.util.module_from_spec(spec)
spec.loader.exec_module(conf)


def rst_problems(text):
    """The warnings docutils reports on a text, as Sphinx would with -W."""
    stream = io.StringIO()
    docutils.core.publish_doctree(text, settings_overrides={"warning_stream": stream, "report_level": 2,
                                                            "halt_level": 5})
    return [line for line in stream.getvalue().split("\n") if line.strip()]


class FakeEnv:
    def __init__(self, docs=()):
        self.found_docs = set(docs)
        self.dependencies = []

    def note_dependency(self, path):
        self.dependencies.append(path)


class ShiftHeadings(unittest.TestCase):
    def test_first_heading_becomes_the_level_asked_and_the_others_follow(self):
        text = "# A\n\ntext\n\n## B\n\n```sh\n# a comment, not a heading\n```\n"
        self.assertEqual(conf._shift_headings(text, 3),
                         "### A\n\ntext\n\n#### B\n\n```sh\n# a comment, not a heading\n```\n")

    def test_a_file_that_starts_at_level_two(self):
        self.assertEqual(conf._shift_headings("## A\n### B", 3), "### A\n#### B")

    def test_text_without_headings_is_unchanged(self):
        self.assertEqual(conf._shift_headings("plain |x| text", 3), "plain |x| text")


class Differences(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.saved = conf.DOCS
        conf.DOCS = self.tmp.name
        self.app = types.SimpleNamespace(env=FakeEnv())

    def tearDown(self):
        conf.DOCS = self.saved
        self.tmp.cleanup()

    def write(self, name, text):
        folder = os.path.join(self.tmp.name, "allantools-differences")
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, name), "w", encoding="utf-8") as f:
            f.write(text)

    def test_no_file_gives_one_sentence(self):
        self.assertEqual(conf._differences_text(self.app), "No deliberate difference is recorded yet.\n")

    def test_every_file_in_name_order_headings_under_the_section_links_from_the_page(self):
        self.write("typed.md", "# tierms\n\nSee [stability](../formulas/stability.md#3-x) and "
                               "[AllanTools](https://github.com/aewallin/allantools) and [here](#tierms).\n")
        self.write("compat.md", "## gradev error bars\n\nFinite, [see](other.md).\n")
        text = conf._differences_text(self.app)
        self.assertLess(text.index("### gradev error bars"), text.index("### tierms"))
        self.assertIn("[stability](formulas/stability.md#3-x)", text)
        self.assertIn("[see](allantools-differences/other.md)", text)
        self.assertIn("(https://github.com/aewallin/allantools)", text)
        self.assertIn("[here](#tierms)", text)
        self.assertEqual(len(self.app.env.dependencies), 2)


class OtherPages(unittest.TestCase):
    INDEX = ("```{toctree}\n:caption: A\n:glob:\n\nguide\nReference <README>\nvalidation/*\nlater*\n```\n"
             "<!-- other-pages -->\n")

    def test_pages_no_toctree_names_are_listed(self):
        app = types.SimpleNamespace(env=FakeEnv(["index", "guide", "README", "validation/a", "new-page"]))
        self.assertEqual(conf._toctree_entries(self.INDEX), ["guide", "README", "validation/*", "later*"])
        text = conf._other_pages_text(app, self.INDEX)
        self.assertIn(":caption: More pages", text)
        self.assertEqual(text.split("\n\n", 1)[1].strip().split("\n")[0], "new-page")
        self.assertNotIn("guide", text)

    def test_nothing_left_gives_nothing(self):
        app = types.SimpleNamespace(env=FakeEnv(["index", "guide", "README"]))
        self.assertEqual(conf._other_pages_text(app, self.INDEX), "")

    def test_a_glob_that_matches_no_page_yet_is_dropped(self):
        app = types.SimpleNamespace(env=FakeEnv(["index", "guide", "README", "validation/a"]))
        out = conf._drop_empty_globs(app, self.INDEX)
        self.assertNotIn("later*", out)
        self.assertIn("validation/*", out)
        app.env.found_docs.add("later-page")
        self.assertIn("later*", conf._drop_empty_globs(app, self.INDEX))


class PlainTextDocstrings(unittest.TestCase):
    def read(self, text):
        lines = text.split("\n")
        conf._plain_text_docstring(None, "function", "f", None, {}, lines)
        return "\n".join(lines)

    def test_norms_are_text_not_substitutions(self):
        text = "h_cal = S (h - b) with |h_cal| = F; the mean raw |h|; from |a'| = g."
        self.assertTrue(rst_problems(text))
        out = self.read(text)
        self.assertEqual(rst_problems(out), [])
        self.assertIn("\\|h_cal\\|", out)

    def test_norms_after_an_indented_literal_block(self):
        text = (":Parameters:\n\n    **x** : float\n        Example::\n\n            y = |x|\n\n"
                "    **h** : float\n        The raw |h|, in mGauss.\n    **e** : float\n"
                "        |h| - F before, in mGauss.\n")
        out = self.read(text)
        self.assertEqual(rst_problems(out), [])
        self.assertIn("y = |x|", out)
        self.assertIn("The raw \\|h\\|", out)
        self.assertIn("\\|h\\| - F before", out)

    def test_a_list_of_cases_that_ends_without_a_blank_line(self):
        text = ("The true rates come from one of:\n  reference: the columns,\n    named;\n"
                "  schedule: a file.\nmargin: seconds dropped at both ends.")
        self.assertTrue(rst_problems(text))
        self.assertEqual(rst_problems(self.read(text)), [])

    def test_an_indented_example_of_code_is_code(self):
        text = ("Deviations updated sample by sample.\n\n"
                "    rt = cubecal.realtime.oadev_realtime(afs=[1, 10, 100], tau0=1.0)\n"
                "    for x in phase_stream:          # phase samples (s), one at a time\n"
                "        rt.add_phase(x)\n    rt.taus(), rt.devs()\n\nThe calls on NumPy arrays:\n\n"
                "    import cubecal    # instead of: import allantools\n    r = cubecal.dev(y, rate=|x|)\n\n"
                "More text.")
        self.assertTrue(rst_problems(text))
        out = self.read(text)
        self.assertEqual(rst_problems(out), [])
        body = docutils.core.publish_parts(out, writer_name="html")["body"]
        self.assertEqual(body.count("<pre"), 2)
        self.assertIn("rate=|x|)", body)  # code is never changed
        self.assertIn("NumPy arrays:</p>", body)

    def test_an_indented_quote_of_text_stays_a_quote(self):
        text = "As the paper puts it:\n\n    the bias drifts slowly\n\nEnd."
        self.assertEqual(self.read(text), text)

    def test_valid_rst_reads_the_same(self):
        text = ("Parameters\n----------\nx : float\n    The value, in s.\ny : int\n    A count.\n\n"
                "Returns\n-------\nfloat\n    The absolute value of x, in s.\n\n"
                "Example::\n\n    a | b\n    c |d| e\n\n+---+---+\n| a | b |\n+---+---+\n\n"
                ":Parameters:\n\n    **rate** : float\n        In Hz, f(x) = 1.\n\n"
                ".. note::\n\n    x = f(y) here.\n")
        before = docutils.core.publish_parts(text, writer_name="html")["body"]
        after = docutils.core.publish_parts(self.read(text), writer_name="html")["body"]
        self.assertEqual(rst_problems(self.read(text)), [])
        self.assertIn("a | b", after)
        self.assertIn("c |d| e", after)  # code is never changed
        self.assertEqual(before, after)


if __name__ == "__main__":
    unittest.main()
