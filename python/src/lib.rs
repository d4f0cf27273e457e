//! The `angletrack._angletrack` Python extension: the angle tracking observers of
//! `angletrack-core` on numpy arrays, and the design tools of `angletrack`.
//!
//! This crate only converts: arguments in (checked by `arrays`), results out, errors in
//! one place (`errors`). Every computation is a call into the Rust crates.

mod analysis;
mod angle_calibration;
mod arrays;
mod batch;
mod calibration;
mod calibration_file;
mod capture;
mod carrier;
mod counts;
mod design;
mod design_capture;
mod design_functions;
mod diagnostics;
mod dispatch;
mod drive;
mod errors;
mod estimates;
mod export;
mod fixed;
mod fixed_estimates;
mod gains;
mod getters;
mod json;
mod metrics;
mod model_class;
mod motion;
mod observer;
mod paper;
mod resolver;
mod scenario;
mod study;
mod tracker_file;
mod writer;

/// Adds each constant `NAME` of each crate module `path` to the Python module `m` as
/// `PREFIX` + `NAME`: `m; "PREFIX" path: NAME, NAME; ...`.
macro_rules! add_constants {
    ($m:ident; $($prefix:literal $($path:ident)::+ : $($name:ident),+;)+) => {$({
        use $($path)::+ as source;
        $($m.add(concat!($prefix, stringify!($name)), source::$name)?;)+
    })+};
}

// Every class, function and constant the extension exports is listed here, once.
/// The compiled part of the `angletrack` Python package.
#[pyo3::pymodule]
mod _angletrack {
    #[pymodule_export]
    use crate::{
        analysis::{
            DesignReport, PyPredictedError, PyStepResponse, closed_loop_response,
            max_trackable_speed_rad_s, predicted_error, predicted_error_on_kalman_model,
        },
        batch::{PyObserverBatch, track_batch},
        calibration::PySensorCalibration,
        calibration_file::{
            angle_calibration_from_json, angle_calibration_to_json, calibration_from_json,
            sensor_calibration_from_json, sensor_calibration_to_json,
        },
        capture::{
            PyCapture, PyCaptureChunk, PyCaptureReader, check_outputs, read_capture, write_output,
        },
        carrier::{PyWindingsPlan, measured_adc_range, plan_windings},
        counts::{PyCountsExtremes, capture_counts, capture_fault_thresholds},
        design::{PyDesign, PyKalmanSolution},
        design_capture::design_from_capture,
        design_functions::{
            kalman, kalman_from_jerk_density, kalman_from_jerk_std, second_order_bandwidth_ratio,
            second_order_butterworth, second_order_from_bandwidth,
            second_order_from_tracking_error, second_order_from_tracking_error_sampled,
            third_order_butterworth, third_order_from_overshoot, third_order_from_poles,
        },
        diagnostics::PyFaultThresholds,
        drive::{PyDriveAngles, PyDriveOutputs},
        errors::{CaptureError, ConfigError},
        estimates::{Estimate, Estimates},
        export::{
            calibration_source, fixed_gains_file_json, fixed_source, gains_file_json, gains_source,
            read_fixed_gains_file, read_gains_file,
        },
        fixed::PyFixedObserver,
        fixed_estimates::{FixedEstimate, FixedEstimates},
        gains::PyGains,
        metrics::{PyErrorStatistics, PyMetrics, metrics},
        motion::PyMotionProfile,
        observer::{PyObserver, track},
        paper::{PyPaperSetting, paper_benchmark_gains, paper_compared_observers, paper_settings},
        resolver::{PyDemodulatedPairs, PyDemodulator, PyResolverModel, resolver_windings},
        scenario::{PyScenario, PySensorModel},
        study::{lot_outliers, study_resolve, study_runs},
        writer::{PyOutputFile, PyTableWriter, estimate_columns},
    };
    use pyo3::prelude::*;

    /// Adds the constants, and the classes and functions of the modules that register their
    /// own.
    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("FAULT_BITS", crate::diagnostics::fault_bits())?;
        m.add(
            "FRONT_END_FAULT_BITS",
            crate::diagnostics::front_end_fault_bits(),
        )?;
        add_constants! { m;
            "" angletrack: LARGE_STEP_RAD, SETTLING_BAND, MAX_POLE_TIMES_PERIOD,
                SENSOR_CALIBRATION_FORMAT, ANGLE_CALIBRATION_FORMAT;
            "" angletrack::export: GAINS_FILE_FORMAT, FIXED_GAINS_FILE_FORMAT, GAINS_FILE_VERSION;
            "" angletrack::core: HELD_RAIL_SAMPLES;
            "" angletrack::study: STUDY_FORMAT;
            "PAPER_" angletrack::paper: FIVE_PERCENT_DAMPING, BUTTERWORTH_DAMPING, POLE_RATIO,
                POLE_FREQUENCY_RATIO, OVERSHOOT_SAMPLE_PERIOD_S, COMPARISON_SAMPLE_PERIOD_S,
                COMPARISON_BANDWIDTH_HZ, COMPARISON_SENSOR_NOISE_STD;
        }
        crate::angle_calibration::register(m)?;
        crate::tracker_file::register(m)
    }
}
