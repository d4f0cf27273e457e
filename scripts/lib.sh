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

# The oldest Rust the workspace declares ([workspace.package] rust-version): the test build
# runs on it (scripts/test.d/10-rust.sh), so that building and testing every member also
# shows that this Rust builds them.
workspace_msrv() {
  python3 -c 'import tomllib; print(tomllib.load(open("Cargo.toml", "rb"))["workspace"]["package"]["rust-version"])'
}

# Installs the toolchain of each MSRV the workspace and its publishable crates declare
# (minimal profile) when missing, and the Cortex-M4F's standard library for the core's, which
# is checked there. Both lanes of scripts/test.sh call this: an installed toolchain is not
# asked for updates, so that two rustup runs do not race.
need_msrv_toolchains() {
  local msrv core
  for msrv in $( (workspace_msrv; publishable_crates | cut -d' ' -f2) | sort -u); do
    rustup run "$msrv" rustc --version >/dev/null 2>&1 ||
      rustup toolchain install "$msrv" --profile minimal >/dev/null
  done
  core=$(publishable_crates | awk '$1 == "angletrack-core" { print $2 }')
  rustup "+$core" target list --installed | grep -qx thumbv7em-none-eabihf ||
    rustup "+$core" target add thumbv7em-none-eabihf >/dev/null
}
