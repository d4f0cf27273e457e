#!/usr/bin/env bash
# The Python package as its users get it: builds the abi3 wheel with maturin (pinned in
# python/requirements-dev.txt; the release profile less its link-time optimisation) into a
# scratch directory, installs it into a fresh virtual
# environment with no Rust toolchain on PATH (so nothing can be compiled: the wheel alone
# must do), then runs the pytest suite against that installation from a directory where
# the source tree is not importable.
set -euo pipefail
source scripts/lib.sh
need_rust
source python/scripts/venv.sh
angletrack_tools_venv
command -v cc >/dev/null 2>&1 || need_debian_packages gcc
root="$(pwd)"
work="$(mktemp -d)"
deps_job=""
trap '[ -z "$deps_job" ] || kill "$deps_job" 2>/dev/null || true; rm -rf "$work"' EXIT

# PATH without any directory that holds a Rust toolchain (cargo, rustc or rustup).
no_rust_path=""
IFS=: read -ra path_dirs <<<"$PATH"
for dir in "${path_dirs[@]}"; do
  [ -n "$dir" ] || continue
  [ -e "$dir/cargo" ] || [ -e "$dir/rustc" ] || [ -e "$dir/rustup" ] && continue
  no_rust_path="${no_rust_path:+$no_rust_path:}$dir"
done
# `without_rust CMD...`: CMD with that PATH and none of Rust's variables.
without_rust() {
  env -u CARGO_HOME -u RUSTUP_HOME -u RUSTUP_TOOLCHAIN -u CARGO -u RUSTC PATH="$no_rust_path" "$@"
}

# The fresh environment and what the wheel will need there (the package's dependencies and
# its plot and study extras', as python/pyproject.toml declares them, and the test tools, all pinned by
# the tools list), installed while the wheel builds: pip waits on the network and the disk,
# maturin on the two cores. The wheel's own install below then resolves the same
# requirements again, from its metadata, and finds them met.
test_tools=(pytest hypothesis pytest-xdist)
python/.venv/bin/python - >"$work/requirements.txt" <<'PY'
import tomllib
project = tomllib.load(open("python/pyproject.toml", "rb"))["project"]
extras = project["optional-dependencies"]
print("\n".join(project["dependencies"] + extras["plot"] + extras["study"]))
PY
without_rust "$BASH" -euo pipefail -c '
  python3 -m venv "$1"
  "$1/bin/python" -m pip --disable-pip-version-check -q install --only-binary :all: -c "$2" \
    -r "$3" "${@:4}"
' _ "$work/venv" "$root/python/requirements-dev.txt" "$work/requirements.txt" "${test_tools[@]}" \
  >"$work/deps.log" 2>&1 &
deps_job=$!

echo "--- maturin build --profile wheel-test (abi3 wheel)"
status=0
# The release profile without link-time optimisation (Cargo.toml says why).
python/.venv/bin/maturin build --profile wheel-test --manifest-path python/Cargo.toml --out "$work/wheels" \
  >"$work/maturin.log" 2>&1 || status=$?
grep -E "abi3|warning|error" "$work/maturin.log" || true
if [ "$status" -ne 0 ]; then
  cat "$work/maturin.log" >&2; echo "FAIL: maturin build (status $status)" >&2; exit 1
fi
shopt -s nullglob
wheels=("$work"/wheels/angletrack-*-abi3-*.whl)
if [ ${#wheels[@]} -ne 1 ]; then
  ls -l "$work/wheels" >&2
  echo "FAIL: expected one abi3 wheel of angletrack" >&2; exit 1
fi
wheel="${wheels[0]}"
contents=$(python3 -m zipfile -l "$wheel")
for file in angletrack/_angletrack.abi3.so angletrack/py.typed licenses/LICENSE-MIT licenses/LICENSE-APACHE; do
  grep -q "$file" <<<"$contents" || { echo "FAIL: $file is not in $(basename "$wheel")" >&2; exit 1; }
done
echo "built $(basename "$wheel") (with the abi3 extension, the type stubs' marker and both licences)"

echo "--- installing the wheel into a fresh virtual environment, no Rust on PATH"
# The PyPI description's example (python/README.md, its first python block) runs there too.
awk '/^```python/ { on = 1; next } on && /^```/ { exit } on { print }' python/README.md \
  >"$work/readme_example.py"
status=0
wait "$deps_job" || status=$?
deps_job=""
if [ "$status" -ne 0 ]; then
  cat "$work/deps.log" >&2; echo "FAIL: the test environment's dependencies (status $status)" >&2; exit 1
fi
without_rust "$BASH" -euo pipefail -c '
    venv="$1"; wheel="$2"; constraints="$3"
    if command -v cargo || command -v rustc || command -v rustup; then
      echo "FAIL: a Rust toolchain is still on PATH (above)" >&2; exit 1
    fi
    echo "no cargo, rustc or rustup on PATH"
    # Binary wheels only, versions pinned by the tools list: nothing is built here.
    "$venv/bin/python" -m pip --disable-pip-version-check -q install --only-binary :all: \
      -c "$constraints" "$wheel[plot,study]" "${@:5}"
    cd "$venv"
    "$venv/bin/python" -c "import angletrack; print(\"imported\", angletrack.__name__, angletrack.__version__, \"from\", angletrack.__file__)"
    "$venv/bin/angletrack" --version
    "$venv/bin/python" "$4" >"$4.out"
    echo "python/README.md example: $(tail -n 1 "$4.out")"
  ' _ "$work/venv" "$wheel" "$root/python/requirements-dev.txt" "$work/readme_example.py" \
  "${test_tools[@]}"

echo "--- pytest against the installed wheel"
cd "$work"
# Rust is on PATH again here: one test compiles the design command's Rust output with rustc.
# Any non-zero exit fails the step, including pytest's 5 (no test collected).
PATH="$work/venv/bin:$PATH" # The tests are independent (each writes only its own tmp_path): one worker per core.
"$work/venv/bin/python" -m pytest -p no:cacheprovider -q -n "$(nproc)" "$root/python/tests"
