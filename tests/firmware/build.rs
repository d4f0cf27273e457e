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

use variants::{Channel, Entry, Job, NAMES, Observers, adc_counts, entry};

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
                Entry::Plain => gains.update(state, c, s),
                Entry::Calibrated => gains.update_calibrated(state, calibrator, c, s),
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
    let scenario = format!(
        "/// Samples of the simulated resolver.\n\
         pub const SAMPLES: usize = {SAMPLES};\n\
         /// The observers' gains and sample period, as the host used them.\n\
         pub const OBSERVERS: Observers = Observers {{ second_order: {:?}, third_order: {:?}, \
         kalman: {:?}, sample_period_s: {:?} }};\n\
         /// Input samples, then each variant's reference records (see `variants`).\n\
         pub static REFERENCE: &[u8] = include_bytes!(concat!(env!(\"OUT_DIR\"), \"/reference.bin\"));\n",
        observers.second_order, observers.third_order, observers.kalman, observers.sample_period_s
    );
    fs::write(out.join("scenario.rs"), scenario).expect("OUT_DIR is writable");
}
