//! Step responses (`docs/theory.md §2` and `§3`): overshoot and settling time of a sampled
//! response, and the exact step response of a continuous loop.

use core::f64::consts::PI;

use nalgebra::DMatrix;

use crate::linalg;

/// The step size of the large-signal step response: 179 degrees (rad). A 180 degree step
/// would start on the loop's unstable equilibrium (`eps = 0`).
pub const LARGE_STEP_RAD: f64 = 179.0 * PI / 180.0;

/// The settling band of the reported settling times (fraction of the step).
pub const SETTLING_BAND: f64 = 0.02;

/// Overshoot and settling time of a step response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepResponse {
    /// The overshoot, as a fraction of the step (0.1 for 10 %); 0 without overshoot.
    pub overshoot: f64,
    /// The 2 % settling time (s): from the step to the last time the response is outside
    /// 2 % of the step around its final value.
    pub settling_time_s: f64,
}

impl StepResponse {
    /// Overshoot and settling of `response` (one value per sample, the step at sample 0)
    /// toward `target` from `start`, with settling band `band` (a fraction of the step)
    /// and sample period `period_s`.
    pub(crate) fn from_samples(
        response: impl Iterator<Item = f64>,
        start: f64,
        target: f64,
        band: f64,
        period_s: f64,
    ) -> Self {
        let step = target - start;
        let mut peak: f64 = 0.0;
        let mut last_outside = None;
        for (k, y) in response.enumerate() {
            let excess = (y - target) / step;
            peak = peak.max(excess);
            if !(excess.abs() <= band) {
                last_outside = Some(k);
            }
        }
        StepResponse {
            overshoot: peak,
            settling_time_s: last_outside.map_or(0.0, |k| (k + 1) as f64 * period_s),
        }
    }
}

/// The step response of the continuous loop `(c_{N-1} s^{N-1} + .. + c_0) / (s^N + .. + c_0)`
/// (the ATO's angle transfer function), sampled exactly (matrix exponential of the loop
/// with the constant input appended to the state) on a grid fine enough for the overshoot
/// (1/40 of the fastest pole's time constant) and long enough to settle.
pub(crate) fn continuous_step(c: &[f64]) -> StepResponse {
    continuous_step_within(c, MAX_STEP_SAMPLES)
}

/// The most samples of [`continuous_step`]'s grid.
const MAX_STEP_SAMPLES: usize = 1_000_000;

/// [`continuous_step`] on at most `max_samples` samples (at least 100): a coarser grid than
/// its own where the loop is stiff (a fast pole far from the others), for a search that only
/// brackets the overshoot. Exact at its samples all the same (the matrix exponential).
pub(crate) fn continuous_step_within(c: &[f64], max_samples: usize) -> StepResponse {
    let n = c.len();
    let poles = linalg::roots(c);
    let fastest = poles.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let slowest = poles.iter().map(|p| -p.re).fold(f64::INFINITY, f64::min);
    let fastest_oscillation = poles.iter().map(|p| p.im.abs()).fold(0.0, f64::max);
    let h = (1.0 / (40.0 * fastest)).min(0.02 / fastest_oscillation.max(1e-300));
    let horizon = 16.0 / slowest;
    let steps = ((horizon / h).ceil() as usize).clamp(100, max_samples.max(100));
    let h = horizon / steps as f64;
    // State (x, u): dx = S x + k (u - x1), du = 0, with k the continuous gains; over one
    // step of h, x <- Phi x + Gamma u with Phi, Gamma blocks of exp(M h).
    let m = DMatrix::from_fn(n + 1, n + 1, |i, j| {
        let k_i = if i < n { c[n - 1 - i] } else { 0.0 };
        let mut v = 0.0;
        if i < n && j == i + 1 && j < n {
            v += 1.0;
        }
        if i < n && j == 0 {
            v -= k_i;
        }
        if i < n && j == n {
            v += k_i;
        }
        v
    });
    let step_matrix = (m * h).exp();
    let phi = step_matrix.view((0, 0), (n, n)).into_owned();
    let gamma: Vec<f64> = (0..n).map(|i| step_matrix[(i, n)]).collect();
    let response = core::iter::once(0.0).chain(linalg::affine_response(phi, gamma, steps));
    StepResponse::from_samples(response, 0.0, 1.0, 0.02, h)
}
