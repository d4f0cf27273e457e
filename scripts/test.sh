#!/usr/bin/env bash
# Runs every test of the project on a fresh machine: installs what is missing, then runs the
# steps in scripts/test.d/ in order (each one a self-contained shell script). Stops at the
# first failure. Usage: bash scripts/test.sh [STEP-NAME-SUBSTRING]
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
only="${1:-}"
start=$(date +%s)
for step in scripts/test.d/*.sh; do
  case "$step" in *"$only"*) ;; *) continue ;; esac
  echo "=== $(basename "$step") ($(($(date +%s) - start)) s)"
  bash "$step"
done
echo "=== all test steps passed in $(($(date +%s) - start)) s"
