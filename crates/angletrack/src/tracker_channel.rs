//! The float standard chain of one observer as the Python `Observer` and `track` run it
//! (`docs/theory.md §12`, `§15`): the core's [`Tracker`] (the ADC range check or the rails
//! measured, the winding check, the calibration online or stored, the angle correction)
//! behind the crate's [`CountsInput`] (raw counts scaled by one rule for the whole run) and
//! [`ThresholdPolicy`] (the diagnostics' thresholds given, the defaults of a stream, or a
//! whole capture's own), with the state that carries over from one chunk to the next.

use core::fmt;

use angletrack_core::{
    AdcScaling, AngleCorrection, CalibrationStage, ConfigError, CorrectionStage, FaultThresholds,
    FrontEndFaults, Gains, Input, MAX_CORRECTION_ORDER, ObserverState, Rails, Real,
    SensorCalibration, SinCos, Tracker, TrackerFrontEnd, TrackerSettings, TrackerState,
    WindingCheck,
};

use crate::{
    ArgumentError, CountsInput, CountsSettings, EstimateColumns, OnlineCalibrationChoice,
    ThresholdInput, ThresholdPolicy, checked_adc_range, clipping_rails, converted_calibration,
    converted_thresholds,
};

/// What a [`TrackerChannel`] runs with besides its gains.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ChannelOptions {
    /// The diagnostics' thresholds in float64, rounded to the channel's float type (`None`:
    /// by [`ThresholdPolicy`]).
    pub thresholds: Option<FaultThresholds<f64>>,
    /// Whether the samples come in one call holding the whole capture, not as a stream.
    pub whole: bool,
    /// How raw counts are scaled.
    pub counts: CountsSettings,
    /// The online calibration.
    pub calibration: OnlineCalibrationChoice,
    /// The ADC's range in the input's units (codes for counts): [`checked_adc_range`].
    pub adc_range: Option<(f64, f64)>,
    /// Without a range: the rails measured as the samples come ([`clipping_rails`]).
    pub measure_adc_range: bool,
    /// The windings' nominal envelope amplitude for the winding check (`None`: no check).
    pub winding_amplitude: Option<f64>,
    /// A stored sensor calibration and angle correction in place of the online calibration.
    pub stored: Option<(SensorCalibration<f64>, AngleCorrection<f64>)>,
}

/// Why a [`TrackerChannel`] is not built or does not run a chunk: the argument at fault as
/// the Python API names it, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum ChannelError {
    /// The core refused a configuration (it names the parameter).
    Config(ConfigError),
    /// An argument refused (`adc_range`, `winding_amplitude`, `y_s`, `fault_thresholds`).
    Argument(ArgumentError),
}

impl fmt::Display for ChannelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChannelError::Config(e) => e.fmt(f),
            ChannelError::Argument(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ChannelError {}

impl From<ArgumentError> for ChannelError {
    fn from(e: ArgumentError) -> Self {
        ChannelError::Argument(e)
    }
}

impl From<ConfigError> for ChannelError {
    fn from(e: ConfigError) -> Self {
        ChannelError::Config(e)
    }
}

fn refused(argument: &'static str, reason: impl Into<String>) -> ChannelError {
    ChannelError::Argument(ArgumentError::new(argument, reason))
}

/// The float standard chain of one observer and its state (see the module's
/// documentation).
///
/// ```
/// use angletrack::{ChannelOptions, TrackerChannel};
/// use angletrack::core::Gains;
/// let gains = Gains::<f64, 2, angletrack::Exact>::new([0.2, 0.02], 1e-4)?;
/// let options = ChannelOptions { winding_amplitude: Some(-1.0), ..ChannelOptions::default() };
/// let e = TrackerChannel::new(gains, &options).unwrap_err();
/// assert_eq!(e.to_string().split(':').next(), Some("winding_amplitude"));
/// # Ok::<(), angletrack::core::ConfigError>(())
/// ```
#[derive(Debug)]
pub struct TrackerChannel<T: Real, const N: usize, S> {
    /// The chain.
    pub tracker: Tracker<T, Gains<T, N, S>>,
    /// Its state.
    pub state: TrackerState<T, ObserverState<T, N>>,
    /// The scaling of raw counts.
    pub input: CountsInput<T>,
    thresholds: ThresholdPolicy<T>,
    adc_range: Option<(f64, f64)>,
    measure_adc_range: bool,
}

impl<T: Real, const N: usize, S: SinCos<T>> TrackerChannel<T, N, S> {
    /// The chain of `gains` with `options`, from its first sample.
    pub fn new(gains: Gains<T, N, S>, options: &ChannelOptions) -> Result<Self, ChannelError> {
        let adc_range = checked_adc_range(options.adc_range)?;
        clipping_rails(adc_range, options.measure_adc_range)?;
        let given = options.thresholds.as_ref().map(converted_thresholds);
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
            .map_err(|e| refused("winding_amplitude", e.to_string()))?;
        let stages = match &options.stored {
            Some((sensor, correction)) => {
                let (a, b) = correction.coefficients();
                let correction = AngleCorrection::new(a.map(T::from_f64), b.map(T::from_f64))?;
                (
                    CalibrationStage::Stored(converted_calibration(sensor)?),
                    CorrectionStage::Harmonics(correction),
                )
            }
            None => (
                CalibrationStage::Online(gains.online_calibration()),
                CorrectionStage::None,
            ),
        };
        let measure_adc_range = options.measure_adc_range;
        let front_end = front_end((adc_range, measure_adc_range), None, winding, stages)?;
        let mut state = TrackerState::new();
        *state.front_end.calibrator_mut() = options.calibration.calibrator()?;
        Ok(Self {
            tracker: Tracker::new(front_end, gains),
            state,
            input: if options.whole {
                CountsInput::whole(options.counts)
            } else {
                CountsInput::stream(options.counts)
            },
            thresholds,
            adc_range,
            measure_adc_range,
        })
    }

    /// Before running the chunk `y_c`, `y_s` (raw counts when `counts`, scaled by
    /// [`TrackerChannel::input`]) with its `front_end_faults`: checks their lengths, decides
    /// the thresholds of a whole capture and follows the scaling the counts decided with
    /// the ADC range in codes.
    pub fn prepare(
        &mut self,
        counts: bool,
        (y_c, y_s): (&[T], &[T]),
        front_end_faults: Option<&[u8]>,
    ) -> Result<(), ChannelError> {
        ArgumentError::check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        if let Some(faults) = front_end_faults {
            ArgumentError::check_equal_lengths(
                ("y_c", y_c.len()),
                ("front_end_faults", faults.len()),
            )?;
        }
        let input = if counts {
            ThresholdInput::Counts {
                counts_per_unit_stated: self.input.settings().counts_per_unit().is_some(),
            }
        } else {
            ThresholdInput::Floats
        };
        let decided = self.thresholds.decide(input, y_c, y_s).map_err(|e| {
            let reason = format!(
                "{e}: give fault_thresholds=FaultThresholds(nominal_amplitude=A) with A in \
                 counts, or adc_counts_per_unit=A"
            );
            refused("fault_thresholds", reason)
        })?;
        if let Some(thresholds) = decided {
            self.tracker.observer = self.tracker.observer.with_fault_thresholds(thresholds)?;
        }
        // The range in codes is the ADC's: the front end follows the scaling the samples
        // decided (measured or unchecked rails are the same for any).
        let adc = self.input.decided().filter(|_| counts);
        let held = self.tracker.front_end;
        if self.adc_range.is_some() && held.adc() != adc {
            let stages = (held.calibration(), held.correction());
            let clipping = (self.adc_range, self.measure_adc_range);
            self.tracker.front_end = front_end(clipping, adc, held.winding(), stages)?;
        }
        Ok(())
    }

    /// Runs the chain over `y_c`, `y_s` (as [`TrackerChannel::prepare`] checked them) into
    /// the columns, with each sample's `front_end_faults` if given.
    pub fn run(
        &mut self,
        columns: EstimateColumns<'_, T>,
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
        let (tracker, state) = (&self.tracker, &mut self.state);
        columns.write(
            y_c.iter()
                .zip(y_s)
                .enumerate()
                .map(|(k, (&c, &s))| tracker.update(state, ((c, s), faults(k)))),
        );
    }

    /// The thresholds the diagnostics run with, once decided.
    pub fn fault_thresholds(&self) -> Option<FaultThresholds<T>> {
        self.thresholds
            .thresholds()
            .map(|_| self.tracker.observer.fault_thresholds())
    }

    /// Sets the angle from one sample, `atan2(y_s, y_c)`; speed and acceleration 0. A
    /// sample that is not finite is refused, naming it and its value (the observer would
    /// otherwise replace it silently by its own start).
    pub fn initialise(&mut self, y_c: f64, y_s: f64) -> Result<(), ChannelError> {
        finite(&[("y_c", y_c), ("y_s", y_s)])?;
        let (gains, state) = (&self.tracker.observer, &mut self.state.observer);
        gains.initialise(state, T::from_f64(y_c), T::from_f64(y_s));
        Ok(())
    }

    /// Sets the observer's state, refusing what it cannot hold: a value that is not finite
    /// (naming it and its value), or beyond the state's range (the core names it).
    pub fn set_state(
        &mut self,
        angle_rad: f64,
        speed_rad_s: f64,
        acceleration_rad_s2: f64,
    ) -> Result<(), ChannelError> {
        finite(&[
            ("angle_rad", angle_rad),
            ("speed_rad_s", speed_rad_s),
            ("acceleration_rad_s2", acceleration_rad_s2),
        ])?;
        let f = T::from_f64;
        let period = self.tracker.observer.sample_period();
        self.state.observer =
            ObserverState::at(f(angle_rad), f(speed_rad_s), f(acceleration_rad_s2), period)?;
        Ok(())
    }
}

/// The stored stages of their parameters, each checked by the core: the sensor calibration
/// `(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)` and the angle
/// correction's harmonic coefficients `cos`, `sin` (rad, at most
/// [`MAX_CORRECTION_ORDER`] each, the rest 0): [`ChannelOptions::stored`].
///
/// ```
/// use angletrack::stored_stages;
/// let (sensor, correction) = stored_stages((0.0, 0.0, 1.0, 1.0, 0.0), &[1e-3], &[])?;
/// assert_eq!(correction.coefficients().0[0], 1e-3);
/// assert!(stored_stages((0.0, 0.0, 1.0, 1.0, 0.0), &[0.0; 9], &[]).is_err());
/// # let _ = sensor;
/// # Ok::<(), angletrack::ChannelError>(())
/// ```
pub fn stored_stages(
    (o_c, o_s, a_c, a_s, phi): (f64, f64, f64, f64, f64),
    cos: &[f64],
    sin: &[f64],
) -> Result<(SensorCalibration<f64>, AngleCorrection<f64>), ChannelError> {
    let sensor = SensorCalibration::new(o_c, o_s, a_c, a_s, phi)?;
    let table = |values: &[f64], name: &'static str| {
        let mut out = [0.0; MAX_CORRECTION_ORDER];
        if values.len() > MAX_CORRECTION_ORDER {
            return Err(refused(
                name,
                format!("holds more than {MAX_CORRECTION_ORDER} coefficients"),
            ));
        }
        out[..values.len()].copy_from_slice(values);
        Ok(out)
    };
    let correction = AngleCorrection::new(table(cos, "cos")?, table(sin, "sin")?)?;
    Ok((sensor, correction))
}

/// The front end for samples scaled by `adc` (`None`: floats, in the units of the ADC
/// range): the range in codes through the ADC's scaling when the samples are counts (the
/// core's rule); without a range, the rails measured or unchecked.
fn front_end<T: Real>(
    (range, measure): (Option<(f64, f64)>, bool),
    adc: Option<AdcScaling<T>>,
    winding: Option<WindingCheck<T>>,
    (calibration, correction): (CalibrationStage<T>, CorrectionStage<T>),
) -> Result<TrackerFrontEnd<T>, ChannelError> {
    let input = match adc {
        Some(adc) => Input::Counts {
            adc,
            rails: rails((range, measure), code)?,
        },
        None => Input::Units {
            rails: rails((range, measure), |bound| Ok(T::from_f64(bound)))?,
        },
    };
    TrackerFrontEnd::new(TrackerSettings {
        input,
        winding,
        calibration,
        correction,
    })
    .map_err(|e| refused("adc_range", e.to_string()))
}

/// Refuses the first value that is not finite, naming its argument and the value.
fn finite(values: &[(&'static str, f64)]) -> Result<(), ChannelError> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some(&(argument, v)) => Err(refused(argument, format!("{v} is not finite"))),
        None => Ok(()),
    }
}

/// The rails of the clipping arguments, the range's bounds by `bound`.
fn rails<X>(
    (range, measure): (Option<(f64, f64)>, bool),
    bound: impl Fn(f64) -> Result<X, ChannelError>,
) -> Result<Rails<X>, ChannelError> {
    let range = range.map(|(min, max)| Ok::<_, ChannelError>((bound(min)?, bound(max)?)));
    Ok(clipping_rails(range.transpose()?, measure)?)
}

/// A bound of the ADC range for counts as an ADC code: a whole number, beyond int32 taken
/// as int32's extreme (the chain's counts are int32, wider ones refused as samples: the
/// core's `Rails::of_adc_bits` takes an unsigned 32-bit ADC's rail so).
fn code(bound: f64) -> Result<i32, ChannelError> {
    if bound.fract() == 0.0 {
        // A whole number: saturated to int32, as the comment above says.
        Ok(bound as i32)
    } else {
        Err(refused(
            "adc_range",
            format!("{bound}: the samples are counts, expected whole ADC codes"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CountsSettings, Signedness};
    use angletrack_core::Exact;

    fn gains() -> Gains<f64, 2, Exact> {
        Gains::new([0.2, 0.02], 1e-4).unwrap()
    }

    fn columns_of<R>(
        n: usize,
        f: impl FnOnce(EstimateColumns<'_, f64>) -> R,
    ) -> (R, Vec<f64>, Vec<u8>) {
        let (mut angle, mut faults) = (vec![0.0; n], vec![0u8; n]);
        let columns = EstimateColumns {
            angle: Some(&mut angle),
            position: None,
            speed: None,
            acceleration: None,
            phase_error: None,
            faults: Some(&mut faults),
        };
        (f(columns), angle, faults)
    }

    #[test]
    fn refusals_name_the_argument() {
        let argument = |e: ChannelError| match e {
            ChannelError::Argument(e) => e.argument,
            ChannelError::Config(e) => e.parameter().name(),
        };
        let mut channel = TrackerChannel::new(gains(), &ChannelOptions::default()).unwrap();
        let e = channel
            .prepare(false, (&[1.0, 0.0], &[0.0]), None)
            .unwrap_err();
        assert_eq!(argument(e), "y_s");
        let e = channel
            .prepare(false, (&[1.0], &[0.0]), Some(&[0, 0]))
            .unwrap_err();
        assert_eq!(argument(e), "front_end_faults");
        // Counts of a stream in counts, without thresholds.
        let e = channel.prepare(true, (&[1.0], &[0.0]), None).unwrap_err();
        assert_eq!(argument(e), "fault_thresholds");
        let options = ChannelOptions {
            adc_range: Some((0.5, 4095.0)),
            counts: CountsSettings::new(Some(2048), Some(1800.0), None).unwrap(),
            ..ChannelOptions::default()
        };
        let mut channel = TrackerChannel::new(gains(), &options).unwrap();
        let (c, s) = channel
            .input
            .scale(&[3848i32], &[2048], Some(Signedness::Unsigned))
            .unwrap();
        let e = channel.prepare(true, (&c, &s), None).unwrap_err();
        assert_eq!(argument(e), "adc_range");
    }

    #[test]
    fn counts_at_the_stated_range_are_flagged_and_a_whole_capture_decides_its_thresholds() {
        let options = ChannelOptions {
            whole: true,
            adc_range: Some((0.0, 4095.0)),
            counts: CountsSettings::new(Some(2048), None, None).unwrap(),
            ..ChannelOptions::default()
        };
        let mut channel = TrackerChannel::new(gains(), &options).unwrap();
        assert_eq!(channel.fault_thresholds(), None);
        let (c, s) = channel
            .input
            .scale(&[3848i32, 4095], &[2048, 2048], Some(Signedness::Unsigned))
            .unwrap();
        channel.prepare(true, (&c, &s), None).unwrap();
        let amplitude = channel.fault_thresholds().unwrap().nominal_amplitude;
        assert!((1800.0..=2047.0).contains(&amplitude), "{amplitude}");
        let ((), angle, faults) = columns_of(2, |columns| channel.run(columns, (&c, &s), None));
        assert_eq!(angle[0], 0.0);
        assert_eq!(faults[0] & angletrack_core::Faults::FRONT_END.bits(), 0);
        assert_ne!(faults[1] & angletrack_core::Faults::FRONT_END.bits(), 0);
    }

    #[test]
    fn set_state_refuses_what_the_state_cannot_hold() {
        let mut channel = TrackerChannel::new(gains(), &ChannelOptions::default()).unwrap();
        assert!(channel.set_state(1.0, 10.0, 0.0).is_ok());
        assert!(channel.set_state(1.0, 1e9, 0.0).is_err());
        let e = channel.set_state(1.0, f64::NAN, 0.0).unwrap_err();
        assert_eq!(e.to_string(), "speed_rad_s: NaN is not finite");
        let e = channel.initialise(1.0, f64::INFINITY).unwrap_err();
        assert_eq!(e.to_string(), "y_s: inf is not finite");
        channel.initialise(0.0, 1.0).unwrap();
        assert!(channel.state.observer.is_initialised());
    }
}
