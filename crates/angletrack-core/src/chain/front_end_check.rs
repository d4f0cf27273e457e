//! The front end's faults as stages of a chain (`docs/theory.md §15`): [`FrontEndCheck`]
//! (the faults a demodulator gives with each pair, and clipping against a stated ADC range)
//! and [`WindingCheck`] (a winding open or shorted, against the observer's prediction). A
//! sample whose measurement they invalidate is not used: the observer coasts on its
//! prediction ([`Stage::coasts`]) and the estimate carries [`Faults::FRONT_END`].

use super::{Feedback, Prediction, Stage};
use crate::adc::AdcCounts;
use crate::error::{ConfigError, Parameter};
use crate::faults::Faults;
use crate::front_end_faults::FrontEndFaults;
use crate::real::{ChainNumber, Float, check_positive};

/// The mutable state of a [`FrontEndCheck`] or a [`WindingCheck`]: the front-end faults of
/// the last sample, whether it was a measurement, and the faults latched since the last
/// [`FrontEndCheckState::clear_faults`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrontEndCheckState {
    faults: FrontEndFaults,
    coasting: bool,
    latched: FrontEndFaults,
    /// [`WindingCheck`]: the cosine and sine windings found open or shorted, held until
    /// they read again.
    open: [bool; 2],
}

impl FrontEndCheckState {
    /// The front-end faults of the last sample.
    pub fn faults(&self) -> FrontEndFaults {
        self.faults
    }

    /// Whether the last sample was not a measurement (the observer coasted).
    pub fn coasting(&self) -> bool {
        self.coasting
    }

    /// The front-end faults latched since the last clear.
    pub fn latched_faults(&self) -> FrontEndFaults {
        self.latched
    }

    /// Clears the latched faults and returns them.
    pub fn clear_faults(&mut self) -> FrontEndFaults {
        core::mem::take(&mut self.latched)
    }

    /// Books one sample's `faults`, the observer coasting if `coasting`.
    #[inline(always)]
    pub(super) fn set(&mut self, faults: FrontEndFaults, coasting: bool) {
        self.faults = faults;
        self.coasting = coasting;
        self.latched |= faults;
    }

    /// [`Faults::FRONT_END`] while the last sample has a front-end fault.
    #[inline(always)]
    pub(super) fn chain_faults(&self) -> Faults {
        Faults::when(!self.faults.is_empty(), Faults::FRONT_END)
    }
}

/// The front end's faults before the observer, around the stage `S` that takes the samples
/// `(X, X)` (the ADC's [`AdcScaling`](crate::AdcScaling) or
/// [`AdcCounts`](crate::AdcCounts) for raw counts; `()` for pairs already in the
/// observer's units). It takes either the samples alone or the samples with the
/// [`FrontEndFaults`] a demodulator gave them ([`DemodulatedPair`](crate::DemodulatedPair)`
/// ::faults`), and with a stated ADC range flags [`FrontEndFaults::CLIPPING`] for a sample
/// at or beyond a rail (or not a number). While the sample is not a measurement (loss of
/// excitation, a winding open or shorted: [`FrontEndFaults::INVALIDATING`]; both channels
/// clipped) the observer coasts on its prediction; every fault puts [`Faults::FRONT_END`]
/// on the estimate. On a sample without a fault the chain's quiet path runs (a few
/// comparisons).
///
/// ```
/// use angletrack_core::{Chain, ChainState, Faults, FrontEndCheck, FrontEndFaults, Gains};
/// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?;
/// let chain = Chain::new(FrontEndCheck::<f32>::new(), gains);
/// let mut state = ChainState::new();
/// let (mut theta, speed) = (0.0_f32, 0.02_f32);
/// for _ in 0..2000 {
///     chain.update(&mut state, ((theta.cos(), theta.sin()), FrontEndFaults::NONE));
///     theta += speed;
/// }
/// // The excitation is lost for 100 pairs: the observer coasts on its prediction.
/// for _ in 0..100 {
///     let e = chain.update(&mut state, ((0.0, 0.0), FrontEndFaults::LOSS_OF_EXCITATION));
///     assert!(e.faults.contains(Faults::FRONT_END));
///     theta += speed;
/// }
/// let e = chain.update(&mut state, ((theta.cos(), theta.sin()), FrontEndFaults::NONE));
/// let error = libm::remainderf(e.angle - theta, core::f32::consts::TAU);
/// assert!(error.abs() < 0.02, "{error}");
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontEndCheck<X, S = ()> {
    range: Option<(X, X)>,
    inner: S,
}

impl<X> FrontEndCheck<X> {
    /// No ADC range: the faults given with the samples only, before no other stage.
    pub const fn new() -> Self {
        Self {
            range: None,
            inner: (),
        }
    }
}

impl FrontEndCheck<i16> {
    /// The fixed-point chain's check of its 16-bit samples against the ADC's range of codes
    /// `min_counts` to `max_counts` (as the chain takes them), taken through `adc`: exact, a
    /// code at a rail gives the rail's sample (saturated beyond 16 bits, as the samples are).
    /// Refuses codes that are not ordered, or that the saturation joins
    /// ([`Parameter::AdcRange`]).
    ///
    /// ```
    /// use angletrack_core::{AdcCounts, FrontEndCheck, Parameter};
    /// let adc = AdcCounts::offset_binary(12)?;
    /// let check = FrontEndCheck::of_adc_codes(&adc, 0, 4095)?;
    /// assert_eq!(check.adc_range(), Some((-32768, 32752)));
    /// let err = FrontEndCheck::of_adc_codes(&adc, 4095, 0).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AdcRange);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn of_adc_codes(
        adc: &AdcCounts,
        min_counts: i32,
        max_counts: i32,
    ) -> Result<Self, ConfigError> {
        // Ordered in codes first: the ADC's saturation keeps the order, but may join them.
        FrontEndCheck::<i32>::around((), Some((min_counts, max_counts)))?;
        Self::around((), Some(adc.sample(min_counts, max_counts)))
    }
}

impl<X: Copy> FrontEndCheck<X> {
    /// The check of a range its caller found ordered (`min < max`), or of none.
    pub(crate) const fn of_ordered_range(range: Option<(X, X)>) -> Self {
        Self { range, inner: () }
    }
}

impl<X> Default for FrontEndCheck<X> {
    fn default() -> Self {
        Self::new()
    }
}

impl<X: PartialOrd + Copy, S> FrontEndCheck<X, S> {
    /// The check around the stage `inner`, with clipping flagged for a sample at or beyond
    /// `min` or `max` (the ADC's lowest and highest codes, or the range in the samples'
    /// units); `None`: no clipping check. Refuses a range that is empty or not ordered
    /// ([`Parameter::AdcRange`]).
    ///
    /// ```
    /// use angletrack_core::{AdcScaling, FrontEndCheck, Parameter};
    /// let adc = AdcScaling::<f32>::offset_binary(12)?;
    /// let check = FrontEndCheck::around(adc, Some((0u16, 4095u16)))?;
    /// let err = FrontEndCheck::around(adc, Some((4095u16, 0u16))).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AdcRange);
    /// # let _ = check;
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn around(inner: S, range: Option<(X, X)>) -> Result<Self, ConfigError> {
        if let Some((min, max)) = range
            && !(min < max)
        {
            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
        }
        Ok(Self { range, inner })
    }

    /// The stated ADC range, if any.
    pub fn adc_range(&self) -> Option<(X, X)> {
        self.range
    }

    /// The stage the samples go through.
    pub fn inner(&self) -> &S {
        &self.inner
    }

    /// The faults of one sample `(x_c, x_s)` with those `given` with it, booked in `state`.
    #[inline(always)]
    fn check(&self, state: &mut FrontEndCheckState, (x_c, x_s): (X, X), given: FrontEndFaults) {
        let (clipped_c, clipped_s) = match self.range {
            // NaN compares false: clipped.
            Some((min, max)) => (!(x_c > min && x_c < max), !(x_s > min && x_s < max)),
            None => (false, false),
        };
        let faults = given | FrontEndFaults::when(clipped_c || clipped_s, FrontEndFaults::CLIPPING);
        let coasting = given.intersects(FrontEndFaults::INVALIDATING) || (clipped_c && clipped_s);
        state.set(faults, coasting);
    }
}

/// The stage's methods but `forward`, the same for both inputs.
macro_rules! check_stage_methods {
    ($value:ty, $input:ty) => {
        #[inline(always)]
        fn feedback(
            &self,
            state: &mut Self::State,
            memo: Self::Memo,
            used: Option<Feedback<$value>>,
        ) {
            self.inner.feedback(&mut state.1, memo, used);
        }

        #[inline(always)]
        fn faults(&self, state: &mut Self::State) -> Faults {
            state.0.chain_faults() | self.inner.faults(&mut state.1)
        }

        #[inline(always)]
        fn coasts(&self, state: &Self::State) -> bool {
            state.0.coasting || self.inner.coasts(&state.1)
        }

        #[inline(always)]
        fn quiet(&self, state: &Self::State) -> bool {
            state.0.faults.is_empty() && self.inner.quiet(&state.1)
        }
    };
}

/// The samples alone: clipping against the stated range.
impl<V: ChainNumber, X: PartialOrd + Copy, S: Stage<V, (X, X)>> Stage<V, (X, X)>
    for FrontEndCheck<X, S>
{
    type State = (FrontEndCheckState, S::State);
    type Memo = S::Memo;
    const QUIET_FROM_INPUT: bool = true;

    #[inline(always)]
    fn forward(
        &self,
        state: &mut Self::State,
        prediction: &impl Prediction<V>,
        input: (X, X),
    ) -> ((V, V), S::Memo) {
        self.check(&mut state.0, input, FrontEndFaults::NONE);
        self.inner.forward(&mut state.1, prediction, input)
    }

    check_stage_methods!(V, (X, X));
}

/// The samples with the front-end faults a demodulator gave them.
impl<V: ChainNumber, X: PartialOrd + Copy, S: Stage<V, (X, X)>> Stage<V, ((X, X), FrontEndFaults)>
    for FrontEndCheck<X, S>
{
    type State = (FrontEndCheckState, S::State);
    type Memo = S::Memo;
    const QUIET_FROM_INPUT: bool = true;

    #[inline(always)]
    fn forward(
        &self,
        state: &mut Self::State,
        prediction: &impl Prediction<V>,
        (input, given): ((X, X), FrontEndFaults),
    ) -> ((V, V), S::Memo) {
        self.check(&mut state.0, input, given);
        self.inner.forward(&mut state.1, prediction, input)
    }

    check_stage_methods!(V, ((X, X), FrontEndFaults));
}

/// A winding open or shorted, seen against the observer's prediction `p`: flagged
/// ([`FrontEndFaults::WINDING`]) when one winding reads below a quarter of the nominal
/// amplitude `A` where the prediction puts at least half of it on that winding
/// (`|cos p| >= 1/2` for `y_c`), while the other winding is within `A/4` of its predicted
/// value (so that an observer far off, whose prediction disagrees with both windings, is
/// not taken for a winding fault and keeps correcting); then held while that winding reads
/// below `A/4`. The observer coasts while it holds. A winding is seen at once where the
/// prediction puts half the amplitude on it (two thirds of each electrical turn), and
/// otherwise as soon as the shaft turns there; a winding that reads zero where it should
/// read near zero anyway is no error yet.
///
/// ```
/// use angletrack_core::{Chain, ChainState, Faults, FrontEndFaults, Gains, WindingCheck};
/// let gains = Gains::<f64, 3>::new([0.3, 0.04, 0.002], 1e-4)?;
/// let chain = Chain::new(WindingCheck::new(1.0)?, gains);
/// let mut state = ChainState::new();
/// for _ in 0..200 {
///     chain.update(&mut state, (0.643, 0.766)); // 50 degrees
/// }
/// // The cosine winding opens: flagged on the first sample, the angle held.
/// let e = chain.update(&mut state, (0.0, 0.766));
/// assert!(e.faults.contains(Faults::FRONT_END));
/// assert_eq!(state.front_end.faults(), FrontEndFaults::WINDING);
/// assert!((e.angle - 0.8727).abs() < 1e-3);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindingCheck<T> {
    pub(crate) amplitude: T,
}

impl<T: Float> WindingCheck<T> {
    /// The check for windings of nominal amplitude `amplitude` (the envelope's peak in the
    /// samples' units: 1 for a demodulator's pairs), finite and positive
    /// ([`Parameter::NominalAmplitude`]).
    pub fn new(amplitude: T) -> Result<Self, ConfigError> {
        Ok(Self {
            amplitude: check_positive(amplitude, Parameter::NominalAmplitude)?,
        })
    }

    /// The nominal amplitude.
    pub fn amplitude(&self) -> T {
        self.amplitude
    }
}

impl<T: Float> Stage<T, (T, T)> for WindingCheck<T> {
    type State = FrontEndCheckState;
    type Memo = ();
    const QUIET_FROM_INPUT: bool = true;

    #[inline(always)]
    fn forward(
        &self,
        state: &mut FrontEndCheckState,
        prediction: &impl Prediction<T>,
        (y_c, y_s): (T, T),
    ) -> ((T, T), ()) {
        let (sin_p, cos_p) = prediction.sin_cos();
        let a = self.amplitude;
        let quarter = a * T::HALF * T::HALF;
        // Found where the prediction puts half the amplitude on the winding and the other
        // winding agrees with it; held while the winding reads below a quarter (so that the
        // observer is not drawn to the angle of the one winding left as the shaft turns
        // past the other's zero).
        let open_c = y_c.abs() < quarter
            && (state.open[0] || (cos_p.abs() >= T::HALF && (y_s - a * sin_p).abs() < quarter));
        let open_s = y_s.abs() < quarter
            && (state.open[1] || (sin_p.abs() >= T::HALF && (y_c - a * cos_p).abs() < quarter));
        state.open = [open_c, open_s];
        let winding = open_c || open_s;
        state.set(
            FrontEndFaults::when(winding, FrontEndFaults::WINDING),
            winding,
        );
        ((y_c, y_s), ())
    }

    #[inline(always)]
    fn faults(&self, state: &mut FrontEndCheckState) -> Faults {
        state.chain_faults()
    }

    #[inline(always)]
    fn coasts(&self, state: &FrontEndCheckState) -> bool {
        state.coasting
    }

    #[inline(always)]
    fn quiet(&self, state: &FrontEndCheckState) -> bool {
        state.faults.is_empty()
    }
}
