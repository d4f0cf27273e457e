//! The classical 2nd-order ATO (`docs/theory.md §2`): the continuous loop
//! `s^2 + k_a1 s + k_b1` from a tracking error, a bandwidth or the Butterworth setting.

use core::f64::consts::{FRAC_1_SQRT_2, PI};

use angletrack_core::PolePair;

use super::discretisation::discretise;
use super::{Design, DesignMethod, Discretisation};
use crate::error::{Argument, Error, positive};

fn check_damping(damping: f64) -> Result<f64, Error> {
    positive(damping, Argument::Damping)?;
    if damping > 1e3 {
        return Err(Error::OutOfRange {
            argument: Argument::Damping,
            expected: "0 < damping <= 1000",
        });
    }
    Ok(damping)
}

/// The classical 2nd-order ATO designed in the time domain (the paper's rule): the
/// tolerated angle error `max_error_rad` under constant acceleration `acceleration_rad_s2`
/// sets `k_b1 = acceleration / max_error` (the acceleration constant Ka), the damping `m`
/// sets `k_a1 = 2 m sqrt(k_b1)`.
///
/// `m = 1.945` gives 5 % overshoot, `m = sqrt(2)/2` (Butterworth) 20.8 %. The discrete
/// loop's acceleration constant and overshoot differ from the continuous loop's by the
/// discretisation (see the report), more so the fewer samples per loop time constant;
/// [`second_order_from_tracking_error_sampled`](crate::second_order_from_tracking_error_sampled)
/// meets the same specification on the sampled loop.
///
/// ```
/// use angletrack::{Discretisation, second_order_from_tracking_error};
/// // 1 mrad at 1000 rad/s^2, damping 1, 10 kHz:
/// let design =
///     second_order_from_tracking_error(1e-3, 1e3, 1.0, 1e-4, Discretisation::PoleMatching)?;
/// let [k_a1, k_b1] = design.continuous_gains.unwrap();
/// assert!((k_b1 - 1e6).abs() < 1e-6 && (k_a1 - 2e3).abs() < 1e-9);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_from_tracking_error(
    max_error_rad: f64,
    acceleration_rad_s2: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let max_error = positive(max_error_rad, Argument::MaxError)?;
    let acceleration = positive(acceleration_rad_s2, Argument::Acceleration)?;
    let m = check_damping(damping)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let k_b = acceleration / max_error;
    let k_a = 2.0 * m * k_b.sqrt();
    if !(k_a.is_finite() && k_b.is_finite()) {
        return Err(Error::OutOfRange {
            argument: Argument::MaxError,
            expected: "acceleration / max_error finite",
        });
    }
    discretise(
        PolePair::second_order(k_b.sqrt(), m),
        sample_period_s,
        discretisation,
        Argument::MaxError,
        DesignMethod::SecondOrderTrackingError,
    )
}

/// `omega_3dB / omega_n` of the continuous loop `(2 m wn s + wn^2) / (s^2 + 2 m wn s + wn^2)`:
/// `sqrt(1 + 2 m^2 + sqrt((1 + 2 m^2)^2 + 1))`, for a damping `m` in the designs' range
/// `0 < m <= 1000` (refused outside it).
///
/// ```
/// // Damping sqrt(2)/2: the -3 dB bandwidth is 2.06 times the natural frequency.
/// let ratio = angletrack::second_order_bandwidth_ratio(2f64.sqrt() / 2.0)?;
/// assert!((ratio - 2.058).abs() < 1e-3);
/// assert!(angletrack::second_order_bandwidth_ratio(0.0).is_err());
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_bandwidth_ratio(damping: f64) -> Result<f64, Error> {
    Ok(angletrack_core::second_order_bandwidth_ratio(
        check_damping(damping)?,
    ))
}

/// The 2nd-order ATO with a given -3 dB bandwidth of the continuous closed loop
/// `(k_a1 s + k_b1) / (s^2 + k_a1 s + k_b1)` and damping `m`: natural frequency
/// `wn = 2 pi bandwidth / sqrt(1 + 2 m^2 + sqrt((1 + 2 m^2)^2 + 1))`, `k_b1 = wn^2`,
/// `k_a1 = 2 m wn`.
///
/// ```
/// use angletrack::{Discretisation, DesignReport, second_order_from_bandwidth};
/// let design = second_order_from_bandwidth(200.0, 0.8, 1e-5, Discretisation::PoleMatching)?;
/// let report = DesignReport::new(&design, 0.0)?;
/// assert!((report.bandwidth_hz.unwrap() - 200.0).abs() < 1.0);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_from_bandwidth(
    bandwidth_hz: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let bandwidth = positive(bandwidth_hz, Argument::Bandwidth)?;
    let ratio = second_order_bandwidth_ratio(damping)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let wn = 2.0 * PI * bandwidth / ratio;
    discretise(
        PolePair::second_order(wn, damping),
        sample_period_s,
        discretisation,
        Argument::Bandwidth,
        DesignMethod::SecondOrderBandwidth,
    )
}

/// The 2nd-order Butterworth setting with time constant `Tc = 1 / wn`:
/// `k_a1 = sqrt(2) / Tc`, `k_b1 = 1 / Tc^2` (damping `sqrt(2)/2`, 20.8 % overshoot).
///
/// ```
/// use angletrack::{Discretisation, second_order_butterworth};
/// let design = second_order_butterworth(2e-3, 1e-4, Discretisation::PoleMatching)?;
/// let [k_a1, k_b1] = design.continuous_gains.unwrap();
/// assert!((k_a1 - 707.106_781).abs() < 1e-3 && (k_b1 - 2.5e5).abs() < 1e-6);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let tc = positive(time_constant_s, Argument::TimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    discretise(
        PolePair::second_order(1.0 / tc, FRAC_1_SQRT_2),
        sample_period_s,
        discretisation,
        Argument::TimeConstant,
        DesignMethod::SecondOrderButterworth,
    )
}
