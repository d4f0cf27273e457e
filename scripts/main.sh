#!/usr/bin/env bash
# The project's main job on a fresh machine: creates the Python environment python/.venv,
# builds and installs the angletrack package (`pip install ./python`: the Rust extension and
# the `angletrack` command line), then reproduces the paper's comparison of the three
# observers: out/report/report.md with its tables and PNG plots.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
need_rust
source python/scripts/venv.sh
angletrack_venv
python/.venv/bin/angletrack report --out out/report
