//! The one predictor-corrector recursion that every angle tracking observer runs.

use crate::gains::{Gains, Order, SupportedOrder, predict};
use crate::monitor::{Faults, MonitorState};
use crate::real::Real;
use crate::sincos::SinCos;

/// What an observer knows after a sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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
    /// Phase-detector output `eps = y_s cos(angle_p) - y_c sin(angle_p)` of this sample,
    /// about `A sin(theta - angle_p)` (in the input's units); 0 when the sample was rejected.
    pub phase_error: T,
    /// The diagnostics of this sample (the state also latches them).
    pub faults: Faults,
}

impl<T: Real> Estimate<T> {
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
/// Separate from the immutable [`Gains`], so that one gain set can drive many channels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObserverState<T, const N: usize> {
    /// The corrected state. Its angle `x[0]` is the predicted angle (in [-pi, pi)) plus the
    /// correction, so it may lie up to that correction outside [-pi, pi): it is wrapped
    /// (and its turn counted) when read, and never feeds the next prediction.
    pub(crate) x: [T; N],
    /// The next sample's predicted angle `(A x)[0]`, computed from this sample's prediction
    /// as `(A X_p)[0] + (A L)[0] eps`, in the turn counted by `turns` (wrapped when used).
    pub(crate) next_angle: T,
    pub(crate) turns: i64,
    pub(crate) phase_error: T,
    pub(crate) faults: Faults,
    pub(crate) monitor: MonitorState<T>,
    pub(crate) initialised: bool,
}

impl<T: Real, const N: usize> Default for ObserverState<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real, const N: usize> ObserverState<T, N> {
    /// A state that initialises itself from the first sample it is given: the angle from
    /// `atan2(y_s, y_c)` (so tracking never starts 180 degrees off), speed and acceleration 0.
    ///
    /// ```
    /// use angletrack_core::{Gains, ObserverState};
    /// let gains = Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let mut state = ObserverState::new();
    /// let first = gains.update(&mut state, 0.0, 1.0); // theta = 90 degrees
    /// assert!((first.angle - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new() -> Self {
        Self {
            x: [zero(); N],
            next_angle: zero(),
            turns: 0,
            phase_error: zero(),
            faults: Faults::NONE,
            monitor: MonitorState::new(),
            initialised: false,
        }
    }

    /// A state starting at a known angle (rad, any value: it is wrapped and the whole turns
    /// counted), speed (rad/s) and acceleration (rad/s^2; ignored at order 2), for the
    /// given sample period `sample_period` (s).
    ///
    /// Non-finite values are replaced by 0. Speed and acceleration are limited to what a
    /// sampled loop can represent: half a turn per sample (`pi / Ts` rad/s, beyond which
    /// the angle aliases) and `pi / Ts^2` rad/s^2, so that no state starts near overflow.
    ///
    /// ```
    /// use angletrack_core::ObserverState;
    /// let state = ObserverState::<f32, 3>::at(7.0, 100.0, 0.0, 1e-4);
    /// assert_eq!(state.turns(), 1);
    /// assert!((state.angle() - (7.0 - core::f32::consts::TAU)).abs() < 1e-6);
    /// assert!((state.speed(1e-4) - 100.0).abs() < 1e-3);
    /// ```
    pub fn at(angle: T, speed: T, acceleration: T, sample_period: T) -> Self {
        let finite_or_zero = |v: T| if v.is_finite() { v } else { T::ZERO };
        let limited = |v: T| finite_or_zero(v).max(-T::PI).min(T::PI);
        let mut x = [T::ZERO; N];
        x[0] = finite_or_zero(angle);
        let turns = wrap_angle(&mut x[0]) as i64;
        if N > 1 {
            x[1] = limited(speed * sample_period);
        }
        if N > 2 {
            x[2] = limited(acceleration * sample_period * sample_period);
        }
        Self {
            x,
            next_angle: predict(&x)[0],
            turns,
            phase_error: T::ZERO,
            faults: Faults::NONE,
            monitor: MonitorState::new(),
            initialised: true,
        }
    }

    /// The estimated angle (rad), in [-pi, pi).
    pub fn angle(&self) -> T {
        wrapped(self.x[0], self.turns).0
    }

    /// Whole turns counted since initialisation.
    pub fn turns(&self) -> i64 {
        wrapped(self.x[0], self.turns).1
    }

    /// The estimated speed (rad/s) for the sample period `sample_period` (s).
    pub fn speed(&self, sample_period: T) -> T {
        if N > 1 {
            self.x[1] / sample_period
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

    /// The faults latched since they were last cleared (like reading an RDC chip's fault
    /// register, without clearing it).
    pub fn latched_faults(&self) -> Faults {
        self.monitor.latched
    }

    /// Starts again at `angle` (rad, wrapped) and `whole` turns, speed and acceleration 0,
    /// filters empty, with the faults `latched`.
    #[inline(always)]
    fn restart(&mut self, angle: T, whole: i32, latched: Faults) {
        *self = Self::new();
        self.x[0] = angle;
        self.next_angle = angle;
        self.turns = whole as i64;
        self.monitor.latched = latched;
        self.initialised = true;
    }

    /// Books one step of the recursion: the whole turns it crossed and its phase-detector
    /// output; the sample's faults start empty.
    #[inline(always)]
    fn advance(&mut self, whole: i32, phase_error: T) {
        if whole != 0 {
            self.turns = self.turns.wrapping_add(whole as i64);
        }
        self.phase_error = phase_error;
        self.faults = Faults::NONE;
    }

    /// Marks the current sample as rejected (flag and latch).
    fn reject_sample(&mut self) {
        self.faults = Faults::BAD_SAMPLE;
        self.monitor.latched |= Faults::BAD_SAMPLE;
    }

    /// Returns the latched faults and clears them; a fault still present sets its flag
    /// again at the next sample.
    ///
    /// ```
    /// use angletrack_core::{Faults, Gains, ObserverState};
    /// let gains = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let mut state = ObserverState::new();
    /// gains.update(&mut state, 1.0, 0.0);
    /// gains.update(&mut state, f32::NAN, 0.0); // a broken ADC read
    /// assert!(state.clear_faults().contains(Faults::BAD_SAMPLE));
    /// assert!(state.latched_faults().is_empty());
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn clear_faults(&mut self) -> Faults {
        core::mem::take(&mut self.monitor.latched)
    }
}

const fn zero<T: Real>() -> T {
    T::ZERO
}

/// A corrected angle `x0` of a state counting `turns` turns, as read: wrapped into
/// [-pi, pi), and the turn count with the wrap's whole turns.
#[inline(always)]
pub(crate) fn wrapped<T: Real>(x0: T, turns: i64) -> (T, i64) {
    // The usual case returns both as they are (no addition of zero turns on the way). The
    // test repeats `wrap_angle`'s on purpose: calling it and matching its zero costs 3
    // instructions per update on a Cortex-M4F (tests/firmware, 144.3 -> 147.3).
    if x0.abs() < T::PI {
        return (x0, turns);
    }
    let (angle, whole) = wrap_whole_turns(x0);
    (angle, turns.wrapping_add(whole as i64))
}

/// Wraps `angle` into [-pi, pi) and returns the whole turns removed.
///
/// The usual case, no wrap, is one comparison and a branch; everything else is out of line
/// ([`wrap_whole_turns`]). A non-finite angle, or one too large for its turns to be counted,
/// becomes 0.
#[inline(always)]
pub(crate) fn wrap_angle<T: Real>(angle: &mut T) -> i32 {
    // One comparison: |a| < pi (false for NaN). The edge a = -pi takes the rare path, which
    // keeps it.
    if angle.abs() < T::PI {
        return 0;
    }
    let (wrapped, whole) = wrap_whole_turns(*angle);
    *angle = wrapped;
    whole
}

/// The angle of one sample, `atan2(y_s, y_c)` wrapped to [-pi, pi), and the whole turns the
/// wrap removed; `None` for a non-finite sample. Initialises single observers and banks; out
/// of line and a function of values only (see [`Gains::update`]).
#[cold]
#[inline(never)]
pub(crate) fn sample_angle<T: Real>(y_c: T, y_s: T) -> Option<(T, i32)> {
    let mut angle = y_s.atan2(y_c);
    if !angle.is_finite() {
        return None;
    }
    let whole = wrap_angle(&mut angle);
    Some((angle, whole))
}

/// At most one turn off [-pi, pi): `a - k 2 pi` for `k` in {-1, 0, 1}, by selects and no
/// branch (so that a loop over the lanes of a [`ChannelBank`](crate::ChannelBank)
/// vectorises), with 2 pi in two parts (Cody-Waite): `a - TAU_HI` is exact (Sterbenz), so the
/// wrapped angle loses no precision however many turns have been counted. Returns the
/// wrapped angle and `k`.
///
/// For |a| < [`one_turn_limit`] the result is in [-pi, pi): in `f32`, `TAU_LO < 0` and `PI` lies
/// above pi, so rounding cannot cross an edge; in `f64` it can, and
/// [`Real::ONE_TURN_EDGE_FIX`] adds the move by one more turn that puts it back.
#[inline(always)]
pub(crate) fn wrap_one_turn<T: Real>(a: T) -> (T, i32) {
    let up = a >= T::PI;
    let down = a < -T::PI;
    let k = if up {
        T::ONE
    } else if down {
        -T::ONE
    } else {
        T::ZERO
    };
    // k = 0 gives back a exactly.
    let wrapped = (a - k * T::TAU_HI) - k * T::TAU_LO;
    let whole = i32::from(up) - i32::from(down);
    if !T::ONE_TURN_EDGE_FIX {
        return (wrapped, whole);
    }
    let high = wrapped >= T::PI;
    let low = wrapped < -T::PI;
    let wrapped = if high {
        wrapped - T::TAU
    } else if low {
        wrapped + T::TAU
    } else {
        wrapped
    };
    (wrapped, whole + i32::from(high) - i32::from(low))
}

/// The largest |angle| (rad) [`wrap_one_turn`] is used on: 2.5 pi, a margin of half a turn
/// below where one turn would not be enough.
pub(crate) fn one_turn_limit<T: Real>() -> T {
    T::PI * T::from_f32(2.5)
}

/// The rare case of [`wrap_angle`]: `a` outside (-pi, pi), or not finite. Up to
/// [`one_turn_limit`], exactly as [`wrap_one_turn`] does (so a bank's lanes and a single
/// observer agree to the bit); more turns are counted with a floor.
#[cold]
#[inline(never)]
pub(crate) fn wrap_whole_turns<T: Real>(a: T) -> (T, i32) {
    if a.abs() < one_turn_limit() {
        return wrap_one_turn(a);
    }
    let whole = ((a + T::PI) * T::FRAC_1_TAU).floor_to_i32();
    let k = T::from_i32(whole);
    let mut wrapped = (a - k * T::TAU_HI) - k * T::TAU_LO;
    let mut whole = whole;
    // Rounding can leave the result on the far side of an edge.
    if wrapped >= T::PI {
        wrapped -= T::TAU;
        whole = whole.wrapping_add(1);
    }
    if wrapped < -T::PI {
        wrapped += T::TAU;
        whole = whole.wrapping_sub(1);
    }
    if wrapped >= -T::PI && wrapped < T::PI {
        (wrapped, whole)
    } else {
        // NaN, or a magnitude whose turns do not fit: k * 2 pi is not representable.
        (T::ZERO, 0)
    }
}

/// False lock: the angle `atan2(y_s, y_c)` reached from `angle` by the shortest way, and the
/// whole turns crossed on the way (the caller keeps speed and acceleration).
#[cold]
#[inline(never)]
fn re_acquired<T: Real>(angle: T, y_c: T, y_s: T) -> (T, i32) {
    let mut jump = y_s.atan2(y_c) - angle;
    wrap_angle(&mut jump);
    let mut angle = angle + jump;
    let whole = wrap_angle(&mut angle);
    (angle, whole)
}

/// How a step wraps the predicted angle: [`FullWrap`] for a single channel, [`NoWrap`] or
/// [`OneTurnWrap`] for the lanes of a bank.
pub(crate) trait Wrap {
    /// Wraps `angle` into [-pi, pi); returns the whole turns removed.
    fn wrap<T: Real>(angle: &mut T) -> i32;
}

/// Any number of turns: a comparison and a branch, the rare case out of line.
pub(crate) struct FullWrap;

/// At most one turn, by selects ([`wrap_one_turn`]): for angles within
/// [`one_turn_limit`], which the caller makes sure of.
pub(crate) struct OneTurnWrap;

/// No wrap at all: for angles already in [-pi, pi), which the caller makes sure of (it is
/// then what [`OneTurnWrap`] gives, to the bit).
pub(crate) struct NoWrap;

impl Wrap for NoWrap {
    #[inline(always)]
    fn wrap<T: Real>(_angle: &mut T) -> i32 {
        0
    }
}

impl Wrap for FullWrap {
    #[inline(always)]
    fn wrap<T: Real>(angle: &mut T) -> i32 {
        wrap_angle(angle)
    }
}

impl Wrap for OneTurnWrap {
    #[inline(always)]
    fn wrap<T: Real>(angle: &mut T) -> i32 {
        let (wrapped, whole) = wrap_one_turn(*angle);
        *angle = wrapped;
        whole
    }
}

/// What one step of the recursion gives besides the new state.
#[derive(Clone, Copy)]
pub(crate) struct Step<T> {
    /// Phase-detector output (0 for a sample that was not used).
    pub(crate) eps: T,
    /// In-phase component `y_c cos + y_s sin` of the predicted angle (about `A cos(error)`).
    pub(crate) in_phase: T,
    /// Whole turns the wrap of the predicted angle removed.
    pub(crate) whole: i32,
}

impl<T: Real, const N: usize, S: SinCos<T>> Gains<T, N, S>
where
    Order<N>: SupportedOrder,
{
    /// One sample of the observer: predict, detect the phase error, correct, monitor.
    ///
    /// ```text
    /// X_p = A X_e                      (Taylor step of the scaled state)
    /// eps = y_s cos(x1_p) - y_c sin(x1_p)
    /// X_e = X_p + L eps                (x1 wrapped to [-pi, pi), whole turns counted)
    /// ```
    ///
    /// `y_c` and `y_s` are the demodulated cosine and sine signals (any consistent unit,
    /// nominal amplitude as in the [`FaultThresholds`](crate::FaultThresholds), 1 by
    /// default). The first accepted sample of an uninitialised state sets the angle from
    /// `atan2(y_s, y_c)`.
    ///
    /// A bad sample (NaN, infinite, or amplitude above the input bound) is not used: the
    /// state coasts on its prediction (speed and acceleration) and the estimate carries
    /// [`Faults::BAD_SAMPLE`]. The diagnostics then flag loss of signal, degradation of
    /// signal, loss of tracking and false lock, and re-acquire the angle from `atan2` on a
    /// false lock (see [`FaultThresholds`](crate::FaultThresholds)). Never fails, never
    /// panics, and the state stays finite.
    #[inline]
    pub fn update(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) -> Estimate<T> {
        self.update_in_place(state, y_c, y_s)
    }

    /// The body of [`Gains::update`], inlined into the block APIs so that the state stays in
    /// registers from one sample to the next.
    #[inline(always)]
    fn update_in_place(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) -> Estimate<T> {
        let (amplitude2, valid) = self.thresholds.accept(y_c, y_s);
        if !(valid && state.initialised) {
            // Rare: the first sample, or one that is rejected. Out of line, through functions
            // of values only, so that the state can live in registers in a loop over samples;
            // the usual path below then knows the sample is used.
            if !state.initialised {
                match if valid { sample_angle(y_c, y_s) } else { None } {
                    Some((angle, whole)) => state.restart(angle, whole, state.monitor.latched),
                    None => state.reject_sample(),
                }
            } else {
                let (x, next_angle, whole) = self.coast(state.x, state.next_angle);
                state.x = x;
                state.next_angle = next_angle;
                state.advance(whole, T::ZERO);
                state.reject_sample();
            }
            return self.estimate(state);
        }
        let step = self.step::<FullWrap>(&mut state.x, &mut state.next_angle, y_c, y_s, true);
        state.advance(step.whole, step.eps);
        if self.thresholds.thresholds.monitor {
            let speed = if N > 1 { state.x[1] } else { T::ZERO };
            let (faults, re_acquire) = self.thresholds.observe(
                &mut state.monitor,
                amplitude2,
                step.eps,
                step.in_phase,
                speed,
            );
            state.faults = faults;
            if re_acquire {
                let (angle, whole) = re_acquired(state.x[0], y_c, y_s);
                state.x[0] = angle;
                state.next_angle = predict(&state.x)[0];
                state.turns = state.turns.wrapping_add(whole as i64);
                state.monitor.primed = false;
            }
        }
        self.estimate(state)
    }

    /// The recursion itself, on one channel's scaled state `x` and the predicted angle
    /// `next_angle` the previous sample left: predict, detect, correct. A sample that is not
    /// `valid` is not used (the correction is zero: the state coasts on its prediction). `W`
    /// wraps the predicted angle: [`FullWrap`] for one channel; [`NoWrap`] or [`OneTurnWrap`]
    /// for the lanes of a bank, as the bank's angles need.
    ///
    /// ```text
    /// X_p = A X_e                      (the angle row is next_angle, wrapped)
    /// eps = y_s cos(x1_p) - y_c sin(x1_p)
    /// X_e = X_p + L eps                (x1_e wrapped when read)
    /// next_angle = (A X_p)[0] + (A L)[0] eps
    /// ```
    ///
    /// `next_angle` is `(A X_e)[0]` with the sum taken in another order: the sample's phase
    /// error reaches the next phase detector through one multiplication and one addition, the
    /// shortest chain a loop over samples can wait on. The angle of `x` feeds nothing but the
    /// estimate, so it is not wrapped here.
    ///
    /// This is the only implementation of the recursion: the single-channel update and
    /// the multi-channel [`ChannelBank`](crate::ChannelBank) both call it.
    #[inline(always)]
    pub(crate) fn step<W: Wrap>(
        &self,
        x: &mut [T; N],
        next_angle: &mut T,
        y_c: T,
        y_s: T,
        valid: bool,
    ) -> Step<T> {
        let mut p = predict(x);
        p[0] = *next_angle;
        let whole = W::wrap(&mut p[0]);
        let (detected, in_phase) = S::phase_detector(p[0], y_c, y_s);
        let eps = if valid { detected } else { T::ZERO };
        *next_angle = predict(&p)[0] + self.next_angle_gain * eps;
        let mut i = 0;
        while i < N {
            p[i] += self.l[i] * eps;
            i += 1;
        }
        *x = p;
        Step {
            eps,
            in_phase,
            whole,
        }
    }

    /// The recursion on a sample that is not used (the state coasts on its prediction): the
    /// new scaled state, the next predicted angle and the whole turns crossed. Out of line,
    /// as the rare case of [`Gains::update`].
    #[cold]
    #[inline(never)]
    fn coast(&self, mut x: [T; N], mut next_angle: T) -> ([T; N], T, i32) {
        let step = self.step::<FullWrap>(&mut x, &mut next_angle, T::ZERO, T::ZERO, false);
        (x, next_angle, step.whole)
    }

    /// Sets the state from one sample: angle `atan2(y_s, y_c)`, speed and acceleration 0,
    /// turns 0, faults cleared. A non-finite sample leaves the state unchanged.
    #[cold]
    #[inline(never)]
    pub fn initialise(&self, state: &mut ObserverState<T, N>, y_c: T, y_s: T) {
        if let Some((angle, whole)) = sample_angle(y_c, y_s) {
            state.restart(angle, whole, Faults::NONE);
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

    /// Runs the observer over a block of samples, calling `sink(k, estimate)` for each
    /// sample `k`; no allocation. Processes `min(y_c.len(), y_s.len())` samples and returns
    /// that count.
    ///
    /// ```
    /// use angletrack_core::{Gains, ObserverState};
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?;
    /// let mut state = ObserverState::new();
    /// let (y_c, y_s) = ([1.0_f32; 64], [0.0_f32; 64]);
    /// let mut speeds = [0.0_f32; 64];
    /// let n = gains.update_each(&mut state, &y_c, &y_s, |k, e| speeds[k] = e.speed);
    /// assert_eq!(n, 64);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn update_each<F: FnMut(usize, Estimate<T>)>(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: &[T],
        y_s: &[T],
        mut sink: F,
    ) -> usize {
        let n = y_c.len().min(y_s.len());
        let mut local = *state;
        for (k, (&c, &s)) in y_c.iter().zip(y_s).enumerate() {
            sink(k, self.update_in_place(&mut local, c, s));
        }
        *state = local;
        n
    }

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
            *slot = self.update_in_place(&mut local, c, s);
            n += 1;
        }
        *state = local;
        n
    }
}

/// What every angle tracking observer does, whatever its order and gains: code that uses an
/// observer takes `impl AngleTrackingObserver<T>` and does not care which one it is.
pub trait AngleTrackingObserver<T: Real> {
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
pub struct Observer<T: Real, const N: usize, S = <T as Real>::DefaultSinCos>
where
    Order<N>: SupportedOrder,
{
    /// The gains (immutable; replace them to retune).
    pub gains: Gains<T, N, S>,
    /// The state.
    pub state: ObserverState<T, N>,
}

/// The classical 2nd-order (type II) angle tracking observer.
pub type SecondOrderObserver<T, S = <T as Real>::DefaultSinCos> = Observer<T, 2, S>;
/// The 3rd-order (type III) angle tracking observer: continuous design by pole placement, or
/// the time-invariant Kalman ATO (same recursion, Kalman gains).
pub type ThirdOrderObserver<T, S = <T as Real>::DefaultSinCos> = Observer<T, 3, S>;

impl<T: Real, const N: usize, S: SinCos<T>> Observer<T, N, S>
where
    Order<N>: SupportedOrder,
{
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

impl<T: Real, const N: usize, S: SinCos<T>> AngleTrackingObserver<T> for Observer<T, N, S>
where
    Order<N>: SupportedOrder,
{
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
