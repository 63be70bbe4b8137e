#!/usr/bin/python3
"""The shape of the tree, checked: the `architecture` test of `make test`.

  check-architecture.py SOURCE_DIR            fails (exit 1) on any rule broken, one line per breach
  check-architecture.py SOURCE_DIR --figures  prints the figures docs/architecture.md quotes

Rules (docs/architecture.md, "Rules that keep it so"):
  layers     a file includes only folders at or below its own in LAYERS, never another
             folder's detail/, and the core's umbrella header includes every installed core header;
  functions  at most MAX_LONG functions over LONG_LINES lines (universal-ctags measures them), each
             with a comment on the line above that says why it reads better whole;
  flags      no string literal of the library (src/ outside src/cli) names a command-line flag:
             errors name fields (cubecal::Field) and each face renders them;
  loops      the OpenMP channel loop is written once, in src/detail/for_channels.hpp;
  json       one JSON function style: `nlohmann::json to_json(const T&)` and `T from_json(...)`
             readers; no `void to_json(nlohmann::json&, ...)`.
"""
import os
import re
import subprocess
import sys

# Bottom to top. A folder may include its own and any folder in a lower row; the same row is not
# enough (folders of one row are independent of each other).
LAYERS = [
    ["(root)"],  # error.hpp, field.hpp, printable_text.hpp, stage_times.hpp
    ["math"],  # Vec3, Mat3, Matrix, IndexRange
    ["detail"],  # src/detail: private, shared by the library's folders (SIMD, solvers, Eigen views, the channel loop)
    ["stats"],
    ["noise"],
    ["spectral"],
    ["sim"],
    ["calib"],
    ["io"],
    ["acquire", "pipeline"],
    ["report"],
    ["cli", "python"],
]
UMBRELLA = "include/cubecal/cubecal.hpp"
CORE = {"(root)", "math", "stats", "noise", "spectral", "sim", "calib"}
LONG_LINES = 100
MAX_LONG = 5
# Flags of other programs that a written file quotes (Kalibr's kalibr_calibrate_imu_camera --imu).
FOREIGN_FLAGS = {"--imu"}
FLAG = re.compile(r'"(?:[^"\\\n]|\\.)*?(?<![A-Za-z0-9-])--[a-z][a-z0-9-]*(?:[^"\\\n]|\\.)*"')
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def rank_of(folder):
    for i, row in enumerate(LAYERS):
        if folder in row:
            return i
    return None


def sources(root):
    for top in ("src", "include", "python/src"):
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames.sort()
            for name in sorted(filenames):
                if name.endswith((".cpp", ".hpp", ".h")):
                    yield os.path.relpath(os.path.join(dirpath, name), root)


def folder_of(rel):
    """(folder, is_detail) of a source path relative to the root."""
    parts = rel.split("/")
    if parts[0] == "python":
        return "python", False
    if parts[0] == "include":
        parts = parts[2:]
    elif parts[0] == "src":
        parts = parts[1:]
    folder = parts[0] if len(parts) > 1 else "(root)"
    return folder, "detail" in parts[:-1]


def resolve(root, rel, inc):
    """The repository path an include names, or None (a system or third-party header)."""
    if inc.startswith("cubecal/"):
        for base in ("include", "src", "src/acquire/include"):
            if os.path.exists(os.path.join(root, base, inc)):
                return os.path.join(base, inc)
        return None
    full = os.path.normpath(os.path.join(os.path.dirname(rel), inc))
    return full if os.path.exists(os.path.join(root, full)) else None


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def layer_breaches(root):
    out = []
    for rel in sources(root):
        if rel == UMBRELLA:
            continue
        src_folder, _ = folder_of(rel)
        src_rank = rank_of(src_folder)
        for n, line in enumerate(open(os.path.join(root, rel), encoding="utf-8", errors="replace"), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = resolve(root, rel, m.group(1))
            if target is None:
                continue
            dst_folder, dst_detail = folder_of(target)
            if dst_folder == src_folder:
                continue
            dst_rank = rank_of(dst_folder)
            if src_rank is None or dst_rank is None:
                out.append(f"{rel}:{n}: folder without a layer ({src_folder} -> {dst_folder}): add it to LAYERS")
            elif dst_rank >= src_rank:
                out.append(f"{rel}:{n}: {src_folder} includes {m.group(1)} ({dst_folder}, not below it)")
            elif dst_detail and dst_folder != "detail":
                out.append(f"{rel}:{n}: includes another folder's detail/ header {m.group(1)}")
    return out


def installed_core_headers(root):
    heads = []
    for rel in sources(root):
        if not rel.startswith("include/cubecal/") or rel == UMBRELLA:
            continue
        folder, detail = folder_of(rel)
        if folder in CORE and not detail:
            heads.append(rel[len("include/"):])
    return heads


def umbrella_breaches(root):
    path = os.path.join(root, UMBRELLA)
    included = {m.group(1) for m in map(INCLUDE.match, open(path, encoding="utf-8")) if m}
    return [f"{UMBRELLA}: does not include {h}" for h in installed_core_headers(root) if h not in included]


def long_functions(root):
    """[(lines, "path:line", name, has_reason)] of the functions over LONG_LINES lines in src/ and python/src."""
    cmd = ["ctags", "-R", "--fields=+ne", "--kinds-C++=f", "--languages=C++", "-o", "-", "src", "python/src"]
    tags = subprocess.run(cmd, cwd=root, check=True, capture_output=True, text=True).stdout
    found = []
    for row in tags.splitlines():
        cols = row.split("\t")
        if cols[0].startswith("__anon"):
            continue  # a lambda counts in its function
        fields = dict(c.split(":", 1) for c in cols[3:] if ":" in c)
        if "line" not in fields or "end" not in fields:
            continue
        start, end = int(fields["line"]), int(fields["end"])
        if end - start + 1 <= LONG_LINES:
            continue
        lines = open(os.path.join(root, cols[1]), encoding="utf-8", errors="replace").read().split("\n")
        # The comment sits above the declaration, which may start a few lines above the name's line.
        above = [lines[i].strip() for i in range(max(0, start - 4), start - 1)]
        has_reason = any(a.startswith("//") and "whole" in a for a in above)
        found.append((end - start + 1, f"{cols[1]}:{start}", cols[0], has_reason))
    return sorted(found, reverse=True)


def library_literals_naming_flags(root):
    out = []
    for rel in sources(root):
        if rel.startswith(("src/cli/", "python/")):
            continue
        text = open(os.path.join(root, rel), encoding="utf-8", errors="replace").read()
        text = strip_comments(text)
        for m in FLAG.finditer(text):
            if set(re.findall(r"--[a-z][a-z0-9-]*", m.group(0))) <= FOREIGN_FLAGS:
                continue
            line = text.count("\n", 0, m.start()) + 1
            out.append(f"{rel}:{line}: {m.group(0)[:80]}")
    return out


def omp_loops(root):
    out = []
    for rel in sources(root):
        if rel.endswith("detail/for_channels.hpp"):
            continue
        for n, line in enumerate(open(os.path.join(root, rel), encoding="utf-8", errors="replace"), 1):
            if re.match(r"\s*#\s*pragma\s+omp\s+parallel", line):
                out.append(f"{rel}:{n}: an OpenMP loop of its own (use detail::for_channels)")
    return out


JSON_DEF = re.compile(r"^\s*(?:inline\s+|static\s+)*([\w:<>]+)\s+(\w*(?:to|from)_json)\s*\(", re.M)


def json_styles(root):
    """Declarations and definitions of JSON functions, by style."""
    counts = {}
    for rel in sources(root):
        text = strip_comments(open(os.path.join(root, rel), encoding="utf-8", errors="replace").read())
        for ret, name in JSON_DEF.findall(text):
            if ret in ("return", "else"):
                continue
            if name == "to_json":
                style = "void to_json(json&, T)" if ret == "void" else "json to_json(T)"
            elif name == "from_json":
                style = "void from_json(const json&, T&)" if ret == "void" else "T from_json(json, ...)"
            else:
                style = "T x_from_json(json, ...)" if name.endswith("from_json") else "json x_to_json(T)"
            counts[style] = counts.get(style, 0) + 1
    return counts


def error_bases(root):
    text = open(os.path.join(root, "include/cubecal/error.hpp"), encoding="utf-8").read()
    classes = re.findall(r"class\s+(\w+)\s*(?:final\s*)?:\s*public\s+([\w:]+)", text)
    return classes


def figures(root):
    longs = long_functions(root)
    print("long functions (> %d lines): %d" % (LONG_LINES, len(longs)))
    for n, where, name, reason in longs:
        print(f"  {n:4d} {where} {name}{'' if reason else '  (no reason comment)'}")
    print("library string literals naming a --flag:", len(library_literals_naming_flags(root)))
    print("OpenMP loops outside the helper:", len(omp_loops(root)))
    print("error classes (class: base):", ", ".join(f"{c}: {b}" for c, b in error_bases(root)))
    print("JSON function styles:", ", ".join(f"{k} x{v}" for k, v in json_styles(root).items() if v))
    heads = [r for r in sources(root) if r.startswith("include/") and "/detail/" not in r]
    print("headers under include/cubecal (not detail/):", len(heads))
    print("core headers not in cubecal.hpp:", len(umbrella_breaches(root)))
    print("include breaches of the layer order:", len(layer_breaches(root)))


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    if "--figures" in sys.argv:
        figures(root)
        return 0
    breaches = layer_breaches(root) + umbrella_breaches(root)
    longs = long_functions(root)
    if len(longs) > MAX_LONG:
        breaches += [f"{w}: {name} is {n} lines (at most {MAX_LONG} functions over {LONG_LINES}; split it)"
                     for n, w, name, _ in longs]
    breaches += [f"{w}: {name} is {n} lines without a comment above saying why it reads better whole"
                 for n, w, name, reason in longs if not reason]
    breaches += [f"{b} (name the field: cubecal::Field, rendered by each face)" for b in library_literals_naming_flags(root)]
    breaches += omp_loops(root)
    styles = json_styles(root)
    if len(styles) > 2:
        breaches.append(f"JSON functions in {len(styles)} styles ({', '.join(styles)}): one writer and one reader style")
    for b in breaches:
        print(b)
    print(f"check-architecture: {len(breaches)} breach(es)" if breaches else "check-architecture: ok")
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
