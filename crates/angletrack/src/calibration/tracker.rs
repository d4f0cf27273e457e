//! The angles the calibration's second pass measures the error against: an observer's on
//! the calibrated samples, or the reference column's, unwrapped.

use std::f64::consts::TAU;

use angletrack_core::{Chain, ChainState, Gains, ObserverState, SensorCalibration};
use nalgebra::Complex;

use super::error_transfer;

/// An observer run on the calibrated samples (the calibration's own loop or the gains').
pub(super) trait Tracker: Send + Sync {
    /// The observer's angle, position (with its turns) and speed (rad per sample) after
    /// the raw sample `(y_c, y_s)`; `None` when it flags a fault.
    fn step(&mut self, y_c: f64, y_s: f64) -> Option<(f64, f64, f64)>;
    /// The loop's `E/D` at `omega` rad per sample.
    fn transfer(&self, omega: f64) -> Complex<f64>;
}

/// An observer on the calibrated samples, started on the first finite sample at its angle
/// and at the first pass's speed, so that a slow loop does not spend the capture locking.
pub(super) struct LoopTracker<const N: usize> {
    chain: Chain<SensorCalibration<f64>, Gains<f64, N>>,
    state: Option<ChainState<(), ObserverState<f64, N>>>,
    /// The first pass's speed (rad/s).
    speed_rad_s: f64,
}

impl<const N: usize> LoopTracker<N> {
    pub(super) fn new(
        sensor: SensorCalibration<f64>,
        gains: Gains<f64, N>,
        speed_rad_s: f64,
    ) -> Box<Self> {
        Box::new(Self {
            chain: Chain::new(sensor, gains),
            state: None,
            speed_rad_s,
        })
    }
}

impl<const N: usize> Tracker for LoopTracker<N> {
    fn step(&mut self, y_c: f64, y_s: f64) -> Option<(f64, f64, f64)> {
        let ts = self.chain.observer.sample_period();
        let state = match &mut self.state {
            Some(state) => state,
            None if y_c.is_finite() && y_s.is_finite() => {
                let (c, s) = self.chain.front_end.correct(y_c, y_s);
                // A first-pass speed the loop cannot hold (beyond half a turn a sample):
                // the loop starts from the sample alone and locks by itself.
                let observer =
                    ObserverState::at(s.atan2(c), self.speed_rad_s, 0.0, ts).unwrap_or_default();
                self.state.insert(ChainState {
                    front_end: (),
                    observer,
                })
            }
            None => return None,
        };
        let estimate = self.chain.update(state, (y_c, y_s));
        estimate
            .faults
            .is_empty()
            .then(|| (estimate.angle, estimate.position(), estimate.speed * ts))
    }

    fn transfer(&self, omega: f64) -> Complex<f64> {
        error_transfer(&self.chain.observer, omega)
    }
}

/// An angle unwrapped from its wrapped samples.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Unwrap {
    last: Option<f64>,
    pub(super) position: f64,
}

impl Unwrap {
    pub(super) fn add(&mut self, angle: f64) -> f64 {
        if let Some(last) = self.last {
            let step = angle - last;
            self.position += step - TAU * (step / TAU).round();
        } else {
            self.position = angle;
        }
        self.last = Some(angle);
        self.position
    }
}
