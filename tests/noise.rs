//! The noise predictions of the design report checked by simulation over 10^6 samples:
//! the RMS errors of the discrete Lyapunov equation (`docs/theory.md §8`), and the Kalman
//! floor `sqrt(P11)` (`§4`).

use angletrack::paper::{POLE_FREQUENCY_RATIO, POLE_RATIO};
use angletrack::{
    Chain, ChainState, DesignReport, Discretisation, Gains, Metrics, MetricsOptions, Motion,
    MotionProfile, Scenario, SensorModel, kalman, predicted_error, run,
    second_order_from_bandwidth, third_order_from_poles,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const SAMPLES: usize = 1_000_000;
const TS: f64 = 1e-4;
const SIGMA: f64 = 0.02;

/// A shaft at 150 rad/s seen through a sensor with white noise `SIGMA`, 10^6 samples.
fn constant_speed() -> Scenario {
    let profile = MotionProfile::new(0.2, 150.0).then(Motion::ConstantSpeed {
        speed_rad_s: 150.0,
        duration_s: (SAMPLES - 1) as f64 * TS,
    });
    let scenario = Scenario::generate(&profile, &SensorModel::with_noise(SIGMA), TS, 2026).unwrap();
    assert_eq!(scenario.len(), SAMPLES);
    scenario
}

/// Skip the first 0.5 s (the loops settle in a few tens of ms).
fn measured(scenario: &Scenario, estimates: &angletrack::Run) -> Metrics {
    let options = MetricsOptions {
        skip_s: 0.5,
        ..MetricsOptions::default()
    };
    Metrics::new(scenario, estimates, &options).unwrap()
}

fn within_5_percent(what: &str, simulated: f64, predicted: f64) {
    let ratio = simulated / predicted;
    println!("{what}: simulated {simulated:.6e}, predicted {predicted:.6e}, ratio {ratio:.4}");
    assert!(
        (ratio - 1.0).abs() < 0.05,
        "{what}: simulated {simulated:e}, predicted {predicted:e}"
    );
}

#[test]
fn predicted_rms_errors_match_simulation_over_a_million_samples() {
    let scenario = constant_speed();
    let second = second_order_from_bandwidth(80.0, 0.8, TS, Discretisation::PoleMatching).unwrap();
    let third = third_order_from_poles(
        POLE_RATIO,
        0.01,
        POLE_FREQUENCY_RATIO,
        TS,
        Discretisation::Tustin,
    )
    .unwrap();
    let optimal = kalman(1e-12, SIGMA * SIGMA, TS).unwrap();

    let r2 = DesignReport::new(&second, SIGMA).unwrap();
    let m2 = measured(&scenario, &run(&second.gains, &scenario));
    within_5_percent(
        "2nd order angle",
        m2.angle_error_rad.rms,
        r2.angle_error_rms_rad,
    );
    within_5_percent(
        "2nd order speed",
        m2.speed_error_rad_s.rms,
        r2.speed_error_rms_rad_s,
    );

    let r3 = DesignReport::new(&third, SIGMA).unwrap();
    let m3 = measured(&scenario, &run(&third.gains, &scenario));
    within_5_percent(
        "3rd order angle",
        m3.angle_error_rad.rms,
        r3.angle_error_rms_rad,
    );
    within_5_percent(
        "3rd order speed",
        m3.speed_error_rad_s.rms,
        r3.speed_error_rms_rad_s,
    );

    // The firmware's arithmetic: f32 with the fast sin/cos adds nothing visible at this noise.
    let rk = DesignReport::new(&optimal, SIGMA).unwrap();
    let single: Gains<f32, 3> = optimal.to_gains().unwrap();
    let mk = measured(&scenario, &run(&single, &scenario));
    within_5_percent(
        "Kalman f32 angle",
        mk.angle_error_rad.rms,
        rk.angle_error_rms_rad,
    );
    within_5_percent(
        "Kalman f32 speed",
        mk.speed_error_rad_s.rms,
        rk.speed_error_rms_rad_s,
    );
    // No bias at constant speed.
    assert!(mk.angle_error_rad.mean.abs() < 0.05 * mk.angle_error_rad.rms);
}

#[test]
fn kalman_ato_reaches_its_floor_on_the_model_it_was_designed_for() {
    // The shaft of the Kalman model: a random jerk, X[k+1] = A3 X[k] + G v[k], var(v) = q.
    let (q, r) = (1e-20, SIGMA * SIGMA);
    let design = kalman(q, r, TS).unwrap();
    let floor = design.kalman.unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let jerk = Normal::new(0.0, q.sqrt()).unwrap();
    let noise = Normal::new(0.0, SIGMA).unwrap();
    let mut x = [0.3, 0.01, 0.0]; // scaled: (theta, Ts Omega, Ts^2 alpha)
    let chain = Chain::new((), design.gains);
    let mut state = ChainState::new();
    let (mut sum_angle, mut sum_speed, mut count) = (0.0, 0.0, 0usize);
    for k in 0..SAMPLES {
        let v = jerk.sample(&mut rng);
        x = [
            x[0] + x[1] + 0.5 * x[2] + v / 6.0,
            x[1] + x[2] + 0.5 * v,
            x[2] + v,
        ];
        let y_c = x[0].cos() + noise.sample(&mut rng);
        let y_s = x[0].sin() + noise.sample(&mut rng);
        let e = chain.update(&mut state, (y_c, y_s));
        if k >= 20_000 {
            let angle_error = x[0] - e.position();
            sum_angle += angle_error * angle_error;
            sum_speed += (x[1] / TS - e.speed).powi(2);
            count += 1;
        }
        assert!(
            x[1].abs() < 1.0,
            "the shaft must stay below 1 rad per sample"
        );
    }
    let angle_rms = (sum_angle / count as f64).sqrt();
    let speed_rms = (sum_speed / count as f64).sqrt();
    within_5_percent(
        "Kalman angle vs sqrt(P11)",
        angle_rms,
        floor.angle_floor_rad(),
    );
    within_5_percent(
        "Kalman speed vs sqrt(P22)/Ts",
        speed_rms,
        floor.speed_floor_rad_s(TS),
    );
    // The same figure through the generic prediction with process noise.
    let predicted = predicted_error(&design.gains, SIGMA, q).unwrap();
    assert!((predicted.angle_rms_rad / floor.angle_floor_rad() - 1.0).abs() < 1e-6);
}
