//! The state of one fixed-point channel ([`FixedState`]) and what the fixed-point update
//! reports ([`FixedEstimate`]), in the integers of `docs/theory.md §14`.

use super::update::MONITOR_WINDOW;
use crate::faults::Faults;

/// The mutable state of one fixed-point observer channel: the integer state vector (binary
/// angle, speed, acceleration), the next sample's predicted binary angle, the reciprocal of
/// the signal's magnitude, the turn count and the monitor's filters.
///
/// ```
/// use angletrack_core::{FixedGains, FixedState};
/// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
/// let mut state = FixedState::new();
/// let e = gains.update(&mut state, 0, 16384);
/// // A quarter turn, (cos, sin) = (0, 1), to within 2^-26 of a turn:
/// assert!((e.angle - (1 << 30)).abs() < 64);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedState<const N: usize> {
    /// Binary angle (2^32 per turn, wrapping), speed (2^-32 turn per sample), acceleration
    /// (2^-(32 + F) turn per sample^2).
    pub(crate) x: [i32; N],
    /// The predicted binary angle of the next sample.
    pub(crate) next_angle: i32,
    /// `2^27 / amplitude` (amplitude in counts), tracked by one Newton step per sample.
    pub(crate) reciprocal: i32,
    /// Whole turns of the binary angle `x[0]` since initialisation.
    pub(crate) turns: i64,
    /// The last sample's normalised phase error (Q15).
    pub(crate) phase_error: i32,
    /// The faults of the monitor's last window.
    pub(crate) faults: Faults,
    /// Faults latched since the last [`FixedState::clear_faults`].
    pub(crate) latched: Faults,
    /// The monitor's sum of `|eps|` (Q15) over the current window.
    pub(crate) error_sum: i32,
    /// Samples left in the monitor's window (its flags are decided when this reaches 0).
    pub(crate) window_left: u32,
    /// Whether the first sample has set the angle.
    pub(crate) initialised: bool,
}

impl<const N: usize> Default for FixedState<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> FixedState<N> {
    /// A state waiting for its first sample (which sets the angle from `atan2`).
    pub const fn new() -> Self {
        Self {
            x: [0; N],
            next_angle: 0,
            reciprocal: 1 << 13,
            turns: 0,
            phase_error: 0,
            faults: Faults::NONE,
            latched: Faults::NONE,
            error_sum: 0,
            window_left: MONITOR_WINDOW,
            initialised: false,
        }
    }

    /// The faults latched since the last clear.
    pub fn latched_faults(&self) -> Faults {
        self.latched
    }

    /// Clears the latched faults.
    pub fn clear_faults(&mut self) {
        self.latched = Faults::NONE;
    }

    /// The tracked reciprocal `2^27 / amplitude` (amplitude in counts), in
    /// [`MIN_RECIPROCAL`](crate::fixed::MIN_RECIPROCAL),
    /// [`MAX_RECIPROCAL`](crate::fixed::MAX_RECIPROCAL).
    pub fn reciprocal(&self) -> i32 {
        self.reciprocal
    }
}

/// What the fixed-point observer knows after a sample, in its integers
/// (`docs/theory.md §14`); [`FixedGains`](crate::FixedGains) converts them to physical
/// units on a host.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FixedEstimate {
    /// Binary angle (2^32 per turn; `i32::MIN` is -pi).
    pub angle: i32,
    /// Whole turns since initialisation: the position is `turns + angle / 2^32` turns, exact.
    pub turns: i64,
    /// Speed (2^-32 turn per sample).
    pub speed: i32,
    /// Acceleration (2^-(32 + F) turn per sample^2, `F` from
    /// [`FixedGains::acceleration_fraction_bits`](crate::FixedGains::acceleration_fraction_bits));
    /// 0 for a 2nd-order observer.
    pub acceleration: i32,
    /// Normalised phase error (Q15: 2^15 is 1), about `sin(theta - angle_p)`.
    pub phase_error: i32,
    /// The diagnostics of the monitor's last window (`docs/theory.md §14`).
    pub faults: Faults,
}
