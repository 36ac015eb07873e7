#!/usr/bin/env bash
# Builds in Release and runs the benchmarks of bench/ (the figures of the README).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j2 --target bench_lzb bench_lemke bench_event_driven bench_packing >/dev/null
build/release/bench/bench_lzb "$@"
build/release/bench/bench_lemke "$@"
build/release/bench/bench_event_driven "$@"
build/release/bench/bench_packing "$@"
