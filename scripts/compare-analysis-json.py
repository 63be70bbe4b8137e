#!/usr/bin/python3
"""Checks that an analysis.json keeps every key path and value of a baseline
analysis.json (written by an earlier cubecal) and lists the keys it adds.

usage: compare-analysis-json.py BASELINE NEW [--ignore KEY ...]

Key paths are dotted, with [i] for array elements. Values compare exactly
(numbers as parsed from the files). Exit status 0 when the baseline is
contained in the new file, 1 otherwise."""
import json
import sys


def walk(a, b, path, missing, differ, added, ignore):
    if path in ignore:
        return
    if isinstance(a, dict):
        if not isinstance(b, dict):
            differ.append((path, a, b))
            return
        for k, v in a.items():
            p = f"{path}.{k}" if path else k
            if p in ignore:
                continue
            if k not in b:
                missing.append(p)
            else:
                walk(v, b[k], p, missing, differ, added, ignore)
        for k in b:
            if k not in a:
                added.append(f"{path}.{k}" if path else k)
    elif isinstance(a, list):
        if not isinstance(b, list) or len(a) != len(b):
            differ.append((path, f"list of {len(a)}", f"{type(b).__name__} of {len(b) if isinstance(b, list) else '-'}"))
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", missing, differ, added, ignore)
    else:
        if a != b or type(a) is not type(b) and not (isinstance(a, (int, float)) and isinstance(b, (int, float))):
            differ.append((path, a, b))


def main(argv):
    args = [a for a in argv[1:]]
    ignore = set()
    while "--ignore" in args:
        i = args.index("--ignore")
        ignore.add(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        print(__doc__)
        return 2
    with open(args[0]) as f:
        base = json.load(f)
    with open(args[1]) as f:
        new = json.load(f)
    missing, differ, added = [], [], []
    walk(base, new, "", missing, differ, added, ignore)
    # Added keys without array indices: one line per kind of key.
    import re
    kinds = sorted({re.sub(r"\[\d+\]", "[]", k) for k in added})
    print(f"missing keys: {len(missing)}")
    for k in missing[:20]:
        print("  ", k)
    print(f"different values: {len(differ)}")
    for p, a, b in differ[:20]:
        print(f"   {p}: {a!r} -> {b!r}")
    print(f"added keys: {len(added)} ({len(kinds)} kinds)")
    for k in kinds:
        print("  ", k)
    return 0 if not missing and not differ else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
