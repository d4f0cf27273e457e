//! The observer variants of the firmware test and the layout of the reference data: shared by
//! the build script (which computes the reference on the host) and the firmware (which checks
//! itself against it), so that both run the same list in the same order.

use angletrack_core::{
    AdcScaling, Calibrator, ConfigError, DemodulatedPair, Demodulator, DemodulatorSettings,
    Estimate, Exact, Fast, FaultThresholds, Gains, ObserverState, SinCos,
};

/// The variants, as printed: `<observer>-<float>-<sincos>[-<entry>]`. `unmonitored` is the
/// Kalman ATO with the diagnostics switched off (`FaultThresholds::disabled()`: the bare
/// loop); `calibrated` the Kalman ATO through `Gains::update_calibrated` with the online
/// calibration learning; `adc` the Kalman ATO through `Gains::update_adc` on 12-bit counts
/// ([`adc_counts`]).
pub const NAMES: [&str; 9] = [
    "second-order-f32-exact",
    "second-order-f32-fast",
    "third-order-f32-exact",
    "third-order-f32-fast",
    "kalman-f32-exact",
    "kalman-f32-fast",
    "kalman-f32-fast-unmonitored",
    "kalman-f32-fast-calibrated",
    "kalman-f32-fast-adc",
];

/// The variant whose types the loop alone (`count loop`) runs with: the unmonitored Kalman
/// ATO.
pub const LOOP_VARIANT: usize = 6;

/// Which entry point of the core a variant runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Entry {
    /// `Gains::update`.
    Plain,
    /// `Gains::update_calibrated`, the calibration learning.
    Calibrated,
    /// `Gains::update_adc` on [`adc_counts`] of the inputs, 12-bit two's complement.
    Adc,
}

/// The entry point of variant `index`.
pub const fn entry(index: usize) -> Entry {
    match index {
        7 => Entry::Calibrated,
        8 => Entry::Adc,
        _ => Entry::Plain,
    }
}

/// An input sample (amplitude about 1) as a 12-bit two's complement ADC reading (full
/// scale +-2048 counts), truncated: the same on the host and on the target.
pub fn adc_counts(y: f32) -> i16 {
    (y * 2048.0) as i16
}

/// The state one channel needs for any entry point.
#[derive(Debug, Clone, Copy)]
pub struct Channel<const N: usize> {
    /// The observer's state.
    pub state: ObserverState<f32, N>,
    /// The online calibration (learning for [`Entry::Calibrated`], else off).
    pub calibrator: Calibrator<f32>,
    /// The ADC front end of [`Entry::Adc`].
    pub adc: AdcScaling<f32>,
}

impl<const N: usize> Channel<N> {
    /// A fresh channel for the entry point `entry`.
    pub fn new(entry: Entry) -> Self {
        let mut calibrator = Calibrator::new();
        if entry == Entry::Calibrated {
            calibrator.enable();
        }
        Self {
            state: ObserverState::new(),
            calibrator,
            adc: AdcScaling::twos_complement(12).unwrap_or_default(),
        }
    }
}

/// Bytes of one reference record: angle (rad, f32), turns (i32), speed (rad/s, f32),
/// acceleration (rad/s^2, f32), little endian.
pub const RECORD_BYTES: usize = 16;

/// Bytes of one input sample: `y_c`, `y_s` (f32, little endian).
pub const SAMPLE_BYTES: usize = 8;

/// The discrete gains of the three observers and the sample period (s), in `f32`.
#[derive(Debug, Clone, Copy)]
pub struct Observers {
    /// `(l1, l2)` of the 2nd-order ATO.
    pub second_order: [f32; 2],
    /// `(l1, l2, l3)` of the 3rd-order ATO (pole placement).
    pub third_order: [f32; 3],
    /// `(l1, l2, l3)` of the Kalman ATO.
    pub kalman: [f32; 3],
    /// Sample period (s).
    pub sample_period_s: f32,
}

/// Something to do with one variant's checked gains.
pub trait Job {
    /// Runs on variant `index` (into [`NAMES`]) with its gains.
    fn run<const N: usize, S: SinCos<f32>>(&mut self, index: usize, gains: Gains<f32, N, S>);
}

impl Observers {
    /// Runs `job` on variant `index`. Returns `false` (and runs nothing) if `index` is not a
    /// variant or its gains are refused.
    pub fn run(&self, index: usize, job: &mut impl Job) -> bool {
        let ts = self.sample_period_s;
        let fast = index % 2 == 1 || index >= 6;
        let third = |l: [f32; 3]| -> Result<Gains<f32, 3, Exact>, ConfigError> {
            let gains = Gains::new(l, ts)?;
            if index == 6 {
                gains.with_fault_thresholds(FaultThresholds::disabled())
            } else {
                Ok(gains)
            }
        };
        match index {
            0 | 1 => Gains::new(self.second_order, ts).map(|g| run_with(index, g, fast, job)),
            2 | 3 => third(self.third_order).map(|g| run_with(index, g, fast, job)),
            4..=8 => third(self.kalman).map(|g| run_with(index, g, fast, job)),
            _ => return false,
        }
        .is_ok()
    }
}

/// Runs `job` with `gains`, with the fast or the exact sin/cos.
fn run_with<const N: usize>(
    index: usize,
    gains: Gains<f32, N, Exact>,
    fast: bool,
    job: &mut impl Job,
) {
    if fast {
        job.run(index, gains.with_sin_cos::<Fast>());
    } else {
        job.run(index, gains);
    }
}

/// The reference record of one estimate (written by the build script only).
#[allow(dead_code)]
pub fn encode(estimate: &Estimate<f32>) -> [u8; RECORD_BYTES] {
    let mut r = [0; RECORD_BYTES];
    r[0..4].copy_from_slice(&estimate.angle.to_le_bytes());
    r[4..8].copy_from_slice(&(estimate.turns as i32).to_le_bytes());
    r[8..12].copy_from_slice(&estimate.speed.to_le_bytes());
    r[12..16].copy_from_slice(&estimate.acceleration.to_le_bytes());
    r
}

/// `(angle, turns, speed, acceleration)` of a reference record.
pub fn decode(r: &[u8]) -> (f32, i32, f32, f32) {
    let word = |i: usize| [r[i], r[i + 1], r[i + 2], r[i + 3]];
    (
        f32::from_le_bytes(word(0)),
        i32::from_le_bytes(word(4)),
        f32::from_le_bytes(word(8)),
        f32::from_le_bytes(word(12)),
    )
}

/// The resolver front end's variant, counted per ADC sample pair: the synchronous
/// demodulator (`Demodulator::push`) alone.
pub const DEMODULATOR: &str = "demodulator-f32";

/// ADC samples of each winding per carrier period of the demodulator variant.
pub const SAMPLES_PER_PERIOD: usize = 16;

/// The demodulator variant's carrier amplitude at the ADC (counts) and delay (rad).
pub const CARRIER_AMPLITUDE_COUNTS: f32 = 1800.0;
/// The carrier delay of the demodulator variant's raw samples (rad, 305 degrees).
pub const CARRIER_DELAY_RAD: f32 = 5.323_254;

/// Bytes of one demodulated pair's reference record: `y_c`, `y_s` (f32, little endian).
pub const PAIR_BYTES: usize = 8;

/// The demodulator of the variant: a 10 kHz carrier, 16 samples per period, 12-bit ADC,
/// the delay resolved near its true value.
pub fn demodulator() -> Result<Demodulator<f32, SAMPLES_PER_PERIOD>, ConfigError> {
    let mut settings = DemodulatorSettings::new(10e3, CARRIER_AMPLITUDE_COUNTS, 0.0, 4095.0);
    settings.expected_delay_rad = CARRIER_DELAY_RAD - 0.5;
    Demodulator::new(settings)
}

/// The reference record of one demodulated pair (written by the build script only).
#[allow(dead_code)]
pub fn encode_pair(pair: &DemodulatedPair<f32>) -> [u8; PAIR_BYTES] {
    let mut r = [0; PAIR_BYTES];
    r[0..4].copy_from_slice(&pair.y_c.to_le_bytes());
    r[4..8].copy_from_slice(&pair.y_s.to_le_bytes());
    r
}

/// The fixed-point variant: the Kalman ATO's gains quantised (`angletrack_core::fixed`) on the
/// inputs as 16-bit counts ([`fixed_counts`]), with default diagnostics. Counted and checked
/// apart from [`NAMES`], whose variants run in `f32`.
pub const FIXED: &str = "kalman-fixed";

/// The [`NAMES`] variant the fixed-point variant is checked against (its host reference).
pub const FIXED_REFERENCE: usize = 5;

/// An input sample (amplitude about 1) in the fixed-point variant's counts: amplitude 2^14,
/// rounded; the same on the host and on the target.
pub fn fixed_counts(y: f32) -> i16 {
    let scaled = y * 16384.0;
    (if scaled >= 0.0 { scaled + 0.5 } else { scaled - 0.5 }) as i16
}

/// The fixed-point variant's gains: the Kalman ATO's, quantised.
pub fn fixed_gains(observers: &Observers) -> Result<angletrack_core::FixedGains<3>, ConfigError> {
    angletrack_core::FixedGains::new(
        observers.kalman.map(f64::from),
        f64::from(observers.sample_period_s),
    )
}
