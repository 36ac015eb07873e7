#!/usr/bin/env bash
# Installs what is missing, builds the work-precision benchmark in Release and writes
# docs/performance.md and docs/performance/*.png from two runs of it. About ten minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}" python3-matplotlib python3-numpy
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j2 --target bench_work_precision >/dev/null
# Debian's Python, which python3-matplotlib provides for
/usr/bin/python3 bench/work_precision.py --bench build/release/bench/bench_work_precision "$@"
