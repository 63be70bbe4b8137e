"""Sphinx configuration of cubecal's documentation site (`make docs`).

The site is built from docs/ as it is: the markdown pages (MyST), the Python
module's docstrings (autodoc of the built module: PYTHONPATH=build/python) and
the C++ API: Doxygen's own HTML of include/cubecal (the `docs` target's, whose
warnings fail it) copied into the site under cpp/, with a page, cpp-api.md,
that lists every header by layer with its summary from Doxygen's XML and
links to it. (breathe renders the same XML into Sphinx pages, but over the
123 headers it takes half a minute of CPU and reports each namespace once per
header as a duplicate declaration.) CMake's `docs_site` target runs it with
-W --keep-going: a warning fails the build.

Pages that list what the code holds are completed here at read time, so a new
module, header or page appears without editing a page:

- python-api.md: the marker <!-- python-modules --> becomes one section per
  public module of the package (PYTHON_MODULES below: the one list to edit);
- cpp-api.md: <!-- doxygen-headers --> becomes a table per layer of
  include/cubecal, each header linked to its Doxygen page with its summary;
- from-allantools.md: <!-- allantools-differences --> becomes the text of every
  docs/allantools-differences/*.md, headings moved under the page's section;
- index.md: <!-- other-pages --> becomes a toctree of every page no toctree of
  index.md names, so a new page is never an orphan.

Math ($...$, $$...$$) is rendered in the browser by KaTeX from Debian's
libjs-katex, copied into the site: no page loads anything from the network.
"""
from __future__ import annotations

import fnmatch
import glob
import importlib
import os
import pkgutil
import re
import shutil
import sys

DOCS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(DOCS)

# Where the build puts what the site documents (set by CMake; the defaults are
# the build tree `make` uses).
BUILD = os.environ.get("CUBECAL_BUILD_DIR", os.path.join(ROOT, "build"))
DOXYGEN = os.environ.get("CUBECAL_DOXYGEN_DIR", os.path.join(BUILD, "docs", "doxygen"))
DOXYGEN_XML = os.path.join(DOXYGEN, "xml")
DOXYGEN_HTML = os.path.join(DOXYGEN, "extra")  # holds cpp/, Doxygen's HTML
KATEX_DIR = os.environ.get("CUBECAL_KATEX_DIR", "/usr/share/javascript/katex")
sys.path.insert(0, os.path.join(BUILD, "python"))

# The Python modules documented on python-api.md, in this order: "cubecal"
# (the package's own namespace, what `import cubecal` gives) and then every
# public submodule found in the built package (a name without a leading "_"),
# so a module added to python/cubecal appears by itself. List a module here to
# place it; PYTHON_MODULES_HIDDEN leaves one out.
PYTHON_MODULES = ["cubecal"]
PYTHON_MODULES_HIDDEN: list[str] = []

project = "cubecal"
author = "the cubecal authors"
copyright = "the cubecal authors"
try:
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        release = re.search(r"project\(cubecal\s+VERSION\s+([0-9.]+)", f.read()).group(1)
except (OSError, AttributeError):
    release = ""
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",  # only its HTML for math; the script is KaTeX's (mathjax_path)
    "numpydoc",
]

root_doc = "index"
source_suffix = {".md": "markdown"}
exclude_patterns = ["allantools-differences/*", "_static", "_templates", "**/.*"]
templates_path: list[str] = []

# Markdown: $...$ math, ::: fences, and heading anchors so that the pages'
# links to #some-heading (GitHub's slugs) resolve in the site.
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 6
myst_dmath_double_inline = True

# Warnings are errors (-W on the command line); references are checked
# (nitpicky), except the types that live outside the project.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|np|typing|collections|pandas|matplotlib|os|pathlib)(\..*)?"),
    (r"py:.*", r"(array_like|array-like|optional|callable|iterable|sequence|mapping|path-like|file-like)"),
    (r"py:class", r"(int|float|str|bool|bytes|dict|list|tuple|object|None|complex|type|slice)"),
    (r"py:class", r"(Any|Optional|Union|Sequence|Mapping|Iterable|Iterator|Callable|Literal|ndarray)"),
    (r"py:class", r"pybind11_(builtins|object)\..*|pybind11_object"),
]

# Python docstrings: numpydoc; members in source order; signatures from the
# type stubs' style (the module's own annotations).
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"members": True, "show-inheritance": True}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# HTML: the Read the Docs theme as Debian ships it (fonts included), no
# analytics, no "edit on" links, nothing from the network.
html_theme = "sphinx_rtd_theme"
html_title = f"cubecal {release}"
html_static_path = ["_static"]
html_extra_path = [DOXYGEN_HTML]
html_css_files = ["katex/katex.min.css"]
# On every page (the navigation shows the headings of other pages, formulas included).
html_js_files = [("katex/katex.min.js", {"defer": "defer"}), ("katex/contrib/auto-render.js", {"defer": "defer"}),
                 ("cubecal-math.js", {"defer": "defer"})]
html_theme_options = {"navigation_depth": 3, "collapse_navigation": False, "prev_next_buttons_location": "both"}
html_show_sourcelink = False
html_copy_source = False
mathjax_path = "cubecal-math.js"
mathjax_options = {"defer": "defer"}


# ---------------------------------------------------------------------------
# Pages completed at read time.

def _python_modules() -> list[str]:
    """PYTHON_MODULES, then every other public module of the built package."""
    names = list(PYTHON_MODULES)
    package = importlib.import_module("cubecal")
    found = sorted(m.name for m in pkgutil.walk_packages(package.__path__, "cubecal.")
                   if not any(part.startswith("_") for part in m.name.split(".")))
    names += [n for n in found if n not in names]
    return [n for n in names if n not in PYTHON_MODULES_HIDDEN]


def _python_api_text() -> str:
    out = []
    for name in _python_modules():
        module = importlib.import_module(name)
        out.append(f"## `{name}`\n")
        options = [":members:", ":show-inheritance:"]
        if name == "cubecal":
            # The package's namespace is made of what it imports from its
            # private modules (_dev, _analyze, the extension _cubecal ...).
            options.append(":imported-members:")
        if name != "cubecal" and module.__doc__ is None:
            out.append(f"The module `{name}`.\n")
        out.append("```{eval-rst}\n.. automodule:: " + name + "\n   " + "\n   ".join(options) + "\n```\n")
        shared = _shared_with_package(name, module)
        if shared:
            out.append(f"Also in `{name}`, the same objects as in `cubecal` and documented there: "
                       + ", ".join(f"`{n}`" for n in shared) + ".\n")
    return "\n".join(out)


def _shared_with_package(name, module) -> list:
    """The public names of a submodule that are the package's own objects
    (cubecal.allantools.oadev is cubecal.oadev): documented once, under cubecal."""
    package = importlib.import_module("cubecal")
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in dir(module) if getattr(getattr(module, n), "__module__", None) == name
                 or getattr(getattr(module, n), "__module__", "").startswith("cubecal._")]
    return sorted(n for n in names if not n.startswith("_") and hasattr(module, n)
                  and getattr(package, n, None) is getattr(module, n) and name != "cubecal")


_DOCUMENTED: dict[int, str] = {}


def _skip_duplicates(app, what, name, obj, skip, options):
    """An object already documented under an earlier module (cubecal.oadev and
    cubecal.allantools.oadev, say) is documented once, where it appears first."""
    if what != "module" or skip:
        return None
    if isinstance(obj, (int, float, str, bytes, bool, type(None))):
        return None
    key = id(obj)
    where = _DOCUMENTED.get(key)
    current = app.env.temp_data.get("autodoc:module")
    if where is None:
        _DOCUMENTED[key] = current
        return None
    return True if where != current else None


# The layers of include/cubecal from the bottom up ("" the headers at the top).
CPP_LAYERS = ["", "math", "stats", "noise", "spectral", "sim", "calib", "io", "acquire", "pipeline", "report"]


def _doxygen_headers_text(app) -> str:
    """A table per layer: each header linked to Doxygen's page of it, with its summary."""
    import html
    import xml.etree.ElementTree as ET
    headers = {}
    index = ET.parse(os.path.join(DOXYGEN_XML, "index.xml")).getroot()
    for compound in index.findall("compound[@kind='file']"):
        refid = compound.get("refid")
        path = os.path.join(DOXYGEN_XML, refid + ".xml")
        app.env.note_dependency(path)
        cdef = ET.parse(path).getroot().find("compounddef")
        where = cdef.find("location").get("file")  # cubecal/stats/allan_curve.hpp
        brief = " ".join("".join(cdef.find("briefdescription").itertext()).split())
        headers[where] = (refid, brief)
    out = []
    for layer in CPP_LAYERS:
        prefix = "cubecal/" + (layer + "/" if layer else "")
        mine = sorted(h for h in headers if h.startswith(prefix) and "/" not in h[len(prefix):])
        if not mine:
            continue
        out.append(f"## {layer or 'The core headers'}\n")
        rows = "".join(
            f'<tr><td><a class="reference external" href="cpp/{headers[h][0]}.html"><code>&lt;{html.escape(h)}&gt;</code></a>'
            f"</td><td>{html.escape(headers[h][1])}</td></tr>\n" for h in mine)
        out.append('```{raw} html\n<table class="docutils align-default"><thead><tr><th>header</th>'
                   "<th>what it declares</th></tr></thead><tbody>\n" + rows + "</tbody></table>\n```\n")
    missing = sorted(h for h in headers if not any(
        h.startswith("cubecal/" + (l + "/" if l else "")) and "/" not in h[len("cubecal/" + (l + "/" if l else "")):]
        for l in CPP_LAYERS))
    if missing:
        raise RuntimeError(f"docs/conf.py: headers in no layer of CPP_LAYERS: {', '.join(missing)}")
    return "\n".join(out)


def _shift_headings(text: str, top: int) -> str:
    """The text with its headings moved so that the first becomes level `top`."""
    lines = text.split("\n")
    levels = []
    fenced = False
    for line in lines:
        if line.lstrip().startswith(("```", "~~~")):
            fenced = not fenced
        elif not fenced and re.match(r"#{1,6} ", line):
            levels.append(len(line) - len(line.lstrip("#")))
    if not levels:
        return text
    shift = top - min(levels)
    fenced = False
    for i, line in enumerate(lines):
        if line.lstrip().startswith(("```", "~~~")):
            fenced = not fenced
        elif not fenced and re.match(r"#{1,6} ", line):
            level = min(6, len(line) - len(line.lstrip("#")) + shift)
            lines[i] = "#" * level + " " + line.lstrip("#").lstrip()
    return "\n".join(lines)


def _differences_text(app) -> str:
    files = sorted(glob.glob(os.path.join(DOCS, "allantools-differences", "*.md")))
    if not files:
        return "No deliberate difference is recorded yet.\n"
    out = []
    for path in files:
        app.env.note_dependency(path)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        # Links are written relative to the file; the page is one level up.
        text = re.sub(r"\]\((?![a-z][a-z0-9+.-]*:|#|/)([^)\s]+)\)",
                      lambda m: "](" + os.path.normpath(os.path.join("allantools-differences", m.group(1))) + ")",
                      text)
        out.append(_shift_headings(text, 3).rstrip() + "\n")
    return "\n".join(out)


def _toctree_entries(text: str) -> list[str]:
    """The entries of the toctrees written in a page (glob patterns included)."""
    entries = []
    for block in re.findall(r"```\{toctree\}[^\n]*\n(.*?)```", text, re.S):
        for line in block.split("\n"):
            line = line.strip()
            if not line or line.startswith(":"):
                continue
            m = re.match(r".*<(.+)>$", line)
            entries.append(m.group(1) if m else line)
    return entries


def _other_pages_text(app, text: str) -> str:
    named = _toctree_entries(text)
    left = sorted(d for d in app.env.found_docs
                  if d != root_doc and not any(fnmatch.fnmatch(d, e) for e in named))
    if not left:
        return ""
    return "```{toctree}\n:caption: More pages\n:maxdepth: 1\n\n" + "\n".join(left) + "\n```\n"


# Docstrings are read as reStructuredText. Two plain-text habits of the
# module's docstrings that RST would warn about are read as they are meant:
# |x| is the norm of x (RST would look for a substitution named x), and an
# indented block (a list of cases, an example) may end without a blank line
# before the text that follows it (RST: "ends without a blank line"; adding
# the blank line changes nothing RST reads without a warning); and an indented
# example of code after a paragraph is code (a literal block, as if the
# paragraph ended with "::"), not a block quote whose indented loop body RST
# would call an unexpected indentation.
_NORM = re.compile(r"(?<![\\|`\w])\|([^|`\s](?:[^|`\n]*?[^|`\s])?)\|(?![|`\w])")
_CODE = re.compile(r"\w\(|\s=\s|^\s*(for|if|while|import|from|with|def|class|return|print)\b|^\s*(>>>|\$ )|\s#\s")
_NOT_PARAGRAPH = re.compile(r"^\s*(:|\.\.|[-*+] |>>>|\d+[.)] |#\.)")


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _literal_examples(lines: list) -> list:
    """Each indented block of code after a paragraph made a literal block."""
    out = list(lines)
    i = 0
    while i < len(out):
        line = out[i]
        if not line.strip() or i < 2 or out[i - 1].strip():
            i += 1
            continue
        k = i - 1
        while k >= 0 and not out[k].strip():
            k -= 1
        paragraph = out[k] if k >= 0 else ""
        j = i
        while j < len(out) and (not out[j].strip() or _indent(out[j]) > _indent(paragraph)):
            j += 1
        block = [b for b in out[i:j] if b.strip()]
        if (k >= 0 and _indent(line) > _indent(paragraph) and not _NOT_PARAGRAPH.match(paragraph)
                and not paragraph.rstrip().endswith("::") and any(_CODE.search(b) for b in block)):
            if paragraph.rstrip().endswith(":"):
                out[k] = paragraph.rstrip() + ":"
            else:
                out[k + 1:k + 1] = ["", " " * _indent(paragraph) + "::"]
                j += 2
        i = max(j, i + 1)
    return out


def _plain_text_docstring(app, what, name, obj, options, lines):
    lines[:] = _literal_examples(lines)
    out = []
    literal = -1  # the indentation of the "::" line whose literal block this is in, or -1
    previous = ""
    for line in lines:
        stripped = line.strip()
        indent = _indent(line)
        if previous.strip() and stripped and indent < _indent(previous):
            out.append("")
        if stripped and literal >= 0 and indent <= literal:
            literal = -1
        in_literal = literal >= 0 and (indent > literal or not stripped)
        line_block = stripped.startswith("| ") or stripped == "|"  # RST line blocks and table rows
        out.append(line if in_literal or line_block else _NORM.sub(r"\\|\1\\|", line))
        if line.rstrip().endswith("::") and literal < 0:
            literal = indent
        previous = line
    lines[:] = out


def _drop_empty_globs(app, text: str) -> str:
    """A toctree's glob entry that matches no page yet (a page another change
    adds) is left out rather than warned about."""
    def keep(line: str) -> bool:
        entry = line.strip()
        return not ("*" in entry and not entry.startswith(":")
                    and not any(fnmatch.fnmatch(d, entry) for d in app.env.found_docs))
    return "\n".join(line for line in text.split("\n") if keep(line))


def _public_name(app, env, node, contnode):
    """A type named by a private module (cubecal._dev.DevResult, as pybind11 and
    the annotations spell it) resolves to where the reference documents it
    (cubecal.DevResult)."""
    if node.get("refdomain") != "py":
        return None
    m = re.fullmatch(r"cubecal\.(?:_\w+\.)+(\w+)", node.get("reftarget", ""))
    if not m:
        return None
    domain = env.get_domain("py")
    public = "cubecal." + m.group(1)
    if public not in domain.objects:
        return None
    return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], public, node, contnode)


def _source_read(app, docname, source):
    text = source[0]
    if "<!-- python-modules -->" in text:
        text = text.replace("<!-- python-modules -->", _python_api_text())
    if "<!-- doxygen-headers -->" in text:
        text = text.replace("<!-- doxygen-headers -->", _doxygen_headers_text(app))
    if "<!-- allantools-differences -->" in text:
        text = text.replace("<!-- allantools-differences -->", _differences_text(app))
    if docname == root_doc:
        text = _drop_empty_globs(app, text)
    if "<!-- other-pages -->" in text:
        text = text.replace("<!-- other-pages -->", _other_pages_text(app, text))
    source[0] = text


def _copy_katex(app, exception):
    """KaTeX (script, style, fonts) from Debian's libjs-katex into _static/katex."""
    if exception is not None or app.builder.format != "html":
        return
    dest = os.path.join(app.outdir, "_static", "katex")
    for part in ("katex.min.js", "katex.min.css", os.path.join("contrib", "auto-render.js"), "fonts"):
        src = os.path.join(KATEX_DIR, part)
        if not os.path.exists(src):
            raise RuntimeError(f"{src} not found: the site's math needs Debian's libjs-katex "
                               "(scripts/install-deps.sh installs it)")
        target = os.path.join(dest, part)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        if os.path.isdir(src):
            shutil.copytree(src, target, dirs_exist_ok=True)
        else:
            shutil.copyfile(src, target)


def _check_inputs(app):
    for need in (os.path.join(DOXYGEN_XML, "index.xml"), os.path.join(DOXYGEN_HTML, "cpp", "index.html")):
        if not os.path.isfile(need):
            raise RuntimeError(f"{need} not found: the C++ API pages need Doxygen's XML and HTML "
                               "(the docs_site target makes them)")


def setup(app):
    app.connect("builder-inited", _check_inputs)
    app.connect("source-read", _source_read)
    app.connect("autodoc-skip-member", _skip_duplicates)
    app.connect("autodoc-process-docstring", _plain_text_docstring)
    app.connect("missing-reference", _public_name)
    app.connect("build-finished", _copy_katex)
    return {"parallel_read_safe": False}
