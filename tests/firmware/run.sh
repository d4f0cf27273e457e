#!/usr/bin/env bash
# The firmware test: builds the QEMU instruction-count plugin and the Cortex-M4F firmware,
# runs the firmware under `qemu-system-arm -machine mps2-an386 -cpu cortex-m4`, and
#  1. checks every observer variant against the host's reference (fails if out of tolerance);
#  2. checks that the check can fail: with one input sample corrupted it must report FAIL;
#  3. counts instructions with the TCG plugin (plugin/insn_count.c), per sample from two runs
#     of 1000 and 2000 samples, for each variant `<observer>-f32-<sincos>` and prints
#     `insns_per_update <variant>: N`: the instructions executed inside the out-of-line
#     update (the firmware's `update::<N, S>` wrapper) and the functions it calls,
#     transitively (the plugin's address ranges, from the symbol table), per call;
#     `insns_per_iteration <variant>: N`: all instructions of one iteration of the loop
#     calling it (update plus loop: inputs, call through a black-boxed pointer, result);
#     `insns_per_sample_in_block <variant>: N`: the instructions inside `update_block::<N, S>`
#     and the functions it calls, per sample of one call over all samples;
#     and `insns_per_iteration loop: N`: the loop alone, with an empty callee;
#     `insns_per_sample_pair demodulator-f32: N`: the instructions inside the out-of-line
#     `demodulate` (the core's `Demodulator::push`) and what it calls, per ADC sample pair;
#     `insns_per_sample_pair_in_block demodulator-f32: N`: the same inside one
#     `demodulate_block` call (`Demodulator::push_block`) over all samples;
#  4. prints the code size of each f32 update function, alone and with the out-of-line
#     functions it calls.
# Needs: cargo with the thumbv7em-none-eabihf target, qemu-system-arm, gcc,
# arm-none-eabi-nm/objdump (scripts/test.d/30-firmware.sh installs them).
# Usage: bash tests/firmware/run.sh   (FIRMWARE_TARGET_DIR overrides the build directory)
set -euo pipefail
shopt -s inherit_errexit
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

# The functions of the firmware: symbol tables (mangled and demangled, side by side), and the
# functions a function calls (direct branches to another symbol: calls and tail calls;
# calls through a pointer are not seen).
symbols=$(paste <(arm-none-eabi-nm "$elf") <(arm-none-eabi-nm -C "$elf"))
sized_symbols=$(arm-none-eabi-nm -S "$elf")
mangled() { awk -F'\t' -v d="$1" '{ sub(/^[0-9a-f]+ [tT] /, "", $2) } $2 == d { split($1, m, " "); print m[3]; exit }' <<<"$symbols"; }
demangled() { awk -F'\t' -v m="$1" '{ split($1, f, " ") } f[3] == m { sub(/^[0-9a-f]+ [a-zA-Z] /, "", $2); print $2; exit }' <<<"$symbols"; }
# sized NAME: "ADDRESS SIZE" (hex) of the symbol NAME (mangled), or nothing.
sized() { awk -v s="$1" 'NF == 4 && $4 == s { print $1, $2; exit }' <<<"$sized_symbols"; }
size_of() {
  local hex
  hex=$(sized "$1")
  hex=${hex#* }
  echo $((16#${hex:-0}))
}
callees() {
  arm-none-eabi-objdump -d --no-show-raw-insn --disassemble="$1" "$elf" |
    sed -n 's/.*\tb[a-z.]*\t[0-9a-f]* <\([^>+]*\)>$/\1/p' | sort -u | grep -vxF "$1" || true
}
# reachable ROOT: ROOT and every function it calls, transitively (mangled names, one a line,
# breadth first, each once).
reachable() {
  local -A seen=()
  local queue=("$1") f c
  while [ ${#queue[@]} -gt 0 ]; do
    f=${queue[0]}
    queue=("${queue[@]:1}")
    [ -z "${seen[$f]:-}" ] || continue
    seen[$f]=1
    echo "$f"
    for c in $(callees "$f"); do queue+=("$c"); done
  done
}
# measured ROOT: the insn_count plugin's `ranges=` value covering ROOT and the functions it
# calls, transitively: `START-END:...` (hex, END exclusive, the Thumb bit cleared).
measured() {
  local f entry start list=()
  while read -r f; do
    entry=$(sized "$f")
    [ -n "$entry" ] || { echo "no size for $f in $elf" >&2; exit 1; }
    start=$((16#${entry% *} & ~1))
    list+=("$(printf '0x%x-0x%x' "$start" $((start + 16#${entry#* })))")
  done < <(reachable "$1")
  (IFS=:; echo "${list[*]}")
}
# function_of KIND VARIANT: the mangled name of the firmware's out-of-line KIND (update or
# update_block) for VARIANT: 2nd order for second-order-*, else 3rd (the 3rd-order and the
# Kalman ATO share it); fast sin/cos unless the name ends in -exact; the update of a variant
# ending in -calibrated or -adc is update_calibrated or update_adc.
function_of() {
  local order=3 sin_cos=Fast kind=$1 name f
  case $2 in second-order-*) order=2 ;; esac
  case $2 in *-exact) sin_cos=Exact ;; esac
  case $1-$2 in update-*-calibrated) kind=update_calibrated ;; update-*-adc) kind=update_adc ;; esac
  name="angletrack_firmware_test::$kind::<$order, angletrack_core::sincos::$sin_cos>"
  f=$(mangled "$name")
  [ -n "$f" ] || { echo "no $name symbol in $elf" >&2; exit 1; }
  echo "$f"
}

# insns SAMPLES VARIANT [block]: "ALL IN_RANGES", the instructions executed by a count run and
# those of them inside the address ranges $ranges (ALL again if $ranges is empty).
insns() {
  local log="$target_dir/insns.log" all in_ranges
  rm -f "$log"
  plugin_option="$plugin,out=$log${ranges:+,ranges=$ranges}" qemu count "$2" "$1" ${3:+"$3"} >&2
  all=$(sed -n 's/^insns_executed: //p' "$log")
  in_ranges=$(sed -n 's/^insns_in_ranges: //p' "$log")
  if [ -z "$all" ] || { [ -n "$ranges" ] && [ -z "$in_ranges" ]; }; then
    echo "no instruction count in $log (count $2 $1 ${3:-})" >&2
    exit 1
  fi
  echo "$all ${in_ranges:-$all}"
}
# per_sample VARIANT [block]: "ALL IN_RANGES" per sample, from runs of 1000 and 2000 samples.
per_sample() {
  local a b
  a=$(insns 1000 "$@")
  b=$(insns 2000 "$@")
  awk -v a="$a" -v b="$b" 'BEGIN {
    split(a, x, " "); split(b, y, " ")
    printf "%.1f %.1f", (y[1] - x[1]) / 1000, (y[2] - x[2]) / 1000
  }'
}
ranges=""
counts=$(per_sample loop)
echo "insns_per_iteration loop: ${counts% *}"
for variant in second-order-f32-exact second-order-f32-fast third-order-f32-exact \
  third-order-f32-fast kalman-f32-exact kalman-f32-fast kalman-f32-fast-unmonitored \
  kalman-f32-fast-calibrated kalman-f32-fast-adc; do
  root=$(function_of update "$variant")
  ranges=$(measured "$root")
  counts=$(per_sample "$variant")
  echo "insns_per_update $variant: ${counts#* }"
  echo "insns_per_iteration $variant: ${counts% *}"
  # The calibrated and ADC entry points have no block form.
  case $variant in *-calibrated | *-adc) continue ;; esac
  root=$(function_of update_block "$variant")
  ranges=$(measured "$root")
  block=$(per_sample "$variant" block)
  echo "insns_per_sample_in_block $variant: ${block#* }"
done

# The resolver front end: the synchronous demodulator per ADC sample pair (its once-per-period
# work amortised over the period's 16 samples).
ranges=$(measured "$(mangled "angletrack_firmware_test::demodulate")")
counts=$(per_sample demodulator-f32)
echo "insns_per_sample_pair demodulator-f32: ${counts#* }"
echo "insns_per_iteration demodulator-f32: ${counts% *}"
ranges=$(measured "$(mangled "angletrack_firmware_test::demodulate_block")")
block=$(per_sample demodulator-f32 block)
echo "insns_per_sample_pair_in_block demodulator-f32: ${block#* }"

# The fixed-point Kalman ATO (16-bit samples, default diagnostics).
ranges=$(measured "$(mangled "angletrack_firmware_test::fixed::update_fixed")")
counts=$(per_sample kalman-fixed)
echo "insns_per_update kalman-fixed-m4: ${counts#* }"
echo "insns_per_iteration kalman-fixed-m4: ${counts% *}"
echo "code_size update-kalman-fixed: $(size_of "$(mangled "angletrack_firmware_test::fixed::update_fixed")") bytes"

# Code size: each update function, then with every function it calls (transitively).
for order in 2 3; do
  for sin_cos in Fast Exact; do
    types="$order, angletrack_core::sincos::$sin_cos"
    root=$(mangled "angletrack_firmware_test::update::<$types>")
    [ -n "$root" ] || { echo "no update::<$types> symbol in $elf" >&2; exit 1; }
    # The update itself: the wrapper, plus the core's update if the compiler kept it apart.
    core=$(mangled "<angletrack_core::gains::Gains<f32, $types>>::update")
    own=$(($(size_of "$root") + ${core:+$(size_of "$core")}+0))
    total=0
    called=()
    while read -r f; do
      total=$((total + $(size_of "$f")))
      [ "$f" = "$root" ] || [ "$f" = "$core" ] ||
        called+=("$(demangled "$f" | sed 's/::<.*//; s/.*:://')")
    done < <(reachable "$root")
    echo "code_size update-order$order-f32-${sin_cos,,}: $own bytes;" \
      "$total bytes with the ${#called[@]} functions it calls (${called[*]:-none})"
  done
done
