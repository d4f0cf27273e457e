#!/usr/bin/env bash
# The firmware test: builds the QEMU instruction-count plugin and the Cortex-M4F firmware,
# runs the firmware under `qemu-system-arm -machine mps2-an386 -cpu cortex-m4`, and
#  1. checks every observer variant against the host's reference (fails if out of tolerance);
#  2. checks that the check can fail: with one input sample corrupted it must report FAIL;
#  3. prints `insns_per_update <observer>-f32-<sincos>: N`: the instructions of one loop
#     iteration calling the out-of-line update, from two runs of different lengths;
#     `insns_per_iteration loop: N` is the same loop with an empty callee;
#     `insns_per_sample_in_block ...: N` the same per sample of one `update_block` call;
#  4. prints the code size of each f32 update function, alone and with the out-of-line
#     functions it calls.
# Needs: cargo with the thumbv7em-none-eabihf target, qemu-system-arm, gcc,
# arm-none-eabi-nm/objdump (scripts/test.d/30-firmware.sh installs them).
# Usage: bash tests/firmware/run.sh   (FIRMWARE_TARGET_DIR overrides the build directory)
set -euo pipefail
cd "$(dirname "$0")"
target_dir="${FIRMWARE_TARGET_DIR:-$PWD/target}"
export CARGO_TARGET_DIR="$target_dir"
elf="$target_dir/thumbv7em-none-eabihf/release/angletrack-firmware-test"
plugin="$target_dir/insn_count.so"

mkdir -p "$target_dir"
gcc -O2 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden -o "$plugin" plugin/insn_count.c
cargo build --release --locked -q

# qemu ARGS...: runs the firmware with ARGS on its semihosting command line.
qemu() {
  local config="enable=on,target=native,arg=angletrack-firmware-test"
  for a in "$@"; do config+=",arg=$a"; done
  timeout 300 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -monitor none \
    -serial none ${plugin_option:+-plugin "$plugin_option"} -semihosting-config "$config" \
    -kernel "$elf"
}

plugin_option=""
qemu check
if output=$(qemu check tamper); then
  echo "$output"
  echo "the check did not fail on a corrupted input sample" >&2
  exit 1
fi
grep -q FAIL <<<"$output" || { echo "$output"; echo "tamper run failed without FAIL" >&2; exit 1; }
echo "check with one corrupted input sample: fails as it must ($(grep -c FAIL <<<"$output") of $(grep -c "^check " <<<"$output") variants FAIL)"

# insns SAMPLES VARIANT [block]: instructions executed by a count run.
insns() {
  local log="$target_dir/insns.log"
  rm -f "$log"
  plugin_option="$plugin,out=$log" qemu count "$2" "$1" ${3:-}
  sed -n 's/^insns_executed: //p' "$log"
}
# per_sample VARIANT [block]: instructions per sample, from runs of 1000 and 2000 samples.
per_sample() {
  local a b
  a=$(insns 1000 "$@")
  b=$(insns 2000 "$@")
  awk -v a="$a" -v b="$b" 'BEGIN { printf "%.1f", (b - a) / 1000 }'
}
echo "insns_per_iteration loop: $(per_sample loop)"
for variant in second-order-f32-exact second-order-f32-fast third-order-f32-exact \
  third-order-f32-fast kalman-f32-exact kalman-f32-fast kalman-f32-fast-unmonitored; do
  echo "insns_per_update $variant: $(per_sample "$variant")"
  echo "insns_per_sample_in_block $variant: $(per_sample "$variant" block)"
done

# Code size: each update function, then with every function it calls (transitively).
symbols=$(paste <(arm-none-eabi-nm "$elf") <(arm-none-eabi-nm -C "$elf"))
mangled() { awk -F'\t' -v d="$1" '{ sub(/^[0-9a-f]+ [tT] /, "", $2) } $2 == d { split($1, m, " "); print m[3]; exit }' <<<"$symbols"; }
demangled() { awk -F'\t' -v m="$1" '{ split($1, f, " ") } f[3] == m { sub(/^[0-9a-f]+ [a-zA-Z] /, "", $2); print $2; exit }' <<<"$symbols"; }
size_of() {
  local hex
  hex=$(arm-none-eabi-nm -S "$elf" | awk -v s="$1" '$4 == s { print $2; exit }')
  echo $((16#${hex:-0}))
}
callees() {
  arm-none-eabi-objdump -d --no-show-raw-insn --disassemble="$1" "$elf" |
    sed -n 's/.*\tb[a-z.]*\t[0-9a-f]* <\([^>+]*\)>$/\1/p' | sort -u | grep -vxF "$1" || true
}
for order in 2 3; do
  for sin_cos in Fast Exact; do
    types="$order, angletrack_core::sincos::$sin_cos"
    root=$(mangled "angletrack_firmware_test::update::<$types>")
    [ -n "$root" ] || { echo "no update::<$types> symbol in $elf" >&2; exit 1; }
    # The update itself: the wrapper, plus the core's update if the compiler kept it apart.
    core=$(mangled "<angletrack_core::gains::Gains<f32, $types>>::update")
    own=$(($(size_of "$root") + ${core:+$(size_of "$core")}+0))
    declare -A seen=()
    queue=("$root")
    total=0
    called=()
    while [ ${#queue[@]} -gt 0 ]; do
      f=${queue[0]}
      queue=("${queue[@]:1}")
      [ -z "${seen[$f]:-}" ] || continue
      seen[$f]=1
      total=$((total + $(size_of "$f")))
      [ "$f" = "$root" ] || [ "$f" = "$core" ] ||
        called+=("$(demangled "$f" | sed 's/::<.*//; s/.*:://')")
      for c in $(callees "$f"); do queue+=("$c"); done
    done
    unset seen
    echo "code_size update-order$order-f32-${sin_cos,,}: $own bytes;" \
      "$total bytes with the ${#called[@]} functions it calls (${called[*]:-none})"
  done
done
