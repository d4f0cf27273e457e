#!/usr/bin/env bash
# The project's main job on a fresh machine. Until the Python tool lands, it tracks a
# simulated resolver with the three observers and prints their errors.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
need_rust
cargo run --release -q -p angletrack-core --example track_resolver
