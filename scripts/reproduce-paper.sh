#!/usr/bin/env bash
# Installs what is missing, builds mimpact, runs every experiment of docs/experiments.md and writes
# docs/results/ (figures and README.md) from what the runs wrote. About thirty seconds.
#   bash scripts/reproduce-paper.sh [--only C|N|M|scaling|J|S|W]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" python3-matplotlib python3-numpy
echo "building the command line and the Python module into build/release" \
     "(about three minutes the first time on two cores)" >&2
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
# the Python module too: the README's Python example runs right after the demo
cmake --build build/release -j2 --target mimpact _mimpact >&2
# Debian's Python, which python3-matplotlib provides for
/usr/bin/python3 scripts/reproduce_paper.py --mimpact build/release/bin/mimpact "$@"
