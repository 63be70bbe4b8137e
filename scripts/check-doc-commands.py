#!/usr/bin/python3
"""Runs the commands the docs quote and checks the numbers they quote.

A runnable example in README.md or docs/**/*.md is marked by an HTML comment
on the line before it (blank lines between are allowed):

    <!-- doc-test -->
    ```console
    $ cubecal dev ../shared/data/stable32/phasedat/PHASE.DAT --type phase --rate 1 --taus decade
    ...the output the docs quote...
    ```

Each line of a console block that starts with "$ " is a command (a line ending
in a backslash runs on to the next); the lines after it, up to the next "$ "
or the end of the block, are its expected output. A marker may also carry
the command itself, hidden, for output shown as a Markdown table or a plain
fenced block:

    <!-- doc-test $ scripts/adis16405-example.sh cubecal adis16405-out -->
    | run | axis | N | ...

Marker options, before any "$": `stderr` (the expected output is standard
error followed by standard output; default: standard output only), `exit=N`
(the expected exit code; default 0), `slow=REASON` (run only with --slow: the
ctest run stays within a minute or two), `skip=REASON` (too slow to run at all,
e.g. CPU minutes of bootstrap: the block is listed and counted, not run).

Commands run with bash in a scratch directory whose ../shared/data is the
reference data (--data, CUBECAL_SHARED_DATA in ctest), with `cubecal` on PATH
meaning the binary under test (--cubecal), `build/` the build tree it is in
(BUILD/bin/cubecal: ./build/bin/test_x runs that tree's test program) and
`scripts/` the repository's, so a command runs as the docs write it and paths
it prints read as in the docs. The
commands of one block run in order in one scratch directory (a block may
simulate a file and analyze it); blocks run in parallel (--jobs).

Comparison, line by line: a line of the expected output that is exactly
"..." stands for any number of lines of the program's output. Otherwise each
expected line is split into numbers and the text between them. The text must
be equal up to runs of white space (column padding); each number must equal
the printed one rounded to the digits the docs quote: a quoted 2.451 matches
a printed 2.4507 or 2.451, a quoted 7.4e-06 a printed 7.392e-06. A number is
a decimal or exponent literal not glued to a letter, digit, '_' or '.' before
it (run1.csv, adis16405 and x2.4 are text, compared exactly).

Each mismatch is reported as FILE:LINE with the docs' line, the program's line
and the numbers that differ; the exit code is 1 when any block fails.
--update rewrites the expected output of the failing blocks in place from the
program's output (only inside marked blocks): a line whose text still matches
keeps its layout and gets the new numbers at the digits it quoted; any other
line is replaced by the program's line; "..." lines are kept.

Besides the marked blocks, every command written anywhere in the docs (a
line of a fenced block, or a `cubecal ...` span in the text, tables included)
is checked against the program's own --help: its command (and calibrate's
subcommand) must exist and each --flag it gives must be one that command
takes. Illustrative commands on files the reader brings (imu.csv, log.csv)
cannot run here, but a renamed or removed option is caught.

Usage: scripts/check-doc-commands.py [--cubecal BIN] [--data DIR] [--jobs N]
       [--slow] [--update] [--list] [--only SUBSTRING] [REPO_ROOT]
"""
from __future__ import annotations

import argparse
import concurrent.futures
import dataclasses
import glob
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

MARKER = re.compile(r"^\s*<!--\s*doc-test\b(.*?)-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([\w-]*)")
# A number not glued to a word before it: sign, digits, decimals, exponent.
NUMBER = re.compile(r"(?<![\w.])[-+−]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
ELLIPSIS = "..."
TIMEOUT_S = 300


@dataclasses.dataclass
class Command:
    text: str  # as written (continuations joined)
    line: int  # 1-based line of the "$ " line, or of the marker holding the command
    expected: list[str]
    expected_lines: list[int]  # 1-based file line of each expected line
    end_line: int = 0  # 1-based last line of a "$ " command (its continuations)


@dataclasses.dataclass
class Block:
    path: str
    marker_line: int
    options: dict[str, str]
    commands: list[Command]


def parse_options(text: str) -> tuple[dict[str, str], str | None]:
    """The marker's options and its hidden command (after '$'), if any."""
    command = None
    if "$" in text:
        text, command = text.split("$", 1)
        command = command.strip()
    options: dict[str, str] = {}
    for word in shlex.split(text):
        key, _, value = word.partition("=")
        options[key] = value
    unknown = set(options) - {"stderr", "exit", "skip", "slow"}
    if unknown:
        raise ValueError(f"unknown doc-test option(s) {', '.join(sorted(unknown))}")
    return options, command


def console_commands(lines: list[str], first: int) -> list[Command]:
    """The "$ " commands of a console block and their expected output."""
    commands: list[Command] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("$ "):
            start = i
            text = line[2:]
            while text.endswith("\\") and i + 1 < len(lines):
                i += 1
                text = text[:-1] + " " + lines[i].strip()
            commands.append(Command(text.strip(), first + start, [], [], first + i))
        elif commands:
            commands[-1].expected.append(line)
            commands[-1].expected_lines.append(first + i)
        elif line.strip():
            raise ValueError(f"line {first + i}: output before the first '$ ' command of a console block")
        i += 1
    return commands


def blocks_of(path: str, text: str) -> list[Block]:
    lines = text.split("\n")
    blocks: list[Block] = []
    i = 0
    while i < len(lines):
        m = MARKER.match(lines[i])
        if not m:
            i += 1
            continue
        marker_line = i + 1
        try:
            options, hidden = parse_options(m.group(1))
        except ValueError as e:
            raise ValueError(f"{path}:{marker_line}: {e}") from None
        j = i + 1
        while j < len(lines) and not lines[j].strip():
            j += 1
        if j == len(lines):
            raise ValueError(f"{path}:{marker_line}: a doc-test marker with no block after it")
        fence = FENCE.match(lines[j])
        if fence:
            indent, ticks, lang = fence.groups()
            k = j + 1
            while k < len(lines) and not lines[k].strip().startswith(ticks):
                k += 1
            if k == len(lines):
                raise ValueError(f"{path}:{j + 1}: the fenced block is not closed")
            body = [b[len(indent):] if b.startswith(indent) else b.lstrip() for b in lines[j + 1:k]]
            first = j + 2
            end = k + 1
        elif lines[j].lstrip().startswith("|"):
            k = j
            while k < len(lines) and lines[k].lstrip().startswith("|"):
                k += 1
            body = lines[j:k]
            first = j + 1
            end = k
            lang = "table"
        else:
            raise ValueError(f"{path}:{marker_line}: a doc-test marker must precede a fenced block or a table")
        try:
            if hidden is not None:
                commands = [Command(hidden, marker_line, body, list(range(first, first + len(body))))]
            elif lang == "console":
                commands = console_commands(body, first)
            else:
                raise ValueError(f"line {j + 1}: a marker without '$ command' must precede a ```console block")
        except ValueError as e:
            raise ValueError(f"{path}:{e}") from None
        if not commands:
            raise ValueError(f"{path}:{marker_line}: the marked block holds no '$ ' command")
        blocks.append(Block(path, marker_line, options, commands))
        i = end
    return blocks


def split_numbers(line: str) -> tuple[list[str], list[str]]:
    """The line's text pieces (len = numbers + 1) and its number literals."""
    texts, numbers, pos = [], [], 0
    for m in NUMBER.finditer(line):
        texts.append(line[pos:m.start()])
        numbers.append(m.group())
        pos = m.end()
    texts.append(line[pos:])
    return texts, numbers


def skeleton(line: str) -> str:
    texts, _ = split_numbers(line)
    return "#".join(" ".join(t.split()) for t in texts).strip()


def value(literal: str) -> float:
    return float(literal.replace("−", "-"))


def quantum(literal: str) -> float:
    """Half a unit in the last place the literal quotes."""
    mantissa, _, exponent = literal.replace("−", "-").lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def number_matches(quoted: str, printed: str) -> bool:
    q, p = value(quoted), value(printed)
    if math.isnan(q) or math.isnan(p):
        return math.isnan(q) and math.isnan(p)
    return abs(p - q) <= quantum(quoted) * (1 + 1e-9) + 1e-12 * abs(q)


def restyle(quoted: str, printed: str) -> str:
    """The printed number in the quoted literal's style (digits, exponent)."""
    mantissa, e, exponent = quoted.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    p = value(printed)
    if e:
        s = f"{p:.{decimals}e}"
        m, _, x = s.partition("e")
        width = len(exponent.lstrip("+-"))
        sign = "-" if int(x) < 0 else ("+" if exponent.startswith("+") else "")
        s = f"{m}e{sign}{abs(int(x)):0{width}d}"
    else:
        s = f"{p:.{decimals}f}"
    if quoted.startswith("+") and p >= 0:
        s = "+" + s
    if quoted.startswith("−"):
        s = s.replace("-", "−", 1)
    return s


def line_problems(expected: str, actual: str) -> list[str]:
    """What differs between a quoted line and a printed line of equal skeleton."""
    _, qs = split_numbers(expected)
    _, ps = split_numbers(actual)
    return [f"{q} (printed {p})" for q, p in zip(qs, ps) if not number_matches(q, p)]


def updated_line(expected: str, actual: str) -> str:
    texts, qs = split_numbers(expected)
    _, ps = split_numbers(actual)
    out = texts[0]
    for k, (q, p) in enumerate(zip(qs, ps)):
        new = q if number_matches(q, p) else restyle(q, p)
        out += new + texts[k + 1]
    return out


@dataclasses.dataclass
class LineResult:
    doc_line: int  # 0: past the end of the quoted output
    expected: str | None
    actual: str | None
    problems: list[str]


def compare(cmd: Command, output: list[str]) -> tuple[list[LineResult], list[str]]:
    """Line results of every mismatch and the updated expected output."""
    exp = list(cmd.expected)
    lines = list(cmd.expected_lines)
    while exp and not exp[-1].strip():
        exp.pop()
        lines.pop()
    out = list(output)
    while out and not out[-1].strip():
        out.pop()
    bad: list[LineResult] = []
    new: list[str] = []
    j = 0
    for k, e in enumerate(exp):
        if e.strip() == ELLIPSIS:
            new.append(e)
            nxt = next((x for x in exp[k + 1:] if x.strip() != ELLIPSIS), None)
            if nxt is None:
                j = len(out)
            else:
                # The next quoted line, searched from here: the first line of its
                # text and numbers, else of its text alone (table rows share a
                # text); not found, the lines compare in order (and --update
                # takes the program's).
                want = skeleton(nxt)
                same_text = [k2 for k2 in range(j, len(out)) if skeleton(out[k2]) == want]
                same = [k2 for k2 in same_text if not line_problems(nxt, out[k2])]
                if same or same_text:
                    j = (same or same_text)[0]
            continue
        if j >= len(out):
            bad.append(LineResult(lines[k], e, None, ["the program printed no more lines"]))
            continue
        a = out[j]
        if skeleton(e) != skeleton(a):
            bad.append(LineResult(lines[k], e, a, ["the text differs"]))
            new.append(a)
        else:
            problems = line_problems(e, a)
            if problems:
                bad.append(LineResult(lines[k], e, a, problems))
            new.append(updated_line(e, a))
        j += 1
    if j < len(out) and not (exp and exp[-1].strip() == ELLIPSIS):
        extra = out[j:]
        bad.append(LineResult(lines[-1] if lines else cmd.line, None, extra[0],
                              [f"the program printed {len(extra)} more line(s) than the docs quote"]))
        new.extend(extra)
    return bad, new


class Scratch:
    """A scratch directory: TMP/work to run in, TMP/shared/data the reference
    data, TMP/bin/cubecal the binary under test, work/scripts the repository's."""

    def __init__(self, cubecal: str, data: str, root: str):
        self.tmp = tempfile.TemporaryDirectory(prefix="cubecal-doc-")
        tmp = self.tmp.name
        os.makedirs(os.path.join(tmp, "shared"))
        os.symlink(data, os.path.join(tmp, "shared", "data"))
        bindir = os.path.join(tmp, "bin")
        os.makedirs(bindir)
        os.symlink(cubecal, os.path.join(bindir, "cubecal"))
        self.work = os.path.join(tmp, "work")
        os.makedirs(self.work)
        os.symlink(os.path.join(root, "scripts"), os.path.join(self.work, "scripts"))
        # build/bin/... as the docs write it: the build tree of the binary under test.
        build = os.path.dirname(os.path.dirname(cubecal))
        if os.path.basename(os.path.dirname(cubecal)) == "bin":
            os.symlink(build, os.path.join(self.work, "build"))
        self.env = dict(os.environ)
        self.env["PATH"] = bindir + os.pathsep + self.env.get("PATH", "")
        self.env["CUBECAL_SHARED_DATA"] = data
        self.env["LC_ALL"] = "C.UTF-8"

    def close(self) -> None:
        self.tmp.cleanup()


class Runner:
    def __init__(self, cubecal: str, data: str, root: str):
        self.cubecal = os.path.abspath(cubecal)
        self.data = os.path.abspath(data)
        self.root = os.path.abspath(root)

    def scratch(self) -> Scratch:
        return Scratch(self.cubecal, self.data, self.root)

    def run(self, block: Block, cmd: Command, where: Scratch) -> tuple[int, list[str], float, str]:
        """Exit code, output lines (stderr first with the stderr option), seconds, stderr."""
        t0 = time.monotonic()
        p = subprocess.run(["bash", "-c", "set -o pipefail; " + cmd.text], cwd=where.work, env=where.env,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=TIMEOUT_S)
        seconds = time.monotonic() - t0
        text = p.stdout.decode("utf-8", "replace")
        if "stderr" in block.options:
            text = p.stderr.decode("utf-8", "replace") + text
        return p.returncode, text.split("\n"), seconds, p.stderr.decode("utf-8", "replace")


def rel(path: str, root: str) -> str:
    return os.path.relpath(path, root)


def check_block(runner: Runner, block: Block, commands: list[Command], root: str) -> list[tuple]:
    """check_command's result for each command, run in order in one scratch directory."""
    scratch = runner.scratch()
    try:
        return [check_command(runner, block, c, root, scratch) for c in commands]
    finally:
        scratch.close()


def check_command(runner: Runner, block: Block, cmd: Command, root: str,
                  scratch: Scratch) -> tuple[list[str], list[str] | None, float]:
    """The report lines of one command and its updated output (None: unchanged)."""
    where = f"{rel(block.path, root)}:{cmd.line}"
    try:
        code, output, seconds, stderr = runner.run(block, cmd, scratch)
    except subprocess.TimeoutExpired:
        return [f"{where}: FAIL: `{cmd.text}` ran over {TIMEOUT_S} s"], None, TIMEOUT_S
    report: list[str] = []
    want_code = int(block.options.get("exit", "0") or 0)
    if code != want_code:
        report.append(f"{where}: FAIL: `{cmd.text}` exited {code}, the docs expect {want_code}")
        for s in [x for x in stderr.strip().split("\n") if x][-3:]:
            report.append(f"    stderr: {s}")
    bad, new = compare(cmd, output)
    for r in bad:
        report.append(f"{rel(block.path, root)}:{r.doc_line}: FAIL: {'; '.join(r.problems)}")
        if r.expected is not None:
            report.append(f"    - docs:    {r.expected.strip()}")
        if r.actual is not None:
            report.append(f"    + program: {r.actual.strip()}")
    return report, (new if bad else None), seconds


def update_file(path: str, edits: list[tuple[Command, list[str]]]) -> None:
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    # From the bottom up, so earlier line numbers stay valid.
    for cmd, new in sorted(edits, key=lambda e: -(e[0].end_line or e[0].line)):
        exp_lines = list(cmd.expected_lines)
        exp = list(cmd.expected)
        while exp and not exp[-1].strip():
            exp.pop()
            exp_lines.pop()
        if exp_lines:
            first, last = exp_lines[0] - 1, exp_lines[-1] - 1
            indent = re.match(r"\s*", lines[first]).group() if lines[first].strip() else ""
            lines[first:last + 1] = [indent + n if n.strip() else n for n in new]
        else:  # nothing quoted yet: the program's lines go after the command
            at = cmd.end_line or cmd.line
            indent = re.match(r"\s*", lines[cmd.line - 1]).group()
            lines[at:at] = [indent + n if n.strip() else n for n in new]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines))


# A command in the docs: `cubecal WORD [SUBWORD] ...` up to a pipe, a
# redirection to another program, a comment or the end of its span.
COMMAND_RE = re.compile(r"(?:^|\| *|&& *|\$\(|^\$ )(?:\./build/bin/|build/bin/)?cubecal((?: +[^|;&#`)\n]*)?)")
FLAG_RE = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")


def written_commands(path: str, text: str) -> list[tuple[int, str]]:
    """Every `cubecal ...` the file writes: fenced-block lines (with their
    continuation lines) and backtick spans, as (line, command text)."""
    found: list[tuple[int, str]] = []
    lines = text.split("\n")
    fenced = False
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.lstrip().startswith("```"):
            fenced = not fenced
            i += 1
            continue
        if fenced:
            joined, first = line, i
            while joined.rstrip().endswith("\\") and i + 1 < len(lines):
                i += 1
                joined = joined.rstrip()[:-1] + " " + lines[i].strip()
            for m in COMMAND_RE.finditer(joined.strip().removeprefix("$ ")):
                found.append((first + 1, " ".join(("cubecal" + m.group(1)).split())))
        else:
            for span in re.findall(r"`([^`]+)`", line):
                for m in COMMAND_RE.finditer(span.strip()):
                    found.append((i + 1, " ".join(("cubecal" + m.group(1)).split())))
        i += 1
    return found


def check_written_flags(cubecal: str, root: str, files: list[str]) -> tuple[int, list[str]]:
    """Checks each written command's name and --flags against its --help."""
    helps: dict[tuple[str, ...], str | None] = {}

    def help_of(words: tuple[str, ...]) -> str | None:
        if words not in helps:
            r = subprocess.run([cubecal, *words, "--help"], capture_output=True, text=True)
            helps[words] = r.stdout if r.returncode == 0 else None
        return helps[words]

    top = help_of(())
    names = set(re.findall(r"^  ([a-z][a-z-]*) ", top or "", re.M))
    problems, checked = [], 0
    for path in files:
        with open(path, encoding="utf-8") as f:
            commands = written_commands(path, f.read())
        for line, cmd in commands:
            words = cmd.split()[1:]
            if not words or words[0].startswith("-") or words[0].isupper() or words[0] not in names and \
                    not re.fullmatch(r"[a-z][a-z-]*", words[0]):
                continue  # `cubecal --help`, `cubecal COMMAND`, prose such as "cubecal's"
            where = f"{rel(path, root)}:{line}"
            if words[0] not in names:
                problems.append(f"{where}: `{cmd}`: cubecal has no command '{words[0]}'")
                continue
            key = (words[0],)
            if words[0] == "calibrate" and len(words) > 1 and not words[1].startswith("-") \
                    and not words[1].isupper():
                key = (words[0], words[1])
            text = help_of(key)
            if text is None:
                problems.append(f"{where}: `{cmd}`: `cubecal {' '.join(key)} --help` fails: no such command")
                continue
            checked += 1
            for flag in FLAG_RE.findall(cmd):
                if not any(re.search(r"(?<![\w-])" + re.escape(flag) + r"(?![\w-])", t) for t in (text, top or "")):
                    problems.append(f"{where}: `{cmd}`: cubecal {' '.join(key)} takes no {flag}")
    return checked, problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--cubecal", default=None, help="the binary (default ROOT/build/bin/cubecal)")
    ap.add_argument("--data", default=os.environ.get("CUBECAL_SHARED_DATA"),
                    help="the reference data (default $CUBECAL_SHARED_DATA, else ROOT/../shared/data)")
    ap.add_argument("--jobs", type=int, default=2, help="commands run at once (default 2)")
    ap.add_argument("--slow", action="store_true", help="also run the blocks marked slow=")
    ap.add_argument("--update", action="store_true", help="rewrite the quoted output of failing blocks in place")
    ap.add_argument("--list", action="store_true", help="list the marked commands, run nothing")
    ap.add_argument("--only", default="", help="run only the commands whose file:line or text contains this")
    a = ap.parse_args()
    root = os.path.abspath(a.root)
    cubecal = a.cubecal or os.path.join(root, "build", "bin", "cubecal")
    data = a.data or os.path.join(root, "..", "shared", "data")
    files = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"),
                                                                 recursive=True))
    blocks: list[Block] = []
    try:
        for path in files:
            with open(path, encoding="utf-8") as f:
                blocks += blocks_of(path, f.read())
    except ValueError as e:
        print(f"check-doc-commands: {e}", file=sys.stderr)
        return 2
    jobs = []
    skipped = []
    for b in blocks:
        for c in b.commands:
            where = f"{rel(b.path, root)}:{c.line}"
            if a.only and a.only not in where and a.only not in c.text:
                continue
            if "skip" in b.options:
                skipped.append(f"{where}: skipped ({b.options['skip'] or 'no reason given'}): `{c.text}`")
            elif "slow" in b.options and not a.slow:
                skipped.append(f"{where}: slow, run with --slow ({b.options['slow'] or 'no reason given'}): "
                               f"`{c.text}`")
            else:
                jobs.append((b, c))
    numbers = sum(len(split_numbers(e)[1]) for b, c in jobs for e in c.expected)
    if a.list:
        for b, c in jobs:
            print(f"{rel(b.path, root)}:{c.line}: `{c.text}` ({sum(len(split_numbers(e)[1]) for e in c.expected)} numbers)")
        for s in skipped:
            print(s)
        return 0
    if not os.access(cubecal, os.X_OK):
        print(f"check-doc-commands: {cubecal} is not an executable (build it, or give --cubecal)", file=sys.stderr)
        return 2
    if not os.path.isdir(data):
        print(f"check-doc-commands: {data}: no reference data directory (give --data)", file=sys.stderr)
        return 2
    flags_checked, flag_problems = (0, []) if a.only else check_written_flags(cubecal, root, files)
    for p in flag_problems:
        print(p)
    runner = Runner(cubecal, data, root)
    failed = len(flag_problems)
    edits: dict[str, list[tuple[Command, list[str]]]] = {}
    t0 = time.monotonic()
    by_block: dict[int, tuple[Block, list[Command]]] = {}
    for b, c in jobs:
        by_block.setdefault(id(b), (b, []))[1].append(c)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        futures = [(b, cs, pool.submit(check_block, runner, b, cs, root)) for b, cs in by_block.values()]
        results = [(b, c, r) for b, cs, fut in futures for c, r in zip(cs, fut.result())]
        for b, c, (report, new, seconds) in results:
            where = f"{rel(b.path, root)}:{c.line}"
            if report:
                failed += 1
                print("\n".join(report))
                if new is not None:
                    edits.setdefault(b.path, []).append((c, new))
            else:
                print(f"{where}: ok ({seconds:.1f} s) `{c.text}`")
    for s in skipped:
        print(s)
    print(f"\n{flags_checked} written command(s) checked against their --help, {len(flag_problems)} wrong")
    print(f"{len(jobs)} command(s) run, {numbers} quoted number(s), {failed} failed, {len(skipped)} skipped "
          f"({time.monotonic() - t0:.1f} s)")
    if a.update and edits:
        for path, e in edits.items():
            update_file(path, e)
            print(f"updated {rel(path, root)} ({len(e)} block(s)): review with git diff")
    elif failed:
        print("to take the program's output into the docs: scripts/check-doc-commands.py --update "
              "(then review git diff)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
