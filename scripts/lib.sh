# Shared helpers for the scripts: sourced, not run.

# Installs Debian packages that are missing (CI and fresh machines run as root).
need_debian_packages() {
  local missing=()
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  if [ ${#missing[@]} -gt 0 ]; then
    local sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

# Makes sure the Rust toolchain has the targets and components the project builds with.
need_rust() {
  if ! command -v cargo >/dev/null 2>&1 || ! command -v rustup >/dev/null 2>&1; then
    echo "angletrack needs Rust installed with rustup (https://rustup.rs)" >&2
    exit 1
  fi
  rustup component add rustfmt clippy >/dev/null 2>&1 || true
  rustup target add thumbv7em-none-eabihf thumbv6m-none-eabi >/dev/null
}

# Prints one line per workspace member that may be published (no `publish = false`): its
# name, its rust-version (the MSRV it declares) and its directory.
publishable_crates() {
  cargo metadata --no-deps --format-version 1 | python3 -c '
import json, os, sys
for p in json.load(sys.stdin)["packages"]:
    if p["publish"] != []:
        print(p["name"], p["rust_version"], os.path.dirname(p["manifest_path"]))'
}

# The nightly toolchain with Miri, and cargo-fuzz, for the robustness step and its fuzz build.
need_fuzz_tools() {
  rustup toolchain install nightly --profile minimal >/dev/null 2>&1 || true
  rustup +nightly component add miri rust-src >/dev/null
  if [[ "$(cargo fuzz --version 2>/dev/null || true)" != *" 0.13."* ]]; then
    cargo install cargo-fuzz --version 0.13.2 --locked
  fi
}

# wait_fuzz_build STATE_DIR tools|status: waits for the fuzz build of scripts/fuzz-build.sh
# writing to STATE_DIR to have installed the nightly tools, or to end; fails if it ends
# without a status (killed) or, for `status`, with one other than 0 (its log's last lines on
# stderr); for `tools`, if it ended without installing them.
wait_fuzz_build() {
  local state="$1" what="$2" pid status
  until [ -f "$state/$what" ] || [ -f "$state/status" ]; do
    pid=$(cat "$state/pid" 2>/dev/null || true)
    if [ -n "$pid" ] && ! kill -0 "$pid" 2>/dev/null && [ ! -f "$state/status" ]; then
      echo "FAIL: the fuzz build (process $pid) ended without a status" >&2; return 1
    fi
    sleep 1
  done
  [ -f "$state/$what" ] && [ "$what" = tools ] && return 0
  status=$(cat "$state/status")
  if [ "$status" -ne 0 ] || [ ! -f "$state/$what" ]; then
    tail -n 60 "$state/log" >&2
    echo "FAIL: the fuzz targets' build failed (status $status)" >&2
    return 1
  fi
}

# stop_fuzz_build STATE_DIR: stops the fuzz build writing to STATE_DIR, if it still runs.
stop_fuzz_build() {
  local pid
  pid=$(cat "$1/pid" 2>/dev/null || true)
  [ -z "$pid" ] || kill -- "-$pid" 2>/dev/null || true
}
