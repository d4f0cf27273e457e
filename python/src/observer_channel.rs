//! The core observer behind `Observer`: `Channel`, one per float type, order and sin/cos,
//! and its run over numpy arrays through the front-end chain (the ADC range check, the rails
//! measured, the winding check, the online calibration).

use angletrack::{EstimateColumns, ThresholdInput, ThresholdPolicy, online_calibration};
use angletrack_core::{
    CalibrationMode, CalibrationStatus, Calibrator, Chain, ChainState, Faults, FrontEndCheck,
    FrontEndCheckState, FrontEndFaults, Gains as CoreGains, HeldRailCheck, HeldRails,
    Observer as CoreObserver, ObserverState, Real, SinCos, WindingCheck,
};
use pyo3::prelude::*;

use crate::arrays::check_equal_lengths;
use crate::calibration::{CalibrationChoice, PySensorCalibration};
use crate::counts::AdcInput;
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::{Arg, PhaseSinCos, Run, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimate, Estimates, OutputArrays};
use crate::observer::{ObserverOps, ObserverOptions};

/// The core observer behind the binding's front end: integer counts scaled
/// (`crate::counts`), the online calibration, and the diagnostics' thresholds by the crate's
/// `ThresholdPolicy` (of a stream for `Observer`, of a whole capture for `track`).
#[derive(Debug)]
pub struct Channel<T: Real, const N: usize, S> {
    observer: CoreObserver<T, N, S>,
    calibrator: Calibrator<T>,
    adc: AdcInput<T>,
    thresholds: ThresholdPolicy<T>,
    adc_range: Option<(f64, f64)>,
    held_rails: Option<HeldRailCheck>,
    rails: HeldRails<T>,
    winding: Option<WindingCheck<T>>,
    front_end: (FrontEndCheckState, FrontEndCheckState),
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
        Ok(Self {
            observer: CoreObserver::new(gains),
            calibrator: options.calibration.calibrator()?,
            adc: AdcInput::new(options.adc, options.whole),
            thresholds,
            adc_range: options.clipping.range,
            held_rails: options.clipping.measure.then_some(HeldRailCheck::new()),
            rails: HeldRails::default(),
            winding: options
                .winding_amplitude
                .map(|a| WindingCheck::new(T::from_f64(a)))
                .transpose()
                .map_err(|e| Error::value("winding_amplitude", e.to_string()))?,
            front_end: Default::default(),
        })
    }
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Run for Channel<T, N, S> {
    fn run(&mut self, py: Python<'_>, y_c: Arg<'_, '_>, y_s: Arg<'_, '_>) -> Result<Estimates> {
        self.run_with_faults(py, y_c, y_s, None)
    }
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Channel<T, N, S> {
    /// The ADC range in the observer's units: counts through the decided scaling when
    /// `counts` (the samples were counts), else as given.
    fn range_in_units(&self, counts: bool) -> Option<(T, T)> {
        let (min, max) = self.adc_range?;
        match self.adc.decided().filter(|_| counts) {
            Some(adc) => {
                let mid = f64::from(adc.mid_scale_counts());
                let per_unit = adc.counts_per_unit().to_f64();
                Some((
                    T::from_f64((min - mid) / per_unit),
                    T::from_f64((max - mid) / per_unit),
                ))
            }
            None => Some((T::from_f64(min), T::from_f64(max))),
        }
    }
}
impl<T: Sample, const N: usize, S: PhaseSinCos<T>> ObserverOps for Channel<T, N, S> {
    fn run_with_faults(
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
            self.observer.gains = self.observer.gains.with_fault_thresholds(thresholds)?;
        }
        let check = FrontEndCheck::around((), self.range_in_units(counts))
            .map_err(|e| Error::value("adc_range", e.to_string()))?;
        let out = OutputArrays::<T>::new(py, y_c.len())?;
        out.fill(py, |columns| {
            run_columns(columns, self, check, (y_c, y_s), front_end_faults)
        })?;
        out.into_estimates(py, y_c.len(), None)
    }

    fn front_end_faults(&self) -> FrontEndFaults {
        self.front_end.0.latched_faults()
            | self.front_end.1.latched_faults()
            | self.rails.check().latched_faults()
    }

    fn estimate(&self) -> Estimate {
        Estimate::from_core(&self.observer.gains.estimate(&self.observer.state))
    }

    fn reset(&mut self) {
        self.observer.state = ObserverState::new();
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) {
        let (y_c, y_s) = (T::from_f64(y_c), T::from_f64(y_s));
        let o = &mut self.observer;
        o.gains.initialise(&mut o.state, y_c, y_s);
    }

    fn set_state(
        &mut self,
        angle_rad: f64,
        speed_rad_s: f64,
        acceleration_rad_s2: f64,
    ) -> Result<()> {
        // The core refuses what the state cannot hold, naming the argument.
        self.observer.state = ObserverState::at(
            T::from_f64(angle_rad),
            T::from_f64(speed_rad_s),
            T::from_f64(acceleration_rad_s2),
            self.observer.gains.sample_period(),
        )?;
        Ok(())
    }

    fn is_initialised(&self) -> bool {
        self.observer.state.is_initialised()
    }

    fn latched_faults(&self) -> Faults {
        self.observer.state.latched_faults()
    }

    fn clear_faults(&mut self) -> Faults {
        self.observer.state.clear_faults()
    }

    fn fault_thresholds(&self) -> Option<PyFaultThresholds> {
        // The gains' own (checked) thresholds, once the policy has them.
        let thresholds = self.observer.gains.fault_thresholds();
        self.thresholds
            .thresholds()
            .map(|_| PyFaultThresholds::from_typed(&thresholds))
    }

    fn amplitude(&self) -> f64 {
        self.observer.state.amplitude().to_f64()
    }

    fn calibration(&self) -> PySensorCalibration {
        PySensorCalibration::from_core(&self.calibrator.calibration())
    }

    fn calibration_mode(&self) -> CalibrationMode {
        self.calibrator.mode()
    }

    fn calibration_turns_learned(&self) -> u32 {
        self.calibrator.turns_learned()
    }

    fn calibration_status(&self) -> CalibrationStatus {
        self.calibrator.status()
    }

    fn set_calibration(&mut self, choice: &CalibrationChoice) -> Result<()> {
        self.calibrator = choice.calibrator()?;
        Ok(())
    }
}

/// Runs `channel` over `y_c`, `y_s` into the columns (all of equal length, checked by the
/// caller), through the front-end `check` with the samples' `front_end_faults` if given.
/// Called with the GIL released: no Python object is touched.
fn run_columns<T: Real, const N: usize, S: SinCos<T>>(
    columns: EstimateColumns<'_, T>,
    channel: &mut Channel<T, N, S>,
    check: FrontEndCheck<T>,
    (y_c, y_s): (&[T], &[T]),
    front_end_faults: Option<&[u8]>,
) {
    let gains = channel.observer.gains;
    // The front-end check (quiet on a sample without a fault), the rails measured and the
    // winding check if asked for, then the online calibration (with the calibration off,
    // the chain's quiet path: one branch on the mode).
    let chain = Chain::new(
        (
            check,
            (
                channel.held_rails,
                (channel.winding, online_calibration(&gains)),
            ),
        ),
        gains,
    );
    let mut state = ChainState {
        front_end: (
            (channel.front_end.0, ()),
            (channel.rails, (channel.front_end.1, channel.calibrator)),
        ),
        observer: channel.observer.state,
    };
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
            .map(|(k, (&c, &s))| chain.update(&mut state, ((c, s), faults(k)))),
    );
    let ((check, ()), (rails, (winding, calibrator))) = state.front_end;
    (
        channel.front_end,
        channel.rails,
        channel.calibrator,
        channel.observer.state,
    ) = ((check, winding), rails, calibrator, state.observer);
}
