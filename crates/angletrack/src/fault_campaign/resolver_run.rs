//! The measurement of one resolver case, as `angletrack track --carrier-hz` runs a capture:
//! the crate's [`DemodulatorStream`] (with the excitation's samples or without, the carrier
//! delay stated or not) and the core's standard chain in `f64` on its pairs, each pair's
//! front-end faults given to it (the observer coasts through those that invalidate a pair),
//! the winding check at the pairs' nominal amplitude 1 and the healthy sensor's stored
//! calibration. Each estimate is compared with the true electrical angle at its pair's
//! centre.

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use angletrack_core::{
    CalibrationStage, CorrectionStage, FaultThresholds, FrontEndFaults, Gains, Input, Rails,
    SensorCalibration, Tracker, TrackerFrontEnd, TrackerSettings, TrackerState, WindingCheck,
};

use super::cases::{Case, FaultKind, Onset, SensorKind};
use super::measurement::CaseResult;
use super::resolver::{
    CARRIER_AMPLITUDE_COUNTS, CARRIER_HZ, MID_RUN_PERIODS, ResolverKind, ResolverScenario,
    SAMPLES_PER_PERIOD, START_UP_PAIRS, WINDING_DELAY_RAD, Windings, windings,
};
use super::{GAINS, HEALTHY_SENSOR};
use crate::{DemodulatorArguments, DemodulatorStream};

/// `x` (rad) wrapped to [-pi, pi).
fn wrapped(x: f64) -> f64 {
    (x + PI).rem_euclid(TAU) - PI
}

/// `x` (rad) wrapped to [-pi/2, pi/2): the error of an angle whose half turn is unresolved.
fn within_half_turn(x: f64) -> f64 {
    (x + FRAC_PI_2).rem_euclid(PI) - FRAC_PI_2
}

/// The demodulator of `kind`, as a user states it: the carrier, the 8 samples per period,
/// the carrier amplitude of the healthy sensor, the 12-bit ADC's codes, and the windings'
/// delay unless the kind leaves it unstated.
fn demodulator(kind: ResolverKind) -> DemodulatorStream {
    let arguments = DemodulatorArguments {
        carrier_hz: CARRIER_HZ,
        carrier_amplitude_counts: CARRIER_AMPLITUDE_COUNTS,
        samples_per_period: Some(SAMPLES_PER_PERIOD as f64),
        adc_range: (0.0, 4095.0),
        expected_delay_rad: (kind != ResolverKind::DelayNotStated).then_some(WINDING_DELAY_RAD),
        ..DemodulatorArguments::default()
    };
    DemodulatorStream::new(&arguments).expect("the campaign's demodulator")
}

/// The chain of the pairs: in their unit (no rails: clipping is the demodulator's, on the
/// raw samples), the winding check and the monitor at the nominal amplitude 1, the healthy
/// sensor's stored calibration in the pairs' unit, the campaign's gains at the carrier.
fn tracker() -> Tracker<f64, Gains<f64, 3>> {
    let (o_c, o_s, a_c, a_s, q) = HEALTHY_SENSOR
        .calibration()
        .expect("the healthy sensor is within the bounds")
        .parameters();
    let a = HEALTHY_SENSOR.amplitude;
    let calibration = SensorCalibration::new(o_c / a, o_s / a, a_c / a, a_s / a, q)
        .expect("the healthy calibration");
    let settings = TrackerSettings::<f64> {
        input: Input::Units {
            rails: Rails::Unchecked,
        },
        winding: Some(WindingCheck::new(1.0).expect("a positive amplitude")),
        calibration: CalibrationStage::Stored(calibration),
        correction: CorrectionStage::None,
    };
    let gains = Gains::<f64, 3>::new(GAINS, 1.0 / CARRIER_HZ)
        .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(1.0)))
        .expect("the campaign's gains");
    Tracker::new(
        TrackerFrontEnd::new(settings).expect("valid settings"),
        gains,
    )
}

/// Runs the resolver `case` on `scenario` (its speed's healthy resolver). The judged pairs
/// are those from [`START_UP_PAIRS`] and from the first whose window holds a faulty sample;
/// the latency is counted in pairs (carrier periods). A pair marked half turn unresolved
/// has its angle judged modulo a half turn (the status says it may be half a turn off), and
/// the status reveals it (the coverage and latency count it, the false alarms do not): its
/// half turn is not asserted, nor, under a stored calibration learned on the other half
/// turn, its offsets. [`CaseResult::half_turn_unresolved`] counts them.
pub fn run_case(case: Case, scenario: &ResolverScenario) -> CaseResult {
    let FaultKind::Carrier(fault) = case.fault else {
        unreachable!("a resolver case");
    };
    run_windings(case, &windings(scenario, fault, case.onset), scenario)
}

/// [`run_case`] on the windings `raw` (the case's fault injected in them) of `scenario`.
pub fn run_windings(case: Case, raw: &Windings, scenario: &ResolverScenario) -> CaseResult {
    let SensorKind::Resolver(kind) = case.setup.sensor else {
        unreachable!("a resolver case");
    };
    let mut stream = demodulator(kind);
    let excitation = (kind == ResolverKind::ExcitationColumn).then_some(&raw.excitation[..]);
    let pairs = stream
        .push(&raw.raw_c, &raw.raw_s, excitation)
        .expect("windings of one length");
    // A pair's window is 1.25 carrier periods about its centre: the first pair holding a
    // faulty sample is the first whose window ends after the onset.
    let onset_s = match case.onset {
        Onset::Start => 0.0,
        Onset::MidRun => MID_RUN_PERIODS as f64 / CARRIER_HZ,
    };
    let onset = pairs
        .time_s
        .iter()
        .position(|&t| t + 0.625 / CARRIER_HZ > onset_s)
        .unwrap_or(pairs.time_s.len());
    let adc_hz = CARRIER_HZ * SAMPLES_PER_PERIOD as f64;
    let tracker = tracker();
    let mut state = TrackerState::new();
    let mut result = CaseResult::new(case);
    for k in 0..pairs.y_c.len() {
        let faults = FrontEndFaults::from_bits(pairs.faults[k]);
        let e = tracker.update(&mut state, ((pairs.y_c[k], pairs.y_s[k]), faults));
        let flagged = !e.faults.is_empty() || !state.front_end.faults().is_empty();
        let unresolved = pairs.half_turn_unresolved[k];
        if k + 1 == START_UP_PAIRS {
            state.observer.clear_faults();
            state.front_end.clear_faults();
        }
        let error = wrapped(e.angle - scenario.angle_at(pairs.time_s[k] * adc_hz));
        let error = if unresolved {
            within_half_turn(error)
        } else {
            error
        };
        result.judge(k, (onset, START_UP_PAIRS), error, (flagged, unresolved));
    }
    result.latched =
        !state.observer.latched_faults().is_empty() || !state.front_end.latched_faults().is_empty();
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fault_campaign::resolver::{CarrierFault, MID_SCALE, delayed_windings};
    use crate::fault_campaign::{NumberType, Setup, Speed};

    /// The case of `fault` from the start at 1 kHz electrical on `kind`.
    fn case(fault: CarrierFault, kind: ResolverKind) -> Case {
        Case {
            fault: FaultKind::Carrier(fault),
            onset: Onset::Start,
            speed: Speed::Fast,
            setup: Setup {
                sensor: SensorKind::Resolver(kind),
                number: NumberType::F64,
            },
        }
    }

    /// The faults listed as undetectable ([`super::super::resolver::UNDETECTABLE`]) give the
    /// shaft half a turn further, every judged pair wrong and none flagged, while their
    /// healthy twins track right.
    #[test]
    fn the_undetectable_carrier_faults_read_as_the_shaft_half_a_turn_further() {
        let scenario = ResolverScenario::generate(Speed::Fast);
        let column = ResolverKind::ExcitationColumn;
        let healthy = run_case(case(CarrierFault::Healthy, column), &scenario);
        assert_eq!((healthy.wrong, healthy.flagged), (0, 0));
        assert!(healthy.samples > 2900);
        let half_a_turn_off = |r: CaseResult| {
            assert!(r.samples > 2900, "{}", r.samples);
            assert_eq!((r.wrong, r.flagged), (r.samples, 0));
        };
        let stated = ResolverKind::DelayStated;
        half_a_turn_off(run_case(
            case(CarrierFault::InvertedExcitation, stated),
            &scenario,
        ));
        // The probe inverted: the recorded excitation alone, about mid-scale.
        let mut probe = windings(&scenario, CarrierFault::Healthy, Onset::Start);
        for e in &mut probe.excitation {
            *e = 2.0 * MID_SCALE - *e;
        }
        half_a_turn_off(run_windings(
            case(CarrierFault::Healthy, column),
            &probe,
            &scenario,
        ));
        for kind in [column, stated] {
            let fault = CarrierFault::DelayBeyondStated;
            let late = delayed_windings(&scenario, fault, Onset::Start, 120f64.to_radians());
            half_a_turn_off(run_windings(case(fault, kind), &late, &scenario));
        }
    }
}
