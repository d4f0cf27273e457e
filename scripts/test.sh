#!/usr/bin/env bash
# Runs every test of the project on a fresh machine: installs what is missing, then runs the
# steps in scripts/test.d/ in order (each one a self-contained shell script). Stops at the
# first failure. Usage: bash scripts/test.sh [STEP-NAME-SUBSTRING]
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
only="${1:-}"
start=$(date +%s)
fuzz_state=""
trap '[ -z "$fuzz_state" ] || { stop_fuzz_build "$fuzz_state"; rm -rf "$fuzz_state"; }' EXIT
source scripts/lib.sh
for step in scripts/test.d/*.sh; do
  case "$step" in *"$only"*) ;; *) continue ;; esac
  # The robustness step's fuzz build (both cores for minutes) starts beside the firmware
  # step, whose QEMU runs and link-time-optimised links leave a core idle; the robustness
  # step waits for it (scripts/fuzz-build.sh).
  if [ "$(basename "$step")" = 30-firmware.sh ] && [[ 40-robustness.sh == *"$only"* ]]; then
    fuzz_state=$(mktemp -d)
    export ANGLETRACK_FUZZ_BUILD="$fuzz_state"
    setsid bash scripts/fuzz-build.sh "$fuzz_state" &
  fi
  echo "=== $(basename "$step") ($(($(date +%s) - start)) s)"
  bash "$step"
done
echo "=== all test steps passed in $(($(date +%s) - start)) s"
