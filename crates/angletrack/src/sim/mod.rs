//! Simulation: test scenarios deterministic from a seed (a motion profile of the shaft and a
//! sensor model, sampled into the truth beside `y_c` and `y_s`), runs of an observer over
//! them, the metrics of a run, and many channels at once; and a carrier-excited resolver's
//! raw windings as an ADC samples them (`resolver`).

mod angle_noise;
mod batch;
mod calibrated;
mod columns;
mod fixed_chain;
mod fixed_columns;
mod fixed_tracker;
mod metrics;
mod motion;
mod resolver;
mod roundness;
mod scenario;
mod sensor;

pub use batch::{ChannelBatch, LANES};
pub use calibrated::{
    NOMINAL_AMPLITUDE_SAMPLES, angle_noise, capture_fault_thresholds,
    capture_fault_thresholds_for_pole_pairs, nominal_amplitude, run_calibrated,
};
pub use columns::{EstimateColumns, Output, OutputSet};
pub use fixed_chain::{
    FixedInput, fixed_front_end, fixed_input, fixed_input_shift, fixed_magnitude_tolerance,
    fixed_monitor_amplitude, shifted_calibration,
};
pub use fixed_columns::FixedColumns;
pub use fixed_tracker::{FixedConstantsError, FixedTracker};
pub(crate) use metrics::wrap;
pub use metrics::{ErrorStatistics, Metrics, MetricsOptions, Run, run};
pub use motion::{Kinematics, Motion, MotionProfile};
pub use resolver::ResolverModel;
pub(crate) use scenario::ScenarioSample;
pub use scenario::{MAX_SAMPLES, Scenario};
pub use sensor::{MAX_ANGLE_ERROR_HARMONICS, SensorModel};

#[cfg(test)]
mod tests;
