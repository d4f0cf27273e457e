//! The autocovariance least-squares estimate (ALS; Odelson, Rajamani and Rawlings,
//! Automatica 2006) of the Kalman model's process and measurement noise from a first-pass
//! loop's innovations (`docs/theory.md §16.2`).
//!
//! The innovations of a linear loop are a linear, stable filtering of the angle, and so of
//! the model's white jerk and of the measurement noise: their autocovariances at lags
//! `0..=L` are linear in `(q, r)` whatever the loop's gains. Their sample values, fitted by
//! non-negative least squares, give both.

use core::f64::consts::TAU;

use super::estimate::Uncertain;
use super::linear_loop;

/// The ALS estimate from one capture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlsEstimate {
    /// The jerk's standard deviation (rad/s^3): `sqrt(q) / Ts^3`.
    pub jerk_std_rad_s3: Uncertain,
    /// The phase detector's noise standard deviation (relative to the amplitude):
    /// `sqrt(r)`.
    pub noise_std: Uncertain,
    /// The nominal bandwidth (Hz) of the first-pass Kalman loop whose innovations were used.
    pub first_pass_bandwidth_hz: f64,
    /// The largest lag of the autocovariances fitted.
    pub lags: usize,
}

/// The blocks the innovations are cut into for the estimate's uncertainty (the spread of
/// the blocks' estimates over `sqrt(BLOCKS)`).
const BLOCKS: usize = 8;

/// The autocovariances at lags `0..=lags` of `e` (its mean not removed: the innovations of
/// a loop that tracks a constant acceleration have none).
fn autocovariances(e: &[f64], lags: usize) -> Vec<f64> {
    let n = e.len();
    (0..=lags)
        .map(|j| (j..n).map(|k| e[k] * e[k - j]).sum::<f64>() / n as f64)
        .collect()
}

/// The non-negative least-squares `(q, r)` of `c ≈ q a + r b`: the unconstrained solution,
/// else the better of each alone.
fn nnls(a: &[f64], b: &[f64], c: &[f64]) -> (f64, f64) {
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(u, v)| u * v).sum::<f64>();
    let (aa, ab, bb, ac, bc) = (dot(a, a), dot(a, b), dot(b, b), dot(a, c), dot(b, c));
    let det = aa * bb - ab * ab;
    if det > 0.0 {
        let q = (ac * bb - bc * ab) / det;
        let r = (bc * aa - ac * ab) / det;
        if q >= 0.0 && r >= 0.0 {
            return (q, r);
        }
    }
    let only_q = (ac / aa).max(0.0);
    let only_r = (bc / bb).max(0.0);
    let residual = |q: f64, r: f64| {
        c.iter()
            .zip(a.iter().zip(b))
            .map(|(ci, (ai, bi))| (ci - q * ai - r * bi).powi(2))
            .sum::<f64>()
    };
    if residual(only_q, 0.0) < residual(0.0, only_r) {
        (only_q, 0.0)
    } else {
        (0.0, only_r)
    }
}

/// `sum_k x_k x_{k+j}` for `j` in `0..=lags`.
fn self_products(x: &[f64], lags: usize) -> Vec<f64> {
    (0..=lags)
        .map(|j| x.iter().zip(&x[j.min(x.len())..]).map(|(u, v)| u * v).sum())
        .collect()
}

/// The map from `(q, r)` to the innovations' autocovariances at lags `0..=lags` of the
/// loop `l`: per unit `q` (the innovations' response `g` to one sample of unit scaled jerk)
/// and per unit `r` (the response `h` to a unit impulse of the noise, whose shape is white
/// plus a first-order autoregression of pole `pole` holding `coloured_share` of it).
fn linear_map(
    l: &[f64],
    lags: usize,
    length: usize,
    coloured_share: f64,
    pole: f64,
) -> (Vec<f64>, Vec<f64>) {
    // The angle after one sample of unit scaled jerk `G = (1/6, 1/2, 1)`, zero before it.
    let (mut angle, mut speed) = (1.0 / 6.0, 0.5);
    let jerk = (0..length).map(|k| {
        if k == 0 {
            return 0.0;
        }
        let value = angle;
        angle += speed + 0.5;
        speed += 1.0;
        value
    });
    let g = linear_loop::innovations(l, jerk);
    let h = linear_loop::innovations(l, (0..length).map(|k| if k == 0 { 1.0 } else { 0.0 }));
    let per_q = self_products(&g, lags);
    let white = self_products(&h, lags);
    let per_r = if coloured_share > 0.0 {
        // The autoregression `n[k] = pole n[k-1] + e[k]`, `var(e) = (1 - pole^2)`.
        let mut state = 0.0;
        let hc: Vec<f64> = h
            .iter()
            .map(|&x| {
                state = pole * state + x;
                state
            })
            .collect();
        let coloured = self_products(&hc, lags);
        white
            .iter()
            .zip(&coloured)
            .map(|(w, c)| (1.0 - coloured_share) * w + coloured_share * (1.0 - pole * pole) * c)
            .collect()
    } else {
        white
    };
    (per_q, per_r)
}

/// The ALS estimate of `(q, r)` from the first-pass Kalman loop `l` of nominal bandwidth
/// `bandwidth_hz` run on the signals' own angle `angle`, the noise's shape (its coloured
/// share and pole, `docs/theory.md §16.1`) taken as known. `None` when the capture is too
/// short for the lags the loop needs.
pub(super) fn estimate(
    l: &[f64],
    bandwidth_hz: f64,
    angle: &[f64],
    ts: f64,
    coloured_share: f64,
    pole: f64,
) -> Option<AlsEstimate> {
    // The loop's correlation time, a few of them: where q's signature lies.
    let time_constant = 1.0 / (TAU * bandwidth_hz * ts);
    let lags = ((3.0 * time_constant).ceil() as usize).max(8);
    // The start left out: the loop's transient from its first samples.
    let settle = (10.0 * time_constant).ceil() as usize;
    if angle.len() < settle + BLOCKS * 4 * lags {
        return None;
    }
    let span = (0.5 * time_constant) as usize;
    let innovations = linear_loop::innovations_started(l, angle, span.max(1));
    let innovations = &innovations[settle..];
    // The responses last until the loop (and the noise's colour) has forgotten the impulse.
    let memory = 20.0 * time_constant + 20.0 / (1.0 - pole).max(1e-3);
    let length = (memory as usize + lags).min(angle.len());
    let (per_q, per_r) = linear_map(l, lags, length, coloured_share, pole);
    let solve = |e: &[f64]| nnls(&per_q, &per_r, &autocovariances(e, lags));
    let (q, r) = solve(innovations);
    let block = innovations.len() / BLOCKS;
    let parts: Vec<(f64, f64)> = (0..BLOCKS)
        .map(|b| solve(&innovations[b * block..(b + 1) * block]))
        .collect();
    let spread = |pick: fn(&(f64, f64)) -> f64| {
        let mean = parts.iter().map(pick).sum::<f64>() / BLOCKS as f64;
        let variance =
            parts.iter().map(|p| (pick(p) - mean).powi(2)).sum::<f64>() / (BLOCKS - 1) as f64;
        (variance / BLOCKS as f64).sqrt()
    };
    // A variance v of spread s: its root sqrt(v), spread s / (2 sqrt(v)), or where v hardly
    // stands out of s the root that would just match it (an upper bound).
    let root = |v: f64, s: f64, scale: f64| {
        let value = v.sqrt() * scale;
        let std = if v > 2.0 * s {
            0.5 * value * s / v
        } else {
            s.sqrt() * scale
        };
        Uncertain { value, std }
    };
    Some(AlsEstimate {
        jerk_std_rad_s3: root(q, spread(|p| p.0), 1.0 / ts.powi(3)),
        noise_std: root(r, spread(|p| p.1), 1.0),
        first_pass_bandwidth_hz: bandwidth_hz,
        lags,
    })
}
