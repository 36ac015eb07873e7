#!/usr/bin/env bash
# Installs what is missing (Debian bookworm), builds everything in Release and runs every
# test; builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs
# them; installs the package and builds an application against it with find_package.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"

jobs=2
echo "== Release build, all tests"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j"$jobs"
ctest --test-dir build/release -j"$jobs" --output-on-failure

echo "== benchmarks, one quick pass (they must run; their figures come from scripts/bench.sh)"
for bench in bench_lzb bench_lemke; do
  build/release/bench/$bench --benchmark_min_time=0.001 >build/release/bench/$bench.log 2>&1 ||
    { cat build/release/bench/$bench.log; exit 1; }
done

echo "== ASan + UBSan build, unit tests"
cmake -S . -B build/sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMIMPACT_SANITIZE=ON \
  -DMIMPACT_BUILD_BENCHMARKS=OFF >/dev/null
unit_tests=(test_lemke test_lcp_file test_contact_law test_delassus test_lzb_impulse_integrator
            test_lzb_allocation test_pulse_analysis test_nesterenko test_kernel_model test_simulation_loop test_event_location
            test_lzb_impact_problem test_registered_plugins test_chain_scene)
cmake --build build/sanitize -j"$jobs" --target "${unit_tests[@]}"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/sanitize -j"$jobs" -L unit --output-on-failure

echo "== the kernel and its tests without plugins/"
cmake -S . -B build/kernel-only -DCMAKE_BUILD_TYPE=Release -DMIMPACT_BUILD_PLUGINS=OFF >/dev/null
cmake --build build/kernel-only -j"$jobs"
ctest --test-dir build/kernel-only -j"$jobs" --output-on-failure

echo "== installed package: find_package(mimpact) from an application"
rm -rf build/install build/linking
cmake --install build/release --prefix build/install >/dev/null
cmake -S examples/linking -B build/linking -DCMAKE_PREFIX_PATH="$PWD/build/install" >/dev/null
cmake --build build/linking -j"$jobs"
build/linking/two_balls
