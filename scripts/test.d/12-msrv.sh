#!/usr/bin/env bash
# The oldest Rust each publishable crate declares (`rust-version`) builds it: installs that
# toolchain (minimal profile) and checks the crate with it, for the core also on the
# Cortex-M4F it is mostly used on. A check, not a build: the MSRV is about what compiles.
set -euo pipefail
source scripts/lib.sh
need_rust
crates=$(publishable_crates)
echo "$crates"
while read -r name msrv _dir; do
  if [ "$msrv" = null ]; then
    echo "FAIL: $name declares no rust-version" >&2; exit 1
  fi
  rustup toolchain install "$msrv" --profile minimal >/dev/null 2>&1 ||
    rustup toolchain install "$msrv" --profile minimal
  cargo "+$msrv" check -q -p "$name"
  if [ "$name" = angletrack-core ]; then
    rustup "+$msrv" target add thumbv7em-none-eabihf >/dev/null 2>&1 ||
      rustup "+$msrv" target add thumbv7em-none-eabihf
    cargo "+$msrv" check -q -p "$name" --target thumbv7em-none-eabihf
  fi
  echo "$name builds with Rust $msrv"
done <<<"$crates"
