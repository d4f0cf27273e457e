//! The wraps of the recursion agree with each other and land in [-pi, pi).

use crate::const_config::Real;
use crate::wrap::{one_turn_limit, wrap_angle, wrap_one_turn};

/// The one-turn wrap of a bank's lanes (by selects) lands in [-pi, pi) and removes exactly
/// the turns it reports, for every angle up to its limit, including every float within 2000
/// ulps of the edges +-pi and +-2 pi; and it is what the single observer's wrap gives.
#[test]
fn the_one_turn_wrap_lands_in_range_and_agrees_with_the_full_wrap() {
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
