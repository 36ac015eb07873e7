#!/usr/bin/python3
"""Checks the sizes a reader can hold (issue 45, item 5) in the library's own code: every
source file at most 500 lines, every function (and lambda) at most 80 lines from its first line
to its closing brace, at most 6 parameters, every class or struct at most 20 data members.
Functions, parameters and members are read by Universal Ctags (Debian's `universal-ctags`).
The parameters of the Python bindings (python/src) are not counted: pybind11 reads a binding's
Python signature, its keyword names and defaults, off the C++ function's parameters, so there
they are the Python API (Simulation(system, integrator=..., ...)), not a C++ caller's burden.

    /usr/bin/python3 scripts/check_sizes.py [--report]     (--report: the largest of each)

Exits 1 naming every file, function and class beyond its limit.
"""
import argparse
import collections
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ("common", "numerics", "kernel", "plugins", "granular", "chains", "packings",
          "analysis", "apps", "python/src")
MAX_FILE_LINES, MAX_FUNCTION_LINES, MAX_PARAMETERS, MAX_MEMBERS = 500, 80, 6, 20
SIGNATURES_OF_PYTHON = "python/src/"  # their parameters are the Python keyword signature


def sources():
    listed = subprocess.run(["git", "ls-files", *LAYERS], cwd=ROOT, capture_output=True,
                            text=True, check=True).stdout.split()
    return [path for path in listed if path.endswith((".cpp", ".hpp"))]


def tags(paths):
    out = subprocess.run(["ctags", "--output-format=json", "--fields=+neS", "--kinds-c++=fm",
                          "--language-force=c++", "-f", "-", *paths], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def parameter_count(signature):
    inner = signature.strip()[1:signature.rfind(")")].strip()
    if inner in ("", "void"):
        return 0
    depth, count = 0, 1
    for character in inner:
        depth += character in "<([{"
        depth -= character in ">)]}"
        count += character == "," and depth == 0
    return count


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--report", action="store_true", help="print the largest of each kind")
    args = parser.parse_args()
    paths = sources()
    files = {path: len((ROOT / path).read_text().splitlines()) for path in paths}
    functions, members = [], collections.Counter()
    for tag in tags(paths):
        where = f"{tag['path']}:{tag['line']}"
        if tag["kind"] == "function":
            name = tag.get("scope", "") + "::" + tag["name"]
            functions.append((tag.get("end", tag["line"]) - tag["line"] + 1,
                              parameter_count(tag.get("signature", "()")), name, where))
        elif tag["kind"] == "member" and tag.get("scopeKind") in ("class", "struct"):
            members[(tag["scope"], tag["path"])] += 1
    failures = [f"{path}: {lines} lines (at most {MAX_FILE_LINES})"
                for path, lines in files.items() if lines > MAX_FILE_LINES]
    failures += [f"{where}: {name}: {lines} lines (at most {MAX_FUNCTION_LINES})"
                 for lines, _, name, where in functions if lines > MAX_FUNCTION_LINES]
    failures += [f"{where}: {name}: {count} parameters (at most {MAX_PARAMETERS})"
                 for _, count, name, where in functions
                 if count > MAX_PARAMETERS and not where.startswith(SIGNATURES_OF_PYTHON)]
    failures += [f"{path}: {scope}: {count} data members (at most {MAX_MEMBERS})"
                 for (scope, path), count in members.items() if count > MAX_MEMBERS]
    if args.report:
        print("largest files:", *sorted(files.items(), key=lambda f: -f[1])[:5], sep="\n  ")
        print("longest functions:", *(f"{l} {n} {w}" for l, _, n, w in sorted(functions)[-5:]),
              sep="\n  ")
        print("most data members:", *members.most_common(5), sep="\n  ")
    print(*failures, sep="\n") if failures else None
    print(f"sizes: {len(files)} files, {len(functions)} functions, {len(members)} classes; "
          f"{len(failures)} beyond their limits")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
