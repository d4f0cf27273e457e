//! Carrier-modulated resolver signals (`docs/theory.md §13`): the windings as an ADC samples
//! them, `N` times per period of the excitation carrier, for the core's
//! [`Demodulator`](angletrack_core::Demodulator) and the `track --carrier-hz` path.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::{MotionProfile, Scenario};
use crate::error::{Argument, Error, finite, non_negative, positive};

/// A resolver excited by a sine carrier and sampled by an ADC clocked with the excitation:
///
/// ```text
/// raw_c[k] = mid + common_mode + A cos(theta) sin(2 pi k / N - delay) + w_c
/// raw_s[k] = mid + common_mode + A (1 + imbalance) sin(theta) sin(2 pi k / N - delay) + w_s
/// A = excitation_amplitude_counts * transformation_ratio
/// ```
///
/// sampled at `N carrier_hz`, then rounded to the ADC's codes `0 .. 2^adc_bits - 1`
/// (saturating) with `mid = 2^(adc_bits - 1)`; without an ADC (`adc_bits` 0) `mid` is 0 and
/// nothing is rounded. `w_c`, `w_s` are independent white Gaussian noises of standard
/// deviation `noise_std_counts`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResolverModel {
    /// The excitation carrier frequency (Hz).
    pub carrier_hz: f64,
    /// ADC samples of each winding per carrier period.
    pub samples_per_period: usize,
    /// The carrier's phase delay from the excitation to the ADC (rad, any value; positive:
    /// the windings' carrier lags the excitation).
    pub carrier_delay_rad: f64,
    /// The excitation's amplitude (ADC counts, as the windings would show it at ratio 1).
    pub excitation_amplitude_counts: f64,
    /// The resolver's transformation ratio (winding amplitude over excitation amplitude).
    pub transformation_ratio: f64,
    /// The sine winding's relative amplitude error against the cosine winding's.
    pub winding_imbalance: f64,
    /// A DC common mode on both windings (counts).
    pub common_mode_counts: f64,
    /// The ADC's resolution (bits); 0 for no quantisation.
    pub adc_bits: u32,
    /// The standard deviation of the noise on each sample (counts).
    pub noise_std_counts: f64,
}

impl Default for ResolverModel {
    /// The issue's reference front end: a 10 kHz carrier sampled 16 times per period
    /// (160 kHz) by a 12-bit ADC, amplitude 1800 counts (3600 excitation, ratio 0.5), noise
    /// 1 LSB, no delay, no imbalance, no common mode.
    fn default() -> Self {
        Self {
            carrier_hz: 10e3,
            samples_per_period: 16,
            carrier_delay_rad: 0.0,
            excitation_amplitude_counts: 3600.0,
            transformation_ratio: 0.5,
            winding_imbalance: 0.0,
            common_mode_counts: 0.0,
            adc_bits: 12,
            noise_std_counts: 1.0,
        }
    }
}

impl ResolverModel {
    /// The carrier amplitude of a winding at the ADC (counts) at envelope 1.
    pub fn amplitude_counts(&self) -> f64 {
        self.excitation_amplitude_counts * self.transformation_ratio
    }

    /// The ADC sample period (s): `1 / (N carrier_hz)`.
    pub fn adc_sample_period_s(&self) -> f64 {
        1.0 / (self.samples_per_period as f64 * self.carrier_hz)
    }

    /// The ADC's mid-scale code, `2^(adc_bits - 1)` (0 without an ADC).
    pub fn mid_scale_counts(&self) -> f64 {
        if self.adc_bits == 0 {
            0.0
        } else {
            f64::from(self.adc_bits - 1).exp2()
        }
    }

    fn validate(&self) -> Result<(), Error> {
        positive(self.carrier_hz, Argument::CarrierFrequency)?;
        if !(2..=1 << 16).contains(&self.samples_per_period) {
            return Err(Error::OutOfRange {
                argument: Argument::SamplesPerPeriod,
                expected: "2 to 65536",
            });
        }
        finite(self.carrier_delay_rad, Argument::CarrierDelay)?;
        // Beyond, a turn is below the delay's f64 resolution: the carrier would be noise.
        if self.carrier_delay_rad.abs() > 1e3 {
            return Err(Error::OutOfRange {
                argument: Argument::CarrierDelay,
                expected: "within +-1000 rad",
            });
        }
        positive(
            self.excitation_amplitude_counts,
            Argument::ExcitationAmplitude,
        )?;
        positive(self.transformation_ratio, Argument::TransformationRatio)?;
        finite(self.winding_imbalance, Argument::WindingImbalance)?;
        if self.winding_imbalance <= -1.0 {
            return Err(Error::OutOfRange {
                argument: Argument::WindingImbalance,
                expected: "> -1",
            });
        }
        finite(self.common_mode_counts, Argument::CommonMode)?;
        if self.adc_bits > 24 {
            return Err(Error::OutOfRange {
                argument: Argument::AdcBits,
                expected: "0 (no ADC) to 24",
            });
        }
        non_negative(self.noise_std_counts, Argument::NoiseStdCounts)?;
        Ok(())
    }

    /// The ADC code of a winding's voltage `v` (counts): rounded and saturated.
    fn quantise(&self, v: f64) -> f64 {
        if self.adc_bits == 0 {
            return v;
        }
        v.round().clamp(0.0, f64::from(self.adc_bits).exp2() - 1.0)
    }
}

impl Scenario {
    /// The windings of a carrier-excited resolver following `profile`, as an ADC samples
    /// them: a scenario at the ADC rate whose `y_c` and `y_s` are the raw samples (counts)
    /// of the cosine and sine windings beside the truth at each sample. The noise is drawn
    /// from a ChaCha8 generator seeded with `seed` (the same arguments give the same
    /// scenario on every machine). At most [`MAX_SAMPLES`](crate::MAX_SAMPLES) samples.
    ///
    /// ```
    /// use angletrack::{Motion, MotionProfile, ResolverModel, Scenario};
    /// let profile = MotionProfile::new(0.0, 314.159)
    ///     .then(Motion::ConstantSpeed { speed_rad_s: 314.159, duration_s: 0.01 });
    /// let capture = Scenario::resolver_windings(&profile, &ResolverModel::default(), 3)?;
    /// assert_eq!(capture.len(), 1601); // 10 ms at 160 kHz
    /// assert!(capture.y_c.iter().all(|&c| (0.0..4096.0).contains(&c)));
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn resolver_windings(
        profile: &MotionProfile,
        model: &ResolverModel,
        seed: u64,
    ) -> Result<Self, Error> {
        model.validate()?;
        let ts = model.adc_sample_period_s();
        let (n, truth) = profile.sample(ts)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, model.noise_std_counts)
            .map_err(|_| Error::NotFinite(Argument::NoiseStdCounts))?;
        let base = model.mid_scale_counts() + model.common_mode_counts;
        let amplitude_c = model.amplitude_counts();
        let amplitude_s = amplitude_c * (1.0 + model.winding_imbalance);
        let per_period = model.samples_per_period;
        let mut scenario = Scenario {
            sample_period_s: ts,
            time_s: Vec::with_capacity(n),
            ..Scenario::default()
        };
        for (k, state) in truth.enumerate() {
            let phase = std::f64::consts::TAU * (k % per_period) as f64 / per_period as f64;
            let carrier = (phase - model.carrier_delay_rad).sin();
            let (sin, cos) = state.angle_rad.sin_cos();
            let raw_c = base + amplitude_c * cos * carrier + normal.sample(&mut rng);
            let raw_s = base + amplitude_s * sin * carrier + normal.sample(&mut rng);
            scenario.time_s.push(k as f64 * ts);
            scenario.angle_rad.push(state.angle_rad);
            scenario.speed_rad_s.push(state.speed_rad_s);
            scenario.acceleration_rad_s2.push(state.acceleration_rad_s2);
            scenario.y_c.push(model.quantise(raw_c));
            scenario.y_s.push(model.quantise(raw_s));
        }
        Ok(scenario)
    }
}

#[cfg(test)]
mod tests;
