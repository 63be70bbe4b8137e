#!/usr/bin/python3
"""Builds the documentation site (`make docs`, ctest docs.site): Doxygen's XML
and HTML of include/cubecal, then Sphinx over docs/ with warnings as errors.

    scripts/build-docs-site.py --build BUILD_DIR --out SITE_DIR [--doxygen DOXYGEN]

BUILD_DIR is a configured build tree: its Doxyfile (configured from
docs/Doxyfile.in) and its Python module (BUILD_DIR/python, the module the
Python pages document). Doxygen writes into SITE_DIR/../SITE_NAME-doxygen; the
site is SITE_DIR/index.html. Every Sphinx run starts afresh (-E): a page that
lists modules or headers is never left stale. Exit code 1 on any warning.
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_doxygen(doxygen: str, build: str, out: str) -> int:
    """Doxygen's XML (the headers' summaries) and HTML (the reference, under extra/cpp)."""
    with open(os.path.join(build, "Doxyfile"), encoding="utf-8") as f:
        config = f.read()
    config += (f"\nOUTPUT_DIRECTORY = {out}\nGENERATE_XML = YES\nXML_PROGRAMLISTING = NO\n"
               "GENERATE_HTML = YES\nHTML_OUTPUT = extra/cpp\n")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "extra"))
    return subprocess.run([doxygen, "-"], input=config.encode(), cwd=build).returncode


def drop_dead_summary_links(html_dir: str) -> int:
    """Doxygen 1.9.4 heads a class page with a link to #nested-classes when the
    class has nested classes, even when they are private and so not shown: the
    link leads nowhere, and is taken out (the only edit of Doxygen's pages)."""
    fixed = 0
    for name in os.listdir(html_dir):
        if not name.endswith(".html"):
            continue
        path = os.path.join(html_dir, name)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if 'href="#nested-classes"' in text and 'name="nested-classes"' not in text \
                and 'id="nested-classes"' not in text:
            text = text.replace('<a href="#nested-classes">Classes</a> &#124;\n', "")
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            fixed += 1
    return fixed


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="the configured build tree")
    ap.add_argument("--out", required=True, help="the site's directory (index.html)")
    ap.add_argument("--doxygen", default=shutil.which("doxygen") or "doxygen")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    out = os.path.abspath(a.out)
    doxygen_dir = out.rstrip("/") + "-doxygen"
    t0 = time.monotonic()
    if run_doxygen(a.doxygen, build, doxygen_dir) != 0:
        print("build-docs-site: doxygen failed (a warning is an error: see above)", file=sys.stderr)
        return 1
    drop_dead_summary_links(os.path.join(doxygen_dir, "extra", "cpp"))
    env = dict(os.environ)
    env["CUBECAL_BUILD_DIR"] = build
    env["CUBECAL_DOXYGEN_DIR"] = doxygen_dir
    env["PYTHONPATH"] = os.path.join(build, "python") + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    cmd = [sys.executable, "-m", "sphinx", "-b", "html", "-E", "-W", "--keep-going", "-q",
           "-d", doxygen_dir + "/doctrees", os.path.join(ROOT, "docs"), out]
    r = subprocess.run(cmd, env=env)
    if r.returncode != 0:
        print("build-docs-site: sphinx-build reported warnings (errors here): see above", file=sys.stderr)
        return 1
    print(f"build-docs-site: {out}/index.html ({time.monotonic() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
