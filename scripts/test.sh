#!/usr/bin/env bash
# Installs what is missing (the tests' data too: opencv-doc's photographs), builds, and runs the
# whole test suite. A test that skips says so by name in ctest's summary.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
echo "== installed (+${SECONDS} s)"
bash scripts/build.sh
echo "== built (+${SECONDS} s)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
