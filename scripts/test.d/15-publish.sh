#!/usr/bin/env bash
# What the Rust package registry and a vendoring firmware project get from the publishable crates:
# - their manifests agree with the workspace (version, licence, repository, lints, shared
#   dependencies' versions), since they write those keys out instead of inheriting them, and
#   their READMEs state their MSRV;
# - `cargo publish --dry-run` of the whole workspace: each publishable crate is packaged and
#   built from its package, against the others' packages (as the registry will serve them);
# - the core's package also builds for the Cortex-M4F, and the Rust example of each crate's
#   README builds against it (the core's package for the Cortex-M4F; the std crate's, which
#   runs, against its source: its package names the core by a version no registry serves yet);
# - their docs build without warnings, the core's for the Cortex-M4F as on docs.rs.
set -euo pipefail
source scripts/lib.sh
need_rust
root="$(pwd)"
# The scratch builds below share the workspace's compiled dependencies.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
# This step's builds (the crates copied out, their README examples, the packages `cargo
# publish` verifies) show that they build and that the example runs: no debugger reads them,
# so they leave out the dev profile's debug information, which only adds to their build time
# (an environment setting, so that it reaches the scratch packages outside the workspace too).
export CARGO_PROFILE_DEV_DEBUG=false
crates=$(publishable_crates)

echo "--- manifests agree with the workspace"
python3 - $(cut -d' ' -f3 <<<"$crates") <<'EOF'
import sys, tomllib
workspace = tomllib.load(open("Cargo.toml", "rb"))["workspace"]
failures = []
for crate_dir in sys.argv[1:]:
    manifest = tomllib.load(open(f"{crate_dir}/Cargo.toml", "rb"))
    package = manifest["package"]
    for key in ["version", "edition", "license", "repository", "authors"]:
        if package.get(key) != workspace["package"][key]:
            failures.append(f"{crate_dir}: package.{key} = {package.get(key)!r}, "
                            f"the workspace's is {workspace['package'][key]!r}")
    if package.get("readme") != "README.md":
        failures.append(f"{crate_dir}: readme must be the crate's own README.md")
    elif f"Rust {package['rust-version']} or newer" not in open(f"{crate_dir}/README.md").read():
        failures.append(f"{crate_dir}/README.md does not say \"Rust {package['rust-version']} or newer\"")
    if manifest.get("lints") != workspace["lints"]:
        failures.append(f"{crate_dir}: [lints] differ from [workspace.lints]")
    version_of = lambda spec: spec if isinstance(spec, str) else spec.get("version")
    for name, spec in manifest.get("dependencies", {}).items():
        if name in workspace["dependencies"]:
            shared = version_of(workspace["dependencies"][name])
            if version_of(spec) != shared:
                failures.append(f"{crate_dir}: dependency {name} = {version_of(spec)!r}, "
                                f"[workspace.dependencies] has {shared!r}")
print("\n".join(failures) or "the publishable crates' manifests agree with the workspace")
sys.exit(1 if failures else 0)
EOF

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

echo "--- cargo publish --dry-run"
# --workspace packages every member without `publish = false`, each verified by a build
# from its package against a local registry of the others (the core is not on the registry
# yet, so the std crate could not be verified on its own). --allow-dirty: the test command
# also runs on work trees with uncommitted changes.
# Cargo unpacks each verified package into its registry's source cache and builds it into
# the target directory, and takes a registry version it finds unpacked or built as
# immutable: an earlier run's copy of these unpublished crates would be used instead of the
# current one. Their unpacked copies and their builds' fingerprints are removed first.
rm -rf "$CARGO_TARGET_DIR/package"
cargo_home="${CARGO_HOME:-$HOME/.cargo}"
# A crate's version, from its manifest's first `version` line.
crate_version() { # $1: the crate's directory
  sed -n 's/^version = "\(.*\)"/\1/p' "$1/Cargo.toml" | head -n 1
}
while read -r name _msrv dir; do
  version=$(crate_version "$dir")
  rm -rf "$cargo_home"/registry/src/*/"$name-$version"
  [ -d "$CARGO_TARGET_DIR/debug/.fingerprint" ] &&
    find "$CARGO_TARGET_DIR/debug/.fingerprint" -maxdepth 1 -regex ".*/$name-[0-9a-f]*" -exec rm -rf {} +
done <<<"$crates"
log="$scratch/publish.log"
status=0
cargo publish --dry-run --workspace --allow-dirty >"$log" 2>&1 || status=$?
grep -E "^ *(Packaged|Verifying|Finished)|warning|error" "$log" || true
if [ "$status" -ne 0 ]; then
  cat "$log" >&2; echo "FAIL: cargo publish --dry-run (status $status)" >&2; exit 1
fi

echo "--- the core's package on the Cortex-M4F, and the READMEs' examples"
# A README's first ```rust block, as a file.
readme_example() { # $1: README, $2: output file
  awk '/^```rust/ { on = 1; next } on && /^```/ { exit } on { print }' "$1" >"$2"
  [ -s "$2" ] || { echo "FAIL: no rust example in $1" >&2; exit 1; }
}
# A scratch package depending on a crate; the workspace's lock file keeps the dependencies'
# versions (and so their compiled artifacts).
scratch_package() { # $1: directory, $2: name, $3: dependency line
  mkdir -p "$1/src"
  printf '[package]\nname = "%s"\nversion = "0.0.0"\nedition = "2024"\npublish = false\n\n[dependencies]\n%s\n\n[workspace]\n' \
    "$2" "$3" >"$1/Cargo.toml"
  cp "$root/Cargo.lock" "$1/Cargo.lock"
}
# The package as `cargo publish` unpacked it to verify it, copied out of the workspace's tree.
cp -r "$CARGO_TARGET_DIR/package/angletrack-core-$(crate_version crates/angletrack-core)" \
  "$scratch/angletrack-core"
(cd "$scratch/angletrack-core" && cargo build -q --target thumbv7em-none-eabihf)
echo "the angletrack-core package builds for thumbv7em-none-eabihf"
scratch_package "$scratch/core-readme" core-readme \
  'angletrack-core = { path = "../angletrack-core" }'
readme_example crates/angletrack-core/README.md "$scratch/core-readme/src/lib.rs"
(cd "$scratch/core-readme" && cargo build -q --target thumbv7em-none-eabihf)
echo "crates/angletrack-core/README.md's example builds for thumbv7em-none-eabihf against the package"
scratch_package "$scratch/std-readme" std-readme \
  "angletrack = { path = \"$root/crates/angletrack\" }"
readme_example crates/angletrack/README.md "$scratch/std-readme/src/main.rs"
(cd "$scratch/std-readme" && cargo run -q >"$scratch/std-readme.out")
grep -q "const GAINS: \[f32; 2\]" "$scratch/std-readme.out"
echo "crates/angletrack/README.md's example runs"

echo "--- docs"
while read -r name _msrv _dir; do
  target=(--target thumbv7em-none-eabihf)
  [ "$name" = angletrack-core ] || target=()
  RUSTDOCFLAGS="-D warnings" cargo doc -q --no-deps -p "$name" "${target[@]}"
  echo "$name: docs build without warnings (${target[1]:-host})"
done <<<"$crates"
