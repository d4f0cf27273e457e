//! The exact product of two 32-bit integers as a 64-bit one, for the demodulator's fixed
//! point (`docs/theory.md §13`) and its carrier loop: one instruction on a core with a
//! 32 x 32 -> 64 multiplier (Cortex-M3/M4/M7: `SMULL`), and on ARMv6-M (Cortex-M0/M0+, where
//! a 64-bit product is a library call of some 40 instructions for any operands) four 16 x 16
//! products of the operands' halves. Both forms give the same integer for every input (tests
//! below); which one is compiled changes the speed only. ARMv6-M is told apart as in
//! `multiply.rs`: the Arm architecture without 32-bit atomics.

/// `a b`, exact.
#[inline(always)]
pub(crate) fn wide_product(a: i32, b: i32) -> i64 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        i64::from(a) * i64::from(b)
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        halves(a, b)
    }
}

/// `a b` from 32-bit products: `a = h 2^16 + l` and `b = k 2^16 + m` with `h`, `k` signed
/// in [-2^15, 2^15) and `l`, `m` in [0, 2^16), so `a b = h k 2^32 + (h m + l k) 2^16 + l m`:
/// `|h k| <= 2^30`, `h m` and `l k` within (-2^31, 2^31), `l m` below 2^32 unsigned; the two
/// middle products are added in 64 bits (their sum may not fit 32).
#[cfg_attr(
    not(all(target_arch = "arm", not(target_has_atomic = "32"))),
    allow(dead_code)
)]
#[inline(always)]
fn halves(a: i32, b: i32) -> i64 {
    let (h, l) = (a >> 16, a & 0xffff);
    let (k, m) = (b >> 16, b & 0xffff);
    let low = (l as u32) * (m as u32);
    let middle = i64::from(h * m) + i64::from(l * k);
    (i64::from(h * k) << 32) + (middle << 16) + i64::from(low)
}

#[cfg(test)]
mod tests {
    use super::{halves, wide_product};
    use proptest::prelude::*;

    const EDGES: [i32; 11] = [
        i32::MIN,
        i32::MIN + 1,
        -65_537,
        -65_536,
        -1,
        0,
        1,
        65_535,
        65_536,
        i32::MAX - 1,
        i32::MAX,
    ];

    #[test]
    fn the_halves_give_the_exact_product_at_the_corners() {
        for &a in &EDGES {
            for &b in &EDGES {
                let exact = i128::from(a) * i128::from(b);
                assert_eq!(i128::from(halves(a, b)), exact, "{a} {b}");
                assert_eq!(i128::from(wide_product(a, b)), exact, "{a} {b}");
            }
        }
    }

    proptest! {
        #[test]
        fn the_halves_give_the_exact_product(a: i32, b: i32) {
            prop_assert_eq!(i128::from(halves(a, b)), i128::from(a) * i128::from(b));
        }
    }
}
