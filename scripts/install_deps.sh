#!/usr/bin/env bash
# Installs what cellmetry needs from Debian 12's packages, only if something is missing.
# Why each dependency is there: docs/dependencies.md.
set -euo pipefail
packages=(
  build-essential cmake ninja-build
  libeigen3-dev libceres-dev libnlopt-cxx-dev libnlopt-dev libyaml-cpp-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  libopencv-dev libopencv-contrib-dev libapriltag-dev libtbb-dev libboost-math-dev
  libsuitesparse-dev   # SuiteSparseQR: the sparse R factor behind identifiability and sigma
  opencv-doc   # OpenCV's ArUco/ChArUco and calibration photographs: real images the detector tests use
  liburdfdom-dev   # the URDF parser: the urdf robot model, and test_exports reading `export --format urdf`
  chromium   # tests only: test_report, test_report_browser open report.html headless (plots, layout)
  clang-14 libclang-rt-14-dev   # scripts/sanitize.sh, scripts/fuzz.sh: ASan, UBSan, libFuzzer
)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
