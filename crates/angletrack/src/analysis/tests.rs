//! Unit tests of the analysis: steady-state errors, the report, noise on the Kalman model
//! (`docs/theory.md §8`) and the speed limits (`§9`).

use std::f64::consts::PI;

use angletrack_core::{Chain, ChainState, Gains, ObserverState};

use crate::*;

const PM: Discretisation = Discretisation::PoleMatching;

#[test]
fn error_per_unit_jerk_matches_a_simulation_of_the_core() {
    let ts = 1e-4;
    let design = third_order_from_poles(10.0, 0.01, 2.0, ts, PM).unwrap();
    let report = DesignReport::new(&design, 0.0).unwrap();
    let jerk = 50.0; // rad/s^3
    let mut state = ChainState {
        front_end: (),
        observer: ObserverState::at(0.0, 0.0, 0.0, ts).unwrap(),
    };
    let mut error = 0.0;
    for k in 0..40_000 {
        let t = k as f64 * ts;
        let theta = jerk * t * t * t / 6.0;
        let e = Chain::new((), design.gains).update(&mut state, (theta.cos(), theta.sin()));
        error = theta - e.position();
    }
    // sin(e) ~ e: the small error makes the nonlinear loop linear to 1e-6.
    let predicted = jerk * report.error_per_unit_jerk_s3.unwrap();
    assert!(
        (error / predicted - 1.0).abs() < 1e-4,
        "{error} vs {predicted}"
    );
    // The discrete figure tends to the continuous 1/k_c2 as the sample rate grows.
    let gap = |ts: f64| {
        let design = third_order_from_poles(10.0, 0.01, 2.0, ts, PM).unwrap();
        let report = DesignReport::new(&design, 0.0).unwrap();
        let continuous = report.continuous_error_per_unit_jerk_s3.unwrap();
        (continuous / report.error_per_unit_jerk_s3.unwrap() - 1.0).abs()
    };
    let (coarse, fine) = (gap(1e-4), gap(1e-6));
    assert!(
        fine < 0.01 * coarse.max(1e-300) + 2e-3,
        "{coarse} -> {fine}"
    );
    assert!(fine < 2e-3);
}

#[test]
fn report_renders_every_figure() {
    let design = kalman(1e-10, 1e-4, 1e-4).unwrap();
    let report = DesignReport::new(&design, 0.01).unwrap();
    let text = report.to_string();
    for needle in [
        "steady-state Kalman",
        "pole 3 z",
        "-3 dB bandwidth",
        "error per unit jerk",
        "Kalman floor",
        "linear step",
        "179 degree step",
        "max trackable speed",
        "acquired from rest",
    ] {
        assert!(text.contains(needle), "missing {needle} in\n{text}");
    }
    assert_eq!(report.max_speed_rad_s, PI / 1e-4);
    assert!(report.acquisition_speed_rad_s > 0.0);
    assert!(report.acquisition_speed_rad_s < report.max_speed_rad_s);
    assert!(matches!(
        DesignReport::new(&design, -1.0),
        Err(Error::OutOfRange {
            argument: Argument::SensorNoiseStd,
            ..
        })
    ));
}

#[test]
fn acquisition_speed_separates_lock_from_cycle_slip() {
    let ts = 1e-4;
    let design = second_order_from_bandwidth(100.0, 1.0, ts, PM).unwrap();
    let report = DesignReport::new(&design, 0.0).unwrap();
    let speed = report.acquisition_speed_rad_s;
    // The bare loop of the paper, as the report simulates it.
    let bare = design
        .gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    let final_error = |speed: f64| {
        let mut state = ChainState {
            front_end: (),
            observer: ObserverState::at(0.0, 0.0, 0.0, ts).unwrap(),
        };
        let mut error = 0.0;
        for k in 0..20_000 {
            let theta = speed * ts * k as f64;
            error = theta
                - Chain::new((), bare)
                    .update(&mut state, (theta.cos(), theta.sin()))
                    .position();
        }
        error
    };
    assert!(final_error(0.98 * speed).abs() < 0.1);
    assert!(
        final_error(1.02 * speed).abs() > 1.0,
        "a cycle is slipped above"
    );
}

/// The largest unwrapped angle error (rad) of `gains` (with their default diagnostics, as
/// in the firmware) over a shaft at rest brought at `acceleration` rad/s^2 up to `speed`
/// rad/s, then held there for 0.1 s; with `acceleration` 0, a shaft and an observer both
/// started at `speed`.
fn worst_error_up_to<const N: usize>(gains: &Gains<f64, N>, speed: f64, acceleration: f64) -> f64 {
    let ts = gains.sample_period();
    let ramp_s = if acceleration > 0.0 {
        speed / acceleration
    } else {
        0.0
    };
    let start_speed = if acceleration > 0.0 { 0.0 } else { speed };
    let mut state = ChainState {
        front_end: (),
        observer: ObserverState::at(0.0, start_speed, 0.0, ts).unwrap(),
    };
    let samples = ((ramp_s + 0.1) / ts) as usize;
    // The state is the one of the sample before the first: the shaft starts one sample on.
    let angle = |t: f64| {
        let ramp = t.min(ramp_s);
        start_speed * t + 0.5 * acceleration * ramp * ramp + acceleration * ramp_s * (t - ramp)
    };
    (1..=samples)
        .map(|k| {
            let theta = angle(k as f64 * ts);
            (theta
                - Chain::new((), *gains)
                    .update(&mut state, (theta.cos(), theta.sin()))
                    .position())
            .abs()
        })
        .fold(0.0, f64::max)
}

/// `docs/theory.md §9`: every compared observer tracks up to the documented limit without a
/// cycle slip, started there or ramped up to it, and a locked loop keeps following beyond it.
#[test]
fn observers_track_up_to_the_documented_speed_limit_without_a_cycle_slip() {
    use crate::paper::ComparedObserver;
    let check = |name: &str, worst: [f64; 3]| {
        let [started, ramped, beyond] = worst;
        assert!(
            started < 1e-6,
            "{name} started below the limit: {started} rad"
        );
        assert!(ramped < 0.1, "{name} ramped below the limit: {ramped} rad");
        assert!(beyond < 0.1, "{name} ramped beyond the limit: {beyond} rad");
    };
    for observer in ComparedObserver::ALL {
        let design = observer.design().unwrap();
        let limit = max_trackable_speed_rad_s(design.sample_period()).unwrap();
        assert_eq!(design.report(0.0).unwrap().max_speed_rad_s, limit);
        let speeds = [(0.99 * limit, 0.0), (0.99 * limit, 2e3), (2.5 * limit, 2e3)];
        let worst = match &design {
            AnyDesign::Second(d) => speeds.map(|(v, a)| worst_error_up_to(&d.gains, v, a)),
            AnyDesign::Third(d) => speeds.map(|(v, a)| worst_error_up_to(&d.gains, v, a)),
        };
        check(observer.name(), worst);
    }
}

#[test]
fn observers_compare_with_the_kalman_floor_on_its_own_model() {
    use crate::paper::ComparedObserver;
    let designs = ComparedObserver::ALL.map(|o| o.design().unwrap());
    let AnyDesign::Third(optimal) = &designs[2] else {
        panic!("the Kalman ATO is 3rd order")
    };
    let solution = optimal.kalman.unwrap();
    let (sigma, q) = (
        solution.measurement_noise_r.sqrt(),
        solution.process_noise_q,
    );
    let floor = solution.angle_floor_rad();
    let own = predicted_error_on_kalman_model(&optimal.gains, sigma, q)
        .unwrap()
        .unwrap();
    assert!((own.angle_rms_rad / floor - 1.0).abs() < 1e-8);
    // Sensor noise alone is below the floor, which adds the random jerk.
    let report = DesignReport::new(optimal, sigma).unwrap();
    assert!(report.angle_error_rms_rad < floor);
    assert_eq!(report.kalman_angle_floor_rad, Some(floor));
    let AnyDesign::Third(third) = &designs[1] else {
        panic!("the 3rd-order ATO is 3rd order")
    };
    let third = predicted_error_on_kalman_model(&third.gains, sigma, q)
        .unwrap()
        .unwrap();
    assert!(
        third.angle_rms_rad > floor,
        "{} vs {floor}",
        third.angle_rms_rad
    );
    let AnyDesign::Second(second) = &designs[0] else {
        panic!("the 2nd-order ATO is 2nd order")
    };
    assert_eq!(
        predicted_error_on_kalman_model(&second.gains, sigma, q),
        Ok(None)
    );
    let without_jerk = predicted_error_on_kalman_model(&second.gains, sigma, 0.0).unwrap();
    assert_eq!(
        without_jerk,
        Some(predicted_error(&second.gains, sigma, 0.0).unwrap())
    );
}
