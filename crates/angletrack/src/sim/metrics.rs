//! Running an observer over a scenario, and measuring the run against the truth.

use core::f64::consts::{PI, TAU};

use angletrack_core::{Chain, ChainState, Estimate, Gains, Real, SinCos};

use super::Scenario;
use crate::analysis::StepResponse;
use crate::error::{Argument, Error, non_negative, positive};

/// The estimates of one run, one value per sample, in `f64`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Run {
    /// Estimated multi-turn angle `turns * 2 pi + angle` (rad).
    pub angle_rad: Vec<f64>,
    /// Estimated speed (rad/s).
    pub speed_rad_s: Vec<f64>,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    pub acceleration_rad_s2: Vec<f64>,
}

/// Runs the observer `gains` (any float type, order and sin/cos) over the scenario's signals,
/// from a fresh state (initialised by the first sample's `atan2`, as in firmware). The
/// signals are rounded to `T` first. The loop runs the same at any amplitude (its phase
/// error is normalised, `docs/theory.md §12`); the gains' diagnostics thresholds apply as
/// in firmware, and compare amplitudes: the core's defaults assume amplitude 1, so set them
/// with `Gains::with_fault_thresholds` for another
/// [`SensorModel::amplitude`](crate::SensorModel::amplitude)
/// ([`capture_fault_thresholds`](crate::capture_fault_thresholds) estimates it from the
/// signals), or disable them to study the bare loop of the paper.
///
/// ```
/// use angletrack::{Gains, Motion, MotionProfile, Scenario, SensorModel, run};
/// let profile = MotionProfile::new(0.5, 20.0)
///     .then(Motion::ConstantSpeed { speed_rad_s: 20.0, duration_s: 0.1 });
/// let scenario = Scenario::generate(&profile, &SensorModel::default(), 1e-4, 1)?;
/// let gains = Gains::<f32, 3>::new([0.1, 0.005, 1e-4], 1e-4)?;
/// let estimates = run(&gains, &scenario);
/// assert_eq!(estimates.angle_rad.len(), scenario.len());
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn run<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<T, N, S>,
    scenario: &Scenario,
) -> Run {
    let chain = Chain::new((), *gains);
    let mut state = ChainState::new();
    run_with(scenario, |c, s| chain.update(&mut state, (c, s)))
}

/// The estimates of `update` (one observer's per-sample step, its state captured) over the
/// scenario's signals rounded to `T`.
pub(super) fn run_with<T: Real>(
    scenario: &Scenario,
    mut update: impl FnMut(T, T) -> Estimate<T>,
) -> Run {
    let n = scenario.y_c.len().min(scenario.y_s.len());
    let mut out = Run {
        angle_rad: Vec::with_capacity(n),
        speed_rad_s: Vec::with_capacity(n),
        acceleration_rad_s2: Vec::with_capacity(n),
    };
    for (&c, &s) in scenario.y_c.iter().zip(&scenario.y_s) {
        let e = update(T::from_f64(c), T::from_f64(s));
        out.angle_rad.push(e.position());
        out.speed_rad_s.push(e.speed.to_f64());
        out.acceleration_rad_s2.push(e.acceleration.to_f64());
    }
    out
}

/// What [`Metrics::new`] measures and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricsOptions {
    /// The error statistics (RMS, max, mean) skip the samples before this time (s): the
    /// initial transient.
    pub skip_s: f64,
    /// The loop counts as locked while the wrapped angle error stays within this (rad).
    pub lock_tolerance_rad: f64,
    /// The settling band, as a fraction of the move (0.02 for the usual 2 %).
    pub settling_band: f64,
}

impl Default for MetricsOptions {
    /// No skipped samples, lock within 0.01 rad, 2 % settling band.
    fn default() -> Self {
        Self {
            skip_s: 0.0,
            lock_tolerance_rad: 0.01,
            settling_band: 0.02,
        }
    }
}

/// Mean, RMS and largest magnitude of a series.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorStatistics {
    /// Root mean square.
    pub rms: f64,
    /// Largest magnitude.
    pub max: f64,
    /// Mean (signed: a bias).
    pub mean: f64,
}

impl ErrorStatistics {
    fn of(values: impl Iterator<Item = f64>) -> Self {
        let (mut sum, mut sum_squares, mut max, mut count) = (0.0, 0.0, 0.0_f64, 0usize);
        for v in values {
            sum += v;
            sum_squares += v * v;
            max = max.max(v.abs());
            count += 1;
        }
        let n = count.max(1) as f64;
        Self {
            rms: (sum_squares / n).sqrt(),
            max,
            mean: sum / n,
        }
    }
}

/// The quality of a run against the truth. Errors are `truth - estimate`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Angle error wrapped to [-pi, pi) (rad), over the samples from `skip_s` on.
    pub angle_error_rad: ErrorStatistics,
    /// Speed error (rad/s), over the samples from `skip_s` on.
    pub speed_error_rad_s: ErrorStatistics,
    /// Number of samples in the statistics.
    pub samples: usize,
    /// Largest excursion of the estimated angle past the truth's final angle, in the
    /// direction of the whole move, as a fraction of the move (0.1 for 10 %); `None` when
    /// the truth ends where it started.
    pub overshoot: Option<f64>,
    /// Time (s) after which the estimated angle stays within `settling_band` of the move
    /// around the truth's final angle; `None` when the truth ends where it started.
    pub settling_time_s: Option<f64>,
    /// Time (s) from which the wrapped angle error stays within `lock_tolerance_rad` to the
    /// end; `None` if it is outside at the last sample.
    pub time_to_lock_s: Option<f64>,
}

/// `x` wrapped into [-pi, pi).
pub(crate) fn wrap(x: f64) -> f64 {
    // A multi-turn error (thousands of turns into a long run) is first brought within about
    // a turn of zero by one rounding, so that the exact remainder, whose steps grow with the
    // turns, takes one or two: it was the costliest part of a study's error statistics.
    let near = x - TAU * (x / TAU).round();
    (near + PI).rem_euclid(TAU) - PI
}

impl Metrics {
    /// Measures `run` against `scenario`'s truth. The estimated multi-turn angle is aligned
    /// to the truth's turn at the first sample (an observer counts turns from its own start).
    ///
    /// ```
    /// use angletrack::{Gains, Metrics, MetricsOptions, Motion, MotionProfile, Scenario,
    ///     SensorModel, run};
    /// let profile = MotionProfile::new(0.0, 0.0).then(Motion::Trapezoidal {
    ///     distance_rad: 3.0, max_speed_rad_s: 30.0, max_acceleration_rad_s2: 300.0 });
    /// let profile = profile.then(Motion::ConstantSpeed { speed_rad_s: 0.0, duration_s: 0.2 });
    /// let scenario = Scenario::generate(&profile, &SensorModel::with_noise(1e-3), 1e-4, 3)?;
    /// let gains = Gains::<f64, 3>::new([0.1, 0.005, 1e-4], 1e-4)?;
    /// let metrics = Metrics::new(&scenario, &run(&gains, &scenario), &MetricsOptions::default())?;
    /// assert!(metrics.angle_error_rad.max < 0.05 && metrics.time_to_lock_s.is_some());
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn new(scenario: &Scenario, run: &Run, options: &MetricsOptions) -> Result<Self, Error> {
        let skip = non_negative(options.skip_s, Argument::Skip)?;
        let lock = positive(options.lock_tolerance_rad, Argument::LockTolerance)?;
        let band = positive(options.settling_band, Argument::SettlingBand)?;
        let n = scenario.len();
        let lengths = [
            scenario.angle_rad.len(),
            scenario.speed_rad_s.len(),
            run.angle_rad.len(),
            run.speed_rad_s.len(),
        ];
        if n == 0 || lengths.iter().any(|&len| len != n) {
            return Err(Error::OutOfRange {
                argument: Argument::SeriesLength,
                expected: "non-empty truth and run series of equal lengths",
            });
        }
        let ts = scenario.sample_period_s;
        let first = (skip / ts).ceil();
        if !(first < n as f64) {
            return Err(Error::OutOfRange {
                argument: Argument::Skip,
                expected: "shorter than the run",
            });
        }
        let first = first as usize;
        let angle_errors = || {
            scenario
                .angle_rad
                .iter()
                .zip(&run.angle_rad)
                .map(|(t, e)| wrap(t - e))
        };
        let angle_error_rad = ErrorStatistics::of(angle_errors().skip(first));
        let speed_error_rad_s = ErrorStatistics::of(
            scenario
                .speed_rad_s
                .iter()
                .zip(&run.speed_rad_s)
                .map(|(t, e)| t - e)
                .skip(first),
        );
        let time_to_lock_s = {
            let last_outside = angle_errors()
                .enumerate()
                .rev()
                .find(|(_, e)| !(e.abs() <= lock))
                .map(|(k, _)| k);
            match last_outside {
                Some(k) if k + 1 == n => None,
                Some(k) => Some((k + 1) as f64 * ts),
                None => Some(0.0),
            }
        };
        let start = scenario.angle_rad[0];
        let target = scenario.angle_rad[n - 1];
        let turn = ((start - run.angle_rad[0]) / TAU).round() * TAU;
        let step = if (target - start).abs() > 1e-12 * (1.0 + start.abs()) {
            Some(StepResponse::from_samples(
                run.angle_rad.iter().map(|a| a + turn),
                start,
                target,
                band,
                ts,
            ))
        } else {
            None
        };
        Ok(Metrics {
            angle_error_rad,
            speed_error_rad_s,
            samples: n - first,
            overshoot: step.map(|s| s.overshoot),
            settling_time_s: step.map(|s| s.settling_time_s),
            time_to_lock_s,
        })
    }
}
