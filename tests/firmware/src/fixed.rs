//! The fixed-point variant (`variants::FIXED`): its out-of-line update, its check against the
//! host's reference of the `f32` Kalman ATO, and its count.

use core::hint::black_box;

use angletrack_core::{FixedEstimate, FixedGains, FixedState};
use cortex_m_semihosting::hprintln;

use crate::variants::{self, FIXED, RECORD_BYTES, fixed_counts};

/// Largest accepted |position - host f32 reference| of the fixed-point variant (rad): its
/// inputs are rounded to 2^-14 of the amplitude and its gains to 16 bits
/// (`docs/theory.md §14`); twice 2^-16 of a turn (the RMS bound of `tests/fixed.rs`), where
/// 4.7e-5 rad was measured.
const FIXED_POSITION_TOLERANCE_RAD: f32 = 1.9e-4;

/// One fixed-point update, kept out of line: the unit whose instructions are counted.
#[inline(never)]
pub fn update_fixed(
    gains: &FixedGains<3>,
    state: &mut FixedState<3>,
    y_c: i16,
    y_s: i16,
) -> FixedEstimate {
    gains.update(state, y_c, y_s)
}

/// `check` mode: the fixed-point variant against the `f32` reference `records`; `false` if
/// it is out of tolerance.
pub fn check(gains: &FixedGains<3>, y_c: &[f32], y_s: &[f32], records: &[u8]) -> bool {
    let mut state = FixedState::new();
    let (mut worst, mut at) = (0.0f32, 0);
    for (k, r) in records.chunks_exact(RECORD_BYTES).enumerate() {
        let e = update_fixed(gains, &mut state, fixed_counts(y_c[k]), fixed_counts(y_s[k]));
        let (angle_ref, turns_ref, _, _) = variants::decode(r);
        let turns = (e.turns - i64::from(turns_ref)) as f32;
        let angle = e.angle as f32 * (core::f32::consts::TAU / 4_294_967_296.0);
        let d = (turns * core::f32::consts::TAU + (angle - angle_ref)).abs();
        if d > worst || d.is_nan() {
            (worst, at) = (d, k);
        }
    }
    let ok = worst <= FIXED_POSITION_TOLERANCE_RAD;
    hprintln!(
        "check {}: max |position - host f32| {:e} rad (sample {}): {}",
        FIXED,
        worst,
        at,
        if ok { "ok" } else { "FAIL" }
    );
    ok
}

/// `count` mode: `y_c.len()` fixed-point updates and nothing else.
pub fn count(gains: &FixedGains<3>, y_c: &[f32], y_s: &[f32]) {
    let mut state = FixedState::new();
    for (&c, &s) in y_c.iter().zip(y_s) {
        black_box(&update_fixed(gains, &mut state, fixed_counts(c), fixed_counts(s)));
    }
}
