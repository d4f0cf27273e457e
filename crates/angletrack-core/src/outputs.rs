//! What a drive takes from the observer (`docs/theory.md §13`): the angle at the PWM update
//! instant (extrapolated by a latency from speed and acceleration), as the motor's electrical
//! angle for its pole pairs and the shaft's mechanical angle for the resolver's speed ratio,
//! and the speed with an optional low-pass.

use crate::error::{ConfigError, Parameter};
use crate::real::Float;
use crate::real::check_positive;
use crate::state::Estimate;
use crate::wrap::wrap_angle;

/// The immutable, checked configuration of the drive outputs. `Copy`; the speed filter's
/// memory is a [`DriveOutputsState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveOutputs<T> {
    pole_pairs: u32,
    speed_ratio: u32,
    latency: T,
    half_latency_squared: T,
    sample_period: T,
    speed_filter_factor: T,
    per_speed_ratio: T,
    electrical_per_resolver: T,
}

/// The mutable state of the drive outputs: the speed filter's memory.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveOutputsState<T> {
    speed: T,
    primed: bool,
}

/// The angle and speed a drive needs, at the PWM update instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveAngle<T> {
    /// The motor's electrical angle (rad, in [-pi, pi)): pole pairs times the mechanical
    /// angle, from the multi-turn resolver angle, so exact however many turns.
    pub electrical_angle: T,
    /// The motor's electrical speed (rad/s), filtered.
    pub electrical_speed: T,
    /// The shaft's mechanical angle (rad, in [-pi, pi)), with the resolver's speed ratio
    /// taken out; the turn count's start is where the observer started.
    pub mechanical_angle: T,
    /// Whole mechanical turns.
    pub mechanical_turns: i64,
    /// The shaft's mechanical speed (rad/s), filtered.
    pub mechanical_speed: T,
}

impl<T: Float> DriveOutputs<T> {
    /// Outputs for a motor of `pole_pairs` pole pairs read by a resolver of speed ratio
    /// `speed_ratio` (electrical turns of the resolver per mechanical turn: 1 for a 1X
    /// resolver), the angle extrapolated by `latency_s` (s, in [0, 1]: from the observer's
    /// sample instant to the PWM update), for observer estimates every `sample_period_s`
    /// (s). Without a speed filter; add one with [`DriveOutputs::with_speed_cutoff_hz`].
    ///
    /// ```
    /// use angletrack_core::{DriveOutputs, DriveOutputsState, Estimate, Faults, Parameter};
    /// let outputs = DriveOutputs::<f32>::new(4, 1, 50e-6, 1e-4)?;
    /// let estimate = Estimate::new(0.1, 3, 100.0, 0.0, 0.0, Faults::NONE);
    /// let drive = outputs.outputs(&mut DriveOutputsState::default(), &estimate);
    /// assert!((drive.mechanical_angle - 0.105).abs() < 1e-6); // 0.1 + 100 * 50e-6
    /// assert!((drive.electrical_angle - 0.42).abs() < 1e-5);  // 4 pole pairs
    /// let err = DriveOutputs::<f32>::new(0, 1, 0.0, 1e-4).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::PolePairs);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(
        pole_pairs: u32,
        speed_ratio: u32,
        latency_s: T,
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        // Up to 2^16 each, so that their products with a turn remainder fit a u64.
        if !(1..=1 << 16).contains(&pole_pairs) {
            return Err(ConfigError::OutOfRange(Parameter::PolePairs));
        }
        if !(1..=1 << 16).contains(&speed_ratio) {
            return Err(ConfigError::OutOfRange(Parameter::SpeedRatio));
        }
        if !latency_s.is_finite() {
            return Err(ConfigError::NotFinite(Parameter::Latency));
        }
        if !(latency_s >= T::ZERO && latency_s <= T::ONE) {
            return Err(ConfigError::OutOfRange(Parameter::Latency));
        }
        let sample_period = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        // u32 up to 2^16 converts exactly through i32.
        let ratio = T::from_i32(speed_ratio as i32);
        Ok(Self {
            pole_pairs,
            speed_ratio,
            latency: latency_s,
            half_latency_squared: latency_s * latency_s * T::HALF,
            sample_period,
            speed_filter_factor: T::ONE,
            per_speed_ratio: T::ONE / ratio,
            electrical_per_resolver: T::from_i32(pole_pairs as i32) / ratio,
        })
    }

    /// The same outputs with a first-order low-pass of cut-off `cutoff_hz` (Hz, below half
    /// the sample rate) on the speed: [`DriveOutputs::with_speed_time_constant_s`] with
    /// `tau = 1 / (2 pi cutoff_hz)`.
    ///
    /// ```
    /// use angletrack_core::{DriveOutputs, Parameter};
    /// let outputs = DriveOutputs::<f32>::new(4, 1, 0.0, 1e-4)?.with_speed_cutoff_hz(200.0)?;
    /// let err = DriveOutputs::<f32>::new(4, 1, 0.0, 1e-4)?.with_speed_cutoff_hz(6e3).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::SpeedFilter);
    /// # let _ = outputs;
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_speed_cutoff_hz(self, cutoff_hz: T) -> Result<Self, ConfigError> {
        let cutoff = check_positive(cutoff_hz, Parameter::SpeedFilter)?;
        if !(cutoff * self.sample_period < T::HALF) {
            return Err(ConfigError::OutOfRange(Parameter::SpeedFilter));
        }
        self.with_speed_time_constant_s(T::ONE / (T::TAU * cutoff))
    }

    /// The same outputs with a first-order low-pass of time constant `time_constant_s` (s)
    /// on the speed, discretised by backward Euler: `v_f += Ts / (tau + Ts) (v - v_f)`, whose
    /// pole `tau / (tau + Ts)` is `exp(-Ts / tau)` to first order and stable for every
    /// `tau > 0`.
    pub fn with_speed_time_constant_s(self, time_constant_s: T) -> Result<Self, ConfigError> {
        let tau = check_positive(time_constant_s, Parameter::SpeedFilter)?;
        Ok(Self {
            speed_filter_factor: self.sample_period / (tau + self.sample_period),
            ..self
        })
    }

    /// The drive's angle and speed from one observer estimate (of the resolver's electrical
    /// angle): extrapolated by the latency, `theta + w t + a t^2 / 2` with the whole turns
    /// counted, then divided by the speed ratio and multiplied by the pole pairs with the
    /// turn count in integers. Call it once per estimate: it advances the speed filter.
    #[inline]
    pub fn outputs(
        &self,
        state: &mut DriveOutputsState<T>,
        estimate: &Estimate<T>,
    ) -> DriveAngle<T> {
        let t = self.latency;
        let mut angle =
            estimate.angle + estimate.speed * t + estimate.acceleration * self.half_latency_squared;
        let turns = estimate
            .turns
            .wrapping_add(i64::from(wrap_angle(&mut angle)));
        // At least 1 by construction; `max` lets the compiler see it, so that the
        // remainders below have no division-by-zero panic path.
        let ratio = i64::from(self.speed_ratio.max(1));
        // The resolver's turns in the current mechanical turn, then the electrical turns'
        // fraction (in 1/ratio turns): exact integers, so no precision is lost to the count.
        let within = turns.rem_euclid(ratio) as u64;
        let electrical_part = (u64::from(self.pole_pairs) * within) % ratio as u64;
        let mut mechanical_turns = turns.div_euclid(ratio);
        let mut mechanical_angle =
            (T::TAU * T::from_i32(within as i32) + angle) * self.per_speed_ratio;
        mechanical_turns =
            mechanical_turns.wrapping_add(i64::from(wrap_angle(&mut mechanical_angle)));
        let mut electrical_angle =
            T::TAU * T::from_i32(electrical_part as i32) * self.per_speed_ratio
                + angle * self.electrical_per_resolver;
        wrap_angle(&mut electrical_angle);
        let speed = (estimate.speed + estimate.acceleration * t) * self.per_speed_ratio;
        if state.primed && speed.is_finite() {
            state.speed += self.speed_filter_factor * (speed - state.speed);
        } else {
            state.speed = speed;
            state.primed = speed.is_finite();
        }
        DriveAngle {
            electrical_angle,
            electrical_speed: state.speed * T::from_i32(self.pole_pairs as i32),
            mechanical_angle,
            mechanical_turns,
            mechanical_speed: state.speed,
        }
    }

    /// The latency (s) the angle is extrapolated by.
    pub fn latency_s(&self) -> T {
        self.latency
    }
}

#[cfg(test)]
mod tests;
