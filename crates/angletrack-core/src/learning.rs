//! Online correction of offsets, gain imbalance and quadrature error (`docs/theory.md §12`):
//! [`Calibrator`] (the mutable state: the [`SensorCalibration`] applied, and its
//! estimator), the state of the chain's [`OnlineCalibration`](crate::OnlineCalibration)
//! stage, which corrects each sample before the phase detector and learns the calibration
//! from the observer's own angle while it tracks.
//!
//! A fresh calibrator first finds each channel's centre from the raw samples alone
//! ([`centre`]; provisionally after one turn), and applies it once found, so that an offset
//! of any size (a bias, counts off mid-scale) lets the observer lock; the estimator then
//! learns from the centre's calibration on.
//!
//! The estimator integrates, over whole electrical turns of the observer's predicted angle
//! `p`, the raw samples against `(1, cos p, sin p)`: per completed turn, a Fourier estimate of
//! the regression `y_c = o_c + a1 cos p + b1 sin p`, `y_s = o_s + a2 cos p + b2 sin p`,
//! blended into the running estimate with the factor `max(1/(n+1), 1/16)`.

use crate::calibration::SensorCalibration;
use crate::calibration_settings::CheckedCalibration;
use crate::faults::Faults;
use crate::real::Float;
use crate::update::UsedSample;

use centre::{CentreFinder, CentreStep};

mod centre;

/// The estimator's lock test: the normalised phase error of the corrected sample (the sine
/// of its angle from the observer's prediction) within 0.29 (17 degrees). Wider than the
/// angle errors the calibration removes (5 % offsets, 10 % imbalance and 3 degrees of
/// quadrature give at most 0.13 rad), narrower than what an observer that has lost the
/// angle shows over a turn.
const MAX_LOCK_PHASE_ERROR: f32 = 0.29;

/// The smallest blend factor of a turn's estimate, `1/16`: the estimate then averages about
/// the last 16 turns, following a slow drift (temperature, air gap) while averaging noise.
const MIN_BLEND: f32 = 0.0625;

/// The largest relative change of the speed over a learned turn, 1/64: equal sample weights
/// then stand for equal angle steps to about 1.6 %, whose leak into the offsets (about
/// `A / 64 / (2 pi)` per turn, blended at 1/16) stays below the noise's.
const MAX_SPEED_CHANGE: f32 = 0.015_625;

/// What a [`Calibrator`] does with each sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationMode {
    /// Nothing: the samples reach the observer as they are (the default).
    #[default]
    Off,
    /// Corrects each sample and learns the calibration while the observer tracks.
    Learning,
    /// Corrects each sample with the calibration as it is, learning nothing.
    Frozen,
}

/// Where a learning [`Calibrator`] stands ([`Calibrator::status`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationStatus {
    /// The channels' centres are not found yet: the samples are corrected by the running
    /// centre (the middle of each channel's range so far) and nothing is learned. A rotor
    /// at rest, or one that has not turned a whole turn, stays here: its centre is unknown
    /// (the calibration stays the identity, and the angle is wrong if the signals are
    /// biased).
    FindingCentre,
    /// The centre is known (found, or set with the calibration): learning as the observer
    /// tracks, or ready to.
    Centred,
    /// The centre is known, but [`Calibrator::STALL_TURNS`] electrical turns at speed have
    /// passed since it was found or since the last turn learned, and none passed the
    /// estimator's test (lock on the corrected phase error, steady speed, whole turns).
    Stalled,
}

/// The online calibration's state: the [`SensorCalibration`] applied to each sample, the
/// mode, and either the search for the channels' centres or the estimator's sums over the
/// current turn. No allocation (`Copy`, 25 floats and a few words); one per channel,
/// beside its [`ObserverState`](crate::ObserverState).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibrator<T> {
    calibration: SensorCalibration<T>,
    mode: CalibrationMode,
    /// The blended regression `[o_c, o_s, a1, b1, a2, b2]`.
    regression: [T; 6],
    /// Turns learned (blended) so far.
    turns_learned: u32,
    /// The angle (rad) the observer has covered at speed since the centre was found or the
    /// last turn was learned, in turns it did not learn.
    unlearned_rad: T,
    /// The faults of the calibration against the settings' bounds, computed when the
    /// calibration changes (`None`: to be computed at the next sample).
    sensor_faults: Option<Faults>,
    /// The centre's search, or the current turn's sums.
    phase: Phase<T>,
}

/// A [`Calibrator`]'s search for the centre, then its estimator's turn.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase<T> {
    /// Before the centre is known.
    FindingCentre(CentreFinder<T>),
    /// The current partial turn of the estimator.
    Centred(Turn<T>),
}

/// The estimator's current partial turn.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Turn<T> {
    /// The angle (rad, signed) the observer's speed has covered in it.
    progress: T,
    /// The speed (rad per sample) where it started: at the sample that ended the turn
    /// before (0 after a reset: unknown, and the turn is dropped).
    start_speed: T,
    /// Each sample with the weight `w` (1, and the fraction of the last one that completes
    /// the turn): `[sum w, sum w y_c, sum w y_s, sum w y_c cos p, sum w y_c sin p,
    /// sum w y_s cos p, sum w y_s sin p]`.
    sums: [T; 7],
}

impl<T: Float> Turn<T> {
    const EMPTY: Self = Self {
        progress: T::ZERO,
        start_speed: T::ZERO,
        sums: [T::ZERO; 7],
    };
}

impl<T: Float> Default for Calibrator<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Float> Calibrator<T> {
    /// A calibrator that is off, with no correction and nothing learned.
    ///
    /// ```
    /// use angletrack_core::{CalibrationMode, Calibrator};
    /// let mut calibrator = Calibrator::<f32>::new();
    /// assert_eq!(calibrator.mode(), CalibrationMode::Off);
    /// calibrator.enable(); // learn while tracking
    /// assert_eq!(calibrator.mode(), CalibrationMode::Learning);
    /// ```
    pub const fn new() -> Self {
        Self {
            calibration: SensorCalibration::IDENTITY,
            mode: CalibrationMode::Off,
            regression: [T::ZERO; 6],
            turns_learned: 0,
            unlearned_rad: T::ZERO,
            sensor_faults: Some(Faults::NONE),
            phase: Phase::FindingCentre(CentreFinder::new()),
        }
    }

    /// The electrical turns at speed without a learned turn after which
    /// [`Calibrator::status`] says [`CalibrationStatus::Stalled`]: 16.
    pub const STALL_TURNS: u32 = 16;

    /// A calibrator applying a stored `calibration` without learning
    /// ([`CalibrationMode::Frozen`]); [`Calibrator::enable`] continues learning from it, as
    /// from an estimate of 16 turns.
    ///
    /// ```
    /// use angletrack_core::{CalibrationMode, Calibrator, SensorCalibration};
    /// // Loaded from flash at start-up.
    /// let stored = SensorCalibration::<f32>::new(90.0, -90.0, 1800.0, 1980.0, 0.052)?;
    /// let calibrator = Calibrator::from_calibration(stored);
    /// assert_eq!(calibrator.mode(), CalibrationMode::Frozen);
    /// assert_eq!(calibrator.calibration(), stored);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_calibration(calibration: SensorCalibration<T>) -> Self {
        let mut calibrator = Self::new();
        calibrator.set_calibration(calibration);
        calibrator.mode = CalibrationMode::Frozen;
        calibrator
    }

    /// The calibration applied to each sample (unless off); while
    /// [`CalibrationStatus::FindingCentre`], the identity (and once a finding turn has
    /// passed, the provisional centre's offsets, applied so that the observer locks while
    /// the next turn confirms it).
    pub fn calibration(&self) -> SensorCalibration<T> {
        self.calibration
    }

    /// Replaces the calibration (its offsets are the centre; learning continues from it, as
    /// from an estimate of 16 turns); the current partial turn is discarded.
    pub fn set_calibration(&mut self, calibration: SensorCalibration<T>) {
        self.calibration = calibration;
        self.regression = calibration.regression();
        self.turns_learned = 16;
        self.unlearned_rad = T::ZERO;
        self.sensor_faults = None;
        self.phase = Phase::Centred(Turn::EMPTY);
    }

    /// Where learning stands: finding the centre, centred, or stalled (see
    /// [`CalibrationStatus`]).
    ///
    /// ```
    /// use angletrack_core::{CalibrationStatus, Calibrator, SensorCalibration};
    /// assert_eq!(Calibrator::<f32>::new().status(), CalibrationStatus::FindingCentre);
    /// let stored = SensorCalibration::<f32>::new(2.5, 2.5, 1.0, 1.0, 0.0)?;
    /// let calibrator = Calibrator::from_calibration(stored);
    /// assert_eq!(calibrator.status(), CalibrationStatus::Centred);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn status(&self) -> CalibrationStatus {
        match self.phase {
            Phase::FindingCentre(_) => CalibrationStatus::FindingCentre,
            Phase::Centred(_)
                if self.unlearned_rad >= T::TAU * T::from_i32(Self::STALL_TURNS as i32) =>
            {
                CalibrationStatus::Stalled
            }
            Phase::Centred(_) => CalibrationStatus::Centred,
        }
    }

    /// Forgets what was learned, the centre included: no correction, the centre is found
    /// again, and the next completed turn's estimate is taken as it is. Keeps the mode.
    pub fn restart_learning(&mut self) {
        *self = Self {
            mode: self.mode,
            ..Self::new()
        };
    }

    /// The mode.
    pub fn mode(&self) -> CalibrationMode {
        self.mode
    }

    /// Corrects the samples and learns ([`CalibrationMode::Learning`]).
    pub fn enable(&mut self) {
        self.mode = CalibrationMode::Learning;
    }

    /// Keeps correcting the samples but stops learning ([`CalibrationMode::Frozen`]).
    pub fn freeze(&mut self) {
        self.mode = CalibrationMode::Frozen;
        self.discard_turn();
    }

    /// Neither corrects nor learns ([`CalibrationMode::Off`]); keeps the calibration.
    pub fn disable(&mut self) {
        self.mode = CalibrationMode::Off;
        self.discard_turn();
    }

    /// The number of turns learned since the calibration was started or set.
    pub fn turns_learned(&self) -> u32 {
        self.turns_learned
    }

    /// The faults of the calibration against the bounds of `checked`, computed once per
    /// change of the calibration.
    #[inline(always)]
    pub(crate) fn sensor_faults(&mut self, checked: &CheckedCalibration<T>) -> Faults {
        match self.sensor_faults {
            Some(faults) => faults,
            None => {
                let faults = checked.sensor_faults(&self.calibration);
                self.sensor_faults = Some(faults);
                faults
            }
        }
    }

    /// Drops the current partial turn (counted as unlearned); the centre's search goes on.
    /// The next turn's start speed is unknown (0): that turn is dropped too.
    fn discard_turn(&mut self) {
        self.discard_turn_at(T::ZERO);
    }

    /// [`Calibrator::discard_turn`] at a sample of speed `step` (rad per sample), which
    /// stands for the next turn's start speed (the next sample's, to the speed's change in
    /// one sample).
    #[cold]
    #[inline(never)]
    fn discard_turn_at(&mut self, step: T) {
        if let Phase::Centred(turn) = &mut self.phase {
            self.unlearned_rad += turn.progress.abs();
            *turn = Turn {
                start_speed: step,
                ..Turn::EMPTY
            };
        }
    }

    /// The sample `(y_c, y_s)` corrected by the calibration (before the centre is found,
    /// none, then the provisional centre of the first finding turn: a centre moving with
    /// every sample while the ranges fill would throw off a sensor centred already).
    #[inline(always)]
    pub(crate) fn correct(&self, y_c: T, y_s: T) -> (T, T) {
        self.calibration.correct(y_c, y_s)
    }

    /// One raw sample of the centre's search, which applies the centre once found.
    #[cold]
    #[inline(never)]
    fn find_centre(&mut self, y_c: T, y_s: T) {
        let Phase::FindingCentre(finder) = &mut self.phase else {
            return;
        };
        match finder.add(y_c, y_s) {
            CentreStep::Searching => {}
            CentreStep::Provisional(centre_c, centre_s) => {
                // Its faults (an offset beyond the bounds, against amplitudes of 1) are not
                // the sensor's: they stay none.
                self.calibration = SensorCalibration::with_offsets(centre_c, centre_s);
            }
            CentreStep::Found(calibration) => self.centre_found(calibration),
        }
    }

    /// The centre found: its calibration applied, and the estimator's first turn to
    /// replace it (nothing learned yet).
    #[cold]
    #[inline(never)]
    fn centre_found(&mut self, calibration: SensorCalibration<T>) {
        self.calibration = calibration;
        self.regression = calibration.regression();
        self.turns_learned = 0;
        self.unlearned_rad = T::ZERO;
        self.sensor_faults = None;
        self.phase = Phase::Centred(Turn::EMPTY);
    }

    /// One sample of the estimator: the raw sample `(y_c, y_s)` and what the observer made
    /// of its corrected form (`None`: not used). Before the centre is known, the raw sample
    /// goes to the centre's search only. A sample of an observer not locked on it (a phase
    /// error beyond [`MAX_LOCK_PHASE_ERROR`]), slow or reversing discards the partial turn
    /// (the monitor's faults do not: its loss of tracking is tripped by the errors learning
    /// removes; a false lock half a turn away is a common rotation, which the estimate
    /// leaves out; a rejected sample is not used); a sample
    /// that completes a turn (the speed's angle steps add to 2 pi) ends it, counted only for
    /// the fraction of its step that completes the turn.
    ///
    /// The samples are weighted equally (a synchronous average over time), not by the
    /// estimated speed: the speed ripples at the frequencies the sensor's errors put on the
    /// angle, and that ripple times the signal would bias the offsets.
    #[inline(always)]
    pub(crate) fn learn(
        &mut self,
        checked: &CheckedCalibration<T>,
        used: Option<UsedSample<T>>,
        (y_c, y_s): (T, T),
    ) {
        let Phase::Centred(turn) = &mut self.phase else {
            return self.find_centre(y_c, y_s);
        };
        let Some(used) = used else {
            return self.discard_turn();
        };
        let step = used.scaled_speed;
        let progress = turn.progress;
        // NaN-safe: a NaN speed or phase error fails the comparisons and discards.
        let at_speed = step.abs() >= checked.min_scaled_speed;
        if !(at_speed
            && used
                .phase_error
                .abs_at_most(T::from_f32(MAX_LOCK_PHASE_ERROR)))
            || step * progress < T::ZERO
        {
            if at_speed {
                self.unlearned_rad += step.abs();
            }
            return self.discard_turn_at(step);
        }
        let next = progress + step;
        let (sin, cos) = used.sin_cos;
        if next.abs() >= T::TAU {
            return self.complete_turn(step, (y_c, y_s), (sin, cos));
        }
        turn.progress = next;
        let terms = [T::ONE, y_c, y_s, y_c * cos, y_c * sin, y_s * cos, y_s * sin];
        for (sum, term) in turn.sums.iter_mut().zip(terms) {
            *sum += term;
        }
    }

    /// The sample that completes the current turn, `step` its speed, `(y_c, y_s)` and
    /// `(sin, cos)` as in [`Calibrator::learn`]: counted for the fraction `w` of its step
    /// that completes the turn, then the turn ended, or dropped if the speed changed over
    /// it.
    #[cold]
    #[inline(never)]
    fn complete_turn(&mut self, step: T, (y_c, y_s): (T, T), (sin, cos): (T, T)) {
        let Phase::Centred(turn) = &mut self.phase else {
            return;
        };
        let w = (T::TAU - turn.progress.abs()) / step.abs();
        turn.progress += step;
        let (wc, ws) = (w * y_c, w * y_s);
        let terms = [w, wc, ws, wc * cos, wc * sin, ws * cos, ws * sin];
        for (sum, term) in turn.sums.iter_mut().zip(terms) {
            *sum += term;
        }
        // Equal weights stand for equal angle steps only at a steady speed: a turn over
        // which the speed changed is dropped (its window would leak the fundamental into
        // the offsets). The speed's ripple from the sensor's errors is the same at both
        // ends of a turn, so it does not count.
        if (step - turn.start_speed).abs() <= turn.start_speed.abs() * T::from_f32(MAX_SPEED_CHANGE)
        {
            self.end_turn();
        }
        // Learned or not, this turn is over, and the next one starts at this speed.
        self.discard_turn_at(step);
    }

    /// A completed turn: its Fourier estimate of the regression, blended into the running
    /// one; the calibration it gives is applied only if it passes
    /// [`SensorCalibration::new`]'s checks (finite, positive amplitudes, quadrature within
    /// bound), else the turn is dropped.
    #[cold]
    #[inline(never)]
    fn end_turn(&mut self) {
        let Phase::Centred(turn) = &self.phase else {
            return;
        };
        let inverse = T::ONE / turn.sums[0];
        let twice = inverse * T::TWO;
        let s = &turn.sums;
        let estimate = [
            s[1] * inverse,
            s[2] * inverse,
            s[3] * twice,
            s[4] * twice,
            s[5] * twice,
            s[6] * twice,
        ];
        let blend = if self.turns_learned == 0 {
            T::ONE
        } else {
            (T::ONE / (T::from_i32(self.turns_learned.min(1 << 20) as i32) + T::ONE))
                .max(T::from_f32(MIN_BLEND))
        };
        let mut blended = self.regression;
        for (b, e) in blended.iter_mut().zip(estimate) {
            *b += blend * (e - *b);
        }
        if let Ok(calibration) = SensorCalibration::from_regression(&blended) {
            self.calibration = calibration;
            self.sensor_faults = None;
            self.regression = blended;
            self.turns_learned = self.turns_learned.saturating_add(1);
            self.unlearned_rad = T::ZERO;
            if let Phase::Centred(turn) = &mut self.phase {
                turn.progress = T::ZERO;
            }
        }
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_sensors;
