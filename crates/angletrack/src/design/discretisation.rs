//! Carrying a continuous design to the discrete recursion (`docs/theory.md §7`): each
//! continuous closed-loop pole `s_i` is mapped to a discrete pole `z_i`, and the gains are
//! those whose loop `(I - L e1^T) A` has exactly the poles `z_i`. The loop polynomial is
//! written in `z - 1`, computed from `z_i - 1` directly (`exp_m1` for pole matching), so
//! that a loop a million times slower than its sample rate is designed to full precision.

use angletrack_core::{Gains, Order, SupportedOrder};
use nalgebra::Complex;

use super::{Design, DesignMethod};
use crate::error::{Argument, Error, positive};
use crate::linalg;

/// How a continuous design is carried over to the discrete recursion.
///
/// Each maps every continuous closed-loop pole `s_i` to a discrete pole `z_i`, and the gains
/// are chosen so that the discrete loop has exactly the poles `z_i`. The
/// [`DesignReport`](crate::DesignReport) shows how far the result moves from the continuous
/// design (continuous-equivalent poles `ln(z_i) / Ts`, overshoot of both step responses).
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
    /// `z - 1` for the continuous pole `s` (rad/s) and the sample period `ts` (s).
    pub fn map_pole(self, s: Complex<f64>, ts: f64) -> Complex<f64> {
        let w = s * ts;
        match self {
            Discretisation::PoleMatching => linalg::exp_m1(w),
            Discretisation::ForwardEuler => w,
            Discretisation::Tustin => w / (Complex::new(1.0, 0.0) - w * 0.5),
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

impl core::str::FromStr for Discretisation {
    type Err = Error;

    /// Parses [`Discretisation::id`] (case, `-` and spaces ignored).
    ///
    /// ```
    /// use angletrack::Discretisation;
    /// assert_eq!("Forward-Euler".parse(), Ok(Discretisation::ForwardEuler));
    /// assert!("zoh".parse::<Discretisation>().is_err());
    /// ```
    fn from_str(text: &str) -> Result<Self, Error> {
        let id: String = text
            .trim()
            .chars()
            .map(|c| match c {
                '-' | ' ' => '_',
                c => c.to_ascii_lowercase(),
            })
            .collect();
        [
            Discretisation::PoleMatching,
            Discretisation::ForwardEuler,
            Discretisation::Tustin,
        ]
        .into_iter()
        .find(|d| d.id() == id)
        .ok_or(Error::OutOfRange {
            argument: Argument::Discretisation,
            expected: "pole_matching, forward_euler or tustin",
        })
    }
}

/// The largest `|s_i| Ts` a continuous design may have: every continuous pole must lie
/// below the sample rate in rad/s (`|s_i| <= 1 / Ts`, i.e. pole frequencies below
/// `fs / (2 pi)`). Beyond it the discrete loop no longer behaves like the continuous design
/// whatever the mapping.
pub const MAX_POLE_TIMES_PERIOD: f64 = 1.0;

/// Carries continuous closed-loop poles to discrete gains: the shared last step of every
/// continuous design.
pub(super) fn discretise<const N: usize>(
    poles: Vec<Complex<f64>>,
    sample_period_s: f64,
    discretisation: Discretisation,
    speed_argument: Argument,
    method: DesignMethod,
) -> Result<Design<N>, Error>
where
    Order<N>: SupportedOrder,
{
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    // A NaN pole (an argument so large that the poles overflow) must not be folded away by
    // `f64::max`, which drops NaN: it is kept, and then refused below.
    let fastest = poles
        .iter()
        .map(|s| s.norm() * ts)
        .fold(0.0, |a: f64, b| if b.is_nan() || b > a { b } else { a });
    if !(fastest <= MAX_POLE_TIMES_PERIOD) {
        return Err(Error::TooFastForSampleRate {
            argument: speed_argument,
            pole_times_period: fastest,
            limit: MAX_POLE_TIMES_PERIOD,
        });
    }
    let shifted: Vec<Complex<f64>> = poles
        .iter()
        .map(|&s| discretisation.map_pole(s, ts))
        .collect();
    if discretisation == Discretisation::ForwardEuler {
        // |z| = |1 + s Ts| must stay below 1.
        let largest = shifted
            .iter()
            .map(|u| (Complex::new(1.0, 0.0) + u).norm())
            .fold(0.0, f64::max);
        if !(largest < 1.0) {
            let limit = poles
                .iter()
                .map(|s| -2.0 * s.re / s.norm())
                .fold(f64::INFINITY, f64::min);
            return Err(Error::TooFastForSampleRate {
                argument: speed_argument,
                pole_times_period: fastest,
                limit,
            });
        }
    }
    let c = linalg::monic_from_roots(&shifted);
    let mut coefficients = [0.0; N];
    coefficients.copy_from_slice(&c);
    let gains =
        Gains::from_loop_polynomial(coefficients, ts).map_err(|gains| Error::GainsRefused {
            argument: speed_argument,
            gains,
        })?;
    let continuous = linalg::monic_from_roots(&poles);
    let mut continuous_gains = [0.0; N];
    for (k, gain) in continuous_gains.iter_mut().enumerate() {
        *gain = continuous[N - 1 - k];
    }
    Ok(Design {
        gains,
        method,
        discretisation: Some(discretisation),
        continuous_poles: poles,
        continuous_gains: Some(continuous_gains),
        kalman: None,
    })
}
