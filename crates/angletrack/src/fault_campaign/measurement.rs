//! The measurement of one case: the core's standard chain (`Tracker`) as a user builds it
//! for the case's setup, run on the injected samples, each estimate compared with the true
//! electrical angle and its flags read.

use core::f64::consts::{PI, TAU};

use angletrack_core::fixed::{binary_angle, binary_angle_to_rad};
use angletrack_core::{
    AdcCounts, CalibrationStage, CorrectionStage, FaultThresholds, FixedCalibration, FixedGains,
    Gains, Input, Rails, SensorCalibration, Tracker, TrackerFrontEnd, TrackerSettings,
    TrackerState, WindingCheck,
};

use super::cases::{Case, FaultKind, NumberType, RailsKind, SensorKind};
use super::injection::{Injector, code};
use super::{ERROR_BOUND_RAD, GAINS, HEALTHY_SENSOR, SAMPLE_PERIOD_S, SAMPLES, START_UP};
use crate::AdcScaling;

/// The fixed-point chain's samples per unit of full scale: 12-bit counts shifted left by
/// 4 (`AdcCounts::offset_binary(12)`), 2048 counts of full scale at 16 each.
const FIXED_FULL_SCALE: f64 = 32768.0;

/// What one case measured, on the samples from [`START_UP`] or the onset on, whichever is
/// later (the loop's acquisition from rest is not judged, and before a mid-run onset the
/// run is its healthy twin), and from the onset for the latency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaseResult {
    /// The case.
    pub case: Case,
    /// Samples judged (from [`START_UP`] or the onset on).
    pub samples: usize,
    /// Judged samples whose electrical angle error exceeds [`ERROR_BOUND_RAD`].
    pub wrong: usize,
    /// Wrong samples that were flagged (the estimate's faults or the front end's).
    pub wrong_flagged: usize,
    /// Judged samples that were flagged, wrong or not.
    pub flagged: usize,
    /// Whether a fault (the observer's or the front end's) latched after the start-up (the
    /// latches are cleared at [`START_UP`], as a user clears them once the loop is locked).
    pub latched: bool,
    /// Samples from the onset to the first flag at or after it, if any.
    pub latency: Option<usize>,
    /// Judged samples marked half turn unresolved (a resolver's pairs without a stated
    /// carrier delay: a status, not a fault; their angles judged modulo a half turn).
    pub half_turn_unresolved: usize,
}

impl CaseResult {
    /// The result of `case` before any sample is judged.
    pub fn new(case: Case) -> Self {
        Self {
            case,
            samples: 0,
            wrong: 0,
            wrong_flagged: 0,
            flagged: 0,
            latched: false,
            latency: None,
            half_turn_unresolved: 0,
        }
    }

    /// Judges sample (or pair) `k` of the case, its fault starting at `onset`, the samples
    /// before `start_up` not judged: its angle error `error` (rad, wrapped; modulo a half
    /// turn where `unresolved`), whether it was `flagged`, and whether it is marked half
    /// turn `unresolved` (which reveals it, for the coverage and the latency, but is not a
    /// false alarm).
    pub(super) fn judge(
        &mut self,
        k: usize,
        (onset, start_up): (usize, usize),
        error: f64,
        (flagged, unresolved): (bool, bool),
    ) {
        if (flagged || unresolved) && k >= onset && self.latency.is_none() {
            self.latency = Some(k - onset);
        }
        // Before a mid-run onset the run is its healthy twin's: judged there, not here.
        if k < start_up.max(onset) {
            return;
        }
        let wrong = error.abs() > ERROR_BOUND_RAD;
        self.samples += 1;
        self.wrong += usize::from(wrong);
        self.wrong_flagged += usize::from(wrong && (flagged || unresolved));
        self.flagged += usize::from(flagged);
        self.half_turn_unresolved += usize::from(unresolved);
    }
}

/// One sample's outcome: the angle error (rad, wrapped to +-pi) and whether it was flagged.
type Outcome = (f64, bool);

/// `x` (rad) wrapped to [-pi, pi).
fn wrapped(x: f64) -> f64 {
    (x + PI).rem_euclid(TAU) - PI
}

/// The rails of a setup, in ADC codes.
fn rails(kind: RailsKind, signed: bool) -> Rails<i32> {
    match kind {
        RailsKind::Stated => Rails::of_adc_bits(12, signed).expect("12 bits"),
        RailsKind::Measured => Rails::Measured,
    }
}

/// The healthy sensor's stored calibration (fractions of full scale): a calibration a user
/// learned on the sensor before the fault, kept in the chain.
fn stored_calibration() -> SensorCalibration<f64> {
    HEALTHY_SENSOR
        .calibration()
        .expect("the healthy sensor is within the bounds")
}

/// The float chain of `sensor`: the stored calibration, the winding check and the monitor's
/// thresholds at the healthy amplitude (the calibration keeps the cosine channel's).
fn f32_tracker(sensor: SensorKind) -> Tracker<f32, Gains<f32, 3>> {
    let input = match sensor {
        SensorKind::Units => Input::Units {
            rails: Rails::Stated {
                min: -1.0,
                max: 1.0,
            },
        },
        SensorKind::Unsigned(kind) => Input::Counts {
            adc: AdcScaling::offset_binary(12).expect("12 bits"),
            rails: rails(kind, false),
        },
        SensorKind::Signed(kind) => Input::Counts {
            adc: AdcScaling::twos_complement(12).expect("12 bits"),
            rails: rails(kind, true),
        },
        SensorKind::Resolver(_) => unreachable!("the resolver's chain is resolver_run's"),
    };
    let (o_c, o_s, a_c, a_s, q) = stored_calibration().parameters();
    let calibration =
        SensorCalibration::<f32>::new(o_c as f32, o_s as f32, a_c as f32, a_s as f32, q as f32)
            .expect("the healthy calibration");
    let amplitude = HEALTHY_SENSOR.amplitude as f32;
    let settings = TrackerSettings::<f32> {
        input,
        winding: Some(WindingCheck::new(amplitude).expect("a positive amplitude")),
        calibration: CalibrationStage::Stored(calibration),
        correction: CorrectionStage::None,
    };
    let gains = Gains::<f32, 3>::new(GAINS.map(|g| g as f32), SAMPLE_PERIOD_S as f32)
        .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(amplitude)))
        .expect("the campaign's gains");
    Tracker::new(
        TrackerFrontEnd::new(settings).expect("valid settings"),
        gains,
    )
}

/// The fixed-point chain of 12-bit counts (`signed` or offset binary): the stored
/// calibration in its integers, the monitor at the healthy amplitude.
fn fixed_tracker(signed: bool, kind: RailsKind) -> Tracker<i16, FixedGains<3>> {
    let adc = if signed {
        AdcCounts::twos_complement(12)
    } else {
        AdcCounts::offset_binary(12)
    }
    .expect("12 bits");
    let (o_c, o_s, a_c, a_s, q) = stored_calibration().parameters();
    let f = FIXED_FULL_SCALE;
    let in_samples = SensorCalibration::<f64>::new(o_c * f, o_s * f, a_c * f, a_s * f, q)
        .expect("the healthy calibration");
    let settings = TrackerSettings::<i16> {
        input: Input::Counts {
            adc,
            rails: rails(kind, signed),
        },
        winding: (),
        calibration: Some(FixedCalibration::new(&in_samples).expect("within i16")),
        correction: None,
    };
    let observer = FixedGains::<3>::new(GAINS, SAMPLE_PERIOD_S)
        .and_then(|g| g.with_monitor(Some(HEALTHY_SENSOR.amplitude * f)))
        .expect("the campaign's gains");
    Tracker::new(
        TrackerFrontEnd::new(settings).expect("valid settings"),
        observer,
    )
}

/// Runs `case` on the healthy samples `(y_c, y_s)` of the true angles `theta`, the
/// injection's draws seeded with `seed`.
pub fn run_case(case: Case, theta: &[f64], y_c: &[f64], y_s: &[f64], seed: u64) -> CaseResult {
    let onset = case.onset.sample();
    let mut injector = Injector::new(case.fault, onset, case.setup.sensor, seed);
    let clip_units = case.fault == FaultKind::Clipping;
    let pairs = (0..SAMPLES.min(theta.len())).map(|k| injector.inject(k, y_c[k], y_s[k]));
    let mut result = CaseResult::new(case);
    let mut judge = |k: usize, (error, flagged): Outcome| {
        result.judge(k, (onset, START_UP), error, (flagged, false));
    };
    let latched = match (case.setup.number, case.setup.sensor) {
        (NumberType::F32, sensor) => {
            let tracker = f32_tracker(sensor);
            let mut state = TrackerState::new();
            for (k, (c, s)) in pairs.enumerate() {
                let e = match sensor {
                    SensorKind::Units => {
                        // A converter in units saturates at its range.
                        let unit = |x: f64| if clip_units { x.clamp(-1.0, 1.0) } else { x };
                        tracker.update(&mut state, (unit(c) as f32, unit(s) as f32))
                    }
                    SensorKind::Unsigned(_) => {
                        tracker.update(&mut state, (code(c, false), code(s, false)))
                    }
                    SensorKind::Signed(_) => {
                        tracker.update(&mut state, (code(c, true), code(s, true)))
                    }
                    SensorKind::Resolver(_) => unreachable!("not a pair's setup"),
                };
                let error = wrapped(f64::from(e.angle) - theta[k]);
                judge(
                    k,
                    (
                        error,
                        !e.faults.is_empty() || !state.front_end.faults().is_empty(),
                    ),
                );
                if k + 1 == START_UP {
                    state.observer.clear_faults();
                    state.front_end.clear_faults();
                }
            }
            !state.observer.latched_faults().is_empty()
                || !state.front_end.latched_faults().is_empty()
        }
        (NumberType::Fixed, sensor) => {
            let (signed, kind) = match sensor {
                SensorKind::Signed(kind) => (true, kind),
                SensorKind::Unsigned(kind) => (false, kind),
                SensorKind::Units | SensorKind::Resolver(_) => {
                    unreachable!("the fixed-point setups take counts")
                }
            };
            let tracker = fixed_tracker(signed, kind);
            let mut state = TrackerState::new();
            for (k, (c, s)) in pairs.enumerate() {
                let e = tracker.update(&mut state, (code(c, signed), code(s, signed)));
                let error = binary_angle_to_rad(e.angle.wrapping_sub(binary_angle(theta[k])));
                judge(
                    k,
                    (
                        error,
                        !e.faults.is_empty() || !state.front_end.faults().is_empty(),
                    ),
                );
                if k + 1 == START_UP {
                    state.observer.clear_faults();
                    state.front_end.clear_faults();
                }
            }
            !state.observer.latched_faults().is_empty()
                || !state.front_end.latched_faults().is_empty()
        }
        (NumberType::F64, _) => unreachable!("the resolver's chain is resolver_run's"),
    };
    result.latched = latched;
    result
}
