//! The sensor noise from the radial residual around the Lissajous ellipse
//! (`docs/theory.md §16.1`): per channel, white and coloured, and the quantisation's share.

use super::ellipse::Ellipse;
use super::estimate::{NoiseEstimate, Uncertain};

/// The autocovariances `c_0 .. c_3` of `r` (its mean removed).
fn autocovariances(r: &[f64]) -> [f64; 4] {
    let n = r.len();
    let mean = r.iter().sum::<f64>() / n as f64;
    core::array::from_fn(|lag| {
        (lag..n)
            .map(|k| (r[k] - mean) * (r[k - lag] - mean))
            .sum::<f64>()
            / n as f64
    })
}

/// The harmonics of the angle taken out of the radial residual's colour: what is a
/// function of the angle (the fit's bias at high noise, the signals' harmonics) is radial
/// only, unseen by the phase detector, yet as correlated as the angle is slow.
const RESIDUAL_HARMONICS: usize = 4;

/// `r` less its least-squares fit by a constant and the first [`RESIDUAL_HARMONICS`]
/// harmonics of `theta`.
fn without_angle_pattern(r: &[f64], theta: &[f64]) -> Vec<f64> {
    const M: usize = 2 * RESIDUAL_HARMONICS + 1;
    let row = |t: f64| {
        let mut x = nalgebra::SVector::<f64, M>::zeros();
        x[0] = 1.0;
        for k in 1..=RESIDUAL_HARMONICS {
            let (s, c) = (k as f64 * t).sin_cos();
            x[2 * k - 1] = c;
            x[2 * k] = s;
        }
        x
    };
    let mut normal = nalgebra::SMatrix::<f64, M, M>::zeros();
    let mut rhs = nalgebra::SVector::<f64, M>::zeros();
    for (&ri, &t) in r.iter().zip(theta) {
        let x = row(t);
        normal += x * x.transpose();
        rhs += x * ri;
    }
    let Some(fit) = normal.lu().solve(&rhs) else {
        return r.to_vec();
    };
    r.iter()
        .zip(theta)
        .map(|(&ri, &t)| ri - fit.dot(&row(t)))
        .collect()
}

/// The noise from the radial residual `r` around the ellipse at the angles `theta`.
pub(super) fn noise(
    r: &[f64],
    theta: &[f64],
    ellipse: &Ellipse,
    step: Option<f64>,
) -> NoiseEstimate {
    let n = r.len() as f64;
    let c = autocovariances(&without_angle_pattern(r, theta));
    let rho = c[1] / c[0];
    // White unless the lag-1 correlation stands out of its sampling spread.
    let (white, coloured, pole) = if rho > 3.0 / n.sqrt() && c[2] > 0.0 {
        let pole = (c[2] / c[1]).clamp(0.0, 0.999);
        let coloured = (c[1] / pole.max(1e-12)).min(c[0]);
        ((c[0] - coloured).max(0.0), coloured, pole)
    } else {
        (c[0], 0.0, 0.0)
    };
    // r^2 = (v_c + v_s)/2 + (v_c - v_s)/2 cos(2 theta): the channels apart.
    let (mut s0, mut s1) = (0.0, 0.0);
    let (mut n11, mut n12, mut n22) = (0.0, 0.0, 0.0);
    for (&ri, &t) in r.iter().zip(theta) {
        let x = (2.0 * t).cos();
        s0 += ri * ri;
        s1 += ri * ri * x;
        n11 += 1.0;
        n12 += x;
        n22 += x * x;
    }
    let det = n11 * n22 - n12 * n12;
    let mean = (s0 * n22 - s1 * n12) / det;
    let half_difference = (s1 * n11 - s0 * n12) / det;
    let effective = n * (1.0 - rho.max(0.0)) / (1.0 + rho.max(0.0));
    let spread = (0.5 / effective).sqrt();
    let channel = |v: f64| {
        let value = v.max(0.0).sqrt();
        Uncertain {
            value,
            std: value * spread * core::f64::consts::SQRT_2,
        }
    };
    let std = c[0].sqrt();
    NoiseEstimate {
        amplitude: ellipse.amplitude(),
        cos_std: channel(mean + half_difference),
        sin_std: channel(mean - half_difference),
        std: Uncertain {
            value: std,
            std: std * spread,
        },
        white_std: white.sqrt(),
        coloured_std: coloured.sqrt(),
        coloured_pole: pole,
        quantisation_std: step.map(|q| q / 12f64.sqrt() / ellipse.amplitude()),
    }
}
