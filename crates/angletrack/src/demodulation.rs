//! A resolver's raw windings demodulated as a stream (`docs/theory.md §13`): the core's
//! [`Demodulator`] built from its arguments as a caller states them (the ADC rate or the
//! samples per carrier period; the settings left out at the core's defaults), its state,
//! the rails measured as the samples come when asked ([`WindingRails`]), and the pairs of
//! each pushed block as columns. The Python `Demodulator` is this type.

use angletrack_core::{
    ConfigError, DemodulatedPair, Demodulator, DemodulatorSettings, DemodulatorState,
    FrontEndFaults, Parameter,
};

use crate::{ArgumentError, WindingRails};

/// A demodulator's arguments as a caller writes them; `None`: the core's default.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DemodulatorArguments {
    /// The declared carrier frequency (Hz).
    pub carrier_hz: f64,
    /// A winding's carrier amplitude at envelope 1 (counts).
    pub carrier_amplitude_counts: f64,
    /// The ADC rate (Hz); give this or `samples_per_period`.
    pub adc_rate_hz: Option<f64>,
    /// ADC samples per declared carrier period (the ADC rate over the carrier).
    pub samples_per_period: Option<f64>,
    /// The ADC's codes `(min, max)` clipping is checked against.
    pub adc_range: (f64, f64),
    /// The carrier delay (rad) the half turn is resolved around, as the caller states it:
    /// with the excitation's samples the windings' delay after the excitation, without them
    /// their delay after a carrier of phase 0 at the first sample (positive: lagging). `None`: not stated; the half turn is taken
    /// around 0 and every pair marked [`PairColumns::half_turn_unresolved`] (the windings and
    /// the excitation cannot tell a delay from the one half a turn away: an inverted
    /// excitation probe, or a filter delaying the carrier beyond 90 degrees, reads as the
    /// shaft half a turn further).
    pub expected_delay_rad: Option<f64>,
    /// The carrier periods of the start-up.
    pub startup_periods: Option<u32>,
    /// The phase drift flagged (rad).
    pub phase_drift_bound_rad: Option<f64>,
    /// The excitation level below which it is lost (fraction of nominal).
    pub loss_of_excitation: Option<f64>,
    /// The excitation level below which it is weak (fraction of nominal).
    pub weak_excitation: Option<f64>,
    /// The carrier loop's bandwidth (fraction of the carrier).
    pub carrier_loop_bandwidth: Option<f64>,
    /// The largest carrier error tracked (fraction of the carrier).
    pub max_carrier_error: Option<f64>,
    /// Whether clipping is also checked against the rails measured on each block.
    pub measure_adc_range: bool,
}

fn refused(argument: &'static str, reason: impl Into<String>) -> ArgumentError {
    ArgumentError::new(argument, reason)
}

/// The pairs of one [`DemodulatorStream::push`], one element per pair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PairColumns {
    /// The time (s) each pair holds at, from the first sample pushed.
    pub time_s: Vec<f64>,
    /// The cosine winding's envelope.
    pub y_c: Vec<f64>,
    /// The sine winding's envelope.
    pub y_s: Vec<f64>,
    /// The cosine winding's quadrature component.
    pub quadrature_c: Vec<f64>,
    /// The sine winding's quadrature component.
    pub quadrature_s: Vec<f64>,
    /// The index of each pair's window.
    pub window: Vec<u64>,
    /// The front end's faults of each window (bits).
    pub faults: Vec<u8>,
    /// Whether each pair's half turn rests on nothing stated: `true` on every pair without a
    /// stated delay, and with the excitation on the pairs whose window's excitation resolved
    /// nothing ([`FrontEndFaults::EXCITATION_REFERENCE`]). Not a fault: the angle is right
    /// or exactly half a turn off, the same on every such pair.
    pub half_turn_unresolved: Vec<bool>,
}

/// The core's demodulator of a stream of raw windings, its state and the rails measured
/// (see the module's documentation).
///
/// ```
/// use angletrack::{DemodulatorArguments, DemodulatorStream};
/// let arguments = DemodulatorArguments {
///     carrier_hz: 10e3,
///     carrier_amplitude_counts: 1800.0,
///     samples_per_period: Some(3.5),
///     adc_range: (0.0, 4095.0),
///     ..DemodulatorArguments::default()
/// };
/// let e = DemodulatorStream::new(&arguments).unwrap_err();
/// assert_eq!(e.argument, "samples_per_period");
/// ```
#[derive(Debug, Clone)]
pub struct DemodulatorStream {
    demodulator: Demodulator<f64>,
    state: DemodulatorState<f64>,
    rails: Option<WindingRails>,
    delay_stated: bool,
}

impl DemodulatorStream {
    /// The demodulator of `arguments`, each refusal naming the argument the caller gave:
    /// the ADC rate as `samples_per_period` when that was given, the ADC range as
    /// `adc_max_code`.
    pub fn new(arguments: &DemodulatorArguments) -> Result<Self, ArgumentError> {
        let a = arguments;
        let adc_rate_hz = match (a.adc_rate_hz, a.samples_per_period) {
            (Some(rate), None) => rate,
            (None, Some(n)) => n * a.carrier_hz,
            _ => {
                return Err(refused(
                    "adc_rate_hz",
                    "give adc_rate_hz or samples_per_period, one of them",
                ));
            }
        };
        let (min, max) = a.adc_range;
        let d = DemodulatorSettings::new(
            a.carrier_hz,
            adc_rate_hz,
            a.carrier_amplitude_counts,
            min,
            max,
        );
        let settings = DemodulatorSettings {
            expected_delay_rad: a.expected_delay_rad.unwrap_or(0.0),
            startup_periods: a.startup_periods.unwrap_or(d.startup_periods),
            phase_drift_bound_rad: a.phase_drift_bound_rad.unwrap_or(d.phase_drift_bound_rad),
            loss_of_excitation: a.loss_of_excitation.unwrap_or(d.loss_of_excitation),
            weak_excitation: a.weak_excitation.unwrap_or(d.weak_excitation),
            carrier_loop_bandwidth: a.carrier_loop_bandwidth.unwrap_or(d.carrier_loop_bandwidth),
            max_carrier_error: a.max_carrier_error.unwrap_or(d.max_carrier_error),
            ..d
        };
        let demodulator = Demodulator::new(settings).map_err(|e| named(e, a))?;
        Ok(Self {
            demodulator,
            state: DemodulatorState::new(),
            rails: a.measure_adc_range.then(WindingRails::new),
            delay_stated: a.expected_delay_rad.is_some(),
        })
    }

    /// Whether the carrier delay the half turn is resolved around was stated
    /// ([`DemodulatorArguments::expected_delay_rad`]).
    pub fn is_delay_stated(&self) -> bool {
        self.delay_stated
    }

    /// The core's demodulator.
    pub fn demodulator(&self) -> &Demodulator<f64> {
        &self.demodulator
    }

    /// The demodulator's state.
    pub fn state(&self) -> &DemodulatorState<f64> {
        &self.state
    }

    /// The front-end faults latched so far, the clipping against the rails measured
    /// included.
    pub fn latched_faults(&self) -> FrontEndFaults {
        let measured = self.rails.as_ref().map(WindingRails::latched_faults);
        self.state.latched_faults() | measured.unwrap_or_default()
    }

    /// The rails measured so far (`None` before the first, or without the measurement).
    pub fn measured_adc_range(&self) -> Option<(f64, f64)> {
        self.rails.as_ref().and_then(WindingRails::rails)
    }

    /// The samples found at a measured rail so far (0 without the measurement).
    pub fn clipped_samples(&self) -> u64 {
        self.rails.as_ref().map_or(0, WindingRails::clipped_samples)
    }

    /// Pushes the raw windings `raw_c`, `raw_s` (and the excitation, if given: on every push
    /// of a run or on none), all of one length, and returns the pairs that complete.
    pub fn push(
        &mut self,
        raw_c: &[f64],
        raw_s: &[f64],
        excitation: Option<&[f64]>,
    ) -> Result<PairColumns, ArgumentError> {
        let lengths = [
            ("raw_s", Some(raw_s.len())),
            ("excitation", excitation.map(<[f64]>::len)),
        ];
        for (argument, len) in lengths {
            if let Some(len) = len.filter(|&len| len != raw_c.len()) {
                return Err(refused(
                    argument,
                    format!(
                        "has {len} samples but raw_c has {}: they must be equal",
                        raw_c.len()
                    ),
                ));
            }
        }
        if self.state.samples() > 0 && excitation.is_some() != self.state.has_excitation() {
            return Err(refused(
                "excitation",
                "give the excitation on every push of a run or on none",
            ));
        }
        let demodulator = &self.demodulator;
        let stated = self.delay_stated;
        let mut out = PairColumns::default();
        let sink = |pair: DemodulatedPair<f64>| {
            out.time_s.push(demodulator.centre_s(&pair));
            out.y_c.push(pair.y_c);
            out.y_s.push(pair.y_s);
            out.quadrature_c.push(pair.quadrature_c);
            out.quadrature_s.push(pair.quadrature_s);
            out.window.push(pair.window);
            out.faults.push(pair.faults.bits());
            let no_reference =
                excitation.is_some() && pair.faults.contains(FrontEndFaults::EXCITATION_REFERENCE);
            out.half_turn_unresolved.push(!stated || no_reference);
        };
        let (state, c, s) = (&mut self.state, raw_c, raw_s);
        match (&mut self.rails, excitation) {
            (Some(rails), e) => rails.push_block(demodulator, state, c, s, e, sink),
            (None, Some(e)) => demodulator.push_block_with_excitation(state, c, s, e, sink),
            (None, None) => demodulator.push_block(state, c, s, sink),
        };
        Ok(out)
    }
}

/// The core's refusal under the argument the caller gave: the ADC rate is
/// `samples_per_period` times the carrier when that was given; the ADC range's is
/// `adc_max_code`.
fn named(e: ConfigError, a: &DemodulatorArguments) -> ArgumentError {
    match (e.parameter(), a.samples_per_period) {
        (Parameter::AdcRate, Some(n)) => refused(
            "samples_per_period",
            format!(
                "{n} ADC samples per carrier period are refused (expected 4 or more, up to the \
                 demodulator's limit): {e}"
            ),
        ),
        (Parameter::AdcRange, _) => refused("adc_max_code", e.to_string()),
        (parameter, _) => refused(parameter.name(), e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arguments() -> DemodulatorArguments {
        DemodulatorArguments {
            carrier_hz: 10e3,
            carrier_amplitude_counts: 1800.0,
            adc_rate_hz: Some(160e3),
            adc_range: (0.0, 4095.0),
            ..DemodulatorArguments::default()
        }
    }

    #[test]
    fn refusals_name_the_argument_given() {
        let refused = |a: DemodulatorArguments| DemodulatorStream::new(&a).unwrap_err().argument;
        let mut a = arguments();
        a.adc_rate_hz = Some(30e3);
        assert_eq!(refused(a), "adc_rate_hz");
        a.adc_rate_hz = None;
        a.samples_per_period = Some(3.5);
        assert_eq!(refused(a), "samples_per_period");
        a.adc_rate_hz = Some(160e3);
        assert_eq!(refused(a), "adc_rate_hz");
        let mut a = arguments();
        a.adc_range = (4095.0, 0.0);
        assert_eq!(refused(a), "adc_max_code");
        let mut a = arguments();
        a.carrier_hz = -1.0;
        assert_eq!(refused(a), "carrier_hz");
    }

    #[test]
    fn a_push_of_unequal_lengths_or_a_changed_excitation_is_refused() {
        let mut stream = DemodulatorStream::new(&arguments()).unwrap();
        let e = stream.push(&[2048.0; 4], &[2048.0; 3], None).unwrap_err();
        assert_eq!(e.argument, "raw_s");
        assert_eq!(
            e.to_string(),
            "raw_s: has 3 samples but raw_c has 4: they must be equal"
        );
        assert_eq!(
            stream
                .push(&[2048.0; 4], &[2048.0; 4], None)
                .unwrap()
                .y_c
                .len(),
            0
        );
        let e = stream
            .push(&[2048.0; 4], &[2048.0; 4], Some(&[0.0; 4]))
            .unwrap_err();
        assert_eq!(e.argument, "excitation");
    }

    #[test]
    fn the_pairs_are_the_demodulators_own() {
        let mut stream = DemodulatorStream::new(&arguments()).unwrap();
        let carrier = |k: usize| (std::f64::consts::TAU * k as f64 / 16.0).sin();
        let c: Vec<f64> = (0..1600).map(|k| 2048.0 + 1800.0 * carrier(k)).collect();
        let s = vec![2048.0; 1600];
        let pairs = stream.push(&c, &s, None).unwrap();
        let (demodulator, mut state) = (stream.demodulator, DemodulatorState::new());
        let mut y_c = Vec::new();
        demodulator.push_block(&mut state, &c, &s, |pair| y_c.push(pair.y_c));
        assert!(y_c.len() > 50, "{}", y_c.len());
        assert_eq!(pairs.y_c, y_c);
        assert_eq!(pairs.time_s.len(), y_c.len());
    }

    #[test]
    fn the_half_turn_is_unresolved_unless_the_delay_is_stated_and_the_excitation_resolved_it() {
        let carrier = |k: usize| (std::f64::consts::TAU * k as f64 / 16.0).sin();
        let c: Vec<f64> = (0..1600).map(|k| 2048.0 + 1800.0 * carrier(k)).collect();
        let s = vec![2048.0; 1600];
        let flat = vec![2048.0; 1600];
        let excitation: Vec<f64> = (0..1600).map(|k| 2048.0 + 1500.0 * carrier(k)).collect();
        let unresolved = |delay: Option<f64>, e: Option<&[f64]>| {
            let a = DemodulatorArguments {
                expected_delay_rad: delay,
                ..arguments()
            };
            let pairs = DemodulatorStream::new(&a).unwrap().push(&c, &s, e).unwrap();
            assert!(pairs.half_turn_unresolved.len() > 50);
            let all = pairs.half_turn_unresolved.iter().all(|&u| u);
            assert!(all || pairs.half_turn_unresolved.iter().all(|&u| !u));
            all
        };
        assert!(unresolved(None, None) && unresolved(None, Some(&excitation)));
        assert!(!unresolved(Some(0.0), None) && !unresolved(Some(0.0), Some(&excitation)));
        assert!(unresolved(Some(0.0), Some(&flat)));
    }
}
