#!/usr/bin/env bash
# Regenerates the performance table of README.md (between the perf-table markers):
#  - instructions per update and code size of the f32 update on a Cortex-M4F, from the
#    firmware test under QEMU (tests/firmware/run.sh);
#  - ns per sample on this host and the ratio to the hand-written loop, and the multi-channel
#    throughput (ChannelBank), from the criterion benchmarks (benches/, short measurement:
#    1 s warm-up, 3 s per benchmark), built for the portable x86-64 baseline (SSE2) as cargo
#    builds by default; the multi-channel rows again built with `-C target-cpu=x86-64-v3`
#    (AVX2 and FMA: 8 f32 lanes) when this CPU has them.
# Usage: bash scripts/perf-table.sh [--print]   (--print: print the table, leave README.md)
# Takes about 8 minutes. Host figures depend on the machine: run it on a quiet one.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
need_rust
need_debian_packages qemu-system-arm gcc libc6-dev binutils-arm-none-eabi

firmware=$(bash tests/firmware/run.sh)
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

firmware_value() { sed -n "s/^$1: //p" <<<"$firmware" | head -n1; }

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
table=$(mktemp)
trap 'rm -f "$table"' EXIT
{
  echo "Measured with \`bash scripts/perf-table.sh\` ($(rustc --version | cut -d' ' -f1-2), commit $(git rev-parse --short HEAD))."
  echo
  echo "**Cortex-M4F** (QEMU \`mps2-an386\`, \`f32\`, opt-level 3, fat LTO): instructions per"
  echo "update, counted by the TCG plugin of \`tests/firmware\` inside the measured function and"
  loop_cost=$(awk -v a="$(firmware_value 'insns_per_iteration kalman-f32-fast')" \
    -v b="$(firmware_value 'insns_per_update kalman-f32-fast')" 'BEGIN { printf "%.1f", a - b }')
  echo "the functions it calls: one \`Gains::update\` call (the calling loop adds $loop_cost"
  echo "per sample: loading the inputs, the call, storing the estimate), or per sample of one"
  echo "\`Gains::update_block\` call. The default diagnostics run, except in the last row"
  echo "(\`FaultThresholds::disabled()\`: the bare loop of the paper)."
  echo
  echo "| observer | exact sin/cos (\`libm\`) | exact, in a block | fast sin/cos | fast, in a block |"
  echo "| --- | ---: | ---: | ---: | ---: |"
  # cells VARIANT: its per-call and in-a-block counts as two table cells.
  cells() {
    echo "$(firmware_value "insns_per_update $1") | $(firmware_value "insns_per_sample_in_block $1")"
  }
  for observer in second-order:"2nd-order ATO" third-order:"3rd-order ATO (pole placement)" \
    kalman:"Kalman ATO"; do
    id=${observer%%:*}
    echo "| ${observer#*:} | $(cells "$id-f32-exact") | $(cells "$id-f32-fast") |"
  done
  echo "| Kalman ATO, diagnostics off | | | $(cells kalman-f32-fast-unmonitored) |"
  echo
  echo "The resolver front end's synchronous demodulator (16 ADC samples per carrier period,"
  echo "its once-per-period work included): $(firmware_value 'insns_per_sample_pair demodulator-f32')"
  echo "instructions per ADC sample pair with one \`Demodulator::push\` call each,"
  echo "$(firmware_value 'insns_per_sample_pair_in_block demodulator-f32') in one \`Demodulator::push_block\` call (a DMA buffer)."
  echo
  echo "Code size of the \`f32\` update with fast sin/cos (\`Gains::update\`), alone and with"
  echo "the out-of-line functions it calls:"
  echo
  for order in 2 3; do
    echo "- order $order: $(firmware_value "code_size update-order$order-f32-fast" |
      sed 's/^\([0-9]*\) bytes; \([0-9]*\) bytes with the .* functions it calls (\(.*\))/\1 bytes; \2 bytes with \3/')"
  done
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
  echo "throughput per channel-sample over that of one stream of \`Gains::update\` doing the same"
  echo "work (fast sin/cos, diagnostics off). Build \`x86-64\` is the one above (portable: SSE2,"
  echo "4 \`f32\` lanes); \`x86-64-v3\` is the same benchmarks built with"
  echo "\`RUSTFLAGS=\"-C target-cpu=x86-64-v3\"\` (AVX2 and FMA: 8 \`f32\` lanes), where this CPU has it."
  echo
  echo "| observer | float | build | single stream | bank of 16 | bank of 64 |"
  echo "| --- | --- | --- | ---: | ---: | ---: |"
  printf '%s' "$bank_rows"
} >"$table"

if [ "${1:-}" = --print ]; then
  cat "$table"
  exit 0
fi
grep -q '^<!-- perf-table:begin -->$' README.md && grep -q '^<!-- perf-table:end -->$' README.md || {
  echo "README.md has no <!-- perf-table:begin --> / <!-- perf-table:end --> markers" >&2
  exit 1
}
awk -v table="$table" '
  /^<!-- perf-table:end -->$/ { skip = 0 }
  !skip { print }
  /^<!-- perf-table:begin -->$/ { while ((getline line < table) > 0) print line; skip = 1 }
' README.md >README.md.new
mv README.md.new README.md
cat "$table"
echo "README.md: performance table updated" >&2
