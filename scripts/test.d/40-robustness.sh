#!/usr/bin/env bash
# Robustness of the core: no panic path in the f32 update (proved by linking, for a
# Cortex-M4F and a Cortex-M0), no f64 software routine on the Fast path, the C API's tests
# under Miri (the core's too with ANGLETRACK_MIRI=all), and each fuzz target for half a
# minute on the corpus kept in fuzz/corpus.
set -euo pipefail
source scripts/lib.sh
need_rust
fuzz_seconds="${ANGLETRACK_FUZZ_SECONDS:-30}"

rustup component add llvm-tools >/dev/null
nm_tool=$(ls "$(rustc --print sysroot)"/lib/rustlib/*/bin/llvm-nm | head -n 1)
rustup toolchain install nightly --profile minimal >/dev/null 2>&1 || true
rustup +nightly component add miri rust-src >/dev/null
if [[ "$(cargo fuzz --version 2>/dev/null || true)" != *" 0.13."* ]]; then
  cargo install cargo-fuzz --version 0.13.2 --locked
fi

# The fuzz targets' build (nightly, AddressSanitizer), the longest build of this step and one
# that keeps both cores busy, starts first, in the background, beside the no-panic images and
# Miri, which leave a core idle most of the time (one link-time-optimised image at a time;
# Miri's interpreter on one thread). `cargo fuzz build` takes the same defaults as `cargo
# fuzz run` (release, debug assertions and overflow checks, AddressSanitizer) and builds
# every target; the fuzzing below waits for it.
scratch=$(mktemp -d)
(cd fuzz && exec cargo +nightly fuzz build) >"$scratch/fuzz-build.log" 2>&1 &
fuzz_build=$!
trap 'kill "$fuzz_build" 2>/dev/null || true; rm -rf "$scratch"' EXIT

# The images (tests/no-panic) are built for each core: adding one is one word here.
no_panic_targets=(thumbv7em-none-eabihf thumbv6m-none-eabi)
echo "--- no panic path in the f32 and fixed-point updates (tests/no-panic, ${no_panic_targets[*]})"
image_symbols() { # $1: target; $2: cargo feature flags; prints the image's demangled symbol names
  (cd tests/no-panic && cargo build -q --release --target-dir target --target "$1" $2)
  "$nm_tool" -C --just-symbol-name "tests/no-panic/target/$1/release/angletrack-no-panic"
}
# Each image's symbols are captured first, so that a failed build stops the script (set -e)
# instead of reading as "no symbol found", and so that grep reads a finished list: piping
# nm into `grep -q` under pipefail fails at random when grep exits before nm has written
# everything (nm dies of SIGPIPE). Names only: an address such as 0000df30 is no df routine.
panics='rust_begin_unwind|core::panicking::'
# compiler-builtins' soft-float f64 routines (thumbv6m and thumbv7em alike): the ARM ABI's
# __aeabi_d* (dadd, dcmpeq, d2f, d2iz...), __aeabi_cd*, and conversions into f64
# (__aeabi_f2d, i2d, ui2d, l2d, ul2d); the generic names all contain "df" (__adddf3,
# __extendsfdf2, __truncdfsf2, __floatsidf, __fixdfsi, __eqdf2, __powidf2...), demangled
# bare or under a path (compiler_builtins::float::add::__adddf3). Integer routines such as
# __aeabi_uidiv or __udivmoddi4 do not match.
f64_routines='\b(__aeabi_c?d[a-z0-9_]+|__aeabi_[a-z]+2d|__[a-z]+df[a-z0-9]*)\b'
for target in "${no_panic_targets[@]}"; do
  symbols=$(image_symbols "$target" "")
  if grep -E "$panics" <<<"$symbols"; then
    echo "FAIL: a panic path remains in the f32 or fixed-point update on $target (symbols above)" >&2; exit 1
  fi
  # The Exact sin/cos (libm's sinf/cosf compute in f64) link f64 routines: the check sees them.
  if ! grep -qE "$f64_routines" <<<"$symbols"; then
    echo "FAIL: no f64 routine found in the image with the Exact path on $target" >&2; exit 1
  fi
  symbols=$(image_symbols "$target" "--no-default-features")
  if grep -E "$panics|$f64_routines" <<<"$symbols"; then
    echo "FAIL: the Fast-only f32 image for $target has a panic path or f64 software routines (above)" >&2
    exit 1
  fi
  symbols=$(image_symbols "$target" "--features panic-control")
  if ! grep -qE "$panics" <<<"$symbols"; then
    echo "FAIL: the negative control (a call that can panic) was not detected on $target" >&2; exit 1
  fi
  echo "$target: no panic path; no f64 routine on the Fast path (the Exact path's are found);" \
    "the negative control is detected"
done

echo "--- Miri: the C API's tests (its unsafe slots and extern calls)"
# The workspace optimises its test builds; Miri ignores opt-level and warns, so it gets 0.
# Miri checks what nothing else does where there is unsafe code: the C API's boundary (under
# Miri its libm runs portable code: the x86 sqrt is inline assembly, which Miri cannot run).
# The core forbids unsafe code, its arithmetic is checked for overflow by `cargo test`, and
# its tests take about 10 minutes of Miri's interpreter (half of this command's budget): they
# run under Miri on request (ANGLETRACK_MIRI=all).
# Three tests track half a second of signal through the chains to check convergence
# (a minute each under Miri), one a quarter second of resolver windings through the
# demodulator, one two turns of counts for the rails held flat (7 s); every extern function
# they call is called by another test, so Miri skips them and `cargo test` runs them. So
# does the test of the correction tables' values, which calls no extern function (its 512
# sines in software floating point took 7 % of Miri's time).
cargo +nightly miri test --config profile.test.opt-level=0 -p angletrack-c --lib -- \
  --skip tests::both_orders_track_a_constant_speed --skip tests::adc_counts_track_as_floats_do \
  --skip tests::calibration_learns_offsets_and_round_trips \
  --skip tests_demodulator::a_10_ms_loss_of_excitation_through_the_demodulator_is_coasted_through \
  --skip tests_front_end::without_a_stated_range_the_rails_held_flat_are_found \
  --skip tests_units::tables_agree_with_their_harmonics
if [ "${ANGLETRACK_MIRI:-}" = all ]; then
  cargo +nightly miri test --config profile.test.opt-level=0 -p angletrack-core --lib \
    --features libm/force-soft-floats
fi

echo "--- fuzzing (${fuzz_seconds} s per target)"
status=0
wait "$fuzz_build" || status=$?
if [ "$status" -ne 0 ]; then
  tail -n 60 "$scratch/fuzz-build.log" >&2
  echo "FAIL: the fuzz targets' build failed (status $status)" >&2; exit 1
fi
# libFuzzer writes the inputs it finds into its first corpus directory and only reads the
# others: the kept corpus (fuzz/corpus) is read, and the new inputs go to a scratch
# directory, so that a test run leaves the working tree as it found it.
found=$(mktemp -d)
targets=$(cd fuzz && cargo +nightly fuzz list)
# The targets fuzz side by side: libFuzzer runs in one process on one core, and each gets the
# same half minute of its own core as when they ran one after the other (`-max_total_time`
# is wall time).
for target in $targets; do
  mkdir -p "fuzz/corpus/$target" "$found/$target"
  (cd fuzz && exec cargo +nightly fuzz run "$target" "$found/$target" "corpus/$target" -- \
    -max_len=4096 -max_total_time="$fuzz_seconds" -print_final_stats=1) >"$found/$target.log" 2>&1 &
  echo $! >"$found/$target.pid"
done
failed=0
for target in $targets; do
  status=0
  wait "$(cat "$found/$target.pid")" || status=$?
  log="$found/$target.log"
  grep -E "^Done|stat::number_of_executed_units|panicked|SUMMARY|ERROR" "$log" || true
  echo "$target: $(ls "$found/$target" | wc -l) new inputs beyond fuzz/corpus/$target (in $found/$target)"
  if [ "$status" -ne 0 ]; then
    tail -n 40 "$log" >&2
    echo "FAIL: fuzz target $target failed (status $status)" >&2; failed=1
  fi
done
[ "$failed" -eq 0 ] || exit 1
