//! Computes the firmware's reference on the host: the simulated resolver of the benchmarks
//! (`angletrack-benches`), and every observer variant run over it by the same core crate in
//! `f32`. The firmware embeds both and checks its own estimates against them.

use std::{env, fs, path::PathBuf};

use angletrack_benches::{
    KALMAN_GAINS, SECOND_ORDER_GAINS, THIRD_ORDER_GAINS, benchmark_scenario, channels,
};
use angletrack_core::{Gains, SinCos};

#[path = "src/variants.rs"]
// Shared with the firmware, which alone reads the records back (`decode`).
#[allow(dead_code)]
mod variants;

use angletrack_core::DemodulatorState;
use variants::{
    CARRIER_AMPLITUDE_COUNTS, CARRIER_DELAY_RAD, Channel, Entry, Job, NAMES, Observers,
    SAMPLES_PER_PERIOD, adc_counts, demodulator, encode_pair, entry,
};

/// Samples of the simulated resolver (0.2 s at 10 kHz, about 11 turns).
const SAMPLES: usize = 2000;

/// Runs a variant over the signal and appends its reference records.
struct Reference<'a> {
    y_c: &'a [f32],
    y_s: &'a [f32],
    records: Vec<u8>,
}

impl Job for Reference<'_> {
    fn run<const N: usize, S: SinCos<f32>>(&mut self, index: usize, gains: Gains<f32, N, S>) {
        let mut channel = Channel::<N>::new(entry(index));
        let Channel {
            state,
            calibrator,
            adc,
        } = &mut channel;
        for (&c, &s) in self.y_c.iter().zip(self.y_s) {
            let estimate = match entry(index) {
                Entry::Plain | Entry::Track => gains.update(state, c, s),
                Entry::Calibrated | Entry::CalibratedOff | Entry::TrackCalibratedOff => {
                    gains.update_calibrated(state, calibrator, c, s)
                }
                Entry::Adc => gains.update_adc(state, adc, adc_counts(c), adc_counts(s)),
            };
            self.records.extend_from_slice(&variants::encode(&estimate));
        }
    }
}

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x is readable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=src/variants.rs");

    let observers = Observers {
        second_order: SECOND_ORDER_GAINS.map(|v| v as f32),
        third_order: THIRD_ORDER_GAINS.map(|v| v as f32),
        kalman: KALMAN_GAINS.map(|v| v as f32),
        sample_period_s: angletrack_benches::SAMPLE_PERIOD_S as f32,
    };
    let (y_c, y_s) = channels::<f32>(&benchmark_scenario(SAMPLES));
    let mut data = Vec::new();
    for (c, s) in y_c.iter().zip(&y_s) {
        data.extend_from_slice(&c.to_le_bytes());
        data.extend_from_slice(&s.to_le_bytes());
    }
    let mut reference = Reference {
        y_c: &y_c,
        y_s: &y_s,
        records: data,
    };
    for (index, name) in NAMES.iter().enumerate() {
        assert!(
            observers.run(index, &mut reference),
            "gains of {name} refused"
        );
    }
    fs::write(out.join("reference.bin"), &reference.records).expect("OUT_DIR is writable");
    fs::write(
        out.join("demodulator.bin"),
        demodulator_reference(&y_c, &y_s),
    )
    .expect("OUT_DIR is writable");
    let scenario = format!(
        "/// Samples of the simulated resolver.\n\
         pub const SAMPLES: usize = {SAMPLES};\n\
         /// The observers' gains and sample period, as the host used them.\n\
         pub const OBSERVERS: Observers = Observers {{ second_order: {:?}, third_order: {:?}, \
         kalman: {:?}, sample_period_s: {:?} }};\n\
         /// Input samples, then each variant's reference records (see `variants`).\n\
         pub static REFERENCE: &[u8] = include_bytes!(concat!(env!(\"OUT_DIR\"), \"/reference.bin\"));\n\
         /// The demodulator's raw ADC samples (counts, f32 pairs), then its pairs.\n\
         pub static DEMODULATOR_REFERENCE: &[u8] = \
         include_bytes!(concat!(env!(\"OUT_DIR\"), \"/demodulator.bin\"));\n",
        observers.second_order, observers.third_order, observers.kalman, observers.sample_period_s
    );
    fs::write(out.join("scenario.rs"), scenario).expect("OUT_DIR is writable");
}

/// The demodulator variant's reference: raw 12-bit samples of both windings, the benchmark
/// resolver's signals as envelopes of a 10 kHz carrier (each `(y_c, y_s)` held for one
/// carrier period, sampled 16 times, mid-scale 2048, rounded), then the pairs the core's
/// demodulator makes of them on the host in `f32`.
fn demodulator_reference(y_c: &[f32], y_s: &[f32]) -> Vec<u8> {
    let raw: Vec<(f32, f32)> = (0..SAMPLES)
        .map(|j| {
            let k = j / SAMPLES_PER_PERIOD;
            let phase =
                std::f64::consts::TAU * (j % SAMPLES_PER_PERIOD) as f64 / SAMPLES_PER_PERIOD as f64;
            let carrier =
                f64::from(CARRIER_AMPLITUDE_COUNTS) * (phase + f64::from(CARRIER_DELAY_RAD)).sin();
            let code = |y: f32| (2048.0 + f64::from(y) * carrier).round() as f32;
            (code(y_c[k]), code(y_s[k]))
        })
        .collect();
    let mut data = Vec::new();
    for (c, s) in &raw {
        data.extend_from_slice(&c.to_le_bytes());
        data.extend_from_slice(&s.to_le_bytes());
    }
    let demodulator = demodulator().expect("valid demodulator settings");
    let mut state = DemodulatorState::new();
    for &(c, s) in &raw {
        if let Some(pair) = demodulator.push(&mut state, c, s) {
            data.extend_from_slice(&encode_pair(&pair));
        }
    }
    data
}
