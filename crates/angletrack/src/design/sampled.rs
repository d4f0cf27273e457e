//! The 2nd-order ATO designed on the sampled loop itself (`docs/theory.md §2` and `§7`):
//! the specification of the paper's rule (a tolerated error at an acceleration, and the
//! overshoot of the step response) met by the discrete loop the firmware runs, rather than
//! by the continuous loop a discretisation then approximates.

use angletrack_core::Gains;

use super::{Design, DesignMethod, MAX_POLE_TIMES_PERIOD};
use crate::analysis::small_signal_step;
use crate::error::{Argument, Error, positive};
use crate::linalg;

/// The smallest `sqrt(Ka) Ts`: a loop at most 10^4 samples per radian of its natural
/// frequency, whose step response settles within the longest simulation.
const MIN_NATURAL_TIMES_PERIOD: f64 = 1e-4;

/// The search over the damping-like parameter `m` stops beyond this factor from its start
/// (`m = 1`): overshoots need `m` between about 0.01 (95 %) and 100 (0.1 %).
const DAMPING_SEARCH_FACTOR: f64 = 1e3;

/// The 2nd-order ATO whose *sampled* loop has exactly the steady angle error `max_error_rad`
/// under the constant acceleration `acceleration_rad_s2` and exactly the step-response
/// overshoot `overshoot` (a fraction: 0.05 for 5 %).
///
/// The discrete loop's steady error under an acceleration `alpha` is `alpha / Ka` with the
/// discrete acceleration constant `Ka = l2 / ((1 - l1) Ts^2)`, so `l2 = Ka Ts^2 (1 - l1)`
/// with `Ka = acceleration / max_error` leaves one free gain. Written
/// `l1 = 2 m sqrt(Ka) Ts` as in the continuous rule, `m` acts as a damping: the overshoot of
/// the small-signal step response of the discrete loop falls as `m` grows. `m` is bracketed
/// from `m = 1` by doubling or halving, then found by bisection to a relative 1e-12.
///
/// [`second_order_from_tracking_error`](crate::second_order_from_tracking_error) (the
/// paper's rule) meets the same specification on the continuous loop only: its sampled
/// loop has a larger acceleration constant and less overshoot, more so the fewer samples per
/// loop time constant. Each evaluation simulates the discrete step response until it
/// settles: a loop 10^4 times slower than its sample rate takes about a second to design.
///
/// Refused: `overshoot` outside `(0, 1)` or out of reach of the loop
/// ([`Error::NoSolution`]), `sqrt(Ka) Ts` above [`MAX_POLE_TIMES_PERIOD`]
/// ([`Error::TooFastForSampleRate`], naming `max_error_rad`) or below 1e-4 (a loop whose
/// step response would take millions of samples to simulate).
///
/// ```
/// use angletrack::{DesignReport, second_order_from_tracking_error_sampled};
/// // 1 mrad at 1000 rad/s^2 and 10 % overshoot, on the loop sampled at 5 kHz:
/// let design = second_order_from_tracking_error_sampled(1e-3, 1e3, 0.10, 2e-4)?;
/// let report = DesignReport::new(&design, 0.0)?;
/// assert!((1e3 / report.acceleration_constant_per_s2.unwrap() / 1e-3 - 1.0).abs() < 1e-9);
/// assert!((report.linear_step.overshoot - 0.10).abs() < 1e-6);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_from_tracking_error_sampled(
    max_error_rad: f64,
    acceleration_rad_s2: f64,
    overshoot: f64,
    sample_period_s: f64,
) -> Result<Design<2>, Error> {
    let max_error = positive(max_error_rad, Argument::MaxError)?;
    let acceleration = positive(acceleration_rad_s2, Argument::Acceleration)?;
    let target = positive(overshoot, Argument::Overshoot)?;
    if !(target < 1.0) {
        return Err(Error::OutOfRange {
            argument: Argument::Overshoot,
            expected: "0 < overshoot < 1",
        });
    }
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let natural_times_period = (acceleration / max_error).sqrt() * ts;
    if !(natural_times_period <= MAX_POLE_TIMES_PERIOD) {
        return Err(Error::TooFastForSampleRate {
            argument: Argument::MaxError,
            pole_times_period: natural_times_period,
            limit: MAX_POLE_TIMES_PERIOD,
        });
    }
    if !(natural_times_period >= MIN_NATURAL_TIMES_PERIOD) {
        return Err(Error::OutOfRange {
            argument: Argument::MaxError,
            expected: "sqrt(acceleration / max_error) Ts >= 1e-4",
        });
    }
    let w = natural_times_period;
    let gains_at = |m: f64| Gains::new([2.0 * m * w, w * w * (1.0 - 2.0 * m * w)], ts).ok();
    let overshoot_at = |m: f64| Some(small_signal_step(&gains_at(m)?)?.overshoot);
    let (low, high) =
        bracket(overshoot_at, target).ok_or(Error::NoSolution(Argument::Overshoot))?;
    let above = |m: f64| overshoot_at(m).is_some_and(|o| o > target);
    let m = linalg::bisect(above, low, high, 1e-12);
    let gains = gains_at(m).ok_or(Error::NoSolution(Argument::Overshoot))?;
    Ok(Design {
        method: DesignMethod::SecondOrderSampledTrackingError,
        ..Design::from_gains(gains)
    })
}

/// Damping-like parameters `(low, high)` with the overshoot above `target` at `low` and at or
/// below it at `high`, found from `m = 1` by doubling or halving while the overshoot moves
/// toward the target; `None` if it stops doing so (the target is out of the loop's reach)
/// or the loop leaves the stability region first.
fn bracket(overshoot_at: impl Fn(f64) -> Option<f64>, target: f64) -> Option<(f64, f64)> {
    let mut m = 1.0;
    let mut current = overshoot_at(m)?;
    let factor = if current > target { 2.0 } else { 0.5 };
    while m.max(1.0 / m) <= DAMPING_SEARCH_FACTOR {
        let next_m = m * factor;
        let next = overshoot_at(next_m)?;
        if (current > target) != (next > target) {
            return Some(if factor > 1.0 {
                (m, next_m)
            } else {
                (next_m, m)
            });
        }
        // Moving away from the target: beyond the overshoot's extremum.
        if (next - current) * (target - current) <= 0.0 {
            return None;
        }
        m = next_m;
        current = next;
    }
    None
}
