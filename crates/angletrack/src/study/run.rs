//! One run of a study: one simulated sensor through one motion profile and one setup, and
//! the row of its results.

use std::time::Instant;

use angletrack_core::Faults;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::row::{Errors, StudyRow};
use super::spec::Spec;
use crate::sim::ScenarioSample;
use crate::tracker_file::{CaptureHead, Input as TrackerInput, TrackerFile, TrackerRun};
use crate::{NOMINAL_AMPLITUDE_SAMPLES, Scenario};

/// SplitMix64's finaliser: a seed from the study's seed and a run's indices, well mixed so
/// that neighbouring indices give unrelated generators.
fn derived_seed(seed: u64, parts: &[u64]) -> u64 {
    parts.iter().fold(seed, |acc, &part| {
        let mut z = acc
            ^ part
                .wrapping_add(0x9e37_79b9_7f4a_7c15)
                .wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    })
}

/// The row of run `run` of `spec`.
pub(super) fn run(spec: &Spec, run: u64) -> StudyRow {
    let started = Instant::now();
    let (profiles, setups) = (spec.profiles.len() as u64, spec.setups.len() as u64);
    let sensor = run / (profiles * setups);
    let profile = (run / setups) % profiles;
    let setup = run % setups;
    let mut rng = ChaCha8Rng::seed_from_u64(derived_seed(spec.seed, &[sensor, 0]));
    let drawn = spec.sensor.draw(&mut rng);
    let (profile_name, motion) = &spec.profiles[profile as usize];
    let (setup_name, tracker) = &spec.setups[setup as usize];
    let mut row = StudyRow {
        run,
        sensor,
        profile: profile_name.clone(),
        setup: setup_name.clone(),
        number_type: tracker.number_type.name(),
        parameters: drawn.parameters,
        angle_error_harmonics: drawn.harmonics.clone(),
        samples: 0,
        rms_error_rad: f64::NAN,
        max_error_rad: f64::NAN,
        mean_error_rad: f64::NAN,
        time_to_lock_s: f64::NAN,
        fault_samples: 0,
        faults: String::new(),
        learned: [f64::NAN; 5],
        seconds: 0.0,
        error: None,
    };
    if run >= spec.runs() {
        row.error = Some(format!(
            "run: {run} is beyond the study's {} runs",
            spec.runs()
        ));
        return row;
    }
    let model = spec.sensor.model(&drawn);
    let noise_seed = derived_seed(spec.seed, &[sensor, 1 + profile]);
    let outcome = Scenario::stream(motion, &model, spec.sample_period_s, noise_seed)
        .map_err(|e| format!("sensor: {e}"))
        .and_then(|(len, samples)| track(spec, tracker, Samples::new(len, samples), &mut row));
    if let Err(e) = outcome {
        row.error = Some(e);
    }
    row.seconds = started.elapsed().as_secs_f64();
    row
}

/// A run's samples as the scenario draws them: the first [`NOMINAL_AMPLITUDE_SAMPLES`] held
/// (the chains read the signals' nominal amplitude from them before tracking the first),
/// the rest tracked as they are drawn, so that a run's memory does not grow with its length.
struct Samples<I> {
    len: usize,
    truth: Vec<f64>,
    y_c: Vec<f64>,
    y_s: Vec<f64>,
    rest: I,
}

impl<I: Iterator<Item = ScenarioSample>> Samples<I> {
    fn new(len: usize, mut samples: I) -> Self {
        let head = len.min(NOMINAL_AMPLITUDE_SAMPLES);
        let (mut truth, mut y_c, mut y_s) = (
            Vec::with_capacity(head),
            Vec::with_capacity(head),
            Vec::with_capacity(head),
        );
        for (state, (c, s)) in samples.by_ref().take(head) {
            truth.push(state.angle_rad);
            y_c.push(c);
            y_s.push(s);
        }
        Self {
            len,
            truth,
            y_c,
            y_s,
            rest: samples,
        }
    }

    /// Every sample in order: `(true angle, y_c, y_s)`.
    fn all(self) -> impl Iterator<Item = (f64, f64, f64)> {
        let head = self.truth.into_iter().zip(self.y_c).zip(self.y_s);
        head.map(|((t, c), s)| (t, c, s))
            .chain(self.rest.map(|(state, (c, s))| (state.angle_rad, c, s)))
    }
}

/// How many samples a run feeds its chain at a time: small enough for the chunk's three
/// series (24 KiB) to stay in a core's first-level data cache.
const CHUNK: usize = 1024;

/// Tracks `samples` with `tracker`'s chain (the crate's [`TrackerRun`], as `angletrack
/// track --tracker` runs it), filling `row`'s results. The sensor's signals go in as the
/// file's input takes them: in units, or as the codes of its ADC (`input.bits`, the study's
/// full scale). Each estimate goes into the error statistics as it comes, none is kept.
fn track<I: Iterator<Item = ScenarioSample>>(
    spec: &Spec,
    tracker: &TrackerFile,
    samples: Samples<I>,
    row: &mut StudyRow,
) -> Result<(), String> {
    let lsb_mid = match tracker.input {
        TrackerInput::Units => None,
        TrackerInput::Bits { bits, signed } => Some((
            2.0 * spec.sensor.adc_full_scale / f64::from(bits).exp2(),
            if signed {
                0.0
            } else {
                f64::from(bits - 1).exp2()
            },
        )),
        _ => {
            return Err(
                "input: a study's sensor gives its signals in units, or the codes of \
                        its ADC for input.bits: give one of them"
                    .into(),
            );
        }
    };
    // The sensor model rounds to its ADC's grid and saturates there: its codes fit.
    let input = |y: f64| lsb_mid.map_or(y, |(lsb, mid)| (y / lsb).round() + mid);
    let head_c: Vec<f64> = samples.y_c.iter().map(|&y| input(y)).collect();
    let head_s: Vec<f64> = samples.y_s.iter().map(|&y| input(y)).collect();
    let head = CaptureHead {
        y_c: &head_c,
        y_s: &head_s,
        counts: None,
    };
    let mut chain = TrackerRun::new(tracker, "setup", &head).map_err(|e| e.to_string())?;
    let mut errors = Errors::new(spec, samples.len, row)?;
    let (mut truth, mut y_c, mut y_s) = (
        Vec::with_capacity(CHUNK),
        Vec::with_capacity(CHUNK),
        Vec::with_capacity(CHUNK),
    );
    let mut k = 0;
    let mut flush = |truth: &mut Vec<f64>, y_c: &mut Vec<f64>, y_s: &mut Vec<f64>| {
        let mut truth_k = truth.iter();
        chain.track_each(y_c, y_s, |e| {
            let t = truth_k.next().copied().unwrap_or(f64::NAN);
            errors.add(k, t - e.angle_rad, Faults::from_bits_truncate(e.faults));
            k += 1;
        });
        truth.clear();
        y_c.clear();
        y_s.clear();
    };
    for (t, c, s) in samples.all() {
        truth.push(t);
        y_c.push(input(c));
        y_s.push(input(s));
        if truth.len() == CHUNK {
            flush(&mut truth, &mut y_c, &mut y_s);
        }
    }
    flush(&mut truth, &mut y_c, &mut y_s);
    errors.write(row);
    if let Some(learning) = chain.learning() {
        let (o_c, o_s, a_c, a_s, phi) = learning.calibration.parameters();
        row.learned = [o_c, o_s, a_c, a_s, phi];
    }
    Ok(())
}
