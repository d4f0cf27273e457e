#!/usr/bin/env bash
# The firmware test: builds the QEMU instruction-count plugin and the firmware (src/) for two
# cores, and runs each under QEMU with semihosting:
#  - Cortex-M4F: thumbv7em-none-eabihf on `qemu-system-arm -machine mps2-an386 -cpu cortex-m4`;
#  - Cortex-M0 (no FPU): thumbv6m-none-eabi on `qemu-system-arm -machine microbit` (nRF51:
#    256 KiB of flash, 16 KiB of RAM: it checks the float estimates of the first 200 samples
#    only, the fixed-point ones' integers over all, and runs block updates 200 samples at a
#    time).
# For each core it
#  1. checks every variant (src/variants.rs) against the host's reference (the fixed-point
#     ones' integers exactly, through a hash of all samples) and the baselines'
#     fast arctangent against atan2f (fails if out of tolerance);
#  2. checks that each check can fail: with one input of each check corrupted (`check tamper`),
#     every check must report FAIL;
#  3. counts instructions with the TCG plugin (plugin/insn_count.c), per sample from two runs
#     of 1000 and 2000 samples (the same signal on both cores), and
#     prints, for each variant (`-m0` appended to its name on the M0, `-m4` on the M4F to
#     the fixed-point ones):
#     `insns_per_update <variant>: N`: the instructions executed inside the variant's
#     out-of-line update (the firmware's `update::<T>`, whose address the firmware prints)
#     and the functions it calls, transitively (the plugin's address ranges, from the
#     symbol table), per call;
#     `insns_per_iteration <variant>: N`: all instructions of one iteration of the loop
#     calling it (update plus loop: inputs, call through a black-boxed pointer, result);
#     `insns_per_sample_in_block <variant>: N` (variants with a block form): the instructions
#     inside `update_block::<T>` and the functions it calls, per sample of one call over all
#     samples;
#     and `insns_per_iteration loop: N`: the loop alone, with an empty callee;
#     for the demodulator variants (`demodulator-f32`, `demodulator-fixed`):
#     `insns_per_push <variant>: N`: the instructions inside the out-of-line `demodulate`
#     (the core's `Demodulator::push`) and what it calls, per ADC sample (both windings);
#     `insns_per_sample <variant>: N`: the same inside one `demodulate_block` call
#     (`Demodulator::push_block`, the firmware's DMA buffer) over all samples;
#  4. prints the code size of each variant's update function, alone and with the out-of-line
#     functions it calls (`code_size <variant>: N bytes; M bytes with ...`);
#     and on the Cortex-M0 the C API's fixed-point chain (`c/run.sh count m0`:
#     `insns_per_sample c-chain-fixed-...-m0: N`, per call of its per-sample function);
# then, with the counts of all cores run (kept in counts.txt in the build directory),
#  5. checks them against their budgets (budgets.txt, checked by budgets.sh): prints
#     `budget <count> <variant>: N <= B ok` for each, a warning where an interim ceiling
#     stands above a target the count misses, and fails if a count is above its budget or a
#     budgeted count was not printed (a renamed variant must take its budget with it);
#  6. checks that the budget check can fail: with every budgeted count raised above its
#     budget, then removed, every budget must FAIL.
# `count` mode's inputs are converted before its runs (by build.rs), so that no conversion
# of the harness runs inside the counted ranges.
# Needs: cargo with the thumbv7em-none-eabihf and thumbv6m-none-eabi targets, qemu-system-arm,
# gcc, arm-none-eabi-nm/objdump (scripts/test.d/30-firmware.sh installs them).
# Usage: bash tests/firmware/run.sh [m4|m0]   (default both; FIRMWARE_TARGET_DIR overrides the
# build directory)
set -euo pipefail
shopt -s inherit_errexit
cd "$(dirname "$0")"
target_dir="${FIRMWARE_TARGET_DIR:-$PWD/target}"
export CARGO_TARGET_DIR="$target_dir"
plugin="$target_dir/insn_count.so"

mkdir -p "$target_dir"
gcc -O2 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden -o "$plugin" plugin/insn_count.c

# The sample counts of the two count runs.
runs=(1000 2000)
# Per core (set by `core_settings`): the target, the image and QEMU's machine.
core_settings() {
  case $1 in
    m4)
      target=thumbv7em-none-eabihf machine=(-machine mps2-an386 -cpu cortex-m4)
      ;;
    m0)
      target=thumbv6m-none-eabi machine=(-machine microbit)
      ;;
    *) echo "unknown core $1 (m4 or m0)" >&2; exit 1 ;;
  esac
  core=$1
  elf="$target_dir/$target/release/angletrack-firmware-test"
}
# label VARIANT: its printed name: `-m0` appended on the M0; on the M4F the fixed-point
# variants get `-m4` (they are for cores with or without an FPU), the others keep their names.
label() {
  case $core-$1 in
    m0-*) echo "$1-m0" ;;
    m4-*-fixed*) echo "$1-m4" ;;
    *) echo "$1" ;;
  esac
}

# qemu ARGS...: runs the firmware with ARGS on its semihosting command line.
qemu() {
  local config="enable=on,target=native,arg=angletrack-firmware-test"
  for a in "$@"; do config+=",arg=$a"; done
  timeout 300 qemu-system-arm "${machine[@]}" -nographic -monitor none \
    -serial none ${plugin_option:+-plugin "$plugin_option"} -semihosting-config "$config" \
    -kernel "$elf"
}

# The functions of the firmware: symbol tables (mangled and demangled, side by side), and the
# functions a function calls (direct branches to another symbol: calls and tail calls;
# calls through a pointer are not seen).
load_symbols() {
  symbols=$(paste <(arm-none-eabi-nm "$elf") <(arm-none-eabi-nm -C "$elf"))
  sized_symbols=$(arm-none-eabi-nm -S "$elf")
}
demangled() { awk -F'\t' -v m="$1" '{ split($1, f, " ") } f[3] == m { sub(/^[0-9a-f]+ [a-zA-Z] /, "", $2); print $2; exit }' <<<"$symbols"; }
# sized NAME: "ADDRESS SIZE" (hex) of the symbol NAME (mangled), or nothing.
sized() { awk -v s="$1" 'NF == 4 && $4 == s { print $1, $2; exit }' <<<"$sized_symbols"; }
size_of() {
  local hex
  hex=$(sized "$1")
  hex=${hex#* }
  echo $((16#${hex:-0}))
}
# function_at ADDRESS: the mangled name of the function at ADDRESS (as the firmware prints a
# function pointer: hex, the Thumb bit set).
function_at() {
  local address f
  address=$(printf '%08x' $(($1 & ~1)))
  f=$(awk -v a="$address" 'NF == 4 && $1 == a && ($3 == "t" || $3 == "T") { print $4; exit }' <<<"$sized_symbols")
  [ -n "$f" ] || { echo "no function at $1 in $elf" >&2; exit 1; }
  echo "$f"
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
# functions_of VARIANT: "KIND MANGLED" lines, KIND update or update_block: the out-of-line
# functions of VARIANT, from the addresses the firmware prints.
functions_of() {
  local kind address f
  plugin_option="" qemu functions "$1" | while read -r kind address; do
    f=$(function_at "$address")
    echo "$kind $f"
  done
}

# insns SAMPLES VARIANT [block]: "ALL IN_RANGES", the instructions executed by a count run and
# those of them inside the address ranges $ranges (ALL again if $ranges is empty).
insns() {
  local log="$target_dir/insns-$core.log" all in_ranges
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
# per_sample VARIANT [block]: "ALL IN_RANGES" per sample, from runs of ${runs[0]} and
# ${runs[1]} samples.
per_sample() {
  local a b
  a=$(insns "${runs[0]}" "$@")
  b=$(insns "${runs[1]}" "$@")
  awk -v a="$a" -v b="$b" -v n=$((runs[1] - runs[0])) 'BEGIN {
    split(a, x, " "); split(b, y, " ")
    printf "%.1f %.1f", (y[1] - x[1]) / n, (y[2] - x[2]) / n
  }'
}

# code_size LABEL ROOT: the code size line of the function ROOT (mangled) under LABEL.
code_size() {
  local total=0 called=() f
  while read -r f; do
    total=$((total + $(size_of "$f")))
    [ "$f" = "$2" ] || called+=("$(demangled "$f" | sed 's/::<.*//; s/.*:://')")
  done < <(reachable "$2")
  echo "code_size $1: $(size_of "$2") bytes;" \
    "$total bytes with the ${#called[@]} functions it calls (${called[*]:-none})"
}

# run_core CORE: everything above, on one core.
run_core() {
  core_settings "$1"
  cargo build --release --locked -q --target "$target"
  plugin_option=""
  local output checks failed
  if ! output=$(qemu check); then
    echo "$output"
    echo "the check failed ($core)" >&2
    exit 1
  fi
  echo "$output"
  checks=$(grep -c "^check " <<<"$output" || true)
  if output=$(qemu check tamper); then
    echo "$output"
    echo "the check did not fail on corrupted inputs ($core)" >&2
    exit 1
  fi
  # Every check (the same lines as the clean run's) must fail on its corrupted input.
  failed=$(grep -c "^check .*: FAIL$" <<<"$output" || true)
  if [ "$checks" -eq 0 ] || [ "$(grep -c "^check " <<<"$output")" -ne "$checks" ] ||
    [ "$failed" -ne "$checks" ]; then
    echo "$output"
    echo "with corrupted inputs, $failed of $checks checks FAIL; all must ($core)" >&2
    exit 1
  fi
  echo "check with one corrupted input per check ($core): all $failed of $checks checks FAIL," \
    "as they must"

  load_symbols
  local variants variant name kind root counts functions sizes=()
  variants=$(qemu variants)
  ranges=""
  counts=$(per_sample loop)
  echo "insns_per_iteration $(label loop): ${counts% *}"
  for variant in $variants; do
    name=$(label "$variant")
    # Captured first, so that a failure stops the script (set -e).
    functions=$(functions_of "$variant")
    while read -r kind root; do
      ranges=$(measured "$root")
      if [ "$kind" = update ]; then
        counts=$(per_sample "$variant")
        echo "insns_per_update $name: ${counts#* }"
        echo "insns_per_iteration $name: ${counts% *}"
        sizes+=("$name $root")
      else
        counts=$(per_sample "$variant" block)
        echo "insns_per_sample_in_block $name: ${counts#* }"
      fi
    done <<<"$functions"
  done

  # The resolver front end: the demodulator per ADC sample (its once-per-period work
  # amortised over the period's 16 samples); in fixed point only on the Cortex-M0 (its image
  # has no room for the f32 one's inputs).
  local demodulators=(demodulator-f32 demodulator-fixed)
  [ "$core" = m4 ] || demodulators=(demodulator-fixed)
  for variant in "${demodulators[@]}"; do
    name=$(label $variant)
    functions=$(functions_of $variant)
    while read -r kind root; do
      ranges=$(measured "$root")
      if [ "$kind" = update ]; then
        counts=$(per_sample $variant)
        echo "insns_per_push $name: ${counts#* }"
        echo "insns_per_iteration $name: ${counts% *}"
      else
        counts=$(per_sample $variant block)
        echo "insns_per_sample $name: ${counts#* }"
      fi
    done <<<"$functions"
  done

  # Code size: each update function, then with every function it calls (transitively).
  for variant in "${sizes[@]}"; do
    code_size "${variant% *}" "${variant#* }"
  done
}

cores=("$@")
[ ${#cores[@]} -gt 0 ] || cores=(m4 m0)
counts="$target_dir/counts.txt"
# The cores run side by side: QEMU runs a firmware on one host thread, so each core's runs
# take a host core of their own (their builds wait for each other on cargo's lock). Each
# core's output is kept apart and printed in the cores' order when all have finished.
pids=()
for c in "${cores[@]}"; do
  (
    run_core "$c"
    # The C API's calls of the same chains (c/run.sh, the library built in the workspace's
    # target directory), budgeted beside them.
    if [ "$c" = m0 ]; then env -u CARGO_TARGET_DIR bash c/run.sh count m0; fi
  ) >"$target_dir/counts-$c.txt" 2>"$target_dir/counts-$c.log" &
  pids+=($!)
done
failed=0
for i in "${!cores[@]}"; do
  wait "${pids[$i]}" || { failed=1; echo "FAIL: the firmware test on ${cores[$i]} (its output below)" >&2; }
done
: >"$counts"
for c in "${cores[@]}"; do
  cat "$target_dir/counts-$c.log" >&2
  tee -a "$counts" <"$target_dir/counts-$c.txt"
done
[ "$failed" -eq 0 ] || exit 1
bash budgets.sh check "$counts" "${cores[@]}"
bash budgets.sh tamper "$counts" "${cores[@]}"
