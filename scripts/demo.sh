#!/usr/bin/env bash
# Installs what is missing, builds the mimpact command line and runs the main job: chain C1
# of seed 000 (20 steel beads struck at 1 m/s) at delta_p = 1e-5. Prints the summary JSON
# (post-impact velocities, step count, impact duration, wall time) on stdout.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/packages.sh
ensure_packages "${BUILD_PACKAGES[@]}"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j2 --target mimpact >/dev/null
build/release/examples/cli/mimpact chain examples/scenes/c1.json --delta-p 1e-5 "$@"
