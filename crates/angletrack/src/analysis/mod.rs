//! Analysis of a gain set: step responses, frequency response, noise prediction, speed
//! limits and the design report that gathers them.

mod discrete_loop;
mod display;
mod frequency_response;
mod noise;
mod report;
mod speed;
mod step;

pub(crate) use discrete_loop::{loop_bandwidth_hz, small_signal_step};
pub use frequency_response::closed_loop_response;
pub use noise::{PredictedError, predicted_error, predicted_error_on_kalman_model};
pub use report::DesignReport;
pub use speed::max_trackable_speed_rad_s;
pub use step::{LARGE_STEP_RAD, SETTLING_BAND, StepResponse};
pub(crate) use step::{continuous_step, continuous_step_within};

#[cfg(test)]
mod tests;
