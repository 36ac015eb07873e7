#!/usr/bin/env bash
# Compares the LZB and packing benchmarks of an earlier revision with this checkout's, run in
# turn in one session (this machine's timings drift by tens of per cent between minutes, so a
# comparison is only fair old-new-old-new): builds REV's bench_lzb and bench_packing in a
# worktree, this checkout's in build/release, then runs them ROUNDS times each, alternately,
# and prints per benchmark every time and the ratio of the best (new / old).
#   bash scripts/bench-compare.sh REV [ROUNDS]      (ROUNDS: 3 by default; about 2 min a round)
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 1 ]] || { echo "usage: bash scripts/bench-compare.sh REV [ROUNDS]" >&2; exit 2; }
rev=$1
rounds=${2:-3}
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"

old=build/bench-compare/$(git rev-parse --short "$rev")
if [[ ! -d $old/source ]]; then
  mkdir -p "$old"
  git worktree add --detach "$old/source" "$rev" >/dev/null
fi
targets=(bench_lzb bench_packing)
cmake -S "$old/source" -B "$old/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$old/build" -j2 --target "${targets[@]}" >/dev/null
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j2 --target "${targets[@]}" >/dev/null

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
lzb_filter='C1|ChainSteps|ImpactSetup|ChainLength(Adaptive|Compliant)/10000$'
packing_filter='/(16|32)/'
for round in $(seq "$rounds"); do
  for side in old new; do
    dir=$([[ $side == old ]] && echo "$old/build/bench" || echo build/release/bench)
    echo "round $round: $side" >&2
    "$dir/bench_lzb" --benchmark_filter="$lzb_filter" --benchmark_min_time=0.5 \
      --benchmark_format=json >"$out/${side}_lzb_$round.json" 2>/dev/null
    "$dir/bench_packing" --benchmark_filter="$packing_filter" \
      --benchmark_format=json >"$out/${side}_packing_$round.json" 2>/dev/null
  done
done

/usr/bin/python3 - "$out" "$rev" <<'EOF'
import collections, glob, json, os, sys
out, rev = sys.argv[1], sys.argv[2]
unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
times = collections.defaultdict(lambda: collections.defaultdict(list))
for path in sorted(glob.glob(os.path.join(out, "*.json"))):
    side = os.path.basename(path).split("_")[0]
    for bench in json.load(open(path))["benchmarks"]:
        times[bench["name"]][side].append(bench["real_time"] * unit[bench["time_unit"]])
print(f"| benchmark | {rev} (ms) | this checkout (ms) | new / old, best of each |")
print("|---|---|---|---|")
for name, sides in times.items():
    old, new = sides["old"], sides["new"]
    print(f"| {name.replace('/iterations:1', '')} | {' '.join(f'{t:.3g}' for t in old)} | "
          f"{' '.join(f'{t:.3g}' for t in new)} | {min(new) / min(old):.3f} |")
EOF
