#!/usr/bin/env bash
# The firmware test: every observer variant and the atan2 + PLL baselines on a Cortex-M4F
# (QEMU mps2-an386) and a Cortex-M0 (QEMU microbit), checked against the host within f32
# tolerance, with their instruction counts per update and code sizes; fails if a count is
# above its budget in tests/firmware/budgets.txt.
set -euo pipefail
source scripts/lib.sh
need_rust
need_debian_packages qemu-system-arm gcc libc6-dev binutils-arm-none-eabi
# Its own workspace, so the workspace-wide fmt and clippy of 10-rust.sh do not cover it.
(cd tests/firmware && cargo fmt --check && for target in thumbv7em-none-eabihf thumbv6m-none-eabi; do
  CARGO_TARGET_DIR="${FIRMWARE_TARGET_DIR:-$PWD/target}" cargo clippy --release -q --target "$target" -- -D warnings
done)
bash tests/firmware/run.sh
