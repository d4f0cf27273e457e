//! Unit tests of the analysis: steady-state errors, the report, the acquisition speed.

use std::f64::consts::PI;

use angletrack_core::ObserverState;

use crate::*;

const PM: Discretisation = Discretisation::PoleMatching;

#[test]
fn error_per_unit_jerk_matches_a_simulation_of_the_core() {
    let ts = 1e-4;
    let design = third_order_from_poles(10.0, 0.01, 2.0, ts, PM).unwrap();
    let report = DesignReport::new(&design, 0.0).unwrap();
    let jerk = 50.0; // rad/s^3
    let mut state = ObserverState::at(0.0, 0.0, 0.0, ts);
    let mut error = 0.0;
    for k in 0..40_000 {
        let t = k as f64 * ts;
        let theta = jerk * t * t * t / 6.0;
        let e = design.gains.update(&mut state, theta.cos(), theta.sin());
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
        "max speed",
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
        let mut state = ObserverState::at(0.0, 0.0, 0.0, ts);
        let mut error = 0.0;
        for k in 0..20_000 {
            let theta = speed * ts * k as f64;
            error = theta - bare.update(&mut state, theta.cos(), theta.sin()).position();
        }
        error
    };
    assert!(final_error(0.98 * speed).abs() < 0.1);
    assert!(
        final_error(1.02 * speed).abs() > 1.0,
        "a cycle is slipped above"
    );
}
