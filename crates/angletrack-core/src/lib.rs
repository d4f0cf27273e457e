//! Angle tracking observers (software resolver-to-digital conversion) for firmware:
//! `no_std`, no allocator, no panic on the per-sample path, `f32` or `f64`.
//!
//! A resolver (after demodulation), a sin/cos magnetic encoder or high-frequency injection
//! gives two noisy signals `y_c ~ cos(theta)` and `y_s ~ sin(theta)`. An angle tracking
//! observer (ATO) turns them into angle, speed and acceleration, sample by sample. This crate
//! implements the three observers of Auger, Mansouri-Toudert and Chibah, *Design of advanced
//! resolver-to-digital converters* (2011), as one predictor-corrector recursion on the scaled
//! state `X = (theta, Ts Omega[, Ts^2 alpha])`:
//!
//! ```text
//! X_p = A X_e                          A = [[1, 1, 1/2], [0, 1, 1], [0, 0, 1]] (order 3)
//! eps = (y_s cos(x1_p) - y_c sin(x1_p)) / |y|   heterodyne phase detector, normalised
//! X_e = X_p + L eps                    x1 wrapped to [-pi, pi), whole turns counted
//! ```
//!
//! The phase error is normalised by the signal's magnitude `|y| = sqrt(y_c^2 + y_s^2)` (in
//! `f32` tracked by one Heron step per sample), so the loop's dynamics and the stability
//! checked at construction hold at any amplitude and in any unit: volts, or raw ADC counts.
//!
//! The state also keeps the next sample's predicted angle `(A X_e)[0]`; in `f64` summed as
//! `(A X_p)[0] + (A L)[0] eps` (the same sum in another order): one sample's phase error then
//! reaches the next phase detector through a single multiply-add, which is what a loop over
//! samples waits for on a host (`f32`, the firmware's type, saves that multiply-add's
//! instructions instead).
//!
//! The mathematics is in the repository's `docs/theory.md`: the phase detector (§1), the
//! scaled state and this recursion (§5), the stability check of the gains (§6), the speed
//! limits (§9), the diagnostics (§10), the fast sin/cos (§11) and real signals (§12:
//! amplitude normalisation, ADC scaling, online correction of offsets, imbalance and
//! quadrature). One concept per module: `state` and `update` the recursion, `wrap` the
//! angle wrap and turn count, `gains` and `stability` the checked configuration, `monitor`
//! and `faults` the diagnostics, `real::sincos` the phase detector's sin/cos, `bank` many channels
//! at once, `chain` the front end's stages composed with the observer, `error` the refusals, `real` the float
//! types' arithmetic ([`Float`]) and sin/cos, `const_config` the checked configurations
//! ([`Real`]: [`Float`] with the configurations' checks), `adc` the ADC front end, `calibration` the sensor correction,
//! `calibration_settings` its configuration and `learning` its online estimator.
//! The resolver front end (§13) is `excitation` (the carrier to write out), `demodulator`
//! (ADC samples of the windings to one `(y_c, y_s)` pair per carrier period, the carrier
//! delay compensated) with `front_end_faults`, and `outputs` (the electrical angle at the
//! PWM update instant).
//!
//! Only the discrete gains `L` differ between the classical 2nd-order ATO (order 2), the
//! 3rd-order ATO designed by pole placement and the time-invariant Kalman ATO (order 3).
//! The gains come from the design tools of the `angletrack` crate or its command line
//! (`angletrack design ... --format rust`), or from the common designs here, computed on the
//! target in its float type so that firmware can retune at run time
//! ([`Gains::second_order_from_bandwidth`], [`Gains::third_order_from_poles`],
//! [`Gains::kalman`]); this crate checks them once, at construction, and refuses gains
//! outside the stability region of the discrete loop with a [`ConfigError`] that names the
//! parameter. A gain set can also be a `static`, checked by the compiler
//! ([`Gains::new_const`]).
//!
//! # Firmware use
//!
//! ```
//! use angletrack_core::{
//!     AdcScaling, Calibrator, Chain, ChainState, FaultThresholds, Gains, ObserverState,
//!     OnlineCalibration,
//! };
//!
//! // Once, at start-up: gains for a 20 kHz loop (from `angletrack design`), a 12-bit ADC
//! // (offset binary: full scale is +-1) and a signal of about 1800 counts, 0.88 of full
//! // scale, which the diagnostics compare amplitudes with.
//! let gains = Gains::<f32, 3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
//!     .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(0.88)))
//!     .expect("valid configuration");
//! let adc = AdcScaling::offset_binary(12).expect("valid ADC");
//! let chain = Chain::new(adc, gains);
//! let mut state = ChainState::new();
//!
//! // In the ADC interrupt, every sample: the raw counts as the ADC gives them.
//! # let (raw_c, raw_s) = (2048u16 + 900, 2048u16 + 1559);
//! let estimate = chain.update(&mut state, (raw_c, raw_s));
//! let (angle_rad, speed_rad_s) = (estimate.angle, estimate.speed);
//! # assert!((angle_rad - 1.0472).abs() < 1e-3 && speed_rad_s == 0.0);
//! # assert!(estimate.faults.is_empty());
//!
//! // Or with the sensor's offsets, gain imbalance and quadrature learned while tracking
//! // (store `state.front_end.1.calibration()` in flash, load it with
//! // `Calibrator::from_calibration`):
//! let online = OnlineCalibration::new(gains.calibration_settings(), 50e-6).expect("valid");
//! let calibrated = Chain::new((adc, online), gains);
//! let mut calibrator = Calibrator::new();
//! calibrator.enable();
//! let mut state = ChainState { front_end: ((), calibrator), observer: ObserverState::new() };
//! let estimate = calibrated.update(&mut state, (raw_c, raw_s));
//! # assert!((estimate.angle - 1.0472).abs() < 1e-3);
//! ```
//!
//! The loop needs no nominal amplitude (its phase error is normalised); the diagnostics do,
//! in the input's units ([`FaultThresholds::for_amplitude`]), which [`AdcScaling`] makes
//! fractions of full scale. [`Gains`] is immutable and `Copy`; [`ObserverState`] (and a
//! [`Calibrator`]) are the mutable part, so one gain set serves many channels. An observer
//! on its own is a chain with no front end, `Chain::new((), gains)`, which costs nothing
//! more: a chain's `track` and `update`, their block form `update_block` and their bank
//! forms `track_bank` and `update_bank` are the crate's only per-sample entry points.
//!
//! # No panic, in optimised builds
//!
//! The per-sample entry points (a [`Chain`]'s `track`, `update`, `update_block`,
//! `track_bank` and `update_bank`) have no panic path in an optimised
//! build (`--release`): the repository's `tests/no-panic` image links them for a Cortex-M4F
//! with a panic handler that the linker must drop, and its test fails if any panic path
//! remains. Debug builds keep Rust's overflow checks, which can panic on an integer
//! overflow that release builds wrap. Constructors never panic either: they return a
//! [`ConfigError`].
//!
//! # Float types and the phase detector's sin/cos
//!
//! Everything is generic over the sealed [`Real`] trait (`f32`, `f64`); the `f32` path uses
//! no `f64` arithmetic. [`Real`] is [`Float`], the arithmetic that the per-sample code
//! needs, together with the checks of the configurations: the modules form layers that
//! import only downwards (the numbers, the recursion and its state, the observer and its
//! monitor, the front-end stages, the configurations' checked constructors, the designs),
//! so the per-sample code is bounded by [`Float`] and the constructors by [`Real`]. The sin/cos of the phase detector is a type parameter: [`Fast`]
//! (a branch-free polynomial, the default on `f32`) or [`Exact`] (`libm`, the default on
//! `f64`).
#![no_std]
#![deny(missing_docs)]
// `!(x > 0)` is deliberate throughout: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// Only for the `f64` square root of the `std` feature (`real.rs`).
#[cfg(feature = "std")]
extern crate std;

mod adc;
mod angle_correction;
mod angle_table;
mod bank;
mod calibration;
mod calibration_settings;
mod chain;
mod const_config;
mod demodulator;
mod design;
mod error;
mod excitation;
mod faults;
pub mod fixed;
mod front_end_faults;
mod gains;
mod learning;
mod monitor;
mod monitor_thresholds;
mod outputs;
mod reacquisition;
mod real;
mod recursion;
mod stability;
mod state;
mod tracker;
mod update;
mod wrap;

pub use adc::{AdcCounts, AdcSample, AdcScaling, MAX_MID_SCALE_COUNTS};
pub use angle_correction::{AngleCorrection, MAX_CORRECTION_ORDER};
pub use angle_table::{AngleCorrectionTable, FixedAngleCorrectionTable};
pub use bank::ChannelBank;
pub use calibration::{FixedCalibration, SensorCalibration};
pub use calibration_settings::CalibrationSettings;
pub use chain::{
    Chain, ChainState, Feedback, FrontEndCheck, FrontEndCheckState, HELD_RAIL_SAMPLES,
    HeldRailCheck, HeldRails, OnlineCalibration, Prediction, RAIL_BAND_PER_SPAN, RailSample, Stage,
    UnitGains, WindingCheck, is_piled_up_at_rail,
};
pub use const_config::Real;
pub use demodulator::{
    DemodulatedPair, Demodulator, DemodulatorNumber, DemodulatorSettings, DemodulatorState,
    EXCITATION_REFERENCE_FRACTION, FIXED_PAIR_UNIT,
};
pub use design::{
    Discretisation, MAX_POLE_TIMES_PERIOD, PolePair, UnknownDiscretisation,
    second_order_bandwidth_ratio,
};
pub use error::{ConfigError, Parameter};
pub use excitation::{Excitation, ExcitationState, Waveform};
pub use faults::Faults;
pub use fixed::{FixedEstimate, FixedGains, FixedState};
pub use front_end_faults::FrontEndFaults;
pub use gains::{Gains, Order, SupportedOrder};
pub use learning::{CalibrationMode, CalibrationStatus, Calibrator};
pub use monitor::{
    FaultThresholds, ROUNDNESS_HOLD_WINDOWS, TRACKING_RELEASE_FRACTION, TRACKING_STARTUP_WINDOWS,
};
pub use monitor_thresholds::TRACKING_ERROR_NOISE_FACTOR;
pub use outputs::{DriveAngle, DriveOutputs, DriveOutputsState};
pub use real::sincos::{Detection, Exact, Fast, SinCos, SinCosUnit};
pub use real::{ChainNumber, Float};
pub use state::{Estimate, ObserverState};
pub use tracker::{
    CalibrationStage, CorrectionStage, FixedCalibrationStage, FixedCorrectionStage, Input, Rails,
    TRACKER_TABLE_LENGTH, Tracker, TrackerFrontEnd, TrackerFrontEndState, TrackerInput,
    TrackerNumber, TrackerSettings, TrackerState,
};

#[cfg(test)]
mod test_support;
