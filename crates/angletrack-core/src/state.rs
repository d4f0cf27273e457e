//! The scaled state of one channel and its prediction: [`ObserverState`] (what the recursion
//! updates), [`Estimate`] (what it reports, in physical units) and the Taylor step `A x`
//! that predicts the next sample (`docs/theory.md §5`).

use crate::error::{ConfigError, Parameter};
use crate::faults::Faults;
use crate::monitor::MonitorState;
use crate::reacquisition::Refit;
use crate::real::{Float, check_positive};
use crate::wrap::{wrap_angle, wrapped};

/// What an observer knows after a sample.
///
/// Its fields are read directly; it may gain fields (`#[non_exhaustive]`), so code outside
/// this crate makes one with [`Estimate::new`] (an observer of its own, compared with this
/// crate's) or [`Estimate::default`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct Estimate<T> {
    /// Estimated shaft angle (rad), wrapped to [-pi, pi).
    pub angle: T,
    /// Whole turns counted since initialisation (positive counter-clockwise). The
    /// multi-turn position is `turns * 2 pi + angle` (rad), exact in this split form.
    pub turns: i64,
    /// Estimated speed (rad/s).
    pub speed: T,
    /// Estimated acceleration (rad/s^2); always 0 for a 2nd-order observer.
    pub acceleration: T,
    /// Normalised phase-detector output of this sample,
    /// `(y_s cos(angle_p) - y_c sin(angle_p)) / A`, with `A` the tracked magnitude
    /// `sqrt(y_c^2 + y_s^2)` ([`ObserverState::amplitude`]): about `sin(theta - angle_p)`,
    /// dimensionless whatever the input's units (`docs/theory.md §1, §12`); 0 when the
    /// sample was rejected.
    pub phase_error: T,
    /// The diagnostics: the monitor's flags of its last window (held until the next one
    /// ends, `docs/theory.md §10`) and this sample's [`Faults::BAD_SAMPLE`] (the state also
    /// latches them).
    pub faults: Faults,
}

impl<T: Float> Estimate<T> {
    /// An estimate from its parts: angle (rad, wrapped to [-pi, pi)), whole turns, speed
    /// (rad/s), acceleration (rad/s^2), normalised phase error and faults.
    ///
    /// ```
    /// use angletrack_core::{Estimate, Faults};
    /// let e = Estimate::new(1.0_f32, 2, 50.0, 0.0, 1e-3, Faults::NONE);
    /// assert_eq!((e.angle, e.turns, e.speed), (1.0, 2, 50.0));
    /// ```
    pub const fn new(
        angle: T,
        turns: i64,
        speed: T,
        acceleration: T,
        phase_error: T,
        faults: Faults,
    ) -> Self {
        Self {
            angle,
            turns,
            speed,
            acceleration,
            phase_error,
            faults,
        }
    }

    /// The multi-turn position `turns * 2 pi + angle` (rad) in `f64`: exact to `f64`
    /// rounding whatever the number of turns. Meant for host-side code (on a Cortex-M4F
    /// `f64` arithmetic is emulated in software).
    pub fn position(&self) -> f64 {
        self.turns as f64 * core::f64::consts::TAU + self.angle.to_f64()
    }
}

/// The mutable state of one observer channel: the scaled state vector
/// `x = (theta, Ts Omega[, Ts^2 alpha])`, the next sample's predicted angle and the turn
/// count.
///
/// Separate from the immutable [`Gains`](crate::Gains), so that one gain set can drive many
/// channels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObserverState<T, const N: usize> {
    /// The corrected state. Its angle `x[0]` is the predicted angle (in [-pi, pi)) plus the
    /// correction, so it may lie up to that correction outside [-pi, pi): it is wrapped
    /// (and its turn counted) when read; the next prediction starts from `next_angle`.
    pub(crate) x: [T; N],
    /// The next sample's predicted angle `(A x)[0]` (in `f64` summed from this sample's
    /// prediction as `(A X_p)[0] + (A L)[0] eps`, see `Gains::step`), in
    /// the turn counted by `turns` (wrapped when used).
    /// While the state is not tracking (before its first used sample, after a rejected
    /// one) it is parked outside [-pi, pi) (`PARKED_ANGLE`), so that the one comparison of
    /// the wrap sends the next sample to the update's rare path, which starts tracking
    /// again: the usual path needs no test of its own and stores no fault flag
    /// ([`ObserverState::predicted_angle`] gives the prediction at any time).
    pub(crate) next_angle: T,
    pub(crate) turns: i64,
    pub(crate) phase_error: T,
    pub(crate) faults: Faults,
    pub(crate) monitor: MonitorState<T>,
    /// The magnitude `sqrt(y_c^2 + y_s^2)` the phase error is normalised by
    /// ([`Float::track_magnitude`], `docs/theory.md §12`); set exactly by the first used
    /// sample.
    pub(crate) amplitude: T,
    /// The angle is known (from a first sample, or [`ObserverState::at`]).
    pub(crate) initialised: bool,
    /// The angle and the magnitude are known and the last sample was used: the predicted
    /// angle `next_angle` is live and the usual path of the update runs (else it is parked).
    pub(crate) tracking: bool,
    /// The samples coasted through front-end faults since the last used one (saturated):
    /// after a few, the next used sample sets the angle from its `atan2` (the speed and
    /// the acceleration kept); after many, the next samples are fitted first
    /// (`crate::reacquisition`).
    pub(crate) coasted: u32,
    /// The fit under way after a long coast.
    pub(crate) refit: Refit<T>,
}

impl<T: Float, const N: usize> Default for ObserverState<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Float, const N: usize> ObserverState<T, N> {
    /// Where `next_angle` is parked while the state is not tracking: `2 pi`, outside the
    /// [-pi, pi) the wrap keeps a predicted angle in.
    pub(crate) const PARKED_ANGLE: T = T::TAU;

    /// A state that initialises itself from the first sample it is given: the angle from
    /// `atan2(y_s, y_c)` (so tracking never starts 180 degrees off), speed and acceleration 0.
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, Gains, ObserverState};
    /// let chain = Chain::new((), Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?);
    /// let mut state = ChainState { front_end: (), observer: ObserverState::new() };
    /// let first = chain.update(&mut state, (0.0, 1.0)); // theta = 90 degrees
    /// assert!((first.angle - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new() -> Self {
        Self {
            x: [T::ZERO; N],
            next_angle: Self::PARKED_ANGLE,
            turns: 0,
            phase_error: T::ZERO,
            faults: Faults::NONE,
            monitor: MonitorState::new(),
            amplitude: T::ZERO,
            initialised: false,
            tracking: false,
            coasted: 0,
            refit: Refit::new(),
        }
    }

    /// A state starting at a known angle `angle_rad` (wrapped, the whole turns counted),
    /// speed `speed_rad_s` and acceleration `acceleration_rad_s2`, for the sample period
    /// `sample_period_s` (s).
    ///
    /// Refuses, naming the parameter, what the state cannot hold as given: a value that is
    /// not finite, an angle of `2^31 - 1` turns or more (the turns are counted in 32 bits
    /// as the angle is wrapped), a speed beyond half a turn per sample (`pi / Ts` rad/s,
    /// beyond which the angle aliases, `docs/theory.md §9`) or an acceleration beyond
    /// `pi / Ts^2` rad/s^2, and a speed or an acceleration other than 0 for an observer of
    /// an order that has none.
    ///
    /// ```
    /// use angletrack_core::{ObserverState, Parameter};
    /// let state = ObserverState::<f32, 3>::at(7.0, 100.0, 0.0, 1e-4)?;
    /// assert_eq!(state.turns(), 1);
    /// assert!((state.angle() - (7.0 - core::f32::consts::TAU)).abs() < 1e-6);
    /// assert!((state.speed(1e-4) - 100.0).abs() < 1e-3);
    /// let err = ObserverState::<f32, 2>::at(0.0, 0.0, 1.0, 1e-4).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::InitialAcceleration);
    /// let err = ObserverState::<f64, 3>::at(0.0, 4e4, 0.0, 1e-4).unwrap_err();
    /// assert_eq!(err.parameter().name(), "speed_rad_s");
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn at(
        angle_rad: T,
        speed_rad_s: T,
        acceleration_rad_s2: T,
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        let ts = check_positive(sample_period_s, Parameter::SamplePeriod)?;
        let finite = |v: T, parameter| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(ConfigError::NotFinite(parameter))
            }
        };
        let angle = finite(angle_rad, Parameter::InitialAngle)?;
        let speed = finite(speed_rad_s, Parameter::InitialSpeed)? * ts;
        let acceleration = finite(acceleration_rad_s2, Parameter::InitialAcceleration)? * ts * ts;
        let out_of_range = |parameter| Err(ConfigError::OutOfRange(parameter));
        if !(angle.abs() < T::from_i32(i32::MAX - 1) * T::TAU) {
            return out_of_range(Parameter::InitialAngle);
        }
        if (N < 2 && speed != T::ZERO) || !(speed.abs() <= T::PI) {
            return out_of_range(Parameter::InitialSpeed);
        }
        if (N < 3 && acceleration != T::ZERO) || !(acceleration.abs() <= T::PI) {
            return out_of_range(Parameter::InitialAcceleration);
        }
        let mut x = [T::ZERO; N];
        x[0] = angle;
        let turns = wrap_angle(&mut x[0]) as i64;
        if N > 1 {
            x[1] = speed;
        }
        if N > 2 {
            x[2] = acceleration;
        }
        Ok(Self {
            x,
            next_angle: Self::PARKED_ANGLE,
            turns,
            phase_error: T::ZERO,
            faults: Faults::NONE,
            monitor: MonitorState::new(),
            amplitude: T::ZERO,
            initialised: true,
            // The magnitude is not known yet: the first used sample sets it.
            tracking: false,
            coasted: 0,
            refit: Refit::new(),
        })
    }

    /// The estimated angle (rad), in [-pi, pi).
    pub fn angle(&self) -> T {
        wrapped(self.x[0], self.turns).0
    }

    /// Whole turns counted since initialisation.
    pub fn turns(&self) -> i64 {
        wrapped(self.x[0], self.turns).1
    }

    /// The estimated speed (rad/s) for the sample period `sample_period_s` (s).
    pub fn speed(&self, sample_period_s: T) -> T {
        if N > 1 {
            self.x[1] / sample_period_s
        } else {
            T::ZERO
        }
    }

    /// The scaled state vector `(theta, Ts Omega[, Ts^2 alpha])`, the angle in [-pi, pi).
    pub fn scaled_state(&self) -> [T; N] {
        let mut x = self.x;
        x[0] = self.angle();
        x
    }

    /// `false` until the first sample (or [`ObserverState::at`]) has set the angle.
    pub fn is_initialised(&self) -> bool {
        self.initialised
    }

    /// The signal's magnitude `sqrt(y_c^2 + y_s^2)` (in the input's units) as the observer
    /// tracks it to normalise its phase error (`docs/theory.md §12`): the last used sample's
    /// in `f64`; in `f32` exact for a steady amplitude and following a change within a few
    /// samples (one Heron step per sample); 0 until a first sample is used.
    /// The monitor's filtered amplitude, which the loss-of-signal and degradation checks
    /// compare, is [`ObserverState::filtered_amplitude`].
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, FaultThresholds, Gains};
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?
    ///     .with_fault_thresholds(FaultThresholds::for_amplitude(1800.0))?;
    /// let chain = Chain::new((), gains);
    /// let mut state = ChainState::new();
    /// chain.track(&mut state, (1800.0, 0.0)); // raw ADC counts, mid-scale removed
    /// chain.track(&mut state, (1800.0, 0.0));
    /// assert!((state.observer.amplitude() - 1800.0).abs() < 1e-2);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn amplitude(&self) -> T {
        self.amplitude
    }

    /// The monitor's amplitude `sqrt(mean of y_c^2 + y_s^2)` over its last window (input
    /// units), which its loss-of-signal and degradation checks compare
    /// (`docs/theory.md §10`); the first sample's until a window ends (always, while the
    /// monitor is off), 0 before a first sample is used.
    pub fn filtered_amplitude(&self) -> T {
        if self.initialised {
            self.monitor.amplitude2.sqrt()
        } else {
            T::ZERO
        }
    }

    /// The faults latched since they were last cleared (like reading an RDC chip's fault
    /// register, without clearing it).
    pub fn latched_faults(&self) -> Faults {
        self.monitor.latched
    }

    /// Returns the latched faults and clears them; a fault still present sets its flag
    /// again at the next sample.
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, Faults, Gains};
    /// let chain = Chain::new((), Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?);
    /// let mut state = ChainState::new();
    /// chain.track(&mut state, (1.0, 0.0));
    /// chain.track(&mut state, (f32::NAN, 0.0)); // a broken ADC read
    /// assert!(state.observer.clear_faults().contains(Faults::BAD_SAMPLE));
    /// assert!(state.observer.latched_faults().is_empty());
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn clear_faults(&mut self) -> Faults {
        core::mem::take(&mut self.monitor.latched)
    }

    /// Starts again at `angle` (rad, wrapped) and `whole` turns, speed and acceleration 0,
    /// from a sample of `y_c^2 + y_s^2` `amplitude2` (the angle being that sample's), with
    /// the faults `latched`. The magnitude is that sample's; the monitor's phase filters
    /// start from the next used sample, as after [`ObserverState::at`], so that a step or a
    /// false lock right after the first sample is seen at once.
    #[inline(always)]
    pub(crate) fn restart(&mut self, angle: T, whole: i32, amplitude2: T, latched: Faults) {
        *self = Self::new();
        self.x[0] = angle;
        self.turns = whole as i64;
        self.monitor.latched = latched;
        self.initialised = true;
        self.amplitude = magnitude(amplitude2);
        self.monitor.amplitude2 = amplitude2;
    }

    /// The first used sample after the angle was set, of `y_c^2 + y_s^2` `amplitude2`: a
    /// state from [`ObserverState::at`] has no magnitude yet and takes this sample's; one
    /// started by a first sample keeps that sample's, which the recursion then tracks as
    /// usual (as a [`ChannelBank`](crate::ChannelBank) lane does). The predicted angle
    /// leaves its parking place, the faults are the monitor's again, and the monitor starts
    /// its first window, of this sample alone (a window under way goes on: rejected samples
    /// do not restart it). The per-sample update needs no test for any of it.
    #[cold]
    #[inline(never)]
    pub(crate) fn start_tracking(&mut self, amplitude2: T) {
        if !(self.amplitude > T::ZERO) {
            self.amplitude = magnitude(amplitude2);
            self.monitor.amplitude2 = amplitude2;
        }
        // The first window is the first used sample alone: an angle set without looking at
        // the signal (`ObserverState::at`) may be 180 degrees off, a false lock to catch
        // before the loop runs from it; then windows of `window` samples.
        if self.monitor.remaining == 0 {
            self.monitor.start_window(1, T::ONE);
        }
        self.next_angle = predict(&self.x)[0];
        self.faults = self.monitor.sample_faults();
        self.tracking = true;
    }

    /// The next sample's predicted angle `(A x)[0]` (rad, not wrapped), tracking or not.
    #[inline(always)]
    pub(crate) fn predicted_angle(&self) -> T {
        // Loaded first and replaced where not tracking: the tracking path then has no
        // branch of its own to take (one instruction fewer on a Cortex-M4F).
        let mut angle = self.next_angle;
        if !self.tracking {
            angle = predict(&self.x)[0];
        }
        angle
    }

    /// Books one step of the recursion: the whole turns it crossed and its phase-detector
    /// output (the caller stores the sample's faults).
    #[inline(always)]
    pub(crate) fn advance(&mut self, whole: i32, phase_error: T) {
        if whole != 0 {
            self.turns = self.turns.wrapping_add(whole as i64);
        }
        self.phase_error = phase_error;
    }

    /// Marks the current sample as rejected (flag and latch; the monitor's flags of its
    /// last window hold) and parks the predicted angle, so that the next sample goes
    /// through the rare path, which clears the flag.
    pub(crate) fn reject_sample(&mut self) {
        self.monitor.latched |= Faults::BAD_SAMPLE;
        self.park(Faults::BAD_SAMPLE);
    }

    /// The sample was not used: its faults are `flag` and the monitor's flags of its last
    /// window, and the predicted angle is parked, so that the next sample goes through the
    /// rare path, which starts tracking again.
    pub(crate) fn park(&mut self, flag: Faults) {
        self.faults = flag | self.monitor.sample_faults();
        self.next_angle = Self::PARKED_ANGLE;
        self.tracking = false;
    }
}

/// The prediction `A x` of the recursion: a Taylor step of the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`, `A[i][j] = 1/(j-i)!` for `j >= i`.
///
/// Each row adds left to right, `(x0 + x1) + x2/2`: in the loop every state is corrected at
/// the same time, so `x0 + x1` runs while `x2/2` is multiplied and the chain from one
/// sample's phase error to the next predicted angle is two additions after the correction
/// (`x0 + (x1 + x2/2)` would be three).
#[inline(always)]
pub(crate) fn predict<T: Float, const N: usize>(x: &[T; N]) -> [T; N] {
    let mut p = *x;
    let mut i = 0;
    while i < N {
        let mut sum = x[i];
        let mut j = i + 1;
        while j < N {
            sum += if j - i == 1 { x[j] } else { x[j] * T::HALF };
            j += 1;
        }
        p[i] = sum;
        i += 1;
    }
    p
}

/// The magnitude `sqrt(y_c^2 + y_s^2 + m)` of a sample from its `amplitude2` (which includes
/// `m`, see [`CheckedThresholds::accept`](crate::monitor::CheckedThresholds::accept)):
/// exactly, for the first sample, which starts the tracker of [`heron_step`]. Out of line,
/// as the square root is a software routine on a Cortex-M4F.
#[cold]
#[inline(never)]
pub(crate) fn magnitude<T: Float>(amplitude2: T) -> T {
    amplitude2.sqrt()
}
