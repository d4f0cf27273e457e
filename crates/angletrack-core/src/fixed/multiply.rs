//! The three products of the fixed-point path (`docs/theory.md §14`), each an exact integer
//! function written twice: once through a 64-bit product, which a core with a 32 x 32 -> 64
//! multiplier runs in one instruction (Cortex-M3/M4/M7: `SMULWB`, `SMULWT`, `SMMLAR`,
//! `SMLAL`), and once in 32-bit halves, for a core without one (Cortex-M0/M0+, where a
//! 64-bit product is a library call of some 40 instructions). Both forms give the same
//! integers for every input (tests below), so a firmware on either core and its simulation
//! on a host agree bit for bit; which one is compiled changes the speed only.
//!
//! Stable Rust offers no `cfg` for the Cortex-M's long multiply; ARMv6-M is the Arm
//! architecture without 32-bit atomics (`target_has_atomic = "32"`), so the halves are
//! compiled there, the 64-bit product everywhere else.

/// `floor(a b / 2^16)` for a 16-bit `b`: at most `2^31 2^15 / 2^16 = 2^30` in magnitude.
#[inline(always)]
pub(crate) fn mul_q16(a: i32, b: i16) -> i32 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        wide::mul_q16(a, b)
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        halves::mul_q16(a, b)
    }
}

/// `x + round(g e / 2^16)` (halves rounded up), wrapping: the correction of a state kept
/// in 32 bits by gain multiplier `g` and phase error `e` (Q15).
#[inline(always)]
pub(crate) fn add_round_q16(x: i32, g: i32, e: i16) -> i32 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        wide::add_round_q16(x, g, e)
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        halves::add_round_q16(x, g, e)
    }
}

/// `x + g e 2^k` for `k` in 1..=15 (`s = 2^k`: the 64-bit product multiplies by `s`, the
/// halves shift by `k`), wrapping modulo 2^64: the correction of the 64-bit acceleration
/// state.
#[inline(always)]
pub(crate) fn add_wide(x: i64, g: i32, e: i16, s: i32, k: u32) -> i64 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        wide::add_wide(x, g, e, s, k)
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        halves::add_wide(x, g, e, s, k)
    }
}

/// Through 64-bit products.
#[cfg_attr(
    all(target_arch = "arm", not(target_has_atomic = "32")),
    allow(dead_code)
)]
mod wide {
    #[inline(always)]
    pub(crate) fn mul_q16(a: i32, b: i16) -> i32 {
        ((i64::from(a) * i64::from(b)) >> 16) as i32
    }

    #[inline(always)]
    pub(crate) fn add_round_q16(x: i32, g: i32, e: i16) -> i32 {
        // With e in the top half-word: round(g e 2^16 / 2^32), one `SMMLAR`.
        let e = i64::from(i32::from(e) << 16);
        x.wrapping_add(((i64::from(g) * e + (1 << 31)) >> 32) as i32)
    }

    #[inline(always)]
    pub(crate) fn add_wide(x: i64, g: i32, e: i16, s: i32, _k: u32) -> i64 {
        // e 2^k fits 32 bits for k <= 16: `MUL` and `SMLAL`.
        x.wrapping_add(i64::from(g) * i64::from(i32::from(e) * s))
    }
}

/// Through 32-bit products of `a`'s halves: `a = h 2^16 + l`, `h` signed, `l` in [0, 2^16),
/// so `a b = h b 2^16 + l b` with `|h b| <= 2^30` and `l b` in [-2^31 + 2^15, 2^31 - 2^15]
/// (`b` in [-2^15, 2^15 - 1]): no product overflows, and `h b 2^16` is a multiple of 2^16,
/// so the floor (or the rounding) applies to `l b` alone.
#[cfg_attr(
    not(all(target_arch = "arm", not(target_has_atomic = "32"))),
    allow(dead_code)
)]
mod halves {
    #[inline(always)]
    fn split(a: i32) -> (i32, i32) {
        (a >> 16, a & 0xffff)
    }

    #[inline(always)]
    pub(crate) fn mul_q16(a: i32, b: i16) -> i32 {
        let (high, low) = split(a);
        let b = i32::from(b);
        high * b + ((low * b) >> 16)
    }

    #[inline(always)]
    pub(crate) fn add_round_q16(x: i32, g: i32, e: i16) -> i32 {
        let (high, low) = split(g);
        let e = i32::from(e);
        // low e + 2^15 < 2^31: (2^16 - 1)(2^15 - 1) + 2^15 = 2^31 - 2^16 + 1.
        x.wrapping_add(high * e + ((low * e + (1 << 15)) >> 16))
    }

    #[inline(always)]
    pub(crate) fn add_wide(x: i64, g: i32, e: i16, _s: i32, k: u32) -> i64 {
        let (high, low) = split(g);
        let e = i32::from(e);
        // g e 2^k = (h e) 2^(16 + k) + (l e) 2^k, each term's high and low words by 32-bit
        // shifts (a variable 64-bit shift is a library call on a Cortex-M0): for k in
        // 1..=15 every shift is below 32.
        let (p1, p2) = (high * e, low * e);
        let term1 = words(p1 >> (16 - k), (p1 << (16 + k)) as u32);
        let term2 = words(p2 >> (32 - k), (p2 << k) as u32);
        x.wrapping_add(term1).wrapping_add(term2)
    }

    /// The 64-bit integer of words `high` and `low`.
    #[inline(always)]
    fn words(high: i32, low: u32) -> i64 {
        (i64::from(high) << 32) | i64::from(low)
    }
}

#[cfg(test)]
mod tests {
    use super::{halves, wide};
    use proptest::prelude::*;

    /// The corners of both operands' ranges and a few values around zero.
    const EDGES: [i32; 9] = [
        i32::MIN,
        i32::MIN + 1,
        -65_537,
        -1,
        0,
        1,
        65_535,
        65_536,
        i32::MAX,
    ];
    const EDGES_16: [i16; 7] = [i16::MIN, i16::MIN + 1, -1, 0, 1, 16_384, i16::MAX];

    fn agree(a: i32, b: i16, x: i32, x64: i64) {
        assert_eq!(
            halves::mul_q16(a, b),
            wide::mul_q16(a, b),
            "mul_q16({a}, {b})"
        );
        let exact = (f64::from(a) * f64::from(b) / 65_536.0).floor();
        assert_eq!(f64::from(wide::mul_q16(a, b)), exact, "mul_q16({a}, {b})");
        assert_eq!(
            halves::add_round_q16(x, a, b),
            wide::add_round_q16(x, a, b),
            "add_round_q16({x}, {a}, {b})"
        );
        let rounded = (f64::from(a) * f64::from(b) / 65_536.0 + 0.5).floor() as i64;
        assert_eq!(
            i64::from(wide::add_round_q16(x, a, b)),
            i64::from(x.wrapping_add(rounded as i32)),
            "add_round_q16({x}, {a}, {b})"
        );
        for k in 1..=15 {
            let s = 1 << k;
            assert_eq!(
                halves::add_wide(x64, a, b, s, k),
                wide::add_wide(x64, a, b, s, k)
            );
            let product = (i128::from(a) * i128::from(b)) << k;
            assert_eq!(
                i128::from(wide::add_wide(x64, a, b, s, k)),
                i128::from((i128::from(x64) + product) as i64),
                "add_wide({x64}, {a}, {b}, {k})"
            );
        }
    }

    #[test]
    fn both_forms_agree_at_the_corners() {
        for &a in &EDGES {
            for &b in &EDGES_16 {
                agree(a, b, a ^ 0x5555, i64::MAX.wrapping_sub(i64::from(a)));
            }
        }
    }

    proptest! {
        #[test]
        fn both_forms_agree_everywhere(a: i32, b: i16, x: i32, x64: i64) {
            agree(a, b, x, x64);
        }
    }
}
