//! [`CentreFinder`]: each channel's centre (its offset, any size: a 2.5 V bias, counts off
//! mid-scale) found from the raw samples alone, before the observer can lock on them
//! (`docs/theory.md §12`, "Finding the centre").
//!
//! The centre is the middle of each channel's range, `(min + max) / 2`, and is taken once a
//! whole turn about it has passed without moving the ranges: the samples' quadrant about
//! the running centre counts quarter turns (no trigonometry), and a turn of five quadrant
//! boundaries crossed in one direction, over which the ranges grew by no more than
//! [`MAX_GROWTH`] of themselves and no sample came within half the half-ranges of the
//! centre ([`INNER_BOX`]) in at least [`MIN_TURN_SAMPLES`] samples, finds it. A rotor at rest (a cloud of noise, whose samples come near
//! its centre) or one that turns less than a turn never does: the centre is then not found,
//! never guessed.

use crate::calibration::SensorCalibration;
use crate::real::Float;

/// The largest growth of the two channels' ranges over the finding turn, relative to
/// their sum: 1/64. A sinusoid's range is complete after a turn; noise extends it by a
/// fraction of its own size (about 0.3 of a standard deviation from the first turn to the
/// second).
const MAX_GROWTH: f32 = 0.015_625;

/// The inner box a finding turn's samples must stay out of: half of each half-range about
/// the centre. An ellipse of quadrature `phi` up to 30 degrees stays outside it (at
/// `sin(pi/4 - phi/2)` of the half-ranges or more); a cloud of noise at rest falls into it
/// nine samples in ten (half its half-range is about two standard deviations).
const INNER_BOX: f32 = 0.5;

/// The fewest samples of a finding turn: 16 (the centre is found below a sixteenth of a
/// turn per sample). A cloud of noise, whose samples fall in random quadrants, would need
/// 16 in a row outside the inner box.
const MIN_TURN_SAMPLES: u8 = 16;

/// The quadrant boundaries a finding turn crosses (net, one direction): five, so that the
/// turn covers a whole turn wherever in a quadrant it starts.
const TURN_QUARTERS: i8 = 5;

/// `quadrant` before the first sample.
const NO_SAMPLE: u8 = 4;

/// `quadrant` of a finding turn that a sample inside the inner box spoilt: it restarts at
/// the next quadrant boundary.
const SPOILT: u8 = 5;

/// What a sample told the search ([`CentreFinder::add`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum CentreStep<T> {
    /// Nothing new.
    Searching,
    /// A finding turn ended with the ranges still growing: the middle `(c, s)` of the
    /// ranges of the whole turn so far, to apply provisionally (the observer then locks
    /// while the next turn confirms it).
    Provisional(T, T),
    /// The centre found: the centres as offsets, the half-ranges as amplitudes, no
    /// quadrature.
    Found(SensorCalibration<T>),
}

/// The search for the two channels' centres from raw samples (see the module's
/// documentation). `Copy`, nine floats and three bytes. Meant to be cheap per sample (a few
/// float comparisons and subtractions, the rest integer tests of the bits), since it runs
/// on every sample of the first turns: the ranges' middle and inner box are updated only
/// when a range grows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CentreFinder<T> {
    /// `[min_c, max_c, min_s, max_s]` of the samples so far.
    bounds: [T; 4],
    /// The middle of each channel's range: the running centre.
    centre: (T, T),
    /// [`INNER_BOX`] of each channel's half-range.
    inner: (T, T),
    /// How far the two ranges grew (summed) over the current turn.
    growth: T,
    /// The last sample's quadrant about the running centre (0 to 3), [`NO_SAMPLE`] before
    /// the first, [`SPOILT`] after a sample inside the inner box.
    quadrant: u8,
    /// The quadrant boundaries crossed over the current turn, signed (counter-clockwise
    /// positive).
    quarters: i8,
    /// The samples of the current turn (saturated).
    samples: u8,
}

impl<T: Float> CentreFinder<T> {
    /// A search that has seen no sample.
    pub(crate) const fn new() -> Self {
        Self {
            bounds: [T::ZERO; 4],
            centre: (T::ZERO, T::ZERO),
            inner: (T::ZERO, T::ZERO),
            growth: T::ZERO,
            quadrant: NO_SAMPLE,
            quarters: 0,
            samples: 0,
        }
    }

    /// One raw sample `(y_c, y_s)` (not finite: ignored): what it told (the estimator
    /// learns the quadrature, and refines the rest).
    #[inline(never)]
    pub(crate) fn add(&mut self, y_c: T, y_s: T) -> CentreStep<T> {
        if !(y_c.is_finite() && y_s.is_finite()) {
            return CentreStep::Searching;
        }
        if self.quadrant == NO_SAMPLE {
            self.bounds = [y_c, y_c, y_s, y_s];
            self.centre = (y_c, y_s);
            self.restart_turn(SPOILT);
            return CentreStep::Searching;
        }
        let [min_c, max_c, min_s, max_s] = self.bounds;
        if y_c < min_c || y_c > max_c || y_s < min_s || y_s > max_s {
            self.extend(y_c, y_s);
        }
        let (d_c, d_s) = (y_c - self.centre.0, y_s - self.centre.1);
        if d_c.abs_at_most(self.inner.0) && d_s.abs_at_most(self.inner.1) {
            // Near the centre (or the ranges still nothing): the turn tells nothing.
            self.restart_turn(SPOILT);
            return CentreStep::Searching;
        }
        let quadrant: u8 = match (d_c.sign_bit(), d_s.sign_bit()) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        self.samples = self.samples.saturating_add(1);
        match quadrant.wrapping_sub(self.quadrant) & 3 {
            _ if self.quadrant == SPOILT => self.restart_turn(quadrant),
            0 => {}
            1 => self.quarters += 1,
            3 => self.quarters -= 1,
            // Across the centre in one sample (a quarter turn per sample): a new turn.
            _ => self.restart_turn(quadrant),
        }
        self.quadrant = quadrant;
        if self.quarters.abs() < TURN_QUARTERS {
            return CentreStep::Searching;
        }
        self.turn_completed()
    }

    /// A sample outside the ranges: the ranges, their middle and inner box updated, and the
    /// growth counted.
    #[cold]
    #[inline(never)]
    fn extend(&mut self, y_c: T, y_s: T) {
        let [min_c, max_c, min_s, max_s] = &mut self.bounds;
        let grown = widen(y_c, min_c, max_c) + widen(y_s, min_s, max_s);
        self.growth += grown;
        let [min_c, max_c, min_s, max_s] = self.bounds;
        self.centre = ((min_c + max_c) * T::HALF, (min_s + max_s) * T::HALF);
        let inner = T::from_f32(INNER_BOX) * T::HALF;
        self.inner = ((max_c - min_c) * inner, (max_s - min_s) * inner);
    }

    /// The end of a finding turn: the centre found if the ranges held still over it.
    #[cold]
    #[inline(never)]
    fn turn_completed(&mut self) -> CentreStep<T> {
        let [min_c, max_c, min_s, max_s] = self.bounds;
        let (range_c, range_s) = (max_c - min_c, max_s - min_s);
        let steady = self.growth <= (range_c + range_s) * T::from_f32(MAX_GROWTH)
            && self.samples >= MIN_TURN_SAMPLES;
        self.restart_turn(self.quadrant);
        let (centre_c, centre_s) = self.centre;
        if !steady {
            return CentreStep::Provisional(centre_c, centre_s);
        }
        match SensorCalibration::new(
            centre_c,
            centre_s,
            range_c * T::HALF,
            range_s * T::HALF,
            T::ZERO,
        ) {
            Ok(calibration) => CentreStep::Found(calibration),
            Err(_) => CentreStep::Searching,
        }
    }

    /// Starts a new finding turn from a sample in `quadrant`.
    fn restart_turn(&mut self, quadrant: u8) {
        self.growth = T::ZERO;
        self.quarters = 0;
        self.samples = 0;
        self.quadrant = quadrant;
    }
}

/// Widens the range `[min, max]` to hold `value`; returns how far it grew.
#[inline(always)]
fn widen<T: Float>(value: T, min: &mut T, max: &mut T) -> T {
    if value < *min {
        let grown = *min - value;
        *min = value;
        grown
    } else if value > *max {
        let grown = value - *max;
        *max = value;
        grown
    } else {
        T::ZERO
    }
}
