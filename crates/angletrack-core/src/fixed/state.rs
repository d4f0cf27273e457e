//! The state of one fixed-point channel ([`FixedState`]) and what the fixed-point update
//! reports ([`FixedEstimate`]), in the integers of `docs/theory.md §14`.

use crate::faults::Faults;
use crate::monitor::TrackingCheck;
use crate::reacquisition::FixedRefit;

/// The state vector of the fixed-point recursion: binary angle (2^32 per turn), speed
/// (2^-32 turn per sample) and acceleration (2^-63 turn per sample^2; 0 for a 2nd-order
/// observer), each wrapping: modulo one turn, one turn per sample and two turns per
/// sample^2, a lattice the recursion maps onto itself, so that a wrap changes nothing the
/// observer computes (`docs/theory.md §14`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(C)]
pub(crate) struct FixedVector {
    pub(crate) angle: i32,
    pub(crate) speed: i32,
    pub(crate) acceleration: i64,
}

/// The mutable state of one fixed-point observer channel: the integer state vector (binary
/// angle, speed, acceleration), the next sample's predicted binary angle, the reciprocal of
/// the signal's magnitude, the turn count and the monitor's window sums.
///
/// ```
/// use angletrack_core::{Chain, ChainState, FixedGains};
/// let chain = Chain::new((), FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?);
/// let mut state = ChainState::new(); // its `observer` is a `FixedState`
/// let e = chain.update(&mut state, (0, 16384));
/// // A quarter turn, (cos, sin) = (0, 1), to within 2^-26 of a turn:
/// assert!((e.angle - (1 << 30)).abs() < 64);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
// `repr(C)`: the fields the per-sample path reads and writes side by side, which a
// Cortex-M loads and stores with one instruction (the window's first, at offset 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C)]
pub struct FixedState<const N: usize> {
    /// The monitor's sum of `|eps|` (Q15, each term within one unit below) over the
    /// current window.
    pub(crate) error_sum: u32,
    /// Samples left in the window (its end: the reciprocal, the flags; the first sample's
    /// window has one sample, at whose end the state is initialised).
    pub(crate) window_left: u32,
    /// The last sample's normalised phase error (Q15).
    pub(crate) phase_error: i32,
    /// The last sample `(y_c, y_s)` (counts), from which the window's end reads the
    /// amplitude, the in-phase component, and the angle on the first sample and after a
    /// false lock.
    pub(crate) sample: [i16; 2],
    /// The predicted binary angle of the next sample.
    pub(crate) next_angle: i32,
    /// `2^27 / amplitude` (amplitude in counts), updated at each window's end.
    pub(crate) reciprocal: i32,
    /// The state vector (the corrected estimate of the last sample).
    pub(crate) x: FixedVector,
    /// Whole turns the binary angle crossed since initialisation (the position is
    /// `turns + angle / 2^32` turns).
    pub(crate) turns: i64,
    /// The faults of the monitor's last window.
    pub(crate) faults: Faults,
    /// Faults latched since the last [`FixedState::clear_faults`].
    pub(crate) latched: Faults,
    /// Window ends left that flag degradation after one whose last sample was off the
    /// circle (`crate::monitor::ROUNDNESS_HOLD_WINDOWS`).
    pub(crate) round_hold: u8,
    /// Whether the first sample has set the angle.
    pub(crate) initialised: bool,
    /// The samples coasted through front-end faults since the last used one (saturated):
    /// after a few, the next sample's window end sets the angle from its `atan2` (the
    /// speed and the acceleration kept); after many, the next samples are fitted first
    /// (`crate::reacquisition`).
    pub(crate) coasted: u16,
    /// The per-sample tracking-error check (`crate::monitor::TrackingCheck`), on `|eps|` in
    /// Q15; its flag is added to the window's in the estimate. Beside `coasted`, both 16
    /// bits: the state stays within the C API's storage for it.
    pub(crate) tracking: TrackingCheck<i16>,
    /// The fit under way after a long coast.
    pub(crate) refit: FixedRefit,
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
            // Above every threshold: the first window is not taken for a healthy one.
            error_sum: 1 << 31,
            window_left: 1,
            phase_error: 0,
            sample: [0; 2],
            next_angle: 0,
            reciprocal: 1 << 13,
            x: FixedVector {
                angle: 0,
                speed: 0,
                acceleration: 0,
            },
            turns: 0,
            faults: Faults::NONE,
            latched: Faults::NONE,
            round_hold: 0,
            tracking: TrackingCheck::new(),
            initialised: false,
            coasted: 0,
            refit: FixedRefit::new(),
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
    /// Acceleration (2^-63 turn per sample^2, wrapping modulo two turns per sample^2);
    /// 0 for a 2nd-order observer.
    pub acceleration: i64,
    /// Normalised phase error (Q15: 2^15 is 1), about `sin(theta - angle_p)`.
    pub phase_error: i32,
    /// The diagnostics of the monitor's last window (`docs/theory.md §14`).
    pub faults: Faults,
}
