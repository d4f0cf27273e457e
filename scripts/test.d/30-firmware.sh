#!/usr/bin/env bash
# The firmware test: every observer on a Cortex-M4F under QEMU (mps2-an386), checked against
# the host within f32 tolerance, with its instruction count per update and its code size.
set -euo pipefail
source scripts/lib.sh
need_rust
need_debian_packages qemu-system-arm gcc libc6-dev binutils-arm-none-eabi
# Its own workspace, so the workspace-wide fmt and clippy of 10-rust.sh do not cover it.
(cd tests/firmware && cargo fmt --check && CARGO_TARGET_DIR="${FIRMWARE_TARGET_DIR:-$PWD/target}" cargo clippy --release -q -- -D warnings)
bash tests/firmware/run.sh
