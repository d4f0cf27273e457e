//! The linear algebra behind design and analysis (nalgebra, `f64`): polynomial roots and
//! products, the matrices of the discrete loop, the discrete Lyapunov equation (the
//! Riccati equation of the Kalman design is the core's).

use nalgebra::{Complex, DMatrix, DVector};

/// `A[i][j] = 1/(j-i)!` for `j >= i`: the Taylor step of the scaled state of order `n`.
pub(crate) fn transition(n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, n, |i, j| match j.checked_sub(i) {
        Some(0) | Some(1) => 1.0,
        Some(2) => 0.5,
        Some(3) => 1.0 / 6.0,
        _ => 0.0,
    })
}

/// `G`, the effect on the scaled state of one sample of constant `n`-th derivative scaled by
/// `Ts^n`: `g_i = 1/(n-i)!` (`(1/6, 1/2, 1)` at order 3, `(1/2, 1)` at order 2).
pub(crate) fn taylor_remainder(n: usize) -> DVector<f64> {
    DVector::from_fn(n, |i, _| {
        let mut f = 1.0;
        for k in 1..=(n - i) {
            f *= k as f64;
        }
        1.0 / f
    })
}

/// The closed-loop matrix of the filtered estimate, `F = (I - L e1^T) A`.
pub(crate) fn closed_loop(l: &[f64]) -> DMatrix<f64> {
    let n = l.len();
    let correction = DMatrix::identity(n, n) - DVector::from_column_slice(l) * e1(n).transpose();
    correction * transition(n)
}

/// The first component of `x[k+1] = m x[k] + b`, `x[0] = 0`, for `k = 0 .. samples`: the
/// step response of a linear recursion (no allocation per sample).
pub(crate) fn affine_response(
    m: DMatrix<f64>,
    b: Vec<f64>,
    samples: usize,
) -> impl Iterator<Item = f64> {
    let n = b.len();
    let mut x = vec![0.0; n];
    let mut next = vec![0.0; n];
    (0..samples).map(move |_| {
        for (i, value) in next.iter_mut().enumerate() {
            *value = b[i] + (0..n).map(|j| m[(i, j)] * x[j]).sum::<f64>();
        }
        core::mem::swap(&mut x, &mut next);
        x[0]
    })
}

/// The first unit vector of dimension `n`.
pub(crate) fn e1(n: usize) -> DVector<f64> {
    let mut v = DVector::zeros(n);
    v[0] = 1.0;
    v
}

/// The coefficients, lowest first and without the leading 1, of the monic polynomial
/// `prod (x - r_i)` (the roots come in conjugate pairs, so the imaginary parts cancel).
pub(crate) fn monic_from_roots(roots: &[Complex<f64>]) -> Vec<f64> {
    let mut p = vec![Complex::new(1.0, 0.0)];
    for &r in roots {
        let mut next = vec![Complex::new(0.0, 0.0); p.len() + 1];
        for (k, &c) in p.iter().enumerate() {
            next[k + 1] += c;
            next[k] -= c * r;
        }
        p = next;
    }
    p.pop();
    p.into_iter().map(|c| c.re).collect()
}

/// The roots of the monic polynomial `x^n + c[n-1] x^(n-1) + ... + c[0]`.
///
/// The variable is scaled so that the coefficients are of order 1 before the eigenvalues of
/// the companion matrix are taken, and each root is polished by Newton steps: roots of
/// very different sizes (a loop far slower than its sample rate) keep their relative
/// accuracy.
pub(crate) fn roots(c: &[f64]) -> Vec<Complex<f64>> {
    let n = c.len();
    let scale = c
        .iter()
        .enumerate()
        .map(|(k, &ck)| ck.abs().powf(1.0 / (n - k) as f64))
        .fold(0.0_f64, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return vec![Complex::new(0.0, 0.0); n];
    }
    let scaled: Vec<f64> = c
        .iter()
        .enumerate()
        .map(|(k, &ck)| ck / scale.powi((n - k) as i32))
        .collect();
    let companion = DMatrix::from_fn(n, n, |i, j| {
        if i == 0 {
            -scaled[n - 1 - j]
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    let mut r: Vec<Complex<f64>> = companion
        .complex_eigenvalues()
        .iter()
        .map(|&u| u * scale)
        .collect();
    for root in &mut r {
        for _ in 0..3 {
            let (value, slope) = evaluate_monic(c, *root);
            if slope.norm() == 0.0 {
                break;
            }
            let step = value / slope;
            if !(step.norm() < 1e-3 * root.norm().max(f64::MIN_POSITIVE)) {
                break;
            }
            *root -= step;
        }
    }
    // Exact conjugate pairs and real roots, as the coefficients are real.
    for root in &mut r {
        if root.im.abs() <= 1e-12 * root.norm() {
            root.im = 0.0;
        }
    }
    r.sort_by(|a, b| {
        (a.re, a.im)
            .partial_cmp(&(b.re, b.im))
            .unwrap_or(core::cmp::Ordering::Equal)
    });
    r
}

/// The value and derivative of the monic polynomial with coefficients `c` at `x`.
fn evaluate_monic(c: &[f64], x: Complex<f64>) -> (Complex<f64>, Complex<f64>) {
    let mut value = Complex::new(1.0, 0.0);
    let mut slope = Complex::new(0.0, 0.0);
    for &ck in c.iter().rev() {
        slope = slope * x + value;
        value = value * x + ck;
    }
    (value, slope)
}

/// `exp(w) - 1` for complex `w`, accurate when `w` is small.
pub(crate) fn exp_m1(w: Complex<f64>) -> Complex<f64> {
    let half = 0.5 * w.im;
    let sin_half = half.sin();
    Complex::new(
        w.re.exp_m1() * w.im.cos() - 2.0 * sin_half * sin_half,
        w.re.exp() * w.im.sin(),
    )
}

/// `ln(1 + u)` for complex `u`, accurate when `u` is small.
pub(crate) fn ln_1p(u: Complex<f64>) -> Complex<f64> {
    Complex::new(
        0.5 * (2.0 * u.re + u.re * u.re + u.im * u.im).ln_1p(),
        u.im.atan2(1.0 + u.re),
    )
}

/// The steady-state solution `S = F S F^T + Q` of the discrete Lyapunov equation, by the
/// doubling (Smith) iteration `S <- S + F S F^T, F <- F^2`: a sum of positive terms, stable
/// however close to 1 the poles are. `None` if `F` is not stable.
pub(crate) fn discrete_lyapunov(f: &DMatrix<f64>, q: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let mut s = q.clone();
    let mut a = f.clone();
    for _ in 0..80 {
        let next = &s + &a * &s * a.transpose();
        a = &a * &a;
        let done = (&next - &s).norm() <= 1e-16 * next.norm();
        s = next;
        if done || a.norm() < 1e-30 {
            return s.iter().all(|v| v.is_finite()).then_some(s);
        }
    }
    None
}

/// The point where `above` turns from true (at `low`) to false (at `high`), by bisection to
/// a relative `tolerance`.
pub(crate) fn bisect(
    above: impl Fn(f64) -> bool,
    mut low: f64,
    mut high: f64,
    tolerance: f64,
) -> f64 {
    while high - low > tolerance * high {
        let mid = 0.5 * (low + high);
        if above(mid) {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_and_products_round_trip() {
        let roots = [
            Complex::new(-3e-7, 0.0),
            Complex::new(-1e-3, 2e-3),
            Complex::new(-1e-3, -2e-3),
        ];
        let c = monic_from_roots(&roots);
        let back = super::roots(&c);
        for r in &roots {
            let nearest = back
                .iter()
                .map(|b| (b - r).norm() / r.norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-10, "{r}: {nearest}");
        }
    }
}
