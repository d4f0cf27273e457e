//! Unit and property tests of the core: tracking accuracy, turn counting, stability check,
//! float types, sin/cos accuracy.

extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use crate::gains::characteristic_polynomial_in_s;
use crate::*;

/// Under Miri (about 10^5 times slower) the tests run the same loops at a 10 times
/// longer sample period, so that 10 times fewer samples cover the same transients.
pub(crate) const MIRI_SPEEDUP: usize = if cfg!(miri) { 10 } else { 1 };
pub(crate) const TS: f64 = 1e-4 * MIRI_SPEEDUP as f64; // 10 kHz

/// A sample count, shortened under Miri.
pub(crate) const fn n(samples: usize) -> usize {
    samples / MIRI_SPEEDUP
}

/// Discrete loop polynomial (in s = z - 1) of pole matching `z = exp(s Ts)` for real poles
/// and complex pairs `(re, im)` given in rad/s.
fn matched_loop_polynomial(real: &[f64], pairs: &[(f64, f64)], ts: f64) -> Vec<f64> {
    // Polynomial coefficients, lowest first, leading 1.
    let mut poly = std::vec![1.0];
    let mul = |poly: &Vec<f64>, factor: &[f64]| {
        let mut out = std::vec![0.0; poly.len() + factor.len() - 1];
        for (i, a) in poly.iter().enumerate() {
            for (j, b) in factor.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    };
    for &p in real {
        let zm1 = (p * ts).exp_m1();
        poly = mul(&poly, &[-zm1, 1.0]);
    }
    for &(re, im) in pairs {
        let (sin, cos) = (im * ts).sin_cos();
        let half = (im * ts / 2.0).sin();
        let real_part = (re * ts).exp_m1() * cos - 2.0 * half * half;
        let imag_part = (re * ts).exp() * sin;
        poly = mul(
            &poly,
            &[
                real_part * real_part + imag_part * imag_part,
                -2.0 * real_part,
                1.0,
            ],
        );
    }
    poly.pop(); // leading 1
    poly
}

/// 2nd-order gains: continuous poles of s^2 + 2 m w s + w^2.
fn second_order(w: f64, m: f64) -> [f64; 2] {
    let c = if m < 1.0 {
        matched_loop_polynomial(&[], &[(-m * w, w * (1.0 - m * m).sqrt())], TS)
    } else {
        let d = w * (m * m - 1.0).sqrt();
        matched_loop_polynomial(&[-m * w + d, -m * w - d], &[], TS)
    };
    Gains::<f64, 2>::from_loop_polynomial([c[0], c[1]], TS)
        .unwrap()
        .gains()
}

/// 3rd-order pole placement: poles -K/T and (-1 +- j psi)/T.
fn third_order(k: f64, t: f64, psi: f64) -> [f64; 3] {
    let c = matched_loop_polynomial(&[-k / t], &[(-1.0 / t, psi / t)], TS);
    Gains::<f64, 3>::from_loop_polynomial([c[0], c[1], c[2]], TS)
        .unwrap()
        .gains()
}

/// Steady-state Kalman gain of the triple integrator (scaled state) for q/r, by iterating the
/// Riccati recursion (the design crate solves the DARE; this is an independent check).
pub(crate) fn kalman(q_over_r: f64) -> [f64; 3] {
    let a = [[1.0, 1.0, 0.5], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]];
    let g = [1.0 / 6.0, 0.5, 1.0];
    let mut p = [[0.0; 3]; 3];
    let mut k = [0.0; 3];
    for _ in 0..n(20_000) {
        // P_p = A P A^T + q G G^T
        let mut ap = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                ap[i][j] = (0..3).map(|m| a[i][m] * p[m][j]).sum();
            }
        }
        let mut pp = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                pp[i][j] = (0..3).map(|m| ap[i][m] * a[j][m]).sum::<f64>() + q_over_r * g[i] * g[j];
            }
        }
        for i in 0..3 {
            k[i] = pp[i][0] / (pp[0][0] + 1.0);
        }
        for i in 0..3 {
            for j in 0..3 {
                p[i][j] = pp[i][j] - k[i] * pp[0][j];
            }
        }
    }
    k
}

/// Runs an observer on a noise-free resolver following `theta(t)` (rad) and returns the
/// errors (angle wrapped, speed) of every sample with the truth.
fn run<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<T, N, S>,
    samples: usize,
    theta: impl Fn(f64) -> (f64, f64),
) -> Vec<(f64, f64)>
where
    Order<N>: SupportedOrder,
{
    let mut state = ObserverState::at(
        T::from_f64(theta(0.0).0),
        T::from_f64(theta(0.0).1),
        T::ZERO,
        gains.sample_period(),
    );
    (1..samples)
        .map(|k| {
            let t = k as f64 * TS;
            let (angle, speed) = theta(t);
            let e = gains.update(
                &mut state,
                T::from_f64(angle.cos()),
                T::from_f64(angle.sin()),
            );
            (wrap(angle - e.position()), speed - e.speed.to_f64())
        })
        .collect()
}

pub(crate) fn wrap(a: f64) -> f64 {
    (a + core::f64::consts::PI).rem_euclid(core::f64::consts::TAU) - core::f64::consts::PI
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n as f64
}

/// The three observers of the tests (computed once: Miri is slow at it).
pub(crate) fn designs() -> (Gains<f64, 2>, Gains<f64, 3>, Gains<f64, 3>) {
    static DESIGNS: std::sync::OnceLock<(Gains<f64, 2>, Gains<f64, 3>, Gains<f64, 3>)> =
        std::sync::OnceLock::new();
    *DESIGNS.get_or_init(|| {
        let w = 2.0 * core::f64::consts::PI * 50.0; // 50 Hz natural frequency
        (
            Gains::new(second_order(w, 1.0), TS).unwrap(),
            Gains::new(
                third_order(39.04, 39.04 / (3.0 * w), 1.5 * core::f64::consts::PI),
                TS,
            )
            .unwrap(),
            Gains::new(kalman(1e-9 * (MIRI_SPEEDUP as f64).powi(6)), TS).unwrap(),
        )
    })
}

#[test]
fn constant_speed_gives_zero_mean_error_for_all_three_observers() {
    let (o2, o3, ok) = designs();
    let omega = 2.0 * core::f64::consts::PI * 37.0; // 37 rev/s, starts 0.3 rad off
    let theta = |t: f64| (0.3 + omega * t, omega);
    let check = |errors: Vec<(f64, f64)>, name: &str| {
        let tail = &errors[errors.len() / 2..];
        let mean_angle = mean(tail.iter().map(|e| e.0));
        let max_speed = tail.iter().map(|e| e.1.abs()).fold(0.0, f64::max);
        assert!(
            mean_angle.abs() < 1e-9,
            "{name}: mean angle error {mean_angle}"
        );
        assert!(max_speed < 1e-5, "{name}: speed error {max_speed}");
    };
    check(run(&o2, n(40_000), theta), "2nd order");
    check(run(&o3, n(40_000), theta), "3rd order");
    check(run(&ok, n(40_000), theta), "Kalman");
}

#[test]
fn constant_acceleration_biases_only_the_second_order() {
    let (o2, o3, ok) = designs();
    let alpha = 500.0; // rad/s^2
    let theta = |t: f64| (0.5 * alpha * t * t, alpha * t);
    let n = n(40_000);
    let tail = |errors: Vec<(f64, f64)>| mean(errors[n * 3 / 4..].iter().map(|e| e.0));
    // Discrete acceleration constant Ka = l2 / ((1 - l1) Ts^2): the bias is alpha / Ka.
    let [l1, l2] = o2.gains();
    let ka = l2 / ((1.0 - l1) * TS * TS);
    let bias = tail(run(&o2, n, theta));
    assert!(
        (bias / (alpha / ka) - 1.0).abs() < 0.01,
        "bias {bias} vs alpha/Ka {}",
        alpha / ka
    );
    assert!(tail(run(&o3, n, theta)).abs() < 1e-9);
    assert!(tail(run(&ok, n, theta)).abs() < 1e-9);
}

#[test]
fn multi_turn_f32_keeps_full_resolution_after_a_million_turns() {
    // Exact sin/cos isolates the wrapping: 8 samples a turn, 1e6 turns. A loop fast enough
    // that the f32 state quantisation (a limit cycle of a few ulps for slow loops) stays
    // below an ulp of the angle.
    let gains = Gains::<f32, 3, Exact>::new([0.3, 0.04, 0.002], TS as f32).unwrap();
    let per_turn = 8u64;
    let step = core::f64::consts::TAU / per_turn as f64;
    let mut state = ObserverState::<f32, 3>::at(0.0, (step / TS) as f32, 0.0, TS as f32);
    let turns = if cfg!(miri) { 100 } else { 1_000_000u64 };
    let mut worst = 0.0f64;
    for k in 1..=turns * per_turn {
        let phase = (k % per_turn) as f64 * step; // exact truth, wrapped
        let e = gains.update(&mut state, phase.cos() as f32, phase.sin() as f32);
        if k > (turns - 10) * per_turn {
            worst = worst.max(wrap(phase - e.angle as f64).abs());
        }
        assert!(e.angle >= -core::f32::consts::PI && e.angle < core::f32::consts::PI);
    }
    let last = gains.estimate(&state);
    assert_eq!(last.turns, turns as i64);
    // Full f32 resolution: an ulp near pi is 2.4e-7 rad; a naive f32 multi-turn angle
    // (6.3e6 rad) would have an ulp of 0.5 rad. What remains is the f32 loop's own rounding
    // noise at 8 samples a turn: 0.87e-6 rad at worst over these last 10 turns, up to 1.0e-6
    // over 10^5 turns (as with the recursion before the next angle was kept in the state),
    // so the bound is 5 ulp. Miri perturbs std's f64 cos/sin (used for the truth here) by a
    // few ulps on purpose.
    let ulps = if cfg!(miri) { 6.0 } else { 5.0 };
    assert!(worst < ulps * 2.4e-7, "worst wrapped-angle error {worst}");
}

#[test]
fn f32_and_f64_agree_within_f32_precision() {
    let (_, _, ok) = designs();
    let g32 = Gains::<f32, 3, Exact>::new(ok.gains().map(|g| g as f32), TS as f32).unwrap();
    let theta = |t: f64| (1.0 + 200.0 * t + 300.0 * t * t, 200.0 + 600.0 * t);
    let e64 = run(&ok, n(20_000), theta);
    let e32 = run(&g32, n(20_000), theta);
    let angle = e64
        .iter()
        .zip(&e32)
        .map(|(a, b)| (a.0 - b.0).abs())
        .fold(0.0, f64::max);
    let speed = e64
        .iter()
        .zip(&e32)
        .map(|(a, b)| (a.1 - b.1).abs())
        .fold(0.0, f64::max);
    assert!(angle < 2e-5, "angle differs by {angle}");
    // Speed is x2 / Ts: f32 rounding of x2 (~1e-7 relative) times 1/Ts.
    assert!(speed < 0.05, "speed differs by {speed}");
}

/// The largest of `error(x, sin x, cos x)` (sin and cos in `f64`) over `n + 1` angles `x`
/// evenly spread over [-pi, pi].
fn worst_over_the_angle_range<T: Real>(n: usize, mut error: impl FnMut(T, f64, f64) -> f64) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..=n {
        let x = T::from_f64(-core::f64::consts::PI + core::f64::consts::TAU * i as f64 / n as f64);
        let (s64, c64) = x.to_f64().sin_cos();
        worst = worst.max(error(x, s64, c64));
    }
    worst
}

/// A sweep that found no error at all compared nothing: each float type must show some.
fn assert_the_sweeps_measured_something(e32: f64, e64: f64) {
    assert!(
        e32 > 1e-9 && e64 > 1e-17,
        "the sweep measured something: {e32} {e64}"
    );
}

#[test]
fn fast_sin_cos_error_is_within_its_documented_bound() {
    fn check<T: Real>() -> f64 {
        let n = if cfg!(miri) { 2_000 } else { 2_000_000 };
        let worst = worst_over_the_angle_range::<T>(n, |x, s64, c64| {
            let (s, c) = x.fast_sin_cos();
            (s.to_f64() - s64).abs().max((c.to_f64() - c64).abs())
        });
        assert!(worst < T::FAST_SIN_COS_MAX_ERROR.to_f64(), "error {worst}");
        worst
    }
    assert_the_sweeps_measured_something(check::<f32>(), check::<f64>());
}

/// The folded phase detector of `Fast` computes what the sin/cos it folds would give: both
/// outputs within the sin/cos error bound times the input amplitude (plus a few roundings) of
/// the exact `y_s cos - y_c sin` and `y_c cos + y_s sin`, over the whole angle range and
/// for inputs of every sign.
#[test]
fn fast_phase_detector_matches_the_sin_cos_it_folds() {
    fn check<T: Real>() -> f64 {
        let n = if cfg!(miri) { 500 } else { 200_000 };
        let inputs = [
            (0.8, 0.6),
            (-0.3, 0.95),
            (-1.9, -2.2),
            (3.5, -0.1),
            (0.0, -1.0),
        ];
        worst_over_the_angle_range::<T>(n, |x, s64, c64| {
            let mut worst = 0.0f64;
            for (y_c, y_s) in inputs {
                let (eps, in_phase) =
                    <Fast as SinCos<T>>::phase_detector(x, T::from_f64(y_c), T::from_f64(y_s));
                let (y_c, y_s) = (T::from_f64(y_c).to_f64(), T::from_f64(y_s).to_f64());
                let amplitude = y_c.abs() + y_s.abs();
                let bound =
                    amplitude * (T::FAST_SIN_COS_MAX_ERROR.to_f64() + 4.0 * T::EPSILON.to_f64());
                let d_eps = (eps.to_f64() - (y_s * c64 - y_c * s64)).abs();
                let d_in = (in_phase.to_f64() - (y_c * c64 + y_s * s64)).abs();
                assert!(
                    d_eps <= bound && d_in <= bound,
                    "at {x}: {d_eps} {d_in} > {bound}"
                );
                worst = worst.max(d_eps / amplitude).max(d_in / amplitude);
            }
            worst
        })
    }
    assert_the_sweeps_measured_something(check::<f32>(), check::<f64>());
}

#[test]
fn fast_sin_cos_observer_matches_the_exact_one() {
    let fast = Gains::<f32, 3, Fast>::new([0.3, 0.04, 0.002], TS as f32).unwrap();
    let exact: Gains<f32, 3, Exact> = fast.with_sin_cos();
    let theta = |t: f64| (2.0 + 150.0 * t, 150.0);
    let a = run(&fast, n(20_000), theta);
    let b = run(&exact, n(20_000), theta);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x.0 - y.0).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "fast sin/cos moved the angle by {worst} rad");
}

#[test]
fn stability_check_accepts_just_inside_and_refuses_just_outside() {
    // Order 2 boundary 2 l1 + l2 = 4 (a pole at z = -1).
    assert!(Gains::<f64, 2>::new([1.5, 1.0 - 1e-9], 1e-3).is_ok());
    assert_eq!(
        Gains::<f64, 2>::new([1.5, 1.0 + 1e-9], 1e-3).unwrap_err(),
        ConfigError::Unstable {
            parameter: Parameter::AngleGain,
            condition: "2 l1 + l2 < 4"
        }
    );
    // Order 3, Hurwitz determinant boundary: 2 l2 (4 l1 - l3) = l3 (8 - 4 l1 - 2 l2).
    let (l1, l2) = (0.5, 0.2);
    let l3_edge = 2.0 * l2 * 4.0 * l1 / (8.0 - 4.0 * l1 - 2.0 * l2 + 2.0 * l2);
    assert!(Gains::<f64, 3>::new([l1, l2, l3_edge * (1.0 - 1e-9)], 1e-3).is_ok());
    assert_eq!(
        Gains::<f64, 3>::new([l1, l2, l3_edge * (1.0 + 1e-9)], 1e-3)
            .unwrap_err()
            .parameter(),
        Parameter::AccelerationGain
    );
    // Tiny gains (a slow loop at a high sample rate) are accepted in f32 too.
    assert!(Gains::<f32, 3>::new([3e-3, 3e-6, 1e-9], 1e-6).is_ok());
}

#[test]
fn bad_configuration_is_refused_naming_the_parameter() {
    let e = Gains::<f32, 2>::new([0.1, 0.01], 0.0).unwrap_err();
    assert_eq!(e, ConfigError::NotPositive(Parameter::SamplePeriod));
    let e = Gains::<f32, 2>::new([0.1, 0.01], f32::NAN).unwrap_err();
    assert_eq!(e, ConfigError::NotFinite(Parameter::SamplePeriod));
    let e = Gains::<f32, 3>::new([0.1, f32::INFINITY, 0.001], 1e-4).unwrap_err();
    assert_eq!(e, ConfigError::NotFinite(Parameter::SpeedGain));
    let e = Gains::<f32, 2>::new([0.1, 0.01], 1e-39).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    let e = Gains::<f64, 2>::new([0.1, 0.01], 1.4e-148).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    let e = Gains::<f64, 2>::new([0.1, 0.01], 1e4).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    assert!(Gains::<f32, 2>::new([0.1, 0.01], 1e-12).is_ok());
    let text = std::format!("{}", ConfigError::NotFinite(Parameter::SpeedGain));
    assert_eq!(text, "speed_gain (l2) must be finite");
}

#[test]
fn non_finite_samples_leave_the_state_finite() {
    let (_, _, ok) = designs();
    let mut state = ObserverState::new();
    for k in 0..1000 {
        let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][k % 3];
        let e = ok.update(&mut state, if k % 2 == 0 { bad } else { 1.0 }, bad);
        assert!(e.angle.is_finite() && e.speed.is_finite() && e.acceleration.is_finite());
    }
}

#[test]
fn first_sample_initialises_from_atan2_in_every_quadrant() {
    let (o2, _, _) = designs();
    for i in 0..16 {
        let theta = -3.0 + 0.4 * i as f64;
        let mut ato = Observer::new(o2);
        let e = ato.update(theta.cos(), theta.sin());
        assert!((e.angle - theta).abs() < 1e-12);
        assert_eq!(ato.order(), 2);
    }
}

/// Roots of a monic polynomial (lowest coefficient first) by Durand-Kerner, for the
/// eigenvalue cross-check of the stability test.
fn spectral_radius(c_in_z: &[f64]) -> f64 {
    type C = (f64, f64);
    let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let n = c_in_z.len();
    let eval = |z: C| {
        let mut acc: C = (1.0, 0.0);
        for k in (0..n).rev() {
            acc = mul(acc, z);
            acc.0 += c_in_z[k];
        }
        acc
    };
    let mut roots: Vec<C> = (0..n)
        .map(|k| {
            mul(
                (0.4, 0.9),
                if k == 0 {
                    (1.0, 0.0)
                } else {
                    (0.4f64.powi(k as i32), 0.9f64.powi(k as i32))
                },
            )
        })
        .collect();
    for _ in 0..if cfg!(miri) { 100 } else { 500 } {
        for i in 0..n {
            let mut den: C = (1.0, 0.0);
            for j in 0..n {
                if i != j {
                    den = mul(den, (roots[i].0 - roots[j].0, roots[i].1 - roots[j].1));
                }
            }
            let num = eval(roots[i]);
            let d2 = den.0 * den.0 + den.1 * den.1;
            let q = (
                (num.0 * den.0 + num.1 * den.1) / d2,
                (num.1 * den.0 - num.0 * den.1) / d2,
            );
            roots[i] = (roots[i].0 - q.0, roots[i].1 - q.1);
        }
    }
    roots.iter().map(|r| r.0.hypot(r.1)).fold(0.0, f64::max)
}

/// Characteristic polynomial in z (monic, lowest first) from the one in s = z - 1.
fn poly_in_z(c_s: &[f64]) -> Vec<f64> {
    let n = c_s.len();
    let mut full: Vec<f64> = c_s.to_vec();
    full.push(1.0);
    // p(z) = sum_k full[k] (z - 1)^k
    let mut out = std::vec![0.0; n + 1];
    for (k, &ck) in full.iter().enumerate() {
        let mut binom = 1.0;
        for (j, slot) in out.iter_mut().enumerate().take(k + 1) {
            // coefficient of z^j in (z-1)^k: binom(k, j) (-1)^(k-j)
            let sign = if (k - j) % 2 == 0 { 1.0 } else { -1.0 };
            *slot += ck * binom * sign;
            binom = binom * (k - j) as f64 / (j + 1) as f64;
        }
    }
    out.pop();
    out
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: if cfg!(miri) { 4 } else { 400 },
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn stability_check_agrees_with_the_eigenvalues(l1 in -0.5..2.5f64, l2 in -0.5..4.5f64, l3 in -0.2..2.0f64) {
        let radius = spectral_radius(&poly_in_z(&characteristic_polynomial_in_s(&[l1, l2, l3])));
        prop_assume!((radius - 1.0).abs() > 1e-6);
        prop_assert_eq!(Gains::<f64, 3>::new([l1, l2, l3], 1e-3).is_ok(), radius < 1.0, "radius {}", radius);
        let radius2 = spectral_radius(&poly_in_z(&characteristic_polynomial_in_s(&[l1, l2])));
        prop_assume!((radius2 - 1.0).abs() > 1e-6);
        prop_assert_eq!(Gains::<f64, 2>::new([l1, l2], 1e-3).is_ok(), radius2 < 1.0);
    }

    #[test]
    fn whole_turns_added_to_the_truth_change_only_the_turn_count(
        theta0 in -3.0..3.0f64, speed in -300.0..300.0f64, n in -1000i64..1000,
    ) {
        let (_, _, ok) = designs();
        let shifted = theta0 + n as f64 * core::f64::consts::TAU;
        let mut a = ObserverState::at(theta0, speed, 0.0, TS);
        let mut b = ObserverState::at(shifted, speed, 0.0, TS);
        prop_assert_eq!(b.turns() - a.turns(), n);
        for k in 1..crate::tests::n(300).max(20) {
            let t = k as f64 * TS;
            let (ya, yb) = (theta0 + speed * t, shifted + speed * t);
            let ea = ok.update(&mut a, ya.cos(), ya.sin());
            let eb = ok.update(&mut b, yb.cos(), yb.sin());
            prop_assert_eq!(eb.turns - ea.turns, n);
            prop_assert!(wrap(ea.angle - eb.angle).abs() < 1e-9);
            prop_assert!((ea.speed - eb.speed).abs() < 1e-5);
        }
    }

    #[test]
    fn loop_polynomial_round_trips(l1 in 0.01..1.0f64, l2 in 0.001..0.5f64, l3 in 1e-5..0.01f64) {
        prop_assume!(Gains::<f64, 3>::new([l1, l2, l3], 1e-3).is_ok());
        let g = Gains::<f64, 3>::new([l1, l2, l3], 1e-3).unwrap();
        let back = Gains::<f64, 3>::from_loop_polynomial(g.loop_polynomial(), 1e-3).unwrap();
        for (a, b) in back.gains().iter().zip(g.gains()) {
            prop_assert!((a - b).abs() < 1e-12);
        }
    }
}

#[test]
fn a_channel_bank_gives_exactly_the_single_channel_results() {
    fn check<T: Real, S: SinCos<T>>() {
        let l = [T::from_f64(0.061), T::from_f64(0.0019), T::from_f64(3.1e-5)];
        let gains = Gains::<T, 3, S>::new(l, T::from_f64(TS)).unwrap();
        // Single observers without the fault monitor: the bank does not run it.
        let single = gains
            .with_fault_thresholds(FaultThresholds::disabled())
            .unwrap();
        const L: usize = 8;
        let mut bank = ChannelBank::<T, 3, L>::new();
        let mut states = [ObserverState::<T, 3>::new(); L];
        for k in 0..if cfg!(miri) { 100 } else { 5000 } {
            let mut y_c = [T::ZERO; L];
            let mut y_s = [T::ZERO; L];
            for lane in 0..L {
                let theta = 0.3 * lane as f64 + (20.0 + 45.0 * lane as f64) * k as f64 * TS;
                y_c[lane] = T::from_f64(theta.cos());
                y_s[lane] = T::from_f64(if k % 97 == lane {
                    f64::NAN
                } else {
                    theta.sin()
                });
            }
            gains.update_bank(&mut bank, &y_c, &y_s);
            for lane in 0..L {
                let e = single.update(&mut states[lane], y_c[lane], y_s[lane]);
                let b = gains.bank_estimate(&bank, lane).unwrap();
                assert_eq!(b, e, "lane {lane}, sample {k}");
            }
        }
        assert!(gains.bank_estimate(&bank, L).is_none());
        assert!(
            bank.turns().iter().any(|&t| t > 0),
            "the lanes turned: {:?}",
            bank.turns()
        );
    }
    check::<f32, Fast>();
    check::<f64, Exact>();
}

/// The one-turn wrap of a bank's lanes (by selects) lands in [-pi, pi) and removes exactly
/// the turns it reports, for every angle up to its limit, including every float within 2000
/// ulps of the edges +-pi and +-2 pi; and it is what the single observer's wrap gives.
#[test]
fn the_one_turn_wrap_lands_in_range_and_agrees_with_the_full_wrap() {
    use crate::observer::{one_turn_limit, wrap_angle, wrap_one_turn};
    fn check<T: Real>(a: T) {
        let (wrapped, whole) = wrap_one_turn(a);
        assert!(wrapped >= -T::PI && wrapped < T::PI, "{a} -> {wrapped}");
        // The turns removed, to the rounding of one subtraction at |a|.
        let removed = a.to_f64() - wrapped.to_f64() - f64::from(whole) * core::f64::consts::TAU;
        assert!(
            removed.abs() <= 4.0 * a.abs().to_f64().max(1.0) * T::EPSILON.to_f64(),
            "{a}"
        );
        let mut full = a;
        assert_eq!((wrap_angle(&mut full), full), (whole, wrapped), "{a}");
    }
    let limit = one_turn_limit::<f64>();
    let sweep = if cfg!(miri) { 200 } else { 200_000 };
    for k in 0..=sweep {
        let a = -limit + 2.0 * limit * k as f64 / sweep as f64;
        check(a);
        check(a as f32);
    }
    let ulps = if cfg!(miri) { 20 } else { 2000 };
    for edge in [core::f64::consts::PI, core::f64::consts::TAU] {
        for sign in [1.0, -1.0] {
            let (e64, e32) = (sign * edge, (sign * edge) as f32);
            for d in -ulps..=ulps {
                check(f64::from_bits((e64.to_bits() as i64 + d) as u64));
                check(f32::from_bits((e32.to_bits() as i32 + d as i32) as u32));
            }
        }
    }
}

/// Gains so strong that one correction can move the angle by more than half a turn make the
/// bank run its lanes one by one with the full wrap: still exactly the single observers.
#[test]
fn a_bank_with_corrections_beyond_half_a_turn_gives_the_single_channel_results() {
    let gains = Gains::<f32, 3>::new([0.9, 0.3, 0.01], 1e-4).unwrap();
    let single = gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    const L: usize = 4;
    let mut bank = ChannelBank::<f32, 3, L>::new();
    let mut states = [ObserverState::<f32, 3>::new(); L];
    for k in 0..if cfg!(miri) { 50 } else { 2000 } {
        let mut y_c = [0.0f32; L];
        let mut y_s = [0.0f32; L];
        for lane in 0..L {
            // Amplitude up to 3.9 (accepted: the bound is 4), angle jumping about.
            let theta = (k * (lane + 3)) as f32 * 0.77;
            let amplitude = 0.5 + 3.4 * ((k + lane) % 5) as f32 / 4.0;
            y_c[lane] = amplitude * libm::cosf(theta);
            y_s[lane] = amplitude * libm::sinf(theta);
        }
        gains.update_bank(&mut bank, &y_c, &y_s);
        for lane in 0..L {
            let e = single.update(&mut states[lane], y_c[lane], y_s[lane]);
            assert_eq!(
                gains.bank_estimate(&bank, lane).unwrap(),
                e,
                "lane {lane}, sample {k}"
            );
            assert!(e.angle >= -core::f32::consts::PI && e.angle < core::f32::consts::PI);
        }
    }
}
