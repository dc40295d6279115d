#!/usr/bin/env bash
# Runs the libFuzzer harnesses (fuzz/, docs/reliability.md) for a bounded time each, from their
# seed corpus (fuzz/corpus/<harness>/; new inputs go to build-asan/fuzz/corpus/<harness>/, the
# repository's corpus is left as it is).
#   bash scripts/fuzz.sh SECONDS [HARNESS...]     # default: every harness
# Harnesses run side by side, one per core. A finding (crash, sanitizer report, an exception other
# than InputError, a hang over 10 s, more than 2 GB) fails with exit 1 and leaves the input in
# build-asan/fuzz/artifacts/. Reproduce with
#   build-asan/bin/<harness> <input>
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:?usage: scripts/fuzz.sh SECONDS [HARNESS...]}
shift
harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
  harnesses=(fuzz_recording fuzz_job fuzz_robot_config fuzz_detections fuzz_image fuzz_json_lines
             fuzz_import fuzz_yaml fuzz_camera_file fuzz_compensation_targets fuzz_result fuzz_urdf)
fi
build=${CELLMETRY_ASAN_BUILD:-build-asan}
bash scripts/sanitize.sh --configure
cmake --build "$build" -j"$(nproc)" --target "${harnesses[@]}"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
mkdir -p "$build/fuzz/artifacts" "$build/fuzz/logs"
# One harness: its libFuzzer run, output (less the per-input chatter) to its log, exit status to
# its .status file. libFuzzer uses one core, so harnesses run side by side, one per core.
fuzz_one() {
  local h=$1 corpus="$build/fuzz/corpus/$1" log="$build/fuzz/logs/$1.log"
  mkdir -p "$corpus"
  rm -f "$log.status"
  set +e
  "$build/bin/$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$build/fuzz/artifacts/$h-" -print_final_stats=1 \
    "$corpus" "fuzz/corpus/$h" 2>&1 | grep -v -E '^(#[0-9]+\s+(NEW|REDUCE|pulse)|\s+NEW_FUNC)' |
    sed '/Recommended dictionary/,/End of recommended dictionary/d' >"$log"
  echo "${PIPESTATUS[0]}" >"$log.status"
}
for h in "${harnesses[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  echo "== $h: ${seconds} s"
  fuzz_one "$h" &
done
wait
failed=0
for h in "${harnesses[@]}"; do
  log="$build/fuzz/logs/$h.log"
  echo "== $h"
  cat "$log"
  status=$(cat "$log.status" 2>/dev/null || echo "no status")
  if [ "$status" != 0 ]; then
    echo "fuzz.sh: $h found a problem (exit $status); see $build/fuzz/artifacts/" >&2
    failed=1
  fi
done
exit "$failed"
