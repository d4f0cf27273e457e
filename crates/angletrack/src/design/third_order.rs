//! The 3rd-order ATO by pole placement (`docs/theory.md §3`): a real pole at `-K/T` and a
//! complex pair at `(-1 +- j psi)/T`, from `(K, T, psi)`, from a target overshoot and
//! settling time, or the Butterworth setting.

use angletrack_core::PolePair;

use super::discretisation::{ContinuousPoles, discretise};
use super::{Design, DesignMethod, Discretisation};
use crate::analysis::{continuous_step, continuous_step_within};
use crate::error::{Argument, Error, positive};
use crate::linalg;

/// The continuous poles `-K/T` and `(-1 +- j psi)/T` of the 3rd-order pole placement.
fn third_order_poles(k: f64, t: f64, psi: f64) -> (f64, PolePair<f64>) {
    (
        -k / t,
        PolePair::Complex {
            re: -1.0 / t,
            im: psi / t,
        },
    )
}

fn check_pole_family(k: f64, psi: f64) -> Result<(), Error> {
    positive(k, Argument::PoleRatio)?;
    positive(psi, Argument::PoleFrequencyRatio)?;
    if k > 1e6 {
        return Err(Error::OutOfRange {
            argument: Argument::PoleRatio,
            expected: "0 < K <= 1e6",
        });
    }
    if psi > 1e3 {
        return Err(Error::OutOfRange {
            argument: Argument::PoleFrequencyRatio,
            expected: "0 < psi <= 1000",
        });
    }
    Ok(())
}

/// The 3rd-order ATO by pole placement (the paper's rule): a real pole at `-K/T` and a
/// complex pair at `(-1 +- j psi)/T` (rad/s), i.e.
/// `k_a2 = (K + 2)/T`, `k_b2 = (psi^2 + 2K + 1)/T^2`, `k_c2 = K (psi^2 + 1)/T^3`.
///
/// `K = 39.04`, `psi = 3 pi / 2` gives 10 % overshoot.
///
/// ```
/// use angletrack::{Discretisation, third_order_from_poles};
/// use std::f64::consts::PI;
/// let design = third_order_from_poles(39.04, 0.01, 1.5 * PI, 1e-5, Discretisation::PoleMatching)?;
/// let [k_a2, k_b2, k_c2] = design.continuous_gains.unwrap();
/// let psi2 = (1.5 * PI).powi(2);
/// assert!((k_a2 - 41.04 / 0.01).abs() < 1e-9);
/// assert!((k_b2 - (psi2 + 79.08) / 1e-4).abs() < 1e-6);
/// assert!((k_c2 / (39.04 * (psi2 + 1.0) / 1e-6) - 1.0).abs() < 1e-12);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_from_poles(
    pole_ratio: f64,
    pole_time_constant_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    check_pole_family(pole_ratio, pole_frequency_ratio)?;
    let t = positive(pole_time_constant_s, Argument::PoleTimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    discretise(
        third_order_poles(pole_ratio, t, pole_frequency_ratio),
        sample_period_s,
        discretisation,
        Argument::PoleTimeConstant,
        DesignMethod::ThirdOrderPolePlacement,
    )
}

/// The 3rd-order Butterworth setting with time constant `Tc`:
/// `k_a2 = 2/Tc`, `k_b2 = 2/Tc^2`, `k_c2 = 1/Tc^3` (poles `-1/Tc` and
/// `(-1 +- j sqrt(3)) / (2 Tc)`; 30.9 % overshoot).
///
/// ```
/// use angletrack::{Discretisation, third_order_butterworth};
/// let design = third_order_butterworth(1e-3, 1e-5, Discretisation::Tustin)?;
/// let [k_a2, k_b2, k_c2] = design.continuous_gains.unwrap();
/// assert!((k_a2 - 2e3).abs() < 1e-9 && (k_b2 - 2e6).abs() < 1e-6 && (k_c2 - 1e9).abs() < 1e-3);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    let tc = positive(time_constant_s, Argument::TimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let half = 0.5 / tc;
    let poles = (
        -1.0 / tc,
        PolePair::Complex {
            re: -half,
            im: 3.0_f64.sqrt() * half,
        },
    );
    discretise(
        poles,
        sample_period_s,
        discretisation,
        Argument::TimeConstant,
        DesignMethod::ThirdOrderButterworth,
    )
}

/// The smallest and largest `K` searched by [`third_order_from_overshoot`].
const POLE_RATIO_SEARCH: (f64, f64) = (0.05, 1e4);

/// The most samples of a step response while [`third_order_from_overshoot`] tabulates the
/// overshoot over `K` to find its bracket: at large `K` the real pole is fast and the grid
/// that resolves it holds a million samples; the bracket needs the slow pair's peak only.
const BRACKET_STEP_SAMPLES: usize = 5_000;

/// The 3rd-order ATO from a target overshoot of the (linear, continuous) step response and
/// a target 2 % settling time, within the pole family `-K/T`, `(-1 +- j psi)/T` with `psi`
/// fixed (the paper uses `psi = 3 pi / 2`).
///
/// The overshoot depends on `K` and `psi` only (`T` scales time). The search: the overshoot
/// of the continuous step response (computed exactly by the matrix exponential) is
/// tabulated over `K` on a logarithmic grid from 0.05 to 10^4 (each response on at most 5,000
/// samples: the bracket needs the slow pair's peak only); the first bracket in which it
/// crosses the target (from above: small `K` gives large overshoot) is refined by bisection
/// to a relative 1e-10. Then `T` is the target settling time divided by the settling time
/// of the loop with `T = 1`. [`Error::NoSolution`] names the overshoot if no `K` in the range
/// gives it.
///
/// ```
/// use angletrack::{Discretisation, third_order_from_overshoot};
/// use std::f64::consts::PI;
/// // The paper's 10 % with psi = 3 pi / 2 gives K = 39.04.
/// let design = third_order_from_overshoot(0.10, 0.05, 1.5 * PI, 1e-5, Discretisation::PoleMatching)?;
/// let k_over_t = -design.continuous_poles.iter().map(|p| p.re).fold(0.0, f64::min);
/// let one_over_t = -design.continuous_poles.iter().map(|p| p.re).fold(f64::MIN, f64::max);
/// assert!((k_over_t / one_over_t - 39.04).abs() < 0.05);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_from_overshoot(
    overshoot: f64,
    settling_time_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    let target = positive(overshoot, Argument::Overshoot)?;
    let settling = positive(settling_time_s, Argument::SettlingTime)?;
    check_pole_family(1.0, pole_frequency_ratio)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let psi = pole_frequency_ratio;
    let loop_of = |k: f64| linalg::monic_from_roots(&third_order_poles(k, 1.0, psi).poles());
    let bracket_overshoot =
        |k: f64| continuous_step_within(&loop_of(k), BRACKET_STEP_SAMPLES).overshoot;
    let overshoot_at = |k: f64| continuous_step(&loop_of(k)).overshoot;
    let (lo, hi) = POLE_RATIO_SEARCH;
    let steps = 60;
    let ratio = (hi / lo).powf(1.0 / steps as f64);
    let mut bracket = None;
    let mut k_prev = lo;
    let mut o_prev = bracket_overshoot(lo);
    for i in 1..=steps {
        let k = lo * ratio.powi(i);
        let o = bracket_overshoot(k);
        if (o_prev - target) * (o - target) <= 0.0 {
            bracket = Some((k_prev, k, o_prev > target));
            break;
        }
        k_prev = k;
        o_prev = o;
    }
    let (a, b, decreasing) = bracket.ok_or(Error::NoSolution(Argument::Overshoot))?;
    let k = linalg::bisect(|k| (overshoot_at(k) > target) == decreasing, a, b, 1e-10);
    let unit = continuous_step(&linalg::monic_from_roots(
        &third_order_poles(k, 1.0, psi).poles(),
    ));
    let t = settling / unit.settling_time_s;
    if !t.is_finite() || t <= 0.0 {
        return Err(Error::NoSolution(Argument::SettlingTime));
    }
    discretise(
        third_order_poles(k, t, psi),
        sample_period_s,
        discretisation,
        Argument::SettlingTime,
        DesignMethod::ThirdOrderOvershoot,
    )
}
