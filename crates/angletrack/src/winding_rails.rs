//! Clipping of a resolver's raw windings flagged without a stated ADC range, against the
//! rails measured as the samples come (`docs/theory.md §15`): the demodulator checks its
//! samples against one range, fixed when it is built; a capture that states none and holds
//! no rail in its first samples gives it a guess, which clipping that starts later (a gain
//! raised, a larger excitation) may never reach. [`WindingRails`] measures the rails on each
//! block of samples as it comes (the rule of [`measured_adc_range`](crate::measured_adc_range), a
//! winding held at a rail whatever the other does) and flags
//! [`FrontEndFaults::CLIPPING`] on every pair whose window holds a sample at a rail.

use std::collections::VecDeque;

use angletrack_core::{DemodulatedPair, Demodulator, DemodulatorState, FrontEndFaults};

use crate::rails::measured_winding_range;

/// The rails of a resolver's raw windings measured block by block, and the clipping they
/// show flagged on the demodulated pairs (see the module's documentation).
///
/// ```
/// use angletrack::WindingRails;
/// use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState, FrontEndFaults};
/// // Volts, a 10 kHz carrier at 160 kHz, amplitude 2 clipped at +-0.9; the demodulator's
/// // range a guess (-4 to 3) the clipping never reaches.
/// let settings = DemodulatorSettings::new(10e3, 160e3, 2.0, -4.0, 3.0);
/// let demodulator = Demodulator::<f64>::new(settings)?;
/// let (mut state, mut rails) = (DemodulatorState::new(), WindingRails::new());
/// let carrier = |k: usize| (std::f64::consts::TAU * k as f64 / 16.0).sin();
/// let c: Vec<f64> = (0..1600).map(|k| (2.0 * carrier(k)).clamp(-0.9, 0.9)).collect();
/// let s = vec![0.0; 1600];
/// let mut flagged = 0;
/// rails.push_block(&demodulator, &mut state, &c, &s, None, |pair| {
///     flagged += usize::from(pair.faults.contains(FrontEndFaults::CLIPPING));
/// });
/// assert_eq!(rails.rails(), Some((-0.9, 0.9)));
/// assert!(flagged > 70, "{flagged}");
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct WindingRails {
    /// The rails found so far: `(low, high)`, a side without a rail put beyond the samples.
    rails: Option<(f64, f64)>,
    /// The indices of the clipped samples a window still to complete may hold, ascending.
    clipped: VecDeque<u64>,
    /// The samples booked so far (the index of the next one).
    booked: u64,
    /// The clipped samples found so far.
    clipped_samples: u64,
    /// The faults flagged since the start.
    latched: FrontEndFaults,
}

impl WindingRails {
    /// No rail found yet.
    ///
    /// ```
    /// assert_eq!(angletrack::WindingRails::new().rails(), None);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// The rails found so far, `(low, high)` (a side without a rail is put one span beyond
    /// the samples: it flags nothing); `None` before the first.
    pub fn rails(&self) -> Option<(f64, f64)> {
        self.rails
    }

    /// The samples found at a rail so far (a channel at or beyond it).
    pub fn clipped_samples(&self) -> u64 {
        self.clipped_samples
    }

    /// [`FrontEndFaults::CLIPPING`] if a pair was flagged so far.
    pub fn latched_faults(&self) -> FrontEndFaults {
        self.latched
    }

    /// [`Demodulator::push_block`] (or with the excitation's samples) with the rails measured
    /// on the block first, so that each of its samples is checked against the rails its own
    /// block shows: every pair whose window holds a sample with a channel at or beyond a
    /// rail is flagged [`FrontEndFaults::CLIPPING`]. Push every block of a run through the
    /// same `WindingRails` (the pairs' windows span blocks). Returns the samples processed
    /// (the shortest of the lengths).
    pub fn push_block(
        &mut self,
        demodulator: &Demodulator<f64>,
        state: &mut DemodulatorState<f64>,
        raw_c: &[f64],
        raw_s: &[f64],
        excitation: Option<&[f64]>,
        mut sink: impl FnMut(DemodulatedPair<f64>),
    ) -> usize {
        let n = raw_c
            .len()
            .min(raw_s.len())
            .min(excitation.map_or(usize::MAX, <[f64]>::len));
        let (c, s) = (&raw_c[..n], &raw_s[..n]);
        self.book(c, s);
        // A sample at a time: the pair's window ends at the sample that completes it.
        for k in 0..n {
            let pair = match excitation {
                Some(e) => demodulator.push_with_excitation(state, c[k], s[k], e[k]),
                None => demodulator.push(state, c[k], s[k]),
            };
            if let Some(mut pair) = pair {
                pair.faults |= self.faults_of_window(pair.first_sample, state.samples());
                sink(pair);
            }
        }
        n
    }

    /// Measures the rails on the samples `c`, `s` (those found before kept: a side's rail is
    /// the innermost found) and notes the indices of the samples at or beyond one.
    fn book(&mut self, c: &[f64], s: &[f64]) {
        if let Some((low, high)) = measured_winding_range(c, s) {
            self.rails = Some(match self.rails {
                Some((l, h)) => (l.max(low), h.min(high)),
                None => (low, high),
            });
        }
        if let Some((low, high)) = self.rails {
            let at_rail = |v: f64| v <= low || v >= high;
            for (k, (&c, &s)) in c.iter().zip(s).enumerate() {
                if at_rail(c) || at_rail(s) {
                    self.clipped.push_back(self.booked + k as u64);
                    self.clipped_samples += 1;
                }
            }
        }
        self.booked += c.len() as u64;
    }

    /// [`FrontEndFaults::CLIPPING`] if a clipped sample is among `first..end` (a window's
    /// samples); the clipped samples before `first` are forgotten (windows complete in order
    /// of their first samples).
    fn faults_of_window(&mut self, first: u64, end: u64) -> FrontEndFaults {
        while self.clipped.front().is_some_and(|&j| j < first) {
            self.clipped.pop_front();
        }
        let faults = if self.clipped.front().is_some_and(|&j| j < end) {
            FrontEndFaults::CLIPPING
        } else {
            FrontEndFaults::NONE
        };
        self.latched |= faults;
        faults
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::DemodulatorSettings;

    /// Raw windings in volts at 16 samples per carrier period, the shaft at 50 rev/s (0.002
    /// turn a sample), amplitude `amplitude(k)`, clipped at +-0.9.
    fn windings(n: usize, amplitude: impl Fn(usize) -> f64) -> (Vec<f64>, Vec<f64>) {
        windings_at(n, amplitude, 0.3)
    }

    /// [`windings`] with the carrier's phase at the first sample `phase` (rad).
    fn windings_at(n: usize, amplitude: impl Fn(usize) -> f64, phase: f64) -> (Vec<f64>, Vec<f64>) {
        let tau = std::f64::consts::TAU;
        let at = |k: usize, angle: fn(f64) -> f64| {
            let carrier = (tau * k as f64 / 16.0 + phase).sin();
            (amplitude(k) * angle(tau * 0.002 * k as f64) * carrier).clamp(-0.9, 0.9)
        };
        (
            (0..n).map(|k| at(k, f64::cos)).collect(),
            (0..n).map(|k| at(k, f64::sin)).collect(),
        )
    }

    /// The pairs of `c`, `s` pushed in blocks of `block` samples: `(first sample, faults)`.
    fn pairs(c: &[f64], s: &[f64], block: usize) -> (WindingRails, Vec<(u64, FrontEndFaults)>) {
        let settings = DemodulatorSettings::new(10e3, 160e3, 0.7, -2.0, 1.0);
        let demodulator = Demodulator::<f64>::new(settings).unwrap();
        let (mut state, mut rails) = (DemodulatorState::new(), WindingRails::new());
        let mut out = Vec::new();
        for (c, s) in c.chunks(block).zip(s.chunks(block)) {
            let pushed = rails.push_block(&demodulator, &mut state, c, s, None, |p| {
                out.push((p.first_sample, p.faults))
            });
            assert_eq!(pushed, c.len());
        }
        assert_eq!(state.samples(), c.len() as u64);
        (rails, out)
    }

    #[test]
    fn clipping_that_starts_in_a_later_block_flags_the_windows_that_hold_it() {
        // Clean (0.7) for 8,000 samples, then 1.2 clipped at +-0.9; blocks of 5,000, so the
        // clipping starts part way through the second.
        let (c, s) = windings(16_000, |k| if k < 8_000 { 0.7 } else { 1.2 });
        let clipped: Vec<bool> = c
            .iter()
            .zip(&s)
            .map(|(c, s)| c.abs() >= 0.9 || s.abs() >= 0.9)
            .collect();
        assert!(!clipped[..8_000].contains(&true));
        let (rails, pairs) = pairs(&c, &s, 5_000);
        assert_eq!(rails.rails(), Some((-0.9, 0.9)));
        assert_eq!(
            rails.clipped_samples(),
            clipped.iter().filter(|&&x| x).count() as u64
        );
        // A window is a period and a quarter, 20 samples here (one more or less as the loop
        // moves): a pair whose first 19 samples hold a clipped one is flagged; one whose
        // 22 samples from its first hold none is not.
        let holds = |first: u64, length: usize| {
            let first = first as usize;
            clipped[first..(first + length).min(clipped.len())].contains(&true)
        };
        let (mut surely_held, mut surely_clean) = (0, 0);
        for &(first, faults) in &pairs {
            let flagged = faults.contains(FrontEndFaults::CLIPPING);
            if holds(first, 19) {
                assert!(flagged, "the window from sample {first}");
                surely_held += 1;
            } else if !holds(first, 22) {
                assert!(!flagged, "the window from sample {first}");
                surely_clean += 1;
            }
        }
        assert!(
            surely_held > 300 && surely_clean > 300,
            "{surely_held} {surely_clean}"
        );
        assert_eq!(rails.latched_faults(), FrontEndFaults::CLIPPING);
    }

    #[test]
    fn a_rail_is_a_carrier_peak_held_over_4_samples() {
        // At 16 samples per period 4 samples span 3/16 to 4/16 of a period, where they fall:
        // a peak holds them at the rail once the carrier is driven 1/cos(33.75 degrees) =
        // 1.08 to 1/cos(45 degrees) = 1.41 times past it (docs/guide/cli.md). Found at 1.5
        // wherever the samples fall, never at 1.05.
        for phase in [0.0, 0.1, 0.2, 0.3] {
            for (amplitude, found) in [(1.5, Some((-0.9, 0.9))), (1.05, None)] {
                let (c, s) = windings_at(16_000, |_| amplitude, phase);
                assert_eq!(
                    pairs(&c, &s, 16_000).0.rails(),
                    found,
                    "{amplitude} {phase}"
                );
            }
        }
    }

    #[test]
    fn clean_windings_flag_nothing_and_blocks_give_the_pairs_of_one_push() {
        let (c, s) = windings(6_000, |_| 0.7);
        let (rails, whole) = pairs(&c, &s, 6_000);
        assert_eq!((rails.rails(), rails.clipped_samples()), (None, 0));
        assert!(whole.iter().all(|p| p.1.is_empty()) && whole.len() > 300);
        // The same pairs in blocks of 7 samples as in one block.
        assert_eq!(pairs(&c, &s, 7).1, whole);
    }
}
