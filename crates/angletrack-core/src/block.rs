//! The block form of the one-channel update (`update.rs`): [`Gains::update_block`] runs
//! [`Gains::update`] over slices of samples, the state kept in a local copy so that it can
//! live in registers for the whole block.

use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// Runs the observer over a block of samples into `out`; no allocation. Processes
    /// `min(y_c.len(), y_s.len(), out.len())` samples and returns that count.
    ///
    /// ```
    /// use angletrack_core::{Estimate, Gains, ObserverState};
    /// let gains = Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let mut state = ObserverState::new();
    /// let mut out = [Estimate::default(); 3];
    /// let n = gains.update_block(&mut state, &[1.0, 1.0, 1.0], &[0.0, 0.0, 0.0], &mut out);
    /// assert_eq!(n, 3);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn update_block(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: &[T],
        y_s: &[T],
        out: &mut [Estimate<T>],
    ) -> usize {
        let mut local = *state;
        let mut n = 0;
        for ((&c, &s), slot) in y_c.iter().zip(y_s).zip(out.iter_mut()) {
            *slot = self.update_observing(&mut local, c, s, ());
            n += 1;
        }
        *state = local;
        n
    }
}
