//! One run of a study: one simulated sensor through one motion profile and one setup, and
//! the row of its results.

use std::time::Instant;

use angletrack_core::{
    AngleCorrection, CalibrationSettings, CalibrationStage, Calibrator, CorrectionStage, Exact,
    Fast, FaultThresholds, FixedGains, Float, Gains, Input, ObserverState, Order, Rails, Real,
    SensorCalibration, SinCos, SupportedOrder, Tracker, TrackerFrontEnd, TrackerSettings,
    TrackerState, WindingCheck,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::row::{Errors, StudyRow};
use super::spec::Spec;
use crate::tracker_file::{
    AdcRange, Calibration, Correction, Input as TrackerInput, NumberType, SinCosKind, TrackerFile,
};
use crate::{Scenario, capture_fault_thresholds, fixed_front_end, fixed_input};

/// SplitMix64's finaliser: a seed from the study's seed and a run's indices, well mixed so
/// that neighbouring indices give unrelated generators.
fn derived_seed(seed: u64, parts: &[u64]) -> u64 {
    parts.iter().fold(seed, |acc, &part| {
        let mut z = acc
            ^ part
                .wrapping_add(0x9e37_79b9_7f4a_7c15)
                .wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    })
}

/// The row of run `run` of `spec`.
pub(super) fn run(spec: &Spec, run: u64) -> StudyRow {
    let started = Instant::now();
    let (profiles, setups) = (spec.profiles.len() as u64, spec.setups.len() as u64);
    let sensor = run / (profiles * setups);
    let profile = (run / setups) % profiles;
    let setup = run % setups;
    let mut rng = ChaCha8Rng::seed_from_u64(derived_seed(spec.seed, &[sensor, 0]));
    let drawn = spec.sensor.draw(&mut rng);
    let (profile_name, motion) = &spec.profiles[profile as usize];
    let (setup_name, tracker) = &spec.setups[setup as usize];
    let mut row = StudyRow {
        run,
        sensor,
        profile: profile_name.clone(),
        setup: setup_name.clone(),
        number_type: tracker.number_type.name(),
        parameters: drawn.parameters,
        angle_error_harmonics: drawn.harmonics.clone(),
        samples: 0,
        rms_error_rad: f64::NAN,
        max_error_rad: f64::NAN,
        mean_error_rad: f64::NAN,
        time_to_lock_s: f64::NAN,
        fault_samples: 0,
        faults: String::new(),
        learned: [f64::NAN; 5],
        seconds: 0.0,
        error: None,
    };
    if run >= spec.runs() {
        row.error = Some(format!(
            "run: {run} is beyond the study's {} runs",
            spec.runs()
        ));
        return row;
    }
    let model = spec.sensor.model(&drawn);
    let noise_seed = derived_seed(spec.seed, &[sensor, 1 + profile]);
    let outcome = Scenario::generate(motion, &model, spec.sample_period_s, noise_seed)
        .map_err(|e| format!("sensor: {e}"))
        .and_then(|scenario| track(spec, tracker, &scenario, &mut row));
    if let Err(e) = outcome {
        row.error = Some(e);
    }
    row.seconds = started.elapsed().as_secs_f64();
    row
}

/// Tracks `scenario` with `tracker` (dispatched on its number type, order and sin/cos),
/// filling `row`'s results.
fn track(
    spec: &Spec,
    tracker: &TrackerFile,
    scenario: &Scenario,
    row: &mut StudyRow,
) -> Result<(), String> {
    let exact = match tracker.sin_cos {
        SinCosKind::Default => tracker.number_type == NumberType::F64,
        kind => kind == SinCosKind::Exact,
    };
    match (tracker.number_type, tracker.gains.gains.len(), exact) {
        (NumberType::Fixed, 2, _) => track_fixed::<2>(spec, tracker, scenario, row),
        (NumberType::Fixed, _, _) => track_fixed::<3>(spec, tracker, scenario, row),
        (NumberType::F32, 2, false) => track_with::<f32, 2, Fast>(spec, tracker, scenario, row),
        (NumberType::F32, 2, true) => track_with::<f32, 2, Exact>(spec, tracker, scenario, row),
        (NumberType::F32, _, false) => track_with::<f32, 3, Fast>(spec, tracker, scenario, row),
        (NumberType::F32, _, true) => track_with::<f32, 3, Exact>(spec, tracker, scenario, row),
        (_, 2, false) => track_with::<f64, 2, Fast>(spec, tracker, scenario, row),
        (_, 2, true) => track_with::<f64, 2, Exact>(spec, tracker, scenario, row),
        (_, _, false) => track_with::<f64, 3, Fast>(spec, tracker, scenario, row),
        (_, _, true) => track_with::<f64, 3, Exact>(spec, tracker, scenario, row),
    }
}

fn typed<T: Float + Real>(c: &SensorCalibration<f64>) -> Result<SensorCalibration<T>, String> {
    let (o_c, o_s, a_c, a_s, phi) = c.parameters();
    SensorCalibration::new(
        T::from_f64(o_c),
        T::from_f64(o_s),
        T::from_f64(a_c),
        T::from_f64(a_s),
        T::from_f64(phi),
    )
    .map_err(|e| format!("calibration: {e}"))
}

fn typed_thresholds<T: Float + Real>(t: &FaultThresholds<f64>) -> FaultThresholds<T> {
    FaultThresholds::for_amplitude(T::from_f64(t.nominal_amplitude))
        .with_max_input_amplitude(T::from_f64(t.max_input_amplitude))
        .with_loss_of_signal(T::from_f64(t.loss_of_signal))
        .with_degradation_low(T::from_f64(t.degradation_low))
        .with_degradation_high(T::from_f64(t.degradation_high))
        .with_loss_of_tracking(T::from_f64(t.loss_of_tracking))
        .with_max_speed(t.max_speed.map(T::from_f64))
        .with_filter_factor(T::from_f64(t.filter_factor))
        .with_false_lock(T::from_f64(t.false_lock))
        .with_monitor(t.monitor)
        .with_re_acquire(t.re_acquire)
}

fn typed_settings<T: Float + Real>(s: &CalibrationSettings<f64>) -> CalibrationSettings<T> {
    let mut out = CalibrationSettings::default();
    out.min_speed_rad_s = s.min_speed_rad_s.map(T::from_f64);
    out.max_offset = T::from_f64(s.max_offset);
    out.max_amplitude_mismatch = T::from_f64(s.max_amplitude_mismatch);
    out.max_quadrature_rad = T::from_f64(s.max_quadrature_rad);
    out
}

/// The standard chain of `tracker` in `T`, order `N`, sin/cos `S`, over `scenario`.
fn track_with<T: Float + Real, const N: usize, S: SinCos<T>>(
    spec: &Spec,
    tracker: &TrackerFile,
    scenario: &Scenario,
    row: &mut StudyRow,
) -> Result<(), String>
where
    Order<N>: SupportedOrder,
{
    let file = &tracker.gains;
    let mut values = [T::ZERO; N];
    for (slot, &g) in values.iter_mut().zip(&file.gains) {
        *slot = T::from_f64(g);
    }
    let thresholds = match &tracker.fault_thresholds {
        Some(t) => typed_thresholds(t),
        None => typed_thresholds(&capture_fault_thresholds(&scenario.y_c, &scenario.y_s)),
    };
    let mut gains = Gains::<T, N>::new(values, T::from_f64(file.sample_period_s))
        .and_then(|g| g.with_fault_thresholds(thresholds))
        .map_err(|e| format!("gains: {e}"))?
        .with_sin_cos::<S>();
    let mut calibrator = Calibrator::new();
    let calibration = match &tracker.calibration {
        Calibration::None => CalibrationStage::None,
        Calibration::Stored(c) => CalibrationStage::Stored(typed(c)?),
        Calibration::Online { initial, settings } => {
            gains = gains
                .with_calibration_settings(typed_settings(settings))
                .map_err(|e| format!("calibration: {e}"))?;
            if let Some(c) = initial {
                calibrator = Calibrator::from_calibration(typed(c)?);
            }
            calibrator.enable();
            CalibrationStage::Online(gains.online_calibration())
        }
    };
    let correction = match &tracker.correction {
        Correction::Harmonics(h) => {
            let (cos, sin) = h.coefficients();
            CorrectionStage::Harmonics(
                AngleCorrection::new(cos.map(T::from_f64), sin.map(T::from_f64))
                    .map_err(|e| format!("correction: {e}"))?,
            )
        }
        _ => CorrectionStage::None,
    };
    let rails = match tracker.adc_range {
        AdcRange::Stated { min, max } => Rails::Stated {
            min: T::from_f64(min),
            max: T::from_f64(max),
        },
        _ => Rails::Measured,
    };
    let winding = tracker
        .winding_amplitude
        .map(|a| WindingCheck::new(T::from_f64(a)))
        .transpose()
        .map_err(|e| format!("winding_check: {e}"))?;
    let front_end = TrackerFrontEnd::new(TrackerSettings {
        input: Input::Units { rails },
        winding,
        calibration,
        correction,
    })
    .map_err(|e| format!("adc_range: {e}"))?;
    let chain: Tracker<T, Gains<T, N, S>> = Tracker::new(front_end, gains);
    let mut state: TrackerState<T, ObserverState<T, N>> = TrackerState::new();
    *state.front_end.calibrator_mut() = calibrator;
    let mut errors = Errors::new(spec, scenario, row)?;
    for (k, ((&c, &s), &truth)) in scenario
        .y_c
        .iter()
        .zip(&scenario.y_s)
        .zip(&scenario.angle_rad)
        .enumerate()
    {
        let e = chain.update(&mut state, (T::from_f64(c), T::from_f64(s)));
        errors.add(k, truth - e.angle.to_f64(), e.faults);
    }
    errors.write(row);
    if matches!(tracker.calibration, Calibration::Online { .. }) {
        let (o_c, o_s, a_c, a_s, phi) = state.front_end.calibrator().calibration().parameters();
        row.learned = [o_c, o_s, a_c, a_s, phi].map(T::to_f64);
    }
    Ok(())
}

/// The fixed-point chain of `tracker` (order `N`) over `scenario`, its samples the sensor's
/// ADC codes (the study's `adc_bits`, the tracker's `input.bits`) as int16 counts.
fn track_fixed<const N: usize>(
    spec: &Spec,
    tracker: &TrackerFile,
    scenario: &Scenario,
    row: &mut StudyRow,
) -> Result<(), String>
where
    Order<N>: SupportedOrder,
{
    let TrackerInput::Bits { bits, signed } = tracker.input else {
        return Err("input: the fixed-point chain takes the ADC's counts: give input.bits".into());
    };
    let lsb = 2.0 * spec.sensor.adc_full_scale / f64::from(bits).exp2();
    let mid = if signed { 0 } else { 1_i32 << (bits - 1) };
    // The sensor model rounds to its ADC's grid and saturates there: its codes fit.
    let code = |y: f64| ((y / lsb).round() as i32 + mid) as i16;
    let head = scenario.len().min(crate::NOMINAL_AMPLITUDE_SAMPLES);
    let counts =
        |y: &[f64]| -> Vec<f64> { y[..head].iter().map(|&v| f64::from(code(v))).collect() };
    let input = fixed_input(&counts(&scenario.y_c), &counts(&scenario.y_s), mid as u64)
        .map_err(|e| format!("input: {e}"))?;
    let sensor = match &tracker.calibration {
        Calibration::Stored(c) => Some(*c),
        _ => None,
    };
    let correction = match &tracker.correction {
        Correction::Harmonics(h) => Some(*h),
        _ => None,
    };
    let rails = match tracker.adc_range {
        AdcRange::FullScale => {
            Rails::of_adc_bits(bits, signed).map_err(|e| format!("adc_range: {e}"))?
        }
        AdcRange::Stated { min, max } => Rails::Stated {
            min: min as i32,
            max: max as i32,
        },
        AdcRange::Measured => Rails::Measured,
    };
    let front_end = fixed_front_end(
        mid,
        input.shift,
        sensor.as_ref(),
        correction.as_ref(),
        rails,
    )
    .map_err(|e| format!("calibration: {e}"))?;
    let mut values = [0.0; N];
    values.copy_from_slice(&tracker.gains.gains[..N]);
    let gains = FixedGains::<N>::new(values, tracker.gains.sample_period_s)
        .and_then(|g| {
            g.with_monitor_tolerance(Some(input.monitor_amplitude), input.magnitude_tolerance)
        })
        .map_err(|e| format!("gains: {e}"))?;
    let chain = Tracker::new(front_end, gains);
    let mut state = TrackerState::new();
    let mut errors = Errors::new(spec, scenario, row)?;
    for (k, ((&c, &s), &truth)) in scenario
        .y_c
        .iter()
        .zip(&scenario.y_s)
        .zip(&scenario.angle_rad)
        .enumerate()
    {
        let e = chain.update(&mut state, (code(c), code(s)));
        errors.add(k, truth - chain.observer.position_rad(&e), e.faults);
    }
    errors.write(row);
    Ok(())
}
