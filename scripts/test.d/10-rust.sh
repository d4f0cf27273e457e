#!/usr/bin/env bash
# Formatting, lints (on the current Rust), the no_std core with defmt for the Cortex-M4F,
# and every Rust test, built with the oldest Rust the workspace declares (its
# rust-version): one build shows both that the tests pass and that this Rust builds every
# member, where a separate check would compile the std crate and its dependencies once more.
set -euo pipefail
source scripts/lib.sh
need_rust
need_msrv_toolchains
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
# The core alone for the Cortex-M4F and the Cortex-M0 (features of a --workspace build
# unify): the images of tests/no-panic (40-robustness.sh) build it by itself for both, in
# release, with its default features and without them. Firmware that logs with defmt: the
# optional feature builds for the Cortex-M4F.
cargo build -p angletrack-core --features defmt --target thumbv7em-none-eabihf
cargo clippy -p angletrack-core --features defmt --all-targets -- -D warnings
msrv=$(workspace_msrv)
cargo "+$msrv" test --workspace
echo "every workspace member builds and passes its tests with Rust $msrv"
