//! Learning a sensor's calibration from a capture, in constant memory
//! ([`CaptureCalibrator`], `docs/theory.md §12`): its offsets, imbalance and quadrature
//! from the Lissajous ellipse of the signals (a least-squares fit, which no speed or speed
//! ripple changes), then its angle-dependent error (the Fourier coefficients of an
//! [`AngleCorrection`]) against the capture's reference column when it has one, else
//! against an observer's angle (self-calibration), with each coefficient's uncertainty.
//!
//! Without a reference, an angle-synchronous speed ripple and a sensor's angle error cannot
//! be told apart: both are harmonics of the angle in `atan2(s, c) - theta_hat`. The
//! self-calibration therefore learns orders 1 and 2 from the ellipse only (unless
//! `lowest_order` asks for them), and a calibration against a reference learns every order.
//!
//! In a self-calibration, the angle error `e = atan2(s, c) - theta_hat` of the calibrated
//! samples `(c, s)` against the observer's angle `theta_hat` holds the sensor's error
//! `d(theta)` as the loop leaves it: the loop follows what lies within its bandwidth and
//! lets the rest through. At a steady electrical speed `omega` (rad per sample) the
//! harmonic `k` of `d` reaches `e` multiplied by the loop's error transfer at `k omega`,
//!
//! ```text
//! E(z) / D(z) = (1 - l1) / (1 + G(z)),   G(z) = e1^T (z I - A)^-1 A L
//! ```
//!
//! (`docs/theory.md §5`: the estimate is `p + l1 eps`, the next prediction `A (x_p + L eps)`),
//! which the fit divides out. An order where the loop passes less than half
//! ([`MIN_ERROR_TRANSFER`]) is not learned; the calibration's own loop (the default) is
//! designed from the capture's speed so that every order passes.

use angletrack_core::{AngleCorrection, Gains, MAX_CORRECTION_ORDER, SensorCalibration};
use nalgebra::Complex;

mod ellipse;
pub(crate) mod file;
mod harmonic_fit;
mod learner;
mod online;
mod quality;
mod reference_following;
mod tracker;

pub use file::{
    ANGLE_CALIBRATION_FORMAT, CALIBRATION_FILE_VERSION, CalibrationFile, SENSOR_CALIBRATION_FORMAT,
    SensorCalibrationRecord,
};
pub use learner::CaptureCalibrator;
pub use online::{
    CalibrationChoiceError, OnlineCalibrationChoice, converted_calibration, mode_name, status_name,
};
pub use quality::{CalibrationMethod, OrderQuality, OrderStatus, SPECTRUM_ORDERS, order_warnings};

/// The smallest `|E/D|` of the loop at a learned harmonic in a self-calibration (see the
/// module's documentation): the learned coefficients are divided by it, so their noise
/// grows by at most 2.
pub const MIN_ERROR_TRANSFER: f64 = 0.5;

/// Why a calibration could not be learned: the option (as the Rust and Python APIs spell
/// it: `lowest_order`, `settle_fraction`, `capture`, ...) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CalibrationError {
    /// The option or input at fault.
    pub option: &'static str,
    /// What is wrong, and the remedy.
    pub reason: String,
}

impl core::fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}: {}", self.option, self.reason)
    }
}

impl std::error::Error for CalibrationError {}

/// How the calibration is learned ([`CaptureCalibrator`], [`learn_angle_correction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationOptions {
    /// The lowest harmonic order learned; `None` chooses it: 1 against a reference, 3 in a
    /// self-calibration (orders 1 and 2 are the ellipse's), raised to the lowest order
    /// above the gains' bandwidth with `own_loop` off. An order given that the loop
    /// follows is refused.
    pub lowest_order: Option<usize>,
    /// The highest harmonic order learned (at most [`MAX_CORRECTION_ORDER`]).
    pub highest_order: usize,
    /// The fraction of the capture, from its start, left out of a self-calibration's fit
    /// while the loop settles (a calibration against a reference uses every sample).
    pub settle_fraction: f64,
    /// Self-calibration even when the capture has a reference column.
    pub self_calibration: bool,
    /// Self-calibration with the calibration's own loop, designed from the capture's speed
    /// (the default), rather than with the gains.
    pub own_loop: bool,
    /// An order is learned only when its amplitude is at least this many times its
    /// uncertainty (3: noise passes with a probability of 1 %); 0 learns every order asked
    /// for, with a warning for those below their uncertainty.
    pub min_significance: f64,
}

impl Default for CalibrationOptions {
    /// Orders chosen up to 8, a fifth of the capture to settle, the reference when there is
    /// one, the calibration's own loop, 3 uncertainties to be learned.
    fn default() -> Self {
        Self {
            lowest_order: None,
            highest_order: MAX_CORRECTION_ORDER,
            settle_fraction: 0.2,
            self_calibration: false,
            own_loop: true,
            min_significance: 3.0,
        }
    }
}

impl CalibrationOptions {
    /// Refuses orders outside `1..=8`, a `settle_fraction` outside `[0, 1)` and a negative
    /// `min_significance`.
    pub fn check(&self) -> Result<(), CalibrationError> {
        let highest = self.highest_order;
        if !(1..=MAX_CORRECTION_ORDER).contains(&highest) {
            return Err(CalibrationError {
                option: "highest_order",
                reason: format!("must be in 1..=8, got {highest}"),
            });
        }
        if let Some(lowest) = self.lowest_order
            && !(1..=highest).contains(&lowest)
        {
            return Err(CalibrationError {
                option: "lowest_order",
                reason: format!("must be in 1..=highest_order ({highest}), got {lowest}"),
            });
        }
        if !(0.0..1.0).contains(&self.settle_fraction) {
            return Err(CalibrationError {
                option: "settle_fraction",
                reason: format!("must be in [0, 1), got {}", self.settle_fraction),
            });
        }
        if !(self.min_significance >= 0.0 && self.min_significance.is_finite()) {
            return Err(CalibrationError {
                option: "min_significance",
                reason: format!(
                    "must be a finite number >= 0, got {}",
                    self.min_significance
                ),
            });
        }
        Ok(())
    }
}

/// What a [`CaptureCalibrator`] learned from a capture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureCalibration {
    /// The offsets, imbalance and quadrature (input units, rad).
    pub sensor: SensorCalibration<f64>,
    /// The angle-dependent error `d(theta)` (rad), the learned orders only.
    pub correction: AngleCorrection<f64>,
    /// The mean electrical speed of the capture (rad/s).
    pub speed_rad_s: f64,
    /// The whole electrical turns the fit used.
    pub turns: f64,
    /// The RMS (rad) of the angle error over the fit, its mean removed, before the
    /// correction.
    pub error_rms_rad: f64,
    /// The RMS (rad) of what the learned harmonics leave of it (noise, orders not learned).
    pub residual_rms_rad: f64,
    /// How the angle error was measured.
    pub method: CalibrationMethod,
    /// Orders 1 to [`SPECTRUM_ORDERS`] of the angle error (index `k - 1`): amplitude,
    /// uncertainty and whether learned; those not learned are the residual's spectrum.
    pub orders: [OrderQuality; SPECTRUM_ORDERS],
}

impl CaptureCalibration {
    /// One line per learned order below its own uncertainty ([`order_warnings`]).
    pub fn warnings(&self) -> Vec<String> {
        order_warnings(&self.orders)
    }
}

/// The loop's transfer `E/D` from the sensor's angle error to the error of the estimate
/// against the measured angle, at `omega` rad per sample (see the module's documentation).
// Index loops: the triangular matrices' rows and columns read best by index.
#[allow(clippy::needless_range_loop)]
pub fn error_transfer<const N: usize>(gains: &Gains<f64, N>, omega: f64) -> Complex<f64> {
    let l = gains.gains();
    let z = Complex::from_polar(1.0, omega);
    // A L for A = the Taylor matrix (rows 1, 1, 1/2 / 0, 1, 1 / 0, 0, 1).
    let mut al = [0.0; 3];
    for i in 0..N {
        let mut factorial = 1.0;
        for j in i..N {
            al[i] += l[j] / factorial;
            factorial *= (j - i + 1) as f64;
        }
    }
    // Back substitution of (z I - A) v = A L (A upper triangular, ones on its diagonal).
    let mut v = [Complex::new(0.0, 0.0); 3];
    for i in (0..N).rev() {
        let mut rhs = Complex::new(al[i], 0.0);
        let mut factorial = 1.0;
        for j in i + 1..N {
            factorial *= (j - i) as f64;
            rhs += v[j] / factorial;
        }
        v[i] = rhs / (z - 1.0);
    }
    (1.0 - l[0]) / (1.0 + v[0])
}

/// Learns a sensor's calibration from a capture `(y_c, y_s)` held in memory, with its
/// `reference` angle (rad, electrical) if it has one: a [`CaptureCalibrator`] run over it
/// (see there and [`CalibrationOptions`]); `gains` run the self-calibration when
/// `options.own_loop` is off.
///
/// ```
/// use angletrack::{CalibrationMethod, Gains, Motion, MotionProfile, Scenario, SensorModel, learn_angle_correction};
/// let gains = Gains::<f64, 3>::new([0.12, 0.0069, 0.000_13], 5e-5)?;
/// let mut sensor = SensorModel::with_noise(1e-3);
/// sensor.offset_cos = 0.05;
/// sensor.angle_error_harmonics[0] = (3, 5e-3, 0.3);
/// let speed = 2.0 * std::f64::consts::PI * 200.0;
/// let profile = MotionProfile::new(0.0, speed)
///     .then(Motion::ConstantSpeed { speed_rad_s: speed, duration_s: 0.25 });
/// let capture = Scenario::generate(&profile, &sensor, 5e-5, 1)?;
/// let learned = learn_angle_correction(&gains, &capture.y_c, &capture.y_s, None, &Default::default())?;
/// assert_eq!(learned.method, CalibrationMethod::OwnLoop);
/// assert!((learned.sensor.offsets().0 - 0.05).abs() < 1e-3);
/// let (a, b) = learned.correction.coefficients();
/// // 5e-3 sin(3 theta + 0.3) = 5e-3 sin(0.3) cos(3 theta) + 5e-3 cos(0.3) sin(3 theta)
/// assert!((a[2] - 5e-3 * 0.3f64.sin()).abs() < 3e-4 && (b[2] - 5e-3 * 0.3f64.cos()).abs() < 3e-4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn learn_angle_correction<const N: usize>(
    gains: &Gains<f64, N>,
    y_c: &[f64],
    y_s: &[f64],
    reference: Option<&[f64]>,
    options: &CalibrationOptions,
) -> Result<CaptureCalibration, CalibrationError> {
    if y_c.len() != y_s.len() || reference.is_some_and(|r| r.len() != y_c.len()) {
        return Err(CalibrationError {
            option: "y_c",
            reason: "y_c, y_s (and reference) must have the same length".into(),
        });
    }
    const CHUNK: usize = 1 << 16;
    let mut calibrator = CaptureCalibrator::new(gains.sample_period(), options)?;
    for (c, s) in y_c.chunks(CHUNK).zip(y_s.chunks(CHUNK)) {
        calibrator.add_geometry(c, s);
    }
    calibrator.start_fit(gains, reference.is_some())?;
    for start in (0..y_c.len()).step_by(CHUNK) {
        let end = (start + CHUNK).min(y_c.len());
        calibrator.add_fit(
            &y_c[start..end],
            &y_s[start..end],
            reference.map(|r| &r[start..end]),
        );
    }
    calibrator.finish()
}

#[cfg(test)]
mod tests;
