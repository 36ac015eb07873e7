#!/usr/bin/env python3
"""Draws docs/pictures/error_corpus.png: each run's estimate of its own error against its true
error over the error corpus (tests/data/error_corpus/corpus.json), from the rows the corpus test
prints (tests/packings/test_error_corpus.cpp).

    python3 scripts/error_corpus_figure.py [--build build/release] [--out docs/pictures/error_corpus.png]
"""
import argparse
import re
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROW = re.compile(r"^(?P<name>.+?, (?P<method>impulse steps|adaptive|compliant))\s+"
                 r"(?P<estimate>\S+)\s+(?P<true>\S+)\s+\S+\s+\S+$")
MARKERS = {"impulse steps": ("o", "tab:blue"), "adaptive": ("s", "tab:orange"),
           "compliant": ("^", "tab:green")}


def rows(build):
    test = f"{build}/tests/packings/test_error_corpus"
    printed = subprocess.run([test, "--gtest_filter=*Bounds*"], capture_output=True, text=True,
                             check=True).stdout
    for line in printed.splitlines():
        match = ROW.match(line)
        if match:
            yield match["name"], match["method"], float(match["estimate"]), float(match["true"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build/release")
    parser.add_argument("--out", default="docs/pictures/error_corpus.png")
    args = parser.parse_args()
    runs = list(rows(args.build))
    figure, axes = plt.subplots(figsize=(6.4, 5.4))
    for method, (marker, colour) in MARKERS.items():
        mine = [(t, e) for _, m, e, t in runs if m == method]
        axes.loglog([t for t, _ in mine], [e for _, e in mine], marker, color=colour,
                    label=f"{method} ({len(mine)} scenes)", markerfacecolor="none")
    low = min(min(t, e) for _, _, e, t in runs) / 3
    high = max(max(t, e) for _, _, e, t in runs) * 3
    axes.plot([low, high], [low, high], "k-", lw=1, label="estimate = true error")
    axes.plot([low, high], [10 * low, 10 * high], "k--", lw=1, label="estimate = 10 x true error")
    axes.set_xlim(low, high)
    axes.set_ylim(low, high)
    axes.set_xlabel("true error (worst body, of the striker's speed; against 1 000 x finer)")
    axes.set_ylabel("the run's estimate of its error")
    axes.set_title(f"The error corpus: {len(runs)} runs, chains and packings")
    axes.legend(loc="upper left", fontsize=8)
    axes.grid(True, which="major", alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)
    print(f"{args.out}: {len(runs)} runs")


if __name__ == "__main__":
    main()
