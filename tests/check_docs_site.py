#!/usr/bin/python3
"""The documentation site, checked as a reader's browser sees it (ctest docs.site).

    tests/check_docs_site.py --build BUILD_DIR --out SITE_DIR [--chromium PATH]
    tests/check_docs_site.py --site SITE_DIR [--chromium PATH]

With --build it first builds the site (scripts/build-docs-site.py: Doxygen and
Sphinx, warnings as errors) into SITE_DIR; --site checks a site already built.

1. Every HTML page and style sheet is read: every local href and src names a
   file of the site, every #anchor an id of its page, and nothing that loads
   (script, style sheet, image, font, frame: src, <link href>, CSS url() and
   @import) comes from the network. Links to other sites in the text (<a href>)
   are fine.
2. Every page of the site is opened in headless Chromium (one browser, the
   pages in turn in a frame of a driver page): it loads, has its title and a
   body, its images decode, its math is rendered (no KaTeX error), and the
   browser fetched no resource outside the site (Resource Timing). The pages
   are Sphinx's and the pages of Doxygen's C++ reference (cpp/) they link to;
   Doxygen's other pages (about 900 in all, alike in make) are read in step 1.
Exit code 1 with one line per problem.
"""
from __future__ import annotations

import argparse
import html.parser
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.parse

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOADING_ATTRS = {"src", "srcset", "poster", "data"}
NETWORK = re.compile(r"^(?:[a-z][a-z0-9+.-]*:)?//", re.I)
SCHEME = re.compile(r"^[a-z][a-z0-9+.-]*:", re.I)


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.refs: list[tuple[str, str, str]] = []  # (tag, attribute, value)
        self.styles: list[str] = []
        self.title = ""
        self._in_style = False
        self._in_title = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key):
                self.ids.add(a[key])
        for key, value in attrs:
            if value is None:
                continue
            if key in ("href", "src", "poster", "data") or (key == "action" and tag == "form"):
                self.refs.append((tag, key, value.strip()))
            elif key == "srcset":
                for part in value.split(","):
                    if part.strip():
                        self.refs.append((tag, key, part.strip().split()[0]))
            elif key == "style":
                self.styles.append(value)
        self._in_style = tag == "style"
        self._in_title = tag == "title"

    def handle_endtag(self, tag):
        self._in_style = False
        self._in_title = False

    def handle_data(self, data):
        if self._in_style:
            self.styles.append(data)
        if self._in_title:
            self.title += data


def css_refs(text: str) -> list[str]:
    refs = [m.group(2) for m in re.finditer(r"url\(\s*(['\"]?)([^'\")]+)\1\s*\)", text)]
    refs += [m.group(2) for m in re.finditer(r"@import\s+(['\"])([^'\"]+)\1", text)]
    return refs


def local_target(site: str, base: str, ref: str) -> tuple[str, str]:
    """The file a relative reference names (query dropped) and its fragment."""
    parsed = urllib.parse.urlsplit(ref)
    path = urllib.parse.unquote(parsed.path)
    target = os.path.normpath(os.path.join(os.path.dirname(base), path)) if path else base
    if os.path.isdir(target):
        target = os.path.join(target, "index.html")
    return target, urllib.parse.unquote(parsed.fragment)


def static_check(site: str) -> tuple[list[str], list[str]]:
    """Problems of every page and style sheet, and the pages to open: the site's
    own and the Doxygen pages (cpp/) they link to."""
    problems: list[str] = []
    linked: set[str] = set()
    pages: dict[str, Page] = {}
    for folder, _, files in os.walk(site):
        for f in files:
            if f.endswith(".html"):
                path = os.path.join(folder, f)
                p = Page()
                with open(path, encoding="utf-8", errors="replace") as fh:
                    p.feed(fh.read())
                pages[path] = p

    def where(path: str) -> str:
        return os.path.relpath(path, site)

    for path, p in sorted(pages.items()):
        for tag, attr, ref in p.refs:
            if not ref or ref.startswith(("javascript:", "mailto:", "data:", "about:")):
                continue
            loads = attr in LOADING_ATTRS or tag == "link" and attr == "href"
            if NETWORK.match(ref) or SCHEME.match(ref):
                if loads:
                    problems.append(f"{where(path)}: <{tag} {attr}> loads {ref} from the network")
                continue
            target, fragment = local_target(site, path, ref)
            if not target.startswith(os.path.abspath(site) + os.sep):
                problems.append(f"{where(path)}: <{tag} {attr}=\"{ref}\"> points outside the site")
            elif not os.path.isfile(target):
                problems.append(f"{where(path)}: <{tag} {attr}=\"{ref}\">: no file {where(target)}")
            elif fragment and target.endswith(".html") and fragment not in pages[target].ids:
                problems.append(f"{where(path)}: <{tag} {attr}=\"{ref}\">: no anchor #{fragment} in {where(target)}")
            elif target.endswith(".html") and not where(path).startswith("cpp" + os.sep):
                linked.add(target)
        for style in p.styles:
            for ref in css_refs(style):
                if NETWORK.match(ref):
                    problems.append(f"{where(path)}: a style loads {ref} from the network")
    for folder, _, files in os.walk(site):
        for f in files:
            if not f.endswith(".css"):
                continue
            path = os.path.join(folder, f)
            with open(path, encoding="utf-8", errors="replace") as fh:
                text = re.sub(r"/\*.*?\*/", "", fh.read(), flags=re.S)
            for ref in css_refs(text):
                if ref.startswith(("data:", "#")):
                    continue
                if NETWORK.match(ref) or SCHEME.match(ref):
                    problems.append(f"{where(path)}: loads {ref} from the network")
                    continue
                target, _ = local_target(site, path, ref)
                if not os.path.isfile(target):
                    problems.append(f"{where(path)}: url({ref}): no file {where(target)}")
    cpp = os.path.join(site, "cpp") + os.sep
    for path, p in pages.items():
        if not p.title.strip() and not path.startswith(os.path.join(cpp, "search") + os.sep):
            problems.append(f"{where(path)}: no <title>")
    return problems, sorted(p for p in pages if not p.startswith(cpp) or p in linked)


DRIVER = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>docs site check</title></head>
<body><pre id="result">running</pre><iframe id="frame" style="width:1200px;height:900px"></iframe>
<script>
const pages = %s;
const results = [];
const frame = document.getElementById("frame");
let i = 0;
function settle(doc, tries, done) {
  const waitMath = doc.querySelector(".math") && doc.documentElement.dataset.mathRendered !== "yes";
  const images = Array.from(doc.images).filter(im => !im.complete);
  if ((waitMath || images.length) && tries > 0) { setTimeout(() => settle(doc, tries - 1, done), 20); return; }
  done();
}
function next() {
  if (i >= pages.length) {
    document.getElementById("result").textContent = "RESULT " + JSON.stringify(results);
    return;
  }
  const url = pages[i++];
  const timer = setTimeout(() => { results.push({url: url, error: "did not load in 20 s"}); next(); }, 20000);
  frame.onload = () => {
    clearTimeout(timer);
    let doc;
    try { doc = frame.contentDocument; } catch (e) { results.push({url: url, error: String(e)}); next(); return; }
    settle(doc, 250, () => {
      const r = {url: url};
      try {
        r.title = doc.title;
        r.text = doc.body ? doc.body.innerText.trim().length : 0;
        r.brokenImages = Array.from(doc.images).filter(im => !im.naturalWidth).map(im => im.getAttribute("src"));
        r.math = doc.querySelectorAll(".math").length;
        r.katex = doc.querySelectorAll(".math .katex").length;
        r.mathErrors = Array.from(doc.querySelectorAll(".katex-error")).map(e => e.getAttribute("title") || e.textContent).slice(0, 5);
        r.remote = frame.contentWindow.performance.getEntriesByType("resource").map(e => e.name)
          .filter(n => !n.startsWith("file:") && !n.startsWith("data:") && !n.startsWith("blob:"));
      } catch (e) { r.error = String(e); }
      results.push(r);
      next();
    });
  };
  frame.src = url;
}
next();
</script></body></html>
"""


def browser_check(site: str, pages: list[str], chromium: str, work: str) -> list[str]:
    urls = ["file://" + urllib.parse.quote(os.path.abspath(p)) for p in pages]
    driver = os.path.join(work, "driver.html")
    with open(driver, "w", encoding="utf-8") as f:
        f.write(DRIVER % json.dumps(urls))
    cmd = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           "--allow-file-access-from-files", "--user-data-dir=" + os.path.join(work, "profile"),
           "--virtual-time-budget=3600000", "--dump-dom", "file://" + driver]
    if shutil.which("timeout"):
        cmd = ["timeout", "600"] + cmd
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace")
    m = re.search(r"RESULT (\[.*\])</pre>", r.stdout, re.S)
    if not m:
        tail = "\n".join((r.stderr or "").strip().split("\n")[-5:])
        return [f"chromium: the driver page did not finish (exit {r.returncode}): {tail}"]
    import html as html_mod
    results = json.loads(html_mod.unescape(m.group(1)))
    problems = []
    seen = {x["url"] for x in results}
    for u in urls:
        if u not in seen:
            problems.append(f"chromium: {u}: not opened")
    for x in results:
        name = os.path.relpath(urllib.parse.unquote(x["url"][len("file://"):]), site)
        if x.get("error"):
            problems.append(f"chromium: {name}: {x['error']}")
            continue
        if not x.get("title"):
            problems.append(f"chromium: {name}: no title after loading")
        if not x.get("text"):
            problems.append(f"chromium: {name}: an empty body")
        for img in x.get("brokenImages", []):
            problems.append(f"chromium: {name}: the image {img} does not decode")
        if x.get("math") and x.get("katex", 0) < x["math"]:
            problems.append(f"chromium: {name}: {x['math'] - x.get('katex', 0)} of {x['math']} formulas not rendered")
        for e in x.get("mathErrors", []):
            problems.append(f"chromium: {name}: KaTeX cannot read a formula: {e[:160]}")
        for u in x.get("remote", []):
            problems.append(f"chromium: {name}: fetched {u} from outside the site")
    return problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--site", help="a site already built")
    ap.add_argument("--build", help="a configured build tree: build the site from it first into --out")
    ap.add_argument("--out", help="where to build the site")
    ap.add_argument("--chromium", default=None)
    a = ap.parse_args()
    t0 = time.monotonic()
    site = a.site
    if a.build:
        if not a.out:
            ap.error("--build needs --out")
        r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "build-docs-site.py"),
                            "--build", a.build, "--out", a.out])
        if r.returncode != 0:
            print("check_docs_site: the site did not build without warnings", file=sys.stderr)
            return 1
        site = a.out
    if not site or not os.path.isfile(os.path.join(site, "index.html")):
        print(f"check_docs_site: no index.html in {site}", file=sys.stderr)
        return 1
    site = os.path.abspath(site)
    t1 = time.monotonic()
    problems, pages = static_check(site)
    t2 = time.monotonic()
    chromium = a.chromium or next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")
                                   if shutil.which(n)), None)
    if not chromium:
        problems.append("chromium not found: scripts/install-deps.sh installs it (Debian package chromium)")
    else:
        with tempfile.TemporaryDirectory(prefix="cubecal-docs-site-") as work:
            problems += browser_check(site, pages, chromium, work)
    t3 = time.monotonic()
    for p in problems:
        print(p)
    print(f"check_docs_site: {len(pages)} pages opened, {len(problems)} problem(s) "
          f"(build {t1 - t0:.0f} s, links {t2 - t1:.0f} s, chromium {t3 - t2:.0f} s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
