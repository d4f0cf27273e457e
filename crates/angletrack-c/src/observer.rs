//! `at_state_f32` (one channel's mutable state, of the order of the gains it is updated
//! with) and `at_estimate_f32` (what an update reports), and the updates: plain, from ADC
//! counts, and through the online calibration.

use core::mem::MaybeUninit;

use angletrack_core::{
    AdcSample, AdcScaling, Chain, Estimate, Gains, ObserverState, Order, SupportedOrder,
};

use crate::calibration::at_calibrator_f32;
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::gains::{at_gains_f32, with_gains};
use crate::slot::{self, Refused, Stored};

/// The 8-byte words of an `at_state_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_STATE_F32_WORDS: usize = 11;

/// One channel's mutable state: angle, speed, acceleration, turn count, the diagnostics'
/// filters and latched faults. A zeroed one (C static memory) is a fresh state, as after
/// `at_state_f32_reset`: it initialises itself from its first sample. It takes the order of
/// the gains it is updated with: updated with gains of another order than its last, it
/// starts afresh. Place it anywhere; copy it by assignment; never write its fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_state_f32 {
    /// Private: which Rust value `storage` holds (0: a fresh state).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_STATE_F32_WORDS],
}

slot::slot_struct!(at_state_f32, AT_STATE_F32_WORDS);

/// What the observer knows after a sample.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct at_estimate_f32 {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    pub angle: f32,
    /// Whole turns counted since initialisation (positive counter-clockwise); the
    /// multi-turn position is `turns * 2 pi + angle` (rad).
    pub turns: i64,
    /// Estimated speed (rad/s).
    pub speed: f32,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    pub acceleration: f32,
    /// Normalised phase-detector output of this sample (about the sine of the phase
    /// error, dimensionless); 0 when the sample was rejected.
    pub phase_error: f32,
    /// This sample's faults (`AT_FAULT_*` bits); the state also latches them.
    pub faults: u32,
}

impl From<Estimate<f32>> for at_estimate_f32 {
    fn from(e: Estimate<f32>) -> Self {
        Self {
            angle: e.angle,
            turns: e.turns,
            speed: e.speed,
            acceleration: e.acceleration,
            phase_error: e.phase_error,
            faults: u32::from(e.faults.bits()),
        }
    }
}

impl at_estimate_f32 {
    /// The estimate of a call whose arguments were NULL or not initialised.
    pub(crate) const INVALID: Self = Self {
        angle: 0.0,
        turns: 0,
        speed: 0.0,
        acceleration: 0.0,
        phase_error: 0.0,
        faults: AT_FAULT_INVALID_ARGUMENT,
    };
}

impl at_state_f32 {
    /// A fresh state (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The state of an observer of order `N`: the one held, or a fresh one if it held none
    /// or one of the other order; refused if another build's.
    pub(crate) fn of_order<const N: usize>(&mut self) -> Result<&mut ObserverState<f32, N>, Refused>
    where
        ObserverState<f32, N>: Stored,
    {
        self.slot_get_or_put(ObserverState::new)
    }

    /// A copy of the state of order `N`: the one held, or a fresh one if it holds none or
    /// one of the other order; refused if another build's.
    pub(crate) fn value_of_order<const N: usize>(&self) -> Result<ObserverState<f32, N>, Refused>
    where
        ObserverState<f32, N>: Stored,
    {
        match self.slot_get() {
            Ok(s) => Ok(*s),
            Err(Refused::NotInitialised) => Ok(ObserverState::new()),
            Err(refused) => Err(refused),
        }
    }

    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        let faults = match self.tag {
            t if t == <ObserverState<f32, 2> as Stored>::TAG => {
                self.of_order::<2>().map(|s| s.clear_faults())
            }
            t if t == <ObserverState<f32, 3> as Stored>::TAG => {
                self.of_order::<3>().map(|s| s.clear_faults())
            }
            _ => return 0,
        };
        faults.map_or(0, |f| u32::from(f.bits()))
    }
}

/// The core's gains of order `N` in `f32`.
type GainsF32<const N: usize> = Gains<f32, N>;
/// The core's state of order `N` in `f32`.
type StateF32<const N: usize> = ObserverState<f32, N>;

/// One sample of one observer, whatever its order and entry point.
pub(crate) trait Sample {
    /// Runs the sample through `gains` on `state`.
    fn update<const N: usize>(
        self,
        gains: &GainsF32<N>,
        state: &mut StateF32<N>,
    ) -> at_estimate_f32
    where
        Order<N>: SupportedOrder;
}

/// A sample of the demodulated signals `(y_c, y_s)`.
pub(crate) struct Signals(pub(crate) f32, pub(crate) f32);

impl Sample for Signals {
    #[inline(always)]
    fn update<const N: usize>(
        self,
        gains: &GainsF32<N>,
        state: &mut StateF32<N>,
    ) -> at_estimate_f32 {
        gains.update(state, self.0, self.1).into()
    }
}

/// A sample of raw ADC counts `(raw_c, raw_s)` with its front end.
pub(crate) struct Counts<'a, I>(pub(crate) &'a AdcScaling<f32>, pub(crate) I, pub(crate) I);

impl<I: AdcSample> Sample for Counts<'_, I> {
    #[inline(always)]
    fn update<const N: usize>(
        self,
        gains: &GainsF32<N>,
        state: &mut StateF32<N>,
    ) -> at_estimate_f32 {
        let (y_c, y_s) = self.0.sample(self.1, self.2);
        gains.update(state, y_c, y_s).into()
    }
}

/// A sample of `(y_c, y_s)` through an online calibration.
pub(crate) struct Calibrated<'a>(
    pub(crate) &'a mut at_calibrator_f32,
    pub(crate) f32,
    pub(crate) f32,
);

impl Sample for Calibrated<'_> {
    #[inline(always)]
    fn update<const N: usize>(
        self,
        gains: &GainsF32<N>,
        state: &mut StateF32<N>,
    ) -> at_estimate_f32 {
        match self.0.get_mut() {
            Ok(calibrator) => {
                // The chain of the gains' online calibration and the observer, on the two
                // states the C API keeps apart.
                Chain::new(gains.online_calibration(), *gains)
                    .update_parts(calibrator, state, (self.1, self.2))
                    .into()
            }
            Err(_) => at_estimate_f32::INVALID,
        }
    }
}

/// Runs `sample` through `gains` (if they were made) on `state`.
#[inline(always)]
pub(crate) fn run(
    gains: &at_gains_f32,
    state: &mut at_state_f32,
    sample: impl Sample,
) -> at_estimate_f32 {
    match gains.get() {
        Ok(any) => with_gains!(any, |g| match state.of_order() {
            Ok(state) => sample.update(g, state),
            Err(_) => at_estimate_f32::INVALID,
        }),
        Err(_) => at_estimate_f32::INVALID,
    }
}
