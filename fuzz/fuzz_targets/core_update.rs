//! Fuzzes the per-sample update: arbitrary gains, sample period, diagnostics thresholds
//! (every field of `FaultThresholds`, and the tracking-error level's rule above a noise) and
//! samples, on both float types, both orders and both sin/cos, through the online
//! calibration (arbitrary settings and stored calibration, learning or frozen) and the ADC
//! front end (arbitrary mid-scale, scale and integer samples of every type). Whatever the
//! input: no panic, and every accepted configuration keeps a finite state and calibration
//! and an angle in [-pi, pi). The fixed-point observer too (`docs/theory.md §14`): arbitrary
//! gains, sample period, monitor amplitude and roundness tolerance, and 16-bit samples; no panic (a build with
//! overflow checks would panic on any overflow), the phase error within [-1, 1] in Q15 and
//! the reciprocal tracker within its range.
#![no_main]

use angletrack_core::fixed::{MAX_RECIPROCAL, MIN_RECIPROCAL};
use angletrack_core::{
    AdcScaling, CalibrationSettings, Calibrator, Chain, ChainState, Estimate, Exact, Fast,
    FaultThresholds, FixedGains, FixedState, Gains, ObserverState, Order, Real, SensorCalibration,
    SinCos, SupportedOrder,
};
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
struct Input {
    float: bool,
    order: bool,
    fast: bool,
    gains: [f64; 3],
    sample_period_s: f64,
    thresholds: Option<Thresholds>,
    initial: Option<(f64, f64, f64)>,
    calibration: Option<Calibration>,
    adc: Option<Adc>,
    samples: Vec<(f64, f64)>,
    fixed: Option<Fixed>,
}

#[derive(Debug, Arbitrary)]
struct Fixed {
    order: bool,
    gains: [f64; 3],
    sample_period_s: f64,
    /// `Some((None, _))`: monitor off; `Some((Some(a), r))`: nominal amplitude `a` counts,
    /// roundness tolerance `r` (`None`: no roundness check).
    monitor: Option<(Option<f64>, Option<f64>)>,
    samples: Vec<(i16, i16)>,
}

#[derive(Debug, Arbitrary)]
struct Calibration {
    /// offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad.
    stored: Option<(f64, f64, f64, f64, f64)>,
    learning: bool,
    min_speed_rad_s: Option<f64>,
    max_offset: f64,
    max_amplitude_mismatch: f64,
    max_quadrature_rad: f64,
}

#[derive(Debug, Arbitrary)]
struct Adc {
    mid_scale_counts: i32,
    counts_per_unit: f64,
    /// 0: i16, 1: u16, else i32.
    sample_type: u8,
    raw: Vec<(i32, i32)>,
}

#[derive(Debug, Arbitrary)]
struct Thresholds {
    nominal_amplitude: f64,
    max_input_amplitude: f64,
    loss_of_signal: f64,
    degradation_low: f64,
    degradation_high: f64,
    loss_of_tracking: f64,
    tracking_error: f64,
    max_speed: Option<f64>,
    filter_factor: f64,
    false_lock: f64,
    magnitude_tolerance: Option<f64>,
    monitor: bool,
    re_acquire: bool,
    /// The angle noise (rad) the tracking-error level is raised above
    /// (`FaultThresholds::with_tracking_error_above_noise`), after the fields.
    noise: Option<f64>,
}

fn run<T: Real, const N: usize, S: SinCos<T>>(input: &Input)
where
    Order<N>: SupportedOrder,
{
    let mut l = [T::ZERO; N];
    for (slot, g) in l.iter_mut().zip(input.gains) {
        *slot = T::from_f64(g);
    }
    let Ok(mut gains) = Gains::<T, N, S>::new(l, T::from_f64(input.sample_period_s)) else {
        return;
    };
    if let Some(t) = &input.thresholds {
        let f = T::from_f64;
        let thresholds = FaultThresholds::for_amplitude(f(t.nominal_amplitude))
            .with_max_input_amplitude(f(t.max_input_amplitude))
            .with_loss_of_signal(f(t.loss_of_signal))
            .with_degradation_low(f(t.degradation_low))
            .with_degradation_high(f(t.degradation_high))
            .with_loss_of_tracking(f(t.loss_of_tracking))
            .with_tracking_error(f(t.tracking_error))
            .with_max_speed(t.max_speed.map(f))
            .with_filter_factor(f(t.filter_factor))
            .with_false_lock(f(t.false_lock))
            .with_magnitude_tolerance(t.magnitude_tolerance.map(f))
            .with_monitor(t.monitor)
            .with_re_acquire(t.re_acquire);
        let thresholds = match t.noise {
            Some(noise) => thresholds.with_tracking_error_above_noise(f(noise)),
            None => thresholds,
        };
        match gains.with_fault_thresholds(thresholds) {
            Ok(g) => gains = g,
            Err(_) => return,
        }
    }
    let mut calibrator = Calibrator::new();
    if let Some(c) = &input.calibration {
        let f = T::from_f64;
        let mut settings = CalibrationSettings::default();
        settings.min_speed_rad_s = c.min_speed_rad_s.map(f);
        settings.max_offset = f(c.max_offset);
        settings.max_amplitude_mismatch = f(c.max_amplitude_mismatch);
        settings.max_quadrature_rad = f(c.max_quadrature_rad);
        if let Ok(g) = gains.with_calibration_settings(settings) {
            gains = g;
        }
        if let Some((o_c, o_s, a_c, a_s, phi)) = c.stored {
            if let Ok(stored) = SensorCalibration::new(f(o_c), f(o_s), f(a_c), f(a_s), f(phi)) {
                calibrator = Calibrator::from_calibration(stored);
            }
        }
        if c.learning {
            calibrator.enable();
        }
    }
    let observer = match input.initial {
        Some((angle, speed, acceleration)) => ObserverState::at(
            T::from_f64(angle),
            T::from_f64(speed),
            T::from_f64(acceleration),
            gains.sample_period(),
        )
        // What the state cannot hold is refused: the fuzzed run starts from its first sample.
        .unwrap_or_default(),
        None => ObserverState::new(),
    };
    let learning = Chain::new(gains.online_calibration(), gains);
    let mut learnt = ChainState {
        front_end: calibrator,
        observer,
    };
    let check = |e: Estimate<T>, state: &ObserverState<T, N>, calibrator: &Calibrator<T>| {
        assert!(
            state.scaled_state().iter().all(|x| x.is_finite()),
            "{state:?}"
        );
        assert!(state.amplitude().is_finite(), "{state:?}");
        assert!(e.angle >= -T::PI && e.angle < T::PI, "{e:?}");
        assert!(e.speed.is_finite() && e.acceleration.is_finite() && e.phase_error.is_finite());
        let (o_c, o_s, a_c, a_s, phi) = calibrator.calibration().parameters();
        assert!(
            [o_c, o_s, a_c, a_s, phi].iter().all(|v| v.is_finite()),
            "{calibrator:?}"
        );
    };
    // Repeat the samples so that slow divergence would show.
    for _ in 0..4 {
        for &(y_c, y_s) in &input.samples {
            let (y_c, y_s) = (T::from_f64(y_c), T::from_f64(y_s));
            let e = learning.update(&mut learnt, (y_c, y_s));
            check(e, &learnt.observer, &learnt.front_end);
        }
    }
    let Some(adc) = &input.adc else {
        return;
    };
    let Ok(scaling) = AdcScaling::<T>::new(adc.mid_scale_counts, T::from_f64(adc.counts_per_unit))
    else {
        return;
    };
    for &(raw_c, raw_s) in &adc.raw {
        let (y_c, y_s) = match adc.sample_type {
            0 => scaling.sample(raw_c as i16, raw_s as i16),
            1 => scaling.sample(raw_c as u16, raw_s as u16),
            _ => scaling.sample(raw_c, raw_s),
        };
        let e = learning.update(&mut learnt, (y_c, y_s));
        check(e, &learnt.observer, &learnt.front_end);
        let mut chained = ChainState {
            front_end: (),
            observer: learnt.observer,
        };
        let e = Chain::new(scaling, gains).update(&mut chained, (raw_c, raw_s));
        learnt.observer = chained.observer;
        check(e, &learnt.observer, &learnt.front_end);
    }
}

fn dispatch<T: Real>(input: &Input) {
    match (input.order, input.fast) {
        (false, false) => run::<T, 2, Exact>(input),
        (false, true) => run::<T, 2, Fast>(input),
        (true, false) => run::<T, 3, Exact>(input),
        (true, true) => run::<T, 3, Fast>(input),
    }
}

/// The fixed-point observer of order `N` over the input's samples.
fn run_fixed<const N: usize>(fixed: &Fixed)
where
    Order<N>: SupportedOrder,
{
    let mut l = [0.0; N];
    l.copy_from_slice(&fixed.gains[..N]);
    let Ok(mut gains) = FixedGains::<N>::new(l, fixed.sample_period_s) else {
        return;
    };
    if let Some((amplitude, tolerance)) = fixed.monitor {
        match gains.with_monitor_tolerance(amplitude, tolerance) {
            Ok(g) => gains = g,
            Err(_) => return,
        }
    }
    // `track` (the state only) must leave exactly the state `update` leaves.
    let chain = Chain::new((), gains);
    let (mut state, mut tracked) = (
        ChainState::<(), FixedState<N>>::new(),
        ChainState::<(), FixedState<N>>::new(),
    );
    for &(c, s) in &fixed.samples {
        let e = chain.update(&mut state, (c, s));
        chain.track(&mut tracked, (c, s));
        assert_eq!(chain.estimate(&tracked), e);
        assert!(e.phase_error.abs() <= 1 << 15, "{e:?}");
        assert!((MIN_RECIPROCAL..=MAX_RECIPROCAL).contains(&state.observer.reciprocal()));
    }
}

fuzz_target!(|input: Input| {
    if let Some(fixed) = &input.fixed {
        if fixed.order {
            run_fixed::<3>(fixed);
        } else {
            run_fixed::<2>(fixed);
        }
    }
    if input.float {
        dispatch::<f32>(&input)
    } else {
        dispatch::<f64>(&input)
    }
});
