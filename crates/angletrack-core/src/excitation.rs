//! The resolver's excitation reference (`docs/theory.md §13`): a phase accumulator that
//! firmware advances once per DAC/PWM update, giving the sine (or square) carrier to write
//! out, and the ADC sampling schedule the carrier implies.
//!
//! The phase is a `u32` turn fraction (2^32 = one turn) advanced by the exact rational step
//! `2^32 carrier_hz / tick_rate_hz`: an integer part and a remainder carried as in
//! Bresenham's line algorithm, so after `tick_rate_hz` ticks the phase is back where it started
//! to the bit. The carrier then never drifts against an ADC clocked from the same timer,
//! however long the drive runs (a float accumulator would drift by its rounding every tick).

use crate::error::{ConfigError, Parameter};
use crate::real::Float;

/// The excitation's waveform.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Waveform {
    /// A sine carrier (a DAC, or a PWM with a filter).
    #[default]
    Sine,
    /// A square carrier, `+1` for the first half of each period and `-1` for the second
    /// (a push-pull driver); the resolver's inductance and the filters round it.
    Square,
}

/// The immutable, checked configuration of the excitation: carrier frequency, tick rate
/// and waveform.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Excitation {
    carrier_hz: u32,
    tick_rate_hz: u32,
    step: u32,
    remainder_step: u32,
    waveform: Waveform,
}

/// The mutable part of the excitation: the phase accumulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ExcitationState {
    phase: u32,
    remainder: u32,
}

impl ExcitationState {
    /// The phase of the next tick, as a fraction of a turn times 2^32 (0 = the start of a
    /// carrier period, where the sine crosses zero upwards).
    pub fn phase(&self) -> u32 {
        self.phase
    }
}

impl Excitation {
    /// A carrier of `carrier_hz` written out `tick_rate_hz` times per second (both in Hz,
    /// integers as timers count). The carrier must be below half the tick rate (else it
    /// aliases).
    ///
    /// ```
    /// use angletrack_core::{Excitation, ExcitationState, Parameter, Waveform};
    /// // 10 kHz carrier written at 160 kHz: 16 ticks per period.
    /// let excitation = Excitation::new(10_000, 160_000, Waveform::Sine)?;
    /// assert_eq!(excitation.samples_per_period(), Some(16));
    /// let mut state = ExcitationState::default();
    /// let first: Vec<f32> = (0..5).map(|_| excitation.tick(&mut state)).collect();
    /// assert!(first[0].abs() < 1e-6 && (first[4] - 1.0).abs() < 1e-6); // sin(0), sin(pi/2)
    /// let err = Excitation::new(90_000, 160_000, Waveform::Sine).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::CarrierFrequency);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(
        carrier_hz: u32,
        tick_rate_hz: u32,
        waveform: Waveform,
    ) -> Result<Self, ConfigError> {
        if tick_rate_hz == 0 {
            return Err(ConfigError::NotPositive(Parameter::TickRate));
        }
        if carrier_hz == 0 {
            return Err(ConfigError::NotPositive(Parameter::CarrierFrequency));
        }
        if u64::from(carrier_hz) * 2 >= u64::from(tick_rate_hz) {
            return Err(ConfigError::OutOfRange(Parameter::CarrierFrequency));
        }
        let scaled = u64::from(carrier_hz) << 32;
        let rate = u64::from(tick_rate_hz);
        // carrier < rate / 2, so the step is below 2^31 and the remainder below the rate.
        Ok(Self {
            carrier_hz,
            tick_rate_hz,
            step: (scaled / rate) as u32,
            remainder_step: (scaled % rate) as u32,
            waveform,
        })
    }

    /// Advances the accumulator by one tick and returns the carrier value of this tick, in
    /// [-1, 1] (scale it to the DAC's codes or the PWM's compare value).
    #[inline]
    pub fn tick<T: Float>(&self, state: &mut ExcitationState) -> T {
        let phase = state.phase;
        state.phase = phase.wrapping_add(self.step);
        // Both terms are below the tick rate, so the sum fits in a u64 and one subtraction
        // brings it back below the rate.
        let sum = u64::from(state.remainder) + u64::from(self.remainder_step);
        let carry = sum >= u64::from(self.tick_rate_hz);
        state.remainder = (sum - u64::from(self.tick_rate_hz) * u64::from(carry)) as u32;
        state.phase = state.phase.wrapping_add(u32::from(carry));
        self.value_at(phase)
    }

    /// The carrier value at `phase` (a turn fraction times 2^32), in [-1, 1].
    #[inline]
    pub fn value_at<T: Float>(&self, phase: u32) -> T {
        match self.waveform {
            Waveform::Sine => phase_to_rad::<T>(phase).fast_sin_cos().0,
            Waveform::Square if phase < 1 << 31 => T::ONE,
            Waveform::Square => -T::ONE,
        }
    }

    /// The number of ticks per carrier period when it is a whole number: the ADC sampling
    /// schedule of a demodulator clocked with the excitation (one ADC sample of each
    /// winding per tick). `None` if the tick rate is not a multiple of the carrier.
    pub fn samples_per_period(&self) -> Option<u32> {
        self.tick_rate_hz
            .is_multiple_of(self.carrier_hz)
            .then(|| self.tick_rate_hz / self.carrier_hz)
    }

    /// For one ADC sample per carrier period (a peak-sampling front end): the time (s) after
    /// the start of each carrier period at which the windings' carrier, delayed by
    /// `carrier_delay_rad` (it lags the excitation by that phase), peaks:
    /// `((pi/2 + delay) mod 2 pi) / (2 pi carrier_hz)`.
    ///
    /// ```
    /// use angletrack_core::{Excitation, Waveform};
    /// let excitation = Excitation::new(10_000, 160_000, Waveform::Sine)?;
    /// let t: f32 = excitation.peak_sample_time_s(0.0);
    /// assert!((t - 25e-6).abs() < 1e-9); // a quarter period
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn peak_sample_time_s<T: Float>(&self, carrier_delay_rad: T) -> T {
        let mut phase = T::FRAC_PI_2 + carrier_delay_rad;
        crate::wrap::wrap_angle(&mut phase);
        if phase < T::ZERO {
            phase += T::TAU;
        }
        // carrier_hz < tick_rate_hz / 2 <= 2^31: it fits an i32.
        phase / (T::TAU * T::from_i32(self.carrier_hz as i32))
    }

    /// The carrier frequency (Hz).
    pub fn carrier_hz(&self) -> u32 {
        self.carrier_hz
    }

    /// The tick rate (Hz).
    pub fn tick_rate_hz(&self) -> u32 {
        self.tick_rate_hz
    }

    /// The waveform.
    pub fn waveform(&self) -> Waveform {
        self.waveform
    }
}

/// A turn fraction times 2^32 as an angle in [-pi, pi) (rad): the phase read as a signed
/// integer, so the angle is already wrapped.
#[inline(always)]
fn phase_to_rad<T: Float>(phase: u32) -> T {
    // 2 pi / 2^32 is exact in both types up to the rounding of pi.
    T::from_i32(phase as i32) * (T::PI * T::from_f32(1.0 / 2_147_483_648.0))
}

#[cfg(test)]
mod tests;
