//! The designs checked across the crates (`docs/theory.md §2, §3, §4, §7`): the core's `f32`
//! designs against the `angletrack` crate's `f64` ones (which are the core's in `f64`) over
//! a grid of settings, and both against ground truth computed here with nalgebra:
//!
//! - the closed-loop poles of the designed discrete loop, the eigenvalues of
//!   `(I - L e1^T) A`, are the continuous poles `s_i` mapped by the discretisation
//!   (`exp(s_i Ts)`, `1 + s_i Ts`, `(1 + s_i Ts / 2) / (1 - s_i Ts / 2)`), within a relative
//!   1e-9 of `z_i - 1` (1e-6 for a double pole);
//! - the Kalman design's covariance solves the discrete algebraic Riccati equation, each
//!   residual entry within 1e-11 of `sqrt(P_ii P_jj)`, and its gains are `P e1 / (r + P11)`
//!   within a relative 1e-13;
//! - the `f32` designs' gains are within a relative 1e-4 of the `f64` designs'.

use angletrack::core::{Gains, Order, SupportedOrder};
use angletrack::{Discretisation, kalman, second_order_from_bandwidth, third_order_from_poles};
use nalgebra::{Complex, DMatrix};

/// Relative agreement of each `f32` gain with the `f64` design's.
const F32_TOLERANCE: f64 = 1e-4;
/// Relative agreement of each discrete pole `z_i - 1` with the mapped continuous pole's.
const POLE_TOLERANCE: f64 = 1e-9;
/// The same for a double pole (critical damping), a Jordan block whose eigenvalues move by
/// the square root of the rounding (about 1e-8 measured).
const DOUBLE_POLE_TOLERANCE: f64 = 1e-6;
/// The Riccati residual, entry by entry, relative to `sqrt(P_ii P_jj)`.
const RICCATI_TOLERANCE: f64 = 1e-11;
/// The Kalman gains against `P e1 / (r + P11)`, relative.
const KALMAN_GAIN_TOLERANCE: f64 = 1e-13;

const BANDWIDTHS_HZ: [f64; 5] = [1.0, 50.0, 200.0, 1e3, 3e3];
const DAMPINGS: [f64; 5] = [0.3, 0.707, 1.0, 2.0, 30.0];
const SAMPLE_PERIODS_S: [f64; 3] = [1e-6, 5e-5, 1e-4];
const POLE_RATIOS: [f64; 4] = [0.5, 1.0, 4.0, 100.0];
const POLE_TIME_CONSTANTS_S: [f64; 3] = [1e-3, 1e-2, 0.3];
const POLE_FREQUENCY_RATIOS: [f64; 3] = [0.3, 1.0, 5.0];
const PROCESS_NOISES: [f64; 5] = [1e-24, 1e-18, 1e-12, 1e-6, 1e-2];
const MEASUREMENT_NOISES: [f64; 4] = [1e-6, 1e-4, 1e-2, 1.0];
const KALMAN_SAMPLE_PERIOD_S: f64 = 50e-6;

/// The largest relative difference between the `f32` gains and the `f64` ones.
fn relative_error<const N: usize>(single: [f32; N], double: [f64; N]) -> f64 {
    (0..N)
        .map(|i| ((f64::from(single[i]) - double[i]) / double[i]).abs())
        .fold(0.0, f64::max)
}

/// The 2nd-order settings of the grid: `(bandwidth_hz, damping, sample_period_s)`.
fn second_order_grid() -> impl Iterator<Item = (f64, f64, f64)> {
    BANDWIDTHS_HZ.into_iter().flat_map(|b| {
        DAMPINGS
            .into_iter()
            .flat_map(move |m| SAMPLE_PERIODS_S.into_iter().map(move |ts| (b, m, ts)))
    })
}

/// The 3rd-order settings of the grid: `(K, T, psi, sample_period_s)`.
fn third_order_grid() -> impl Iterator<Item = (f64, f64, f64, f64)> {
    POLE_RATIOS.into_iter().flat_map(|k| {
        POLE_TIME_CONSTANTS_S.into_iter().flat_map(move |t| {
            POLE_FREQUENCY_RATIOS
                .into_iter()
                .flat_map(move |psi| SAMPLE_PERIODS_S.into_iter().map(move |ts| (k, t, psi, ts)))
        })
    })
}

#[test]
fn f32_second_order_designs_agree_with_f64_designs() {
    let (mut worst, mut designed) = (0.0_f64, 0);
    for (bandwidth, damping, ts) in second_order_grid() {
        let single = Gains::<f32, 2>::second_order_from_bandwidth(
            bandwidth as f32,
            damping as f32,
            ts as f32,
        );
        let Ok(double) =
            second_order_from_bandwidth(bandwidth, damping, ts, Discretisation::PoleMatching)
        else {
            // Too fast for the sample rate in f64: refused in f32 too (no setting of the
            // grid is at the limit).
            assert!(single.is_err(), "{bandwidth} Hz, m = {damping}, Ts = {ts}");
            continue;
        };
        let single = single.unwrap_or_else(|e| panic!("{bandwidth} Hz, m = {damping}: {e}"));
        worst = worst.max(relative_error(single.gains(), double.gains.gains()));
        designed += 1;
    }
    assert!(designed >= 60, "{designed} settings designed");
    assert!(worst < F32_TOLERANCE, "f32: {worst:e}");
    eprintln!("worst f32 gain error {worst:e}");
}

#[test]
fn f32_third_order_designs_agree_with_f64_designs() {
    let (mut worst, mut designed) = (0.0_f64, 0);
    for (k, t, psi, ts) in third_order_grid() {
        let single =
            Gains::<f32, 3>::third_order_from_poles(k as f32, t as f32, psi as f32, ts as f32);
        let Ok(double) = third_order_from_poles(k, t, psi, ts, Discretisation::PoleMatching) else {
            assert!(single.is_err(), "K = {k}, T = {t}, psi = {psi}, Ts = {ts}");
            continue;
        };
        let single = single.unwrap_or_else(|e| panic!("K = {k}, T = {t}, psi = {psi}: {e}"));
        worst = worst.max(relative_error(single.gains(), double.gains.gains()));
        designed += 1;
    }
    assert!(designed >= 90, "{designed} settings designed");
    assert!(worst < F32_TOLERANCE, "f32: {worst:e}");
    eprintln!("worst f32 gain error {worst:e}");
}

#[test]
fn f32_kalman_designs_agree_with_f64_designs() {
    let mut worst = 0.0_f64;
    for q in PROCESS_NOISES {
        for r in MEASUREMENT_NOISES {
            let double = kalman(q, r, KALMAN_SAMPLE_PERIOD_S).unwrap();
            let single =
                Gains::<f32, 3>::kalman(q as f32, r as f32, KALMAN_SAMPLE_PERIOD_S as f32).unwrap();
            worst = worst.max(relative_error(single.gains(), double.gains.gains()));
        }
    }
    assert!(worst < F32_TOLERANCE, "f32: {worst:e}");
    eprintln!("worst f32 gain error {worst:e}");
}

/// `z - 1` for the continuous pole `s` mapped by `discretisation`, written without
/// subtracting 1 from a number close to 1.
fn mapped(s: Complex<f64>, ts: f64, discretisation: Discretisation) -> Complex<f64> {
    let w = s * ts;
    match discretisation {
        // exp(x + j y) - 1 = expm1(x) cos y + (cos y - 1) + j exp(x) sin y.
        Discretisation::PoleMatching => {
            let versine = 2.0 * (0.5 * w.im).sin().powi(2);
            Complex::new(
                w.re.exp_m1() * w.im.cos() - versine,
                w.re.exp() * w.im.sin(),
            )
        }
        Discretisation::ForwardEuler => w,
        // (1 + w/2) / (1 - w/2) - 1 = w / (1 - w/2).
        Discretisation::Tustin => w / (1.0 - 0.5 * w),
    }
}

/// The eigenvalues `z_i - 1` of the discrete loop `(I - L e1^T) A` of the gains, from the
/// matrix `(I - L e1^T) A - I` scaled by `h` and balanced by `diag(1, h, .., h^(N-1))`
/// (`h` the size of the largest `|z_i - 1|`): the unscaled matrix is a small perturbation
/// of a nilpotent one, whose eigenvalues nalgebra would find to the cube root of the
/// rounding only.
fn loop_eigenvalues<const N: usize>(gains: [f64; N], h: f64) -> Vec<Complex<f64>>
where
    Order<N>: SupportedOrder,
{
    // A[i][j] = 1 / (j - i)! above the diagonal.
    let a = |i: usize, j: usize| match j.checked_sub(i) {
        Some(0) | Some(1) => 1.0,
        Some(2) => 0.5,
        _ => 0.0,
    };
    let balanced = DMatrix::from_fn(N, N, |i, j| {
        let identity = if i == j { 1.0 } else { 0.0 };
        // (A - I)[i][j] - l_i A[0][j], without forming 1 - 1 on the diagonal.
        let entry = (a(i, j) - identity) - gains[i] * a(0, j);
        entry * h.powi(j as i32 - i as i32 - 1)
    });
    balanced
        .complex_eigenvalues()
        .iter()
        .map(|&u| u * h)
        .collect()
}

/// The largest distance, relative to the expected one, between each expected `z_i - 1`
/// and the nearest eigenvalue not yet matched.
fn worst_pole_error(mut actual: Vec<Complex<f64>>, expected: &[Complex<f64>]) -> f64 {
    assert_eq!(actual.len(), expected.len());
    let mut worst = 0.0_f64;
    for u in expected {
        let (index, distance) = actual
            .iter()
            .map(|a| (a - u).norm())
            .enumerate()
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        actual.swap_remove(index);
        worst = worst.max(distance / u.norm());
    }
    worst
}

/// The roots of `s^2 + 2 m wn s + wn^2`, the smaller from the product of the roots.
fn quadratic_roots(wn: f64, m: f64) -> [Complex<f64>; 2] {
    let root = Complex::new(m * m - 1.0, 0.0).sqrt() * wn;
    let fast = -(m * wn) - root;
    [fast, wn * wn / fast]
}

#[test]
fn second_order_discrete_poles_are_the_mapped_continuous_poles() {
    let mut worst = 0.0_f64;
    let mut designed = 0;
    for discretisation in Discretisation::ALL {
        for (bandwidth, damping, ts) in second_order_grid() {
            let Ok(design) = second_order_from_bandwidth(bandwidth, damping, ts, discretisation)
            else {
                continue;
            };
            // The -3 dB bandwidth over the natural frequency, sqrt(a + sqrt(a^2 + 1)) with
            // a = 1 + 2 m^2 (`docs/theory.md §2`), written out here.
            let a = 1.0 + 2.0 * damping * damping;
            let wn = 2.0 * std::f64::consts::PI * bandwidth / (a + a.hypot(1.0)).sqrt();
            let expected = quadratic_roots(wn, damping).map(|s| mapped(s, ts, discretisation));
            let h = expected.iter().map(|u| u.norm()).fold(0.0, f64::max);
            let error = worst_pole_error(loop_eigenvalues(design.gains.gains(), h), &expected);
            let tolerance = if damping == 1.0 {
                DOUBLE_POLE_TOLERANCE
            } else {
                POLE_TOLERANCE
            };
            assert!(
                error < tolerance,
                "{discretisation:?}, {bandwidth} Hz, m = {damping}, Ts = {ts}: {error:e}"
            );
            if damping != 1.0 {
                worst = worst.max(error);
            }
            designed += 1;
        }
    }
    assert!(designed >= 150, "{designed} settings designed");
    eprintln!("worst 2nd-order pole error {worst:e}");
}

#[test]
fn third_order_discrete_poles_are_the_mapped_continuous_poles() {
    let mut worst = 0.0_f64;
    let mut designed = 0;
    for discretisation in Discretisation::ALL {
        for (k, t, psi, ts) in third_order_grid() {
            let Ok(design) = third_order_from_poles(k, t, psi, ts, discretisation) else {
                continue;
            };
            let expected = [
                Complex::new(-k / t, 0.0),
                Complex::new(-1.0 / t, psi / t),
                Complex::new(-1.0 / t, -psi / t),
            ]
            .map(|s| mapped(s, ts, discretisation));
            let h = expected.iter().map(|u| u.norm()).fold(0.0, f64::max);
            let error = worst_pole_error(loop_eigenvalues(design.gains.gains(), h), &expected);
            assert!(
                error < POLE_TOLERANCE,
                "{discretisation:?}, K = {k}, T = {t}, psi = {psi}, Ts = {ts}: {error:e}"
            );
            worst = worst.max(error);
            designed += 1;
        }
    }
    assert!(designed >= 250, "{designed} settings designed");
    eprintln!("worst 3rd-order pole error {worst:e}");
}

#[test]
fn kalman_covariance_solves_the_riccati_equation() {
    let a = nalgebra::Matrix3::new(1.0, 1.0, 0.5, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0);
    let g = nalgebra::Vector3::new(1.0 / 6.0, 0.5, 1.0);
    let (mut worst_residual, mut worst_gain) = (0.0_f64, 0.0_f64);
    for q in PROCESS_NOISES {
        for r in MEASUREMENT_NOISES {
            let design = kalman(q, r, KALMAN_SAMPLE_PERIOD_S).unwrap();
            let solution = design.kalman.unwrap();
            let p = nalgebra::Matrix3::from_fn(|i, j| solution.predicted_covariance[i][j]);
            // P = A (P - P e1 e1^T P / (r + P11)) A^T + q g g^T.
            let filtered = p - p.column(0) * p.row(0) / (r + p[(0, 0)]);
            let residual = a * filtered * a.transpose() + g * g.transpose() * q - p;
            for i in 0..3 {
                for j in 0..3 {
                    let scale = (p[(i, i)] * p[(j, j)]).sqrt();
                    worst_residual = worst_residual.max(residual[(i, j)].abs() / scale);
                }
            }
            let l = design.gains.gains();
            for (i, gain) in l.iter().enumerate() {
                let expected = p[(i, 0)] / (r + p[(0, 0)]);
                worst_gain = worst_gain.max((gain / expected - 1.0).abs());
            }
        }
    }
    assert!(
        worst_residual < RICCATI_TOLERANCE,
        "residual {worst_residual:e}"
    );
    assert!(worst_gain < KALMAN_GAIN_TOLERANCE, "gains {worst_gain:e}");
    eprintln!("worst Riccati residual {worst_residual:e}, gains {worst_gain:e}");
}
