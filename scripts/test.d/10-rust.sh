#!/usr/bin/env bash
# Formatting, lints (on the current Rust), the no_std core on its own for two Cortex-M
# targets, and every Rust test, built with the oldest Rust the workspace declares (its
# rust-version): one build shows both that the tests pass and that this Rust builds every
# member, where a separate check would compile the std crate and its dependencies once more.
set -euo pipefail
source scripts/lib.sh
need_rust
need_msrv_toolchains
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
# The core alone (features of a --workspace build unify, so it is built by itself).
cargo build -p angletrack-core --target thumbv7em-none-eabihf --release
cargo build -p angletrack-core --target thumbv6m-none-eabi --release
# Firmware that logs with defmt: the optional feature builds for the Cortex-M4F.
cargo build -p angletrack-core --features defmt --target thumbv7em-none-eabihf
cargo clippy -p angletrack-core --features defmt --all-targets -- -D warnings
msrv=$(workspace_msrv)
cargo "+$msrv" test --workspace
echo "every workspace member builds and passes its tests with Rust $msrv"
