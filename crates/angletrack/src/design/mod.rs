//! Gain design: from time-domain specifications, pole placement and noise variances to the
//! discrete gains of the core's recursion.
//!
//! The gains are the core's designs (`angletrack_core`'s `design.rs`), computed in `f64`;
//! this module adds what needs allocation or a search: the design record ([`Design`]) with
//! its poles for the reports, the specifications met by searching (overshoot, sampled
//! tracking error), and errors that name the caller's argument.
//!
//! Continuous designs (`docs/theory.md §2`, `§3`) give the closed-loop poles `s_i` (rad/s)
//! of the continuous loop `s^N + k_a s^(N-1) + k_b s^(N-2) [+ k_c]`; the core's
//! [`Gains::from_continuous_poles`](angletrack_core::Gains::from_continuous_poles) maps them
//! with a [`Discretisation`] (`§7`) to discrete poles `z_i` and gives the gains whose loop
//! `(I - L e1^T) A` has exactly those poles. The Kalman ATO (`§4`) is designed on the
//! discrete model directly (the core's Riccati solver), and the sampled tracking-error
//! design (`§2`) on the discrete loop.
//!
//! Vectors follow the core's orders: gains in the order of the state they correct (angle
//! first: `(l1, l2, l3)`, `(k_a, k_b, k_c)`), polynomial coefficients lowest power first
//! (`c0` first).

mod designs;
mod discretisation;
mod fixed;
mod kalman;
mod sampled;
mod second_order;
mod third_order;

pub use angletrack_core::Discretisation;
pub use designs::{AnyDesign, Design, DesignMethod, convert_gains};
pub use discretisation::MAX_POLE_TIMES_PERIOD;
pub use fixed::FixedDesignConstants;
pub use kalman::{KalmanSolution, kalman, kalman_from_jerk_density, kalman_from_jerk_std};
pub use sampled::second_order_from_tracking_error_sampled;
pub use second_order::{
    second_order_bandwidth_ratio, second_order_butterworth, second_order_from_bandwidth,
    second_order_from_tracking_error,
};
pub use third_order::{
    third_order_butterworth, third_order_from_overshoot, third_order_from_poles,
};

#[cfg(test)]
mod doc_claims_tests;
#[cfg(test)]
mod tests;
