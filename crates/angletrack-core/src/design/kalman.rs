//! The time-invariant Kalman ATO on the target (`docs/theory.md §4`): the steady-state
//! gain of the Kalman filter of the scaled triple integrator, from the discrete algebraic
//! Riccati equation (DARE) solved in the observer's float type.

use crate::const_config::Real;
use crate::error::{ConfigError, Parameter};
use crate::gains::Gains;
use crate::real::check_positive;
use crate::real::sincos::SinCos;

/// A 3 x 3 matrix, rows first.
type Matrix<T> = [[T; 3]; 3];

/// At most this many doubling steps: step `k` accounts for `2^k` samples, and once the
/// closed loop's `2^k`-th power underflows to zero the solution stops changing exactly.
const MAX_DOUBLING_STEPS: usize = 100;

impl<T: Real, S: SinCos<T>> Gains<T, 3, S> {
    /// The time-invariant Kalman ATO (`docs/theory.md §4`): the steady-state gain of the
    /// Kalman filter of the scaled triple integrator `x[k+1] = A x[k] + g w[k]`,
    /// `g = (1/6, 1/2, 1)`, measured by the phase detector `y = x1 + v`, with scaled
    /// process noise `process_noise_q = var(w)` (a jerk `j` in rad/s^3 gives
    /// `q = (j Ts^3)^2`) and measurement noise `measurement_noise_r = var(v)` (the
    /// normalised phase error's: `(noise / amplitude)^2`), at the sample period
    /// `sample_period_s` (s): the `angletrack` crate's `kalman`, computed in `T`.
    ///
    /// Refuses a non-positive or non-finite argument and a ratio `q / r` outside
    /// [1e-30, 1e6] (named `process_noise_q`).
    ///
    /// ```
    /// use angletrack_core::{Gains, Parameter};
    /// let gains = Gains::<f32, 3>::kalman(1e-12, 1e-4, 50e-6)?;
    /// let [l1, l2, l3] = gains.gains();
    /// assert!(l1 > l2 && l2 > l3 && l3 > 0.0);
    /// let err = Gains::<f32, 3>::kalman(1.0, 1e-7, 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::ProcessNoise);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn kalman(
        process_noise_q: T,
        measurement_noise_r: T,
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        Self::kalman_with_covariance(process_noise_q, measurement_noise_r, sample_period_s)
            .map(|(gains, _)| gains)
    }

    /// [`Gains::kalman`] with the a-priori (predicted) error covariance `P` of the
    /// steady-state filter it solves for, on the scaled state `(theta, Ts Omega, Ts^2 alpha)`
    /// (rows first): `P = A (P - P e1 e1^T P / (P11 + r)) A^T + q g g^T`, and the gains are
    /// `P e1 / (P11 + r)`. The `angletrack` crate reports it with the design.
    ///
    /// ```
    /// use angletrack_core::Gains;
    /// let (gains, p) = Gains::<f64, 3>::kalman_with_covariance(1e-12, 1e-4, 50e-6)?;
    /// let l1 = gains.gains()[0];
    /// assert!((l1 - p[0][0] / (p[0][0] + 1e-4)).abs() < 1e-15);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn kalman_with_covariance(
        process_noise_q: T,
        measurement_noise_r: T,
        sample_period_s: T,
    ) -> Result<(Self, [[T; 3]; 3]), ConfigError> {
        let q = check_positive(process_noise_q, Parameter::ProcessNoise)?;
        let r = check_positive(measurement_noise_r, Parameter::MeasurementNoise)?;
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        let ratio = q / r;
        // `from_f64` (folded to a constant) keeps the bound exact in `f64`: the nearest `f32`
        // to 1e-30 lies above it.
        if !(ratio >= T::from_f64(1e-30) && ratio <= T::from_f32(1e6)) {
            return Err(ConfigError::OutOfRange(Parameter::ProcessNoise));
        }
        // Solved for r = 1 (well scaled): the gain depends on q / r only.
        let p =
            predicted_covariance(ratio).ok_or(ConfigError::OutOfRange(Parameter::ProcessNoise))?;
        let denominator = T::ONE + p[0][0];
        let gains = Self::new(
            [
                p[0][0] / denominator,
                p[1][0] / denominator,
                p[2][0] / denominator,
            ],
            ts,
        )?;
        Ok((gains, p.map(|row| row.map(|v| v * r))))
    }
}

/// The a-priori covariance `P = A (P - P e1 e1^T P / (P11 + 1)) A^T + ratio g g^T` of the
/// steady-state filter (`docs/theory.md §4`), by the structure-preserving doubling
/// algorithm on the dual (control) form, as the `angletrack` crate solves it: quadratic
/// convergence, and no step that loses precision for slow loops. `None` if it does not
/// converge or overflows.
fn predicted_covariance<T: Real>(ratio: T) -> Option<Matrix<T>> {
    let f = T::from_f32;
    let g = [f(1.0) / f(6.0), T::HALF, T::ONE];
    let a = [
        [T::ONE, T::ONE, T::HALF],
        [T::ZERO, T::ONE, T::ONE],
        [T::ZERO, T::ZERO, T::ONE],
    ];
    let mut ak = transpose(&a);
    let mut gk = [[T::ZERO; 3]; 3];
    gk[0][0] = T::ONE;
    let mut hk = [[T::ZERO; 3]; 3];
    for (i, row) in hk.iter_mut().enumerate() {
        for (j, h) in row.iter_mut().enumerate() {
            *h = ratio * g[i] * g[j];
        }
    }
    for _ in 0..MAX_DOUBLING_STEPS {
        let mut i_plus_gh = mul(&gk, &hk);
        for (i, row) in i_plus_gh.iter_mut().enumerate() {
            row[i] += T::ONE;
        }
        let w = inverse(&i_plus_gh)?;
        let akt = transpose(&ak);
        let a_w = mul(&ak, &w);
        let a_next = mul(&a_w, &ak);
        let g_next = add(&gk, &mul(&mul(&a_w, &gk), &akt));
        let h_next = add(&hk, &mul(&mul(&mul(&akt, &hk), &w), &ak));
        // Converged when no entry moves by more than 4 ulps of itself (entry by entry: the
        // entries span many decades for slow loops, and a norm would hide the small ones),
        // which at the latest happens once the loop's power has underflowed to zero.
        let tolerance = T::from_f32(4.0) * T::EPSILON;
        let converged = h_next
            .iter()
            .flatten()
            .zip(hk.iter().flatten())
            .all(|(&next, &h)| (next - h).abs() <= tolerance * next.abs());
        ak = a_next;
        gk = g_next;
        hk = h_next;
        if !hk.iter().flatten().all(|h| h.is_finite()) {
            return None;
        }
        if converged {
            return Some(add(&hk, &transpose(&hk)).map(|row| row.map(|v| v * T::HALF)));
        }
    }
    None
}

fn mul<T: Real>(x: &Matrix<T>, y: &Matrix<T>) -> Matrix<T> {
    core::array::from_fn(|i| {
        core::array::from_fn(|j| x[i][0] * y[0][j] + x[i][1] * y[1][j] + x[i][2] * y[2][j])
    })
}

fn add<T: Real>(x: &Matrix<T>, y: &Matrix<T>) -> Matrix<T> {
    core::array::from_fn(|i| core::array::from_fn(|j| x[i][j] + y[i][j]))
}

fn transpose<T: Real>(x: &Matrix<T>) -> Matrix<T> {
    core::array::from_fn(|i| core::array::from_fn(|j| x[j][i]))
}

/// The inverse by cofactors (`None` if singular or not finite).
fn inverse<T: Real>(x: &Matrix<T>) -> Option<Matrix<T>> {
    let cofactor = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        x[r0][c0] * x[r1][c1] - x[r0][c1] * x[r1][c0]
    };
    let determinant =
        x[0][0] * cofactor(0, 0) + x[0][1] * cofactor(0, 1) + x[0][2] * cofactor(0, 2);
    if !(determinant.abs() > T::ZERO && determinant.is_finite()) {
        return None;
    }
    // The inverse is the transposed cofactor matrix over the determinant.
    Some(core::array::from_fn(|i| {
        core::array::from_fn(|j| cofactor(j, i) / determinant)
    }))
}
