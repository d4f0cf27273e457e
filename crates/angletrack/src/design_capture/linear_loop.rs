//! The linearised loop of a gain set (`docs/theory.md §5`, `§8`, `§16.3`) run on a series
//! (an angle, or a noise), and its steady-state response to coloured noise.

use core::f64::consts::TAU;

use nalgebra::{DMatrix, DVector};

use crate::linalg;

/// The loop `x = (I - L e1^T) A x + L d(theta - (A x)_1)` of gains `l` (2 or 3, the scaled
/// state's) over `angle`, from the state `initial` (angle, speed times `Ts`, acceleration
/// times `Ts^2`), with the phase detector `d`: the identity for the linearised loop, the
/// sine for the observer's own (`docs/theory.md §1`). Yields the angle estimate and the
/// innovation `theta - (A x)_1` (before the detector).
fn run_with(
    l: &[f64],
    angle: impl Iterator<Item = f64>,
    initial: [f64; 3],
    detector: fn(f64) -> f64,
) -> impl Iterator<Item = (f64, f64)> {
    let mut x = initial;
    let third = l.len() == 3;
    angle.map(move |theta| {
        // The Taylor step of the scaled state, then the correction by the innovation.
        let predicted = if third {
            [x[0] + x[1] + 0.5 * x[2], x[1] + x[2], x[2]]
        } else {
            [x[0] + x[1], x[1], 0.0]
        };
        let innovation = theta - predicted[0];
        let detected = detector(innovation);
        for (i, value) in x.iter_mut().enumerate().take(l.len()) {
            *value = predicted[i] + l[i] * detected;
        }
        (x[0], innovation)
    })
}

/// The filtered angle estimates of the linear loop of gains `l` over `angle`, from the
/// state `initial` ([`run_with`]).
fn run(
    l: &[f64],
    angle: impl Iterator<Item = f64>,
    initial: [f64; 3],
) -> impl Iterator<Item = f64> {
    run_with(l, angle, initial, |e| e).map(|(x, _)| x)
}

/// The innovations of the linear loop of gains `l` over `series` from the zero state: the
/// loop's response from `series` to what it has not yet predicted.
pub(super) fn innovations(l: &[f64], series: impl Iterator<Item = f64>) -> Vec<f64> {
    run_with(l, series, [0.0; 3], |e| e)
        .map(|(_, e)| e)
        .collect()
}

/// The innovations of the linear loop of gains `l` over `series`, started on its first
/// sample at the slope of its first `span` samples (as [`smoothed`]'s passes).
pub(super) fn innovations_started(l: &[f64], series: &[f64], span: usize) -> Vec<f64> {
    let Some(&first) = series.first() else {
        return Vec::new();
    };
    let speed = initial_slope(series, span);
    run_with(
        l,
        series.iter().copied(),
        [first - speed, speed, 0.0],
        |e| e,
    )
    .map(|(_, e)| e)
    .collect()
}

/// [`run`] over `angle` from its first sample, moving at `speed` (rad per sample); from
/// rest (`speed` 0) as the observer starts, initialised on its first sample.
pub(super) fn filtered(l: &[f64], angle: &[f64], speed: f64) -> Vec<f64> {
    let Some(&first) = angle.first() else {
        return Vec::new();
    };
    run(l, angle.iter().copied(), [first - speed, speed, 0.0]).collect()
}

/// The mean slope (per sample) of the first `span` samples of `series` against the next
/// `span`: a start for a loop on a noisy series.
fn initial_slope(series: &[f64], span: usize) -> f64 {
    let span = span.clamp(1, series.len() / 2);
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
    (mean(&series[span..2 * span]) - mean(&series[..span])) / span as f64
}

/// The zero-phase smoothing of `series`: the loop of `l` run forward, then backward over
/// its output (`|T(e^jw)|^2`, no delay), each started at the slope of its first
/// `span` samples.
pub(super) fn smoothed(l: &[f64], series: &[f64], span: usize) -> Vec<f64> {
    let mut forward = filtered(l, series, initial_slope(series, span));
    forward.reverse();
    let mut back = filtered(l, &forward, initial_slope(&forward, span));
    back.reverse();
    back
}

/// The mean square over the samples `window` of the wrapped error `angle - estimate` of
/// the observer's own loop of gains `l` (its phase detector the sine, `docs/theory.md §1`)
/// run from rest on `angle`: its lag, and its acquisition of the motion from rest, cycle
/// slips and the detector's saturation included.
pub(super) fn observer_mean_square_error(
    l: &[f64],
    angle: &[f64],
    window: core::ops::Range<usize>,
) -> f64 {
    let Some(&first) = angle.first() else {
        return 0.0;
    };
    let count = window.len().max(1) as f64;
    run_with(l, angle.iter().copied(), [first, 0.0, 0.0], f64::sin)
        .zip(angle)
        .take(window.end)
        .skip(window.start)
        .map(|((estimate, _), theta)| {
            let e = theta - estimate;
            (e - TAU * (e / TAU).round()).powi(2)
        })
        .sum::<f64>()
        / count
}

/// The steady-state variance of the loop's angle estimate driven by a phase-detector noise
/// that is white of variance `white` plus a first-order autoregression of variance
/// `coloured` and pole `pole` (`n[k] = pole n[k-1] + e[k]`), plus a white error of variance
/// `angle_rounding` added to the angle state each sample (the number type's rounding).
/// `None` for an unstable loop.
pub(super) fn noise_variance(
    l: &[f64],
    white: f64,
    coloured: f64,
    pole: f64,
    angle_rounding: f64,
) -> Option<f64> {
    let n = l.len();
    let f = linalg::closed_loop(l);
    let gain = DVector::from_column_slice(l);
    let e1 = linalg::e1(n);
    let direct = &gain * gain.transpose() * white + &e1 * e1.transpose() * angle_rounding;
    let mut variance = linalg::discrete_lyapunov(&f, &direct)?[(0, 0)];
    if coloured > 0.0 {
        // The state (x, n): n[k] = pole n[k-1] + e, x[k] = F x[k-1] + L (pole n[k-1] + e).
        let mut phi = DMatrix::zeros(n + 1, n + 1);
        phi.view_mut((0, 0), (n, n)).copy_from(&f);
        phi.view_mut((0, n), (n, 1)).copy_from(&(&gain * pole));
        phi[(n, n)] = pole;
        let mut input = DVector::zeros(n + 1);
        input.rows_mut(0, n).copy_from(&gain);
        input[n] = 1.0;
        let innovation = coloured * (1.0 - pole * pole);
        let source = &input * input.transpose() * innovation;
        variance += linalg::discrete_lyapunov(&phi, &source)?[(0, 0)];
    }
    Some(variance)
}

/// The largest `|theta - estimate|` of the linear loop (from rest) after a speed step of
/// 1 rad per sample, over `samples`: the peak error per unit speed step.
pub(super) fn speed_step_peak(l: &[f64], samples: usize) -> f64 {
    let ramp = (1..=samples).map(|k| k as f64);
    run(l, ramp.clone(), [0.0; 3])
        .zip(ramp)
        .fold(0.0, |peak, (estimate, theta)| {
            f64::max(peak, (theta - estimate).abs())
        })
}

/// The variance of the linear loop `l`'s tracking error `(1 - T)` on a noise first
/// smoothed by the loop `first` forward and backward (`|T1|^2`): the smoothed angle's own
/// noise as the loop would track it, for the noise of [`noise_variance`]'s white and
/// first-order autoregressive parts, over `length` samples of the impulse response.
pub(super) fn smoothed_noise_tracking_variance(
    l: &[f64],
    first: &[f64],
    white: f64,
    coloured: f64,
    pole: f64,
    length: usize,
) -> f64 {
    // `(1 - T) T1 T1` run forward has the power spectrum of `(1 - T) |T1|^2`.
    let impulse = (0..length).map(|k| if k == 0 { 1.0 } else { 0.0 });
    let once: Vec<f64> = run(first, impulse, [0.0; 3]).collect();
    let twice: Vec<f64> = run(first, once.iter().copied(), [0.0; 3]).collect();
    let tracked: Vec<f64> = run(l, twice.iter().copied(), [0.0; 3]).collect();
    let h: Vec<f64> = twice.iter().zip(&tracked).map(|(s, t)| s - t).collect();
    let mut variance = white * h.iter().map(|x| x * x).sum::<f64>();
    if coloured > 0.0 {
        let mut state = 0.0;
        let energy: f64 = h
            .iter()
            .map(|&x| {
                state = pole * state + x;
                state * state
            })
            .sum();
        variance += coloured * (1.0 - pole * pole) * energy;
    }
    variance
}
