//! What a design needs, estimated from a capture (`docs/theory.md §16.1`, `§16.2`): the
//! sensor noise from the radial residual around the Lissajous ellipse, the motion from the
//! reference angle or from the signals' own angle, each with its uncertainty.

use core::f64::consts::TAU;

use super::DesignCaptureError;
use super::als::{self, AlsEstimate};
use super::ellipse::Ellipse;
use super::jerk::jerk_std;
use super::linear_loop;
use super::noise::noise;

/// The fewest samples a capture must have.
pub const MIN_SAMPLES: usize = 2000;
/// The fewest turns the shaft must travel (forward and back both count): the ellipse fit
/// needs its whole circumference, the motion's statistics more than one event.
pub const MIN_TURNS: f64 = 2.0;
/// The largest noise (relative to the amplitude) of signals that trace an ellipse: above
/// it the fit has taken a blob of noise for one.
pub const MAX_NOISE_STD: f64 = 0.25;
/// Below this travel (rad) the capture is at standstill.
const STANDSTILL_RAD: f64 = 0.1;
/// The share of the capture left out at its start (and, for a smoothed angle, at its end)
/// where the error is predicted or measured: the loops' initial transients.
pub const SKIP_FRACTION: f64 = 0.1;

/// A value estimated from a capture, with its standard uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Uncertain {
    /// The estimate.
    pub value: f64,
    /// Its standard uncertainty (one standard deviation of the estimate).
    pub std: f64,
}

/// A capture's two channels, its sample period and, if it has one, the reference angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureSignals<'a> {
    /// The cosine channel, in any unit (counts, volts).
    pub cos: &'a [f64],
    /// The sine channel, in the cosine's unit.
    pub sin: &'a [f64],
    /// The sample period (s).
    pub sample_period_s: f64,
    /// The true angle (rad, wrapped or not) from an encoder or a simulation, if recorded.
    pub reference_angle_rad: Option<&'a [f64]>,
    /// The channels' quantisation step in their unit (1 for ADC counts), if known.
    pub quantisation_step: Option<f64>,
}

/// The sensor noise, relative to the signals' amplitude (the designs' `sensor_noise_std`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseEstimate {
    /// The Lissajous ellipse's mean amplitude, in the signals' unit.
    pub amplitude: f64,
    /// The noise standard deviation of the cosine channel (relative to its amplitude).
    pub cos_std: Uncertain,
    /// The noise standard deviation of the sine channel (relative to its amplitude).
    pub sin_std: Uncertain,
    /// The phase detector's noise per channel, `sqrt((cos_std^2 + sin_std^2) / 2)`: what
    /// the designs take as `sensor_noise_std`.
    pub std: Uncertain,
    /// The white part's standard deviation.
    pub white_std: f64,
    /// The coloured part's standard deviation (0 for white noise).
    pub coloured_std: f64,
    /// The coloured part's correlation from one sample to the next (its first-order
    /// autoregression's pole, in `[0, 1)`).
    pub coloured_pole: f64,
    /// The quantisation's share of `std` (`step / sqrt(12)` relative to the amplitude),
    /// when the step is known.
    pub quantisation_std: Option<f64>,
}

/// The shaft's motion.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionEstimate {
    /// The jerk's standard deviation (rad/s^3) as a white sequence constant over each
    /// sample (the Kalman model's, [`kalman_from_jerk_std`](crate::kalman_from_jerk_std)):
    /// of [`MotionEstimate::jerk_by_differences_rad_s3`] and the ALS estimate
    /// ([`CaptureEstimates::als`]), the one of smaller relative uncertainty.
    pub jerk_std_rad_s3: Uncertain,
    /// The jerk's standard deviation from the angle's third differences (rad/s^3).
    pub jerk_by_differences_rad_s3: Uncertain,
    /// `true` when [`MotionEstimate::jerk_std_rad_s3`] is the ALS estimate's.
    pub jerk_by_als: bool,
    /// `true` when taken from the reference angle, `false` from the signals' own angle.
    pub from_reference: bool,
    /// The turns travelled.
    pub turns: f64,
    /// The speed (rad/s) at the capture's start, over its first 10 samples of
    /// [`MotionEstimate::angle_rad`]: the speed step a tracker started on it acquires.
    pub initial_speed_rad_s: f64,
    /// The angle the loops' lag is predicted on: the reference, or the signals' angle
    /// smoothed without delay by a first-pass loop ([`CaptureEstimates::first_pass_gains`]).
    pub angle_rad: Vec<f64>,
}

/// Everything estimated from one capture.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureEstimates {
    /// The sample period (s).
    pub sample_period_s: f64,
    /// The sensor noise.
    pub noise: NoiseEstimate,
    /// The motion.
    pub motion: MotionEstimate,
    /// The autocovariance least-squares estimate of the jerk and the noise from a
    /// first-pass Kalman loop's innovations on the signals' own angle; `None` where the
    /// capture is too short for the lags that loop needs.
    pub als: Option<AlsEstimate>,
    /// Without a reference: the gains of the first-pass loop that smoothed the angle, whose
    /// noise the lag predictions take out again; empty with a reference.
    pub first_pass_gains: Vec<f64>,
    /// The first pass's nominal bandwidth (Hz); `None` with a reference.
    pub first_pass_bandwidth_hz: Option<f64>,
    /// The signals' own angle (unwrapped), which a first pass smooths (empty with a
    /// reference).
    own_angle: Vec<f64>,
}

impl CaptureEstimates {
    /// Without a reference, smooths the signals' own angle with a first pass: the Kalman design whose nominal bandwidth is `bandwidth_hz`
    /// (`docs/theory.md §16.2`); with a reference, nothing.
    pub(super) fn smooth_with(&mut self, bandwidth_hz: f64) -> Result<(), DesignCaptureError> {
        if self.motion.from_reference {
            return Ok(());
        }
        let gains = kalman_at(bandwidth_hz, self.noise.std.value, self.sample_period_s)?;
        // The first pass starts at the slope of a few of its time constants.
        let span = (0.5 / (bandwidth_hz * self.sample_period_s)) as usize;
        self.motion.angle_rad = linear_loop::smoothed(&gains, &self.own_angle, span);
        self.motion.initial_speed_rad_s =
            initial_speed(&self.motion.angle_rad, self.sample_period_s);
        self.first_pass_gains = gains;
        self.first_pass_bandwidth_hz = Some(bandwidth_hz);
        Ok(())
    }

    /// Where the choice's grid is centred (Hz): the nominal bandwidth of the Kalman design
    /// of the estimated jerk and noise, at least the initial speed over `2 pi` (a loop much
    /// narrower acquires it badly) and `1e-4` of the sample rate (a jerk too small to see).
    pub(super) fn centre_bandwidth_hz(&self) -> f64 {
        let ts = self.sample_period_s;
        let q = (self.motion.jerk_std_rad_s3.value * ts.powi(3)).powi(2);
        let r = self.noise.std.value.max(MIN_NOISE_STD).powi(2);
        nominal_bandwidth_hz(q / r, ts)
            .max(self.motion.initial_speed_rad_s / TAU)
            .max(1e-4 / ts)
    }

    /// The estimated spectra (one-sided, rad^2/Hz) at `points` frequencies spread
    /// geometrically from a thousandth of the sample rate to the Nyquist frequency, as
    /// `(hz, noise, motion)`: see [`CaptureEstimates::spectra_rad2_per_hz`].
    pub fn spectra(&self, points: usize) -> Vec<(f64, f64, f64)> {
        let nyquist = 0.5 / self.sample_period_s;
        (0..points)
            .map(|i| {
                let hz = nyquist * 1e-3_f64.powf(1.0 - i as f64 / (points.max(2) - 1) as f64);
                let (noise, motion) = self.spectra_rad2_per_hz(hz);
                (hz, noise, motion)
            })
            .collect()
    }

    /// The estimated spectra at `hz` (one-sided, rad^2/Hz): the phase detector's noise
    /// (white and first-order autoregressive parts) and the angle of the white-jerk model
    /// (`2 jerk_std^2 Ts / (2 pi f)^6`), for plotting.
    pub fn spectra_rad2_per_hz(&self, hz: f64) -> (f64, f64) {
        let ts = self.sample_period_s;
        let n = &self.noise;
        let w = TAU * hz * ts;
        let coloured = n.coloured_std.powi(2) * (1.0 - n.coloured_pole.powi(2))
            / (1.0 - 2.0 * n.coloured_pole * w.cos() + n.coloured_pole.powi(2));
        let noise = 2.0 * ts * (n.white_std.powi(2) + coloured);
        let jerk = self.motion.jerk_std_rad_s3.value;
        let motion = 2.0 * jerk * jerk * ts / (TAU * hz).powi(6);
        (noise, motion)
    }

    /// The samples over which errors are predicted: [`SKIP_FRACTION`] left out at the start
    /// and, for a smoothed angle, at the end.
    pub fn window(&self) -> core::ops::Range<usize> {
        let n = self.motion.angle_rad.len();
        let skip = (SKIP_FRACTION * n as f64).ceil() as usize;
        let end = if self.motion.from_reference {
            n
        } else {
            n - skip
        };
        skip..end
    }
}

fn check_series(
    name: &'static str,
    series: &[f64],
    expected: usize,
) -> Result<(), DesignCaptureError> {
    if series.len() != expected {
        return Err(DesignCaptureError::LengthMismatch {
            series: name,
            len: series.len(),
            expected,
        });
    }
    match series.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(DesignCaptureError::NotFinite {
            series: name,
            index,
        }),
        None => Ok(()),
    }
}

/// The angle unwrapped: each step taken as the one within `(-pi, pi]`.
fn unwrapped(wrapped: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for a in wrapped {
        let next = match out.last() {
            None => a,
            Some(&previous) => {
                let step = a - previous;
                previous + step - TAU * (step / TAU).round()
            }
        };
        out.push(next);
    }
    out
}

/// Estimates the sensor noise and the motion from `signals` (`docs/theory.md §16.1`,
/// `§16.2`).
///
/// Refuses a capture shorter than [`MIN_SAMPLES`], at standstill or travelling fewer than
/// [`MIN_TURNS`] turns, series of different lengths or with a sample not finite, and
/// channels that trace no ellipse.
///
/// ```
/// use angletrack::design_capture::{CaptureSignals, estimate_from_capture};
/// let ts = 1e-4;
/// let angle: Vec<f64> = (0..20_000).map(|k| 300.0 * k as f64 * ts).collect();
/// let cos: Vec<f64> = angle.iter().map(|a| 2.0 * a.cos()).collect();
/// let sin: Vec<f64> = angle.iter().map(|a| 2.0 * a.sin()).collect();
/// let signals = CaptureSignals { cos: &cos, sin: &sin, sample_period_s: ts,
///     reference_angle_rad: Some(&angle), quantisation_step: None };
/// let estimates = estimate_from_capture(&signals)?;
/// assert!((estimates.noise.amplitude - 2.0).abs() < 1e-9);
/// assert!(estimates.noise.std.value < 1e-9);
/// # Ok::<(), angletrack::design_capture::DesignCaptureError>(())
/// ```
pub fn estimate_from_capture(
    signals: &CaptureSignals<'_>,
) -> Result<CaptureEstimates, DesignCaptureError> {
    let ts = signals.sample_period_s;
    if !(ts > 0.0 && ts.is_finite()) {
        return Err(DesignCaptureError::Argument {
            name: "sample_period_s",
            expected: "a positive number of seconds",
        });
    }
    if let Some(step) = signals.quantisation_step
        && !(step > 0.0 && step.is_finite())
    {
        return Err(DesignCaptureError::Argument {
            name: "quantisation_step",
            expected: "a positive number in the signals' unit",
        });
    }
    let n = signals.cos.len();
    check_series("cos", signals.cos, n)?;
    check_series("sin", signals.sin, n)?;
    if let Some(reference) = signals.reference_angle_rad {
        check_series("reference_angle_rad", reference, n)?;
    }
    if n < MIN_SAMPLES {
        return Err(DesignCaptureError::TooShort {
            samples: n,
            needed: MIN_SAMPLES,
        });
    }
    let reference = signals
        .reference_angle_rad
        .map(|r| unwrapped(r.iter().copied()));
    // The travel is judged before the fit where a reference says it.
    if let Some(angle) = &reference {
        check_travel(travel(angle))?;
    }
    let ellipse = Ellipse::fit(signals.cos, signals.sin)?;
    let normalised: Vec<(f64, f64)> = signals
        .cos
        .iter()
        .zip(signals.sin)
        .map(|(&c, &s)| ellipse.normalised(c, s))
        .collect();
    let own_angle = unwrapped(normalised.iter().map(|&(c, s)| s.atan2(c)));
    let radial: Vec<f64> = normalised.iter().map(|&(c, s)| c.hypot(s) - 1.0).collect();
    if reference.is_none() {
        check_travel(travel(&own_angle))?;
    }
    let noise = noise(&radial, &own_angle, &ellipse, signals.quantisation_step);
    if !(noise.std.value <= MAX_NOISE_STD) {
        return Err(DesignCaptureError::NoEllipse);
    }
    let own_angle_for_als = own_angle.clone();
    // The reference has no noise to take out; the signals' own angle has the sensor's.
    let (angle, angle_noise, own_angle) = match reference {
        Some(angle) => (angle, (0.0, 0.0, 0.0), Vec::new()),
        None => {
            let variances = (
                noise.white_std.powi(2),
                noise.coloured_std.powi(2),
                noise.coloured_pole,
            );
            (own_angle.clone(), variances, own_angle)
        }
    };
    let from_reference = signals.reference_angle_rad.is_some();
    let by_differences = jerk_std(&angle, ts, angle_noise);
    let als = als_estimate(&own_angle_for_als, ts, &noise, by_differences.value);
    let relative = |u: &Uncertain| {
        if u.value > 0.0 {
            u.std / u.value
        } else {
            f64::INFINITY
        }
    };
    // ALS is consistent for the Kalman model's white noise; with a coloured part it takes
    // the colour's estimated shape as exact, an error its spread does not hold.
    let white = noise.coloured_std == 0.0;
    let jerk_by_als =
        white && als.is_some_and(|a| relative(&a.jerk_std_rad_s3) < relative(&by_differences));
    let mut estimates = CaptureEstimates {
        sample_period_s: ts,
        noise,
        motion: MotionEstimate {
            jerk_std_rad_s3: match als {
                Some(a) if jerk_by_als => a.jerk_std_rad_s3,
                _ => by_differences,
            },
            jerk_by_differences_rad_s3: by_differences,
            jerk_by_als,
            from_reference,
            turns: travel(&angle) / TAU,
            initial_speed_rad_s: initial_speed(&angle, ts),
            angle_rad: angle,
        },
        als,
        first_pass_gains: Vec::new(),
        first_pass_bandwidth_hz: None,
        own_angle,
    };
    let first_pass_hz = FIRST_PASS_WIDENING * estimates.centre_bandwidth_hz();
    estimates.smooth_with(first_pass_hz)?;
    Ok(estimates)
}

/// The ALS estimate (`docs/theory.md §16.2`) on the signals' own angle `own_angle`: its
/// first pass the Kalman loop of the jerk `jerk_rad_s3` and the `noise`, then again of the
/// ALS's own jerk where it found one, the noise's colour taken from `noise`.
fn als_estimate(
    own_angle: &[f64],
    ts: f64,
    noise: &NoiseEstimate,
    jerk_rad_s3: f64,
) -> Option<AlsEstimate> {
    let r = noise.std.value.max(MIN_NOISE_STD).powi(2);
    let coloured_share = noise.coloured_std.powi(2) / r;
    let at = |jerk: f64| {
        let hz = nominal_bandwidth_hz((jerk * ts.powi(3)).powi(2) / r, ts).max(1e-4 / ts);
        let gains = kalman_at(hz, noise.std.value, ts).ok()?;
        als::estimate(
            &gains,
            hz,
            own_angle,
            ts,
            coloured_share.min(1.0),
            noise.coloured_pole,
        )
    };
    let first = at(jerk_rad_s3)?;
    let jerk = first.jerk_std_rad_s3;
    if jerk.value > 2.0 * jerk.std {
        at(jerk.value).or(Some(first))
    } else {
        Some(first)
    }
}

/// `|theta[10] - theta[0]| / (10 Ts)` (rad/s).
fn initial_speed(angle: &[f64], ts: f64) -> f64 {
    const SPAN: usize = 10;
    (angle[SPAN] - angle[0]).abs() / (SPAN as f64 * ts)
}

/// The segments the travel is summed over: few enough that the noise of the signals' own
/// angle adds little, many enough to follow reversals.
const TRAVEL_SEGMENTS: usize = 200;

/// The angle travelled (rad), forward and back: `|delta theta|` summed over
/// [`TRAVEL_SEGMENTS`] segments.
fn travel(angle: &[f64]) -> f64 {
    let step = (angle.len() / TRAVEL_SEGMENTS).max(1);
    let ends: Vec<f64> = angle.iter().step_by(step).copied().collect();
    ends.windows(2).map(|w| (w[1] - w[0]).abs()).sum()
}

fn check_travel(travelled_rad: f64) -> Result<(), DesignCaptureError> {
    if travelled_rad < STANDSTILL_RAD {
        return Err(DesignCaptureError::Standstill { travelled_rad });
    }
    let turns = travelled_rad / TAU;
    if turns < MIN_TURNS {
        return Err(DesignCaptureError::TooFewTurns {
            turns,
            needed: MIN_TURNS,
        });
    }
    Ok(())
}

/// How much wider than the Kalman design of the estimated jerk and noise the first pass
/// is: its lag then stays small where the candidates' errors are decided.
pub(super) const FIRST_PASS_WIDENING: f64 = 4.0;

/// The noise standard deviation below which a noise counts as this one (a capture of
/// exact signals still gets a Kalman design).
const MIN_NOISE_STD: f64 = 1e-9;

/// The nominal bandwidth (Hz) of the Kalman design of ratio `q / r`:
/// `(q / r)^(1/6) / (2 pi Ts)`, where its loop's poles sit for small ratios.
pub(super) fn nominal_bandwidth_hz(q_over_r: f64, ts: f64) -> f64 {
    q_over_r.powf(1.0 / 6.0) / (TAU * ts)
}

/// The `q` of the Kalman design at noise variance `r` whose nominal bandwidth is `hz`.
pub(super) fn kalman_q(hz: f64, r: f64, ts: f64) -> f64 {
    r * (TAU * hz * ts).powi(6)
}

/// The gains of the Kalman design of nominal bandwidth `hz` at noise `noise_std`, `q / r`
/// kept where the design accepts it.
fn kalman_at(hz: f64, noise_std: f64, ts: f64) -> Result<Vec<f64>, DesignCaptureError> {
    let r = noise_std.max(MIN_NOISE_STD).powi(2);
    let ratio = (kalman_q(hz, r, ts) / r).clamp(1e-24, 1e3);
    crate::kalman(ratio * r, r, ts)
        .map(|d| d.gains.gains().to_vec())
        .map_err(|_| DesignCaptureError::Argument {
            name: "sample_period_s",
            expected: "a period at which the first pass's Kalman design exists",
        })
}
