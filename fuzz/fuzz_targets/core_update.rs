//! Fuzzes the per-sample update: arbitrary gains, sample period, diagnostics thresholds and
//! samples, on both float types, both orders and both sin/cos. Whatever the input: no panic,
//! and every accepted configuration keeps a finite state and an angle in [-pi, pi).
#![no_main]

use angletrack_core::{
    Exact, Fast, FaultThresholds, Gains, ObserverState, Order, Real, SinCos, SupportedOrder,
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
    samples: Vec<(f64, f64)>,
}

#[derive(Debug, Arbitrary)]
struct Thresholds {
    nominal_amplitude: f64,
    max_input_amplitude: f64,
    loss_of_signal: f64,
    degradation_low: f64,
    degradation_high: f64,
    loss_of_tracking: f64,
    max_speed: Option<f64>,
    filter_factor: f64,
    false_lock: f64,
    monitor: bool,
    re_acquire: bool,
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
        let thresholds = FaultThresholds {
            nominal_amplitude: f(t.nominal_amplitude),
            max_input_amplitude: f(t.max_input_amplitude),
            loss_of_signal: f(t.loss_of_signal),
            degradation_low: f(t.degradation_low),
            degradation_high: f(t.degradation_high),
            loss_of_tracking: f(t.loss_of_tracking),
            max_speed: t.max_speed.map(f),
            filter_factor: f(t.filter_factor),
            false_lock: f(t.false_lock),
            monitor: t.monitor,
            re_acquire: t.re_acquire,
        };
        match gains.with_fault_thresholds(thresholds) {
            Ok(g) => gains = g,
            Err(_) => return,
        }
    }
    let mut state = match input.initial {
        Some((angle, speed, acceleration)) => ObserverState::at(
            T::from_f64(angle),
            T::from_f64(speed),
            T::from_f64(acceleration),
            gains.sample_period(),
        ),
        None => ObserverState::new(),
    };
    // Repeat the samples so that slow divergence would show.
    for _ in 0..4 {
        for &(y_c, y_s) in &input.samples {
            let e = gains.update(&mut state, T::from_f64(y_c), T::from_f64(y_s));
            assert!(
                state.scaled_state().iter().all(|x| x.is_finite()),
                "{state:?}"
            );
            assert!(e.angle >= -T::PI && e.angle < T::PI, "{e:?}");
            assert!(e.speed.is_finite() && e.acceleration.is_finite() && e.phase_error.is_finite());
        }
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

fuzz_target!(|input: Input| {
    if input.float {
        dispatch::<f32>(&input)
    } else {
        dispatch::<f64>(&input)
    }
});
