//! Gain design on the target, in the observer's own float type (`f32` on a Cortex-M4F, with
//! no `f64` arithmetic): the classical 2nd-order ATO from a bandwidth and a damping ratio
//! (`docs/theory.md §2`), the 3rd-order ATO from its poles `(K, T, psi)` (§3) and the
//! time-invariant Kalman ATO from `q` and `r` (§4, in `design/kalman.rs`), so that firmware
//! can retune at run time. They give the same gains as the `angletrack` crate's designs
//! with their default pole matching, to the float type's precision (tested against that
//! crate's values in `design/tests.rs`).
//!
//! Pole matching (`docs/theory.md §7`): each continuous closed-loop pole `s_i` becomes the
//! discrete pole `z_i = exp(s_i Ts)`, carried as `z_i - 1 = expm1(s_i Ts)` so that a loop
//! far slower than its sample rate keeps its precision, and the gains are those of the loop
//! polynomial `prod (s - (z_i - 1))` in `s = z - 1` ([`Gains::from_loop_polynomial`]).

use crate::const_config::Real;
use crate::error::{ConfigError, Parameter};
use crate::gains::Gains;
use crate::real::check_positive;
use crate::real::sincos::SinCos;

mod kalman;

/// The largest `|s_i| Ts` of a continuous design, as in the `angletrack` crate: every
/// continuous pole below the sample rate in rad/s. Beyond it the discrete loop no longer
/// behaves like the continuous design.
const MAX_POLE_TIMES_PERIOD: f32 = 1.0;

/// A pair of continuous closed-loop poles (rad/s).
#[derive(Debug, Clone, Copy)]
enum PolePair<T> {
    /// `re +- j im`.
    Complex { re: T, im: T },
    /// Two real poles.
    Real(T, T),
}

impl<T: Real> PolePair<T> {
    /// The largest pole magnitude (rad/s).
    fn fastest(self) -> T {
        match self {
            PolePair::Complex { re, im } => (re * re + im * im).sqrt(),
            PolePair::Real(a, b) => a.abs().max(b.abs()),
        }
    }

    /// The monic factor `s^2 + b s + c` (returned as `(b, c)`) of the discrete loop
    /// polynomial in `s = z - 1` whose roots are the pole-matched `z_i - 1`.
    fn matched_factor(self, sample_period: T) -> (T, T) {
        match self {
            PolePair::Complex { re, im } => {
                let (u_re, u_im) = matched_complex(re * sample_period, im * sample_period);
                (-(u_re + u_re), u_re * u_re + u_im * u_im)
            }
            PolePair::Real(a, b) => {
                let (u1, u2) = ((a * sample_period).exp_m1(), (b * sample_period).exp_m1());
                (-(u1 + u2), u1 * u2)
            }
        }
    }
}

/// `exp(x + j y) - 1`, accurate for small `x + j y`: the real part is
/// `expm1(x) cos y - 2 sin^2(y / 2)` with `cos y = 1 - 2 sin^2(y / 2)`, with no
/// cancellation.
fn matched_complex<T: Real>(x: T, y: T) -> (T, T) {
    let sin_half = small_angle_sin(y * T::HALF);
    let versine = T::TWO * sin_half * sin_half;
    let expm1 = x.exp_m1();
    (
        expm1 * (T::ONE - versine) - versine,
        (expm1 + T::ONE) * small_angle_sin(y),
    )
}

/// `sin y` for `|y| <= 1` (a design's poles are below the sample rate), to about an ulp
/// relative, by its Taylor series: `libm`'s `sinf` computes in `f64`, which a Cortex-M4F
/// emulates in software, and the phase detector's polynomial is accurate in absolute terms
/// only, not for the small angles of a slow loop.
fn small_angle_sin<T: Real>(y: T) -> T {
    // The 10th term is below y^21 / 21! < 2e-20: negligible in f64.
    let y2 = y * y;
    let mut term = y;
    let mut sum = y;
    let mut k = 1;
    while k < 10 {
        let n = T::from_i32(2 * k);
        term = -(term * y2 / (n * (n + T::ONE)));
        sum += term;
        k += 1;
    }
    sum
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

/// The ratio of the -3 dB bandwidth of the classical 2nd-order loop to its natural
/// frequency, for the damping ratio `m` (`docs/theory.md §2`):
/// `sqrt(a + sqrt(a^2 + 1))`, `a = 1 + 2 m^2`.
fn second_order_bandwidth_ratio<T: Real>(m: T) -> T {
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
        // The roots of s^2 + 2 m wn s + wn^2, with (1 - m)(1 + m) for 1 - m^2 (no
        // cancellation near critical damping) and the smaller real root from the product
        // of the roots (no cancellation at heavy damping).
        let spread = (T::ONE - m) * (T::ONE + m);
        let pair = if spread > T::ZERO {
            PolePair::Complex {
                re: -(m * wn),
                im: wn * spread.sqrt(),
            }
        } else {
            let fast = -(wn * (m + (-spread).sqrt()));
            PolePair::Real(fast, wn * wn / fast)
        };
        check_sample_rate(pair.fastest(), ts, Parameter::Bandwidth)?;
        let (b, c) = pair.matched_factor(ts);
        Self::from_loop_polynomial([c, b], ts)
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
        let (b, c) = pair.matched_factor(ts);
        let u = (real_pole * ts).exp_m1();
        // (s - u)(s^2 + b s + c), lowest coefficient first.
        Self::from_loop_polynomial([-(u * c), c - u * b, b - u], ts)
    }
}

#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;
