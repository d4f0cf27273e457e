//! The signal chain in `f32` (the core's `Tracker`): `at_chain_f32`, the configuration of
//! one chain built from optional stages (the ADC, a stored sensor calibration or the online
//! calibration with its settings, the harmonic angle correction or its table) and the
//! observer's gains;
//! `at_chain_state_f32`, one channel's state (the observer's, the front-end checks' and the
//! online calibration's);
//! what an update reports, `at_estimate_f32`; and the harmonic angle correction's plain
//! `at_angle_correction_f32`.
//!
//! The chain is the core's standard chain, `Tracker<f32, Gains<f32, N>>`, built by the
//! core's `TrackerFrontEnd::new` from the stages given: counts through the ADC's scaling
//! with clipping at its stated codes (or its rails measured when none are stated), a
//! demodulator's faults, the winding check if asked for, the calibration (none, stored or
//! online) and the angle correction (none, harmonics or table). This file only converts.

use angletrack_core::{
    AngleCorrection, CalibrationStage, Calibrator, ConfigError, CorrectionStage, Estimate, Gains,
    Input, MAX_CORRECTION_ORDER, ObserverState, OnlineCalibration, Rails, Tracker, TrackerFrontEnd,
    TrackerSettings, TrackerState, WindingCheck,
};

use crate::adc::AdcF32;
use crate::calibration::{at_calibration_settings_f32, at_sensor_calibration_f32};
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::gains::{at_gains_f32, with_order};
use crate::mirror::mirror;
use crate::slot::{self, Refused, Slot, Stored, by_order};
use crate::status::{AT_ERR_STAGES, AT_OK, at_status, status_of};
use crate::table::at_angle_correction_table_f32;

/// The 8-byte words of an `at_chain_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_F32_WORDS: usize = 284;
/// The 8-byte words of an `at_chain_state_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_STATE_F32_WORDS: usize = 32;

slot::slot_struct! {
    /// The checked configuration of one signal chain, made by `at_chain_f32_new` from the
    /// observer's gains and optional stages. Immutable once made: one serves any number of
    /// channels (`at_chain_state_f32`). Place it anywhere; copy it by assignment; never write its
    /// fields. A zeroed one is refused.
    at_chain_f32[AT_CHAIN_F32_WORDS]
}

slot::slot_struct! {
    /// One channel's state of a signal chain: the observer's state and the online
    /// calibration's estimator. A zeroed one is fresh (as after `at_chain_state_f32_reset`): the
    /// observer initialises itself from its first sample, the online calibration is off until
    /// `at_chain_state_f32_set_calibration_mode`. Place it anywhere; copy it by assignment;
    /// never write its fields.
    at_chain_state_f32[AT_CHAIN_STATE_F32_WORDS]
}

/// The harmonic orders an `at_angle_correction_f32` holds (the core's
/// `MAX_CORRECTION_ORDER`: the struct's arrays are the core's, checked at compile time).
pub const AT_CORRECTION_ORDER: usize = 8;

const _: () = assert!(AT_CORRECTION_ORDER == MAX_CORRECTION_ORDER);

/// A harmonic angle error `d(theta) = sum_k a_k cos(k theta) + b_k sin(k theta)`, `k = 1..8`
/// (rad), as `angletrack calibrate` learns it: the chain rotates each sample by `-d` at the
/// observer's predicted angle. All zero corrects nothing.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct at_angle_correction_f32 {
    /// `a_k` at index `k - 1` (rad).
    pub cos_coefficients: [f32; AT_CORRECTION_ORDER],
    /// `b_k` at index `k - 1` (rad).
    pub sin_coefficients: [f32; AT_CORRECTION_ORDER],
}

mirror! {
    /// What the observer knows after a sample.
    #[derive(Default)]
    at_estimate_f32: Estimate<f32> = |_: &Self| Estimate::default();
    /// Estimated angle (rad), wrapped to [-pi, pi).
    angle: f32 = angle,
    /// Whole turns counted since initialisation (positive counter-clockwise); the
    /// multi-turn position is `turns * 2 pi + angle` (rad).
    turns: i64 = turns,
    /// Estimated speed (rad/s).
    speed: f32 = speed,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    acceleration: f32 = acceleration,
    /// Normalised phase-detector output of this sample (about the sine of the phase
    /// error, dimensionless); 0 when the sample was rejected.
    phase_error: f32 = phase_error,
    /// This sample's faults (`AT_FAULT_*` bits); the state also latches them.
    faults: u32 = faults,
}

impl at_estimate_f32 {
    /// The estimate of a call whose arguments were refused (NULL, not made, another
    /// build's): `AT_FAULT_INVALID_ARGUMENT`, the rest 0.
    pub(crate) fn invalid() -> Self {
        Self {
            faults: AT_FAULT_INVALID_ARGUMENT,
            ..Self::default()
        }
    }
}

/// What an `at_chain_f32` holds: the core's standard chain of order `N`.
pub(crate) type ChainF32<const N: usize> = Tracker<f32, Gains<f32, N>>;

/// The state of a chain of order `N`.
pub(crate) type StateF32<const N: usize> = TrackerState<f32, ObserverState<f32, N>>;

impl<const N: usize> Stored for ChainF32<N> {
    const TAG: u32 = 0x4154_4b00 | N as u32; // "ATK", the order
}
impl<const N: usize> Stored for StateF32<N> {
    const TAG: u32 = 0x4154_6b00 | N as u32; // "ATk", the order
}

/// The optional stages `at_chain_f32_new` takes, as references.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stages<'a> {
    /// The ADC front end, with its stated range.
    pub(crate) adc: Option<&'a AdcF32>,
    /// A stored calibration.
    pub(crate) stored: Option<&'a at_sensor_calibration_f32>,
    /// The online calibration's settings.
    pub(crate) online: Option<&'a at_calibration_settings_f32>,
    /// The harmonic angle correction.
    pub(crate) correction: Option<&'a at_angle_correction_f32>,
    /// The angle correction's table.
    pub(crate) table: Option<&'a at_angle_correction_table_f32>,
}

/// The chain of `gains` and the checked `stages`.
fn build<const N: usize>(
    gains: &Gains<f32, N>,
    stages: Stages<'_>,
) -> Result<ChainF32<N>, ConfigError> {
    let calibration = match (stages.stored, stages.online) {
        (Some(stored), _) => CalibrationStage::Stored(stored.checked()?),
        (None, Some(settings)) => CalibrationStage::Online(OnlineCalibration::new(
            settings.to_core(),
            gains.sample_period(),
        )?),
        (None, None) => CalibrationStage::None,
    };
    let correction = match (stages.correction, stages.table) {
        (Some(c), _) => CorrectionStage::Harmonics(AngleCorrection::new(
            c.cos_coefficients,
            c.sin_coefficients,
        )?),
        (None, Some(table)) => CorrectionStage::Table(table.checked()?),
        (None, None) => CorrectionStage::None,
    };
    let input = match stages.adc {
        Some(adc) => Input::Counts {
            adc: adc.scaling,
            rails: adc
                .range
                .map_or(Rails::Measured, |(min, max)| Rails::Stated { min, max }),
        },
        None => Input::Units {
            rails: Rails::Unchecked,
        },
    };
    let front_end = TrackerFrontEnd::new(TrackerSettings {
        input,
        winding: None,
        calibration,
        correction,
    })?;
    Ok(Tracker::new(front_end, *gains))
}

impl at_chain_f32 {
    /// Builds and stores the chain (`self` unchanged on error).
    pub(crate) fn set(&mut self, gains: &at_gains_f32, stages: Stages<'_>) -> at_status {
        if (stages.stored.is_some() && stages.online.is_some())
            || (stages.correction.is_some() && stages.table.is_some())
        {
            return AT_ERR_STAGES;
        }
        let built = with_order!(gains.order, N => gains
            .core::<N>()
            .and_then(|g| build(&g, stages).map(|c| self.slot_put(c))));
        built.map_or_else(|status| status, |()| AT_OK)
    }

    /// Stores `chain` with the core's winding check for windings of `amplitude` (`self`
    /// unchanged on error).
    pub(crate) fn set_with_winding_check(&mut self, chain: &Self, amplitude: f32) -> at_status {
        match chain.get() {
            Ok(c) => by_order!(c, |c| self
                .slot_store(WindingCheck::new(amplitude).map(|w| {
                    Tracker::new(c.front_end.with_winding(Some(w)), c.observer)
                }))),
            Err(refused) => refused.status(),
        }
    }
}

impl at_chain_state_f32 {
    /// The calibrator of the state held (of either order), or a fresh one's; refused if
    /// another build's.
    pub(crate) fn calibrator(&mut self) -> Result<&mut Calibrator<f32>, Refused> {
        if self.tag == <StateF32<2> as Stored>::TAG {
            return self.of_order::<2>().map(|s| s.front_end.calibrator_mut());
        }
        self.of_order::<3>().map(|s| s.front_end.calibrator_mut())
    }

    /// Loads the stored calibration `stored` (checked; unchanged on error) into the
    /// calibrator, frozen.
    pub(crate) fn load_calibration(&mut self, stored: &at_sensor_calibration_f32) -> at_status {
        match (stored.checked(), self.calibrator()) {
            (Ok(calibration), Ok(c)) => *c = Calibrator::from_calibration(calibration),
            (Err(error), _) => return status_of(error),
            (_, Err(refused)) => return refused.status(),
        }
        AT_OK
    }

    /// A copy of the calibrator held (a fresh one's for a fresh state).
    pub(crate) fn calibrator_value(&self) -> Result<Calibrator<f32>, Refused> {
        match self.either::<StateF32<2>, StateF32<3>>() {
            Ok(s) => Ok(*by_order!(s, |s| s.front_end.calibrator())),
            Err(Refused::NotInitialised) => Ok(Calibrator::new()),
            Err(refused) => Err(refused),
        }
    }

    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        self.held().map_or(0, |s| {
            u32::from(by_order!(s, |s| s.observer.clear_faults()).bits())
        })
    }
}
