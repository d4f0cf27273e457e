# Sourced by scripts/main.sh and scripts/test.d/20-python.sh (after scripts/lib.sh), from the
# repository root: defines angletrack_tools_venv and angletrack_venv.

# Creates (or reuses) the virtual environment python/.venv with the pinned tools of
# python/requirements-dev.txt (maturin, numpy, matplotlib, pytest, hypothesis).
angletrack_tools_venv() {
  local venv=python/.venv
  if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    need_debian_packages python3 python3-venv python3-pip
  fi
  if ! "$venv/bin/python" -c 'import sys' >/dev/null 2>&1; then
    rm -rf "$venv"
    python3 -m venv "$venv"
  fi
  "$venv/bin/python" -m pip --disable-pip-version-check -q install -r python/requirements-dev.txt
}

# python/.venv with the tools, and the package built and installed from source with
# `pip install ./python` (maturin compiles the Rust extension in release mode).
angletrack_venv() {
  angletrack_tools_venv
  echo "building and installing the angletrack package (pip install ./python)..."
  # --force-reinstall: the version number does not change between two builds of a work tree.
  python/.venv/bin/python -m pip --disable-pip-version-check -q install --force-reinstall --no-deps ./python
}
