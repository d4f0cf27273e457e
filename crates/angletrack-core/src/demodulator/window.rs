//! The demodulator's segments and windows (`docs/theory.md §13`): the samples are summed in
//! segments cut where the tracked carrier phase crosses a quarter and a whole turn; a window
//! is a period's first quarter (weight 1), the rest of the period (weight 2) and the next
//! first quarter (weight 1). Each window gives the components of both windings (their means
//! removed), the carrier loop's phase detector, the faults and the pair.

use super::{
    DemodulatedPair, Demodulator, DemodulatorNumber, DemodulatorState, PendingWindow, QUARTER,
    Segment, Sums,
};
use crate::front_end_faults::FrontEndFaults;

/// The sums of a window: the pending window's and the last first quarter's.
#[inline(always)]
fn complete<V: DemodulatorNumber>(pending: &Sums<V::Wide>, last: &Sums<V::Sum>) -> Sums<V::Wide> {
    Sums {
        xs: pairwise(pending.xs, last.xs, add_product::<V>),
        xc: pairwise(pending.xc, last.xc, add_product::<V>),
        x: pairwise(pending.x, last.x, V::add_sum),
        s: V::add_sum(pending.s, last.s),
        c: V::add_sum(pending.c, last.c),
    }
}

/// A segment's sum of products as a window's.
#[inline(always)]
fn widen_product<V: DemodulatorNumber>(x: V::Sum) -> V::Wide {
    V::widen(V::product_sum(x))
}

/// `acc + x` for a segment's sum of products `x`.
#[inline(always)]
fn add_product<V: DemodulatorNumber>(acc: V::Wide, x: V::Sum) -> V::Wide {
    V::add_sum(acc, V::product_sum(x))
}

/// `acc + 2 x` for a segment's sum of products `x`.
#[inline(always)]
fn add_product_twice<V: DemodulatorNumber>(acc: V::Wide, x: V::Sum) -> V::Wide {
    V::add_twice(acc, V::product_sum(x))
}

/// A segment's sums as a window's.
#[inline(always)]
fn widen<V: DemodulatorNumber>(segment: &Sums<V::Sum>) -> Sums<V::Wide> {
    let [a, b] = segment.xs;
    let [c, d] = segment.xc;
    let [e, f] = segment.x;
    Sums {
        xs: [widen_product::<V>(a), widen_product::<V>(b)],
        xc: [widen_product::<V>(c), widen_product::<V>(d)],
        x: [V::widen(e), V::widen(f)],
        s: V::widen(segment.s),
        c: V::widen(segment.c),
    }
}

/// `f` on the windings' values of `a` and `b`, winding by winding.
#[inline(always)]
fn pairwise<A, B, C>(a: [A; 2], b: [B; 2], f: impl Fn(A, B) -> C) -> [C; 2] {
    let ([a0, a1], [b0, b1]) = (a, b);
    [f(a0, b0), f(a1, b1)]
}

/// The samples a segment takes at the loop's `step` (at least 1) to cover `distance` (1 to
/// 7/8 of a turn) of phase: `ceil(distance / step)`, the division's result. On ARMv6-M
/// (Cortex-M0/M0+, no divider: a 32-bit division is some 100 instructions) it is counted from
/// `guess`, the same kind of segment's last length (or 0), a sample at a time: the step
/// changes by a few percent between windows and a correction by at most a sixteenth of a
/// turn, so the count moves by a few samples at most. ARMv6-M is told apart as in
/// `fixed/multiply.rs`: the Arm architecture without 32-bit atomics.
#[inline(always)]
fn samples_to_reach(distance: u32, step: u32, guess: u32) -> u32 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        let _ = guess;
        (distance - 1) / step + 1
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        counted(distance, step, guess)
    }
}

/// [`samples_to_reach`] by counting from `guess` (taken within 1 to 128): `reach` is
/// `n step` throughout, in 64 bits (a guess from a slower step times this one may pass 2^32);
/// it ends at the least `n` with `n step >= distance`.
#[cfg_attr(
    not(all(target_arch = "arm", not(target_has_atomic = "32"))),
    allow(dead_code)
)]
#[inline(always)]
fn counted(distance: u32, step: u32, guess: u32) -> u32 {
    let mut n = guess.clamp(1, 128);
    // The loop's steps are below 0.3 turn (a carrier error of 0.2 at most and 4 samples a
    // period or more), an i32.
    let mut reach = crate::fixed::wide_product(n as i32, step as i32);
    let (distance, step) = (i64::from(distance), i64::from(step));
    if reach < distance {
        while reach < distance {
            reach += step;
            n += 1;
        }
    } else {
        while n > 1 {
            let below = reach - step;
            if below < distance {
                break;
            }
            (reach, n) = (below, n - 1);
        }
    }
    n
}

/// `2 rest + first + last` weighted sample offsets from the window's first sample, for
/// segments of `first`, `rest` and `last` samples: the centroid times the weight.
#[inline(always)]
fn centre_times_weight(first: u32, rest: u32, last: u32) -> u32 {
    let (a, b, c) = (first, rest, last);
    (a * a.wrapping_sub(1)) / 2
        + 2 * (b * a + b * b.wrapping_sub(1) / 2)
        + c * (a + b)
        + c * c.wrapping_sub(1) / 2
}

impl<V: DemodulatorNumber> Demodulator<V> {
    /// The next segment starts at the next sample: its length from the loop's phase and
    /// step (at least one sample).
    #[inline(always)]
    pub(super) fn begin_segment(&self, state: &mut DemodulatorState<V>) {
        let end = if state.in_first_quarter { QUARTER } else { 0 };
        let distance = end.wrapping_sub(state.phase);
        // A phase already past the end (a correction, or a step above a quarter turn)
        // leaves a segment of one sample.
        let limit = if state.in_first_quarter {
            QUARTER
        } else {
            3 * QUARTER + QUARTER / 2
        };
        let distance = if distance > limit { 1 } else { distance.max(1) };
        let step = state.step.max(1);
        // The same kind of segment's last length: the last first quarter's is the pending
        // window's, the last rest's is kept in the pending window until this one ends.
        let guess = if state.in_first_quarter {
            state.pending.quarter
        } else {
            state.pending.rest
        };
        let length = samples_to_reach(distance, step, guess);
        state.current = Segment {
            first: state.sample,
            length,
            ..Segment::default()
        };
        state.left = length;
    }

    /// A segment is complete: after a first quarter, a window, and the next window begins
    /// with it; after the rest of a period, into the window at weight 2.
    #[inline(never)]
    pub(super) fn end_of_segment(
        &self,
        state: &mut DemodulatorState<V>,
    ) -> Option<DemodulatedPair<V>> {
        let segment = &state.current;
        let pair = if state.in_first_quarter {
            let pair = if state.periods > 0 {
                self.window(state)
            } else {
                None
            };
            let segment = &state.current;
            let mut pending = PendingWindow {
                sums: widen::<V>(&segment.sums),
                first: segment.first,
                quarter: segment.length,
                rest: state.pending.rest,
                clip: segment.clip,
                ..PendingWindow::default()
            };
            if state.excitation {
                let (e, w) = (&segment.excitation, &mut pending.excitation);
                w.xs = widen_product::<V>(e.xs);
                w.xc = widen_product::<V>(e.xc);
                w.x = V::widen(e.x);
            }
            state.pending = pending;
            pair
        } else {
            let (p, r) = (&mut state.pending, &segment.sums);
            p.sums.xs = pairwise(p.sums.xs, r.xs, add_product_twice::<V>);
            p.sums.xc = pairwise(p.sums.xc, r.xc, add_product_twice::<V>);
            p.sums.x = pairwise(p.sums.x, r.x, V::add_twice);
            p.sums.s = V::add_twice(p.sums.s, r.s);
            p.sums.c = V::add_twice(p.sums.c, r.c);
            if state.excitation {
                let (w, e) = (&mut p.excitation, &segment.excitation);
                w.xs = add_product_twice::<V>(w.xs, e.xs);
                w.xc = add_product_twice::<V>(w.xc, e.xc);
                w.x = V::add_twice(w.x, e.x);
            }
            p.rest = segment.length;
            p.clip |= segment.clip;
            state.periods = state.periods.wrapping_add(1);
            None
        };
        state.in_first_quarter = !state.in_first_quarter;
        self.begin_segment(state);
        pair
    }

    /// The window of the pending period and the first quarter just completed: components,
    /// the carrier loop's correction, the faults, the pair.
    fn window(&self, state: &mut DemodulatorState<V>) -> Option<DemodulatedPair<V>> {
        let (pending, last) = (&state.pending, &state.current);
        let sums = complete::<V>(&pending.sums, &last.sums);
        let weight = 2 * pending.rest + pending.quarter + last.length;
        let per_weight = V::per_weight(weight);
        let scale = V::window_scale(per_weight, self.pair_gain);
        let components = |x: V::Wide, xs: V::Wide, xc: V::Wide| {
            let mean = V::mean(x, per_weight);
            (
                V::pair_component(xs, mean, sums.s, scale),
                V::pair_component(xc, mean, sums.c, scale),
            )
        };
        let ([x_c, x_s], [xs_c, xs_s], [xc_c, xc_s]) = (sums.x, sums.xs, sums.xc);
        let ((y_c, q_yc), (y_s, q_ys)) = (components(x_c, xs_c, xc_c), components(x_s, xs_s, xc_s));
        let clip = pending.clip | last.clip;
        let centre = centre_times_weight(pending.quarter, pending.rest, last.length);
        let first_sample = pending.first;
        let segment_samples = [pending.quarter, pending.rest, last.length];
        // The loop's phase and step over the window, before this window's correction.
        let (end_phase, phase_step) = (state.phase, state.step);
        let excitation = if state.excitation {
            let (e, l) = (&pending.excitation, &last.excitation);
            let x = V::add_sum(e.x, l.x);
            let (xs, xc) = (add_product::<V>(e.xs, l.xs), add_product::<V>(e.xc, l.xc));
            // Its carrier in the pair's unit (the windings' nominal amplitude 1): a flat,
            // missing or NaN reference gives no half turn.
            let mean = V::mean(x, per_weight);
            let (i, q) = (
                V::pair_component(xs, mean, sums.s, scale),
                V::pair_component(xc, mean, sums.c, scale),
            );
            let usable = V::add(V::product(i, i), V::product(q, q)) >= self.reference_power;
            Some((
                V::component(xs, x, sums.s, per_weight),
                V::component(xc, x, sums.c, per_weight),
                usable,
            ))
        } else {
            None
        };
        let in_phase = V::add(V::product(y_c, y_c), V::product(y_s, y_s));
        let quadrature = V::add(V::product(q_yc, q_yc), V::product(q_ys, q_ys));
        let power = V::add(in_phase, quadrature);
        let weak = !(power >= self.weak_power);
        let gone = !(power >= self.loss_power);
        // A weak window right after one without carrier, or with under 3/4 of the last
        // window's power (4 p < 3 p_last), holds a loss's end or onset: part of it has no
        // carrier, so its pair (stamped at the window's centroid, not at its carrier's) is
        // no measurement. A steady or slowly fading weak excitation is not lost.
        let twice = V::add(power, power);
        let last = state.last_power;
        let dropped = V::add(twice, twice) < V::add(V::add(last, last), last);
        let lost = gone || (weak && (state.last_lost || dropped));
        (state.last_power, state.last_lost) = (power, gone);
        let clipped = clip >> 31 != 0 || !V::is_finite(power);
        // cos 2e (times the power) below cos(2 bound): out of lock.
        let drifted =
            !lost && V::sub(in_phase, quadrature) < V::times_fraction(power, self.drift_cos2);
        if lost {
            // Through the loss, at the frequency the loop held before it.
            state.step = state.held_step;
        } else {
            let cross = V::add(V::product(y_c, q_yc), V::product(y_s, q_ys));
            self.track_carrier(state, in_phase, quadrature, cross, power, !weak);
        }
        // The step held at a bound of the carrier error allowed: the carrier is beyond it, and
        // neither the loop's phase (lagging by what the bound leaves) nor the start-up's delay
        // (taken back at the bound's step) holds.
        let pinned = state.step == self.step_min || state.step == self.step_max;
        let drifted = drifted || (!lost && pinned);
        // The window after an out-of-lock one is flagged too: the loop's correction of a
        // large phase error shifts that window by a fraction of a period, and its pair, back
        // within the lock bound, is stamped at the wrong time (50 mrad electrical at 1 kHz
        // after a 60 degree carrier step; docs/guide/diagnostics.md).
        let (drifted, settling) = (drifted || state.last_drifted, drifted);
        state.last_drifted = settling;
        state.windows = state.windows.wrapping_add(1);
        let mut no_reference = false;
        if let Some((i, q, usable)) = excitation {
            let decided = usable && self.resolve_from_excitation(state, (i, q));
            no_reference = !decided || !state.reference_resolved;
        }
        if !state.delay_ready {
            if state.windows < u64::from(self.startup_periods) {
                return None;
            }
            self.resolve(state);
        }
        let (y_c, y_s, q_yc, q_ys) = if state.flip {
            (
                V::negate(y_c),
                V::negate(y_s),
                V::negate(q_yc),
                V::negate(q_ys),
            )
        } else {
            (y_c, y_s, q_yc, q_ys)
        };
        let faults = FrontEndFaults::when(lost, FrontEndFaults::LOSS_OF_EXCITATION)
            | FrontEndFaults::when(weak, FrontEndFaults::WEAK_EXCITATION)
            | FrontEndFaults::when(drifted, FrontEndFaults::PHASE_DRIFT)
            | FrontEndFaults::when(clipped, FrontEndFaults::CLIPPING)
            | FrontEndFaults::when(no_reference, FrontEndFaults::EXCITATION_REFERENCE);
        state.latched |= faults;
        Some(DemodulatedPair {
            y_c,
            y_s,
            quadrature_c: q_yc,
            quadrature_s: q_ys,
            window: state.windows - 1,
            first_sample,
            centre_offset_times_weight: centre,
            weight,
            segment_samples,
            end_phase,
            phase_step,
            faults,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{QUARTER, counted, samples_to_reach};
    use proptest::prelude::*;

    proptest! {
        /// From the last length of a segment (at a step within the loop's range) or none,
        /// the count is the division.
        #[test]
        fn counting_gives_the_division(
            distance in 1..=3 * QUARTER + QUARTER / 2,
            samples_per_period in 4.0..64.0_f64,
            error in 0.8..1.2_f64,
            last_error in 0.8..1.2_f64,
            last_distance in 1..=3 * QUARTER + QUARTER / 2,
        ) {
            let nominal = 4_294_967_296.0 / samples_per_period;
            let (step, last) = ((nominal * error) as u32, (nominal * last_error) as u32);
            for guess in [0, (last_distance - 1) / last + 1] {
                prop_assert_eq!(counted(distance, step, guess), (distance - 1) / step + 1);
                prop_assert_eq!(
                    samples_to_reach(distance, step, guess),
                    (distance - 1) / step + 1
                );
            }
        }
    }
}
