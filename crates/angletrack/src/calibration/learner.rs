//! [`CaptureCalibrator`]: a calibration learned from a capture read twice, chunk by chunk,
//! in constant memory (the module's documentation says what each pass does).

use std::f64::consts::{FRAC_PI_2, TAU};

use angletrack_core::{
    AngleCorrection, FaultThresholds, Gains, MAX_CORRECTION_ORDER, SensorCalibration,
};
use nalgebra::Complex;

use super::ellipse::EllipseMoments;
use super::harmonic_fit::{FittedHarmonics, HarmonicFit, undo_loop_following};
use super::quality::{CalibrationMethod, OrderQuality, OrderStatus, SPECTRUM_ORDERS};
use super::reference_following::ReferenceFollowing;
use super::tracker::{LoopTracker, Tracker, Unwrap};
use super::{
    CalibrationError, CalibrationOptions, CaptureCalibration, MIN_ERROR_TRANSFER, error_transfer,
};
use crate::{Discretisation, third_order_butterworth};

/// The largest relative spread `(max - min) / |mean|` of the observer's speed over a
/// self-calibration's fit: the loop's transfer, divided out at the mean speed, then stays
/// within a few percent at the learned orders.
const MAX_SPEED_SPREAD: f64 = 0.2;

/// The fewest whole electrical turns the fit uses.
const MIN_FIT_TURNS: f64 = 5.0;

/// The smallest `|E/D|` of the calibration's own loop at order 1.
const OWN_LOOP_TRANSFER: f64 = 0.9;

/// The highest `k omega` (rad per sample) of a measured order: a quarter of the sample rate,
/// four samples per period of the harmonic.
const MAX_ORDER_PHASE_STEP: f64 = FRAC_PI_2;

/// The second pass's state.
struct FitPass {
    sensor: SensorCalibration<f64>,
    method: CalibrationMethod,
    tracker: Option<Box<dyn Tracker>>,
    harmonics: HarmonicFit,
    lowest: usize,
    settle: u64,
    seen: u64,
    reference: Unwrap,
    following: ReferenceFollowing,
    speed: (f64, f64),
    first_position: Option<f64>,
    last_position: f64,
}

/// A calibration learned from a capture in two passes, chunk by chunk (`docs/theory.md
/// §12`): [`add_geometry`](Self::add_geometry) on every chunk (the Lissajous ellipse, the
/// rows and a first measure of the speed), [`start_fit`](Self::start_fit), then
/// [`add_fit`](Self::add_fit) on every chunk again (the angle error against the reference
/// column, or against an observer's angle) and [`finish`](Self::finish). Its memory does
/// not grow with the capture.
///
/// ```
/// use angletrack::{CaptureCalibrator, CalibrationMethod, Gains, Motion, MotionProfile, Scenario, SensorModel};
/// let mut sensor = SensorModel::with_noise(1e-3);
/// sensor.offset_cos = 0.05;
/// sensor.angle_error_harmonics[0] = (1, 4e-3, 0.2);
/// let speed = std::f64::consts::TAU * 200.0;
/// let profile = MotionProfile::new(0.0, speed)
///     .then(Motion::ConstantSpeed { speed_rad_s: speed, duration_s: 0.1 });
/// let capture = Scenario::generate(&profile, &sensor, 5e-5, 1)?;
/// let mut calibrator = CaptureCalibrator::new(5e-5, &Default::default())?;
/// for (c, s) in capture.y_c.chunks(500).zip(capture.y_s.chunks(500)) {
///     calibrator.add_geometry(c, s);
/// }
/// let gains = Gains::<f64, 3>::new([0.12, 0.0069, 0.000_13], 5e-5)?;
/// assert_eq!(calibrator.start_fit(&gains, true)?, CalibrationMethod::Reference);
/// for k in (0..capture.len()).step_by(500) {
///     let end = (k + 500).min(capture.len());
///     calibrator.add_fit(&capture.y_c[k..end], &capture.y_s[k..end], Some(&capture.angle_rad[k..end]));
/// }
/// let learned = calibrator.finish()?;
/// assert!((learned.sensor.offsets().0 - 0.05).abs() < 1e-3);
/// // The order-1 angle error, which no ellipse shows, learned against the reference.
/// assert!((learned.orders[0].amplitude_rad - 4e-3).abs() < 2e-4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct CaptureCalibrator {
    options: CalibrationOptions,
    sample_period_s: f64,
    ellipse: EllipseMoments,
    rows: u64,
    rough_angle: Unwrap,
    fit: Option<FitPass>,
}

impl core::fmt::Debug for CaptureCalibrator {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("CaptureCalibrator")
            .field("options", &self.options)
            .field("rows", &self.rows)
            .field("fitting", &self.fit.is_some())
            .finish()
    }
}

fn refused(option: &'static str, reason: impl Into<String>) -> CalibrationError {
    CalibrationError {
        option,
        reason: reason.into(),
    }
}

impl CaptureCalibrator {
    /// A calibrator for a capture sampled every `sample_period_s`, checking `options`.
    pub fn new(
        sample_period_s: f64,
        options: &CalibrationOptions,
    ) -> Result<Self, CalibrationError> {
        options.check()?;
        if !(sample_period_s > 0.0 && sample_period_s.is_finite()) {
            return Err(refused(
                "sample_period_s",
                "must be a positive number of seconds",
            ));
        }
        Ok(Self {
            options: *options,
            sample_period_s,
            ellipse: EllipseMoments::new(),
            rows: 0,
            rough_angle: Unwrap::default(),
            fit: None,
        })
    }

    /// The first pass: a chunk of raw samples.
    pub fn add_geometry(&mut self, y_c: &[f64], y_s: &[f64]) {
        self.ellipse.add(y_c, y_s);
        let Some((c0, s0)) = self.ellipse.rough_centre() else {
            return;
        };
        for (&c, &s) in y_c.iter().zip(y_s) {
            self.rows += 1;
            if c.is_finite() && s.is_finite() {
                self.rough_angle.add((s - s0).atan2(c - c0));
            }
        }
    }

    /// The sensor calibration of the Lissajous ellipse of the first pass.
    pub fn sensor_calibration(&self) -> Result<SensorCalibration<f64>, CalibrationError> {
        self.ellipse.fit().ok_or_else(|| {
            refused(
                "capture",
                "its samples fit no ellipse (fewer than a turn, a standstill, a dead or \
                 shorted channel, or a quadrature beyond 45 degrees)",
            )
        })
    }

    /// The mean electrical speed of the first pass (rad per sample).
    fn rough_speed(&self) -> f64 {
        self.rough_angle.position / (self.rows.max(2) - 1) as f64
    }

    /// Ends the first pass and starts the second: against the reference when the capture
    /// has one (`has_reference`) and `self_calibration` is not set, else self-calibration
    /// with the calibration's own loop (`own_loop`) or with `gains`. Returns the method.
    pub fn start_fit<const N: usize>(
        &mut self,
        gains: &Gains<f64, N>,
        has_reference: bool,
    ) -> Result<CalibrationMethod, CalibrationError> {
        let sensor = self.sensor_calibration()?;
        let omega = self.rough_speed();
        let turns = self.rough_angle.position.abs() / TAU;
        if !(turns >= MIN_FIT_TURNS) {
            return Err(refused(
                "capture",
                format!(
                    "it holds {turns:.3} electrical turns; a calibration needs at least \
                     {MIN_FIT_TURNS} (a longer capture, or a faster one)"
                ),
            ));
        }
        let method = if has_reference && !self.options.self_calibration {
            CalibrationMethod::Reference
        } else if self.options.own_loop {
            CalibrationMethod::OwnLoop
        } else {
            CalibrationMethod::Gains
        };
        let amplitude = sensor.amplitudes().0;
        let thresholds = FaultThresholds::for_amplitude(amplitude);
        let tracker: Option<Box<dyn Tracker>> = match method {
            CalibrationMethod::Reference | CalibrationMethod::Unknown => None,
            CalibrationMethod::OwnLoop => Some(self.own_loop(sensor, omega, thresholds)?),
            CalibrationMethod::Gains => {
                let gains = gains
                    .with_fault_thresholds(thresholds)
                    .map_err(|e| refused("gains", e.to_string()))?;
                if (gains.sample_period() / self.sample_period_s - 1.0).abs() > 1e-9 {
                    return Err(refused("gains", "their sample period is not the capture's"));
                }
                Some(LoopTracker::new(
                    sensor,
                    gains,
                    omega / self.sample_period_s,
                ))
            }
        };
        let lowest = self.lowest_order(method, tracker.as_deref(), omega)?;
        let resolved = (1..=SPECTRUM_ORDERS)
            .take_while(|&k| k as f64 * omega.abs() <= MAX_ORDER_PHASE_STEP)
            .last()
            .unwrap_or(0);
        let settle = match method {
            CalibrationMethod::Reference => 0,
            _ => (self.options.settle_fraction * self.rows as f64) as u64,
        };
        self.fit = Some(FitPass {
            sensor,
            method,
            tracker,
            harmonics: HarmonicFit::new(resolved),
            lowest,
            settle,
            seen: 0,
            reference: Unwrap::default(),
            following: ReferenceFollowing::default(),
            speed: (f64::INFINITY, f64::NEG_INFINITY),
            first_position: None,
            last_position: 0.0,
        });
        Ok(method)
    }

    /// The calibration's own loop: a 3rd-order Butterworth loop slow enough that its
    /// `E/D` at the capture's speed is at least [`OWN_LOOP_TRANSFER`], started at that
    /// speed.
    fn own_loop(
        &self,
        sensor: SensorCalibration<f64>,
        omega: f64,
        thresholds: FaultThresholds<f64>,
    ) -> Result<Box<dyn Tracker>, CalibrationError> {
        let ts = self.sample_period_s;
        let mut time_constant_s = 2.0 * ts / omega.abs();
        for _ in 0..40 {
            let design = third_order_butterworth(time_constant_s, ts, Discretisation::PoleMatching)
                .map_err(|e| {
                    refused(
                        "capture",
                        format!("no loop of its own fits its speed ({e})"),
                    )
                })?;
            if error_transfer(&design.gains, omega.abs()).norm() >= OWN_LOOP_TRANSFER {
                let gains = design
                    .gains
                    .with_fault_thresholds(thresholds)
                    .map_err(|e| refused("capture", e.to_string()))?;
                return Ok(LoopTracker::new(sensor, gains, omega / ts));
            }
            time_constant_s *= 1.5;
        }
        Err(refused("capture", "no loop of its own fits its speed"))
    }

    /// The lowest order learned: the one asked for, refused when the loop follows it; else
    /// 1 against a reference, and in self-calibration 3 (orders 1 and 2 are the ellipse's)
    /// or the lowest above the loop's bandwidth.
    fn lowest_order(
        &self,
        method: CalibrationMethod,
        tracker: Option<&dyn Tracker>,
        omega: f64,
    ) -> Result<usize, CalibrationError> {
        let learnable = |k: usize| {
            tracker.is_none_or(|t| t.transfer(k as f64 * omega.abs()).norm() >= MIN_ERROR_TRANSFER)
        };
        let highest = self.options.highest_order;
        match self.options.lowest_order {
            Some(k) if !learnable(k) => {
                let lowest = (k..=highest).find(|&k| learnable(k));
                Err(refused(
                    "lowest_order",
                    format!(
                        "order {k} lies within the loop's bandwidth at the capture's speed \
                         ({:.1} rad/s): the loop follows it and the angle error does not show it; {}",
                        omega / self.sample_period_s,
                        match lowest {
                            Some(m) => format!("the lowest learnable order is {m}, or calibrate with the calibration's own loop"),
                            None => "no order up to highest_order is learnable: calibrate with the calibration's own loop".into(),
                        }
                    ),
                ))
            }
            Some(k) => Ok(k),
            None => {
                let default = if method == CalibrationMethod::Reference {
                    1
                } else {
                    3
                };
                Ok((default..=highest)
                    .find(|&k| learnable(k))
                    .unwrap_or(highest + 1))
            }
        }
    }

    /// The second pass: a chunk of raw samples and, for a calibration against the
    /// reference, the reference angle (rad, electrical) of each. Ignored before
    /// [`start_fit`](Self::start_fit).
    pub fn add_fit(&mut self, y_c: &[f64], y_s: &[f64], reference: Option<&[f64]>) {
        let Some(fit) = self.fit.as_mut() else {
            return;
        };
        for (i, (&raw_c, &raw_s)) in y_c.iter().zip(y_s).enumerate() {
            fit.seen += 1;
            let observed = match fit.tracker.as_mut() {
                Some(tracker) => tracker.step(raw_c, raw_s),
                None => reference
                    .and_then(|r| r.get(i))
                    .filter(|r| r.is_finite())
                    .map(|&r| (r, fit.reference.add(r), f64::NAN)),
            };
            let Some((angle, position, speed)) = observed else {
                continue;
            };
            if fit.seen <= fit.settle || !(raw_c.is_finite() && raw_s.is_finite()) {
                continue;
            }
            let (c, s) = fit.sensor.correct(raw_c, raw_s);
            if fit.tracker.is_none() {
                fit.following.add(s.atan2(c), position);
            }
            let error = s.atan2(c) - angle;
            let error = error - TAU * (error / TAU).round();
            fit.harmonics.add(angle, position, error);
            fit.first_position.get_or_insert(position);
            fit.last_position = position;
            if speed.is_finite() {
                fit.speed = (fit.speed.0.min(speed), fit.speed.1.max(speed));
            }
        }
    }

    /// The calibration learned (see [`CalibrationOptions`] for which orders are learned).
    pub fn finish(self) -> Result<CaptureCalibration, CalibrationError> {
        let omega = self.rough_speed();
        let Some(fit) = self.fit else {
            return Err(refused("capture", "finish before start_fit"));
        };
        let travelled = (fit.last_position - fit.first_position.unwrap_or(0.0)).abs() / TAU;
        if !(travelled >= MIN_FIT_TURNS) {
            return Err(refused(
                "settle_fraction",
                format!(
                    "the fit covers {travelled:.3} electrical turns after the settling (at least \
                     {MIN_FIT_TURNS} needed): a longer capture, or a smaller settle_fraction"
                ),
            ));
        }
        fit.following.check()?;
        let (low, high) = fit.speed;
        if fit.tracker.is_some() && !(high - low <= MAX_SPEED_SPREAD * omega.abs()) {
            return Err(refused(
                "capture",
                "its speed is not steady enough for a self-calibration (the observer's speed \
                 varies by more than 20 % of its mean): a capture at a steadier speed, or one \
                 with a reference column",
            ));
        }
        let fitted = fit.harmonics.finish().ok_or_else(|| {
            refused(
                "capture",
                "its angle error determines no harmonic (too few samples tracked)",
            )
        })?;
        let (orders, kept, correction) = learned_orders(&self.options, &fit, &fitted, omega)?;
        Ok(CaptureCalibration {
            sensor: fit.sensor,
            correction,
            speed_rad_s: omega / self.sample_period_s,
            turns: travelled.floor(),
            error_rms_rad: fitted.error_rms,
            residual_rms_rad: fitted.residual_rms(&kept),
            method: fit.method,
            orders,
        })
    }
}

/// Each order's quality, which orders are kept, and the correction of those learned.
type LearnedOrders = (
    [OrderQuality; SPECTRUM_ORDERS],
    [bool; SPECTRUM_ORDERS],
    AngleCorrection<f64>,
);

/// The orders of `fitted` (see [`LearnedOrders`]).
fn learned_orders(
    options: &CalibrationOptions,
    fit: &FitPass,
    fitted: &FittedHarmonics,
    omega: f64,
) -> Result<LearnedOrders, CalibrationError> {
    let mut orders = [OrderQuality::UNKNOWN; SPECTRUM_ORDERS];
    let mut kept = [false; SPECTRUM_ORDERS];
    let (mut a, mut b) = ([0.0; MAX_CORRECTION_ORDER], [0.0; MAX_CORRECTION_ORDER]);
    let transfer: [Complex<f64>; SPECTRUM_ORDERS] = core::array::from_fn(|i| {
        fit.tracker.as_ref().map_or(Complex::new(1.0, 0.0), |t| {
            t.transfer((i + 1) as f64 * omega.abs())
        })
    });
    let coefficients = if fit.tracker.is_some() {
        undo_loop_following(&fitted.coefficients, &transfer)
    } else {
        fitted.coefficients
    };
    for (i, quality) in orders.iter_mut().enumerate() {
        let k = i + 1;
        let mut coefficient = coefficients[i];
        let mut uncertainty = fitted.uncertainty[i];
        match &fit.tracker {
            // The reference's zero is the mean error away from the sensor's: the
            // coefficients are those of the sensor's angle (`docs/theory.md §12`).
            None => coefficient *= Complex::from_polar(1.0, -(k as f64) * fitted.mean),
            Some(tracker) => {
                let transfer = tracker.transfer(k as f64 * omega.abs());
                coefficient /= transfer;
                uncertainty /= transfer.norm();
            }
        }
        let amplitude = coefficient.norm();
        let learnable = fit
            .tracker
            .as_ref()
            .is_none_or(|t| t.transfer(k as f64 * omega.abs()).norm() >= MIN_ERROR_TRANSFER);
        let status = if uncertainty.is_nan() {
            OrderStatus::Unresolved
        } else if k < fit.lowest || k > options.highest_order {
            if learnable {
                OrderStatus::NotRequested
            } else {
                OrderStatus::WithinLoopBandwidth
            }
        } else if !learnable {
            OrderStatus::WithinLoopBandwidth
        } else if amplitude < options.min_significance * uncertainty {
            OrderStatus::NotSignificant
        } else {
            OrderStatus::Learned
        };
        if status == OrderStatus::Learned {
            kept[i] = true;
            a[i] = coefficient.re;
            b[i] = -coefficient.im;
        }
        *quality = OrderQuality {
            amplitude_rad: if uncertainty.is_nan() {
                f64::NAN
            } else {
                amplitude
            },
            uncertainty_rad: uncertainty,
            status,
        };
    }
    let correction = AngleCorrection::new(a, b).map_err(|e| {
        refused(
            "capture",
            format!("its angle error is beyond what a correction holds ({e})"),
        )
    })?;
    Ok((orders, kept, correction))
}
