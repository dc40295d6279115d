#!/usr/bin/env bash
# Configures and builds cellmetry (Release) into ./build (or $CELLMETRY_BUILD). Uses ccache when
# the machine has it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${CELLMETRY_BUILD:-build}
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
