//! The choice of the observer (`docs/theory.md §16.3`): over the orders and their
//! bandwidths, the design whose predicted RMS angle error (noise through the loop, lag on
//! the capture's motion, the number type's rounding) is least under the constraints.

use core::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_4, TAU};

use super::estimate::{CaptureEstimates, FIRST_PASS_WIDENING, kalman_q};
use super::{DesignCaptureError, linear_loop};
use crate::analysis::{loop_bandwidth_hz, small_signal_step};
use crate::closed_loop_response;
use crate::tracker_file::NumberType;
use crate::{AnyDesign, Discretisation};

/// The observers the choice ranges over.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObserverFamily {
    /// 2nd order, damping `sqrt(2)/2`, by its bandwidth
    /// ([`second_order_from_bandwidth`](crate::second_order_from_bandwidth)).
    SecondOrder,
    /// 3rd order by the paper's pole placement (`K` = 39.04, `psi` = 3 pi / 2) by its
    /// time constant ([`third_order_from_poles`](crate::third_order_from_poles)).
    ThirdOrder,
    /// The steady-state Kalman ATO by its `q` at the estimated `r` ([`kalman`](crate::kalman)).
    Kalman,
}

impl ObserverFamily {
    /// Every family, in the order of the reports.
    pub const ALL: [ObserverFamily; 3] = [Self::SecondOrder, Self::ThirdOrder, Self::Kalman];

    /// The family's name (`second-order`, `third-order`, `kalman`: the CLI's observers).
    pub const fn name(self) -> &'static str {
        match self {
            Self::SecondOrder => "second-order",
            Self::ThirdOrder => "third-order",
            Self::Kalman => "kalman",
        }
    }
}

/// What the chosen design must satisfy besides the least predicted error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignConstraints {
    /// The largest overshoot of the linear step response (fraction); `None`: any.
    pub max_overshoot: Option<f64>,
    /// The smallest -3 dB bandwidth (Hz); `None`: any.
    pub min_bandwidth_hz: Option<f64>,
    /// The largest speed step (rad/s) the loop must acquire: its linear peak error after
    /// the step stays under `pi/4`, where `sin(e) / e` is still 0.9; `None`: no step
    /// beyond the capture's own motion, whose acquisition from rest is inside the predicted
    /// lag already (the observer itself is run on it, `docs/theory.md §16.3`).
    pub speed_step_rad_s: Option<f64>,
    /// The number type the observer runs on: its angle's rounding is one part of the error.
    pub number_type: NumberType,
    /// The bandwidths tried per family (at least 2), spread geometrically over a factor of
    /// [`GRID_SPAN`] either side of the Kalman design of the estimates.
    pub grid_points: usize,
}

impl Default for DesignConstraints {
    /// No constraint, `f32`, 31 bandwidths per family.
    fn default() -> Self {
        Self {
            max_overshoot: None,
            min_bandwidth_hz: None,
            speed_step_rad_s: None,
            number_type: NumberType::F32,
            grid_points: 31,
        }
    }
}

/// The factor either side of the Kalman design's bandwidth over which the grid spreads.
pub const GRID_SPAN: f64 = 30.0;

/// The predicted RMS angle error of a design on the capture's setup, and its parts, each an
/// RMS (rad): `total_rad^2` is the sum of their squares.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedErrorParts {
    /// The sensor noise (white and coloured, quantisation included) through the loop.
    pub noise_rad: f64,
    /// The loop's lag on the capture's motion.
    pub lag_rad: f64,
    /// The number type's rounding of the angle through the loop.
    pub number_type_rad: f64,
    /// The whole.
    pub total_rad: f64,
}

/// One design tried.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureCandidate {
    /// Its family.
    pub family: ObserverFamily,
    /// The design.
    pub design: AnyDesign,
    /// Its -3 dB bandwidth (Hz).
    pub bandwidth_hz: f64,
    /// Its predicted error.
    pub predicted: PredictedErrorParts,
    /// The constraint it breaks, as named in [`DesignConstraints`]; `None`: it meets them.
    pub refused_by: Option<&'static str>,
}

/// The design chosen from a capture, with what it was chosen from.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureDesign {
    /// The estimates from the capture.
    pub estimates: CaptureEstimates,
    /// The constraints.
    pub constraints: DesignConstraints,
    /// The design of least predicted error among those meeting the constraints.
    pub chosen: CaptureCandidate,
    /// The best design of each other family that meets the constraints.
    pub runners_up: Vec<CaptureCandidate>,
    /// Every design tried, family by family, by increasing bandwidth.
    pub candidates: Vec<CaptureCandidate>,
}

/// The variance of the angle's rounding by the number type, `ulp^2 / 12` at `pi` (the
/// wrapped angle's largest): the fixed point's angle has 32 bits per turn.
fn rounding_variance(number_type: NumberType) -> f64 {
    let ulp = match number_type {
        NumberType::F64 => f64::EPSILON * 2.0,
        NumberType::F32 => f64::from(f32::EPSILON) * 2.0,
        NumberType::Fixed => TAU / 2f64.powi(32),
    };
    ulp * ulp / 12.0
}

/// The design of `family` near the -3 dB bandwidth `hz`, at the estimated noise `r`.
fn design_at(family: ObserverFamily, hz: f64, r: f64, ts: f64) -> Option<AnyDesign> {
    let pole = TAU * hz;
    let pm = Discretisation::PoleMatching;
    match family {
        ObserverFamily::SecondOrder => {
            crate::second_order_from_bandwidth(hz, FRAC_1_SQRT_2, ts, pm)
                .ok()
                .map(Into::into)
        }
        ObserverFamily::ThirdOrder => crate::third_order_from_poles(
            crate::paper::POLE_RATIO,
            crate::paper::POLE_FREQUENCY_RATIO / pole,
            crate::paper::POLE_FREQUENCY_RATIO,
            ts,
            pm,
        )
        .ok()
        .map(Into::into),
        ObserverFamily::Kalman => crate::kalman(kalman_q(hz, r, ts), r, ts)
            .ok()
            .map(Into::into),
    }
}

impl CaptureEstimates {
    /// The predicted RMS angle error of the gains `l` on this capture's setup
    /// (`docs/theory.md §16.3`); `None` for an unstable loop.
    pub fn predicted_error(
        &self,
        l: &[f64],
        number_type: NumberType,
    ) -> Option<PredictedErrorParts> {
        let noise = &self.noise;
        let noise_var = linear_loop::noise_variance(
            l,
            noise.white_std.powi(2),
            noise.coloured_std.powi(2),
            noise.coloured_pole,
            0.0,
        )?;
        let rounding_var =
            linear_loop::noise_variance(l, 0.0, 0.0, 0.0, rounding_variance(number_type))?;
        let window = self.window();
        let mut lag_var =
            linear_loop::observer_mean_square_error(l, &self.motion.angle_rad, window);
        if !self.motion.from_reference {
            // The smoothed angle's own noise, tracked alike, is no motion.
            // The smoothed angle's own noise, tracked alike, is no motion.
            // The smoothed angle's own noise, tracked alike, is no motion: its expected
            // share from the noise's spectrum (a realisation of it, such as the radial
            // residual, differs from the angle's own by more than so slow a motion's lag).
            let n = &self.noise;
            let length = ((40.0 / l[0]) as usize).clamp(1000, self.motion.angle_rad.len());
            lag_var -= linear_loop::smoothed_noise_tracking_variance(
                l,
                &self.first_pass_gains,
                n.white_std.powi(2),
                n.coloured_std.powi(2),
                n.coloured_pole,
                length,
            );
        }
        let lag_var = lag_var.max(0.0);
        Some(PredictedErrorParts {
            noise_rad: noise_var.sqrt(),
            lag_rad: lag_var.sqrt(),
            number_type_rad: rounding_var.sqrt(),
            total_rad: (noise_var + lag_var + rounding_var).sqrt(),
        })
    }
}

/// The constraint `candidate` breaks, if any.
fn refusal(
    design: &AnyDesign,
    bandwidth_hz: f64,
    constraints: &DesignConstraints,
) -> Option<&'static str> {
    if let Some(min) = constraints.min_bandwidth_hz
        && bandwidth_hz < min
    {
        return Some("min_bandwidth_hz");
    }
    let ts = design.sample_period();
    if let Some(step) = constraints.speed_step_rad_s {
        let horizon = ((20.0 / (TAU * bandwidth_hz * ts)) as usize).clamp(100, 2_000_000);
        if step * ts * linear_loop::speed_step_peak(&design.gains(), horizon) > FRAC_PI_4 {
            return Some("speed_step_rad_s");
        }
    }
    if let Some(max) = constraints.max_overshoot {
        let overshoot = match design {
            AnyDesign::Second(d) => small_signal_step(&d.gains),
            AnyDesign::Third(d) => small_signal_step(&d.gains),
        }
        .map_or(f64::INFINITY, |s| s.overshoot);
        if overshoot > max {
            return Some("max_overshoot");
        }
    }
    let converts = match (constraints.number_type, design) {
        (NumberType::F32, AnyDesign::Second(d)) => d.to_gains::<f32>().is_ok(),
        (NumberType::F32, AnyDesign::Third(d)) => d.to_gains::<f32>().is_ok(),
        (NumberType::Fixed, AnyDesign::Second(d)) => d.fixed_gains().is_ok(),
        (NumberType::Fixed, AnyDesign::Third(d)) => d.fixed_gains().is_ok(),
        (NumberType::F64, _) => true,
    };
    (!converts).then_some("number_type")
}

fn check_constraints(c: &DesignConstraints) -> Result<(), DesignCaptureError> {
    let bad = |name, expected| Err(DesignCaptureError::Argument { name, expected });
    if let Some(v) = c.max_overshoot
        && !(v >= 0.0 && v.is_finite())
    {
        return bad("max_overshoot", "a fraction of at least 0");
    }
    if let Some(v) = c.min_bandwidth_hz
        && !(v > 0.0 && v.is_finite())
    {
        return bad("min_bandwidth_hz", "a positive number of Hz");
    }
    if let Some(v) = c.speed_step_rad_s
        && !(v > 0.0 && v.is_finite())
    {
        return bad("speed_step_rad_s", "a positive number of rad/s");
    }
    if !(2..=1000).contains(&c.grid_points) {
        return bad("grid_points", "from 2 to 1000");
    }
    Ok(())
}

/// Chooses the observer for the capture of `estimates` (`docs/theory.md §16.3`): over the
/// [`ObserverFamily`]s and [`DesignConstraints::grid_points`] bandwidths each, the design
/// of least predicted RMS angle error among those meeting `constraints`.
///
/// ```
/// use angletrack::design_capture::{CaptureSignals, DesignConstraints, choose_design,
///     estimate_from_capture};
/// let ts = 1e-4;
/// // A shaft at 300 rad/s with a slow speed ripple, 1 % noise on both channels.
/// let angle: Vec<f64> = (0..20_000)
///     .map(|k| { let t = k as f64 * ts; 300.0 * t + 0.2 * (20.0 * t).sin() }).collect();
/// let noise = |k: usize, phase: f64| 0.01 * ((k as f64 * 2.399 + phase).sin() * 1.7);
/// let cos: Vec<f64> = angle.iter().enumerate().map(|(k, a)| a.cos() + noise(k, 0.0)).collect();
/// let sin: Vec<f64> = angle.iter().enumerate().map(|(k, a)| a.sin() + noise(k, 1.0)).collect();
/// let signals = CaptureSignals { cos: &cos, sin: &sin, sample_period_s: ts,
///     reference_angle_rad: Some(&angle), quantisation_step: None };
/// let estimates = estimate_from_capture(&signals)?;
/// let constraints = DesignConstraints { grid_points: 8, ..DesignConstraints::default() };
/// let design = choose_design(estimates, &constraints)?;
/// assert!(design.chosen.predicted.total_rad < 0.01);
/// assert_eq!(design.candidates.len(), 24);
/// # Ok::<(), angletrack::design_capture::DesignCaptureError>(())
/// ```
pub fn choose_design(
    mut estimates: CaptureEstimates,
    constraints: &DesignConstraints,
) -> Result<CaptureDesign, DesignCaptureError> {
    check_constraints(constraints)?;
    let mut candidates = grid(&estimates, constraints);
    // Without a reference the first pass follows the choice: a few times its bandwidth.
    for _ in 0..FIRST_PASS_ROUNDS {
        let (Some(current), Some(chosen)) =
            (estimates.first_pass_bandwidth_hz, best(&candidates, None))
        else {
            break;
        };
        let wanted = FIRST_PASS_WIDENING * chosen.bandwidth_hz;
        if (wanted / current).ln().abs() < FIRST_PASS_SETTLED.ln() {
            break;
        }
        estimates.smooth_with(wanted)?;
        candidates = grid(&estimates, constraints);
    }
    let Some(chosen) = best(&candidates, None) else {
        return Err(DesignCaptureError::NoDesign {
            constraint: candidates
                .last()
                .and_then(|c| c.refused_by)
                .unwrap_or("the grid"),
        });
    };
    let runners_up = ObserverFamily::ALL
        .into_iter()
        .filter(|&f| f != chosen.family)
        .filter_map(|f| best(&candidates, Some(f)))
        .collect();
    Ok(CaptureDesign {
        estimates,
        constraints: *constraints,
        chosen,
        runners_up,
        candidates,
    })
}

/// The most times the first pass is redone after a choice.
const FIRST_PASS_ROUNDS: usize = 3;
/// The first pass is kept when within this factor of the bandwidth the choice asks.
const FIRST_PASS_SETTLED: f64 = 1.5;

/// The candidate of least predicted error meeting the constraints, of `family` if given.
fn best(
    candidates: &[CaptureCandidate],
    family: Option<ObserverFamily>,
) -> Option<CaptureCandidate> {
    candidates
        .iter()
        .filter(|c| c.refused_by.is_none() && family.is_none_or(|f| c.family == f))
        .min_by(|a, b| a.predicted.total_rad.total_cmp(&b.predicted.total_rad))
        .cloned()
}

/// Every family's designs over the grid of bandwidths, predicted and checked.
fn grid(estimates: &CaptureEstimates, constraints: &DesignConstraints) -> Vec<CaptureCandidate> {
    let ts = estimates.sample_period_s;
    let r = estimates.noise.std.value.max(1e-9).powi(2);
    let centre = estimates.centre_bandwidth_hz();
    let highest = 0.2 / ts;
    let low = (centre / GRID_SPAN)
        .max(constraints.min_bandwidth_hz.unwrap_or(0.0))
        .min(highest / 4.0);
    let high = (centre * GRID_SPAN).clamp(4.0 * low, highest);
    let points = constraints.grid_points;
    let mut candidates = Vec::new();
    for family in ObserverFamily::ALL {
        // Each family over the part of the band where it can be designed at this rate.
        let mut top = high;
        while top > low && design_at(family, top, r, ts).is_none() {
            top /= 1.1;
        }
        for i in 0..points {
            let hz = low * (top / low).powf(i as f64 / (points - 1) as f64);
            let Some(design) = design_at(family, hz, r, ts) else {
                continue;
            };
            let gains = design.gains();
            let (Some(bandwidth_hz), Some(predicted)) = (
                bandwidth_near(&design, hz),
                estimates.predicted_error(&gains, constraints.number_type),
            ) else {
                continue;
            };
            let refused_by = refusal(&design, bandwidth_hz, constraints);
            candidates.push(CaptureCandidate {
                family,
                design,
                bandwidth_hz,
                predicted,
                refused_by,
            });
        }
    }
    candidates
}

/// The -3 dB bandwidth (Hz) of `design`, designed near `hz`: bisected between `hz / 16`
/// and `16 hz` (in the logarithm) where the gain brackets `1/sqrt(2)`, else by the
/// report's scan of the whole band.
fn bandwidth_near(design: &AnyDesign, hz: f64) -> Option<f64> {
    let gain = |f: f64| -> f64 {
        let response = match design {
            AnyDesign::Second(d) => closed_loop_response(&d.gains, &[f]),
            AnyDesign::Third(d) => closed_loop_response(&d.gains, &[f]),
        };
        response.map_or(f64::NAN, |h| h[0].norm())
    };
    let nyquist = 0.5 / design.sample_period();
    let (mut low, mut high) = (hz / 16.0, (16.0 * hz).min(nyquist));
    if !(gain(low) > FRAC_1_SQRT_2 && gain(high) < FRAC_1_SQRT_2) {
        return loop_bandwidth_hz(&design.gains(), design.sample_period());
    }
    while high / low > 1.0 + 1e-9 {
        let mid = (low * high).sqrt();
        if gain(mid) > FRAC_1_SQRT_2 {
            low = mid;
        } else {
            high = mid;
        }
    }
    Some((low * high).sqrt())
}
