//! Angles kept in [-pi, pi) with the whole turns counted apart (`docs/theory.md §5`): the
//! wrap of the recursion's predicted angle, for a single channel ([`FullWrap`]) and for the
//! lanes of a bank ([`NoWrap`], the lanes outside wrapped first by [`FullWrap`]), the wrap of an angle as read, and the
//! angle `atan2(y_s, y_c)` of a sample, which (re-)acquires a channel's angle; the first
//! sample's angle, the re-acquisition and the turns crossed on the way are written once over
//! [`TurnArithmetic`], which the floats and the fixed-point format (`fixed/turns.rs`) implement.

use crate::real::{ChainNumber, Float};

/// The angle arithmetic of the first sample, the re-acquisition and the turn count: rad for
/// the floats (an angle in [-pi, pi), the whole turns counted apart), the binary angle for the
/// fixed-point format's `i16` samples (2^32 per turn: it wraps by itself, and the turns it
/// crosses are its carries).
pub(crate) trait TurnArithmetic: ChainNumber {
    /// `atan2(y_s, y_c)` of a sample (NaN for a float sample that is not finite).
    fn atan2(y_c: Self, y_s: Self) -> Self::Angle;
    /// Whether an angle is a number (every binary angle is).
    fn is_finite(angle: Self::Angle) -> bool;
    /// Wraps `angle` into one turn; returns the whole turns removed.
    fn wrap(angle: &mut Self::Angle) -> i32;
    /// `to - from`, wrapped into one turn: the shortest way from `from` to `to`.
    fn difference(to: Self::Angle, from: Self::Angle) -> Self::Angle;
    /// `angle + change` wrapped into one turn, and the whole turns crossed on the way.
    fn advance(angle: Self::Angle, change: Self::Angle) -> (Self::Angle, i32);

    /// Whether [`TurnArithmetic::advance`] crosses a turn: the usual path's test, which
    /// counts nothing.
    #[inline(always)]
    fn crosses(angle: Self::Angle, change: Self::Angle) -> bool {
        Self::advance(angle, change).1 != 0
    }
}

impl<T: Float> TurnArithmetic for T {
    #[inline(always)]
    fn atan2(y_c: T, y_s: T) -> T {
        y_s.atan2(y_c)
    }

    #[inline(always)]
    fn is_finite(angle: T) -> bool {
        angle.is_finite()
    }

    #[inline(always)]
    fn wrap(angle: &mut T) -> i32 {
        wrap_angle(angle)
    }

    #[inline(always)]
    fn difference(to: T, from: T) -> T {
        let mut change = to - from;
        wrap_angle(&mut change);
        change
    }

    #[inline(always)]
    fn advance(angle: T, change: T) -> (T, i32) {
        let mut angle = angle + change;
        let whole = wrap_angle(&mut angle);
        (angle, whole)
    }
}

/// The whole turns (-1, 0 or 1) crossed from `from` to `to` by the shortest way.
#[inline(always)]
pub(crate) fn crossed_turns<A: TurnArithmetic>(from: A::Angle, to: A::Angle) -> i32 {
    A::advance(from, A::difference(to, from)).1
}

/// Whether a turn is crossed from `from` to `to` by the shortest way.
#[inline(always)]
pub(crate) fn crosses_turn<A: TurnArithmetic>(from: A::Angle, to: A::Angle) -> bool {
    A::crosses(from, A::difference(to, from))
}

/// A corrected angle `x0` of a state counting `turns` turns, as read: wrapped into
/// [-pi, pi), and the turn count with the wrap's whole turns.
#[inline(always)]
pub(crate) fn wrapped<T: Float>(x0: T, turns: i64) -> (T, i64) {
    // The usual case returns both as they are (no addition of zero turns on the way). The
    // test repeats `wrap_angle`'s on purpose: calling it and matching its zero costs 3
    // instructions per update on a Cortex-M4F (measured by tests/firmware).
    if x0.abs() < T::PI {
        return (x0, turns);
    }
    let (angle, whole) = wrap_whole_turns(x0);
    (angle, turns.wrapping_add(whole as i64))
}
/// Wraps `angle` into [-pi, pi) and returns the whole turns removed.
///
/// The usual case, no wrap, is one comparison and a branch; everything else is out of line
/// ([`wrap_whole_turns`]). A non-finite angle, or one too large for its turns to be counted,
/// becomes 0.
#[inline(always)]
pub(crate) fn wrap_angle<T: Float>(angle: &mut T) -> i32 {
    // One comparison: |a| < pi (false for NaN). The edge a = -pi takes the rare path, which
    // keeps it.
    if angle.abs() < T::PI {
        return 0;
    }
    let (wrapped, whole) = wrap_whole_turns(*angle);
    *angle = wrapped;
    whole
}

/// The angle of one sample, `atan2(y_s, y_c)` wrapped to [-pi, pi), and the whole turns the
/// wrap removed; `None` for a non-finite sample. Initialises single observers and banks; out
/// of line and a function of values only (see [`Gains::update`](crate::Gains::update)).
#[cold]
#[inline(never)]
pub(crate) fn sample_angle<A: TurnArithmetic>(y_c: A, y_s: A) -> Option<(A::Angle, i32)> {
    let mut angle = A::atan2(y_c, y_s);
    if !A::is_finite(angle) {
        return None;
    }
    let whole = A::wrap(&mut angle);
    Some((angle, whole))
}

/// At most one turn off [-pi, pi): `a - k 2 pi` for `k` in {-1, 0, 1}, by selects and no
/// branch (so that a loop over the lanes of a [`ChannelBank`](crate::ChannelBank)
/// vectorises), with 2 pi in two parts (Cody-Waite): `a - TAU_HI` is exact (Sterbenz), so the
/// wrapped angle loses no precision however many turns have been counted. Returns the
/// wrapped angle and `k`.
///
/// For |a| < [`one_turn_limit`] the result is in [-pi, pi): in `f32`, `TAU_LO < 0` and `PI` lies
/// above pi, so rounding cannot cross an edge; in `f64` it can, and
/// [`Float::ONE_TURN_EDGE_FIX`] adds the move by one more turn that puts it back.
#[inline(always)]
pub(crate) fn wrap_one_turn<T: Float>(a: T) -> (T, i32) {
    let up = a >= T::PI;
    let down = a < -T::PI;
    let k = if up {
        T::ONE
    } else if down {
        -T::ONE
    } else {
        T::ZERO
    };
    // k = 0 gives back a exactly.
    let wrapped = (a - k * T::TAU_HI) - k * T::TAU_LO;
    let whole = i32::from(up) - i32::from(down);
    if !T::ONE_TURN_EDGE_FIX {
        return (wrapped, whole);
    }
    let high = wrapped >= T::PI;
    let low = wrapped < -T::PI;
    let wrapped = if high {
        wrapped - T::TAU
    } else if low {
        wrapped + T::TAU
    } else {
        wrapped
    };
    (wrapped, whole + i32::from(high) - i32::from(low))
}

/// The largest |angle| (rad) [`wrap_one_turn`] is used on: 2.5 pi, a margin of half a turn
/// below where one turn would not be enough.
pub(crate) fn one_turn_limit<T: Float>() -> T {
    T::PI * T::from_f32(2.5)
}

/// The rare case of [`wrap_angle`]: `a` outside (-pi, pi), or not finite. Up to
/// [`one_turn_limit`], exactly as [`wrap_one_turn`] does (so a bank's lanes and a single
/// observer agree to the bit); more turns are counted with a floor.
#[cold]
#[inline(never)]
pub(crate) fn wrap_whole_turns<T: Float>(a: T) -> (T, i32) {
    if a.abs() < one_turn_limit() {
        return wrap_one_turn(a);
    }
    let whole = ((a + T::PI) * T::FRAC_1_TAU).floor_to_i32();
    let k = T::from_i32(whole);
    let mut wrapped = (a - k * T::TAU_HI) - k * T::TAU_LO;
    let mut whole = whole;
    // Rounding can leave the result on the far side of an edge.
    if wrapped >= T::PI {
        wrapped -= T::TAU;
        whole = whole.wrapping_add(1);
    }
    if wrapped < -T::PI {
        wrapped += T::TAU;
        whole = whole.wrapping_sub(1);
    }
    if wrapped >= -T::PI && wrapped < T::PI {
        (wrapped, whole)
    } else {
        // NaN, or a magnitude whose turns do not fit: k * 2 pi is not representable.
        (T::ZERO, 0)
    }
}

/// Re-acquisition after a false lock (`docs/theory.md §10`): the angle `atan2(y_s, y_c)`
/// reached from `angle` by the shortest way, and the whole turns crossed on the way (the
/// caller keeps speed and acceleration).
#[cold]
#[inline(never)]
pub(crate) fn re_acquired<A: TurnArithmetic>(angle: A::Angle, y_c: A, y_s: A) -> (A::Angle, i32) {
    A::advance(angle, A::difference(A::atan2(y_c, y_s), angle))
}

/// How a step wraps the predicted angle: [`FullWrap`] for a single channel, [`NoWrap`] for
/// the lanes of a bank (wrapped before the step where one needs it).
pub(crate) trait Wrap {
    /// Wraps `angle` into [-pi, pi); returns the whole turns removed.
    fn wrap<T: Float>(angle: &mut T) -> i32;
}

/// Any number of turns: a comparison and a branch, the rare case out of line.
pub(crate) struct FullWrap;

/// No wrap at all: for angles already in [-pi, pi), which the caller makes sure of (it is
/// then what [`FullWrap`] gives, to the bit).
pub(crate) struct NoWrap;

impl Wrap for NoWrap {
    #[inline(always)]
    fn wrap<T: Float>(_angle: &mut T) -> i32 {
        0
    }
}

impl Wrap for FullWrap {
    #[inline(always)]
    fn wrap<T: Float>(angle: &mut T) -> i32 {
        wrap_angle(angle)
    }
}

#[cfg(test)]
mod tests;
