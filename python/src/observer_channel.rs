//! The core's standard chain behind `Observer`: `Channel`, one per float type, order and
//! sin/cos, holding the core's `Tracker` (the ADC range check, the rails measured, the
//! winding check, the online calibration) and its state, and its run over numpy arrays.

use angletrack::{ChannelStatus, OnlineCalibrationChoice, TrackerChannel};
use angletrack_core::{Faults, ObserverState};
use pyo3::prelude::*;

use crate::dispatch::{Arg, PhaseSinCos, Sample};
use crate::errors::Result;
use crate::estimates::{Estimates, OutputSelection, run_estimates};
use crate::observer::ObserverOps;

/// The crate's `TrackerChannel` behind `Observer`, and the first ADC argument the caller
/// stated (refused with float samples).
#[derive(Debug)]
pub struct Channel<T: Sample, const N: usize, S> {
    /// The chain.
    pub inner: TrackerChannel<T, N, S>,
    /// The first ADC argument the caller stated.
    pub stated: Option<&'static str>,
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> ObserverOps for Channel<T, N, S> {
    fn run(
        &mut self,
        py: Python<'_>,
        y_c: Arg<'_, '_>,
        y_s: Arg<'_, '_>,
        front_end_faults: Option<&[u8]>,
    ) -> Result<Estimates> {
        let counts = crate::counts::is_counts(y_c);
        let (y_c, y_s) = crate::counts::signals(&mut self.inner.input, self.stated, y_c, y_s)?;
        let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
        self.inner.prepare(counts, (y_c, y_s), front_end_faults)?;
        let (inner, all) = (&mut self.inner, (OutputSelection::ALL, None));
        let ((), estimates) = run_estimates(py, y_c.len(), all, |columns| {
            inner.run(columns, (y_c, y_s), front_end_faults)
        })?;
        Ok(estimates)
    }

    fn status(&self) -> ChannelStatus {
        self.inner.status()
    }

    fn reset(&mut self) {
        self.inner.state.observer = ObserverState::new();
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) -> Result<()> {
        Ok(self.inner.initialise(y_c, y_s)?)
    }

    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration: f64) -> Result<()> {
        Ok(self.inner.set_state(angle_rad, speed_rad_s, acceleration)?)
    }

    fn clear_faults(&mut self) -> Faults {
        self.inner.state.observer.clear_faults()
    }

    fn set_calibration(&mut self, choice: &OnlineCalibrationChoice) -> Result<()> {
        *self.inner.state.front_end.calibrator_mut() = choice.calibrator()?;
        Ok(())
    }
}
