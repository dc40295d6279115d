#!/usr/bin/env bash
# Behaviour check for refactoring: runs every job, simulation and comparison under configs/ that
# finishes within a minute, in a scratch copy of configs/ and tests/data/, and keeps every file
# they write. Run it before a change and after, then compare the two:
#
#   bash scripts/regression.sh record /tmp/before          # with the old build
#   ... change the code, rebuild ...
#   bash scripts/regression.sh record /tmp/after
#   bash scripts/regression.sh compare /tmp/before /tmp/after
#
# `compare` lists every file that differs other than in timings (solver time, seconds, rates);
# it exits 1 if any does. A step that took longer than its limit is reported, not compared.
# `compare --tolerance 1e-6 BEFORE AFTER` lets numbers differ by that much relative (a change that
# swaps a numerical method for an equivalent one moves the last bits).
# The build is ./build (or $CELLMETRY_BUILD).
set -uo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
build=${CELLMETRY_BUILD:-$repo/build}
limit=${CELLMETRY_STEP_SECONDS:-60}

# One step a line: a name, then the cellmetry command line (run in the scratch tree).
steps() {
  cat <<'EOF'
sim_delta_sim          simulate configs/simulations/delta_uniform_125.yaml -o results/delta_sim
sim_delta_validation   simulate configs/simulations/delta_validation.yaml -o results/delta_validation
sim_delta_homing       simulate configs/simulations/delta_homing.yaml -o results/delta_homing_sim
sim_delta_images       simulate configs/simulations/delta_images.yaml -o results/delta_images
sim_delta_physics      simulate configs/simulations/delta_physics_base.yaml -o results/delta_physics
sim_ur3_images         simulate configs/simulations/ur3_apriltag_images.yaml -o results/ur3_apriltag_images
sim_ur3_physics        simulate configs/simulations/ur3_physics_base.yaml -o results/ur3_physics
sim_ur3_two_cameras    simulate configs/simulations/ur3_two_cameras.yaml -o results/ur3_two_cameras
run_vsb_sim_b          run configs/jobs/vsb_sim_b.yaml
run_vsb_exp_a          run configs/jobs/vsb_exp_a.yaml
run_vsb_exp_a_boards   run configs/jobs/vsb_exp_a_boards.yaml
import_vsb_exp_a_excerpt import configs/import/vsb_exp_a_excerpt.yaml -o results/vsb_exp_a_excerpt
run_vsb_exp_a_excerpt  run configs/jobs/vsb_exp_a_excerpt.yaml
run_delta_calibration  run configs/jobs/delta_calibration.yaml
home_delta             home configs/jobs/delta_homing.yaml
detect_delta           detect configs/jobs/delta_detect.yaml
run_delta_images       run configs/jobs/delta_calibration_images.yaml
detect_ur3             detect configs/jobs/ur3_apriltag_detect.yaml
run_ur3_images         run configs/jobs/ur3_apriltag_images.yaml
eval_ur3_images        evaluate results/ur3_apriltag_images_fit results/ur3_apriltag_images/truth.yaml
diagnose_vsb_sim_b     diagnose configs/jobs/vsb_sim_b_diagnose.yaml
diagnose_ur3           diagnose configs/jobs/ur3_diagnose.yaml
diagnose_delta         diagnose configs/jobs/delta_diagnose.yaml
diagnose_vsb_exp_a     diagnose configs/jobs/vsb_exp_a_diagnose.yaml
compare_table7         compare configs/compare/delta_table7.yaml --seeds 1
compare_markers        compare configs/compare/markers.yaml --seeds 1
sim_ur5e_ur3_cell      simulate configs/simulations/ur5e_ur3_cell.yaml -o results/ur5e_ur3_cell
run_ur5e_ur3_cell      run configs/jobs/ur5e_ur3_cell.yaml
eval_ur5e_ur3_cell     evaluate results/ur5e_ur3_cell_fit results/ur5e_ur3_cell/truth.yaml
compare_solvers_sim    compare configs/compare/solvers_serial_sim.yaml
compare_solvers_sim_b  compare configs/compare/solvers_vsb_sim_b.yaml
EOF
}

record() {
  local out=$1
  if [ -e "$out" ]; then
    echo "regression: $out exists; give a new folder" >&2
    exit 2
  fi
  mkdir -p "$out/tree/tests" "$out/logs"
  cp -r "$repo/configs" "$out/tree/configs"
  cp -r "$repo/tests/data" "$out/tree/tests/data"
  mkdir -p "$out/tree/results" "$out/tree/docs"
  export CELLMETRY_PLUGIN_PATH="$build/bin/plugins"
  while read -r name args; do
    [ -z "$name" ] && continue
    local start=$SECONDS
    (cd "$out/tree" && timeout "$limit" "$build/bin/cellmetry" --quiet $args \
        >"$out/logs/$name.out" 2>"$out/logs/$name.err")
    local rc=$?
    echo "$rc $((SECONDS - start))" >"$out/logs/$name.rc"
    if [ $rc -eq 124 ]; then
      echo "  $name: over ${limit} s, not compared"
    else
      echo "  $name: exit $rc, $((SECONDS - start)) s"
    fi
  done < <(steps)
}

case "${1:-}" in
  record) [ $# -eq 2 ] || { echo "usage: $0 record FOLDER" >&2; exit 2; }; record "$2" ;;
  compare)
    shift
    python3 "$repo/scripts/regression_compare.py" "$@" ;;
  *) echo "usage: $0 record FOLDER | compare BEFORE AFTER" >&2; exit 2 ;;
esac
