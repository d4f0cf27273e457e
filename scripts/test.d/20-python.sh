#!/usr/bin/env bash
# The Python package: builds it and installs it into python/.venv (pip install ./python, with
# the pinned tools of python/requirements-dev.txt), then runs its pytest suite against the
# installed package from a directory where the source tree is not importable.
set -euo pipefail
source scripts/lib.sh
need_rust
source python/scripts/venv.sh
angletrack_venv
command -v cc >/dev/null 2>&1 || need_debian_packages gcc
root="$(pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
# Any non-zero exit fails the step, including pytest's 5 (no test collected).
"$root/python/.venv/bin/python" -m pytest -p no:cacheprovider -q "$root/python/tests"
