//! Real sensor signals over arrays (`docs/theory.md §12`): a run with the core's online
//! calibration ([`run_calibrated`]), and the nominal amplitude of a capture estimated from
//! its own samples ([`nominal_amplitude`], [`capture_fault_thresholds`]), so that the
//! diagnostics fit a capture in any unit (volts, raw ADC counts) without the caller stating
//! it.

use angletrack_core::{
    Calibrator, Chain, ChainState, FaultThresholds, Gains, ObserverState, Real, SinCos,
};

use super::Scenario;
use super::angle_noise::angle_noise_about;
use super::metrics::{Run, run_with};

/// The number of samples at the start of a capture from which [`nominal_amplitude`]
/// estimates its amplitude: 4096, a few electrical turns at usual speeds and sample rates,
/// and enough for the median to ignore a few bad samples.
pub const NOMINAL_AMPLITUDE_SAMPLES: usize = 4096;

/// Runs `gains` over the scenario's signals through the online calibration `calibrator`
/// (`Calibrator::new()` then `enable()` to learn from nothing,
/// `Calibrator::from_calibration(stored)` to apply a stored calibration, frozen), from a
/// fresh state, as [`run`](crate::run) does; returns the estimates and the calibrator as
/// the run left it (its [`calibration`](Calibrator::calibration) is what it learned).
///
/// ```
/// use angletrack::{Gains, Motion, MotionProfile, Scenario, SensorModel, run_calibrated};
/// use angletrack::core::Calibrator;
/// let sensor = SensorModel { offset_cos: 0.05, amplitude_imbalance: 0.1, ..SensorModel::default() };
/// let profile = MotionProfile::new(0.0, 300.0)
///     .then(Motion::ConstantSpeed { speed_rad_s: 300.0, duration_s: 1.0 });
/// let scenario = Scenario::generate(&profile, &sensor, 1e-4, 1)?;
/// let gains = Gains::<f64, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
/// let mut calibrator = Calibrator::new();
/// calibrator.enable();
/// let (estimates, calibrator) = run_calibrated(&gains, calibrator, &scenario);
/// assert_eq!(estimates.angle_rad.len(), scenario.len());
/// let (o_c, _) = calibrator.calibration().offsets();
/// assert!((o_c - 0.05).abs() < 2e-3 && (calibrator.calibration().amplitude_ratio() - 1.1).abs() < 2e-3);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn run_calibrated<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<T, N, S>,
    calibrator: Calibrator<T>,
    scenario: &Scenario,
) -> (Run, Calibrator<T>) {
    let chain = Chain::new(gains.online_calibration(), *gains);
    let mut state = ChainState {
        front_end: calibrator,
        observer: ObserverState::new(),
    };
    let run = run_with(scenario, |c, s| chain.update(&mut state, (c, s)));
    (run, state.front_end)
}

/// The nominal amplitude of a capture, estimated from its first [`NOMINAL_AMPLITUDE_SAMPLES`]
/// samples (non-finite ones left out), in the samples' own units: the amplitude the
/// observer's checks see once the signals' bias is removed. Where those samples go round the
/// Lissajous figure's centre (the centre taken half-way between each channel's 1st and 99th
/// percentiles, and each quadrant around it visited by 1 % of the samples), the median of
/// `sqrt((y_c - c_c)^2 + (y_s - c_s)^2)`: a bias (a single-supply ADC's mid-rail, 2.5 V under
/// a 1 V signal) leaves it as it is. Elsewhere (a standstill, a fraction of a turn), the
/// median of `sqrt(y_c^2 + y_s^2)`. The median, so that a few bad samples do not move it;
/// the first samples, so that a long capture costs no more. Imbalance and quadrature of a
/// few percent move it by about as much, inside the diagnostics' bands (0.5 to 1.5 times).
/// `None` when no sample is finite or the median is not positive.
///
/// ```
/// let theta: Vec<f64> = (0..1000).map(|k| 0.01 * k as f64).collect();
/// let y_c: Vec<f64> = theta.iter().map(|t| 1800.0 * t.cos()).collect();
/// let y_s: Vec<f64> = theta.iter().map(|t| 1800.0 * t.sin()).collect();
/// let amplitude = angletrack::nominal_amplitude(&y_c, &y_s).unwrap();
/// assert!((amplitude - 1800.0).abs() < 1.0, "{amplitude}");
/// // The same signal on a bias of 2.5 times its amplitude.
/// let biased = |y: &[f64]| y.iter().map(|v| v + 4500.0).collect::<Vec<_>>();
/// let amplitude = angletrack::nominal_amplitude(&biased(&y_c), &biased(&y_s)).unwrap();
/// assert!((amplitude - 1800.0).abs() < 10.0, "{amplitude}");
/// assert_eq!(angletrack::nominal_amplitude(&[0.0_f32; 8], &[0.0; 8]), None);
/// ```
pub fn nominal_amplitude<T: Real>(y_c: &[T], y_s: &[T]) -> Option<f64> {
    amplitudes(&first_pairs(y_c, y_s)).nominal
}

/// The standard deviation (rad) of a capture's angle about a smooth motion, measured on the
/// same first samples as [`nominal_amplitude`] and about the same centre: the noise the
/// per-sample tracking check sees (`FaultThresholds::tracking_error`). From the second
/// differences of consecutive samples' angles, by their median absolute deviation, so that
/// the speed, a constant acceleration and a few bad samples leave it as it is. For
/// Gaussian noise of standard deviation `s` per channel on a signal of amplitude `a`, about
/// `s / a`. `None` with fewer than 16 finite pairs.
///
/// ```
/// use rand::SeedableRng;
/// use rand_distr::{Distribution, Normal};
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let noise = Normal::new(0.0, 18.0).unwrap(); // 1 % of 1800 counts
/// let (y_c, y_s): (Vec<f64>, Vec<f64>) = (0..4096)
///     .map(|k| 0.02 * k as f64)
///     .map(|t| (1800.0 * t.cos() + noise.sample(&mut rng), 1800.0 * t.sin() + noise.sample(&mut rng)))
///     .unzip();
/// let measured = angletrack::angle_noise(&y_c, &y_s).unwrap();
/// assert!((measured - 0.01).abs() < 1e-3, "{measured}");
/// ```
pub fn angle_noise<T: Real>(y_c: &[T], y_s: &[T]) -> Option<f64> {
    let pairs = first_pairs(y_c, y_s);
    angle_noise_about(&pairs, amplitudes(&pairs).centre)
}

/// What [`amplitudes`] measures on a capture's first pairs.
struct Amplitudes {
    /// The nominal amplitude ([`nominal_amplitude`]).
    nominal: Option<f64>,
    /// The median of the magnitudes around zero.
    raw: Option<f64>,
    /// The centre the nominal amplitude was measured about: the Lissajous figure's, or zero.
    centre: (f64, f64),
}

/// The nominal amplitude of `pairs` (see [`nominal_amplitude`]), the median of their
/// magnitudes around zero (each `None` without pairs) and the centre of the first.
fn amplitudes(pairs: &[(f64, f64)]) -> Amplitudes {
    let around = |(c_c, c_s): (f64, f64)| -> Vec<f64> {
        let mut magnitudes: Vec<f64> = pairs
            .iter()
            .map(|(c, s)| (c - c_c).hypot(s - c_s))
            .collect();
        magnitudes.sort_unstable_by(f64::total_cmp);
        magnitudes
    };
    let raw = around((0.0, 0.0));
    let ring = lissajous_centre(pairs)
        .map(|centre| (centre, around(centre)))
        .filter(|(_, m)| is_ring(m));
    let (centre, magnitudes) = match &ring {
        Some((centre, magnitudes)) => (*centre, magnitudes.as_slice()),
        None => ((0.0, 0.0), raw.as_slice()),
    };
    Amplitudes {
        nominal: median(magnitudes).filter(|&m| m > 0.0),
        raw: median(&raw),
        centre,
    }
}

/// The first [`NOMINAL_AMPLITUDE_SAMPLES`] pairs whose samples are both finite.
fn first_pairs<T: Real>(y_c: &[T], y_s: &[T]) -> Vec<(f64, f64)> {
    y_c.iter()
        .zip(y_s)
        .take(NOMINAL_AMPLITUDE_SAMPLES)
        .map(|(&c, &s)| (c.to_f64(), s.to_f64()))
        .filter(|(c, s)| c.is_finite() && s.is_finite())
        .collect()
}

/// Whether magnitudes around a centre (sorted) are a ring's (the 10th to 90th percentiles within
/// half the median: imbalance and noise of a sensor), not a blob's (noise at a standstill,
/// whose 10th to 90th percentiles span 1.4 times the median).
fn is_ring(sorted: &[f64]) -> bool {
    let last = sorted.len().saturating_sub(1);
    match (
        sorted.get(last / 10),
        sorted.get(last / 2),
        sorted.get(last - last / 10),
    ) {
        (Some(low), Some(middle), Some(high)) => high - low <= 0.5 * middle,
        _ => false,
    }
}

/// The centre of the samples' Lissajous figure (half-way between each channel's 1st and
/// 99th percentiles), if the samples go round it (each quadrant holds 1 % of them).
fn lissajous_centre(pairs: &[(f64, f64)]) -> Option<(f64, f64)> {
    let middle = |mut values: Vec<f64>| {
        values.sort_unstable_by(f64::total_cmp);
        let last = values.len().checked_sub(1)?;
        Some(0.5 * (values[last / 100] + values[last - last / 100]))
    };
    let centre = (
        middle(pairs.iter().map(|p| p.0).collect())?,
        middle(pairs.iter().map(|p| p.1).collect())?,
    );
    let mut quadrants = [0usize; 4];
    for (c, s) in pairs {
        quadrants[usize::from(*c < centre.0) + 2 * usize::from(*s < centre.1)] += 1;
    }
    quadrants
        .iter()
        .all(|&n| n * 100 >= pairs.len() && n > 0)
        .then_some(centre)
}

/// The median of `sorted` (sorted values), `None` if there are none.
pub(super) fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some(0.5 * (sorted[n / 2 - 1] + sorted[n / 2])),
    }
}

/// The default [`FaultThresholds`] scaled to the capture's [`nominal_amplitude`]
/// ([`FaultThresholds::for_amplitude`]; the roundness check only where the first samples
/// show a circle, going all round it or along a line of a dead, stuck or shorted channel,
/// about that circle's amplitude: `roundness.rs`), with the tracking-error level above the capture's
/// [`angle_noise`] (the core's rule, [`FaultThresholds::with_tracking_error_above_noise`]:
/// 8 times it, at least 0.05); the core's defaults (amplitude 1) when it has none.
/// What the Python API and the command line use when the caller gives no thresholds, so
/// that a capture in raw ADC counts or in volts is monitored without its units being
/// stated.
///
/// ```
/// let (y_c, y_s) = ([1800.0_f32, 0.0, -1800.0], [0.0_f32, 1800.0, 0.0]);
/// let t = angletrack::capture_fault_thresholds(&y_c, &y_s);
/// assert_eq!((t.nominal_amplitude, t.loss_of_signal), (1800.0, 450.0));
/// ```
pub fn capture_fault_thresholds<T: Real>(y_c: &[T], y_s: &[T]) -> FaultThresholds<T> {
    capture_fault_thresholds_for_pole_pairs(y_c, y_s, 1)
}

/// [`capture_fault_thresholds`] for a sensor whose angle a drive multiplies by
/// `pole_pairs` (a one-speed resolver or encoder on a motor of that many pole pairs: the
/// electrical angle is `pole_pairs` times the tracked one): the angle-error levels, the
/// per-sample tracking error and the window's loss of tracking, divided by them, so that
/// they bound the electrical angle's error as they bound the tracked angle's at one pole
/// pair; the tracking-error level still at least 8 times the capture's noise. 0 and 1 are
/// [`capture_fault_thresholds`].
///
/// ```
/// let (y_c, y_s): (Vec<f64>, Vec<f64>) = (0..4096).map(|k| (0.01 * k as f64).sin_cos()).map(|(s, c)| (c, s)).unzip();
/// let one = angletrack::capture_fault_thresholds(&y_c, &y_s);
/// let four = angletrack::capture_fault_thresholds_for_pole_pairs(&y_c, &y_s, 4);
/// assert_eq!(four.tracking_error, one.tracking_error / 4.0);
/// assert_eq!(four.loss_of_tracking, one.loss_of_tracking / 4.0);
/// ```
pub fn capture_fault_thresholds_for_pole_pairs<T: Real>(
    y_c: &[T],
    y_s: &[T],
    pole_pairs: u32,
) -> FaultThresholds<T> {
    let pairs = first_pairs(y_c, y_s);
    let Amplitudes {
        nominal: Some(amplitude),
        raw,
        centre,
    } = amplitudes(&pairs)
    else {
        return FaultThresholds::default();
    };
    // A measured amplitude, not a stated one: the pair before any calibration need not be
    // round, so the roundness check (`FaultThresholds::magnitude_tolerance`) runs only on a
    // circle the first samples show (`roundness.rs`), about its amplitude.
    let noise = angle_noise_about(&pairs, centre).unwrap_or(0.0);
    let circle = super::roundness::measured_circle(&pairs, noise);
    let amplitude = circle.map_or(amplitude, |(nominal, _)| nominal);
    let measured = FaultThresholds::for_amplitude(T::from_f64(amplitude))
        .with_magnitude_tolerance(circle.map(|(_, tolerance)| T::from_f64(tolerance)));
    // The core's level above the noise for the electrical angle (its noise `p` times the
    // tracked angle's), taken back to the tracked angle: at least 8 times the noise.
    let p = T::from_f64(f64::from(pole_pairs.max(1)));
    let level = measured
        .with_tracking_error_above_noise(T::from_f64(noise) * p)
        .tracking_error
        / p;
    let mut thresholds = measured
        .with_tracking_error(level)
        .with_loss_of_tracking(measured.loss_of_tracking / p);
    // A biased signal's samples are no bad samples: the input bound covers the bias too
    // (until a calibration removes it, the observer sees it).
    if let Some(raw) = raw {
        let bound = T::from_f64(raw) * T::from_f32(4.0);
        if bound > thresholds.max_input_amplitude {
            thresholds.max_input_amplitude = bound;
        }
    }
    thresholds
}

#[cfg(test)]
mod tests;
