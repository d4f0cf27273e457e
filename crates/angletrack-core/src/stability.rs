//! The characteristic polynomial of the discrete loop `(I - L e1^T) A` as a function of the
//! gains, its inverse (the gains that give a chosen polynomial), and the check that every
//! pole lies inside the unit circle: `docs/theory.md §6`.

/// Defines, for the float type `$t`, the `const fn`s of this module's mathematics (one
/// implementation for both types: constant evaluation cannot call trait methods, so the
/// generic functions below reach these through [`Float`](crate::Float)'s hidden methods).
macro_rules! stability_fns {
    ($t:ident) => {
        use $crate::error::{ConfigError, Parameter};

        /// `(A x)` for the Taylor step `A` (`identity`), or `(A - I) x` (not): the
        /// `const` twin of `state::predict`, which is on the per-sample path and stays
        /// generic so that it inlines there. `(A - I) x` is summed directly, with no
        /// cancellation against `x` when its terms are far smaller.
        const fn taylor_step<const N: usize>(x: &[$t; N], identity: bool) -> [$t; N] {
            let mut p = if identity { *x } else { [0.0; N] };
            let mut i = 0;
            while i < N {
                let mut j = i + 1;
                while j < N {
                    p[i] += if j - i == 1 { x[j] } else { x[j] * 0.5 };
                    j += 1;
                }
                i += 1;
            }
            p
        }

        /// `(A L)[0]`: how much one phase error moves the next predicted angle.
        pub(crate) const fn next_angle_gain<const N: usize>(l: &[$t; N]) -> $t {
            taylor_step(l, true)[0]
        }

        /// See [`characteristic_polynomial_in_s`](super::characteristic_polynomial_in_s).
        pub(crate) const fn characteristic_polynomial_in_s<const N: usize>(l: &[$t; N]) -> [$t; N] {
            let mut v = taylor_step(l, true);
            let mut c = [0.0; N];
            let mut k = 0;
            while k < N {
                c[N - 1 - k] = v[0];
                v = taylor_step(&v, false);
                k += 1;
            }
            c
        }

        /// See [`gains_of_loop_polynomial`](super::gains_of_loop_polynomial).
        pub(crate) const fn gains_of_loop_polynomial<const N: usize>(c: &[$t; N]) -> [$t; N] {
            let mut columns = [[0.0; N]; N];
            let mut j = 0;
            while j < N {
                let mut unit = [0.0; N];
                unit[j] = 1.0;
                columns[j] = characteristic_polynomial_in_s(&unit);
                j += 1;
            }
            let mut l = [0.0; N];
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
        pub(crate) const fn check_stability<const N: usize>(l: &[$t; N]) -> Result<(), ConfigError>
        where
            $crate::stability::Order<N>: $crate::stability::SupportedOrder,
        {
            let c = characteristic_polynomial_in_s(l);
            // w-polynomial: sum_k c_k (2w)^k (1-w)^(N-k), with c_N = 1; coefficients in w.
            let mut w: [$t; 4] = [0.0; 4];
            let mut k = 0;
            while k <= N {
                let ck = if k == N { 1.0 } else { c[k] };
                // (2w)^k (1-w)^(N-k) = 2^k sum_j binom(N-k, j) (-1)^j w^(k+j)
                let mut scale = ck;
                let mut p = 0;
                while p < k {
                    scale *= 2.0;
                    p += 1;
                }
                let m = N - k;
                let mut binom: $t = 1.0;
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
                    // m - j, j + 1 <= 3: exact in both types.
                    binom = binom * ((m - j) as $t) / ((j + 1) as $t);
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
            let mut i = 0;
            while i < conditions.len() {
                if !(w[i] > 0.0) {
                    return Err(ConfigError::Unstable {
                        parameter: conditions[i].0,
                        condition: conditions[i].1,
                    });
                }
                i += 1;
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
    };
}

/// The `f32` functions.
pub(crate) mod for_f32 {
    stability_fns!(f32);
}

/// The `f64` functions.
pub(crate) mod for_f64 {
    stability_fns!(f64);
}

/// The orders the recursion supports: 2 (type II loop) and 3 (type III loop).
///
/// Implemented for [`Order<2>`] and [`Order<3>`] only. It bounds the constructors of
/// [`Gains`](crate::Gains), the only place where the order's mathematics (the stability conditions) is
/// specific to 2 and 3: an observer of any other order cannot be made, and the update,
/// written for any `N`, needs no bound.
pub trait SupportedOrder: sealed::Sealed {}

/// Marker for the observer order `N` (the number of states: angle, speed, acceleration).
#[derive(Debug, Clone, Copy)]
pub struct Order<const N: usize>;

impl SupportedOrder for Order<2> {}
impl SupportedOrder for Order<3> {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Order<2> {}
    impl Sealed for super::Order<3> {}
}

#[cfg(test)]
mod tests;
