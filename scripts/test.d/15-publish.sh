#!/usr/bin/env bash
# What the Rust package registry and a vendoring firmware project get from the publishable crates:
# - their manifests agree with the workspace (version, licence, repository, lints, shared
#   dependencies' versions), since they write those keys out instead of inheriting them, and
#   their READMEs state their MSRV;
# - `cargo publish --dry-run` of the whole workspace packages each publishable crate, and
#   each package, unpacked, compiles from its own files against the others' packages (as the
#   registry will serve them); the core's package also builds for the Cortex-M4F, and the
#   Rust example of its README builds against it there (the std crate's README example runs
#   as a doctest of that crate, in `cargo test`);
# - their docs build without warnings, the core's for the Cortex-M4F as on docs.rs.
set -euo pipefail
source scripts/lib.sh
need_rust
root="$(pwd)"
# The scratch builds below share the workspace's compiled dependencies (those the lints of
# 10-rust checked, in the same profile).
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
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
# --workspace packages every member without `publish = false`. --no-verify: the packages are
# compiled below, checked rather than built: a check finds what a package leaves out (a
# file, a feature, a dependency) as a build does, on the dependencies the workspace's lints
# already checked, where cargo's own verification would compile them all once more.
# --allow-dirty: the test command also runs on work trees with uncommitted changes.
rm -rf "$CARGO_TARGET_DIR/package"
log="$scratch/publish.log"
status=0
cargo publish --dry-run --workspace --allow-dirty --no-verify >"$log" 2>&1 || status=$?
grep -E "^ *(Packaged|Uploading)|warning|error" "$log" || true
if [ "$status" -ne 0 ]; then
  cat "$log" >&2; echo "FAIL: cargo publish --dry-run (status $status)" >&2; exit 1
fi

echo "--- the packages compile from their own files"
# A crate's version, from its manifest's first `version` line.
crate_version() { # $1: the crate's directory
  sed -n 's/^version = "\(.*\)"/\1/p' "$1/Cargo.toml" | head -n 1
}
# The packages unpacked side by side in a workspace of their own, each depending on the
# others' packages by version as the registry will serve them (`[patch]` stands in for the
# registry, which does not serve these versions yet); the workspace's lock file keeps the
# other dependencies' versions, and so their compiled artifacts.
packages="$scratch/packages"
mkdir -p "$packages"
# The same packages as the dry run's, written where cargo keeps packages (the dry run's own
# copies are in a staging directory of cargo's).
package_flags=()
while read -r name _msrv _dir; do package_flags+=(-p "$name"); done <<<"$crates"
cargo package -q --no-verify --allow-dirty "${package_flags[@]}"
members=""
patches=""
while read -r name _msrv dir; do
  unpacked="$name-$(crate_version "$dir")"
  tar -xzf "$CARGO_TARGET_DIR/package/$unpacked.crate" -C "$packages"
  members="$members\"$unpacked\", "
  patches="$patches$name = { path = \"$unpacked\" }\n"
done <<<"$crates"
printf '[workspace]\nmembers = [%s]\nresolver = "3"\n\n[patch.crates-io]\n%b' "$members" "$patches" \
  >"$packages/Cargo.toml"
cp "$root/Cargo.lock" "$packages/Cargo.lock"
(cd "$packages" && cargo check -q --workspace)
echo "every package compiles from its own files: $(cut -d' ' -f1 <<<"$crates" | paste -sd' ')"
core_package="$packages/angletrack-core-$(crate_version crates/angletrack-core)"
(cd "$packages" && cargo build -q -p angletrack-core --target thumbv7em-none-eabihf)
echo "the angletrack-core package builds for thumbv7em-none-eabihf"

echo "--- the core's README example, against its package"
# A README's first ```rust block, as a file.
readme_example() { # $1: README, $2: output file
  awk '/^```rust/ { on = 1; next } on && /^```/ { exit } on { print }' "$1" >"$2"
  [ -s "$2" ] || { echo "FAIL: no rust example in $1" >&2; exit 1; }
}
readme="$scratch/core-readme"
mkdir -p "$readme/src"
printf '[package]\nname = "core-readme"\nversion = "0.0.0"\nedition = "2024"\npublish = false\n\n[dependencies]\nangletrack-core = { path = "%s" }\n\n[workspace]\n' \
  "$core_package" >"$readme/Cargo.toml"
cp "$root/Cargo.lock" "$readme/Cargo.lock"
readme_example crates/angletrack-core/README.md "$readme/src/lib.rs"
(cd "$readme" && cargo build -q --target thumbv7em-none-eabihf)
echo "crates/angletrack-core/README.md's example builds for thumbv7em-none-eabihf against the package"

echo "--- docs"
while read -r name _msrv _dir; do
  target=(--target thumbv7em-none-eabihf)
  [ "$name" = angletrack-core ] || target=()
  RUSTDOCFLAGS="-D warnings" cargo doc -q --no-deps -p "$name" "${target[@]}"
  echo "$name: docs build without warnings (${target[1]:-host})"
done <<<"$crates"
