//! The Lissajous ellipse of the two channels (`docs/theory.md §16.1`): the conic fitted by
//! least squares, read as the calibration model's offsets, amplitudes and quadrature, and
//! each sample's angle and radial residual on it.

use nalgebra::{Matrix2, Matrix5, Vector2, Vector5};

use super::DesignCaptureError;

/// The ellipse `y_c = o_c + A_c cos(theta)`, `y_s = o_s + A_s sin(theta + phi)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Ellipse {
    pub offset_cos: f64,
    pub offset_sin: f64,
    pub amplitude_cos: f64,
    pub amplitude_sin: f64,
    /// `phi` (rad).
    pub quadrature_rad: f64,
}

impl Ellipse {
    /// The least-squares conic `x^2 + b xy + c y^2 + d x + e y + f = 0` through the
    /// samples (centred and scaled for the normal equations' conditioning), then again with
    /// the noise's bias taken out of the normal equations (`docs/theory.md §16.1`).
    pub fn fit(cos: &[f64], sin: &[f64]) -> Result<Self, DesignCaptureError> {
        let plain = Self::fit_with_noise(cos, sin, 0.0)?;
        // The noise per channel in the signals' unit, from the plain fit's radial residual.
        let mean_square = cos
            .iter()
            .zip(sin)
            .map(|(&c, &s)| {
                let (u, v) = plain.normalised(c, s);
                (u.hypot(v) - 1.0).powi(2)
            })
            .sum::<f64>()
            / cos.len() as f64;
        let variance = mean_square * plain.amplitude().powi(2);
        Ok(Self::fit_with_noise(cos, sin, variance).unwrap_or(plain))
    }

    /// The conic fit with each monomial `x^i y^j` of the normal equations replaced by its
    /// unbiased value for a white noise of variance `noise_variance` on each channel (in the
    /// signals' unit): the Hermite polynomials `x^2 - s^2`, `x^3 - 3 s^2 x`,
    /// `x^4 - 6 s^2 x^2 + 3 s^4` (consistent algebraic least squares, Kukush, Markovsky and
    /// Van Huffel 2004). Zero gives the plain least squares.
    pub(super) fn fit_with_noise(
        cos: &[f64],
        sin: &[f64],
        noise_variance: f64,
    ) -> Result<Self, DesignCaptureError> {
        let n = cos.len() as f64;
        let (mx, my) = (cos.iter().sum::<f64>() / n, sin.iter().sum::<f64>() / n);
        let scale = (cos.iter().map(|x| (x - mx).powi(2)).sum::<f64>() / n).sqrt();
        if !(scale > 0.0) {
            return Err(DesignCaptureError::NoEllipse);
        }
        let s2 = noise_variance / (scale * scale);
        let hermite = |t: f64| {
            let t2 = t * t;
            [
                1.0,
                t,
                t2 - s2,
                t2 * t - 3.0 * s2 * t,
                t2 * t2 - 6.0 * s2 * t2 + 3.0 * s2 * s2,
            ]
        };
        // The monomials' sums `sum h_i(x) h_j(y)`, `i + j <= 4`.
        let mut sums = [[0.0; 5]; 5];
        for (&c, &s) in cos.iter().zip(sin) {
            let (hx, hy) = (hermite((c - mx) / scale), hermite((s - my) / scale));
            for i in 0..5 {
                for j in 0..5 - i {
                    sums[i][j] += hx[i] * hy[j];
                }
            }
        }
        // The row `(xy, y^2, x, y, 1)` by its exponents; the target `-x^2`.
        const ROW: [(usize, usize); 5] = [(1, 1), (0, 2), (1, 0), (0, 1), (0, 0)];
        let normal = Matrix5::from_fn(|a, b| sums[ROW[a].0 + ROW[b].0][ROW[a].1 + ROW[b].1]);
        let rhs = Vector5::from_fn(|a, _| -sums[ROW[a].0 + 2][ROW[a].1]);
        let p = normal
            .lu()
            .solve(&rhs)
            .ok_or(DesignCaptureError::NoEllipse)?;
        let (b, c, d, e, f) = (p[0], p[1], p[2], p[3], p[4]);
        let centre = Matrix2::new(2.0, b, b, 2.0 * c)
            .lu()
            .solve(&Vector2::new(-d, -e))
            .ok_or(DesignCaptureError::NoEllipse)?;
        let (x0, y0) = (centre[0], centre[1]);
        let k = x0 * x0 + b * x0 * y0 + c * y0 * y0 - f;
        // The quadratic form at the centre, `u^T M u = 1` on the ellipse.
        let (m11, m12, m22) = (1.0 / k, 0.5 * b / k, c / k);
        if !(m11 > 0.0 && m22 > 0.0 && m11 * m22 > m12 * m12) {
            return Err(DesignCaptureError::NoEllipse);
        }
        let sin_phi = -m12 / (m11 * m22).sqrt();
        let cos2 = 1.0 - sin_phi * sin_phi;
        Ok(Self {
            offset_cos: mx + scale * x0,
            offset_sin: my + scale * y0,
            amplitude_cos: scale / (m11 * cos2).sqrt(),
            amplitude_sin: scale / (m22 * cos2).sqrt(),
            quadrature_rad: sin_phi.asin(),
        })
    }

    /// The sample's `(cos(theta), sin(theta))` scaled by its radius on the unit circle:
    /// the calibration model undone.
    pub fn normalised(&self, c: f64, s: f64) -> (f64, f64) {
        let u = (c - self.offset_cos) / self.amplitude_cos;
        let v = (s - self.offset_sin) / self.amplitude_sin;
        let (sp, cp) = self.quadrature_rad.sin_cos();
        (u, (v - u * sp) / cp)
    }

    /// The amplitude the relative noise is measured against: the mean of the two.
    pub fn amplitude(&self) -> f64 {
        0.5 * (self.amplitude_cos + self.amplitude_sin)
    }
}
