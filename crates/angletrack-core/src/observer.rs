//! [`Observer`]: gains and state bundled into one value, and [`AngleTrackingObserver`], the
//! trait for code that should not care which observer it runs.

use crate::faults::Faults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};

/// What every angle tracking observer does, whatever its order and gains: code that uses an
/// observer takes `impl AngleTrackingObserver<T>` and does not care which one it is.
pub trait AngleTrackingObserver<T: Float> {
    /// Feeds one sample (`y_c ~ cos theta`, `y_s ~ sin theta`) and returns the estimate.
    fn update(&mut self, y_c: T, y_s: T) -> Estimate<T>;
    /// Feeds a block of samples into `out`; returns the number processed,
    /// `min(y_c.len(), y_s.len(), out.len())`.
    fn update_block(&mut self, y_c: &[T], y_s: &[T], out: &mut [Estimate<T>]) -> usize;
    /// The current estimate, without a new sample.
    fn estimate(&self) -> Estimate<T>;
    /// Re-initialises the angle from one sample (`atan2(y_s, y_c)`), speed and acceleration 0.
    fn initialise(&mut self, y_c: T, y_s: T);
    /// Forgets everything: the next sample initialises the observer.
    fn reset(&mut self);
    /// The faults latched since they were last cleared.
    fn latched_faults(&self) -> Faults;
    /// Returns the latched faults and clears them.
    fn clear_faults(&mut self) -> Faults;
    /// The sample period (s).
    fn sample_period(&self) -> T;
    /// The order of the loop: 2 (angle, speed) or 3 (angle, speed, acceleration).
    fn order(&self) -> usize;
}

/// An angle tracking observer: immutable [`Gains`] and its mutable [`ObserverState`].
///
/// `N = 2` is the classical type II ATO, `N = 3` the 3rd-order ATO; the continuous-design
/// and the Kalman 3rd-order observers differ only by their gains. `S` picks the phase
/// detector's sin/cos ([`Fast`](crate::Fast) by default on `f32`,
/// [`Exact`](crate::Exact) on `f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observer<T: Float, const N: usize, S = <T as Float>::DefaultSinCos> {
    /// The gains (immutable; replace them to retune).
    pub gains: Gains<T, N, S>,
    /// The state.
    pub state: ObserverState<T, N>,
}

/// The classical 2nd-order (type II) angle tracking observer.
pub type SecondOrderObserver<T, S = <T as Float>::DefaultSinCos> = Observer<T, 2, S>;
/// The 3rd-order (type III) angle tracking observer: continuous design by pole placement, or
/// the time-invariant Kalman ATO (same recursion, Kalman gains).
pub type ThirdOrderObserver<T, S = <T as Float>::DefaultSinCos> = Observer<T, 3, S>;

impl<T: Float, const N: usize, S: SinCos<T>> Observer<T, N, S> {
    /// An observer with the given gains, initialised by its first sample.
    ///
    /// ```
    /// use angletrack_core::{AngleTrackingObserver, Gains, Observer};
    /// let mut ato = Observer::new(Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?);
    /// let estimate = ato.update(0.0, -1.0);
    /// assert!((estimate.angle + core::f32::consts::FRAC_PI_2).abs() < 1e-6);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new(gains: Gains<T, N, S>) -> Self {
        Self {
            gains,
            state: ObserverState::new(),
        }
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> AngleTrackingObserver<T> for Observer<T, N, S> {
    #[inline]
    fn update(&mut self, y_c: T, y_s: T) -> Estimate<T> {
        self.gains.update(&mut self.state, y_c, y_s)
    }

    fn update_block(&mut self, y_c: &[T], y_s: &[T], out: &mut [Estimate<T>]) -> usize {
        self.gains.update_block(&mut self.state, y_c, y_s, out)
    }

    fn estimate(&self) -> Estimate<T> {
        self.gains.estimate(&self.state)
    }

    fn initialise(&mut self, y_c: T, y_s: T) {
        self.gains.initialise(&mut self.state, y_c, y_s);
    }

    fn reset(&mut self) {
        self.state = ObserverState::new();
    }

    fn latched_faults(&self) -> Faults {
        self.state.latched_faults()
    }

    fn clear_faults(&mut self) -> Faults {
        self.state.clear_faults()
    }

    fn sample_period(&self) -> T {
        self.gains.sample_period
    }

    fn order(&self) -> usize {
        N
    }
}
