//! The Lissajous ellipse of a capture, fitted by least squares chunk by chunk: the sensor's
//! offsets, amplitudes and quadrature from the signals' geometry alone (`docs/theory.md
//! §12`), which neither the speed nor an angle-synchronous speed ripple changes.
//!
//! The conic `A x^2 + B xy + C y^2 + D x + E y + F = 0` with `A + C = 1` (every ellipse can
//! be scaled to it) is linear in `(A - C, B, D, E, F)`: the fit solves the normal equations
//! of `-(x^2 + y^2)/2 = u (x^2 - y^2)/2 + B xy + D x + E y + F`, `u = A - C`, built from the
//! 6x6 scatter matrix of `(x^2, xy, y^2, x, y, 1)`, summed over the samples in constant
//! memory. `x`, `y` are the samples shifted by the first chunk's midrange and divided by its
//! half-range, so that the sums are well conditioned in any unit and on any bias.

use angletrack_core::SensorCalibration;
use nalgebra::{Matrix2, Matrix5, SMatrix, Vector2, Vector5};

/// The scatter matrix of the conic fit, summed over chunks.
#[derive(Debug, Clone)]
pub(crate) struct EllipseMoments {
    scatter: SMatrix<f64, 6, 6>,
    count: u64,
    /// The shift (the first chunk's midrange) and scale (its half-range) of the samples.
    frame: Option<(f64, f64, f64)>,
}

impl EllipseMoments {
    pub(crate) fn new() -> Self {
        Self {
            scatter: SMatrix::zeros(),
            count: 0,
            frame: None,
        }
    }

    /// The first chunk's midrange of each channel and its larger half-range (`None` for a
    /// chunk without a finite sample).
    fn frame_of(y_c: &[f64], y_s: &[f64]) -> Option<(f64, f64, f64)> {
        let range = |y: &[f64]| {
            y.iter()
                .filter(|v| v.is_finite())
                .fold(None, |acc: Option<(f64, f64)>, &v| {
                    Some(acc.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
                })
        };
        let ((c_lo, c_hi), (s_lo, s_hi)) = (range(y_c)?, range(y_s)?);
        let half = 0.5 * (c_hi - c_lo).max(s_hi - s_lo);
        Some((
            0.5 * (c_lo + c_hi),
            0.5 * (s_lo + s_hi),
            if half > 0.0 { half } else { 1.0 },
        ))
    }

    /// The centre the first chunk gave (the midrange of each channel), once a chunk came.
    pub(crate) fn rough_centre(&self) -> Option<(f64, f64)> {
        self.frame.map(|(c, s, _)| (c, s))
    }

    /// Adds the finite samples of a chunk.
    pub(crate) fn add(&mut self, y_c: &[f64], y_s: &[f64]) {
        if self.frame.is_none() {
            self.frame = Self::frame_of(y_c, y_s);
        }
        let Some((shift_c, shift_s, scale)) = self.frame else {
            return;
        };
        for (&c, &s) in y_c.iter().zip(y_s) {
            if !(c.is_finite() && s.is_finite()) {
                continue;
            }
            let (x, y) = ((c - shift_c) / scale, (s - shift_s) / scale);
            let d = [x * x, x * y, y * y, x, y, 1.0];
            for i in 0..6 {
                for j in i..6 {
                    self.scatter[(i, j)] += d[i] * d[j];
                }
            }
            self.count += 1;
        }
    }

    /// The sensor calibration of the fitted ellipse, `None` when the samples fit none (fewer
    /// than 6, on a line or a point, or a quadrature beyond the core's limit).
    pub(crate) fn fit(&self) -> Option<SensorCalibration<f64>> {
        let (shift_c, shift_s, scale) = self.frame?;
        if self.count < 6 {
            return None;
        }
        let s = SMatrix::<f64, 6, 6>::from_fn(|i, j| self.scatter[(i.min(j), i.max(j))]);
        // Regressors r = M d, target t = m . d, d = (x^2, xy, y^2, x, y, 1).
        let m_rows = SMatrix::<f64, 5, 6>::from_row_slice(&[
            0.5, 0.0, -0.5, 0.0, 0.0, 0.0, //
            0.0, 1.0, 0.0, 0.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, 1.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        let target = SMatrix::<f64, 6, 1>::from_column_slice(&[-0.5, 0.0, -0.5, 0.0, 0.0, 0.0]);
        let normal: Matrix5<f64> = m_rows * s * m_rows.transpose();
        let rhs: Vector5<f64> = m_rows * s * target;
        let p = normal.cholesky()?.solve(&rhs);
        let (a, b, c) = (0.5 * (1.0 + p[0]), p[1], 0.5 * (1.0 - p[0]));
        let (d, e, f) = (p[2], p[3], p[4]);
        let centre = Matrix2::new(2.0 * a, b, b, 2.0 * c)
            .lu()
            .solve(&Vector2::new(-d, -e))?;
        let (u0, v0) = (centre[0], centre[1]);
        let centre_value = a * u0 * u0 + b * u0 * v0 + c * v0 * v0 + d * u0 + e * v0 + f;
        if centre_value == 0.0 || !centre_value.is_finite() {
            return None;
        }
        // Centred, the model's ellipse is u^2/A_c^2 - 2 sin(q) u v/(A_c A_s) + v^2/A_s^2 = cos(q)^2.
        let (alpha, beta, gamma) = (-a / centre_value, -b / centre_value, -c / centre_value);
        if !(alpha > 0.0 && gamma > 0.0) {
            return None;
        }
        let sin_q = -beta / (2.0 * (alpha * gamma).sqrt());
        if !(sin_q.abs() < 1.0) {
            return None;
        }
        let q = sin_q.asin();
        let cos_q = q.cos();
        SensorCalibration::new(
            shift_c + scale * u0,
            shift_s + scale * v0,
            scale / (cos_q * alpha.sqrt()),
            scale / (cos_q * gamma.sqrt()),
            q,
        )
        .ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of `y_c = o_c + A_c cos t`, `y_s = o_s + A_s sin(t + q)`, with an angle error
    /// of a few mrad (which moves the points along the ellipse, not off it).
    fn ellipse(o_c: f64, o_s: f64, a_c: f64, a_s: f64, q: f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..5000)
            .map(|k| 0.013 * k as f64 + 5e-3 * (0.039 * k as f64).sin())
            .collect();
        (
            t.iter().map(|t| o_c + a_c * t.cos()).collect(),
            t.iter().map(|t| o_s + a_s * (t + q).sin()).collect(),
        )
    }

    #[test]
    fn volts_on_a_bias_counts_off_mid_scale_and_large_offsets_are_fitted() {
        for (o_c, o_s, a_c, a_s, q) in [
            (2.5, 2.5, 1.0, 1.1, 0.05),
            (3100.0, 3050.0, 900.0, 870.0, -0.03),
            (0.2, -0.2, 1.0, 0.9, 0.0524),
        ] {
            let (y_c, y_s) = ellipse(o_c, o_s, a_c, a_s, q);
            let mut moments = EllipseMoments::new();
            // Three chunks: the first sets the frame.
            for (c, s) in y_c.chunks(1700).zip(y_s.chunks(1700)) {
                moments.add(c, s);
            }
            let (fo_c, fo_s, fa_c, fa_s, fq) = moments.fit().unwrap().parameters();
            let tolerance = 1e-9 * a_c.max(o_c.abs());
            assert!((fo_c - o_c).abs() < tolerance && (fo_s - o_s).abs() < tolerance);
            assert!((fa_c - a_c).abs() < tolerance && (fa_s - a_s).abs() < tolerance);
            assert!((fq - q).abs() < 1e-9, "{fq} {q}");
        }
    }

    #[test]
    fn a_line_or_a_point_fits_no_ellipse() {
        let mut line = EllipseMoments::new();
        let x: Vec<f64> = (0..100).map(f64::from).collect();
        line.add(&x, &x);
        assert!(line.fit().is_none());
        let mut point = EllipseMoments::new();
        point.add(&[1.0; 50], &[2.0; 50]);
        assert!(point.fit().is_none());
        assert!(EllipseMoments::new().fit().is_none());
    }
}
