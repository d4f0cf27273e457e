//! Carrying a continuous design to the discrete recursion (`docs/theory.md §7`): the core's
//! [`Gains::from_continuous_poles`] maps the continuous closed-loop poles with the chosen
//! [`Discretisation`] and gives the gains; this adds what a [`Design`] reports (the poles,
//! the continuous gains) and the errors that name the caller's argument.

use angletrack_core::{ConfigError, Discretisation, Gains, Order, PolePair, SupportedOrder};
use nalgebra::Complex;

use super::{Design, DesignMethod};
use crate::error::{Argument, Error, positive};
use crate::linalg;

/// The largest `|s_i| Ts` a continuous design may have: every continuous pole must lie
/// below the sample rate in rad/s (`|s_i| <= 1 / Ts`, i.e. pole frequencies below
/// `fs / (2 pi)`). Beyond it the discrete loop no longer behaves like the continuous design
/// whatever the mapping. The core's limit, in `f64`.
pub const MAX_POLE_TIMES_PERIOD: f64 = angletrack_core::MAX_POLE_TIMES_PERIOD as f64;

/// The continuous closed-loop poles of a design of order `N` (rad/s), as the core takes
/// them: a pair at order 2, a real pole and a pair at order 3.
pub(super) trait ContinuousPoles<const N: usize>: Copy
where
    Order<N>: SupportedOrder,
{
    /// The poles, the real one first at order 3, each pair in increasing `(re, im)`.
    fn poles(self) -> Vec<Complex<f64>>;

    /// The core's gains for the poles mapped by `discretisation`.
    fn gains(self, ts: f64, discretisation: Discretisation) -> Result<Gains<f64, N>, ConfigError>;
}

impl ContinuousPoles<2> for PolePair<f64> {
    fn poles(self) -> Vec<Complex<f64>> {
        self.poles().map(|(re, im)| Complex::new(re, im)).to_vec()
    }

    fn gains(self, ts: f64, discretisation: Discretisation) -> Result<Gains<f64, 2>, ConfigError> {
        Gains::<f64, 2>::from_continuous_poles(self, ts, discretisation)
    }
}

/// The real pole and the pair of a 3rd-order design.
impl ContinuousPoles<3> for (f64, PolePair<f64>) {
    fn poles(self) -> Vec<Complex<f64>> {
        let (real, pair) = self;
        let mut poles = vec![Complex::new(real, 0.0)];
        poles.extend(ContinuousPoles::<2>::poles(pair));
        poles
    }

    fn gains(self, ts: f64, discretisation: Discretisation) -> Result<Gains<f64, 3>, ConfigError> {
        Gains::<f64, 3>::from_continuous_poles(self.0, self.1, ts, discretisation)
    }
}

/// Carries continuous closed-loop poles to discrete gains: the shared last step of every
/// continuous design.
pub(super) fn discretise<const N: usize>(
    continuous: impl ContinuousPoles<N>,
    sample_period_s: f64,
    discretisation: Discretisation,
    speed_argument: Argument,
    method: DesignMethod,
) -> Result<Design<N>, Error>
where
    Order<N>: SupportedOrder,
{
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let poles = continuous.poles();
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
    if discretisation == Discretisation::ForwardEuler {
        // |z| = |1 + s Ts| must stay below 1; the core refuses the gains too, but the
        // limit on |s| Ts is this crate's to report.
        let largest = poles
            .iter()
            .map(|s| {
                let (re, im) = discretisation.map_pole(s.re, s.im, ts);
                Complex::new(1.0 + re, im).norm()
            })
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
    let gains = continuous
        .gains(ts, discretisation)
        .map_err(|gains| Error::GainsRefused {
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
