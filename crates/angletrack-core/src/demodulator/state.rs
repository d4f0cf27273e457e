//! The demodulator's outputs and mutable state (`docs/theory.md §13`): one demodulated pair
//! per carrier period, and the partial sums, carrier delay and faults kept between samples.

use crate::front_end_faults::FrontEndFaults;
use crate::real::Float;

/// One demodulated pair: the windings' envelopes at the centre of their window.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DemodulatedPair<T> {
    /// The cosine winding's envelope, `~ cos theta` (nominal amplitude 1).
    pub y_c: T,
    /// The sine winding's envelope, `~ sin theta`.
    pub y_s: T,
    /// The cosine winding's quadrature component (90 degrees from the delayed carrier):
    /// about 0; its size shows a delay error or a carrier distortion.
    pub quadrature_c: T,
    /// The sine winding's quadrature component.
    pub quadrature_s: T,
    /// The index of the window: window `p` starts at ADC sample `p N` and the pair holds at
    /// [`Demodulator::window_centre_s`](crate::Demodulator::window_centre_s)`(p)`.
    pub window: u64,
    /// The front end's faults of this window.
    pub faults: FrontEndFaults,
}

/// The mutable state of a [`Demodulator`](crate::Demodulator): partial sums, the carrier delay, the faults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemodulatorState<T> {
    pub(super) index: usize,
    pub(super) sums: [T; 4],
    pub(super) clipped: bool,
    pub(super) first_quarter: ([T; 4], bool),
    pub(super) previous_first_quarter: ([T; 4], bool),
    pub(super) previous_rest: ([T; 4], bool),
    pub(super) periods: u64,
    pub(super) startup_sum: (T, T),
    pub(super) delay: (T, T),
    pub(super) startup_delay: (T, T),
    pub(super) delay_ready: bool,
    pub(super) latched: FrontEndFaults,
}

impl<T: Float> Default for DemodulatorState<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Float> DemodulatorState<T> {
    /// A state at power-up: the next sample is the first of a carrier period (excitation
    /// phase 0), the delay not yet measured.
    pub const fn new() -> Self {
        let zero = ([T::ZERO; 4], false);
        Self {
            index: 0,
            sums: [T::ZERO; 4],
            clipped: false,
            first_quarter: zero,
            previous_first_quarter: zero,
            previous_rest: zero,
            periods: 0,
            startup_sum: (T::ZERO, T::ZERO),
            delay: (T::ONE, T::ZERO),
            startup_delay: (T::ONE, T::ZERO),
            delay_ready: false,
            latched: FrontEndFaults::NONE,
        }
    }

    /// `true` once the start-up delay estimate is done (pairs come out from then on).
    pub fn is_delay_ready(&self) -> bool {
        self.delay_ready
    }

    /// The carrier delay as tracked (rad, in [-pi, pi]); meant for diagnostics, not the
    /// per-sample path (one `atan2`).
    pub fn carrier_delay_rad(&self) -> T {
        self.delay.1.atan2(self.delay.0)
    }

    /// The carrier delay measured at start-up (rad, in [-pi, pi]).
    pub fn startup_delay_rad(&self) -> T {
        self.startup_delay.1.atan2(self.startup_delay.0)
    }

    /// The faults latched since they were last cleared.
    pub fn latched_faults(&self) -> FrontEndFaults {
        self.latched
    }

    /// Returns the latched faults and clears them.
    pub fn clear_faults(&mut self) -> FrontEndFaults {
        core::mem::take(&mut self.latched)
    }
}
