//! The fault injection: the campaign's own, on the healthy sensor's samples (in fractions
//! of the ADC's full scale), then the samples as each sensor kind delivers them (float
//! units, or 12-bit counts rounded and saturated at the ADC's codes as a converter does).

use core::f64::consts::TAU;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::cases::{Channel, FaultKind, SensorKind};
use super::{HEALTHY_SENSOR, SAMPLE_PERIOD_S};

/// Every how many samples an outlier or a NaN comes: far enough apart that the loop
/// settles between two, so that each is measured on its own.
pub const SINGLE_SAMPLE_PERIOD: usize = 500;

/// The amplitude a clipping fault raises the signal to, in fractions of full scale.
pub const CLIPPING_AMPLITUDE: f64 = 1.3;

/// The common-mode carrier: frequency (Hz) and amplitude (fractions of full scale). Near
/// a 10 kHz excitation, below the 10 kHz Nyquist frequency of the 20 kHz sampling: it
/// alternates from sample to sample under a slow beat, as a carrier leaking past the
/// demodulator does.
pub const COMMON_MODE: (f64, f64) = (9.7e3, 0.25);

/// The brown-out's remaining fraction of the amplitude.
pub const BROWN_OUT: f64 = 0.2;

/// The sine channel's amplitude over the cosine's under the imbalance fault.
pub const IMBALANCED_RATIO: f64 = 0.6;

/// The quadrature angle (rad) the quadrature fault adds.
pub const ADDED_QUADRATURE_RAD: f64 = 0.3;

/// The injection of one fault into one run: its onset, and what it remembers (the stuck
/// value, the generator of its noise and outliers, seeded per case so that every run is the
/// same on every machine).
#[derive(Debug)]
pub struct Injector {
    fault: FaultKind,
    onset: usize,
    units: bool,
    held: Option<(f64, f64)>,
    rng: ChaCha8Rng,
    noise: Normal<f64>,
}

impl Injector {
    /// The injection of `fault` from sample `onset` on, into samples going to `sensor`,
    /// its random draws seeded with `seed`.
    pub fn new(fault: FaultKind, onset: usize, sensor: SensorKind, seed: u64) -> Self {
        Self {
            fault,
            onset,
            units: sensor == SensorKind::Units,
            held: None,
            rng: ChaCha8Rng::seed_from_u64(seed),
            // The healthy sensor's own noise, for the signals a fault makes of noise alone.
            noise: Normal::new(0.0, HEALTHY_SENSOR.noise_std).expect("a finite deviation"),
        }
    }

    /// The healthy pair `(c, s)` of sample `k` with the fault injected (fractions of full
    /// scale; a units outlier may be far beyond it, a NaN is a NaN).
    pub fn inject(&mut self, k: usize, c: f64, s: f64) -> (f64, f64) {
        // The stuck value is the last healthy one: the sample before the onset (the first
        // sample for a fault from the start).
        if k + 1 == self.onset.max(1) {
            self.held = Some((c, s));
        }
        if k < self.onset {
            return (c, s);
        }
        let (o_c, o_s) = (HEALTHY_SENSOR.offset_cos, HEALTHY_SENSOR.offset_sin);
        let set = |channel: Channel, value: f64| match channel {
            Channel::Cos => (value, s),
            Channel::Sin => (c, value),
        };
        match self.fault {
            FaultKind::Healthy | FaultKind::AccelerationStep(_) | FaultKind::BeyondSpeedLimit => {
                (c, s)
            }
            FaultKind::Carrier(_) => unreachable!("a carrier fault is injected on the windings"),
            FaultKind::Dead(channel) => set(channel, 0.0),
            FaultKind::Open(channel) => {
                // An open input floats: a small offset and the noise it picks up.
                let value = 0.003 + 2.0 * self.noise.sample(&mut self.rng);
                set(channel, value)
            }
            FaultKind::Shorted(channel) => match channel {
                Channel::Cos => (s, s),
                Channel::Sin => (c, c),
            },
            FaultKind::Stuck(channel) => {
                let (held_c, held_s) = self.held.unwrap_or((c, s));
                match channel {
                    Channel::Cos => (held_c, s),
                    Channel::Sin => (c, held_s),
                }
            }
            FaultKind::Reversed(channel) => match channel {
                Channel::Cos => (-c, s),
                Channel::Sin => (c, -s),
            },
            FaultKind::Clipping => {
                let gain = CLIPPING_AMPLITUDE / HEALTHY_SENSOR.amplitude;
                (gain * c, gain * s)
            }
            FaultKind::LossOfExcitation => (
                o_c + self.noise.sample(&mut self.rng),
                o_s + self.noise.sample(&mut self.rng),
            ),
            FaultKind::BrownOut => (o_c + BROWN_OUT * (c - o_c), o_s + BROWN_OUT * (s - o_s)),
            FaultKind::CommonMode => {
                let (frequency, amplitude) = COMMON_MODE;
                let m = amplitude * (TAU * frequency * k as f64 * SAMPLE_PERIOD_S + 0.3).sin();
                (c + m, s + m)
            }
            FaultKind::Imbalance => {
                let ratio = IMBALANCED_RATIO / (1.0 + HEALTHY_SENSOR.amplitude_imbalance);
                (c, o_s + ratio * (s - o_s))
            }
            FaultKind::Quadrature => {
                // The sine winding picks up a part of the cosine's field: its phase turns by
                // the angle added, its amplitude kept.
                let (sin_d, cos_d) = ADDED_QUADRATURE_RAD.sin_cos();
                let gain = 1.0 + HEALTHY_SENSOR.amplitude_imbalance;
                (c, o_s + cos_d * (s - o_s) + sin_d * gain * (c - o_c))
            }
            FaultKind::Outliers | FaultKind::NotANumber => {
                let n = k - self.onset;
                if !n.is_multiple_of(SINGLE_SAMPLE_PERIOD) {
                    return (c, s);
                }
                // Either channel, in turn.
                let channel = if (n / SINGLE_SAMPLE_PERIOD).is_multiple_of(2) {
                    Channel::Cos
                } else {
                    Channel::Sin
                };
                let value = if self.fault == FaultKind::NotANumber {
                    f64::NAN
                } else if self.units {
                    let sign = if self.rng.random::<bool>() { 1.0 } else { -1.0 };
                    sign * self.rng.random_range(2.0..50.0)
                } else {
                    // A glitch within the converter's range: any code.
                    self.rng.random_range(-1.0..1.0)
                };
                set(channel, value)
            }
        }
    }
}

/// The 12-bit ADC code of `x` (fractions of full scale): rounded, saturated at the codes,
/// offset binary (0 to 4095) or two's complement (-2048 to 2047).
pub fn code(x: f64, signed: bool) -> i32 {
    let half = 2048.0;
    let code = (half * x).round().clamp(-half, half - 1.0) as i32;
    if signed { code } else { code + 2048 }
}
