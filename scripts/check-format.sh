#!/usr/bin/env bash
# Fails when a tracked C++ file is not as .clang-format (Google style, 100 columns) writes it.
# `git ls-files '*.cpp' '*.hpp' | xargs clang-format -i` formats the tree.
set -euo pipefail
cd "$(dirname "$0")/.."
git ls-files -z '*.cpp' '*.hpp' | xargs -0 clang-format --dry-run --Werror
echo "every C++ file is formatted"
