#!/usr/bin/env bash
# The C API on two cores, each example built with arm-none-eabi-gcc against
# crates/angletrack-c/include/angletrack.h and linked with newlib and the static library
# built for its target (the sections in sections.ld, on the Rust firmware test's memory
# maps):
#  - Cortex-M4F (main.c, thumbv7em-none-eabihf, QEMU mps2-an386, link-m4.ld): the float
#    observer from floats, from 12-bit ADC counts and through the online calibration;
#  - Cortex-M0 (main_m0.c, thumbv6m-none-eabi, QEMU microbit, link-m0.ld): the fixed-point
#    chain from raw 12-bit ADC counts, from its integer constants with a stored calibration
#    and the angle-correction table on an imperfect sensor, and from float gains.
# For each:
#  1. runs it: it must exit 0 and print PASS for each of its checks;
#  2. checks that each check can fail: built with -DTAMPER (one input of each check
#     corrupted: the signal 1 % faster than the tracking checks expect, the sensor's offset
#     0.01 off the calibration check's) it must exit 1 and every check must print FAIL;
#  3. checks that the image holds no panic code: no C API call can reach the library's
#     panic handler, so the linker's garbage collection drops it;
#  4. prints the image's code size;
# With `count` first (tests/firmware/run.sh, whose budgets hold the counts), it only counts,
# on the Cortex-M0: the instructions of the fixed-point chain per sample, with the firmware
# test's QEMU plugin (tests/firmware/plugin/insn_count.c): the image built with
# -DCOUNT_SAMPLES=N runs the corrected chain N times, the instructions inside the counted
# function and the functions it calls (from the symbol table), from runs of 1000 and 2000
# samples, per sample:
#  `insns_per_sample c-chain-fixed-corrected-m0: N`: at_chain_fixed_track_u16 from raw
#    12-bit counts (the ADC stage, the rails measured, the stored calibration, the table);
#  `insns_per_sample c-chain-fixed-samples-corrected-m0: N` (-DCOUNT_INT16): the same
#    chain without its ADC on the same samples as int16, at_chain_fixed_track_i16;
#  `insns_per_sample rust-tracker-fixed-corrected-m0: N` and
#    `rust-tracker-fixed-samples-corrected-m0` (-DCOUNT_REFERENCE): the same two in Rust, the
#    core's Tracker called without the door on the chain and state the C structs hold
#    (at_reference_track_u16 and _i16, the library built with its feature count-reference),
#    whose counts the C ones' budgets are relative to;
#  `insns_per_sample rust-chain-fixed-samples-corrected-m0: N` (-DCOUNT_COMPOSED): the same
#    stages composed as a plain Chain (calibration, table, observer) on the int16 samples,
#    at_reference_composed_track_i16: the Tracker's own cost on the same signal;
#  `flash_bytes c-chain-fixed-corrected-m0: N`: the flash (text and data, bytes) that the
#    library adds to a minimal image of that chain (minimal_m0.c, its configuration constants
#    in flash), against the same image without the library's calls.
# Needs: cargo with the thumbv7em-none-eabihf and thumbv6m-none-eabi targets,
# qemu-system-arm, gcc-arm-none-eabi, libnewlib-arm-none-eabi (scripts/test.d/16-c-api.sh
# installs them).
# Usage: bash tests/firmware/c/run.sh [count] [m4|m0]   (default both; CARGO_TARGET_DIR
# overrides the build directory)
set -euo pipefail
shopt -s inherit_errexit
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
target_dir="${CARGO_TARGET_DIR:-$root/target}"
out="$target_dir/c-example"
mkdir -p "$out"

# Per core (set by `core_settings`): the target, the compiler's CPU flags, QEMU's machine,
# the example's source and its number of checks.
core_settings() {
  case $1 in
    m4)
      target=thumbv7em-none-eabihf main=main.c checks=3
      cpu=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
      machine=(-machine mps2-an386 -cpu cortex-m4)
      ;;
    m0)
      target=thumbv6m-none-eabi main=main_m0.c checks=2
      cpu=(-mcpu=cortex-m0 -mthumb)
      machine=(-machine microbit)
      ;;
    *) echo "unknown core $1 (m4 or m0)" >&2; exit 1 ;;
  esac
  core=$1
  lib="$target_dir/$target/release/libangletrack_c.a"
}

# build NAME [CFLAGS...]: the image $out/NAME.elf of the current core.
build() {
  local name=$1
  shift
  arm-none-eabi-gcc "${cpu[@]}" -std=c11 -O2 -g -Wall -Wextra -Werror -ffunction-sections \
    -fdata-sections -I"$root/crates/angletrack-c/include" -I"$root/crates/angletrack-c/tests/c" \
    "$@" "$here/$main" "$here/startup.c" \
    -nostartfiles --specs=nosys.specs -L"$here/.." -L"$here" -T"$here/link-$core.ld" \
    -Wl,--gc-sections,--no-warn-execstack "$lib" -lm -o "$out/$name.elf"
}
# run NAME: runs the image under QEMU with semihosting (its exit status is the image's); the
# image's console (SYS_WRITE0, which QEMU writes to its stderr) on stdout.
run() {
  timeout 120 qemu-system-arm "${machine[@]}" -nographic -monitor none \
    -serial none -semihosting-config enable=on,target=native -kernel "$out/$1.elf" 2>&1
}

# count_per_sample FUNCTION LABEL [CFLAGS...]: the instructions per sample inside FUNCTION
# and the functions it calls (direct branches, transitively), from two runs of the
# -DCOUNT_SAMPLES image built with CFLAGS, printed as LABEL's.
count_per_sample() {
  local plugin="$out/insn_count.so" counted=$1 label=$2 elf f n
  shift 2
  gcc -O2 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden -I"$here/../plugin" \
    -o "$plugin" "$here/../plugin/insn_count.c"
  local -a counts=()
  for n in 1000 2000; do
    build "count-$core-$n" -DCOUNT_SAMPLES="$n" "$@"
    elf="$out/count-$core-$n.elf"
    # The functions reachable from the root, each as START-END (the Thumb bit cleared).
    local -A seen=()
    local queue=("$counted") ranges=() entry
    while [ ${#queue[@]} -gt 0 ]; do
      f=${queue[0]}
      queue=("${queue[@]:1}")
      [ -z "${seen[$f]:-}" ] || continue
      seen[$f]=1
      entry=$(arm-none-eabi-nm -S "$elf" | awk -v s="$f" '!found && NF == 4 && $4 == s { print $1, $2; found = 1 }')
      [ -n "$entry" ] || { echo "no size for $f" >&2; exit 1; }
      ranges+=("$(printf '0x%x-0x%x' $((16#${entry% *} & ~1)) $(((16#${entry% *} & ~1) + 16#${entry#* })))")
      for c in $(arm-none-eabi-objdump -d --no-show-raw-insn --disassemble="$f" "$elf" |
        sed -n 's/.*\tb[a-z.]*\t[0-9a-f]* <\([^>+]*\)>$/\1/p' | sort -u | grep -vxF "$f" || true); do
        queue+=("$c")
      done
    done
    unset seen
    rm -f "$out/insns.log"
    timeout 120 qemu-system-arm "${machine[@]}" -nographic -monitor none -serial none \
      -plugin "$plugin,out=$out/insns.log,ranges=$(IFS=:; echo "${ranges[*]}")" \
      -semihosting-config enable=on,target=native -kernel "$elf" >/dev/null 2>&1 ||
      { echo "FAIL: the counting image ($n samples) exited with an error" >&2; exit 1; }
    counts+=("$(sed -n 's/^insns_in_ranges: //p' "$out/insns.log")")
  done
  awk -v a="${counts[0]}" -v b="${counts[1]}" -v label="$label" \
    'BEGIN { printf "insns_per_sample %s: %.1f\n", label, (b - a) / 1000 }'
}

# flash_added LABEL: the flash (text and data) that the library adds to minimal_m0.c's image
# (the fixed-point chain from counts with a stored calibration and a table, its
# configuration constants in flash), against the same image built without the library's
# calls, printed as LABEL's `flash_bytes`.
flash_added() {
  local sizes=() v
  for v in with without; do
    arm-none-eabi-gcc "${cpu[@]}" -std=c11 -Os -Wall -Wextra -Werror -ffunction-sections \
      -fdata-sections -I"$root/crates/angletrack-c/include" -I"$root/crates/angletrack-c/tests/c" \
      $([ $v = with ] || echo -DWITHOUT_LIBRARY) "$here/minimal_m0.c" "$here/startup.c" \
      -nostartfiles --specs=nosys.specs -L"$here/.." -L"$here" -T"$here/link-$core.ld" \
      -Wl,--gc-sections,--no-warn-execstack "$lib" -o "$out/minimal-$v.elf"
    sizes+=("$(arm-none-eabi-size "$out/minimal-$v.elf" | awk 'NR == 2 { print $1 + $2 }')")
  done
  echo "flash_bytes $1: $((sizes[0] - sizes[1]))"
}

count_only=false
if [ "${1:-}" = count ]; then
  count_only=true
  shift
fi
cores=("$@")
[ ${#cores[@]} -gt 0 ] || cores=(m4 m0)
for c in "${cores[@]}"; do
  core_settings "$c"
  $count_only || echo "--- the C example on the $core ($target)"
  (cd "$root" && CARGO_TARGET_DIR="$target_dir" cargo build -q --locked -p angletrack-c \
    --release --target "$target")
  if $count_only; then
    if [ "$core" = m0 ]; then
      count_per_sample at_chain_fixed_track_u16_order3 c-chain-fixed-corrected-m0
      count_per_sample at_chain_fixed_track_i16_order3 c-chain-fixed-samples-corrected-m0 -DCOUNT_INT16
      flash_added c-chain-fixed-corrected-m0
      # The Rust reference of both: the library rebuilt with its feature count-reference.
      (cd "$root" && CARGO_TARGET_DIR="$target_dir" cargo build -q --locked -p angletrack-c \
        --release --target "$target" --features count-reference)
      count_per_sample at_reference_track_u16 rust-tracker-fixed-corrected-m0 -DCOUNT_REFERENCE
      count_per_sample at_reference_track_i16 rust-tracker-fixed-samples-corrected-m0 \
        -DCOUNT_REFERENCE -DCOUNT_INT16
      count_per_sample at_reference_composed_track_i16 rust-chain-fixed-samples-corrected-m0 \
        -DCOUNT_REFERENCE -DCOUNT_INT16 -DCOUNT_COMPOSED
      # The library as shipped again, for whatever links it next.
      (cd "$root" && CARGO_TARGET_DIR="$target_dir" cargo build -q --locked -p angletrack-c \
        --release --target "$target")
    fi
    continue
  fi

  build "example-$core"
  output=$(run "example-$core") ||
    { echo "$output"; echo "FAIL: the $core C example exited with an error" >&2; exit 1; }
  echo "$output"
  [ "$(grep -c '^PASS' <<<"$output")" -eq "$checks" ] ||
    { echo "FAIL: expected $checks PASS lines" >&2; exit 1; }

  build "tamper-$core" -DTAMPER
  if output=$(run "tamper-$core"); then
    echo "$output"; echo "FAIL: the tampered $core C example passed" >&2; exit 1
  fi
  # Every check (as many lines as the clean run's PASS lines) must fail on its corrupted
  # input.
  failed=$(grep -c '^FAIL' <<<"$output" || true)
  if [ "$failed" -ne "$checks" ] || [ "$(grep -cE '^(PASS|FAIL)' <<<"$output")" -ne "$checks" ]; then
    echo "$output"
    echo "FAIL: with one corrupted input per check, $failed of $checks checks FAIL; all must" >&2
    exit 1
  fi
  echo "checks with one corrupted input each: all $failed of $checks FAIL, as they must"

  if panics=$(arm-none-eabi-nm -C "$out/example-$core.elf" | grep -iE 'panic|rust_begin_unwind'); then
    echo "$panics"; echo "FAIL: the $core C example's image holds panic code" >&2; exit 1
  fi
  echo "no panic code in the image"
  arm-none-eabi-size "$out/example-$core.elf" |
    awk 'NR == 2 { print "image size: text " $1 " bytes, data " $2 ", bss " $3 }'
done
