//! The core's standard chain behind `Observer`: `Channel`, one per float type, order and
//! sin/cos, holding the core's `Tracker` (the ADC range check, the rails measured, the
//! winding check, the online calibration) and its state, and its run over numpy arrays.

use angletrack::{
    EstimateColumns, OnlineCalibrationChoice, ThresholdInput, ThresholdPolicy,
    converted_calibration,
};
use angletrack_core::{
    AdcScaling, AngleCorrection, CalibrationStage, CorrectionStage, Faults, FrontEndFaults,
    Gains as CoreGains, Input, ObserverState, SinCos, Tracker, TrackerFrontEnd, TrackerSettings,
    TrackerState, WindingCheck,
};
use pyo3::prelude::*;

use crate::arrays::check_equal_lengths;
use crate::calibration::PySensorCalibration;
use crate::counts::{AdcInput, Clipping};
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::{Arg, PhaseSinCos, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimate, Estimates, OutputSelection, run_estimates};
use crate::observer::{ObserverOps, ObserverOptions, ObserverStatus};

/// The core's standard chain behind `Observer` (`Tracker`: the clipping checks, the winding
/// check, the online calibration), its state, integer counts scaled (`crate::counts`), and
/// the diagnostics' thresholds by the crate's `ThresholdPolicy` (of a stream for
/// `Observer`, of a whole capture for `track`).
#[derive(Debug)]
pub struct Channel<T: Sample, const N: usize, S> {
    tracker: Tracker<T, CoreGains<T, N, S>>,
    state: TrackerState<T, ObserverState<T, N>>,
    adc: AdcInput<T>,
    thresholds: ThresholdPolicy<T>,
    /// `adc_range` as given (in the samples' units, or in codes for counts), or the rails
    /// measured.
    clipping: Clipping,
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Channel<T, N, S> {
    /// The observer of `gains` with `options`.
    pub fn new(gains: CoreGains<T, N, S>, options: &ObserverOptions) -> Result<Self> {
        let given = options.thresholds.map(|t| t.typed());
        let thresholds = if options.whole {
            ThresholdPolicy::whole(given)
        } else {
            ThresholdPolicy::stream(given)
        };
        let gains = match thresholds.thresholds() {
            Some(t) => gains.with_fault_thresholds(t)?,
            None => gains,
        };
        let winding = options
            .winding_amplitude
            .map(|a| WindingCheck::new(T::from_f64(a)))
            .transpose()
            .map_err(|e| Error::value("winding_amplitude", e.to_string()))?;
        let (calibration, correction) = match &options.stored {
            Some((sensor, correction)) => {
                let (a, b) = correction.coefficients();
                (
                    CalibrationStage::Stored(converted_calibration(sensor)?),
                    CorrectionStage::Harmonics(AngleCorrection::new(
                        a.map(T::from_f64),
                        b.map(T::from_f64),
                    )?),
                )
            }
            None => (
                CalibrationStage::Online(gains.online_calibration()),
                CorrectionStage::None,
            ),
        };
        let front_end = front_end(&options.clipping, None, winding, (calibration, correction))?;
        let mut state = TrackerState::new();
        *state.front_end.calibrator_mut() = options.calibration.calibrator()?;
        Ok(Self {
            tracker: Tracker::new(front_end, gains),
            state,
            adc: AdcInput::new(options.adc, options.whole),
            thresholds,
            clipping: options.clipping,
        })
    }
}

/// The core's front end of the arguments for samples scaled by `adc` (`None`: floats, in
/// the units of `adc_range`): `adc_range` in codes through the ADC's scaling when the
/// samples are counts (the core's rule).
fn front_end<T: Sample>(
    clipping: &Clipping,
    adc: Option<AdcScaling<T>>,
    winding: Option<WindingCheck<T>>,
    (calibration, correction): (CalibrationStage<T>, CorrectionStage<T>),
) -> Result<TrackerFrontEnd<T>> {
    let input = match adc {
        Some(adc) => Input::Counts {
            adc,
            rails: clipping.rails(|(min, max)| Ok((code(min)?, code(max)?)))?,
        },
        None => Input::Units {
            rails: clipping.rails(|(min, max)| Ok((T::from_f64(min), T::from_f64(max))))?,
        },
    };
    TrackerFrontEnd::new(TrackerSettings {
        input,
        winding,
        calibration,
        correction,
    })
    .map_err(|e| Error::value("adc_range", e.to_string()))
}

/// A bound of `adc_range` for counts as an ADC code: a whole number, beyond int32 taken as
/// int32's extreme (the chain's counts are int32, wider ones refused as samples: the core's
/// `Rails::of_adc_bits` takes an unsigned 32-bit ADC's rail so).
fn code(bound: f64) -> Result<i32> {
    if bound.fract() == 0.0 {
        // A whole number: saturated to int32, as the comment above says.
        Ok(bound as i32)
    } else {
        Err(Error::value(
            "adc_range",
            format!("{bound}: the samples are counts, expected whole ADC codes"),
        ))
    }
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
        let (y_c, y_s) = self.adc.signals(y_c, y_s)?;
        let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
        check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        if let Some(faults) = front_end_faults {
            check_equal_lengths(("y_c", y_c.len()), ("front_end_faults", faults.len()))?;
        }
        let input = if counts {
            ThresholdInput::Counts {
                counts_per_unit_stated: self.adc.counts_per_unit_stated(),
            }
        } else {
            ThresholdInput::Floats
        };
        let decided = self.thresholds.decide(input, y_c, y_s).map_err(|e| {
            Error::value(
                "fault_thresholds",
                format!(
                    "{e}: give fault_thresholds=FaultThresholds(nominal_amplitude=A) with A \
                         in counts, or adc_counts_per_unit=A"
                ),
            )
        })?;
        if let Some(thresholds) = decided {
            let gains = self.tracker.observer.with_fault_thresholds(thresholds)?;
            self.tracker.observer = gains;
        }
        // The range in codes is the ADC's: the front end follows the scaling the samples
        // decided (measured or unchecked rails are the same for any).
        let adc = self.adc.decided().filter(|_| counts);
        let held = self.tracker.front_end;
        if self.clipping.range.is_some() && held.adc() != adc {
            let stages = (held.calibration(), held.correction());
            self.tracker.front_end = front_end(&self.clipping, adc, held.winding(), stages)?;
        }
        let (tracker, state) = (&self.tracker, &mut self.state);
        let all = (OutputSelection::ALL, None);
        let ((), estimates) = run_estimates(py, y_c.len(), all, |columns| {
            run_columns(columns, tracker, state, (y_c, y_s), front_end_faults)
        })?;
        Ok(estimates)
    }

    fn status(&self) -> ObserverStatus {
        let (observer, calibrator) = (&self.state.observer, self.state.front_end.calibrator());
        // The gains' own (checked) thresholds, once the policy has them.
        let thresholds = self.tracker.observer.fault_thresholds();
        ObserverStatus {
            estimate: Estimate::from_core(&self.tracker.observer.estimate(observer)),
            initialised: observer.is_initialised(),
            latched_faults: observer.latched_faults(),
            front_end_faults: self.state.front_end.latched_faults(),
            fault_thresholds: (self.thresholds.thresholds())
                .map(|_| PyFaultThresholds::from_typed(&thresholds)),
            amplitude: observer.amplitude().to_f64(),
            calibration: PySensorCalibration::from_core(&calibrator.calibration()),
            calibration_mode: calibrator.mode(),
            calibration_turns_learned: calibrator.turns_learned(),
            calibration_status: calibrator.status(),
        }
    }

    fn reset(&mut self) {
        self.state.observer = ObserverState::new();
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) {
        let (y_c, y_s) = (T::from_f64(y_c), T::from_f64(y_s));
        let gains = &self.tracker.observer;
        gains.initialise(&mut self.state.observer, y_c, y_s);
    }

    fn set_state(
        &mut self,
        angle_rad: f64,
        speed_rad_s: f64,
        acceleration_rad_s2: f64,
    ) -> Result<()> {
        // The core refuses what the state cannot hold, naming the argument.
        self.state.observer = ObserverState::at(
            T::from_f64(angle_rad),
            T::from_f64(speed_rad_s),
            T::from_f64(acceleration_rad_s2),
            self.tracker.observer.sample_period(),
        )?;
        Ok(())
    }

    fn clear_faults(&mut self) -> Faults {
        self.state.observer.clear_faults()
    }

    fn set_calibration(&mut self, choice: &OnlineCalibrationChoice) -> Result<()> {
        *self.state.front_end.calibrator_mut() = choice.calibrator()?;
        Ok(())
    }
}

/// Runs `tracker` from `state` over `y_c`, `y_s` into the columns (all of equal length,
/// checked by the caller), with the samples' `front_end_faults` if given. Called with the
/// GIL released: no Python object is touched.
fn run_columns<T: Sample, const N: usize, S: SinCos<T>>(
    columns: EstimateColumns<'_, T>,
    tracker: &Tracker<T, CoreGains<T, N, S>>,
    state: &mut TrackerState<T, ObserverState<T, N>>,
    (y_c, y_s): (&[T], &[T]),
    front_end_faults: Option<&[u8]>,
) {
    let faults = |k: usize| {
        front_end_faults
            .and_then(|f| f.get(k))
            .map_or(FrontEndFaults::NONE, |&bits| {
                FrontEndFaults::from_bits(bits)
            })
    };
    columns.write(
        y_c.iter()
            .zip(y_s)
            .enumerate()
            .map(|(k, (&c, &s))| tracker.update(state, ((c, s), faults(k)))),
    );
}
