//! What the tests of every module share: the sample period (shortened under Miri), the
//! three observers of the paper designed independently of the `angletrack` crate, a run over
//! a noise-free resolver, and deterministic random bits.

extern crate std;

use std::vec::Vec;

use proptest::prelude::ProptestConfig;

use crate::*;

/// Under Miri (about 10^5 times slower) the tests run the same loops at a 10 times
/// longer sample period, so that 10 times fewer samples cover the same transients.
pub(crate) const MIRI_SPEEDUP: usize = if cfg!(miri) { 10 } else { 1 };
pub(crate) const TS: f64 = 1e-4 * MIRI_SPEEDUP as f64; // 10 kHz

/// A sample count, shortened under Miri.
pub(crate) const fn n(samples: usize) -> usize {
    samples / MIRI_SPEEDUP
}

/// Discrete loop polynomial (in s = z - 1) of pole matching `z = exp(s Ts)`
/// (`docs/theory.md §7`) for real poles and complex pairs `(re, im)` given in rad/s.
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
/// Riccati recursion (the design crate solves the DARE of `docs/theory.md §4`; this is an
/// independent check).
fn kalman(q_over_r: f64) -> [f64; 3] {
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
pub(crate) fn run<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<T, N, S>,
    samples: usize,
    theta: impl Fn(f64) -> (f64, f64),
) -> Vec<(f64, f64)> {
    let mut state = ObserverState::at(
        T::from_f64(theta(0.0).0),
        T::from_f64(theta(0.0).1),
        T::ZERO,
        gains.sample_period(),
    )
    .unwrap();
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

/// The largest `|part(a) - part(b)|` over the samples of two runs (see [`run`]).
pub(crate) fn largest_difference(
    a: &[(f64, f64)],
    b: &[(f64, f64)],
    part: impl Fn(&(f64, f64)) -> f64,
) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (part(x) - part(y)).abs())
        .fold(0.0, f64::max)
}

/// `a` wrapped into [-pi, pi).
pub(crate) fn wrap(a: f64) -> f64 {
    (a + core::f64::consts::PI).rem_euclid(core::f64::consts::TAU) - core::f64::consts::PI
}

pub(crate) fn mean(v: impl Iterator<Item = f64>) -> f64 {
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

/// Samples of the loop's own 2 % settling time after a small angle step (monitor off).
pub(crate) fn settling_samples<const N: usize>(gains: &Gains<f64, N>) -> usize {
    let bare = gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    let step = 0.01f64;
    let mut state = ObserverState::at(0.0, 0.0, 0.0, TS).unwrap();
    let mut last_outside = 0;
    // A linear, stable response: once inside the band for three times as long as it took
    // to get there, it stays.
    for k in 1..n(200_000) {
        let e = bare.update(&mut state, step.cos(), step.sin());
        if (e.angle - step).abs() > 0.02 * step {
            last_outside = k;
        } else if k > 4 * last_outside + 20 {
            break;
        }
    }
    last_outside + 1
}

/// xorshift64*: deterministic random bits for the tests that feed junk or noise.
pub(crate) struct Bits(pub(crate) u64);

impl Bits {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The configuration of the property tests: 400 cases (4 under Miri), no failure file.
pub(crate) fn proptest_config() -> ProptestConfig {
    ProptestConfig {
        cases: if cfg!(miri) { 4 } else { 400 },
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}
