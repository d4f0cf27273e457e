//! The fixed-point observer for cores without an FPU (Cortex-M0/M0+): the angle as a binary
//! angle (2^32 per turn, wrapping, the turns counted apart), the state in scaled integers,
//! 16-bit samples in, a sine table for the phase detector and the phase error normalised by
//! a reciprocal of the amplitude updated once per window (no division per sample), all run
//! by the same one recursion as the floats (`recursion.rs`). Formats, ranges, why nothing overflows and the accuracy:
//! `docs/theory.md §14`.

mod binary_angle;
mod gains;
mod multiply;
mod rare_cases;
mod state;
mod tracking_level;
mod update;
mod wide_product;
mod words;

pub use binary_angle::{binary_angle, binary_angle_to_rad};
pub(crate) use binary_angle::{round_to_i64, sin_cos_q15, taylor_sin};
pub use gains::{FixedConstants, FixedGains, MIN_NORMALISED_AMPLITUDE_COUNTS};
pub use state::{FixedEstimate, FixedState};
pub use tracking_level::MAX_TRACKING_ERROR_Q15;
pub use update::{MAX_RECIPROCAL, MIN_RECIPROCAL, MONITOR_WINDOW};
pub(crate) use wide_product::wide_product;
pub use words::FixedMonitorWords;

#[cfg(test)]
mod monitor_tests;
#[cfg(test)]
mod tests;
