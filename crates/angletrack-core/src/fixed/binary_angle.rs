//! The binary angle of the fixed-point path (`docs/theory.md §14`): a wrapping `i32` with
//! 2^32 units per turn (`i32::MIN` is -pi, 0 is 0), its sin/cos table with a first-order
//! correction inside each table step (the phase detector), and its integer `atan2`
//! (CORDIC, for the first sample and re-acquisition).

use super::multiply::mul_q16;
use crate::wrap::TurnArithmetic;

/// Entries of the sine table per turn (a power of two: the index is the top 8 bits).
const STEPS_PER_TURN: usize = 256;

/// `round(32767 sin(2 pi k / 256))` for `k` in 0..320: the sine over one turn and the
/// cosine (`cos x = sin(x + pi/2)`, 64 entries further).
pub(crate) const SIN_Q15: [i16; STEPS_PER_TURN + STEPS_PER_TURN / 4] = sin_table();

/// Entry `k`'s sine in the low half-word and cosine in the high one (1 KiB): one load per
/// sample, and a Cortex-M4 multiplies the half-words as they are (`SMULBB`, `SMULTB`).
const SIN_COS_Q15: [u32; STEPS_PER_TURN] = sin_cos_table();

/// `round(2 pi 2^12)`: 2 pi in Q12, to turn a residual angle into radians.
const TWO_PI_Q12: i32 = 25_736;

/// `atan(2^-i)` in binary-angle units (2^32 per turn) for the CORDIC's 30 rotations.
const ATAN_BINARY: [i32; 30] = atan_table();

/// `sin x` for `|x| <= pi` by its Taylor series (error below 1e-16): `const`, to build the
/// table at compile time.
pub(crate) const fn taylor_sin(x: f64) -> f64 {
    let mut term = x;
    let mut sum = x;
    let mut n = 1;
    while n < 30 {
        term = -term * x * x / (((2 * n) * (2 * n + 1)) as f64);
        sum += term;
        n += 1;
    }
    sum
}

/// `atan x` for `0 <= x <= 1/2` by its series (error below 1e-17 after 60 terms).
const fn series_atan(x: f64) -> f64 {
    let mut power = x;
    let mut sum = x;
    let mut n = 1;
    while n < 60 {
        power = -power * x * x;
        sum += power / ((2 * n + 1) as f64);
        n += 1;
    }
    sum
}

/// Rounds to the nearest integer, halves away from zero.
pub(crate) const fn round_to_i64(v: f64) -> i64 {
    if v >= 0.0 {
        (v + 0.5) as i64
    } else {
        (v - 0.5) as i64
    }
}

const fn sin_table() -> [i16; STEPS_PER_TURN + STEPS_PER_TURN / 4] {
    let mut table = [0; STEPS_PER_TURN + STEPS_PER_TURN / 4];
    let mut k = 0;
    while k < table.len() {
        // The angle of entry k reduced to [-pi, pi), where the series is accurate.
        let step = (k % STEPS_PER_TURN) as i64;
        let step = if step >= 128 { step - 256 } else { step };
        let x = core::f64::consts::TAU * (step as f64) / (STEPS_PER_TURN as f64);
        table[k] = round_to_i64(32767.0 * taylor_sin(x)) as i16;
        k += 1;
    }
    table
}

const fn sin_cos_table() -> [u32; STEPS_PER_TURN] {
    let mut table = [0; STEPS_PER_TURN];
    let mut k = 0;
    while k < STEPS_PER_TURN {
        let sin = SIN_Q15[k] as u16 as u32;
        let cos = SIN_Q15[k + STEPS_PER_TURN / 4] as u16 as u32;
        table[k] = cos << 16 | sin;
        k += 1;
    }
    table
}

const fn atan_table() -> [i32; 30] {
    let mut table = [0; 30];
    // atan(1) = pi/4: an eighth of a turn, 2^29 exactly.
    table[0] = 1 << 29;
    let mut i = 1;
    while i < 30 {
        let t = series_atan(1.0 / ((1_u64 << i) as f64));
        table[i] = round_to_i64(t / core::f64::consts::TAU * 4_294_967_296.0) as i32;
        i += 1;
    }
    table
}

/// The binary angle (2^32 units per turn, wrapping) of `angle_rad` radians.
///
/// ```
/// use angletrack_core::fixed::{binary_angle, binary_angle_to_rad};
/// assert_eq!(binary_angle(core::f64::consts::FRAC_PI_2), 1 << 30);
/// assert!((binary_angle_to_rad(binary_angle(-3.0)) + 3.0).abs() < 1e-9);
/// ```
pub fn binary_angle(angle_rad: f64) -> i32 {
    let turns = angle_rad / core::f64::consts::TAU;
    let fraction = turns - libm::floor(turns);
    // `fraction` is in [0, 1]; 2^32 units per turn, taken modulo one turn.
    (round_to_i64(fraction * 4_294_967_296.0) as u64 as u32) as i32
}

/// The angle (rad, in [-pi, pi)) of a binary angle.
pub fn binary_angle_to_rad(angle: i32) -> f64 {
    f64::from(angle) * core::f64::consts::TAU / 4_294_967_296.0
}

/// The phase detector at the binary angle `angle` on samples `y_c`, `y_s` in
/// [-32768, 32767] (`docs/theory.md §14`): `(phase error, in-phase component, sin, cos)`,
/// all in counts times 2^15 (the table's Q15) but `sin`, `cos` (Q15).
///
/// The angle is rounded to the nearest of 256 table entries `theta_k`; the residual
/// `d = angle - theta_k` (|d| <= pi/256 rad) enters to first order:
/// `y_s cos(theta) - y_c sin(theta) = e_k cos d - i_k sin d ~ e_k - i_k d`, whose neglected
/// terms are below `|y| d^2 |err| / 2 + |y| d^3 / 6`, about `3e-7 |y|` near lock.
/// No intermediate overflows: `|e_k|, |i_k| <= |y| 32767.5 < 1.52e9` (Cauchy-Schwarz), the
/// residual in 2^-24 turn is in [-2^15, 2^15), times `2 pi 2^12` below `8.44e8`, `i_k >> 16`
/// in [-23194, 23193], their product over 2^16 below `3e8`, and
/// `|e_k - correction| < 1.54e9 < 2^31`.
#[inline(always)]
pub(crate) fn detect(angle: i32, y_c: i32, y_s: i32) -> (i32, i32, i32, i32) {
    // The nearest entry: the top 8 bits of angle + half a step, as an unsigned turn.
    let index = (angle.wrapping_add(1 << 23) as u32 >> 24) as usize;
    let entry = SIN_COS_Q15[index] as i32;
    let (sin, cos) = (i32::from(entry as i16), entry >> 16);
    let phase_error = y_s * cos - y_c * sin;
    let in_phase = y_c * cos + y_s * sin;
    // The angle less the entry's, in 2^-24 turn: bits 8 to 23, sign-extended (one `SBFX`).
    let residual = (angle << 8) >> 16;
    // d in rad times 2^36, then (d 2^36)(i_k / 2^16) / 2^16 / 2^4 = i_k d.
    let residual_rad = residual * TWO_PI_Q12;
    let correction = mul_q16(residual_rad, (in_phase >> 16) as i16) >> 4;
    (phase_error - correction, in_phase, sin, cos)
}

/// `(sin, cos)` in Q15 of the table entry nearest to the binary angle `angle` (within half a
/// step, pi/256 rad): what the fixed-point observer's prediction gives a chain's stages.
#[inline(always)]
pub(crate) fn sin_cos_q15(angle: i32) -> (i16, i16) {
    let index = (angle.wrapping_add(1 << 23) as u32 >> 24) as usize;
    let entry = SIN_COS_Q15[index] as i32;
    (entry as i16, (entry >> 16) as i16)
}

/// `atan2(y_s, y_c)` as a binary angle, by 30 CORDIC rotations (error below 2^-26 of a
/// turn); 0 for (0, 0). Out of line: the first sample and re-acquisition only.
#[cold]
#[inline(never)]
pub(crate) fn atan2(y_s: i32, y_c: i32) -> i32 {
    // Inputs of 16 bits scaled by 2^13: the CORDIC's growth (1.65) keeps |x|, |y| below
    // 2^15 sqrt(2) 2^13 1.65 < 2^31.
    if y_c == 0 && y_s == 0 {
        return 0;
    }
    let (mut x, mut y) = (y_c << 13, y_s << 13);
    let mut angle: i32 = 0;
    if x < 0 {
        // Half a turn first, into the right half-plane, where the rotations converge.
        angle = i32::MIN;
        x = -x;
        y = -y;
    }
    let mut i = 0;
    while i < ATAN_BINARY.len() {
        let (dx, dy) = (y >> i, x >> i);
        if y > 0 {
            x += dx;
            y -= dy;
            angle = angle.wrapping_add(ATAN_BINARY[i]);
        } else {
            x -= dx;
            y += dy;
            angle = angle.wrapping_sub(ATAN_BINARY[i]);
        }
        i += 1;
    }
    angle
}

/// The turns of the fixed-point format ([`TurnArithmetic`] for its `i16` samples, whose
/// angles are binary angles): the angle wraps by itself, and the turn an addition crosses
/// by the shortest way (less than half a turn) is its signed carry.
impl TurnArithmetic for i16 {
    #[inline(always)]
    fn atan2(y_c: i16, y_s: i16) -> i32 {
        atan2(i32::from(y_s), i32::from(y_c))
    }

    #[inline(always)]
    fn is_finite(_angle: i32) -> bool {
        true
    }

    #[inline(always)]
    fn wrap(_angle: &mut i32) -> i32 {
        0
    }

    #[inline(always)]
    fn difference(to: i32, from: i32) -> i32 {
        to.wrapping_sub(from)
    }

    /// The carry alone (the overflow flag of one addition).
    #[inline(always)]
    fn crosses(angle: i32, change: i32) -> bool {
        angle.checked_add(change).is_none()
    }

    #[inline(always)]
    fn advance(angle: i32, change: i32) -> (i32, i32) {
        match angle.checked_add(change) {
            Some(sum) => (sum, 0),
            None if change > 0 => (angle.wrapping_add(change), 1),
            None => (angle.wrapping_add(change), -1),
        }
    }
}
