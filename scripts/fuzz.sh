#!/usr/bin/env bash
# The fuzzers of tests/fuzz (docs/robustness.md): the cases of tests/fuzz/cases.json and seeded
# random inputs through the command line (the Release build, and the ASan + UBSan one when it is
# built) and through the Python module. Fails on any finding; the failing inputs are kept in
# build/fuzz-failures. FUZZ_SECONDS bounds each random run (20 s by default, as in CI), FUZZ_SEED
# seeds it (1). A longer run, with other inputs:
#   FUZZ_SECONDS=3600 FUZZ_SEED=$RANDOM bash scripts/fuzz.sh
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-20}
seed=${FUZZ_SEED:-1}
python=/usr/bin/python3

echo "== fuzz: the command line, Release (seed $seed, ${seconds} s)"
"$python" tests/fuzz/fuzz_cli.py --mimpact build/release/bin/mimpact --seconds "$seconds" \
  --seed "$seed"
if [ -x build/sanitize/bin/mimpact ]; then
  # other inputs than the Release run's (seed + 1): the two runs cover more together
  echo "== fuzz: the command line, ASan + UBSan (seed $((seed + 1)), ${seconds} s)"
  "$python" tests/fuzz/fuzz_cli.py --mimpact build/sanitize/bin/mimpact --sanitized \
    --seconds "$seconds" --seed "$((seed + 1))" --timeout 60 --memory-mb 6000 --slowdown 4
fi
echo "== fuzz: the Python module (seed $seed, ${seconds} s)"
PYTHONPATH=build/release/python "$python" tests/fuzz/fuzz_python.py --seconds "$seconds" \
  --seed "$seed"
