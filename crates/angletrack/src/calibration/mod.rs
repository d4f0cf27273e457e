//! Learning a sensor's calibration from a capture: its offsets, imbalance and quadrature
//! (the core's online [`Calibrator`], run to convergence) and its angle-dependent error
//! (the Fourier coefficients of an [`AngleCorrection`]), with the observer's own angle as
//! the reference (`docs/theory.md §12`).
//!
//! The angle error `e = atan2(s, c) - theta_hat` of the calibrated samples `(c, s)` against
//! the observer's angle `theta_hat` holds the sensor's error `d(theta)` as the loop leaves
//! it: the loop follows what lies within its bandwidth and lets the rest through. At a
//! steady electrical speed `omega` (rad per sample) the harmonic `k` of `d` reaches `e`
//! multiplied by the loop's error transfer at `k omega`,
//!
//! ```text
//! E(z) / D(z) = (1 - l1) / (1 + G(z)),   G(z) = e1^T (z I - A)^-1 A L
//! ```
//!
//! (`docs/theory.md §5`: the estimate is `p + l1 eps`, the next prediction `A (x_p + L eps)`),
//! which the fit divides out. This needs the harmonic well above the loop's bandwidth, where
//! the transfer is near 1: the lowest learned order times the electrical frequency must
//! be where the loop passes at most half of it (`|E/D| >= 1/2`, [`MIN_ERROR_TRANSFER`]);
//! [`learn_angle_correction`] refuses a slower capture.

use angletrack_core::{
    AngleCorrection, Calibrator, Chain, ChainState, FaultThresholds, Gains, MAX_CORRECTION_ORDER,
    ObserverState, SensorCalibration,
};
use nalgebra::Complex;

use crate::error::{Argument, Error};
use crate::sim::online_calibration;

mod file;

pub use file::{
    ANGLE_CALIBRATION_FORMAT, CALIBRATION_FILE_VERSION, CalibrationFile, CalibrationFileError,
    SENSOR_CALIBRATION_FORMAT, SensorCalibrationRecord,
};

/// The smallest `|E/D|` of the loop at the lowest learned harmonic (see the module's
/// documentation): the learned coefficients are divided by it, so their noise grows by at
/// most 2.
pub const MIN_ERROR_TRANSFER: f64 = 0.5;

/// The largest relative spread `(max - min) / |mean|` of the observer's speed over the fit:
/// the reference angle's harmonics then stay within a few percent of their frequency.
const MAX_SPEED_SPREAD: f64 = 0.2;

/// The fewest whole electrical turns the fit uses.
const MIN_FIT_TURNS: f64 = 5.0;

/// The fewest whole turns the online calibration must learn in the settling part of the
/// capture: its first turns after lock carry the loop's settling (measured on the harmonic
/// sensor of the tests: one learned turn leaves a fifth of a 5 % offset unlearned, four
/// leave 4 % of it).
const MIN_SENSOR_TURNS: u32 = 4;

/// How the calibration is learned ([`learn_angle_correction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationOptions {
    /// The lowest harmonic order learned. Orders 1 and 2 hold what the sensor calibration
    /// leaves of the offsets (order 1) and of the imbalance and quadrature (order 2); at a
    /// capture too slow for them to be above the loop's bandwidth, start at 3.
    pub lowest_order: usize,
    /// The highest harmonic order learned (at most [`MAX_CORRECTION_ORDER`]).
    pub highest_order: usize,
    /// The fraction of the capture, from its start, the online calibration learns from
    /// before the fit starts (the fit then runs on the whole capture with the calibration
    /// learned, frozen, skipping this same start while the loop settles).
    pub settle_fraction: f64,
}

impl Default for CalibrationOptions {
    /// Orders 1 to 8, a fifth of the capture to settle.
    fn default() -> Self {
        Self {
            lowest_order: 1,
            highest_order: MAX_CORRECTION_ORDER,
            settle_fraction: 0.2,
        }
    }
}

/// What [`learn_angle_correction`] learned from a capture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureCalibration {
    /// The offsets, imbalance and quadrature (input units, rad).
    pub sensor: SensorCalibration<f64>,
    /// The angle-dependent error `d(theta)` (rad).
    pub correction: AngleCorrection<f64>,
    /// The mean electrical speed of the fit (rad/s).
    pub speed_rad_s: f64,
    /// The whole electrical turns the fit used.
    pub turns: f64,
    /// The RMS (rad) of the angle error over the fit before the correction.
    pub error_rms_rad: f64,
    /// The RMS (rad) of what the fitted harmonics leave of it (noise, orders not learned).
    pub residual_rms_rad: f64,
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

/// Learns a sensor's calibration from a capture `(y_c, y_s)` at roughly constant speed,
/// tracked with `gains`: first the online [`Calibrator`] over the first
/// `options.settle_fraction` of the capture (offsets, imbalance, quadrature), then, with
/// that calibration frozen and a fresh observer over the whole capture, the Fourier
/// coefficients of the angle error against the observer's angle, orders
/// `options.lowest_order..=options.highest_order`, corrected for the loop's transfer (see
/// the module's documentation), over the whole turns after the settling.
///
/// Refuses ([`Argument::CalibrationCapture`]) a capture whose speed is not steady (a spread
/// above 20 %), too slow for the lowest order to be above the loop's bandwidth
/// ([`MIN_ERROR_TRANSFER`]), whose settling part (`settle_fraction`) teaches the online
/// calibration fewer than 4 whole turns, or shorter than 5 turns after the settling, and
/// orders outside `1..=MAX_CORRECTION_ORDER` ([`Argument::CorrectionOrder`]).
///
/// ```
/// use angletrack::{Gains, Motion, MotionProfile, Scenario, SensorModel, learn_angle_correction};
/// let gains = Gains::<f64, 3>::new([0.12, 0.0069, 0.000_13], 5e-5)?;
/// let mut sensor = SensorModel::with_noise(1e-3);
/// sensor.offset_cos = 0.05;
/// sensor.angle_error_harmonics[0] = (3, 5e-3, 0.3);
/// let speed = 2.0 * std::f64::consts::PI * 200.0;
/// let profile = MotionProfile::new(0.0, speed)
///     .then(Motion::ConstantSpeed { speed_rad_s: speed, duration_s: 0.25 });
/// let capture = Scenario::generate(&profile, &sensor, 5e-5, 1)?;
/// let learned = learn_angle_correction(&gains, &capture.y_c, &capture.y_s, &Default::default())?;
/// assert!((learned.sensor.offsets().0 - 0.05).abs() < 2e-3);
/// let (a, b) = learned.correction.coefficients();
/// // 5e-3 sin(3 theta + 0.3) = 5e-3 sin(0.3) cos(3 theta) + 5e-3 cos(0.3) sin(3 theta)
/// assert!((a[2] - 5e-3 * 0.3f64.sin()).abs() < 3e-4 && (b[2] - 5e-3 * 0.3f64.cos()).abs() < 3e-4);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn learn_angle_correction<const N: usize>(
    gains: &Gains<f64, N>,
    y_c: &[f64],
    y_s: &[f64],
    options: &CalibrationOptions,
) -> Result<CaptureCalibration, Error> {
    let (lowest, highest) = (options.lowest_order, options.highest_order);
    if !(1..=highest).contains(&lowest) || highest > MAX_CORRECTION_ORDER {
        return Err(Error::OutOfRange {
            argument: Argument::CorrectionOrder,
            expected: "1 <= lowest_order <= highest_order <= 8",
        });
    }
    if y_c.len() != y_s.len() || y_c.is_empty() {
        return Err(Error::OutOfRange {
            argument: Argument::SeriesLength,
            expected: "y_c and y_s of the same, non-zero length",
        });
    }
    if !(0.0..1.0).contains(&options.settle_fraction) {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "settle_fraction in [0, 1)",
        });
    }
    let gains = &for_capture_amplitude(gains, y_c, y_s);
    let settle = (options.settle_fraction * y_c.len() as f64) as usize;
    let (sensor, sensor_turns) = learn_sensor(gains, &y_c[..settle.max(1)], &y_s[..settle.max(1)]);
    let observed = observe(gains, &sensor, y_c, y_s, settle);
    if observed.is_empty() {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "samples the observer tracks without a fault after the settling",
        });
    }
    let ts = gains.sample_period();
    let speeds: Vec<f64> = observed.iter().map(|o| o.speed_per_sample).collect();
    let mean_speed = speeds.iter().sum::<f64>() / speeds.len().max(1) as f64;
    let (min, max) = speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if !(error_transfer(gains, lowest as f64 * mean_speed).norm() >= MIN_ERROR_TRANSFER) {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "an electrical speed at which the lowest learned order is well above the \
                       loop's bandwidth (the loop passing at most half of it): a faster capture, \
                       a slower loop or a higher lowest_order",
        });
    }
    if !(max - min <= MAX_SPEED_SPREAD * mean_speed.abs()) {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "a roughly constant speed (the observer's speed within 20 % of its mean)",
        });
    }
    if sensor_turns < MIN_SENSOR_TURNS {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "enough turns in its settling part (settle_fraction of the capture) for \
                       the offsets, imbalance and quadrature to be learned over at least 4 \
                       whole turns after lock: a longer capture or a larger settle_fraction",
        });
    }
    // Whole turns only: the harmonics are then orthogonal over the fit.
    let travelled = (observed.last().map_or(0.0, |o| o.unwrapped)
        - observed.first().map_or(0.0, |o| o.unwrapped))
    .abs();
    let turns = (travelled / std::f64::consts::TAU).floor();
    if !(turns >= MIN_FIT_TURNS) {
        return Err(Error::OutOfRange {
            argument: Argument::CalibrationCapture,
            expected: "at least 5 whole electrical turns after the settling",
        });
    }
    let start = observed[0].unwrapped;
    let fit: Vec<&Observed> = observed
        .iter()
        .take_while(|o| (o.unwrapped - start).abs() < turns * std::f64::consts::TAU)
        .collect();
    let n = fit.len() as f64;
    let mean_error = fit.iter().map(|o| o.error).sum::<f64>() / n;
    let mut a = [0.0; MAX_CORRECTION_ORDER];
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    for k in lowest..=highest {
        let (mut sum_cos, mut sum_sin) = (0.0, 0.0);
        for o in &fit {
            let (sin, cos) = (k as f64 * o.angle).sin_cos();
            sum_cos += (o.error - mean_error) * cos;
            sum_sin += (o.error - mean_error) * sin;
        }
        // e = Re(C e^{jk theta}) with C = a - j b; the loop multiplied C by its transfer.
        let learned = Complex::new(2.0 * sum_cos / n, -2.0 * sum_sin / n)
            / error_transfer(gains, k as f64 * mean_speed);
        a[k - 1] = learned.re;
        b[k - 1] = -learned.im;
    }
    let correction = AngleCorrection::new(a, b).map_err(Error::Gains)?;
    let squares =
        |f: &dyn Fn(&Observed) -> f64| (fit.iter().map(|o| f(o).powi(2)).sum::<f64>() / n).sqrt();
    let error_rms_rad = squares(&|o| o.error - mean_error);
    let residual_rms_rad = squares(&|o| {
        let fitted: f64 = (lowest..=highest)
            .map(|k| {
                let transfer = error_transfer(gains, k as f64 * mean_speed);
                let c = Complex::new(a[k - 1], -b[k - 1]) * transfer;
                (c * Complex::from_polar(1.0, k as f64 * o.angle)).re
            })
            .sum();
        o.error - mean_error - fitted
    });
    Ok(CaptureCalibration {
        sensor,
        correction,
        speed_rad_s: mean_speed / ts,
        turns,
        error_rms_rad,
        residual_rms_rad,
    })
}

/// `gains` with the diagnostics' thresholds scaled to the capture's measured amplitude
/// ([`capture_fault_thresholds`](crate::capture_fault_thresholds)) when they carry the
/// defaults (amplitude 1): the loop is amplitude-invariant, its monitor is not, so that a
/// capture in counts (amplitude 1800) or in volts (0.455) is learned as a normalised one.
/// Thresholds the caller set are kept.
fn for_capture_amplitude<const N: usize>(
    gains: &Gains<f64, N>,
    y_c: &[f64],
    y_s: &[f64],
) -> Gains<f64, N> {
    if gains.fault_thresholds() != FaultThresholds::default() {
        return *gains;
    }
    gains
        .with_fault_thresholds(crate::capture_fault_thresholds(y_c, y_s))
        .unwrap_or(*gains)
}

/// The online calibration learned over `y_c`, `y_s`, and the whole turns it learned.
fn learn_sensor<const N: usize>(
    gains: &Gains<f64, N>,
    y_c: &[f64],
    y_s: &[f64],
) -> (SensorCalibration<f64>, u32) {
    let chain = Chain::new(online_calibration(gains), *gains);
    let mut state = ChainState::<Calibrator<f64>, ObserverState<f64, N>>::new();
    state.front_end.enable();
    for (&c, &s) in y_c.iter().zip(y_s) {
        chain.track(&mut state, (c, s));
    }
    let calibrator = state.front_end;
    (calibrator.calibration(), calibrator.turns_learned())
}

/// One sample of the fit.
struct Observed {
    /// The observer's angle, wrapped (rad).
    angle: f64,
    /// The observer's angle with its whole turns (rad).
    unwrapped: f64,
    /// The observer's speed (rad per sample).
    speed_per_sample: f64,
    /// `atan2(s, c)` of the calibrated sample minus the observer's angle, wrapped (rad).
    error: f64,
}

/// The observer with `sensor` frozen over the whole capture, from sample `settle` on.
fn observe<const N: usize>(
    gains: &Gains<f64, N>,
    sensor: &SensorCalibration<f64>,
    y_c: &[f64],
    y_s: &[f64],
    settle: usize,
) -> Vec<Observed> {
    let chain = Chain::new(online_calibration(gains), *gains);
    let mut state = ChainState {
        front_end: Calibrator::from_calibration(*sensor),
        observer: ObserverState::new(),
    };
    let ts = gains.sample_period();
    let mut observed = Vec::with_capacity(y_c.len() - settle);
    for (k, (&raw_c, &raw_s)) in y_c.iter().zip(y_s).enumerate() {
        let estimate = chain.update(&mut state, (raw_c, raw_s));
        if k < settle || !estimate.faults.is_empty() {
            continue;
        }
        let (c, s) = sensor.correct(raw_c, raw_s);
        let error = s.atan2(c) - estimate.angle;
        observed.push(Observed {
            angle: estimate.angle,
            unwrapped: estimate.position(),
            speed_per_sample: estimate.speed * ts,
            error: error.sin().atan2(error.cos()),
        });
    }
    observed
}

#[cfg(test)]
mod tests;
