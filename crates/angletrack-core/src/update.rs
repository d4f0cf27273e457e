//! The float observers' per-sample update around the one recursion (`recursion.rs`,
//! `docs/theory.md §5`), on one channel: [`Gains::update`] and [`Gains::track`], their rare
//! cases (first sample, rejected sample, after a coast) in the order every observer takes
//! them (`update/driver.rs`, the floats' side in `update/coasting.rs`), and the windowed
//! monitor's decision with the re-acquisition after a false lock; the block forms are in
//! `block.rs`. A [`ChannelBank`](crate::ChannelBank) runs the same step on each of its
//! lanes, and this rare path on a lane that needs it.
//!
//! The update needs no [`SupportedOrder`](crate::SupportedOrder) bound: it is written for
//! any order `N`, and a [`Gains`] exists only for the orders its constructors accept.

use crate::faults::Faults;
use crate::gains::Gains;
use crate::monitor::MonitorWindow;
use crate::real::Float;
use crate::real::sincos::{SinCos, SinCosUnit};
use crate::recursion::{Sample, Step};
use crate::state::{Estimate, ObserverState, predict};
use crate::wrap::{FullWrap, NoWrap, Wrap, re_acquired, sample_angle, wrap_angle, wrapped};
use driver::Driver;

/// What [`Gains::track_observing`] shows of a used sample.
#[derive(Clone, Copy)]
pub(crate) struct UsedSample<T> {
    /// `(sin, cos)` of the sample's predicted angle.
    pub(crate) sin_cos: (T, T),
    /// The corrected speed in rad per sample (`Ts Omega`).
    pub(crate) scaled_speed: T,
    /// The sample's faults, as the monitor flagged them.
    pub(crate) faults: Faults,
    /// The sample's normalised phase error `eps` (the sine of the angle between the sample
    /// and its prediction).
    pub(crate) phase_error: T,
}

/// What [`Gains::track_observing`] shows each sample to: a trait rather than a closure,
/// so that its method can be inlined into the update's loop (a closure may stay a call).
pub(crate) trait SampleObserver<T> {
    /// One sample: `Some` for a used sample, `None` for one that was not used.
    fn observe(self, used: Option<UsedSample<T>>);

    /// Whether [`SampleObserver::observe`] reads the sample (`()` does not): what an
    /// observer computes only to show it is then not computed at all.
    #[inline(always)]
    fn observes(&self) -> bool {
        true
    }
}

impl<T> SampleObserver<T> for () {
    #[inline(always)]
    fn observe(self, _used: Option<UsedSample<T>>) {}

    #[inline(always)]
    fn observes(&self) -> bool {
        false
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// One sample of the observer: predict, detect the phase error, correct, monitor (what
    /// [`Chain::update`](crate::Chain::update) runs after its front end).
    ///
    /// ```text
    /// X_p = A X_e                      (Taylor step of the scaled state)
    /// eps = (y_s cos(x1_p) - y_c sin(x1_p)) / A      A = sqrt(y_c^2 + y_s^2), tracked
    /// X_e = X_p + L eps                (x1 wrapped to [-pi, pi), whole turns counted)
    /// ```
    ///
    /// `y_c` and `y_s` are the demodulated cosine and sine signals. The loop is
    /// amplitude-invariant: its phase error is normalised by the signal's magnitude
    /// (`docs/theory.md §12`), so its bandwidth, overshoot and the stability checked at
    /// construction hold for any amplitude and unit. The diagnostics compare amplitudes, so
    /// their [`FaultThresholds`](crate::FaultThresholds) must carry the nominal amplitude in
    /// the input's units (1 by default; [`FaultThresholds::for_amplitude`]), or the samples
    /// come through an [`AdcScaling`](crate::AdcScaling) (a [`Chain`](crate::Chain)'s stage). The first
    /// accepted sample of an uninitialised state sets the angle from `atan2(y_s, y_c)` and
    /// the magnitude from `sqrt(y_c^2 + y_s^2)`; a sample of (near) zero magnitude moves
    /// nothing (`eps = 0`: the state coasts).
    ///
    /// [`FaultThresholds::for_amplitude`]: crate::FaultThresholds::for_amplitude
    ///
    /// A bad sample (NaN, infinite, or amplitude above the input bound) is not used: the
    /// state coasts on its prediction (speed and acceleration) and the estimate carries
    /// [`Faults::BAD_SAMPLE`]. The diagnostics flag loss of signal, degradation of signal,
    /// loss of tracking and false lock once per window of used samples (16 by default: a
    /// fault is flagged within 31 samples, `docs/theory.md §10`), hold the flags until the
    /// next window ends, and re-acquire the angle from `atan2` on a false lock (see
    /// [`FaultThresholds`](crate::FaultThresholds)). Never fails, never panics, and the
    /// state stays finite.
    #[cfg(test)]
    #[inline]
    pub(crate) fn update(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) -> Estimate<T> {
        self.track(state, y_c, y_s);
        self.estimate(state)
    }

    /// [`Gains::update`] without the estimate: the state takes the sample and nothing is
    /// computed in physical units (a chain's `track`); [`Gains::estimate`] reads, to the
    /// bit, everything [`Gains::update`] would have returned for this sample.
    #[inline]
    pub(crate) fn track(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) {
        self.track_observing(state, y_c, y_s, ());
    }

    /// [`Gains::track`] that also shows each sample to `observer`: `Some` with what the
    /// recursion computed for a used sample (after the monitor), `None` for a sample that
    /// was not used (rejected, or the first one). The online calibration learns through it;
    /// the plain track passes `()`, which does nothing and costs nothing.
    #[inline(always)]
    pub(crate) fn track_observing(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: T,
        y_s: T,
        observer: impl SampleObserver<T>,
    ) {
        // `S` is zero-sized: its unit is a value of no size, and the code the one below.
        self.track_observing_with(state, &mut S::default(), y_c, y_s, observer);
    }

    /// The body of every single-channel entry point: [`Gains::track`] with the sin/cos of
    /// `unit` and an `observer`.
    ///
    /// The usual path tests twice: the input check, and whether the predicted angle is in
    /// [-pi, pi) (the wrap's test, which a state that is not tracking fails too, its
    /// predicted angle being parked outside), then the monitor's switch. Everything else,
    /// the first sample, a rejected sample, a wrap, the monitor's decision once per window,
    /// is out of line.
    #[inline(always)]
    pub(crate) fn track_observing_with<U: SinCosUnit<T>>(
        &self,
        state: &mut ObserverState<T, N>,
        unit: &mut U,
        y_c: T,
        y_s: T,
        observer: impl SampleObserver<T>,
    ) {
        let (amplitude2, valid) = self.thresholds.accept(y_c, y_s);
        if !(valid && state.next_angle.abs() < T::PI) {
            // A call in tail position: the usual path then calls nothing and saves no
            // register.
            return self.track_rare(state, unit, y_c, y_s, amplitude2, valid, observer);
        }
        // The monitor's switch is tested here, before the recursion, and the used sample's
        // path is written out for each side (the code of the recursion twice): each copy
        // then ends without a test, one instruction less per monitored sample on a
        // Cortex-M4F than a test after the recursion.
        if self.thresholds.thresholds.monitor {
            self.track_used::<U, true>(state, unit, y_c, y_s, amplitude2, observer);
        } else {
            self.track_used::<U, false>(state, unit, y_c, y_s, amplitude2, observer);
        }
    }

    /// [`Gains::track_observing_with`] on a sample the usual path's two tests sent out of
    /// line: [`Gains::prepare`], then the recursion if the sample is used.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn track_rare<U: SinCosUnit<T>>(
        &self,
        state: &mut ObserverState<T, N>,
        unit: &mut U,
        y_c: T,
        y_s: T,
        amplitude2: T,
        valid: bool,
        observer: impl SampleObserver<T>,
    ) {
        if self.prepare(state, y_c, y_s, amplitude2, valid) {
            self.track_used::<U, true>(state, unit, y_c, y_s, amplitude2, observer);
        } else {
            observer.observe(None);
        }
    }

    /// A used sample, its predicted angle in [-pi, pi): the recursion, the monitor's sums,
    /// and its decision at the end of a window. `MONITOR` `false` leaves the monitor out
    /// (for a caller that has tested its switch); `true` tests the switch.
    #[inline(always)]
    fn track_used<U: SinCosUnit<T>, const MONITOR: bool>(
        &self,
        state: &mut ObserverState<T, N>,
        unit: &mut U,
        y_c: T,
        y_s: T,
        amplitude2: T,
        observer: impl SampleObserver<T>,
    ) {
        let sample = Sample {
            y_c,
            y_s,
            amplitude2,
            valid: true,
        };
        let step = self.step::<NoWrap, U>(
            unit,
            &mut state.x,
            &mut state.next_angle,
            &mut state.amplitude,
            sample,
        );
        state.phase_error = step.eps;
        // The sample's faults are those already in the state: the monitor's of its last
        // window, set where they change (out of line: at a decision, and by `prepare` after
        // a rejected sample).
        if MONITOR
            && self.thresholds.thresholds.monitor
            && state.monitor.accumulate((amplitude2, step.eps))
        {
            self.decide(state, y_c, y_s, amplitude2);
        }
        observer.observe(Some(UsedSample {
            sin_cos: step.sin_cos,
            scaled_speed: if N > 1 { state.x[1] } else { T::ZERO },
            faults: state.faults,
            phase_error: step.eps,
        }));
    }

    /// The rare cases of the update, before the recursion: the driver's
    /// ([`Driver::rare_sample`]: the first sample sets the angle, a rejected sample coasts,
    /// the first sample after a coast re-acquires or is fitted), then the first used sample
    /// after the angle was set starts tracking, and a predicted angle is wrapped. Returns
    /// `true` when the sample is to be used by the recursion, its predicted angle now in
    /// [-pi, pi).
    #[cold]
    #[inline(never)]
    fn prepare(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: T,
        y_s: T,
        amplitude2: T,
        valid: bool,
    ) -> bool {
        // A state that tracks has an angle and has coasted no sample: a valid sample of it
        // is here for the wrap alone, which then costs no more tests than the one.
        if !(valid && state.tracking) {
            let sample = Sample {
                y_c,
                y_s,
                amplitude2,
                valid,
            };
            if !self.rare_sample(state, sample) {
                return false;
            }
            // The first used sample after the angle was set (by the first sample's atan2, by
            // `ObserverState::at` or by a re-acquisition), or after a rejected sample: the
            // predicted angle comes back from its parking place, the sample's faults are
            // the monitor's again, and the magnitude and the monitor's window start if they
            // have not.
            state.start_tracking(amplitude2);
        }
        let whole = wrap_angle(&mut state.next_angle);
        state.turns = state.turns.wrapping_add(whole as i64);
        true
    }

    /// A used sample that changed the tracking-error flag or ended the monitor's window
    /// (out of line): the per-sample check applied ([`TrackingCheck::apply`]); at a window's
    /// end, the flags of its means and of its last sample `(y_c, y_s)`, whose in-phase
    /// component is taken at the corrected angle (by the fast polynomial sin/cos whatever
    /// `S`: a threshold test needs no more than its 3e-7), its square magnitude `amplitude2`
    /// (the roundness check), and on a false lock the angle re-acquired from that sample.
    ///
    /// [`TrackingCheck::apply`]: crate::monitor::TrackingCheck::apply
    #[cold]
    #[inline(never)]
    fn decide(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T, amplitude2: T) {
        let monitor = &mut state.monitor;
        monitor.tracking.apply(
            state.phase_error.abs(),
            self.thresholds.thresholds.tracking_error,
            &mut monitor.latched,
        );
        if monitor.remaining == 0 {
            self.end_window(state, y_c, y_s, amplitude2);
        }
        state.faults = state.monitor.sample_faults();
    }

    /// The end of the monitor's window (see [`Gains::decide`]).
    fn end_window(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T, amplitude2: T) {
        let speed = if N > 1 { state.x[1] } else { T::ZERO };
        let (sin, cos) = wrapped(state.x[0], 0).0.fast_sin_cos();
        let in_phase = y_c * cos + y_s * sin;
        let re_acquire = self
            .thresholds
            .decide(&mut state.monitor, speed, in_phase, amplitude2);
        if re_acquire {
            let (angle, whole) = re_acquired(state.x[0], y_c, y_s);
            state.x[0] = angle;
            state.next_angle = predict(&state.x)[0];
            state.turns = state.turns.wrapping_add(whole as i64);
        }
    }

    /// The recursion itself, on one channel's scaled state `x` and the predicted angle
    /// `next_angle` the previous sample left: predict, detect, correct. A sample that is not
    /// `valid` is not used (the correction is zero: the state coasts on its prediction). `W`
    /// wraps the predicted angle: [`FullWrap`] for one channel;
    /// [`NoWrap`](crate::wrap::NoWrap) for the lanes of a bank, whose angles are wrapped
    /// before the step where they need it.
    ///
    /// ```text
    /// X_p = A X_e                      (the angle row is next_angle, wrapped)
    /// eps = (y_s cos(x1_p) - y_c sin(x1_p)) / sqrt(y_c^2 + y_s^2 + m)
    /// X_e = X_p + L eps                (x1_e wrapped when read)
    /// next_angle = (A X_e)[0]          (f64: (A X_p)[0] + (A L)[0] eps)
    /// ```
    ///
    /// In `f64` (hosts) `next_angle` is `(A X_e)[0]` with the sum taken in another order:
    /// the sample's phase error reaches the next phase detector through one multiplication
    /// and one addition, the shortest chain a loop over samples can wait on; `f32`
    /// (firmware) sums `(A X_e)[0]` itself, one multiplication and one load fewer
    /// ([`Float::FEWEST_INSTRUCTIONS`]). The angle of `x` is not wrapped here (it is
    /// wrapped when read).
    ///
    /// The phase error is normalised by the signal's magnitude (`docs/theory.md §12`), so
    /// that `eps` is the sine of the phase error whatever the amplitude and its units and
    /// the loop's dynamics are the ones its gains were designed and checked for. The
    /// magnitude `amplitude` is [`Float::track_magnitude`] of `sqrt(y_c^2 + y_s^2 + m)`,
    /// `amplitude2` being the `y_c^2 + y_s^2 + m` the input check computed: in `f64` the
    /// square root itself; in `f32` one Heron (Newton) step from the previous sample's
    /// value, two divisions and no square root (which a Cortex-M4F computes in software),
    /// exact for a steady amplitude and within 2 % one sample after a 20 % amplitude step.
    /// `m` is the type's smallest normal number ([`Float::MIN_POSITIVE`]): it keeps the
    /// magnitude positive (never below `sqrt(m)`), so that a zero sample gives `eps = 0`
    /// (the state coasts) instead of `0 / 0`. A sample that is not used leaves `amplitude`
    /// as it is.
    #[inline(always)]
    pub(crate) fn step<W: Wrap, U: SinCosUnit<T>>(
        &self,
        unit: &mut U,
        x: &mut [T; N],
        next_angle: &mut T,
        amplitude: &mut T,
        sample: Sample<T>,
    ) -> Step<T> {
        crate::recursion::step::<Self, U, W, N>(self, unit, x, next_angle, amplitude, sample)
    }

    /// The recursion on a sample that is not used (the state coasts on its prediction): the
    /// new scaled state, the next predicted angle and the whole turns crossed. Out of line,
    /// as the rare case of [`Gains::update`].
    #[cold]
    #[inline(never)]
    pub(super) fn coasted_state(&self, mut x: [T; N], mut next_angle: T) -> ([T; N], T, i32) {
        let mut unused = T::ONE;
        let sample = Sample {
            y_c: T::ZERO,
            y_s: T::ZERO,
            amplitude2: T::ZERO,
            valid: false,
        };
        let step = self.step::<FullWrap, S>(
            &mut S::default(),
            &mut x,
            &mut next_angle,
            &mut unused,
            sample,
        );
        (x, next_angle, step.whole)
    }

    /// Sets the state from one sample: angle `atan2(y_s, y_c)`, speed and acceleration 0,
    /// turns 0, faults cleared. A non-finite sample leaves the state unchanged.
    #[cold]
    #[inline(never)]
    pub fn initialise(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) {
        if let Some((angle, whole)) = sample_angle(y_c, y_s) {
            state.restart(
                angle,
                whole,
                self.thresholds.amplitude2(y_c, y_s),
                Faults::NONE,
            );
        }
    }

    /// The estimate held by `state`, in physical units.
    #[inline(always)]
    pub fn estimate(&self, state: &ObserverState<T, N>) -> Estimate<T> {
        self.estimate_of(&state.x, state.turns, state.phase_error, state.faults)
    }

    /// An estimate in physical units from a scaled state.
    #[inline(always)]
    pub(crate) fn estimate_of(
        &self,
        x: &[T; N],
        turns: i64,
        phase_error: T,
        faults: Faults,
    ) -> Estimate<T> {
        let (angle, turns) = wrapped(x[0], turns);
        Estimate {
            angle,
            turns,
            speed: if N > 1 {
                x[1] * self.sample_rate
            } else {
                T::ZERO
            },
            acceleration: if N > 2 {
                x[2] * self.sample_rate_squared
            } else {
                T::ZERO
            },
            phase_error,
            faults,
        }
    }
}

mod arithmetic;
mod coasting;
pub(crate) mod driver;

#[cfg(test)]
mod amplitude_tests;
#[cfg(test)]
mod tests;
