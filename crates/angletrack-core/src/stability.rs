//! The characteristic polynomial of the discrete loop `(I - L e1^T) A` as a function of the
//! gains, its inverse (the gains that give a chosen polynomial), and the check that every
//! pole lies inside the unit circle: `docs/theory.md §6`.

use crate::error::{ConfigError, Parameter};
use crate::gains::{Order, SupportedOrder};
use crate::real::Real;
use crate::state::predict;

/// Coefficients `c[k]` of the closed-loop characteristic polynomial in `s = z - 1`,
/// `s^N + c[N-1] s^(N-1) + ... + c[0]`, for gains `l`.
///
/// With `D = A - I` (nilpotent) and the rank-one correction, `det(s I - D + A L e1^T)`
/// `= s^N + sum_k s^(N-1-k) e1^T D^k A L`; the coefficients are linear in the gains.
pub(crate) fn characteristic_polynomial_in_s<T: Real, const N: usize>(l: &[T; N]) -> [T; N] {
    let mut v = predict(l);
    let mut c = [T::ZERO; N];
    let mut k = 0;
    while k < N {
        c[N - 1 - k] = v[0];
        let next = predict(&v);
        let mut i = 0;
        while i < N {
            v[i] = next[i] - v[i];
            i += 1;
        }
        k += 1;
    }
    c
}

/// The gains whose loop has the characteristic polynomial `c` (in `s = z - 1`, as
/// [`characteristic_polynomial_in_s`] gives it). The map from gains to coefficients is linear
/// and triangular: `c[N-1-k]` depends on `l[k..N]` only, with a unit coefficient on `l[k]`,
/// so back substitution solves it.
pub(crate) fn gains_of_loop_polynomial<T: Real, const N: usize>(c: &[T; N]) -> [T; N] {
    let mut columns = [[T::ZERO; N]; N];
    let mut j = 0;
    while j < N {
        let mut unit = [T::ZERO; N];
        unit[j] = T::ONE;
        columns[j] = characteristic_polynomial_in_s(&unit);
        j += 1;
    }
    let mut l = [T::ZERO; N];
    let mut k = N;
    while k > 0 {
        k -= 1;
        let mut rest = c[N - 1 - k];
        let mut j = k + 1;
        while j < N {
            rest -= columns[j][N - 1 - k] * l[j];
            j += 1;
        }
        l[k] = rest / columns[k][N - 1 - k];
    }
    l
}

/// Checks that every pole of the discrete loop is strictly inside the unit circle.
///
/// The bilinear map `z = (1 + w) / (1 - w)` (so `s = 2 w / (1 - w)`) sends the unit disc to
/// the left half plane; the Routh-Hurwitz (Lienard-Chipart) conditions on the mapped
/// polynomial are then polynomial in the gains, with no cancellation for small gains
/// (high sample rates), so they hold in `f32` as well as in `f64`:
///
/// * order 2: `l1 > 0`, `l2 > 0`, `2 l1 + l2 < 4`;
/// * order 3: `l3 > 0`, `l2 > 0`, `4 l1 > l3`, `4 l1 + 2 l2 < 8`,
///   `2 l2 (4 l1 - l3) > l3 (8 - 4 l1 - 2 l2)`.
///
/// The conditions are those of orders 2 and 3, hence the bound.
pub(crate) fn check_stability<T: Real, const N: usize>(l: &[T; N]) -> Result<(), ConfigError>
where
    Order<N>: SupportedOrder,
{
    let c = characteristic_polynomial_in_s(l);
    // w-polynomial: sum_k c_k (2w)^k (1-w)^(N-k), with c_N = 1; coefficients in w.
    let mut w = [T::ZERO; 4];
    let mut k = 0;
    while k <= N {
        let ck = if k == N { T::ONE } else { c[k] };
        // (2w)^k (1-w)^(N-k) = 2^k sum_j binom(N-k, j) (-1)^j w^(k+j)
        let mut scale = ck;
        let mut p = 0;
        while p < k {
            scale *= T::TWO;
            p += 1;
        }
        let m = N - k;
        let mut binom = T::ONE;
        let mut j = 0;
        while j <= m {
            let term = if j % 2 == 0 {
                scale * binom
            } else {
                -(scale * binom)
            };
            if k + j < 4 {
                w[k + j] += term;
            }
            binom = binom * from_usize::<T>(m - j) / from_usize::<T>(j + 1);
            j += 1;
        }
        k += 1;
    }
    let conditions: &[(Parameter, &str)] = if N == 2 {
        &[
            (Parameter::SpeedGain, "l2 > 0"),
            (Parameter::AngleGain, "l1 > 0"),
            (Parameter::AngleGain, "2 l1 + l2 < 4"),
        ]
    } else {
        &[
            (Parameter::AccelerationGain, "l3 > 0"),
            (Parameter::SpeedGain, "l2 > 0"),
            (Parameter::AngleGain, "4 l1 > l3"),
            (Parameter::AngleGain, "4 l1 + 2 l2 < 8"),
        ]
    };
    // All coefficients of the w-polynomial positive (w[0] .. w[N]).
    for (i, (parameter, condition)) in conditions.iter().enumerate() {
        if !(w[i] > T::ZERO) {
            return Err(ConfigError::Unstable {
                parameter: *parameter,
                condition,
            });
        }
    }
    // Cubic: the Hurwitz determinant w2 w1 - w3 w0 > 0.
    if N == 3 && !(w[2] * w[1] > w[3] * w[0]) {
        return Err(ConfigError::Unstable {
            parameter: Parameter::AccelerationGain,
            condition: "2 l2 (4 l1 - l3) > l3 (8 - 4 l1 - 2 l2)",
        });
    }
    Ok(())
}

#[inline(always)]
fn from_usize<T: Real>(n: usize) -> T {
    // n <= 3 here: exact in both types.
    T::from_f32(n as u8 as f32)
}

#[cfg(test)]
mod tests;
