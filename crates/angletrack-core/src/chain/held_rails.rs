//! [`HeldRailCheck`]: clipping flagged without a stated ADC range, against the rails
//! measured on the samples as they come: an extreme held flat, as a clipped signal's is and
//! a clean one's is not (the CLI's test of a measured range, made per sample, with a still
//! shaft's constant windings told apart). On floats and on the fixed-point chain's 16-bit
//! samples alike ([`RailSample`]).

use super::front_end_check::FrontEndCheckState;
use super::{Prediction, Stage};
use crate::faults::Faults;
use crate::front_end_faults::FrontEndFaults;
use crate::real::{ChainNumber, Float};

/// Consecutive samples of a channel at an extreme, the other channel moving, that make it
/// a rail (with the samples piled up there).
pub const HELD_RAIL_SAMPLES: u8 = 4;

/// The band just inside an extreme whose samples a rail must outnumber: the span of the
/// samples (lowest to highest) divided by this (half a percent).
pub const RAIL_BAND_PER_SPAN: u16 = 200;

/// Whether an extreme reached by `at` samples, with `in_band` samples in the band just
/// inside it ([`RAIL_BAND_PER_SPAN`]), is piled up as a rail: more than four times as many
/// at it. A clipped signal piles up at its rail; a clean one, even quantised and slow
/// enough to repeat its peak code, thins out toward its peak. The one rule of the
/// streaming [`HeldRailCheck`] and of the std crate's measured range of a capture.
///
/// ```
/// use angletrack_core::is_piled_up_at_rail;
/// assert!(is_piled_up_at_rail(41, 10));
/// assert!(!is_piled_up_at_rail(40, 10));
/// ```
pub const fn is_piled_up_at_rail(at: u64, in_band: u64) -> bool {
    at > 4 * in_band
}

/// The counts of the pile-up test are halved from this value on (their ratio kept).
const COUNT_LIMIT: u16 = 1 << 15;

/// A sample type the [`HeldRailCheck`] measures rails on: `f32` and `f64`, and `i16` (the
/// fixed-point chain's samples after its ADC stage, whose differences are taken in 32 bits).
pub trait RailSample: Copy + PartialOrd + Default {
    /// The band just inside an extreme, in the form [`RailSample::is_near`] takes.
    type Band: Copy;
    /// `false` for NaN and infinities (left to the observer).
    fn is_number(self) -> bool;
    /// The band just inside an extreme for samples from `low` to `high`: the span over
    /// [`RAIL_BAND_PER_SPAN`].
    fn band(low: Self, high: Self) -> Self::Band;
    /// Whether `x` is within `band` of `value`.
    fn is_near(x: Self, value: Self, band: Self::Band) -> bool;
    /// The open interval of samples farther than the band from both extremes `low` and
    /// `high`: a sample inside it is [`RailSample::is_near`] neither (the check's quick path).
    fn far_inside(low: Self, high: Self) -> (Self, Self);
    /// Whether the samples from `low` to `high` span more than 1.5 times the larger of
    /// `|x_c|` and `|x_s|` (both sides of zero, as a resolver's windings do once the ADC's
    /// mid-scale is removed).
    fn spans(low: Self, high: Self, x_c: Self, x_s: Self) -> bool;
}

impl<T: Float> RailSample for T {
    type Band = T;

    #[inline(always)]
    fn is_number(self) -> bool {
        self.is_finite()
    }

    #[inline(always)]
    fn band(low: T, high: T) -> T {
        (high - low) * T::from_f32(1.0 / RAIL_BAND_PER_SPAN as f32)
    }

    #[inline(always)]
    fn is_near(x: T, value: T, band: T) -> bool {
        (x - value).abs() <= band
    }

    #[inline(always)]
    fn far_inside(low: T, high: T) -> (T, T) {
        // Twice the band: a margin for the rounding of the sums.
        let band = T::band(low, high);
        (low + (band + band), high - (band + band))
    }

    #[inline(always)]
    fn spans(low: T, high: T, x_c: T, x_s: T) -> bool {
        high - low > T::from_f32(1.5) * x_c.abs().max(x_s.abs())
    }
}

/// The band is the span itself, the distance multiplied by [`RAIL_BAND_PER_SPAN`] instead:
/// no division per sample (a library call on cores without a divider).
impl RailSample for i16 {
    type Band = i32;

    #[inline(always)]
    fn is_number(self) -> bool {
        true
    }

    #[inline(always)]
    fn band(low: i16, high: i16) -> i32 {
        i32::from(high) - i32::from(low)
    }

    #[inline(always)]
    fn is_near(x: i16, value: i16, span: i32) -> bool {
        // At most 65535 * 200: within an i32.
        (i32::from(x) - i32::from(value)).abs() * i32::from(RAIL_BAND_PER_SPAN) <= span
    }

    #[inline(always)]
    fn far_inside(low: i16, high: i16) -> (i16, i16) {
        // x - low > floor(span / 200) makes 200 (x - low) > span: not near. The quotient
        // by a product and shifts, floor(span / 8) * 5243 / 2^17, exact for every span of
        // ordered extremes (0 to 65535): a core without a divider calls no division routine.
        // Between the extremes: an i16.
        const { assert!(RAIL_BAND_PER_SPAN == 200) };
        let band = (((i32::from(high) - i32::from(low)) >> 3) * 5243) >> 17;
        (
            (i32::from(low) + band) as i16,
            (i32::from(high) - band) as i16,
        )
    }

    #[inline(always)]
    fn spans(low: i16, high: i16, x_c: i16, x_s: i16) -> bool {
        let largest = i32::from(x_c).abs().max(i32::from(x_s).abs());
        2 * (i32::from(high) - i32::from(low)) > 3 * largest
    }
}

/// One side's extreme (the lowest or the highest sample of either channel so far) and the
/// evidence that it is a rail.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Side<T> {
    value: T,
    /// Each channel's consecutive samples at `value` while the other channel moved.
    run: [u8; 2],
    /// Some channel was held at `value` for [`HELD_RAIL_SAMPLES`].
    held: bool,
    /// Samples at `value`, and samples in the band just inside it (half a percent of the
    /// span), since `value` was reached.
    at: u16,
    band: u16,
}

impl<T: RailSample> Side<T> {
    /// Whether the extreme is a rail: held flat, and piled up ([`is_piled_up_at_rail`]).
    fn is_rail(&self) -> bool {
        self.held && is_piled_up_at_rail(u64::from(self.at), u64::from(self.band))
    }

    /// Books channel `k`'s sample `x`, beyond (`beyond(x, value)`), at, or inside the
    /// extreme (within `band` of it: `inside(x, value, band)`), `moved` whether the other
    /// channel moved since the last sample.
    #[inline(always)]
    fn book(&mut self, k: usize, x: T, moved: bool, band: T::Band, low: bool) {
        let beyond = if low { x < self.value } else { x > self.value };
        if beyond {
            // A new extreme: the old one's samples are in its band if it is close.
            let close = T::is_near(x, self.value, band);
            self.band = if close {
                self.band.saturating_add(self.at)
            } else {
                0
            };
            *self = Side {
                value: x,
                band: self.band,
                ..Side::default()
            };
        }
        let run = self.run.get_mut(k);
        if x == self.value {
            self.at = self.at.saturating_add(1);
            if let Some(run) = run {
                *run = run.saturating_add(u8::from(moved));
                self.held |= *run >= HELD_RAIL_SAMPLES;
            }
        } else {
            if let Some(run) = run {
                *run = 0;
            }
            if T::is_near(x, self.value, band) {
                self.band = self.band.saturating_add(1);
            }
        }
        if self.at >= COUNT_LIMIT || self.band >= COUNT_LIMIT {
            self.at /= 2;
            self.band /= 2;
        }
    }
}

/// The state of a [`HeldRailCheck`]: the extremes and their evidence, the last sample, and
/// the check's faults ([`FrontEndCheckState`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HeldRails<T> {
    check: FrontEndCheckState,
    started: bool,
    last: (T, T),
    low: Side<T>,
    high: Side<T>,
    /// Samples strictly inside are far from both extremes ([`RailSample::far_inside`]).
    far_inside: (T, T),
}

impl<T: RailSample> HeldRails<T> {
    /// The front-end faults found (the last sample's, latched, and whether it coasted).
    pub fn check(&self) -> &FrontEndCheckState {
        &self.check
    }

    /// The front-end faults latched since the last clear, cleared.
    pub fn clear_faults(&mut self) -> FrontEndFaults {
        self.check.clear_faults()
    }

    /// The rails found so far, `(low, high)`, each `None` while not found.
    pub fn rails(&self) -> (Option<T>, Option<T>) {
        (
            self.low.is_rail().then_some(self.low.value),
            self.high.is_rail().then_some(self.high.value),
        )
    }
}

/// Clipping without a stated ADC range: the rails measured on the samples as they come.
/// An extreme (the lowest or highest sample of either channel so far) is a rail once a
/// channel sits at it for [`HELD_RAIL_SAMPLES`] consecutive samples while the other channel
/// moves (a still shaft holds both), the samples piled up there (more than four times those
/// of the band half a percent of the span inside it), on a signal spanning more than 1.5
/// times its largest channel (both sides of zero, as a resolver's windings after the ADC's
/// mid-scale is removed). A sample with a channel at a rail is flagged
/// [`FrontEndFaults::CLIPPING`] ([`Faults::FRONT_END`] on the estimate); with both, the
/// observer coasts on its prediction. A finite stated range is the better test
/// ([`FrontEndCheck::around`](crate::FrontEndCheck::around)): use this one where none is
/// known. NaN and infinite samples are left to the observer (`BAD_SAMPLE`).
///
/// ```
/// use angletrack_core::{Chain, ChainState, Faults, Gains, HeldRailCheck};
/// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?;
/// let chain = Chain::new(HeldRailCheck::new(), gains);
/// let mut state = ChainState::new();
/// let mut flagged = 0;
/// for k in 0..2000 {
///     // 50 rev/s, amplitude 1.4, clipped at +-0.9 (rails nobody stated).
///     let theta = 0.0314_f32 * k as f32;
///     let clip = |v: f32| v.clamp(-0.9, 0.9);
///     let e = chain.update(&mut state, (clip(1.4 * theta.cos()), clip(1.4 * theta.sin())));
///     flagged += usize::from(e.faults.contains(Faults::FRONT_END));
/// }
/// assert_eq!(state.front_end.rails(), (Some(-0.9), Some(0.9)));
/// assert!(flagged > 1800, "{flagged}");
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HeldRailCheck;

impl HeldRailCheck {
    /// The check (it has no setting).
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, Gains, HeldRailCheck};
    /// let chain = Chain::new(HeldRailCheck::new(), Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?);
    /// let mut state = ChainState::new();
    /// chain.update(&mut state, (0.8, 0.6));
    /// assert_eq!(state.front_end.rails(), (None, None));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new() -> Self {
        Self
    }
}

impl<T: RailSample + ChainNumber> Stage<T, (T, T)> for HeldRailCheck {
    type State = HeldRails<T>;
    type Memo = ();
    const QUIET_FROM_INPUT: bool = true;

    #[inline(always)]
    fn forward(
        &self,
        s: &mut HeldRails<T>,
        _: &impl Prediction<T>,
        (y_c, y_s): (T, T),
    ) -> ((T, T), ()) {
        if !(y_c.is_number() && y_s.is_number()) {
            s.check.set(FrontEndFaults::NONE, false);
            return ((y_c, y_s), ());
        }
        if !s.started {
            s.started = true;
            (s.low.value, s.high.value) = if y_c < y_s { (y_c, y_s) } else { (y_s, y_c) };
            s.last = (y_c, y_s);
        }
        // Most samples are far from both extremes: no count moves, no channel is held at
        // one, none is clipped (a comparison each instead of the booking).
        let (above, below) = s.far_inside;
        if y_c > above && y_c < below && y_s > above && y_s < below {
            s.low.run = [0; 2];
            s.high.run = [0; 2];
            s.last = (y_c, y_s);
            s.check.set(FrontEndFaults::NONE, false);
            return ((y_c, y_s), ());
        }
        let band = T::band(s.low.value, s.high.value);
        let moved = [y_s != s.last.1, y_c != s.last.0];
        for (k, x) in [y_c, y_s].into_iter().enumerate() {
            let moved = moved.get(k).copied().unwrap_or(false);
            s.low.book(k, x, moved, band, true);
            s.high.book(k, x, moved, band, false);
        }
        s.last = (y_c, y_s);
        s.far_inside = T::far_inside(s.low.value, s.high.value);
        let spans = T::spans(s.low.value, s.high.value, y_c, y_s);
        let (low, high) = (spans && s.low.is_rail(), spans && s.high.is_rail());
        let clipped = |x: T| (low && x <= s.low.value) || (high && x >= s.high.value);
        let (clipped_c, clipped_s) = (clipped(y_c), clipped(y_s));
        s.check.set(
            FrontEndFaults::when(clipped_c || clipped_s, FrontEndFaults::CLIPPING),
            clipped_c && clipped_s,
        );
        ((y_c, y_s), ())
    }

    #[inline(always)]
    fn faults(&self, s: &mut HeldRails<T>) -> Faults {
        s.check.chain_faults()
    }

    #[inline(always)]
    fn coasts(&self, s: &HeldRails<T>) -> bool {
        s.check.coasting()
    }

    #[inline(always)]
    fn quiet(&self, s: &HeldRails<T>) -> bool {
        s.check.faults().is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Chain, ChainState, Gains};

    /// Sample `k` of a resolver at `step` rad per sample from 0.3 rad and amplitude
    /// `amplitude`, rounded to counts and clipped to `[-rail, rail]`.
    fn counts(k: usize, step: f64, amplitude: f64, rail: f64) -> (f64, f64) {
        let theta = 0.3 + step * k as f64;
        let count = |v: f64| libm::round(amplitude * v).clamp(-rail, rail);
        (count(libm::cos(theta)), count(libm::sin(theta)))
    }

    /// `samples` of [`counts`] through the check: the samples flagged, those coasted, and
    /// the rails found.
    fn run(
        step: f64,
        amplitude: f64,
        rail: f64,
        samples: usize,
    ) -> (usize, usize, (Option<f64>, Option<f64>)) {
        let gains = Gains::<f64, 3>::new([0.3, 0.04, 0.002], 1e-4).unwrap();
        let chain = Chain::new(HeldRailCheck::new(), gains);
        let mut state = ChainState::new();
        let (mut flagged, mut coasted) = (0, 0);
        for k in 0..samples {
            let e = chain.update(&mut state, counts(k, step, amplitude, rail));
            flagged += usize::from(e.faults.contains(Faults::FRONT_END));
            coasted += usize::from(state.front_end.check().coasting());
        }
        (flagged, coasted, state.front_end.rails())
    }

    /// The same through the fixed-point chain: signed counts of `bits` bits (2 to 16), the
    /// ADC stage shifting them to 16 bits, then the check.
    fn run_fixed(
        step: f64,
        amplitude: f64,
        rail: f64,
        bits: u32,
        samples: usize,
    ) -> (usize, usize, (Option<i16>, Option<i16>)) {
        let gains = crate::FixedGains::<3>::new([0.3, 0.04, 0.002], 1e-4).unwrap();
        let adc = crate::AdcCounts::twos_complement(bits).unwrap();
        let chain = Chain::new((adc, HeldRailCheck::new()), gains);
        let mut state = ChainState::new();
        let (mut flagged, mut coasted) = (0, 0);
        for k in 0..samples {
            let (c, s) = counts(k, step, amplitude, rail);
            let e = chain.update(&mut state, (c as i16, s as i16));
            flagged += usize::from(e.faults.contains(Faults::FRONT_END));
            coasted += usize::from(state.front_end.1.check().coasting());
        }
        (flagged, coasted, state.front_end.1.rails())
    }

    #[test]
    fn the_fixed_point_band_is_the_span_over_200_for_every_span() {
        for span in 0..=65535 {
            let (low, high) = (i16::MIN, (i32::from(i16::MIN) + span) as i16);
            let (above, below) = <i16 as RailSample>::far_inside(low, high);
            let band = span / i32::from(RAIL_BAND_PER_SPAN);
            assert_eq!(
                (i32::from(above), i32::from(below)),
                (-32768 + band, -32768 + span - band)
            );
        }
    }

    #[test]
    fn the_fixed_point_chain_finds_the_rails_of_clipped_counts() {
        // As the float test below, in the fixed-point chain: the rails at +-2047 counts,
        // shifted by the ADC stage's 4 bits to +-32752.
        let (flagged, coasted, rails) = run_fixed(0.0314, 3184.0, 2047.0, 12, 2000);
        assert_eq!(rails, (Some(-32752), Some(32752)));
        assert!(flagged > 1800, "{flagged}");
        assert!((160..280).contains(&coasted), "{coasted}");
        // 16-bit counts clipped at their full scale: the spans in 32 bits do not wrap.
        let (flagged, _, rails) = run_fixed(0.0314, 46000.0, 32767.0, 16, 2000);
        assert_eq!(rails, (Some(-32767), Some(32767)));
        assert!(flagged > 1800, "{flagged}");
    }

    #[test]
    fn the_fixed_point_chain_finds_no_rail_on_clean_or_still_counts() {
        for step in [0.0314, 6.28e-4] {
            let (flagged, _, rails) = run_fixed(step, 1800.0, 2047.0, 12, 12_000);
            assert_eq!((flagged, rails), (0, (None, None)), "step {step}");
        }
        let (flagged, _, rails) = run_fixed(0.0, 1800.0, 2047.0, 12, 2000);
        assert_eq!((flagged, rails), (0, (None, None)));
    }

    #[test]
    fn signed_12_bit_counts_clipped_at_their_rails_are_found() {
        // Amplitude 1.4 where the rails are at 0.9 (3184 counts), 50 rev/s at 10 kHz: both
        // rails found within the first turn, every sample after flagged (|cos| >= 0.9/1.4
        // on 56 % of the turn: one channel at least is at a rail at every angle).
        let (flagged, coasted, rails) = run(0.0314, 3184.0, 2047.0, 2000);
        assert_eq!(rails, (Some(-2047.0), Some(2047.0)));
        assert!(flagged > 1800, "{flagged}");
        // Both channels clipped around the diagonals: 11 % of the turn.
        assert!((160..280).contains(&coasted), "{coasted}");
    }

    #[test]
    fn a_clean_quantised_signal_at_any_speed_has_no_rail() {
        // 1800 counts: fast, and slow enough to repeat its peak code for 75 samples.
        for step in [0.0314, 6.28e-4] {
            let (flagged, _, rails) = run(step, 1800.0, 2047.0, 12_000);
            assert_eq!((flagged, rails), (0, (None, None)), "step {step}");
        }
    }

    #[test]
    fn a_still_shaft_has_no_rail() {
        // Held still (at 0.3 rad) or turning by a count's noise: no channel moves for long.
        let (flagged, _, rails) = run(0.0, 1800.0, 2047.0, 2000);
        assert_eq!((flagged, rails), (0, (None, None)));
        let (flagged, _, _) = run(1e-6, 1800.0, 2047.0, 2000);
        assert_eq!(flagged, 0);
    }
}
