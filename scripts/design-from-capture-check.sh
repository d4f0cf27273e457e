#!/usr/bin/env bash
# Prints the full grid of issue 37's check (item 4) as Markdown: for every setup of the
# project's capture generator (noise 0.1 % to 5 %, white, coloured and quantised; random
# jerk from 1e2 to 1e7 rad/s^3; steps and reversals), with and without the reference
# column, the design chosen from one capture, its predicted RMS angle error, its error
# measured on a second capture of the same setup (another seed), the best error measured
# on that capture of the choice's grid (31 designs per order) among the designs meeting
# the constraints and over the whole grid, and the estimated noise and jerk over the
# generator's.
# The suite runs three of these setups on shorter captures:
# crates/angletrack/tests/design_from_capture.rs; the generator and the check are
# crates/angletrack/tests/support/capture_generator.rs.
# Usage: bash scripts/design-from-capture-check.sh [--write] [SAMPLES [GRID_POINTS]]
#   (defaults: 100000 samples, 10 s at 10 kHz; 31 designs per order). Deterministic.
#   --write: also replace the table in docs/guide/design-from-capture.md (between its
#     <!-- design-from-capture:begin ... --> and <!-- design-from-capture:end --> markers).
set -euo pipefail
cd "$(dirname "$0")/.."
page=docs/guide/design-from-capture.md

write=false
if [ "${1:-}" = "--write" ]; then
  write=true
  shift
fi

table=$(cargo run -q --release -p angletrack --example design_from_capture_check -- "${1:-100000}" "${2:-31}")
printf '%s\n' "$table"

if $write; then
  tmp=$(mktemp)
  awk -v table="$table" '
    /^<!-- design-from-capture:begin/ { print; print table; skip = 1; next }
    /^<!-- design-from-capture:end -->/ { skip = 0 }
    !skip { print }
  ' "$page" >"$tmp"
  mv "$tmp" "$page"
  echo "wrote the table into $page" >&2
fi
