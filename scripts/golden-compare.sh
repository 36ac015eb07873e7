#!/usr/bin/env bash
# Compares every output of the golden scenes (scripts/golden_compare.py) between an earlier
# revision and this checkout: builds REV's `mimpact` in a worktree and this checkout's in
# build/release, runs both on each scene and prints, per scene, whether its files are the same
# to the bit (but for the measured wall time) or how far they part.
#   bash scripts/golden-compare.sh REV [--keep DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 1 ]] || { echo "usage: bash scripts/golden-compare.sh REV [--keep DIR]" >&2; exit 2; }
rev=$1
shift
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}"

old=build/golden/$(git rev-parse --short "$rev")
if [[ ! -d $old/source ]]; then
  mkdir -p "$old"
  git worktree add --detach "$old/source" "$rev" >/dev/null
fi
cmake -S "$old/source" -B "$old/build" -DCMAKE_BUILD_TYPE=Release -DMIMPACT_BUILD_BENCHMARKS=OFF \
  >/dev/null
cmake --build "$old/build" -j2 --target mimpact >/dev/null
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j2 --target mimpact >/dev/null
exec /usr/bin/python3 scripts/golden_compare.py "$old/build/bin/mimpact" build/release/bin/mimpact "$@"
