#!/usr/bin/python3
"""Runs every command and code block of README.md and docs/*.md as written (issue 25, item 2),
in a scratch directory that holds the checkout's examples/ and scripts/ and its build:

- `sh` blocks run in bash, stopping at the first failing command; a `text` block right after
  one (a line of prose between at most) is its output: each of its lines must be in what the block printed (`...` stands for lines
  left out; the seconds of computation, and of an error estimate's companions, may differ);
- `python` blocks of one page run in order in one interpreter (later blocks use what earlier
  ones defined); `>>>` blocks run as doctests there; a block marked `standalone` runs alone as a
  script (one that starts Dask workers, which import it);
- `json` blocks are scenes, run by `mimpact chain` or `mimpact packing`;
- `cpp` and `cmake` blocks are excerpts of a file the project compiles: each of their lines must
  be in that file, in order.

An HTML comment on the line before a block changes what is done with it, and says why:

    <!-- docs-test: run "COMMAND" because REASON -->   a long block, run smaller
    <!-- docs-test: skip because REASON -->             not run (printed with its reason)
    <!-- docs-test: excerpt of PATH -->                 for cpp and cmake blocks
    <!-- docs-test: standalone -->                      for python blocks

Nothing is skipped silently: every block's fate is printed, and a skip needs a reason.

    /usr/bin/python3 tests/docs/check_docs.py --build build/release [FILE.md ...]
"""
import argparse
import doctest
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```\s*$", re.S | re.M)
DIRECTIVE = re.compile(r"<!--\s*docs-test:\s*(.*?)\s*-->", re.S)
TIMEOUT = 600  # s, for one block


class Block:
    def __init__(self, page, line, language, text, directive):
        self.page, self.line, self.language, self.text, self.directive = (
            page, line, language, text, directive)

    def where(self):
        page = self.page.relative_to(ROOT) if self.page.is_relative_to(ROOT) else self.page
        return f"{page}:{self.line}"


def blocks_of(page):
    """The page's fenced blocks, each with the directive on the line before it and the prose
    between it and the block before it."""
    text = page.read_text()
    end = 0
    for match in FENCE.finditer(text):
        before = text[:match.start()].rstrip()
        directive = None
        if before.endswith("-->"):
            comment = DIRECTIVE.match(before[before.rfind("<!--"):] + "\n")
            directive = comment.group(1) if comment else None
        block = Block(page, text[:match.start()].count("\n") + 1, match.group(1) or "text",
                      match.group(2), directive)
        block.prose = text[end:match.start()]
        end = match.end()
        yield block


def scratch_directory(build):
    """A directory with the checkout's examples/ and scripts/, and the build at build/release."""
    scratch = Path(tempfile.mkdtemp(prefix="mimpact-docs-"))
    for name in ("examples", "scripts", "python", "tests"):
        (scratch / name).symlink_to(ROOT / name)
    (scratch / "build").mkdir()
    (scratch / "build" / "release").symlink_to(Path(build).resolve())
    return scratch


def environment(scratch):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(scratch / "build" / "release" / "python")
    env.pop("MIMPACT_CLI", None)
    return env


def run(command, scratch, shell=True):
    done = subprocess.run(command, shell=shell, executable="/bin/bash" if shell else None,
                          cwd=scratch, env=environment(scratch), capture_output=True, text=True,
                          timeout=TIMEOUT)
    return done.returncode, done.stdout + done.stderr


def normalised(line):
    line = re.sub(r"in [0-9.e+-]+ s of computation", "in X s of computation", line)
    line = re.sub(r"; [0-9.e+-]+ s\)$", "; X s)", line)  # the error estimate's companions' time
    return " ".join(line.split())


def missing_line(shown, lines, normalise, elisions=("...",)):
    """The first of the shown lines (blank ones and elisions aside) that is not among `lines` in
    order after the ones before it, or None."""
    lines = [normalise(line) for line in lines]
    at = 0
    for wanted in shown.splitlines():
        wanted = normalise(wanted)
        if not wanted or wanted in elisions:
            continue
        while at < len(lines) and lines[at] != wanted:
            at += 1
        if at == len(lines):
            return wanted
        at += 1
    return None


def check_output(expected, printed):
    """Each shown line, but `...`, is among the printed lines, in order."""
    missing = missing_line(expected, printed.splitlines(), normalised)
    return f"the output does not show: {missing!r}" if missing is not None else None


def code(line):
    """A line of C++ or CMake without its trailing comment and with its spaces collapsed."""
    return " ".join(re.sub(r"\s+(//|#).*$", "", line).split())


def check_excerpt(block, path):
    """The block's lines, but `...` and blank ones, are lines of `path`, in order (their trailing
    comments aside: the docs may explain a line)."""
    missing = missing_line(block.text, (ROOT / path).read_text().splitlines(), code,
                           ("...", "// ..."))
    if missing is None:
        return None
    return f"{path} has no line {missing!r} (after the ones before it)"


def python_page(blocks, scratch):
    """The page's python blocks in one interpreter, in order; doctests among them."""
    driver = textwrap.dedent("""\
        import doctest, json, sys, traceback
        blocks = json.load(open(sys.argv[1]))
        space = {"__name__": "docs"}
        for where, code in blocks:
            if code.lstrip().startswith(">>>"):
                test = doctest.DocTestParser().get_doctest(code, space, where, where, 0)
                runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
                runner.run(test, clear_globs=False)
                if runner.failures:
                    sys.exit(f"{where}: the doctest fails")
                continue
            try:
                exec(compile(code, where, "exec"), space)
            except Exception:
                traceback.print_exc()
                sys.exit(f"{where}: the block raises")
        """)
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as listing:
        json.dump([[b.where(), b.text] for b in blocks], listing)
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as script:
        script.write(driver)
    return run(["/usr/bin/python3", script.name, listing.name], scratch, shell=False)


def scene_command(block, scratch):
    scene = json.loads(block.text)
    command = "packing" if "lattice" in scene or "beads" in scene else "chain"
    path = Path(tempfile.mkdtemp(dir=scratch)) / "scene.json"
    path.write_text(block.text)
    return f"build/release/bin/mimpact {command} {path} --quiet"


def untracked_changes():
    """`git status` of the checkout, build/ aside (None outside a git checkout)."""
    done = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        return None
    return [line for line in done.stdout.splitlines() if not line[3:].startswith("build/")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(ROOT / "build" / "release"))
    parser.add_argument("pages", nargs="*")
    args = parser.parse_args()
    pages = [Path(p).resolve() for p in args.pages] or (
        [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
        + sorted((ROOT / "docs" / "design").glob("*.md")))
    tree_before = untracked_changes()
    scratch = scratch_directory(args.build)
    failures, counts = [], {}

    def report(block, fate, problem=None):
        counts[fate] = counts.get(fate, 0) + 1
        print(f"{block.where():32s} {block.language:7s} {fate}" + (f": {problem}" if problem else ""))
        if problem and fate == "FAILED":
            failures.append(f"{block.where()}: {problem}")

    for page in pages:
        blocks = list(blocks_of(page))
        python = []
        previous_output = None
        for block in blocks:
            directive = block.directive or ""
            if directive.startswith("skip"):
                if "because" not in directive:
                    report(block, "FAILED", "a skip without its reason")
                else:
                    report(block, "skipped", directive)
                previous_output = None
                continue
            if block.language == "text":
                prose = [line for line in block.prose.splitlines() if line.strip()]
                if len(prose) > 2 or any(line.startswith("#") for line in prose):
                    previous_output = None  # prose between: not that block's output
                if previous_output is None:
                    report(block, "shown", "an illustration, not the output of a block run here")
                    continue
                problem = check_output(block.text, previous_output)
                report(block, "FAILED" if problem else "output matches", problem)
                previous_output = None
                continue
            previous_output = None
            if block.language in ("cpp", "cmake"):
                source = re.match(r"excerpt of (\S+)", directive)
                if not source:
                    report(block, "FAILED", "a code fragment without '<!-- docs-test: excerpt of "
                                            "PATH -->' naming the compiled file it comes from")
                    continue
                problem = check_excerpt(block, source.group(1))
                report(block, "FAILED" if problem else f"excerpt of {source.group(1)}", problem)
                continue
            if block.language == "python":
                if directive.startswith("standalone"):
                    script = Path(tempfile.mkdtemp(dir=scratch)) / "block.py"
                    script.write_text(block.text)
                    status, printed = run(["/usr/bin/python3", str(script)], scratch, shell=False)
                    report(block, "FAILED" if status else "ran alone",
                           printed[-2000:] if status else None)
                else:
                    python.append(block)
                continue
            if block.language in ("sh", "json"):
                smaller = re.match(r'run "(.*)" because (.+)', directive, re.S)
                command = (smaller.group(1) if smaller else
                           block.text if block.language == "sh" else scene_command(block, scratch))
                status, printed = run("set -e\n" + command, scratch)
                fate = "ran smaller (" + smaller.group(2) + ")" if smaller else "ran"
                report(block, "FAILED" if status else fate, printed[-2000:] if status else None)
                previous_output = printed
                continue
            report(block, "FAILED", f"a block of language {block.language!r}, which this test "
                                    "cannot run: give it a language it runs, or text")
        if python:
            status, printed = python_page(python, scratch)
            for block in python:
                report(block, "FAILED" if status else "ran (with the page's other blocks)",
                       printed[-3000:] if status else None)
                if status:
                    break
    shutil.rmtree(scratch)
    # the documented commands write under build/ or where they are told, not into the checkout
    tree_after = untracked_changes()
    if tree_before is None:
        print("not a git checkout: whether the blocks wrote into the tree is not checked")
    elif tree_after != tree_before:
        failures.append("the blocks changed the checkout: " + ", ".join(
            sorted(set(tree_after) ^ set(tree_before))))
    print(", ".join(f"{n} {fate}" for fate, n in sorted(counts.items())))
    if failures:
        sys.exit("docs blocks that fail:\n" + "\n".join(failures))


if __name__ == "__main__":
    main()
