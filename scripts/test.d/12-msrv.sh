#!/usr/bin/env bash
# The oldest Rust each publishable crate declares (`rust-version`) builds it. A crate that
# declares the workspace's rust-version is built and tested with that Rust by 10-rust.sh;
# one that declares an older one (the core, for firmware projects on an older toolchain) is
# checked with it here, also on the Cortex-M4F it is mostly used on. A check, not a build:
# the MSRV is about what compiles.
set -euo pipefail
source scripts/lib.sh
need_rust
crates=$(publishable_crates)
echo "$crates"
workspace=$(workspace_msrv)
need_msrv_toolchains
while read -r name msrv _dir; do
  if [ "$msrv" = null ]; then
    echo "FAIL: $name declares no rust-version" >&2; exit 1
  fi
  if [ "$msrv" = "$workspace" ]; then
    echo "$name: Rust $msrv, the workspace's, which 10-rust.sh builds and tests it with"
    continue
  fi
  cargo "+$msrv" check -q -p "$name"
  if [ "$name" = angletrack-core ]; then
    cargo "+$msrv" check -q -p "$name" --target thumbv7em-none-eabihf
  fi
  echo "$name builds with Rust $msrv"
done <<<"$crates"
