#!/usr/bin/env bash
# Installs what is missing (Debian bookworm), builds everything in Release and runs every
# test; builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs
# them; installs the package, moves it to another prefix and builds applications against it.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"

jobs=2
echo "== the repository stands alone"
bash scripts/check-standalone.sh
echo "== format"
bash scripts/check-format.sh
echo "== structure: no include cycle in a layer, no other layer's internal header (issue 45)"
/usr/bin/python3 scripts/check_includes.py
echo "== sizes a reader can hold (issue 45): files, functions, parameters, data members"
/usr/bin/python3 scripts/check_sizes.py

echo "== Release build, all tests"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DMIMPACT_WERROR=ON >/dev/null
cmake --build build/release -j"$jobs"
ctest --test-dir build/release -j"$jobs" --output-on-failure

echo "== benchmarks, one quick pass (they must run; their figures come from scripts/bench.sh)"
quick_pass=("bench_lzb" "bench_lemke"
            "bench_work_precision --benchmark_filter=WorkPrecision/C1/(lzb/1e-02|compliant/1e-03)/|ChainLength/.*/10/"
            "bench_packing --benchmark_filter=/16/"
            "bench_packing_peers --benchmark_filter=^BM_PackingLammps/0/0/"
            "bench_accuracy --benchmark_filter=C1.e=1,.adaptive/1e-04")
for bench in "${quick_pass[@]}"; do
  log=build/release/bench/${bench%% *}.log
  build/release/bench/$bench --benchmark_min_time=0.001 >"$log" 2>&1 || { cat "$log"; exit 1; }
done

echo "== ASan + UBSan build, unit tests"
cmake -S . -B build/sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMIMPACT_SANITIZE=ON -DMIMPACT_WERROR=ON \
  -DMIMPACT_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/sanitize -j"$jobs" --target mimpact_unit_tests mimpact
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/sanitize -j"$jobs" -L unit --output-on-failure

echo "== fuzzers, seeded and bounded: the command line (Release, ASan + UBSan), the Python module"
bash scripts/fuzz.sh

echo "== the kernel and its tests without plugins/"
cmake -S . -B build/kernel-only -DCMAKE_BUILD_TYPE=Release -DMIMPACT_BUILD_PLUGINS=OFF -DMIMPACT_WERROR=ON >/dev/null
cmake --build build/kernel-only -j"$jobs"
ctest --test-dir build/kernel-only -j"$jobs" --output-on-failure

echo "== installed package, moved to another prefix: find_package(mimpact) from applications"
rm -rf build/install build/install-moved build/linking
cmake --install build/release --prefix build/install >/dev/null
# the package must find its own dependencies wherever it lands (no absolute path inside)
mv build/install build/install-moved
cmake -S examples/linking -B build/linking -DCMAKE_PREFIX_PATH="$PWD/build/install-moved" >/dev/null
cmake --build build/linking -j"$jobs"
build/linking/two_balls
build/linking/chain_from_scene >/dev/null && echo "chain_from_scene: momentum conserved"
site=$(find build/install-moved -name _mimpact*.so -printf '%h\n' | head -1)
PYTHONPATH="$site/.." /usr/bin/python3 -c "
import mimpact
r = mimpact.run_chain('examples/scenes/c1.json')
print('installed Python module: C1 last bead leaves at %.6f m/s' % r.post_impact_velocities[-1])"
