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
    /// samples (centred and scaled for the normal equations' conditioning).
    pub fn fit(cos: &[f64], sin: &[f64]) -> Result<Self, DesignCaptureError> {
        let n = cos.len() as f64;
        let (mx, my) = (cos.iter().sum::<f64>() / n, sin.iter().sum::<f64>() / n);
        let scale = (cos.iter().map(|x| (x - mx).powi(2)).sum::<f64>() / n).sqrt();
        if !(scale > 0.0) {
            return Err(DesignCaptureError::NoEllipse);
        }
        let mut normal = Matrix5::zeros();
        let mut rhs = Vector5::zeros();
        for (&c, &s) in cos.iter().zip(sin) {
            let (x, y) = ((c - mx) / scale, (s - my) / scale);
            let row = Vector5::new(x * y, y * y, x, y, 1.0);
            normal += row * row.transpose();
            rhs -= row * (x * x);
        }
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
