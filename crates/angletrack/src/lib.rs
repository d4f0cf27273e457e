//! Gain design, design analysis, test scenarios and metrics for the angle tracking observers
//! of [`angletrack_core`] (re-exported as [`core`], its main types at the root).
//!
//! Going from a specification to firmware gains, and knowing what they will do:
//!
//! ```
//! use angletrack::{DesignReport, Gains, second_order_from_tracking_error_sampled};
//!
//! // 2nd-order ATO: at most 1 mrad of error at 2000 rad/s^2 and 5 % overshoot, met by the
//! // loop as it runs, sampled at 20 kHz.
//! let design = second_order_from_tracking_error_sampled(1e-3, 2e3, 0.05, 50e-6)?;
//! let report = DesignReport::new(&design, 0.005)?; // sensor noise 0.005 per channel
//! println!("{report}");                             // the design's datasheet
//! let error_rad = 2e3 / report.acceleration_constant_per_s2.unwrap();
//! assert!((error_rad - 1e-3).abs() < 1e-12);        // 1 mrad at 2000 rad/s^2
//! assert!((report.linear_step.overshoot - 0.05).abs() < 1e-6); // 5 %
//! let firmware_gains: Gains<f32, 2> = design.to_gains()?;  // for the Cortex-M4F
//! # let _ = firmware_gains;
//! # Ok::<(), angletrack::Error>(())
//! ```
//!
//! The paper's rule, [`second_order_from_tracking_error`] with damping 1.945, meets the same
//! specification on the continuous loop; sampled at 20 kHz, its loop gives 0.869 mrad and
//! 4.35 %, closer to the specification the faster the sampling.
//!
//! * Design ([`second_order_from_tracking_error`],
//!   [`second_order_from_tracking_error_sampled`], [`second_order_from_bandwidth`],
//!   [`second_order_butterworth`], [`third_order_from_poles`], [`third_order_from_overshoot`],
//!   [`third_order_butterworth`], [`kalman`], [`kalman_from_jerk_std`],
//!   [`kalman_from_jerk_density`]): `f64` designs; continuous ones are carried to the
//!   discrete recursion by a [`Discretisation`] of their poles. Every function checks its
//!   arguments and returns an [`Error`] naming the one at fault.
//! * Analysis ([`DesignReport`], [`predicted_error`], [`predicted_error_on_kalman_model`],
//!   [`max_trackable_speed_rad_s`]): poles, bandwidth, error constants, noise, step
//!   responses (linear and a 179 degree nonlinear step), speed limits.
//! * The paper ([`paper`]): its four settings, the three observers it compares and the
//!   benchmarks' gains, for the tests, examples, benchmarks and report alike.
//! * Scenarios ([`MotionProfile`], [`SensorModel`], [`Scenario`]): deterministic from a seed;
//!   [`ResolverModel`] gives a carrier-excited resolver's raw windings for the core's
//!   [`Demodulator`].
//! * Metrics ([`run`], [`Metrics`]): a run of any observer measured against the truth.
//! * Recorded captures ([`capture`]): delimited text of any layout, `.npy` and `.npz`, read
//!   in chunks of constant memory with every fault named by file, line and column; the
//!   estimates written back as text or `.npy`.
//! * Real sensor signals ([`run_calibrated`], [`nominal_amplitude`],
//!   [`capture_fault_thresholds`], [`SensorModel::calibration`]): a run with the core's
//!   online correction of offsets, imbalance and quadrature, and diagnostics scaled to a
//!   capture's own amplitude (`docs/theory.md §12`).
//! * Many channels ([`ChannelBatch`]): any number of channels on one gain set, run by the
//!   core's vectorisable [`ChannelBank`]s.
//! * Firmware source ([`export`]): the gains, the fixed-point constants and a calibration as a
//!   C header or Rust `const`s, in the firmware's float type.
//! * Calibration files ([`CalibrationFile`]): a sensor calibration learned while tracking
//!   ([`SensorCalibrationRecord`]) or by [`learn_angle_correction`] ([`CaptureCalibration`])
//!   as JSON, read back exactly, every refusal naming the file and the field.
//! * Design from a capture ([`design_capture`]): the noise and the motion estimated from a
//!   recording, the observer of least predicted RMS angle error chosen over the orders and
//!   bandwidths (`docs/theory.md §16`).
//! * Tracker files ([`tracker_file::TrackerFile`]): a whole sensor setup (gains, number
//!   type, input, ADC range, calibration, correction) as one versioned JSON document, and its
//!   firmware constants.
//! * Raw ADC counts and units ([`CountsInput`], [`offset_binary_mid_scale`], [`capture_counts`],
//!   [`ThresholdPolicy`]): a capture's signedness and mid-scale, stated or read from the
//!   whole capture, and the monitor's thresholds.
//!
//! The mathematics is in the repository's `docs/theory.md`: the designs in §2 to §4, the
//! discretisations in §7, the noise prediction in §8, the speed limits in §9; each module
//! cites the section it implements.
// `!(x > 0)` is deliberate throughout: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub use angletrack_core as core;
pub use angletrack_core::{
    AdcScaling, AngleCorrection, CalibrationMode, CalibrationSettings, Calibrator, Chain,
    ChainState, ChannelBank, ConfigError, Estimate, Exact, Fast, FaultThresholds, Faults, Gains,
    ObserverState, Parameter, Real, SensorCalibration, SinCos,
};
// The resolver front end (`docs/theory.md §13`).
pub use angletrack_core::{
    DemodulatedPair, Demodulator, DemodulatorSettings, DemodulatorState, DriveAngle, DriveOutputs,
    DriveOutputsState, Excitation, ExcitationState, FrontEndFaults, Waveform,
};
pub use nalgebra::Complex;

mod analysis;
mod any_channel;
mod any_gains;
mod calibration;
pub mod capture;
mod capture_counts;
mod carrier;
mod channel_status;
mod clipping;
mod counts;
mod demodulation;
mod design;
pub mod design_capture;
mod drive_columns;
mod error;
pub mod export;
pub mod fault_campaign;
mod json_file;
mod linalg;
pub mod lot;
pub mod paper;
mod rails;
mod sim;
pub mod study;
mod thresholds;
mod tracker_channel;
pub mod tracker_file;
mod winding_rails;
mod windings_plan;

/// The example of the crate's README (the page the package registry shows), run as a doctest
/// so that it stays in step with the API.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeExample;

pub use analysis::{
    DesignReport, LARGE_STEP_RAD, PredictedError, SETTLING_BAND, StepResponse,
    closed_loop_response, max_trackable_speed_rad_s, predicted_error,
    predicted_error_on_kalman_model,
};
pub use any_channel::{AnyBatch, AnyChannel};
pub use any_gains::AnyGains;
pub use calibration::{
    ANGLE_CALIBRATION_FORMAT, CALIBRATION_FILE_VERSION, CalibrationChoiceError, CalibrationError,
    CalibrationFile, CalibrationMethod, CalibrationOptions, CaptureCalibration, CaptureCalibrator,
    MIN_ERROR_TRANSFER, OnlineCalibrationChoice, OrderQuality, OrderStatus,
    SENSOR_CALIBRATION_FORMAT, SPECTRUM_ORDERS, SensorCalibrationRecord, converted_calibration,
    error_transfer, learn_angle_correction, mode_name, order_warnings, status_name,
};
pub use capture_counts::{
    CaptureCounts, CountsError, CountsExtremes, Signedness, StatedCounts, capture_counts,
};
pub use carrier::measured_carrier_cycles_per_sample;
pub use channel_status::ChannelStatus;
pub use clipping::{checked_adc_range, clipping_rails};
pub use counts::{
    AdcCount, ChannelCounts, CountsInput, CountsInputError, CountsSettings, UnsignedCountsError,
    offset_binary_mid_scale,
};
pub use demodulation::{DemodulatorArguments, DemodulatorStream, PairColumns};
pub use design::{
    AnyDesign, Design, DesignMethod, Discretisation, FixedDesignConstants, KalmanSolution,
    MAX_POLE_TIMES_PERIOD, convert_gains, kalman, kalman_from_jerk_density, kalman_from_jerk_std,
    second_order_bandwidth_ratio, second_order_butterworth, second_order_from_bandwidth,
    second_order_from_tracking_error, second_order_from_tracking_error_sampled,
    third_order_butterworth, third_order_from_overshoot, third_order_from_poles,
};
pub use drive_columns::DriveColumns;
pub use error::{Argument, ArgumentError, Error};
pub use json_file::JsonFileError;
pub use rails::measured_adc_range;
pub use sim::{
    ChannelBatch, ErrorStatistics, EstimateColumns, FixedColumns, FixedConstantsError, FixedInput,
    FixedTracker, Kinematics, LANES, MAX_ANGLE_ERROR_HARMONICS, MAX_SAMPLES, Metrics,
    MetricsOptions, Motion, MotionProfile, NOMINAL_AMPLITUDE_SAMPLES, Output, OutputSet,
    ResolverModel, Run, Scenario, SensorModel, angle_noise, capture_fault_thresholds,
    capture_fault_thresholds_for_pole_pairs, fixed_front_end, fixed_input, fixed_input_shift,
    fixed_magnitude_tolerance, fixed_monitor_amplitude, nominal_amplitude, run, run_calibrated,
    shifted_calibration,
};
pub use thresholds::{ThresholdInput, ThresholdPolicy, ThresholdsNotStated, converted_thresholds};
pub use tracker_channel::{ChannelError, ChannelOptions, TrackerChannel, stored_stages};
pub use winding_rails::WindingRails;
pub use windings_plan::{
    AdcRangeSource, CARRIER_TOLERANCE, SAMPLES_PER_PERIOD_TOLERANCE, WindingsPlan,
    WindingsPlanError, WindingsSettings,
};
