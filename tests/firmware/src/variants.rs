//! The variants of the firmware test and the layout of the reference data: shared by the
//! build script (which computes the reference on the host) and the firmware (which checks
//! itself against it and counts), so that both run the same list in the same order.
//!
//! A variant is a [`Tracker`] (`trackers.rs`): one of the core's entry points with its gains,
//! or a baseline (`baseline`). The list is the [`variants!`] table below: one line per
//! variant. A variant of an entry point that has a `Tracker` (`Plain`, `Calibrated`, `Adc`,
//! `Corrected`, `Track`, `Fixed`, `PhaseLockedLoop`, ...) is that one line; another `f32`
//! entry point of the core first needs its `EntryPoint` (its state, input type and call),
//! and anything else (another arithmetic, say) its `Tracker`: its state, input and output
//! types, and its estimate as a [`Record`].
//! `run.sh` prints each variant under its name on the Cortex-M4F (`-m4` appended if it
//! contains `-fixed`) and with `-m0` appended on the Cortex-M0.

use angletrack_core::{
    AdcScaling, AngleCorrection, Chain, ConfigError, DemodulatedPair, Demodulator,
    DemodulatorNumber, DemodulatorSettings, Estimate, Exact, Fast, FaultThresholds, FixedGains,
    Gains, MAX_CORRECTION_ORDER,
};

use crate::baseline::{Atan2, FastAtan2, LibmAtan2, PhaseLockedLoop};
use crate::chains::{
    ChainTrack, ChainUpdate, FixedChainTrack, Online, StoredCorrections, fixed_corrections, online,
    stored_corrections,
};
pub use crate::trackers::Tracker;
use crate::trackers::{Fixed, FixedTrack, Plain, Track};

/// The angle-harmonic correction of the `angle-corrected` variant, order 4: a few mrad of
/// each harmonic, as a real resolver has (the benchmark's signal has none: the variant is
/// there for its cost; the host reference checks it all the same).
pub fn correction() -> Result<AngleCorrection<f32>, ConfigError> {
    let mut a = [0.0; MAX_CORRECTION_ORDER];
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    a[..4].copy_from_slice(&[2e-3, -1e-3, 5e-4, 1.5e-3]);
    b[..4].copy_from_slice(&[-1e-3, 3e-3, -5e-4, 1e-3]);
    AngleCorrection::new(a, b)
}

/// The natural frequency of the baselines' PLL (rad/s): that of the benchmarks' 2nd-order
/// ATO (50 Hz, damping 1).
pub const PLL_BANDWIDTH_RAD_S: f32 = core::f32::consts::TAU * 50.0;

/// The estimate compared with the host's: angle (rad), whole turns, speed (rad/s),
/// acceleration (rad/s^2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    /// Angle (rad).
    pub angle: f32,
    /// Whole turns.
    pub turns: i32,
    /// Speed (rad/s).
    pub speed: f32,
    /// Acceleration (rad/s^2).
    pub acceleration: f32,
}

/// Bytes of one encoded [`Record`]: angle (f32), turns (i32), speed (f32), acceleration
/// (f32), little endian.
pub const RECORD_BYTES: usize = 16;

impl Record {
    /// The record of an observer's estimate.
    pub fn of(estimate: &Estimate<f32>) -> Self {
        Self {
            angle: estimate.angle,
            turns: estimate.turns as i32,
            speed: estimate.speed,
            acceleration: estimate.acceleration,
        }
    }

    /// The record's bytes (written by the build script only).
    #[allow(dead_code)]
    pub fn encode(&self) -> [u8; RECORD_BYTES] {
        let mut r = [0; RECORD_BYTES];
        r[0..4].copy_from_slice(&self.angle.to_le_bytes());
        r[4..8].copy_from_slice(&self.turns.to_le_bytes());
        r[8..12].copy_from_slice(&self.speed.to_le_bytes());
        r[12..16].copy_from_slice(&self.acceleration.to_le_bytes());
        r
    }

    /// The record of [`Record::encode`]'s bytes.
    pub fn decode(r: &[u8]) -> Self {
        let word = |i: usize| [r[i], r[i + 1], r[i + 2], r[i + 3]];
        Self {
            angle: f32::from_le_bytes(word(0)),
            turns: i32::from_le_bytes(word(4)),
            speed: f32::from_le_bytes(word(8)),
            acceleration: f32::from_le_bytes(word(12)),
        }
    }
}

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

impl Observers {
    fn second_order(&self) -> Result<Gains<f32, 2, Exact>, ConfigError> {
        Gains::new(self.second_order, self.sample_period_s)
    }
    fn third_order(&self) -> Result<Gains<f32, 3, Exact>, ConfigError> {
        Gains::new(self.third_order, self.sample_period_s)
    }
    fn kalman(&self) -> Result<Gains<f32, 3, Exact>, ConfigError> {
        Gains::new(self.kalman, self.sample_period_s)
    }
    fn fixed(&self) -> Result<Fixed<3>, ConfigError> {
        let gains = FixedGains::new(self.kalman.map(f64::from), f64::from(self.sample_period_s))?;
        Ok(Fixed(alone(gains)))
    }
    fn fixed_unmonitored(&self) -> Result<Fixed<3>, ConfigError> {
        let Fixed(chain) = self.fixed()?;
        Ok(Fixed(alone(chain.observer.with_monitor(None)?)))
    }
    /// The fast Kalman observer through the online calibration, learning or off.
    fn calibrated(
        &self,
        learning: bool,
    ) -> Result<Chain<Online, Gains<f32, 3, Fast>>, ConfigError> {
        let gains = fast(self.kalman()?);
        Ok(Chain::new(online(&gains, learning)?, gains))
    }
    /// The fast Kalman observer through a stored calibration and the angle error's table.
    fn corrected(&self) -> Result<ChainTrack<StoredCorrections, 3, Fast>, ConfigError> {
        let gains = fast(self.kalman()?);
        Ok(ChainTrack(Chain::new(
            stored_corrections(&correction()?)?,
            gains,
        )))
    }
    /// The fixed-point observer through a stored calibration and the angle error's table.
    fn fixed_corrected(&self) -> Result<FixedChainTrack<3>, ConfigError> {
        let Fixed(chain) = self.fixed()?;
        Ok(FixedChainTrack(Chain::new(
            fixed_corrections(&correction()?)?,
            chain.observer,
        )))
    }
    fn pll<A: Atan2>(&self) -> PhaseLockedLoop<A> {
        PhaseLockedLoop::new(PLL_BANDWIDTH_RAD_S, self.sample_period_s)
    }
}

/// The observer alone: a chain with no front end.
fn alone<O>(observer: O) -> Chain<(), O> {
    Chain::new((), observer)
}

/// The gains with the fast (polynomial) sin/cos.
fn fast<const N: usize>(gains: Gains<f32, N, Exact>) -> Gains<f32, N, Fast> {
    gains.with_sin_cos()
}

/// The gains with the diagnostics off (`FaultThresholds::disabled()`: the bare loop).
fn unmonitored<const N: usize>(
    gains: Gains<f32, N, Exact>,
) -> Result<Gains<f32, N, Exact>, ConfigError> {
    gains.with_fault_thresholds(FaultThresholds::disabled())
}

/// Something to do with one variant's tracker.
pub trait Job {
    /// Runs on variant `index` (into [`NAMES`]).
    fn run<T: Tracker>(&mut self, index: usize, tracker: T);
}

/// The variant table: `"name" => |observers| tracker,` one line per variant (the tracker a
/// `Result<impl Tracker, ConfigError>`), which makes [`NAMES`] and [`Observers::run`].
macro_rules! variants {
    ($($name:literal => |$o:ident| $tracker:expr,)*) => {
        /// The variants, as printed: `<observer>-<arithmetic>-<sincos>[-<entry>]`, or
        /// `baseline-<arctangent>-pll-<arithmetic>`.
        pub const NAMES: &[&str] = &[$($name),*];

        impl Observers {
            /// Runs `job` on variant `index`. Returns `Ok(false)` (and runs nothing) if
            /// `index` is not a variant, the error if its gains are refused.
            pub fn run(&self, index: usize, job: &mut impl Job) -> Result<bool, ConfigError> {
                let mut i = 0;
                $(
                    if index == i {
                        let $o = self;
                        job.run(index, $tracker?);
                        return Ok(true);
                    }
                    i += 1;
                )*
                let _ = i;
                Ok(false)
            }
        }
    };
}

variants! {
    "second-order-f32-exact" => |o| o.second_order().map(alone).map(Plain),
    "second-order-f32-fast" => |o| o.second_order().map(fast).map(alone).map(Plain),
    "third-order-f32-exact" => |o| o.third_order().map(alone).map(Plain),
    "third-order-f32-fast" => |o| o.third_order().map(fast).map(alone).map(Plain),
    "kalman-f32-exact" => |o| o.kalman().map(alone).map(Plain),
    "kalman-f32-fast" => |o| o.kalman().map(fast).map(alone).map(Plain),
    "kalman-f32-fast-unmonitored" => |o| o.kalman().and_then(unmonitored).map(fast).map(alone).map(Plain),
    "kalman-f32-fast-calibrated" => |o| o.calibrated(true).map(ChainUpdate),
    "kalman-f32-fast-calibrated-off" => |o| o.calibrated(false).map(ChainUpdate),
    "kalman-f32-fast-track" => |o| o.kalman().map(fast).map(alone).map(Track),
    "kalman-f32-fast-track-unmonitored" => |o| o.kalman().and_then(unmonitored).map(fast).map(alone).map(Track),
    "kalman-f32-fast-track-calibrated-off" => |o| o.calibrated(false).map(ChainTrack),
    "kalman-f32-fast-track-corrected" => |o| o.corrected(),
    "kalman-f32-fast-adc" => |o| Ok(ChainUpdate(Chain::new(AdcScaling::twos_complement(12)?, fast(o.kalman()?)))),
    "kalman-f32-fast-angle-corrected" => |o| Ok(ChainUpdate(Chain::new(correction()?, fast(o.kalman()?)))),
    "kalman-fixed" => |o| o.fixed(),
    "kalman-fixed-track" => |o| o.fixed().map(FixedTrack),
    "kalman-fixed-track-unmonitored" => |o| o.fixed_unmonitored().map(FixedTrack),
    "kalman-fixed-track-corrected" => |o| o.fixed_corrected(),
    "baseline-atan2-pll-f32" => |o| Ok(o.pll::<LibmAtan2>()),
    "baseline-fast-atan2-pll-f32" => |o| Ok(o.pll::<FastAtan2>()),
}

/// The variant whose types the loop alone (`count loop`) runs with.
pub const LOOP_VARIANT: &str = "kalman-f32-fast-unmonitored";

/// The resolver front end's variants, counted per ADC sample: the demodulator
/// (`Demodulator::push`, `Demodulator::push_block`) alone, in `f32` and in fixed point.
pub const DEMODULATORS: [&str; 2] = ["demodulator-f32", "demodulator-fixed"];

/// ADC samples of each winding per carrier period of the demodulator variants.
pub const SAMPLES_PER_PERIOD: usize = 16;

/// The demodulator variants' carrier amplitude at the ADC (counts) and delay (rad).
pub const CARRIER_AMPLITUDE_COUNTS: f32 = 1800.0;
/// The carrier delay of the demodulator variants' raw samples (rad, 55 degrees: the
/// windings' carrier behind a carrier of phase 0 at the first sample).
pub const CARRIER_DELAY_RAD: f32 = 0.959_931_2;

/// Bytes of one input sample or demodulated pair: `y_c`, `y_s` (f32, little endian; a
/// fixed-point pair as the float it stands for, exact).
pub const PAIR_BYTES: usize = 8;

/// The demodulator of the variants: a 10 kHz carrier sampled at 160 kHz, 12-bit ADC, the
/// delay resolved near its true value.
pub fn demodulator<V: DemodulatorNumber<Real = f32>>() -> Result<Demodulator<V>, ConfigError> {
    let mut settings = DemodulatorSettings::new(
        10e3,
        10e3 * SAMPLES_PER_PERIOD as f32,
        CARRIER_AMPLITUDE_COUNTS,
        0.0,
        4095.0,
    );
    settings.expected_delay_rad = CARRIER_DELAY_RAD - 0.5;
    Demodulator::new(settings)
}

/// FNV-1a's (64-bit) start.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a (64-bit) of `hash` extended by the little-endian bytes of `words`: how `check`
/// compares the integers of a fixed-point variant's every estimate with the host's (a
/// single differing bit changes it).
pub fn fold_integers(mut hash: u64, words: &[i64]) -> u64 {
    for word in words {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    hash
}

/// The reference record of one demodulated pair (written by the build script only).
#[allow(dead_code)]
pub fn encode_pair<V: DemodulatorNumber<Real = f32>>(
    pair: &DemodulatedPair<V>,
) -> [u8; PAIR_BYTES] {
    let mut r = [0; PAIR_BYTES];
    r[0..4].copy_from_slice(&V::to_real(pair.y_c).to_le_bytes());
    r[4..8].copy_from_slice(&V::to_real(pair.y_s).to_le_bytes());
    r
}
