#!/usr/bin/env python3
"""Writes the typed result classes into the package's type stubs.

Each Result class of cubecal (python/cubecal/_result.py and the modules that
define results) declares its fields in `_spec`; this script writes them as
the class bodies of the stub beside the module (python/cubecal/NAME.pyi),
between the lines

    # BEGIN result classes (scripts/result-stubs.py)
    # END result classes

and leaves the rest of the stub (the functions, written by hand) as it is.
With --check it writes nothing and fails when a stub differs from what it
would write (python/tests/test_typed_results.py runs it so).

    PYTHONPATH=build/python python3 scripts/result-stubs.py python/cubecal [--check]
"""
import argparse
import importlib
import inspect
import keyword
import os
import sys

BEGIN = "# BEGIN result classes (scripts/result-stubs.py)"
END = "# END result classes"
MODULES = ("_result", "_analyze", "_model", "_spectral", "_calibrate", "_dev", "_plan")
TYPES = {"array": "NDArray[np.float64]", "int_array": "NDArray[np.int64]", "bool_array": "NDArray[np.bool_]",
         "matrix": "NDArray[np.float64]", "ndarray": "NDArray[Any]"}


def stub_type(text, optional):
    parts = [p.strip() for p in text.split("|")]
    out = []
    for p in parts:
        if p.startswith("list[") and p.endswith("]"):
            out.append(f"list[{TYPES.get(p[5:-1], p[5:-1])}]")
        else:
            out.append(TYPES.get(p, p))
    if optional and "None" not in out:
        out.append("None")
    return " | ".join(out)


def method_stub(name, function):
    sig = inspect.signature(function)
    text = str(sig).replace("'", "")
    return f"    def {name}{text}: ..."


def class_stub(cls):
    bases = ", ".join(b.__name__ for b in cls.__bases__)
    lines = [f"class {cls.__name__}({bases}):"]
    for name, (type_text, optional, _) in cls.__dict__.get("_fields_own", {}).items():
        if keyword.iskeyword(name) or not name.isidentifier():
            lines.append(f"    # {name}: only as an item, r[{name!r}]")
            continue
        lines.append(f"    {name}: {stub_type(type_text, optional)}")
    for name, annotation in cls.__dict__.get("__annotations__", {}).items():
        lines.append(f"    {name}: {annotation}")  # an attribute besides the document's fields
    for name, member in cls.__dict__.items():
        if name.startswith("_") and name != "__init__" or not inspect.isfunction(member):
            continue
        if name == "__init__":
            continue
        lines.append(method_stub(name, member))
    if len(lines) == 1:
        lines.append("    ...")
    return "\n".join(lines)


def classes_of(module):
    from cubecal._result import Result
    out = []
    for name, obj in vars(module).items():
        if inspect.isclass(obj) and issubclass(obj, Result) and obj.__module__ == module.__name__ \
                and obj is not Result and not name.startswith("_"):
            out.append(obj)
    return out


def generated(module):
    return "\n\n\n".join(class_stub(c) for c in classes_of(module))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("package", help="the source directory of the package (python/cubecal)")
    p.add_argument("--check", action="store_true", help="fail when a stub differs; write nothing")
    a = p.parse_args()
    stale = []
    for name in MODULES:
        module = importlib.import_module("cubecal." + name)
        path = os.path.join(a.package, name + ".pyi")
        with open(path) as f:
            text = f.read()
        if BEGIN not in text or END not in text:
            sys.exit(f"{path}: no {BEGIN!r} ... {END!r} lines")
        head, rest = text.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        new = head + BEGIN + "\n\n\n" + generated(module) + "\n\n\n" + END + tail
        if new != text:
            stale.append(path)
            if not a.check:
                with open(path, "w") as f:
                    f.write(new)
    if stale and a.check:
        sys.exit("stale stubs (run scripts/result-stubs.py python/cubecal): " + ", ".join(stale))
    print("\n".join(f"wrote {s}" for s in stale) if stale else "stubs up to date")


if __name__ == "__main__":
    main()
