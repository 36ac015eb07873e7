#!/usr/bin/env bash
# Installs what is missing, builds mimpact and runs one experiment of the papers end to end:
# Nakagawa's tapered chain (Nguyen & Brogliato 2011, section 4), at three restitutions. Prints its report
# (text and table) and leaves its figures in build/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/reproduce-paper.sh --only N --out build/demo --work build/demo/runs
