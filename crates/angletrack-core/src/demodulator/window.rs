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
        xs: pairwise(pending.xs, last.xs, V::add_sum),
        xc: pairwise(pending.xc, last.xc, V::add_sum),
        x: pairwise(pending.x, last.x, V::add_sum),
        s: V::add_sum(pending.s, last.s),
        c: V::add_sum(pending.c, last.c),
    }
}

/// A segment's sums as a window's.
#[inline(always)]
fn widen<V: DemodulatorNumber>(segment: &Sums<V::Sum>) -> Sums<V::Wide> {
    let [a, b] = segment.xs;
    let [c, d] = segment.xc;
    let [e, f] = segment.x;
    Sums {
        xs: [V::widen(a), V::widen(b)],
        xc: [V::widen(c), V::widen(d)],
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
        let length = (distance - 1) / step + 1;
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
                clip: segment.clip,
                ..PendingWindow::default()
            };
            if state.excitation {
                let (e, w) = (&segment.excitation, &mut pending.excitation);
                w.xs = V::widen(e.xs);
                w.xc = V::widen(e.xc);
                w.x = V::widen(e.x);
            }
            state.pending = pending;
            pair
        } else {
            let (p, r) = (&mut state.pending, &segment.sums);
            p.sums.xs = pairwise(p.sums.xs, r.xs, V::add_twice);
            p.sums.xc = pairwise(p.sums.xc, r.xc, V::add_twice);
            p.sums.x = pairwise(p.sums.x, r.x, V::add_twice);
            p.sums.s = V::add_twice(p.sums.s, r.s);
            p.sums.c = V::add_twice(p.sums.c, r.c);
            if state.excitation {
                let (w, e) = (&mut p.excitation, &segment.excitation);
                w.xs = V::add_twice(w.xs, e.xs);
                w.xc = V::add_twice(w.xc, e.xc);
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
        let excitation = if state.excitation {
            let (e, l) = (&pending.excitation, &last.excitation);
            let x = V::add_sum(e.x, l.x);
            Some((
                V::component(V::add_sum(e.xs, l.xs), x, sums.s, per_weight),
                V::component(V::add_sum(e.xc, l.xc), x, sums.c, per_weight),
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
        state.windows = state.windows.wrapping_add(1);
        if let Some(iq) = excitation {
            self.resolve_from_excitation(state, iq);
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
            | FrontEndFaults::when(clipped, FrontEndFaults::CLIPPING);
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
            faults,
        })
    }
}
