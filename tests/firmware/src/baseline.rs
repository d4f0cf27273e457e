//! The baselines of the firmware test: what open motor-control firmware does instead of an
//! angle tracking observer (the ODrive style). The angle of each sample is computed by an
//! arctangent, then tracked by a 2nd-order phase-locked loop:
//!
//! ```text
//! predicted   = angle + Ts * speed
//! phase_error = wrap(atan2(y_s, y_c) - predicted)
//! angle       = wrap(predicted + kp Ts * phase_error)     (turns counted at each wrap)
//! speed      += ki Ts * phase_error
//! ```
//!
//! with `kp = 2 bandwidth` and `ki = bandwidth^2` (critically damped, natural frequency
//! `bandwidth`). Written once, generic over the arctangent ([`Atan2`]): `libm`'s `atan2f`
//! ([`LibmAtan2`]) or a fast polynomial ([`FastAtan2`]).

use core::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

use angletrack_core::Float;

/// A four-quadrant arctangent in `f32`.
pub trait Atan2 {
    /// `atan2(y, x)` (rad, in [-pi, pi]).
    fn atan2(y: f32, x: f32) -> f32;
}

/// `libm`'s `atan2f` (within an ulp or two).
#[derive(Debug, Clone, Copy)]
pub struct LibmAtan2;

impl Atan2 for LibmAtan2 {
    #[inline(always)]
    fn atan2(y: f32, x: f32) -> f32 {
        Float::atan2(y, x)
    }
}

/// A fast arctangent: the octant's ratio `r = min(|x|, |y|) / max(|x|, |y|)` in [0, 1],
/// `atan(r) ~ pi/4 r + r (1 - r) (0.2447 + 0.0663 r)` (Rajan, Wang, Inkol and Joyal,
/// *Efficient approximations for the arctangent function*, 2006: within 1.5e-3 rad), then
/// the octant's symmetries. The firmware's `check` measures its largest error against
/// `atan2f` ([`FAST_ATAN2_MAX_ERROR_RAD`] is the bound it enforces).
#[derive(Debug, Clone, Copy)]
pub struct FastAtan2;

/// The largest error (rad) of [`FastAtan2`] that the firmware's `check` accepts.
pub const FAST_ATAN2_MAX_ERROR_RAD: f32 = 1.6e-3;

impl Atan2 for FastAtan2 {
    #[inline(always)]
    fn atan2(y: f32, x: f32) -> f32 {
        let (ax, ay) = (x.abs(), y.abs());
        let (small, large) = if ay > ax { (ax, ay) } else { (ay, ax) };
        // 0 / 0 (the origin) is NaN: give angle 0 there, as atan2f does.
        let r = if large > 0.0 { small / large } else { 0.0 };
        let mut a = r * (FRAC_PI_4 + (1.0 - r) * (0.2447 + 0.0663 * r));
        if ay > ax {
            a = FRAC_PI_2 - a;
        }
        if x < 0.0 {
            a = PI - a;
        }
        if y < 0.0 { -a } else { a }
    }
}

/// The loop's per-sample gains, from its bandwidth and the sample period.
#[derive(Debug, Clone, Copy)]
pub struct PhaseLockedLoop<A> {
    /// `Ts` (s): the angle advance per unit of speed.
    sample_period_s: f32,
    /// `kp Ts = 2 bandwidth Ts`: the angle's share of the phase error.
    angle_gain: f32,
    /// `ki Ts = bandwidth^2 Ts` (1/s): the speed's share of the phase error.
    speed_gain: f32,
    atan2: core::marker::PhantomData<A>,
}

/// The loop's state: the angle in [-pi, pi), whole turns, speed.
#[derive(Debug, Clone, Copy, Default)]
pub struct PllState {
    /// Angle (rad, in [-pi, pi)).
    pub angle: f32,
    /// Whole turns.
    pub turns: i32,
    /// Speed (rad/s).
    pub speed: f32,
}

impl<A: Atan2> PhaseLockedLoop<A> {
    /// The critically damped loop of natural frequency `bandwidth_rad_s` (rad/s) at
    /// `sample_period_s` (s).
    pub fn new(bandwidth_rad_s: f32, sample_period_s: f32) -> Self {
        Self {
            sample_period_s,
            angle_gain: 2.0 * bandwidth_rad_s * sample_period_s,
            speed_gain: bandwidth_rad_s * bandwidth_rad_s * sample_period_s,
            atan2: core::marker::PhantomData,
        }
    }

    /// One sample `(y_c, y_s)`: the state moves to the new estimate, which it is.
    #[inline(always)]
    pub fn update(&self, state: &mut PllState, y_c: f32, y_s: f32) {
        let predicted = state.angle + self.sample_period_s * state.speed;
        let mut phase_error = A::atan2(y_s, y_c) - predicted;
        // The measurement is in [-pi, pi] and the prediction within a step of it: one turn
        // at most either way.
        if phase_error >= PI {
            phase_error -= TAU;
        } else if phase_error < -PI {
            phase_error += TAU;
        }
        let mut angle = predicted + self.angle_gain * phase_error;
        if angle >= PI {
            angle -= TAU;
            state.turns += 1;
        } else if angle < -PI {
            angle += TAU;
            state.turns -= 1;
        }
        state.angle = angle;
        state.speed += self.speed_gain * phase_error;
    }
}
