//! The stability check against the eigenvalues of the loop, at its edges, and the map
//! between gains and loop polynomial (`docs/theory.md §6`).

extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use crate::stability::for_f64::characteristic_polynomial_in_s;
use crate::test_support::proptest_config;
use crate::*;

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
    #![proptest_config(proptest_config())]

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
    fn loop_polynomial_round_trips(l1 in 0.01..1.0f64, l2 in 0.001..0.5f64, l3 in 1e-5..0.01f64) {
        prop_assume!(Gains::<f64, 3>::new([l1, l2, l3], 1e-3).is_ok());
        let g = Gains::<f64, 3>::new([l1, l2, l3], 1e-3).unwrap();
        let back = Gains::<f64, 3>::from_loop_polynomial(g.loop_polynomial(), 1e-3).unwrap();
        for (a, b) in back.gains().iter().zip(g.gains()) {
            prop_assert!((a - b).abs() < 1e-12);
        }
    }
}
