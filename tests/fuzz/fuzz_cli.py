#!/usr/bin/env python3
"""Fuzzes the `mimpact` command line: scene files (chains and packings), bead lists and LCP files.

Every input must end cleanly: an exit status of 0 with finite outputs, or 1 (2 for bad command
lines) with one clear message, within the time limit, without a sanitizer report, with the output
directory complete or absent and no file's content echoed. The inputs are

  1. the cases of tests/fuzz/cases.json, each with what must happen (refused with a message, or
     run), and how long it may take;
  2. mutations of the seeds in tests/fuzz/corpus/ and tests/data/lcp/: keys deleted, duplicated,
     renamed and retyped, numbers replaced by 0, -0, subnormals, 1e308, 1e999, huge integers,
     deep nesting, long strings, truncated files, open comments, byte-order marks, bad CSV rows,
     bead files elsewhere, LCP files with extreme entries.

The mutations follow a seeded random generator: the same --seed and --cases give the same
inputs. A failing input is kept in --failures (default build/fuzz-failures) to replay.

  python3 tests/fuzz/fuzz_cli.py --mimpact build/release/bin/mimpact --seconds 60
  python3 tests/fuzz/fuzz_cli.py --mimpact build/sanitize/bin/mimpact --cases 3000 --seed 7
"""
import argparse
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
SECRET = "MIMPACT-FUZZ-SECRET-7f3a"  # the content of a file no message may echo

# Numbers a mutation puts in place of another: the edges of double precision and of integers.
SPECIAL_NUMBERS = ["0", "-0", "-0.0", "5e-324", "2.2250738585072014e-308", "1e-300", "1e-162",
                   "1e-30", "1e308", "1.7976931348623157e308", "-1e308", "1e999", "-1e999",
                   "9223372036854775807", "9223372036854775808", "18446744073709551616",
                   "100000000000000000000000000000", "-1", "-2147483649", "2147483648", "1e8",
                   "1e9", "0.5", "3"]
SPECIAL_STRINGS = ["", "left", "right", "adaptive", "compliant", "auto", "asynchronous", "impulse-step",
                   "frozen", "open", "nan", "inf", "x" * 100_000, "\u00e9\u00e8", "\x01",
                   "/dev/zero", "../secret.csv", "beads.csv"]


class Failure(Exception):
    pass


# ---------------------------------------------------------------- mutations of JSON documents
class Duplicated:
    """An object whose key `key` is written twice (JSON text allows it, the reader must refuse)."""

    def __init__(self, items, key):
        self.items, self.key = items, key


class Raw:
    """A number written as it is (1e999, -0, 18446744073709551616)."""

    def __init__(self, text):
        self.text = text


def dump(value):
    if isinstance(value, Raw):
        return value.text
    if isinstance(value, Duplicated):
        parts = [json.dumps(k) + ": " + dump(v) for k, v in value.items.items()]
        parts.append(json.dumps(value.key) + ": " + dump(value.items[value.key]))
        return "{" + ", ".join(parts) + "}"
    if isinstance(value, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + dump(v) for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(dump(v) for v in value) + "]"
    return json.dumps(value)


def places(value, path=()):
    """Every (container, key) in the document, depth first."""
    found = []
    if isinstance(value, dict):
        for key in value:
            found.append((value, key, path + (key,)))
            found.extend(places(value[key], path + (key,)))
    elif isinstance(value, list):
        for index in range(len(value)):
            found.append((value, index, path + (index,)))
            found.extend(places(value[index], path + (index,)))
    return found


def nested(depth, inner):
    return Raw("[" * depth + inner + "]" * depth)


# Counts scale by at most 10: a hundred times more beads is a valid scene that runs for minutes
# (the compliant method on 800 beads against a wall: 280 s), not a bug to find.
COUNTS = ("count", "rows", "columns")


def mutate_value(rng, old, key):
    choice = rng.random()
    if isinstance(old, (int, float)) and not isinstance(old, bool) and choice < 0.5:
        if rng.random() < 0.5:
            return Raw(rng.choice(SPECIAL_NUMBERS))
        scale = 10.0 ** (1 if key in COUNTS else rng.randint(1, 3))
        return old * scale if rng.random() < 0.5 else old / scale
    if choice < 0.6:
        return Raw(rng.choice(SPECIAL_NUMBERS))
    if choice < 0.7:
        return rng.choice(SPECIAL_STRINGS)
    if choice < 0.8:
        return rng.choice([None, True, False, [], {}, [old, old], {"x": old}])
    if choice < 0.9:
        return nested(rng.choice([2, 70, 10_000, 100_000]), rng.choice(["1", "{}", "\"a\""]))
    return [old] * rng.choice([2, 3, 50])


def mutate_document(rng, document, text):
    """One to three structural mutations, or one of the text: the mutated file's text."""
    if rng.random() < 0.2:
        return mutate_text(rng, text)
    for _ in range(rng.randint(1, 3)):
        spots = places(document)
        if not spots:
            break
        container, key, _ = rng.choice(spots)
        action = rng.random()
        if isinstance(container, dict) and action < 0.15:
            del container[key]
        elif isinstance(container, dict) and action < 0.25:
            renamed = key[:-1] if rng.random() < 0.5 else key + "x"
            container[renamed] = container.pop(key)
        elif isinstance(container, dict) and action < 0.32:
            replacement = Duplicated(dict(container), key)
            if container is document:
                return dump(replacement)
            for parent, name, _ in places(document):
                if parent[name] is container:
                    parent[name] = replacement
                    break
        elif isinstance(container, dict) and action < 0.38:
            container[rng.choice(["unknown", "striker", "integrater", "x" * 2000])] = 1
        elif isinstance(container, list) and action < 0.3 and container:
            container.append(container[-1])
        else:
            container[key] = mutate_value(rng, container[key], key)
    return dump(document)


def mutate_text(rng, text):
    action = rng.randrange(6)
    if action == 0:
        return text[: rng.randrange(len(text))]
    if action == 1:
        at = rng.randrange(len(text))
        return text[:at] + "/*" + text[at:]
    if action == 2:
        return "\ufeff" + text
    if action == 3:
        at = rng.randrange(len(text))
        return text[:at] + chr(rng.randrange(1, 0x10ffff) if rng.random() < 0.3 else
                               rng.randrange(1, 128)) + text[at:]
    if action == 4:
        return text.replace("}", "", 1)
    return text + rng.choice(["}", "]", ",", "// end", "\0"])


# ---------------------------------------------------------------- bead lists and LCP files
def mutate_csv(rng, text):
    lines = text.splitlines()
    action = rng.randrange(9)
    if action == 0:
        return ""
    if action == 1:
        lines = lines[1:]
    elif action == 2:
        lines.append(rng.choice(["1,2", "1,2,3,4", "a,b,c", "nan,0,0.005", "inf,0,0.005",
                                 "0,0,-0.005", "0,0,0", "1e308,1e308,1e308", ",,", " , , ",
                                 "0x10,0,0.005", "1e999,0,0.005", "0,0,5e-324"]))
    elif action == 3:
        lines.insert(1, lines[1])
    elif action == 4:
        lines = lines + ["%d,0,0.005" % (0.02 * (k + 2)) for k in range(rng.choice([10, 10_000]))]
    elif action == 5:
        return "\ufeff" + text.replace("\n", "\r\n")
    elif action == 6:
        lines[0] = rng.choice(["x,y", "y,x,radius", "x,y,radius,extra", "X,Y,R", ""])
    elif action == 7:
        return text + "\0\0\0"
    else:
        lines = [lines[0]] + ["0.%d,0,0.005" % k for k in range(rng.choice([2, 500]))]
    return "\n".join(lines) + "\n"


def mutate_lcp(rng, text):
    words = text.split()
    if rng.random() < 0.3:
        n = rng.choice([0, 1, 2, 3, 10, 10000, 10001, -1])
        entries = [rng.choice(["1", "-1", "0", "1e-300", "1e300", "-1e300", "nan", "inf",
                               "5e-324", "1e308", "-1e308", "2"]) for _ in range(
                                   min(max(n, 0), 10) ** 2 + min(max(n, 0), 10))]
        return " ".join([str(n), "0", str(n), str(n), str(n), str(n)] + entries) + "\n"
    for _ in range(rng.randint(1, 4)):
        if not words:
            break
        at = rng.randrange(len(words))
        action = rng.random()
        if action < 0.6:
            words[at] = rng.choice(["1e-300", "1e300", "-1e300", "nan", "-inf", "1e999", "0",
                                    "-0", "5e-324", "x", "1e308", "-1e308", "10000",
                                    "99999999999999999999"])
        elif action < 0.8:
            del words[at]
        else:
            words = words[:at]
    return " ".join(words) + "\n"


# ---------------------------------------------------------------- running one input
def limit_memory(megabytes):
    def apply():
        size = megabytes * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (size, size))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def finite_numbers(value, path="summary"):
    """Raises Failure at the first number that is not finite, or a null inside an array."""
    if isinstance(value, float) and not math.isfinite(value):
        raise Failure(f"non-finite output: {path} = {value}")
    if isinstance(value, dict):
        for key, item in value.items():
            finite_numbers(item, f"{path}.{key}")
    if isinstance(value, list):
        for index, item in enumerate(value):
            if item is None:
                raise Failure(f"non-finite output: {path}[{index}] = null")
            finite_numbers(item, f"{path}[{index}]")


def check_csv(path):
    for number, line in enumerate(path.read_text().splitlines()[1:], start=2):
        for cell in line.split(","):
            if not math.isfinite(float(cell)):
                raise Failure(f"non-finite output: {path.name} line {number}: {cell}")


class Runner:
    def __init__(self, mimpact, timeout, memory_mb, sanitized, slowdown=1.0):
        self.mimpact, self.timeout, self.memory_mb = mimpact, timeout, memory_mb
        self.slowdown = slowdown
        self.environment = dict(os.environ)
        if sanitized:  # ASan reserves terabytes of address space: limit its heap instead
            self.environment["ASAN_OPTIONS"] = (
                f"detect_leaks=1:allocator_may_return_null=1:hard_rss_limit_mb={memory_mb}:"
                "abort_on_error=1")
            self.environment["UBSAN_OPTIONS"] = "print_stacktrace=1:halt_on_error=1"
        self.sanitized = sanitized

    def run(self, work, command, arguments, expect=None, max_seconds=None, out=True,
            existing_output=False):
        """Runs `mimpact COMMAND ARGUMENTS` in `work`; raises Failure with what went wrong."""
        out_dir = work / "out"
        if existing_output:
            out_dir.mkdir(exist_ok=True)
            (out_dir / "summary.json").write_text("{\"old\": true}\n")
            (out_dir / "velocities.csv").write_text("old\n")
        full = [self.mimpact, command] + arguments
        if out and command != "lcp":
            full += ["--out", str(out_dir), "--quiet"]
        limit = max_seconds * self.slowdown if max_seconds is not None else self.timeout
        start = time.monotonic()
        try:
            done = subprocess.run(full, cwd=work, capture_output=True, timeout=limit + 5,
                                  env=self.environment,
                                  preexec_fn=None if self.sanitized else
                                  limit_memory(self.memory_mb))
        except subprocess.TimeoutExpired:
            raise Failure(f"run past its limit: still running after {limit + 5:g} s")
        seconds = time.monotonic() - start
        stderr = done.stderr.decode(errors="replace")
        stdout = done.stdout.decode(errors="replace")
        if done.returncode < 0 or done.returncode > 2:
            raise Failure(f"crash: exit status {done.returncode}: {stderr[-300:]}")
        if re.search(r"runtime error:|AddressSanitizer|LeakSanitizer", stderr):
            raise Failure("sanitizer report: " + stderr[:300])
        if seconds > limit:
            raise Failure(f"run past its limit: {seconds:.1f} s, allowed {limit:g} s")
        if "out of memory" in stderr or "bad_alloc" in stderr:
            raise Failure("exhausted memory: " + stderr[:200])
        if SECRET in stderr or SECRET in stdout:
            raise Failure("echoed a file's content: " + stderr[:200])
        if re.search(r"json\.exception|Unable to cast|basic_string|std::|what\(\)", stderr):
            raise Failure("a library's raw message: " + stderr[:200])
        if any(len(line) > 1000 for line in stderr.splitlines()):
            raise Failure("a message over 1000 characters: " + stderr[:200])
        leftovers = [p.name for p in work.iterdir() if "partial" in p.name]
        if leftovers:
            raise Failure(f"left {leftovers} beside the output")
        if done.returncode != 0:
            if not stderr.strip():
                raise Failure("failed without a message")
            if out and out_dir.exists() and not existing_output:
                raise Failure("failed but left an output directory")
            if existing_output and (out_dir / "summary.json").read_text() != "{\"old\": true}\n":
                raise Failure("failed but changed the existing output directory")
        else:
            try:
                self.check_outputs(command, stdout,
                                   out_dir if out and command != "lcp" else None)
            except (ValueError, KeyError, OSError) as error:
                raise Failure(f"unreadable output: {error!r}")
        if expect is not None:
            expect(done.returncode, stderr, stdout, seconds)
        return done.returncode, stderr

    @staticmethod
    def check_outputs(command, stdout, out_dir):
        if command == "lcp":
            result = json.loads(stdout)
            if result["status"] == "solved":
                finite_numbers(result)
            return
        if out_dir is None:
            finite_numbers(json.loads(stdout))
            return
        names = sorted(p.name for p in out_dir.iterdir())
        if "summary.json" not in names:
            raise Failure(f"succeeded without summary.json: {names}")
        if (out_dir / "velocities.csv").exists() and \
                (out_dir / "velocities.csv").read_text() == "old\n":
            raise Failure("an old run's velocities.csv beside the new summary.json")
        finite_numbers(json.loads((out_dir / "summary.json").read_text()))
        for name in names:
            if name.endswith(".csv"):
                check_csv(out_dir / name)


# ---------------------------------------------------------------- the inputs
def load_seed(path):
    text = "\n".join(line for line in path.read_text().splitlines()
                     if not line.lstrip().startswith("//"))
    return json.loads(text), text


def write_inputs(work, case_files):
    for name, text in case_files.items():
        target = work / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(text, bytes):
            target.write_bytes(text)
        else:
            target.write_text(text, encoding="utf-8", errors="surrogatepass")


def generated(recipe):
    """The text of a generated case (cases.json "generate")."""
    kind, _, argument = recipe.partition(":")
    if kind == "nested":  # nested:DEPTH:FIELD: C1 with FIELD's value DEPTH arrays deep
        depth, field = argument.split(":")
        document, _ = load_seed(HERE / "corpus" / "chain" / "c1_impulse_steps.json")
        for container, key, _ in places(document):
            if key == field:
                container[key] = nested(int(depth), json.dumps(container[key]))
                return dump(document)
    if kind == "long_side":  # long_side:N: C1 with a striker's side N characters long
        document, _ = load_seed(HERE / "corpus" / "chain" / "c1_impulse_steps.json")
        document["strikers"][0]["side"] = "l" * int(argument)
        return dump(document)
    if kind == "bead_row":  # bead_row:N:D: N touching beads of radius 5 mm along x, in D dims
        count, dimension = (int(a) for a in argument.split(":"))
        header = "x,y,radius" if dimension == 2 else "x,y,z,radius"
        zeros = ",0" * (dimension - 1)
        return header + "\n" + "".join(f"{0.01 * i!r}{zeros},0.005\n" for i in range(count))
    if kind == "ring":  # ring:N: a bead of radius 1 m ringed by N touching beads pi / N wide
        count = int(argument)
        small = math.pi / count * 0.999
        rows = ["x,y,radius", "0,0,1.0"]
        for k in range(count):
            angle = 2.0 * math.pi * k / count
            rows.append(f"{(1.0 + small) * math.cos(angle)!r},"
                        f"{(1.0 + small) * math.sin(angle)!r},{small!r}")
        return "\n".join(rows) + "\n"
    raise ValueError(f"unknown recipe {recipe!r}")


def case_expectation(case):
    def expect(status, stderr, stdout, seconds):
        wanted = case.get("status", 1)
        if status != wanted:
            raise Failure(f"exit status {status}, expected {wanted}: {stderr[:300]}")
        for fragment in case.get("message", []):
            if fragment not in stderr:
                raise Failure(f"message lacks {fragment!r}: {stderr[:400]}")
        for fragment in case.get("stdout", []):
            if fragment not in stdout:
                raise Failure(f"output lacks {fragment!r}: {stdout[:400]}")
    return expect


def run_case(runner, case, work):
    files = {}
    for name, content in case.get("files", {}).items():
        if isinstance(content, dict) and "generate" in content:
            files[name] = generated(content["generate"])
        elif isinstance(content, (dict, list)):
            files[name] = json.dumps(content)
        else:
            files[name] = content.replace("$SECRET", SECRET)
    for name, source in case.get("copy", {}).items():
        files[name] = (SOURCE / source).read_text()
    write_inputs(work, files)
    arguments = [a.replace("$WORK", str(work)) for a in case["arguments"]]
    runner.run(work, case["command"], arguments, expect=case_expectation(case),
               max_seconds=case.get("seconds", 1.0), out=case.get("out", True),
               existing_output=case.get("existing_output", False))


def random_input(rng, seeds):
    kind = rng.choice(["chain", "chain", "packing", "packing", "csv", "lcp"])
    if kind == "lcp":
        seed = rng.choice(seeds["lcp"])
        return "lcp", {"problem.dat": mutate_lcp(rng, seed.read_text())}, ["problem.dat"]
    files = {"secret.csv": f"x,y,radius\n{SECRET},0,0.005\n"}
    if kind == "csv":
        document, text = load_seed(HERE / "corpus" / "packing" / "bead_list.json")
        csv = (HERE / "corpus" / "packing" / "beads.csv").read_text()
        if rng.random() < 0.3:
            document["beads"]["file"] = rng.choice(
                ["/dev/zero", "secret.csv", "../secret.csv", "", ".", "missing.csv",
                 "/etc/hostname", "sub/../beads.csv", "sub"])
        files.update({"scenes/scene.json": dump(document), "scenes/beads.csv":
                      mutate_csv(rng, csv), "scenes/sub/x": "", "secret.csv":
                      f"x,y,radius\n{SECRET},0,0.005\n"})
        return "packing", files, ["scenes/scene.json"]
    seed = rng.choice(seeds[kind])
    document, text = load_seed(seed)
    files["scenes/scene.json"] = mutate_document(rng, document, text)
    files["scenes/beads.csv"] = (HERE / "corpus" / "packing" / "beads.csv").read_text()
    arguments = ["scenes/scene.json"]
    if rng.random() < 0.1:
        arguments += ["--delta-p", rng.choice(["1e-6", "1e-12", "0", "nan", "1e999", "-1",
                                                "1e300"])]
    if rng.random() < 0.1:
        arguments += ["--accuracy", rng.choice(["1e-3", "1e-5", "0", "nan", "1", "-1e-4",
                                                 "1e300"])]
    if rng.random() < 0.05:
        arguments += ["--no-error-estimate"]
    if kind == "chain" and rng.random() < 0.05:
        arguments += ["--tolerance", rng.choice(["1e-3", "0", "nan", "1e-20"])]
    return kind, files, arguments


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mimpact", required=True, help="the mimpact executable")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--cases", type=int, default=0, help="random inputs (0: until --seconds)")
    parser.add_argument("--seconds", type=float, default=60.0, help="time for random inputs")
    parser.add_argument("--timeout", type=float, default=20.0, help="s a random input may run")
    parser.add_argument("--memory-mb", type=int, default=3000, help="memory a run may take")
    parser.add_argument("--sanitized", action="store_true",
                        help="the executable is built with ASan+UBSan")
    parser.add_argument("--slowdown", type=float, default=1.0,
                        help="how much slower the executable runs (the cases' limits grow)")
    parser.add_argument("--skip-cases", action="store_true", help="random inputs only")
    parser.add_argument("--failures", default=str(SOURCE / "build" / "fuzz-failures"))
    arguments = parser.parse_args()
    mimpact = str(Path(arguments.mimpact).resolve())
    runner = Runner(mimpact, arguments.timeout, arguments.memory_mb, arguments.sanitized,
                    arguments.slowdown)
    # a random input runs within 1 GB and half its time where the command can be told so
    # (--max-memory, --max-seconds): a run stopped there ends cleanly, and is counted
    chain_help = subprocess.run([mimpact, "chain", "--help"], capture_output=True,
                                text=True).stdout
    limits = ["--max-memory", "1"] if "max-memory" in chain_help else []
    if "max-seconds" in chain_help:
        limits += ["--max-seconds", f"{arguments.timeout / 2:g}"]
    stopped = 0  # random inputs stopped by --max-seconds
    failures_dir = Path(arguments.failures)
    counts = {}

    def record(kind, name, message, files=None, command_line=None):
        key = message.split(":")[0]
        counts[key] = counts.get(key, 0) + 1
        print(f"FAIL {kind} {name}: {message}", flush=True)
        if files is not None:
            target = failures_dir / name
            shutil.rmtree(target, ignore_errors=True)
            write_inputs(target, files)
            (target / "command").write_text(" ".join(command_line) + "\n")

    total = 0
    if not arguments.skip_cases:
        cases = json.loads((HERE / "cases.json").read_text())["cli"]
        for case in cases:
            total += 1
            with tempfile.TemporaryDirectory(prefix="mimpact-fuzz-") as scratch:
                try:
                    run_case(runner, case, Path(scratch))
                except Failure as failure:
                    record("case", case["name"], str(failure))
        print(f"{len(cases)} cases of cases.json: {sum(counts.values())} failed", flush=True)

    rng = random.Random(arguments.seed)
    seeds = {"chain": sorted((HERE / "corpus" / "chain").glob("*.json")),
             "packing": sorted((HERE / "corpus" / "packing").glob("*.json")),
             "lcp": sorted((SOURCE / "tests" / "data" / "lcp").glob("lcp_*.dat"))}
    start = time.monotonic()
    random_count = 0
    slowest = []  # (seconds, input): where the time went
    while (random_count < arguments.cases if arguments.cases else
           time.monotonic() - start < arguments.seconds):
        random_count += 1
        total += 1
        command, files, command_arguments = random_input(rng, seeds)
        if command != "lcp":
            command_arguments = command_arguments + limits
        existing = rng.random() < 0.1
        with tempfile.TemporaryDirectory(prefix="mimpact-fuzz-") as scratch:
            work = Path(scratch)
            write_inputs(work, files)
            began = time.monotonic()
            try:
                status, stderr = runner.run(work, command, command_arguments,
                                            existing_output=existing)
                stopped += status == 1 and "(--max-seconds)" in stderr
            except Failure as failure:
                record("input", f"seed{arguments.seed}-{random_count}", str(failure), files,
                       ["mimpact", command] + command_arguments)
            slowest = sorted(slowest + [(time.monotonic() - began, random_count)])[-3:]
    failed = sum(counts.values())
    print(f"{random_count} random inputs (seed {arguments.seed}) in "
          f"{time.monotonic() - start:.0f} s; {total} in all, {failed} failed")
    for kind, count in sorted(counts.items()):
        print(f"  {count:5d}  {kind}")
    if stopped:
        print(f"{stopped} random inputs stopped cleanly at --max-seconds (long runs, not failures)")
    if slowest:
        print("slowest inputs: " + ", ".join(f"seed{arguments.seed}-{n} {t:.1f} s"
                                              for t, n in reversed(slowest)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
