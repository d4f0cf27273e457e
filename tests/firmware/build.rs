//! Computes the firmware's reference on the host: the simulated resolver of the benchmarks
//! (`angletrack-benches`), and every variant (observers and baselines) run over it by the same
//! code in `f32`. The firmware embeds both and checks its own estimates against them.

use std::{env, fs, path::PathBuf};

use angletrack_benches::{
    KALMAN_GAINS, SECOND_ORDER_GAINS, THIRD_ORDER_GAINS, benchmark_scenario, channels,
};
#[path = "src/baseline.rs"]
// Shared with the firmware, which alone checks the fast arctangent's error bound.
#[allow(dead_code)]
mod baseline;
#[path = "src/chains.rs"]
// Shared with the firmware.
#[allow(dead_code)]
mod chains;
#[path = "src/trackers.rs"]
// Shared with the firmware.
#[allow(dead_code)]
mod trackers;
#[path = "src/variants.rs"]
// Shared with the firmware, which alone reads the records back (`decode`).
#[allow(dead_code)]
mod variants;

use angletrack_core::DemodulatorNumber;
use angletrack_core::DemodulatorState;
use variants::{
    CARRIER_AMPLITUDE_COUNTS, CARRIER_DELAY_RAD, FNV_OFFSET, Job, NAMES, Observers,
    SAMPLES_PER_PERIOD, Tracker, demodulator, encode_pair, fold_integers,
};

/// Samples of the simulated resolver (0.2 s at 10 kHz, about 11 turns): the inputs of
/// every run, on both cores.
const SAMPLES: usize = 2000;
/// Samples whose estimates the Cortex-M0 checks within tolerances (the first 20 ms, through
/// the acquisition): every variant's reference records must fit its 256 KiB of flash, with
/// a few KiB to spare (the Cortex-M4F checks all; the fixed-point variants' integers are
/// checked over all samples on both).
const CHECKED_SAMPLES_M0: usize = 200;
/// The most samples of one block update on the Cortex-M0, whose estimates must fit its
/// 16 KiB of RAM with the stack the rest needs (the Cortex-M4F runs all in one block).
const BLOCK_SAMPLES_M0: usize = 160;

/// Largest accepted difference (rad) of every variant's multi-turn position from the
/// simulated shaft's over the second half of the samples, once the loops have settled: the
/// sensor noise (0.01) and the baselines' lag under acceleration (4 mrad) are within it. A
/// sanity check of the variants themselves (a baseline that did not track would be no
/// baseline); the firmware's own check is against the records, much tighter.
const TRACKING_TOLERANCE_RAD: f64 = 0.03;

/// Runs a variant over the signal and appends its reference records (of the first
/// `checked` samples).
struct Reference<'a> {
    y_c: &'a [f32],
    y_s: &'a [f32],
    /// The simulated shaft's angle (rad, multi-turn).
    angle_rad: &'a [f64],
    checked: usize,
    records: Vec<u8>,
    /// Per variant, the hash of its integers over all samples (fixed-point variants only).
    integers: Vec<Option<u64>>,
}

impl Job for Reference<'_> {
    fn run<T: Tracker>(&mut self, index: usize, tracker: T) {
        let mut state = tracker.new_state();
        let mut worst = 0.0f64;
        let mut integers = None;
        for (k, (&c, &s)) in self.y_c.iter().zip(self.y_s).enumerate() {
            let output = tracker.update(&mut state, T::input(c), T::input(s));
            if let Some(words) = tracker.integers(&state, &output) {
                integers = Some(fold_integers(integers.unwrap_or(FNV_OFFSET), &words));
            }
            let record = tracker.record(&state, &output);
            if k < self.checked {
                self.records.extend_from_slice(&record.encode());
            }
            let position =
                f64::from(record.turns) * std::f64::consts::TAU + f64::from(record.angle);
            if 2 * k >= self.y_c.len() {
                worst = worst.max((position - self.angle_rad[k]).abs());
            }
        }
        assert!(
            worst <= TRACKING_TOLERANCE_RAD,
            "{} does not track the shaft: {worst} rad off",
            NAMES[index]
        );
        assert_eq!(self.integers.len(), index, "variants run in order");
        self.integers.push(integers);
    }
}

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    // The Cortex-M0 (thumbv6m) build runs on QEMU's micro:bit (nRF51), the other on mps2-an386.
    let m0 = env::var("TARGET").is_ok_and(|t| t.starts_with("thumbv6m"));
    let (memory, checked, block) = if m0 {
        ("memory-m0.x", CHECKED_SAMPLES_M0, BLOCK_SAMPLES_M0)
    } else {
        ("memory-m4.x", SAMPLES, SAMPLES)
    };
    fs::copy(memory, out.join("memory.x")).expect("memory.x is readable");
    println!("cargo:rustc-link-search={}", out.display());
    // Named apart (not memory.x): the linker looks in the package's directory first.
    for input in [
        "memory-m4.x",
        "memory-m0.x",
        "src/variants.rs",
        "src/trackers.rs",
        "src/chains.rs",
        "src/baseline.rs",
    ] {
        println!("cargo:rerun-if-changed={input}");
    }

    let observers = Observers {
        second_order: SECOND_ORDER_GAINS.map(|v| v as f32),
        third_order: THIRD_ORDER_GAINS.map(|v| v as f32),
        kalman: KALMAN_GAINS.map(|v| v as f32),
        sample_period_s: angletrack_benches::SAMPLE_PERIOD_S as f32,
    };
    let scenario = benchmark_scenario(SAMPLES);
    let (y_c, y_s) = channels::<f32>(&scenario);
    let mut reference = Reference {
        y_c: &y_c,
        y_s: &y_s,
        angle_rad: &scenario.angle_rad,
        checked,
        records: Vec::new(),
        integers: Vec::new(),
    };
    for (index, name) in NAMES.iter().enumerate() {
        assert_eq!(
            observers.run(index, &mut reference),
            Ok(true),
            "gains of {name} refused"
        );
    }
    fs::write(out.join("reference.bin"), &reference.records).expect("OUT_DIR is writable");
    // `count` mode's inputs of the trackers that take counts, converted here rather than in
    // the counted loop (`trackers::Inputs`).
    let counts = |convert: fn(f32) -> i16, y: &[f32]| -> Vec<i16> {
        y.iter().map(|&y| convert(y)).collect()
    };
    let (adc_c, adc_s) = (
        counts(trackers::adc_counts, &y_c),
        counts(trackers::adc_counts, &y_s),
    );
    let (fixed_c, fixed_s) = (
        counts(trackers::fixed_counts, &y_c),
        counts(trackers::fixed_counts, &y_s),
    );
    let (raw_c, raw_s) = demodulator_inputs(&y_c, &y_s);
    let (raw_c16, raw_s16): (Vec<i16>, Vec<i16>) = (
        raw_c.iter().map(|&c| c as i16).collect(),
        raw_s.iter().map(|&s| s as i16).collect(),
    );
    // The Cortex-M0's flash (256 KiB) holds the fixed-point demodulator's inputs only: the
    // f32 one (in software floats there) is not run on it.
    let f32_samples = if m0 { 0 } else { SAMPLES };
    let (raw_c, raw_s) = (&raw_c[..f32_samples], &raw_s[..f32_samples]);
    fs::write(
        out.join("demodulator.bin"),
        demodulator_reference::<f32>(raw_c, raw_s),
    )
    .expect("OUT_DIR is writable");
    fs::write(
        out.join("demodulator-fixed.bin"),
        demodulator_reference::<i16>(&raw_c16, &raw_s16),
    )
    .expect("OUT_DIR is writable");
    let f32_demodulator = !m0;
    let (variants, integers) = (NAMES.len(), &reference.integers);
    let scenario = format!(
        "/// Samples of the simulated resolver.\n\
         pub const SAMPLES: usize = {SAMPLES};\n\
         /// Samples whose estimates `check` compares with the host's.\n\
         pub const CHECKED_SAMPLES: usize = {checked};\n\
         /// The most samples of one block update.\n\
         pub const BLOCK_SAMPLES: usize = {block};\n\
         /// The simulated resolver's samples, cosine winding.\n\
         pub static Y_C: [f32; SAMPLES] = {y_c:?};\n\
         /// The simulated resolver's samples, sine winding.\n\
         pub static Y_S: [f32; SAMPLES] = {y_s:?};\n\
         /// The samples as 12-bit ADC counts (`trackers::adc_counts`), cosine winding.\n\
         pub static ADC_C: [i16; SAMPLES] = {adc_c:?};\n\
         /// The samples as 12-bit ADC counts, sine winding.\n\
         pub static ADC_S: [i16; SAMPLES] = {adc_s:?};\n\
         /// The samples in the fixed-point variants' counts (`trackers::fixed_counts`), cosine winding.\n\
         pub static FIXED_C: [i16; SAMPLES] = {fixed_c:?};\n\
         /// The samples in the fixed-point variants' counts, sine winding.\n\
         pub static FIXED_S: [i16; SAMPLES] = {fixed_s:?};\n\
         /// The observers' gains and sample period, as the host used them.\n\
         pub const OBSERVERS: Observers = Observers {{ second_order: {:?}, third_order: {:?}, \
         kalman: {:?}, sample_period_s: {:?} }};\n\
         /// Each variant's reference records of the first `CHECKED_SAMPLES` samples (see `variants`).\n\
         pub static REFERENCE: &[u8] = include_bytes!(concat!(env!(\"OUT_DIR\"), \"/reference.bin\"));\n\
         /// Each variant's `variants::fold_integers` of its estimates' integers over all samples \
         (the fixed-point variants; `None` for the float ones).\n\
         pub static INTEGERS: [Option<u64>; {variants}] = {integers:?};\n\
         /// The demodulator's raw ADC samples (counts), cosine winding.\n\
         pub const F32_DEMODULATOR: bool = {f32_demodulator};\n\
         pub static RAW_C: [f32; {f32_samples}] = {raw_c:?};\n\
         /// The demodulator's raw ADC samples (counts), sine winding.\n\
         pub static RAW_S: [f32; {f32_samples}] = {raw_s:?};\n\
         /// The same as `i16` codes, for the fixed-point demodulator.\n\
         pub static RAW_C16: [i16; SAMPLES] = {raw_c16:?};\n\
         pub static RAW_S16: [i16; SAMPLES] = {raw_s16:?};\n\
         /// The fixed-point demodulator's pairs, as the host made them.\n\
         pub static DEMODULATOR_FIXED_PAIRS: &[u8] = \
         include_bytes!(concat!(env!(\"OUT_DIR\"), \"/demodulator-fixed.bin\"));\n\
         /// The demodulator's pairs from the raw samples, as the host made them.\n\
         pub static DEMODULATOR_PAIRS: &[u8] = \
         include_bytes!(concat!(env!(\"OUT_DIR\"), \"/demodulator.bin\"));\n",
        observers.second_order, observers.third_order, observers.kalman, observers.sample_period_s
    );
    fs::write(out.join("scenario.rs"), scenario).expect("OUT_DIR is writable");
}

/// The demodulator variants' inputs: raw 12-bit samples of both windings (`raw_c`,
/// `raw_s`), the benchmark resolver's signals as envelopes of a 10 kHz carrier (each
/// `(y_c, y_s)` held for one carrier period, sampled 16 times, mid-scale 2048, rounded).
fn demodulator_inputs(y_c: &[f32], y_s: &[f32]) -> (Vec<f32>, Vec<f32>) {
    (0..SAMPLES)
        .map(|j| {
            let k = j / SAMPLES_PER_PERIOD;
            let phase =
                std::f64::consts::TAU * (j % SAMPLES_PER_PERIOD) as f64 / SAMPLES_PER_PERIOD as f64;
            let carrier =
                f64::from(CARRIER_AMPLITUDE_COUNTS) * (phase - f64::from(CARRIER_DELAY_RAD)).sin();
            let code = |y: f32| (2048.0 + f64::from(y) * carrier).round() as f32;
            (code(y_c[k]), code(y_s[k]))
        })
        .unzip()
}

/// The bytes of the pairs the core's demodulator makes of the raw samples on the host, in
/// the number type `V`.
fn demodulator_reference<V: DemodulatorNumber<Real = f32>>(raw_c: &[V], raw_s: &[V]) -> Vec<u8> {
    let demodulator = demodulator::<V>().expect("valid demodulator settings");
    let mut state = DemodulatorState::new();
    let mut pairs = Vec::new();
    for (&c, &s) in raw_c.iter().zip(raw_s) {
        if let Some(pair) = demodulator.push(&mut state, c, s) {
            pairs.extend_from_slice(&encode_pair(&pair));
        }
    }
    assert!(
        raw_c.is_empty() || pairs.len() > 50 * variants::PAIR_BYTES,
        "too few pairs"
    );
    pairs
}
