//! Fuzzes the design functions with arbitrary arguments: each returns a design or a typed
//! error, never panics; every design converts to f32 and f64 gains the core accepts, its
//! report (simulations included) is finite where it says it is, and the observer it
//! configures keeps a finite state on a short run with a DC offset and imbalance.
#![no_main]

use angletrack::{
    Design, DesignReport, Discretisation, kalman, kalman_from_jerk_density, kalman_from_jerk_std,
    second_order_butterworth, second_order_from_bandwidth, second_order_from_tracking_error,
    third_order_butterworth, third_order_from_overshoot, third_order_from_poles,
};
use angletrack_core::{Chain, ChainState, Order, SupportedOrder};
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Call {
    SecondFromTrackingError(f64, f64, f64),
    SecondFromBandwidth(f64, f64),
    SecondButterworth(f64),
    ThirdFromPoles(f64, f64, f64),
    ThirdButterworth(f64),
    ThirdFromOvershoot(f64, f64, f64),
    Kalman(f64, f64),
    KalmanFromJerkStd(f64, f64),
    KalmanFromJerkDensity(f64, f64),
}

#[derive(Debug, Arbitrary)]
struct Input {
    call: Call,
    sample_period_s: f64,
    discretisation: u8,
    report: bool,
    noise: f64,
}

fn check<const N: usize>(design: Design<N>, input: &Input)
where
    Order<N>: SupportedOrder,
{
    let gains = design
        .to_gains::<f64>()
        .expect("a design's own gains are valid");
    let _ = design.to_gains::<f32>(); // may be refused (f32 range), never panics
    let chain = Chain::new((), gains);
    let mut state = ChainState::new();
    for k in 0..256 {
        let theta = 0.01 * k as f64;
        let e = chain.update(&mut state, (theta.cos() + 0.1, theta.sin() * 0.9));
        let x = state.observer.scaled_state();
        assert!(x.iter().all(|x| x.is_finite()) && e.speed.is_finite());
    }
    // Reports simulate the loop for its settling horizon: only for loops that settle in
    // a bounded number of samples, so that the fuzzer keeps its pace.
    let bandwidth_samples = 1.0 / (gains.gains()[N - 1].abs().powf(1.0 / N as f64));
    if input.report && bandwidth_samples < 2_000.0 {
        if let Ok(report) = DesignReport::new(&design, input.noise) {
            assert!(report.gains.iter().all(|g| g.is_finite()));
            assert!(
                report.discrete_poles.iter().all(|z| z.norm() < 1.0),
                "{report}"
            );
            let _ = format!("{report}");
        }
    }
}

fuzz_target!(|input: Input| {
    let ts = input.sample_period_s;
    let d = match input.discretisation % 3 {
        0 => Discretisation::PoleMatching,
        1 => Discretisation::ForwardEuler,
        _ => Discretisation::Tustin,
    };
    match input.call {
        Call::SecondFromTrackingError(e, a, m) => {
            if let Ok(x) = second_order_from_tracking_error(e, a, m, ts, d) {
                check(x, &input)
            }
        }
        Call::SecondFromBandwidth(b, m) => {
            if let Ok(x) = second_order_from_bandwidth(b, m, ts, d) {
                check(x, &input)
            }
        }
        Call::SecondButterworth(tc) => {
            if let Ok(x) = second_order_butterworth(tc, ts, d) {
                check(x, &input)
            }
        }
        Call::ThirdFromPoles(k, t, psi) => {
            if let Ok(x) = third_order_from_poles(k, t, psi, ts, d) {
                check(x, &input)
            }
        }
        Call::ThirdButterworth(tc) => {
            if let Ok(x) = third_order_butterworth(tc, ts, d) {
                check(x, &input)
            }
        }
        Call::ThirdFromOvershoot(o, s, psi) => {
            if let Ok(x) = third_order_from_overshoot(o, s, psi, ts, d) {
                check(x, &input)
            }
        }
        Call::Kalman(q, r) => {
            if let Ok(x) = kalman(q, r, ts) {
                check(x, &input)
            }
        }
        Call::KalmanFromJerkStd(j, s) => {
            if let Ok(x) = kalman_from_jerk_std(j, s, ts) {
                check(x, &input)
            }
        }
        Call::KalmanFromJerkDensity(j, s) => {
            if let Ok(x) = kalman_from_jerk_density(j, s, ts) {
                check(x, &input)
            }
        }
    }
});
