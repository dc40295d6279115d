#!/usr/bin/env bash
# Configures (CMakePresets.json's "release") and builds cellmetry into ./build (or
# $CELLMETRY_BUILD). Uses ccache when the machine has it; CELLMETRY_WERROR=1 (CI) makes every
# compiler warning an error.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${CELLMETRY_BUILD:-build}
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
launcher+=("-DCMAKE_COMPILE_WARNING_AS_ERROR=$([ -n "${CELLMETRY_WERROR:-}" ] && echo ON || echo OFF)")
cmake --preset release -B "$build" "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
