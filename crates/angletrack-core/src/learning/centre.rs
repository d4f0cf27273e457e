//! [`CentreFinder`]: each channel's centre (its offset, any size: a 2.5 V bias, counts off
//! mid-scale) found from the raw samples alone, before the observer can lock on them
//! (`docs/theory.md §12`, "Finding the centre").
//!
//! The centre is the middle of each channel's range, `(min + max) / 2`, and is taken once a
//! whole turn about it has passed without moving the ranges: the samples' quadrant about
//! the running centre counts quarter turns (no trigonometry), and a turn of five quadrant
//! boundaries crossed in one direction, over which neither range grew by more than
//! [`MAX_GROWTH`] of itself and no sample came within half the ranges of the centre
//! ([`MIN_RADIUS2`]), finds it. A rotor at rest (a cloud of noise, whose samples come near
//! its centre) or one that turns less than a turn never does: the centre is then not found,
//! never guessed.

use crate::calibration::SensorCalibration;
use crate::real::Float;

/// The largest growth of a channel's range over the finding turn, relative to the range:
/// 1/32. A sinusoid's range is complete after a turn; noise extends it by a fraction of its
/// own size (about 0.3 of a standard deviation from the first turn to the second).
const MAX_GROWTH: f32 = 0.031_25;

/// The smallest squared radius of a sample about the centre over the finding turn, in
/// half-ranges: 1/4. An ellipse of quadrature `phi` stays at `1 - sin|phi|` or more (0.29 at
/// the largest calibration's pi/4); a cloud of noise at rest comes near its centre.
const MIN_RADIUS2: f32 = 0.25;

/// The quadrant boundaries a finding turn crosses (net, one direction): five, so that the
/// turn covers a whole turn wherever in a quadrant it starts.
const TURN_QUARTERS: i8 = 5;

/// `quadrant` before the first sample.
const NO_SAMPLE: u8 = 4;

/// The search for the two channels' centres from raw samples (see the module's
/// documentation). `Copy`, seven floats and two bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CentreFinder<T> {
    /// `[min_c, max_c, min_s, max_s]` of the samples so far.
    bounds: [T; 4],
    /// How far each channel's range grew over the current turn: `[cos, sin]`.
    growth: [T; 2],
    /// The smallest squared radius about the running centre, in half-ranges, over the
    /// current turn.
    min_radius2: T,
    /// The last sample's quadrant about the running centre (0 to 3), [`NO_SAMPLE`] before
    /// the first.
    quadrant: u8,
    /// The quadrant boundaries crossed over the current turn, signed (counter-clockwise
    /// positive).
    quarters: i8,
}

impl<T: Float> CentreFinder<T> {
    /// A search that has seen no sample.
    pub(crate) const fn new() -> Self {
        Self {
            bounds: [T::ZERO; 4],
            growth: [T::ZERO; 2],
            min_radius2: T::ZERO,
            quadrant: NO_SAMPLE,
            quarters: 0,
        }
    }

    /// The running centre `(c, s)`: the middle of each channel's range so far, `(0, 0)`
    /// before the first sample.
    #[inline(always)]
    pub(crate) fn centre(&self) -> (T, T) {
        let [min_c, max_c, min_s, max_s] = self.bounds;
        ((min_c + max_c) * T::HALF, (min_s + max_s) * T::HALF)
    }

    /// One raw sample `(y_c, y_s)` (not finite: ignored). Returns the calibration of the
    /// centre found, at the sample that finds it: the centres as offsets, the half-ranges
    /// as amplitudes, no quadrature (the estimator learns it, and refines the rest).
    #[cold]
    #[inline(never)]
    pub(crate) fn add(&mut self, y_c: T, y_s: T) -> Option<SensorCalibration<T>> {
        if !(y_c.is_finite() && y_s.is_finite()) {
            return None;
        }
        if self.quadrant == NO_SAMPLE {
            self.bounds = [y_c, y_c, y_s, y_s];
            self.quadrant = 0;
            self.restart_turn();
            return None;
        }
        let [min_c, max_c, min_s, max_s] = &mut self.bounds;
        self.growth[0] += extend(y_c, min_c, max_c);
        self.growth[1] += extend(y_s, min_s, max_s);
        let (centre_c, centre_s) = self.centre();
        let [min_c, max_c, min_s, max_s] = self.bounds;
        let (half_c, half_s) = ((max_c - min_c) * T::HALF, (max_s - min_s) * T::HALF);
        let (d_c, d_s) = (y_c - centre_c, y_s - centre_s);
        let (r_c, r_s) = (d_c / half_c, d_s / half_s);
        // NaN (a range still zero) counts as inside: the turn cannot find the centre.
        let radius2 = r_c * r_c + r_s * r_s;
        self.min_radius2 = if radius2 >= self.min_radius2 {
            self.min_radius2
        } else if radius2.is_finite() {
            radius2
        } else {
            T::ZERO
        };
        let quadrant: u8 = match (d_c >= T::ZERO, d_s >= T::ZERO) {
            (true, true) => 0,
            (false, true) => 1,
            (false, false) => 2,
            (true, false) => 3,
        };
        match quadrant.wrapping_sub(self.quadrant) & 3 {
            0 => {}
            1 => self.quarters += 1,
            3 => self.quarters -= 1,
            // Across the centre in one sample: near it, or a quarter turn per sample; the
            // turn tells nothing.
            _ => self.restart_turn(),
        }
        self.quadrant = quadrant;
        if self.quarters.abs() < TURN_QUARTERS {
            return None;
        }
        let steady = |growth: T, half: T| growth <= half * T::TWO * T::from_f32(MAX_GROWTH);
        let found = steady(self.growth[0], half_c)
            && steady(self.growth[1], half_s)
            && self.min_radius2 >= T::from_f32(MIN_RADIUS2);
        self.restart_turn();
        if !found {
            return None;
        }
        SensorCalibration::new(centre_c, centre_s, half_c, half_s, T::ZERO).ok()
    }

    /// Starts a new finding turn from the current sample.
    fn restart_turn(&mut self) {
        self.growth = [T::ZERO; 2];
        self.min_radius2 = T::from_f32(f32::MAX);
        self.quarters = 0;
    }
}

/// Extends the range `[min, max]` to hold `value`; returns how far it grew.
#[inline(always)]
fn extend<T: Float>(value: T, min: &mut T, max: &mut T) -> T {
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
