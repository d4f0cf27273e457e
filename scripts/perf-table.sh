#!/usr/bin/env bash
# Regenerates the performance tables of the user guide, docs/guide/performance.md:
#  - between the firmware-table markers, instructions per update and code size on a
#    Cortex-M4F and a Cortex-M0 of every variant of the firmware test under QEMU
#    (tests/firmware/run.sh), beside the atan2 + PLL baselines with the ratio to each;
#  - between the perf-table markers, ns per sample on this host and the ratio to the
#    hand-written loop, and the multi-channel throughput (ChannelBank), from the criterion
#    benchmarks (benches/, short measurement: 1 s warm-up, 3 s per benchmark), built for the
#    portable x86-64 baseline (SSE2) as cargo builds by default; the multi-channel rows again
#    built with `-C target-cpu=x86-64-v3` (AVX2 and FMA: 8 f32 lanes) when this CPU has them.
# Usage: bash scripts/perf-table.sh [--firmware] [--counts FILE] [--print]
#        bash scripts/perf-table.sh --check FILE
#   --firmware: the firmware table only (about a minute; the host table takes about 8);
#   --counts FILE: the firmware table from FILE, the output of an earlier run of
#     tests/firmware/run.sh (kept in tests/firmware/target/counts.txt), instead of a new run;
#   --print: print the tables, leave the guide;
#   --check FILE: no run and no change: fails unless the guide's firmware table is the one
#     FILE's counts give (the same rows, every number within 5 %), as
#     scripts/test.d/30-firmware.sh checks after each firmware test.
# Host figures depend on the machine: run it on a quiet one. Firmware counts do not.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
page=docs/guide/performance.md

firmware_only=false print=false counts="" check=""
while [ $# -gt 0 ]; do
  case $1 in
    --firmware) firmware_only=true ;;
    --print) print=true ;;
    --counts) counts=${2:?--counts needs a file}; shift ;;
    --check) check=${2:?--check needs a file}; firmware_only=true; counts=$check; shift ;;
    *) echo "usage: bash scripts/perf-table.sh [--firmware] [--counts FILE] [--print] | --check FILE" >&2; exit 1 ;;
  esac
  shift
done
if [ -z "$check" ]; then
  need_rust
  need_debian_packages qemu-system-arm gcc libc6-dev binutils-arm-none-eabi
fi

if [ -n "$counts" ]; then
  firmware=$(cat "$counts")
else
  firmware=$(bash tests/firmware/run.sh)
fi
firmware_value() { sed -n "s/^$1: //p" <<<"$firmware" | head -n1; }

# describe VARIANT: the table's words for a variant of tests/firmware/src/variants.rs (its
# name in backquotes for one not listed here).
describe() {
  case $1 in
    kalman-f32-fast) echo "Kalman ATO, \`f32\`, fast sin/cos" ;;
    kalman-f32-fast-unmonitored) echo "Kalman ATO, \`f32\`, fast sin/cos, diagnostics off" ;;
    kalman-f32-exact) echo "Kalman ATO, \`f32\`, exact sin/cos (\`libm\`)" ;;
    kalman-f32-fast-calibrated) echo "Kalman ATO, \`f32\`, fast, online calibration learning (a chain's \`update\`)" ;;
    kalman-f32-fast-calibrated-off) echo "Kalman ATO, \`f32\`, fast, online calibration off (a chain's \`update\`)" ;;
    kalman-f32-fast-track) echo "Kalman ATO, \`f32\`, fast sin/cos, \`track\` (estimate on demand)" ;;
    kalman-f32-fast-track-unmonitored) echo "Kalman ATO, \`f32\`, fast sin/cos, \`track\`, diagnostics off" ;;
    kalman-f32-fast-track-calibrated-off) echo "Kalman ATO, \`f32\`, fast, a chain's \`track\`, online calibration off" ;;
    kalman-f32-fast-track-corrected) echo "Kalman ATO, \`f32\`, fast, a chain's \`track\`, stored calibration and angle table" ;;
    kalman-f32-fast-adc) echo "Kalman ATO, \`f32\`, fast, from 12-bit counts (an \`AdcScaling\` chain)" ;;
    kalman-f32-fast-angle-corrected) echo "Kalman ATO, \`f32\`, fast, angle correction of order 4 (an \`AngleCorrection\` chain)" ;;
    kalman-fixed) echo "Kalman ATO, fixed point" ;;
    kalman-fixed-track) echo "Kalman ATO, fixed point, \`track\` (estimate on demand)" ;;
    kalman-fixed-track-unmonitored) echo "Kalman ATO, fixed point, \`track\`, diagnostics off" ;;
    kalman-fixed-track-corrected) echo "Kalman ATO, fixed point, a chain's \`track\`, stored calibration and angle table" ;;
    second-order-f32-fast) echo "2nd-order ATO, \`f32\`, fast sin/cos" ;;
    second-order-f32-exact) echo "2nd-order ATO, \`f32\`, exact sin/cos" ;;
    third-order-f32-fast) echo "3rd-order ATO (pole placement), \`f32\`, fast sin/cos" ;;
    third-order-f32-exact) echo "3rd-order ATO (pole placement), \`f32\`, exact sin/cos" ;;
    baseline-atan2-pll-f32) echo "**baseline**: \`libm\` \`atan2f\` + 2nd-order PLL, \`f32\`" ;;
    baseline-fast-atan2-pll-f32) echo "**baseline**: fast atan2 (error 1.51e-3 rad) + 2nd-order PLL, \`f32\`" ;;
    *) echo "\`$1\`" ;;
  esac
}
# cells LABEL [SUFFIX]: the instructions per update of LABEL and its ratio to each baseline
# on the same core (the baselines' labels end in SUFFIX: -m0 on the Cortex-M0); empty cells
# if the firmware test did not print it.
cells() {
  local n core_suffix=${2:-}
  n=$(firmware_value "insns_per_update $1")
  if [ -z "$n" ]; then
    echo " | | "
    return
  fi
  awk -v n="$n" -v a="$(firmware_value "insns_per_update baseline-atan2-pll-f32$core_suffix")" \
    -v b="$(firmware_value "insns_per_update baseline-fast-atan2-pll-f32$core_suffix")" \
    'BEGIN { printf "%s | %.2f | %.2f", n, n / a, n / b }'
}
# code LABEL: "own (with callees)" bytes of LABEL's update.
code() {
  firmware_value "code_size $1" | sed -n 's/^\([0-9]*\) bytes; \([0-9]*\) bytes with .*/\1 (\2)/p'
}

firmware_table=$(mktemp)
host_table=$(mktemp)
trap 'rm -f "$firmware_table" "$host_table"' EXIT
{
  echo "Generated by \`bash scripts/perf-table.sh --firmware\` from the firmware test's counts ($(rustc --version | cut -d' ' -f1-2), commit $(git rev-parse --short HEAD));"
  echo "\`scripts/test.d/30-firmware.sh\` fails unless every figure is within 5 % of its latest run's."
  echo
  echo "**Cortex-M4F and Cortex-M0** (QEMU \`mps2-an386\` and \`microbit\`, opt-level 3, fat LTO; the"
  echo "Cortex-M0 has no FPU: every \`f32\` operation is a call to a soft-float routine):"
  echo "instructions per update, counted by the TCG plugin of \`tests/firmware\` inside the"
  echo "variant's out-of-line update and the functions it calls, per call, over samples 1000 to"
  echo "2000 of the benchmark signal; in the next columns, that count over the baselines' on the"
  echo "same core (below 1: cheaper than the baseline). The default diagnostics run unless"
  echo "\"diagnostics off\" (\`FaultThresholds::disabled()\`: the bare loop of the paper). The"
  echo "baselines are what open firmware does instead (the ODrive style): the angle of each"
  echo "sample by an arctangent, tracked by a critically damped 2nd-order PLL of the same 50 Hz"
  echo "as the 2nd-order ATO (\`tests/firmware/src/baseline.rs\`). Code: bytes of the update"
  echo "function, and in parentheses with the out-of-line functions it calls (\`libm\`, and on the"
  echo "Cortex-M0 the soft-float routines)."
  echo
  echo "| variant | M4F | / \`atan2f\` + PLL | / fast atan2 + PLL | M0 | / \`atan2f\` + PLL | / fast atan2 + PLL | code M4F | code M0 |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
  # One row per variant, in the firmware's order: its M4F label (the f32 variants' names,
  # or NAME-m4), its M0 label NAME-m0.
  sed -n 's/^insns_per_update \(.*\): .*/\1/p' <<<"$firmware" | grep -v -- '-m0$' |
    while read -r m4; do
      name=${m4%-m4}
      echo "| $(describe "$name") | $(cells "$m4") | $(cells "$name-m0" -m0) | $(code "$m4") | $(code "$name-m0") |"
    done
  echo
  echo "Per sample inside one block update (\`Chain::update_block\`; 200 samples a call on the"
  echo "Cortex-M0, whose 16 KiB of RAM hold no more estimates), M4F / M0:"
  echo
  sed -n 's/^insns_per_sample_in_block \(.*\): \(.*\)/\1 \2/p' <<<"$firmware" | grep -v -- '-m0 ' |
    while read -r m4 n; do
      echo "$(describe "${m4%-m4}"): $n / $(firmware_value "insns_per_sample_in_block ${m4%-m4}-m0");"
    done | sed '$ s/;$/./; s/^/- /'
  echo
  echo "The calling loop adds $(awk -v a="$(firmware_value 'insns_per_iteration kalman-f32-fast')" \
    -v b="$(firmware_value 'insns_per_update kalman-f32-fast')" 'BEGIN { printf "%.1f", a - b }') instructions per sample on the Cortex-M4F"
  echo "(loading the inputs, the call, storing the estimate). The resolver front end's synchronous"
  echo "demodulator (16 ADC samples per carrier period, its once-per-period work included) costs"
  echo "$(firmware_value 'insns_per_push demodulator-f32') / $(firmware_value 'insns_per_push demodulator-fixed-m0') instructions per ADC sample (M4F in f32 / M0 in fixed point) with one"
  echo "\`Demodulator::push\` call each, $(firmware_value 'insns_per_sample demodulator-f32') / $(firmware_value 'insns_per_sample demodulator-fixed-m0') in one \`Demodulator::push_block\` call."
} >"$firmware_table"

# replace_section NAME FILE: the guide's lines between <!-- NAME:begin --> and
# <!-- NAME:end --> replaced by FILE.
replace_section() {
  grep -q "^<!-- $1:begin -->$" "$page" && grep -q "^<!-- $1:end -->$" "$page" || {
    echo "$page has no <!-- $1:begin --> / <!-- $1:end --> markers" >&2
    exit 1
  }
  awk -v table="$2" -v begin="<!-- $1:begin -->" -v end="<!-- $1:end -->" '
    $0 == end { skip = 0 }
    !skip { print }
    $0 == begin { while ((getline line < table) > 0) print line; skip = 1 }
  ' "$page" >"$page.new"
  mv "$page.new" "$page"
}

# check_section NAME FILE: fails unless the guide's lines between the NAME markers are FILE's
# but for the first line (the provenance: rustc, commit), with each number within 5 % (and
# 0.01, the ratios' rounding) of FILE's and every other character the same.
check_section() {
  python3 - "$page" "$1" "$2" <<'PYTHON'
import re, sys
page, name, table = sys.argv[1:]
text = open(page, encoding="utf-8").read()
begin, end = f"<!-- {name}:begin -->\n", f"\n<!-- {name}:end -->"
if begin not in text or end not in text:
    sys.exit(f"FAIL: {page} has no {begin.strip()} / {end.strip()} markers")
shown = text.split(begin, 1)[1].split(end, 1)[0].splitlines()[1:]
generated = open(table, encoding="utf-8").read().rstrip("\n").splitlines()[1:]
number = re.compile(r"\d+(?:\.\d+)?(?:e-?\d+)?")
problems = []
if len(shown) != len(generated):
    problems.append(f"{len(shown)} lines in the guide, {len(generated)} generated")
for k, (a, b) in enumerate(zip(shown, generated), start=2):
    if number.sub("#", a) != number.sub("#", b):
        problems.append(f"line {k} of the table differs:\n  guide:     {a}\n  generated: {b}")
        continue
    for x, y in zip(map(float, number.findall(a)), map(float, number.findall(b))):
        if abs(x - y) > 0.05 * max(abs(x), abs(y)) + 0.01:
            problems.append(f"line {k}: {x:g} in the guide, {y:g} measured:\n  {b}")
if problems:
    print("\n".join(problems), file=sys.stderr)
    sys.exit(f"FAIL: {page}'s {name} is not the firmware test's: regenerate it with "
             f"`bash scripts/perf-table.sh --firmware --counts tests/firmware/target/counts.txt`")
print(f"{page}: the {name} is the one the firmware test's counts give (within 5 %)")
PYTHON
}

if [ -n "$check" ]; then
  check_section firmware-table "$firmware_table"
  exit 0
fi
if $firmware_only; then
  if $print; then
    cat "$firmware_table"
  else
    replace_section firmware-table "$firmware_table"
    cat "$firmware_table"
    echo "$page: firmware table updated" >&2
  fi
  exit 0
fi

target_dir=$(cargo metadata --format-version 1 --no-deps |
  sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
cargo bench -q -p angletrack-benches --bench update -- \
  --warm-up-time 1 --measurement-time 3 --noplot >/dev/null
v3_dir="$target_dir/x86-64-v3"
has_v3=false
if grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo && grep -qw bmi2 /proc/cpuinfo; then
  has_v3=true
  RUSTFLAGS="-C target-cpu=x86-64-v3" CARGO_TARGET_DIR="$v3_dir" cargo bench -q \
    -p angletrack-benches --bench update -- '/(update-fast-unmonitored|bank-fast-16|bank-fast-64)$' \
    --warm-up-time 1 --measurement-time 3 --noplot >/dev/null
fi

# ns_per_sample GROUP ID [TARGET_DIR]: the fastest of criterion's samples (time per iteration over the
# throughput). The fastest, not the median: on a shared machine other load only ever adds
# time, and the median moved by 4x between runs there; criterion's report keeps the spread.
ns_per_sample() {
  local dir="${3:-$target_dir}/criterion/$1/$2/new"
  local elements
  elements=$(sed -E 's/.*"throughput":\{"Elements":([0-9]+)\}.*/\1/' "$dir/benchmark.json")
  sed -E 's/.*"iters":\[([^]]*)\].*"times":\[([^]]*)\].*/\1;\2/' "$dir/sample.json" |
    awk -F';' -v e="$elements" '{
      n = split($1, iters, ","); split($2, times, ",")
      for (i = 1; i <= n; i++) { t = times[i] / iters[i]; if (i == 1 || t < best) best = t }
      printf "%.2f", best / e
    }'
}

# bank_row GROUP BUILD TARGET_DIR: one row of the multi-channel table, "observer | float |
# build | single stream | bank of 16 (gain) | bank of 64 (gain)".
bank_row() {
  local single row bank lanes
  single=$(ns_per_sample "$1" update-fast-unmonitored "$3")
  row="| ${1%-*} | ${1##*-} | $2 | $single"
  for lanes in 16 64; do
    bank=$(ns_per_sample "$1" "bank-fast-$lanes" "$3")
    row+=" | $bank ($(awk -v a="$single" -v b="$bank" 'BEGIN { printf "%.1fx", a / b }'))"
  done
  echo "$row |"
}

cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)
{
  echo "Generated by \`bash scripts/perf-table.sh\` ($(rustc --version | cut -d' ' -f1-2), commit $(git rev-parse --short HEAD)); measured, not checked by the test command."
  echo
  echo "**Host** (${cpu:-unknown CPU}, one stream): ns per sample (fastest criterion sample), and in"
  echo "parentheses the ratio to the hand-written loop (one struct, the standard library's"
  echo "\`sin_cos\`, explicit wrap) on the same samples."
  echo
  echo "| observer | float | hand-written | update, exact | update, fast | block, exact | block, fast | update, fast, diagnostics off |"
  echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
  bank_rows=""
  for observer in second-order third-order kalman; do
    for float in f32 f64; do
      group="$observer-$float"
      base=$(ns_per_sample "$group" baseline)
      row="| $observer | $float | $base"
      for id in update-exact update-fast block-exact block-fast update-fast-unmonitored; do
        ns=$(ns_per_sample "$group" "$id")
        row+=" | $ns ($(awk -v a="$ns" -v b="$base" 'BEGIN { printf "%.2f", a / b }'))"
      done
      echo "$row |"
      bank_rows+="$(bank_row "$group" x86-64 "$target_dir")"$'\n'
      if $has_v3; then
        bank_rows+="$(bank_row "$group" x86-64-v3 "$v3_dir")"$'\n'
      fi
    done
  done
  echo
  echo "**Host, multi-channel**: \`ChannelBank\`s of 16 and 64 channels sharing one gain set"
  echo "(fast sin/cos; a bank runs no fault monitor), ns per channel-sample, and in parentheses the"
  echo "throughput per channel-sample over that of one stream of \`Chain::update\` doing the same"
  echo "work (fast sin/cos, diagnostics off). Build \`x86-64\` is the one above (portable: SSE2,"
  echo "4 \`f32\` lanes); \`x86-64-v3\` is the same benchmarks built with"
  echo "\`RUSTFLAGS=\"-C target-cpu=x86-64-v3\"\` (AVX2 and FMA: 8 \`f32\` lanes), where this CPU has it."
  echo
  echo "| observer | float | build | single stream | bank of 16 | bank of 64 |"
  echo "| --- | --- | --- | ---: | ---: | ---: |"
  printf '%s' "$bank_rows"
} >"$host_table"

if $print; then
  cat "$firmware_table" "$host_table"
  exit 0
fi
replace_section firmware-table "$firmware_table"
replace_section perf-table "$host_table"
cat "$firmware_table" "$host_table"
echo "$page: performance tables updated" >&2
