#!/usr/bin/env bash
# Installs what is missing, builds, and identifies the UR3 base frame on the bundled VSB sim_b
# recording (the 2020 paper's simulation B).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
./build/bin/cellmetry run configs/jobs/vsb_sim_b.yaml
