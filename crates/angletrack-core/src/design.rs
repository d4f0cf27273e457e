//! Gain design on the target, in the observer's own float type (`f32` on a Cortex-M4F, with
//! no `f64` arithmetic): the classical 2nd-order ATO from a bandwidth and a damping ratio
//! (`docs/theory.md §2`), the 3rd-order ATO from its poles `(K, T, psi)` (§3) and the
//! time-invariant Kalman ATO from `q` and `r` (§4, in `design/kalman.rs`), so that firmware
//! can retune at run time. These are the designs: the `angletrack` crate's design functions
//! call them in `f64` and add what needs allocation (reports, frequency responses, the
//! searches over a specification).
//!
//! A continuous design reaches the recursion through a [`Discretisation`]
//! (`docs/theory.md §7`, `design/discretisation.rs`): pole matching by default, each
//! continuous closed-loop pole `s_i` becoming the discrete pole `z_i = exp(s_i Ts)`, carried
//! as `z_i - 1 = expm1(s_i Ts)` so that a loop far slower than its sample rate keeps its
//! precision, and the gains are those of the loop polynomial `prod (s - (z_i - 1))` in
//! `s = z - 1` ([`Gains::from_loop_polynomial`]).

use crate::const_config::Real;
use crate::error::{ConfigError, Parameter};
use crate::gains::Gains;
use crate::real::check_positive;
use crate::real::sincos::SinCos;

mod discretisation;
mod kalman;

pub use discretisation::{Discretisation, UnknownDiscretisation};

/// The largest `|s_i| Ts` a continuous design may have: every continuous pole must lie
/// below the sample rate in rad/s (`|s_i| <= 1 / Ts`, i.e. pole frequencies below
/// `fs / (2 pi)`). Beyond it the discrete loop no longer behaves like the continuous design
/// whatever the mapping.
pub const MAX_POLE_TIMES_PERIOD: f32 = 1.0;

/// A pair of continuous closed-loop poles (rad/s): the 2nd-order loop's, or the pair beside
/// the real pole of the 3rd-order loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PolePair<T> {
    /// `re +- j im`.
    Complex {
        /// The real part (rad/s).
        re: T,
        /// The imaginary part of the upper pole (rad/s).
        im: T,
    },
    /// Two real poles (rad/s).
    Real(T, T),
}

impl<T: Real> PolePair<T> {
    /// The roots of `s^2 + 2 m wn s + wn^2` for the natural frequency
    /// `natural_frequency_rad_s` (`wn`) and the damping `damping` (`m`): complex below
    /// `m = 1`, real from it on.
    ///
    /// ```
    /// use angletrack_core::PolePair;
    /// assert_eq!(PolePair::second_order(2.0_f64, 0.0), PolePair::Complex { re: -0.0, im: 2.0 });
    /// let PolePair::Real(fast, slow) = PolePair::second_order(1.0_f64, 1.25) else { panic!() };
    /// assert!((fast - -2.0).abs() < 1e-15 && (slow - -0.5).abs() < 1e-15);
    /// ```
    pub fn second_order(natural_frequency_rad_s: T, damping: T) -> Self {
        let (wn, m) = (natural_frequency_rad_s, damping);
        // With (1 - m)(1 + m) for 1 - m^2 (no cancellation near critical damping) and the
        // smaller real root from the product of the roots (no cancellation at heavy
        // damping).
        let spread = (T::ONE - m) * (T::ONE + m);
        if spread > T::ZERO {
            PolePair::Complex {
                re: -(m * wn),
                im: wn * spread.sqrt(),
            }
        } else {
            let fast = -(wn * (m + (-spread).sqrt()));
            PolePair::Real(fast, wn * wn / fast)
        }
    }

    /// The largest pole magnitude (rad/s).
    pub fn fastest(self) -> T {
        match self {
            PolePair::Complex { re, im } => (re * re + im * im).sqrt(),
            PolePair::Real(a, b) => a.abs().max(b.abs()),
        }
    }

    /// The two poles as `(re, im)`, in increasing order of `(re, im)`: the lower or the
    /// faster real one first.
    pub fn poles(self) -> [(T, T); 2] {
        match self {
            PolePair::Complex { re, im } => {
                let im = im.abs();
                [(re, -im), (re, im)]
            }
            // A comparison, not `min`/`max`, which would drop a NaN pole.
            PolePair::Real(a, b) if b < a => [(b, T::ZERO), (a, T::ZERO)],
            PolePair::Real(a, b) => [(a, T::ZERO), (b, T::ZERO)],
        }
    }
}

/// Refuses a design whose fastest pole `fastest` (rad/s) is at or beyond the sample rate
/// (rad/s), naming `parameter` (NaN, from an overflow, is refused too).
fn check_sample_rate<T: Real>(
    fastest: T,
    sample_period: T,
    parameter: Parameter,
) -> Result<(), ConfigError> {
    if !(fastest * sample_period <= T::from_f32(MAX_POLE_TIMES_PERIOD)) {
        return Err(ConfigError::OutOfRange(parameter));
    }
    Ok(())
}

/// `value` in `(0, max]`, naming `parameter`.
fn check_bounded<T: Real>(value: T, max: f32, parameter: Parameter) -> Result<T, ConfigError> {
    let value = check_positive(value, parameter)?;
    if !(value <= T::from_f32(max)) {
        return Err(ConfigError::OutOfRange(parameter));
    }
    Ok(value)
}

/// The ratio `omega_3dB / omega_n` of the -3 dB bandwidth of the classical 2nd-order loop
/// `(2 m wn s + wn^2) / (s^2 + 2 m wn s + wn^2)` to its natural frequency, for the damping
/// ratio `m` (`docs/theory.md §2`): `sqrt(a + sqrt(a^2 + 1))`, `a = 1 + 2 m^2`.
///
/// ```
/// // Damping sqrt(2)/2: the -3 dB bandwidth is 2.06 times the natural frequency.
/// let ratio = angletrack_core::second_order_bandwidth_ratio(2f64.sqrt() / 2.0);
/// assert!((ratio - 2.058).abs() < 1e-3);
/// ```
pub fn second_order_bandwidth_ratio<T: Real>(m: T) -> T {
    let a = T::ONE + T::TWO * m * m;
    (a + (a * a + T::ONE).sqrt()).sqrt()
}

impl<T: Real, S: SinCos<T>> Gains<T, 2, S> {
    /// The classical 2nd-order ATO `s^2 + 2 m wn s + wn^2` (`docs/theory.md §2`) whose
    /// closed-loop -3 dB bandwidth is `bandwidth_hz` (Hz), with damping ratio `damping`
    /// (`m`), pole-matched at the sample period `sample_period_s` (s)
    /// (`docs/theory.md §7`): the `angletrack` crate's `second_order_from_bandwidth` with
    /// its default discretisation, computed in `T`.
    ///
    /// Refuses a non-positive or non-finite argument, a damping above 1000 and a design
    /// whose poles are faster than the sample rate (`wn Ts > 1`, named `bandwidth_hz`).
    ///
    /// ```
    /// use angletrack_core::{Gains, Parameter};
    /// // Retune at run time: 200 Hz, critically damped, at 20 kHz.
    /// let gains = Gains::<f32, 2>::second_order_from_bandwidth(200.0, 1.0, 50e-6)?;
    /// let [l1, l2] = gains.gains();
    /// assert!((l1 - 0.049_36).abs() < 1e-5 && (l2 - 0.000_624_7).abs() < 1e-7);
    /// let err = Gains::<f32, 2>::second_order_from_bandwidth(200e3, 1.0, 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::Bandwidth);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn second_order_from_bandwidth(
        bandwidth_hz: T,
        damping: T,
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        let bandwidth = check_positive(bandwidth_hz, Parameter::Bandwidth)?;
        let m = check_bounded(damping, 1e3, Parameter::Damping)?;
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        let wn = T::TAU * bandwidth / second_order_bandwidth_ratio(m);
        let pair = PolePair::second_order(wn, m);
        check_sample_rate(pair.fastest(), ts, Parameter::Bandwidth)?;
        Self::from_continuous_poles(pair, ts, Discretisation::PoleMatching)
    }
}

impl<T: Real, S: SinCos<T>> Gains<T, 3, S> {
    /// The 3rd-order ATO by pole placement (`docs/theory.md §3`): a real pole at `-K/T`
    /// and a complex pair at `(-1 +- j psi)/T`, from `pole_ratio` (`K`, in (0, 1e6]),
    /// `pole_time_constant_s` (`T`, s) and `pole_frequency_ratio` (`psi`, in (0, 1000]),
    /// pole-matched at the sample period `sample_period_s` (s) (`docs/theory.md §7`): the
    /// `angletrack` crate's `third_order_from_poles` with its default discretisation,
    /// computed in `T`.
    ///
    /// Refuses a non-positive or non-finite argument, `K` or `psi` out of range and poles
    /// faster than the sample rate (named `pole_time_constant_s`).
    ///
    /// ```
    /// use angletrack_core::{Gains, Parameter};
    /// // K = 1, T = 2 ms, psi = 1 at 20 kHz.
    /// let gains = Gains::<f32, 3>::third_order_from_poles(1.0, 2e-3, 1.0, 50e-6)?;
    /// let [l1, l2, l3] = gains.gains();
    /// assert!(l1 > 0.0 && l2 > 0.0 && l3 > 0.0);
    /// let err = Gains::<f32, 3>::third_order_from_poles(1.0, 1e-5, 1.0, 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::PoleTimeConstant);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn third_order_from_poles(
        pole_ratio: T,
        pole_time_constant_s: T,
        pole_frequency_ratio: T,
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        let k = check_bounded(pole_ratio, 1e6, Parameter::PoleRatio)?;
        let psi = check_bounded(pole_frequency_ratio, 1e3, Parameter::PoleFrequencyRatio)?;
        let t = check_positive(pole_time_constant_s, Parameter::PoleTimeConstant)?;
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        let real_pole = -(k / t);
        let pair = PolePair::Complex {
            re: -(T::ONE / t),
            im: psi / t,
        };
        let fastest = real_pole.abs().max(pair.fastest());
        check_sample_rate(fastest, ts, Parameter::PoleTimeConstant)?;
        Self::from_continuous_poles(real_pole, pair, ts, Discretisation::PoleMatching)
    }
}

#[cfg(test)]
mod tests;
