//! The demodulator's carrier loop (`docs/theory.md §13`): the phase and step of its
//! oscillator corrected once per window from the phase detector `sum I Q / sum (I^2 + Q^2)`
//! (`sin(2e)/2` for a phase error `e`), and the carrier's half turn resolved from the
//! recorded excitation or, at the end of the start-up, from the expected delay.

use super::{Demodulator, DemodulatorNumber, DemodulatorState, QUARTER};
use crate::fixed::wide_product;

/// The largest phase correction per window (a sixteenth of a turn).
const MAX_CORRECTION: i32 = 1 << 28;

impl<V: DemodulatorNumber> Demodulator<V> {
    /// The loop's correction from a window's detector products (`in_phase` and
    /// `quadrature` powers, their `cross` product, the `power`), while the carrier is there;
    /// `full` for a window of full (not weak) excitation.
    #[inline(always)]
    pub(super) fn track_carrier(
        &self,
        state: &mut DemodulatorState<V>,
        in_phase: V::Wide,
        quadrature: V::Wide,
        cross: V::Wide,
        power: V::Wide,
        full: bool,
    ) {
        if !state.delay_ready && state.windows.is_multiple_of(2) && in_phase < quadrature {
            // Acquiring a quarter turn off, where the detector's error vanishes too
            // (unstably): a quarter turn on (not on the next window, which holds samples
            // from before).
            state.phase = state.phase.wrapping_add(QUARTER);
        } else {
            // sum I Q / sum (I^2 + Q^2) = sin(2e) / 2, about e (rad), in Q31.
            self.correct(state, V::ratio_q31(cross, power), full);
        }
    }

    /// The carrier loop's correction for a phase error `error` (Q31 rad): the phase now,
    /// the step (within the carrier error allowed) from the next sample on.
    ///
    /// A window of weak excitation (one that straddles the onset or the end of a loss, or a
    /// carrier fading) corrects the phase only: its error is too unsure for the frequency.
    /// A window of full excitation also moves the held step (the frequency the loop keeps
    /// through a loss) 1/64 of the way to the loop's.
    #[inline(always)]
    fn correct(&self, state: &mut DemodulatorState<V>, error: i32, full: bool) {
        // 32 by 32 bits into 64 (one instruction where the core has it, four 16-bit
        // products on ARMv6-M), the rest in 32 bits: |error| <= 2^31 times the proportional
        // gain, at most sqrt(2) 0.5 / pi in Q16 (below 2^14), over 2^16 is below 2^29; times
        // the integral gain, at most 0.5^2 / pi / 4 in Q24 (below 2^18.4), over 2^24 below
        // 2^25.4; the steps are below 0.3 turn (2^30.3: 4 samples a period or more, a carrier
        // error of 0.2 at most): the same integers as in 64 bits.
        let phase = (wide_product(error, self.phase_gain) >> 16) as i32;
        let phase = phase.clamp(-MAX_CORRECTION, MAX_CORRECTION);
        state.phase = state.phase.wrapping_add(phase as u32);
        if full {
            let change = (wide_product(error, self.step_gain) >> 24) as i32;
            let step = (state.step as i32).wrapping_add(change);
            state.step = step.max(self.step_min as i32).min(self.step_max as i32) as u32;
            let held = state.held_step as i32;
            let toward = (state.step as i32).wrapping_sub(held) >> 6;
            state.held_step = held.wrapping_add(toward) as u32;
        }
    }

    /// A window's excitation components `(I, Q)` against the loop's phase: kept for the
    /// delay, and from the end of the start-up the half turn taken from them. Returns
    /// whether they decide it: not when the delay after the excitation is within 14 degrees
    /// (`atan(1/4)`) of a quarter turn from the expected one, where noise would choose either
    /// half turn window by window; the one last decided is then kept.
    #[inline(always)]
    pub(super) fn resolve_from_excitation(
        &self,
        state: &mut DemodulatorState<V>,
        (i, q): (V::Wide, V::Wide),
    ) -> bool {
        state.excitation_iq = (i, q);
        // cos and sin of (the delay after the excitation - expected), times its amplitude:
        // cos < 0, the loop holds the other half turn.
        let along = V::sub(
            V::times_fraction(i, self.expected_cos),
            V::times_fraction(q, self.expected_sin),
        );
        let across = V::add(
            V::times_fraction(i, self.expected_sin),
            V::times_fraction(q, self.expected_cos),
        );
        let zero = V::Wide::default();
        let magnitude = |x: V::Wide| if x < zero { V::sub(zero, x) } else { x };
        let (a, c) = (magnitude(along), magnitude(across));
        // 4 a >= c, each step within the fixed point's i32 (a and c below 2^30.6,
        // `number_fixed.rs`): c - 2 a > -a; past it a < c / 2, so 2 a fits.
        let decided = a >= c || {
            let rest = V::sub(V::sub(c, a), a);
            rest <= zero || rest <= V::add(a, a)
        };
        if decided && (state.delay_ready || state.windows >= u64::from(self.startup_periods)) {
            state.flip = along < zero;
            state.reference_resolved = true;
        }
        decided
    }

    /// The end of the start-up: unless a recorded excitation resolved it, the half turn whose
    /// phase at the first sample (the loop's phase taken back at its step) is within a
    /// quarter turn of the expected delay.
    #[cold]
    #[inline(never)]
    pub(super) fn resolve(&self, state: &mut DemodulatorState<V>) {
        let back = state.sample.wrapping_mul(u64::from(state.step)) as u32;
        let mut delay = state.phase.wrapping_sub(back);
        if !state.reference_resolved {
            state.flip = (delay.wrapping_sub(self.expected) as i32).unsigned_abs() > QUARTER;
        }
        if state.flip {
            delay = delay.wrapping_add(2 * QUARTER);
        }
        state.startup_delay = delay;
        state.delay_ready = true;
    }
}
