//! The demodulator's per-sample path (`docs/theory.md §13`): each ADC sample of the windings
//! (and of the excitation) multiplied by the carrier loop's reference and summed into the
//! current segment, one sample at a time or a block (a DMA buffer) at a time.

use super::{DemodulatedPair, Demodulator, DemodulatorNumber, DemodulatorState, Segment};

impl<V: DemodulatorNumber> Demodulator<V> {
    /// One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
    /// winding, in counts, any offset). Returns a pair once per tracked carrier period,
    /// after the start-up; never panics. A NaN sample gives NaN pairs for the windows that
    /// hold it, flagged [`FrontEndFaults::CLIPPING`](crate::FrontEndFaults::CLIPPING) and
    /// [`FrontEndFaults::LOSS_OF_EXCITATION`](crate::FrontEndFaults::LOSS_OF_EXCITATION),
    /// and does not reach the carrier loop.
    #[inline]
    pub fn push(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
    ) -> Option<DemodulatedPair<V>> {
        self.push_one::<false>(state, raw_c, raw_s, V::default())
    }

    /// [`Demodulator::push`] with the excitation's sample taken at the same instant (any
    /// offset and amplitude): the carrier's half-turn ambiguity is resolved from it, every
    /// window. Push all samples of a run one way or the other.
    #[inline]
    pub fn push_with_excitation(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) -> Option<DemodulatedPair<V>> {
        self.push_one::<true>(state, raw_c, raw_s, excitation)
    }

    #[inline(always)]
    fn push_one<const E: bool>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) -> Option<DemodulatedPair<V>> {
        if state.left == 0 {
            self.start(state, E);
        }
        let mut segment = state.current;
        let mut phase = state.phase;
        self.accumulate::<E>(
            &mut segment,
            &mut phase,
            state.step,
            raw_c,
            raw_s,
            excitation,
        );
        state.current = segment;
        state.phase = phase;
        state.sample = state.sample.wrapping_add(1);
        state.left -= 1;
        if state.left == 0 {
            self.end_of_segment(state)
        } else {
            None
        }
    }

    /// One sample into a segment's sums, at the loop's `phase`, which it advances.
    #[inline(always)]
    fn accumulate<const E: bool>(
        &self,
        segment: &mut Segment<V::Sum>,
        phase: &mut u32,
        step: u32,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) {
        let table = V::sine_table();
        let index = (*phase >> 24) as usize;
        let (sin, cos) = (table[index], table[index + 64]);
        *phase = phase.wrapping_add(step);
        let (c, clip_c) = V::prepare(raw_c, self.clip_centre, self.clip_half_span);
        let (s, clip_s) = V::prepare(raw_s, self.clip_centre, self.clip_half_span);
        let sums = &mut segment.sums;
        V::mac(&mut sums.xs[0], c, sin);
        V::mac(&mut sums.xc[0], c, cos);
        V::mac(&mut sums.xs[1], s, sin);
        V::mac(&mut sums.xc[1], s, cos);
        V::accumulate(&mut sums.x[0], c);
        V::accumulate(&mut sums.x[1], s);
        V::accumulate(&mut sums.s, sin);
        V::accumulate(&mut sums.c, cos);
        if E {
            let sums = &mut segment.excitation;
            V::mac(&mut sums.xs, excitation, sin);
            V::mac(&mut sums.xc, excitation, cos);
            V::accumulate(&mut sums.x, excitation);
        }
        segment.clip |= clip_c | clip_s;
    }

    /// [`Demodulator::push`] over a block of ADC samples (a DMA buffer), calling
    /// `sink(pair)` for each pair that completes; no allocation. Processes
    /// `min(raw_c.len(), raw_s.len())` samples and returns that count, the same pairs as
    /// [`Demodulator::push`] on each sample.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState};
    /// // 10 kHz carrier at 150 kHz (15 samples per period), delay 0, shaft at 0.
    /// let demodulator = Demodulator::<f32>::new(DemodulatorSettings::new(10e3, 150e3, 1800.0, 0.0, 4095.0))?;
    /// let mut state = DemodulatorState::new();
    /// let raw_c: [f32; 15 * 40] = core::array::from_fn(|j| {
    ///     2048.0 + 1800.0 * (core::f32::consts::TAU * (j % 15) as f32 / 15.0).sin()
    /// });
    /// let raw_s = [2048.0_f32; 15 * 40];
    /// let mut pairs = 0;
    /// let n = demodulator.push_block(&mut state, &raw_c, &raw_s, |pair| {
    ///     assert!((pair.y_c - 1.0).abs() < 1e-2 && pair.y_s.abs() < 1e-3);
    ///     pairs += 1;
    /// });
    /// // 39 windows (each a period and the quarter after it), the first 23 for the start-up.
    /// assert_eq!((n, pairs), (600, 16));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn push_block<F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        sink: F,
    ) -> usize {
        self.run::<false, F>(state, raw_c, raw_s, &[], sink)
    }

    /// [`Demodulator::push_block`] with the excitation's samples (see
    /// [`Demodulator::push_with_excitation`]): `min` of the three lengths.
    #[inline]
    pub fn push_block_with_excitation<F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        excitation: &[V],
        sink: F,
    ) -> usize {
        self.run::<true, F>(state, raw_c, raw_s, excitation, sink)
    }

    #[inline(always)]
    fn run<const E: bool, F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        excitation: &[V],
        mut sink: F,
    ) -> usize {
        let mut n = raw_c.len().min(raw_s.len());
        if E {
            n = n.min(excitation.len());
        }
        let (mut c, mut s) = (raw_c.get(..n).unwrap_or(&[]), raw_s.get(..n).unwrap_or(&[]));
        let mut x = if E {
            excitation.get(..n).unwrap_or(&[])
        } else {
            &[]
        };
        while !c.is_empty() {
            if state.left == 0 {
                self.start(state, E);
            }
            // One segment (or what the block holds of it) at a time, its sums in locals: the
            // inner loop touches no memory but the samples and the reference table. It ends
            // at the segment's end or the block's, two exits: a loop the compiler does not
            // unroll, whose entry costs little (segments are a few samples long).
            let (mut segment, mut phase, step) = (state.current, state.phase, state.step);
            let mut left = state.left;
            let mut excitation = x.iter();
            for (&c, &s) in c.iter().zip(s) {
                let x = if E {
                    excitation.next().copied().unwrap_or_default()
                } else {
                    V::default()
                };
                self.accumulate::<E>(&mut segment, &mut phase, step, c, s, x);
                left -= 1;
                if left == 0 {
                    break;
                }
            }
            let count = state.left - left;
            (c, s) = (
                c.get(count as usize..).unwrap_or(&[]),
                s.get(count as usize..).unwrap_or(&[]),
            );
            if E {
                x = x.get(count as usize..).unwrap_or(&[]);
            }
            (state.current, state.phase, state.left) = (segment, phase, left);
            state.sample = state.sample.wrapping_add(u64::from(count));
            if left == 0
                && let Some(pair) = self.end_of_segment(state)
            {
                sink(pair);
            }
        }
        n
    }

    /// Before a run's first sample: the loop at the declared carrier, phase 0.
    #[cold]
    #[inline(never)]
    fn start(&self, state: &mut DemodulatorState<V>, excitation: bool) {
        state.step = self.step;
        state.held_step = self.step;
        state.excitation = excitation;
        state.in_first_quarter = true;
        self.begin_segment(state);
    }
}
