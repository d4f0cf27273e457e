//! Carrying a continuous design to the discrete recursion (`docs/theory.md §7`): each
//! continuous closed-loop pole `s_i` is mapped to a discrete pole `z_i`, and the gains are
//! those whose loop `(I - L e1^T) A` has exactly the poles `z_i`
//! ([`Gains::from_loop_polynomial`]). The loop polynomial is written in `z - 1`, computed
//! from `z_i - 1` directly, so that a loop a million times slower than its sample rate is
//! designed to full precision.

use core::fmt;
use core::str::FromStr;

#[cfg(doc)]
use super::MAX_POLE_TIMES_PERIOD;
use super::{PolePair, check_sample_rate};
use crate::const_config::Real;
use crate::error::{ConfigError, Parameter};
use crate::gains::Gains;
use crate::real::check_positive;
use crate::real::sincos::SinCos;

/// How a continuous design is carried over to the discrete recursion.
///
/// Each maps every continuous closed-loop pole `s_i` to a discrete pole `z_i`, and the gains
/// are chosen so that the discrete loop has exactly the poles `z_i`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Discretisation {
    /// `z = exp(s Ts)`: the discrete poles are exactly the sampled continuous poles (the
    /// default). Stable for any stable continuous design.
    #[default]
    PoleMatching,
    /// `z = 1 + s Ts`: the explicit Euler step of the continuous loop. Unstable once
    /// `|1 + s Ts| >= 1` for some pole (lightly damped poles first); refused there.
    ForwardEuler,
    /// `z = (1 + s Ts/2) / (1 - s Ts/2)`: the bilinear (trapezoidal) map. Stable for any
    /// stable continuous design; compresses high frequencies.
    Tustin,
}

impl Discretisation {
    /// Every discretisation, the default first.
    pub const ALL: [Discretisation; 3] = [
        Discretisation::PoleMatching,
        Discretisation::ForwardEuler,
        Discretisation::Tustin,
    ];

    /// `z - 1` as `(re, im)` for the continuous pole `re + j im` (rad/s) and the sample
    /// period `ts` (s), accurate when `|s| Ts` is small (no `1 +` that would round away),
    /// for the poles of a design: `|s| Ts <= 1` ([`MAX_POLE_TIMES_PERIOD`]). Pole matching's
    /// sine is a series for that range, so that `f32` needs no `f64` routine.
    ///
    /// ```
    /// use angletrack_core::Discretisation;
    /// let (re, im) = Discretisation::Tustin.map_pole(-1e3_f64, 0.0, 1e-4);
    /// assert!((re - -0.1 / 1.05).abs() < 1e-15 && im == 0.0);
    /// ```
    pub fn map_pole<T: Real>(self, re: T, im: T, ts: T) -> (T, T) {
        let (x, y) = (re * ts, im * ts);
        match self {
            Discretisation::PoleMatching => matched(x, y),
            Discretisation::ForwardEuler => (x, y),
            Discretisation::Tustin => {
                // w / (1 - w/2) = w conj(1 - w/2) / |1 - w/2|^2, w = x + j y.
                let real = T::ONE - x * T::HALF;
                let denominator = real * real + y * y * T::HALF * T::HALF;
                ((x * real - y * y * T::HALF) / denominator, y / denominator)
            }
        }
    }

    /// The name used in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Discretisation::PoleMatching => "pole matching",
            Discretisation::ForwardEuler => "forward Euler",
            Discretisation::Tustin => "Tustin",
        }
    }

    /// The identifier used on command lines and in the Python API: `pole_matching`,
    /// `forward_euler`, `tustin` (what [`str::parse`] accepts, with `-` or a space for
    /// `_`, in any case).
    pub const fn id(self) -> &'static str {
        match self {
            Discretisation::PoleMatching => "pole_matching",
            Discretisation::ForwardEuler => "forward_euler",
            Discretisation::Tustin => "tustin",
        }
    }
}

/// The error of parsing a [`Discretisation`]: the text names none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownDiscretisation;

impl fmt::Display for UnknownDiscretisation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("the discretisation must be pole_matching, forward_euler or tustin")
    }
}

impl core::error::Error for UnknownDiscretisation {}

impl FromStr for Discretisation {
    type Err = UnknownDiscretisation;

    /// Parses [`Discretisation::id`] (case, surrounding space, and `-` or a space for `_`
    /// ignored).
    ///
    /// ```
    /// use angletrack_core::Discretisation;
    /// assert_eq!("Forward-Euler".parse(), Ok(Discretisation::ForwardEuler));
    /// assert!("zoh".parse::<Discretisation>().is_err());
    /// ```
    fn from_str(text: &str) -> Result<Self, UnknownDiscretisation> {
        let text = text.trim();
        let same = |id: &str| {
            text.len() == id.len()
                && text.bytes().zip(id.bytes()).all(|(c, i)| match c {
                    b'-' | b' ' => i == b'_',
                    c => c.to_ascii_lowercase() == i,
                })
        };
        Discretisation::ALL
            .into_iter()
            .find(|d| same(d.id()))
            .ok_or(UnknownDiscretisation)
    }
}

/// `exp(x + j y) - 1`, accurate for small `x + j y`: the real part is
/// `expm1(x) cos y - 2 sin^2(y / 2)` with `cos y = 1 - 2 sin^2(y / 2)`, with no
/// cancellation.
fn matched<T: Real>(x: T, y: T) -> (T, T) {
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

impl<T: Real> PolePair<T> {
    /// The monic factor `s^2 + b s + c` (returned as `(b, c)`) of the discrete loop
    /// polynomial in `s = z - 1` whose roots are the mapped `z_i - 1`.
    fn discrete_factor(self, sample_period: T, discretisation: Discretisation) -> (T, T) {
        match self {
            PolePair::Complex { re, im } => {
                let (u_re, u_im) = discretisation.map_pole(re, im, sample_period);
                (-(u_re + u_re), u_re * u_re + u_im * u_im)
            }
            PolePair::Real(a, b) => {
                let u1 = discretisation.map_pole(a, T::ZERO, sample_period).0;
                let u2 = discretisation.map_pole(b, T::ZERO, sample_period).0;
                (-(u1 + u2), u1 * u2)
            }
        }
    }
}

impl<T: Real, S: SinCos<T>> Gains<T, 2, S> {
    /// The 2nd-order gains whose discrete loop has the continuous closed-loop poles `pair`
    /// (rad/s) mapped by `discretisation` at the sample period `sample_period_s` (s): the
    /// last step of every continuous 2nd-order design.
    ///
    /// Refuses a non-positive or non-finite sample period and poles faster than the sample
    /// rate (`|s_i| Ts > 1`), both named `sample_period_s`, and gains that
    /// [`Gains::from_loop_polynomial`] refuses (with its reason: mapped poles outside the
    /// stability region, as a forward Euler step too long for a lightly damped pair gives,
    /// or gains that underflow).
    ///
    /// ```
    /// use angletrack_core::{Discretisation, Gains, PolePair};
    /// let pair = PolePair::second_order(1e3_f64, 1.0);
    /// let gains = Gains::<f64, 2>::from_continuous_poles(pair, 1e-4, Discretisation::Tustin)?;
    /// assert!(gains.gains()[0] > 0.0);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_continuous_poles(
        pair: PolePair<T>,
        sample_period_s: T,
        discretisation: Discretisation,
    ) -> Result<Self, ConfigError> {
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        check_sample_rate(pair.fastest(), ts, Parameter::SamplePeriod)?;
        let (b, c) = pair.discrete_factor(ts, discretisation);
        Self::from_loop_polynomial([c, b], ts)
    }
}

impl<T: Real, S: SinCos<T>> Gains<T, 3, S> {
    /// The 3rd-order gains whose discrete loop has the continuous closed-loop poles
    /// `real_pole` and `pair` (rad/s) mapped by `discretisation` at the sample period
    /// `sample_period_s` (s): the last step of every continuous 3rd-order design.
    ///
    /// Refuses as [`Gains::<T, 2>::from_continuous_poles`](Gains::from_continuous_poles)
    /// does.
    ///
    /// ```
    /// use angletrack_core::{Discretisation, Gains, PolePair};
    /// let pair = PolePair::Complex { re: -500.0_f32, im: 500.0 };
    /// let gains =
    ///     Gains::<f32, 3>::from_continuous_poles(-500.0, pair, 1e-4, Discretisation::default())?;
    /// assert!(gains.gains()[2] > 0.0);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_continuous_poles(
        real_pole: T,
        pair: PolePair<T>,
        sample_period_s: T,
        discretisation: Discretisation,
    ) -> Result<Self, ConfigError> {
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        let fastest = real_pole.abs().max(pair.fastest());
        check_sample_rate(fastest, ts, Parameter::SamplePeriod)?;
        let (b, c) = pair.discrete_factor(ts, discretisation);
        let u = discretisation.map_pole(real_pole, T::ZERO, ts).0;
        // (s - u)(s^2 + b s + c), lowest coefficient first.
        Self::from_loop_polynomial([-(u * c), c - u * b, b - u], ts)
    }
}
