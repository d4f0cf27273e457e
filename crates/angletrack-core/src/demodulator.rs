//! The demodulator of a resolver front end (`docs/theory.md §13`): ADC samples of both
//! windings at any rate of at least 4 per carrier period, and optionally of the excitation,
//! in; one `(y_c, y_s)` pair per carrier period out, with the carrier tracked in phase and
//! frequency and the front end's diagnostics.
//!
//! Per sample: a phase accumulator (the carrier loop's oscillator) indexes a sine table,
//! and each winding's sample is multiplied by the reference `sin` and `cos` and summed,
//! with the samples and the reference themselves (eight sums; three more with the
//! excitation). The sums are cut into segments where the tracked carrier phase crosses a
//! quarter and a whole turn; a window is a period and the two quarters around it at half
//! weight (a trapezoid): its weights have a double zero at twice the carrier, so that the
//! product's component there leaves no bias however fast the envelope moves. Each
//! window's components have the windings' means over the window removed (offsets and any
//! non-whole number of samples per period leave no bias) and are divided by its weight.
//!
//! The carrier loop locks the oscillator to the windings' own carrier (modulo half a turn):
//! its phase detector is `sum I Q / sum (I^2 + Q^2)` over both windings, `sin(2e)/2` for a
//! phase error `e` at every shaft angle; a proportional-integral correction of the phase
//! and the step once per window. The pair is then the in-phase component. The half turn
//! is resolved from the recorded excitation when there is one, else from the expected
//! delay at the end of the start-up; the delay chosen is exposed.

use crate::error::{ConfigError, Parameter};
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;

mod carrier_loop;
mod construction;
mod number;
mod number_fixed;
mod push;
mod settings;
mod state;
mod window;

pub use number::{DemodulatorNumber, FIXED_PAIR_UNIT};
pub use settings::DemodulatorSettings;
pub use state::{DemodulatedPair, DemodulatorState};
use state::{PendingWindow, Segment, Sums};

/// The recorded excitation's least carrier amplitude as a fraction of the windings' nominal
/// one: below it (a flat or missing reference) the window's excitation resolves nothing
/// ([`FrontEndFaults::EXCITATION_REFERENCE`](crate::FrontEndFaults::EXCITATION_REFERENCE)).
pub const EXCITATION_REFERENCE_FRACTION: f32 = 0.125;

/// A quarter turn of the carrier loop's phase.
const QUARTER: u32 = 1 << 30;

/// The immutable, checked configuration of a demodulator in the number type `V` (`f32`,
/// `f64`, or `i16` for fixed point): the carrier loop's nominal step and gains, the
/// scale, the thresholds. `Copy`; the mutable part is a [`DemodulatorState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Demodulator<V: DemodulatorNumber> {
    step: u32,
    step_min: u32,
    step_max: u32,
    /// The proportional gain in phase units per Q31 detector unit, Q16.
    phase_gain: i32,
    /// The integral gain in step units per Q31 detector unit, Q24.
    step_gain: i32,
    clip_centre: V,
    clip_half_span: V,
    pair_gain: V::Wide,
    loss_power: V::Wide,
    weak_power: V::Wide,
    /// `cos(2 bound)`: the loop is out of lock where `cos 2e` is below it.
    drift_cos2: V::Wide,
    /// The recorded excitation's least usable power, in the pair's unit
    /// ([`EXCITATION_REFERENCE_FRACTION`] squared).
    reference_power: V::Wide,
    expected: u32,
    expected_cos: V::Wide,
    expected_sin: V::Wide,
    startup_periods: u32,
    carrier_hz: V::Real,
    adc_rate_hz: V::Real,
}

impl<V: DemodulatorNumber> Demodulator<V> {
    /// Checks `settings` and builds the configuration (the type's `new_const`, e.g.
    /// [`Demodulator::<f32>::new_const`](Demodulator::<f32>::new_const), at run time).
    ///
    /// Refuses a non-positive carrier frequency or amplitude, an ADC rate below 4 samples
    /// per carrier period or above the type's maximum, an empty ADC range or a margin
    /// covering it, a loss-of-excitation threshold outside [0, 1), a weak-excitation
    /// threshold outside [loss, 1], a drift bound outside (0, pi/2], a carrier loop
    /// bandwidth outside (0, 0.5], a carrier error outside (0, 0.2], and no start-up
    /// period, naming the setting.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, Parameter};
    /// // 10 kHz carrier, 48 kHz ADC (4.8 samples per period).
    /// let settings = DemodulatorSettings::<f32>::new(10e3, 48e3, 1800.0, 0.0, 4095.0);
    /// let demodulator = Demodulator::<f32>::new(settings)?;
    /// assert!((demodulator.pair_period_s() - 1e-4).abs() < 1e-10);
    /// let slow = DemodulatorSettings { adc_rate_hz: 30e3, ..settings };
    /// assert_eq!(Demodulator::<f32>::new(slow).unwrap_err().parameter(), Parameter::AdcRate);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(settings: DemodulatorSettings<V::Real>) -> Result<Self, ConfigError> {
        V::demodulator(settings)
    }

    /// Checks that `gains` run at the pair rate: their sample period must be the declared
    /// carrier period (to a relative 1e-4), else [`ConfigError::OutOfRange`] naming the
    /// sample period.
    pub fn check_gains<const M: usize, S: SinCos<V>>(
        &self,
        gains: &Gains<V, M, S>,
    ) -> Result<(), ConfigError>
    where
        V: Float + DemodulatorNumber<Real = V>,
    {
        let period = self.pair_period_s();
        if ((gains.sample_period() - period) / period).abs() <= V::from_f32(1e-4) {
            Ok(())
        } else {
            Err(ConfigError::OutOfRange(Parameter::SamplePeriod))
        }
    }

    /// The time (s) at which `pair` holds ([`DemodulatedPair::instant_sample`]), counting
    /// from the first ADC sample pushed (at time 0), from the ADC rate. In `f64`, for
    /// host-side code.
    pub fn centre_s(&self, pair: &DemodulatedPair<V>) -> f64 {
        pair.instant_sample() / self.adc_rate_hz.to_f64()
    }

    /// The carrier frequency (Hz) the loop tracks now (the declared one before the first
    /// sample); for diagnostics.
    pub fn tracked_carrier_hz(&self, state: &DemodulatorState<V>) -> V::Real {
        let step = if state.step == 0 {
            self.step
        } else {
            state.step
        };
        // step / 2^32 turns per sample, as two factors of 2^16 to stay within f32's range.
        let per = V::Real::from_f32(1.0 / 65_536.0);
        V::Real::from_i32((step >> 16) as i32) * per * self.adc_rate_hz
            + V::Real::from_i32((step & 0xffff) as i32) * per * per * self.adc_rate_hz
    }

    /// The time (s) from a pair's centre to its window's last sample, at the declared
    /// carrier: 5/8 of a period (the window's middle, 5/8 of a period before the quarter
    /// period after its period ends) less half an ADC sample (the last sample stands for
    /// the half sample before it). Add the time to the output for a drive's latency.
    pub fn centre_to_end_s(&self) -> V::Real {
        V::Real::from_f32(0.625) / self.carrier_hz - V::Real::HALF / self.adc_rate_hz
    }

    /// The declared carrier period (s): the sample period the observer's gains are designed
    /// for.
    pub fn pair_period_s(&self) -> V::Real {
        V::Real::ONE / self.carrier_hz
    }

    /// The ADC sample period (s).
    pub fn adc_sample_period_s(&self) -> V::Real {
        V::Real::ONE / self.adc_rate_hz
    }

    /// The declared ADC samples per carrier period (any ratio of at least 4).
    pub fn samples_per_period(&self) -> V::Real {
        self.adc_rate_hz / self.carrier_hz
    }
}

#[cfg(test)]
mod construction_tests;
#[cfg(test)]
mod range_tests;
#[cfg(test)]
mod reference_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod threshold_tests;
