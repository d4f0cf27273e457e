#!/usr/bin/env bash
# The C API on a Cortex-M4F: builds libangletrack_c.a for thumbv7em-none-eabihf, compiles the
# C example (main.c, startup.c) with arm-none-eabi-gcc against crates/angletrack-c/include/
# angletrack.h, links it with newlib (snprintf, sinf) into an image for QEMU mps2-an386
# (link.ld, on the Rust firmware test's memory-m4.x), and
#  1. runs it: it must exit 0 and print PASS for each tracking check;
#  2. checks that each check can fail: built with -DTAMPER (one input of each check
#     corrupted: the signal 1 % faster than the tracking checks expect, the sensor's offset
#     0.01 off the calibration check's) it must exit 1 and every check must print FAIL;
#  3. checks that the image holds no panic code: no C API call can reach the library's
#     panic handler, so the linker's garbage collection drops it;
#  4. prints the image's code size.
# Needs: cargo with the thumbv7em-none-eabihf target, qemu-system-arm, gcc-arm-none-eabi,
# libnewlib-arm-none-eabi (scripts/test.d/16-c-api.sh installs them).
# Usage: bash tests/firmware/c/run.sh   (CARGO_TARGET_DIR overrides the build directory)
set -euo pipefail
shopt -s inherit_errexit
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
target_dir="${CARGO_TARGET_DIR:-$root/target}"
out="$target_dir/c-example"
mkdir -p "$out"

(cd "$root" && CARGO_TARGET_DIR="$target_dir" cargo build -q --locked -p angletrack-c --release \
  --target thumbv7em-none-eabihf)
lib="$target_dir/thumbv7em-none-eabihf/release/libangletrack_c.a"

cpu=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
# build NAME [CFLAGS...]: the image $out/NAME.elf.
build() {
  local name=$1
  shift
  arm-none-eabi-gcc "${cpu[@]}" -std=c11 -O2 -g -Wall -Wextra -Werror -ffunction-sections \
    -fdata-sections -I"$root/crates/angletrack-c/include" -I"$root/crates/angletrack-c/tests/c" \
    "$@" "$here/main.c" "$here/startup.c" \
    -nostartfiles --specs=nosys.specs -L"$here/.." -T"$here/link.ld" -Wl,--gc-sections,--no-warn-execstack \
    "$lib" -lm -o "$out/$name.elf"
}
# run NAME: runs the image under QEMU with semihosting (its exit status is the image's); the
# image's console (SYS_WRITE0, which QEMU writes to its stderr) on stdout.
run() {
  timeout 120 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -monitor none \
    -serial none -semihosting-config enable=on,target=native -kernel "$out/$1.elf" 2>&1
}

build example
output=$(run example) || { echo "$output"; echo "FAIL: the C example exited with an error" >&2; exit 1; }
echo "$output"
checks=3
[ "$(grep -c '^PASS' <<<"$output")" -eq "$checks" ] ||
  { echo "FAIL: expected $checks PASS lines" >&2; exit 1; }

build tamper -DTAMPER
if output=$(run tamper); then
  echo "$output"; echo "FAIL: the tampered C example passed" >&2; exit 1
fi
# Every check (as many lines as the clean run's PASS lines) must fail on its corrupted input.
failed=$(grep -c '^FAIL' <<<"$output" || true)
if [ "$failed" -ne "$checks" ] || [ "$(grep -cE '^(PASS|FAIL)' <<<"$output")" -ne "$checks" ]; then
  echo "$output"
  echo "FAIL: with one corrupted input per check, $failed of $checks checks FAIL; all must" >&2
  exit 1
fi
echo "checks with one corrupted input each: all $failed of $checks FAIL, as they must"

if panics=$(arm-none-eabi-nm -C "$out/example.elf" | grep -iE 'panic|rust_begin_unwind'); then
  echo "$panics"; echo "FAIL: the C example's image holds panic code" >&2; exit 1
fi
echo "no panic code in the image"
arm-none-eabi-size "$out/example.elf" | awk 'NR == 2 { print "image size: text " $1 " bytes, data " $2 ", bss " $3 }'
