//! The figures of Auger, Mansouri-Toudert and Chibah, *Design of advanced resolver-to-digital
//! converters* (2011), reproduced through the `angletrack` API: the designs of
//! `docs/theory.md §2` and `§3`, the Kalman ATO of `§4`.

use angletrack::paper::{BUTTERWORTH_DAMPING, FIVE_PERCENT_DAMPING, PaperSetting};
use angletrack::{
    AnyDesign, Chain, ChainState, DesignReport, Discretisation, Gains, Metrics, MetricsOptions,
    Motion, MotionProfile, Scenario, SensorModel, kalman_from_jerk_std, run,
    second_order_butterworth, second_order_from_tracking_error,
};
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

const PM: Discretisation = Discretisation::PoleMatching;

/// Sample rate over closed-loop -3 dB bandwidth for the overshoot figures (at least 200).
const RATIO: f64 = 400.0;

/// The sample period that puts the sample rate at `ratio` times the closed-loop -3 dB
/// bandwidth of `design(ts)` (iterated: the discrete bandwidth depends a little on `ts`).
fn period_for_ratio(ratio: f64, design: impl Fn(f64) -> AnyDesign) -> (f64, DesignReport) {
    let mut ts = 1e-6;
    for _ in 0..3 {
        let report = design(ts).report(0.0).unwrap();
        ts = 1.0 / (ratio * report.bandwidth_hz.unwrap());
    }
    let report = design(ts).report(0.0).unwrap();
    let achieved = 1.0 / (ts * report.bandwidth_hz.unwrap());
    assert!(
        achieved >= ratio * 0.999,
        "sample rate only {achieved} x bandwidth"
    );
    (ts, report)
}

/// Checks the paper's overshoot (percent) for the linear step response of the continuous
/// design and of the discrete loop sampled at `RATIO` times its bandwidth (0.3 point), and
/// returns the report for the large-step checks.
fn check_overshoot(paper_percent: f64, design: impl Fn(f64) -> AnyDesign) -> DesignReport {
    let (_, report) = period_for_ratio(RATIO, design);
    let continuous = 100.0 * report.continuous_step.unwrap().overshoot;
    let discrete = 100.0 * report.linear_step.overshoot;
    assert!(
        (continuous - paper_percent).abs() < 0.3,
        "continuous {continuous} %"
    );
    assert!(
        (discrete - paper_percent).abs() < 0.3,
        "discrete {discrete} %"
    );
    // The nonlinear loop, 179 degree step: the phase detector's sin(e) < e lowers the loop
    // gain during the transient; the loop still ends at 179 degrees (no cycle slip) and its
    // overshoot stays within 2 points of the linear figure (the example paper_figures prints it).
    let nonlinear = 100.0 * report.large_step.overshoot;
    assert!((report.large_step_final_rad.to_degrees() - 179.0).abs() < 1e-3);
    assert!(
        (nonlinear - discrete).abs() < 2.0,
        "nonlinear {nonlinear} % vs {discrete} %"
    );
    report
}

/// [`check_overshoot`] of one of the paper's settings, against the overshoot it quotes.
fn check_setting(setting: PaperSetting) -> DesignReport {
    check_overshoot(setting.overshoot_percent(), |ts| {
        setting.design(ts, PM).unwrap()
    })
}

#[test]
fn second_order_damping_1_945_overshoots_5_percent() {
    let report = check_setting(PaperSetting::SecondOrderFivePercent);
    assert!(report.large_step.overshoot < report.linear_step.overshoot);
}

#[test]
fn second_order_butterworth_overshoots_20_8_percent() {
    let setting = PaperSetting::SecondOrderButterworth;
    check_setting(setting);
    // The dedicated Butterworth setting is the same loop.
    let report = check_overshoot(setting.overshoot_percent(), |ts| {
        second_order_butterworth(1e-2, ts, PM).unwrap().into()
    });
    assert!(report.large_step.overshoot < report.linear_step.overshoot);
}

#[test]
fn third_order_k_39_04_psi_3pi_2_overshoots_10_percent() {
    check_setting(PaperSetting::ThirdOrderTenPercent);
}

#[test]
fn third_order_butterworth_overshoots_30_9_percent() {
    check_setting(PaperSetting::ThirdOrderButterworth);
}

#[test]
fn second_order_bias_under_constant_acceleration_is_alpha_over_k_b() {
    // 1 mrad tolerated at 1000 rad/s^2: k_b1 = 1e6 s^-2. At 1 MHz the discrete acceleration
    // constant is within 0.2 % of k_b1.
    let (max_error, alpha, ts) = (1e-3, 1e3, 1e-6);
    for damping in [BUTTERWORTH_DAMPING, 1.0, FIVE_PERCENT_DAMPING] {
        let design = second_order_from_tracking_error(max_error, alpha, damping, ts, PM).unwrap();
        let [_, k_b] = design.continuous_gains.unwrap();
        let ka = DesignReport::new(&design, 0.0)
            .unwrap()
            .acceleration_constant_per_s2
            .unwrap();
        let profile = MotionProfile::new(0.0, 0.0).then(Motion::ConstantAcceleration {
            acceleration_rad_s2: alpha,
            duration_s: 0.06,
        });
        let scenario = Scenario::generate(&profile, &SensorModel::default(), ts, 0).unwrap();
        let options = MetricsOptions {
            skip_s: 0.05,
            ..MetricsOptions::default()
        };
        let metrics = Metrics::new(&scenario, &run(&design.gains, &scenario), &options).unwrap();
        let bias = metrics.angle_error_rad.mean;
        assert!(
            (bias / (alpha / k_b) - 1.0).abs() < 0.01,
            "m {damping}: bias {bias}"
        );
        // And exactly the discrete figure (the loop is linear to sin(1e-3) ~ 1e-3).
        assert!(
            (bias / (alpha / ka) - 1.0).abs() < 1e-4,
            "m {damping}: bias {bias}"
        );
        assert!(metrics.angle_error_rad.max - bias < 1e-6 * bias);
    }
}

/// The full extended Kalman filter of the model of `docs/theory.md §4`: 3 states, the 2-D
/// measurement `(cos x1, sin x1)` with covariance `r I`, and a time-varying covariance.
struct ExtendedKalmanFilter {
    x: Vector3<f64>,
    p: Matrix3<f64>,
    a: Matrix3<f64>,
    process: Matrix3<f64>,
    r: f64,
}

impl ExtendedKalmanFilter {
    fn new(angle: f64, q: f64, r: f64) -> Self {
        let g = Vector3::new(1.0 / 6.0, 0.5, 1.0);
        Self {
            x: Vector3::new(angle, 0.0, 0.0),
            // Angle known to the noise; speed and acceleration unknown (scaled units).
            p: Matrix3::from_diagonal(&Vector3::new(r, 1e-2, 1e-6)),
            a: Matrix3::new(1.0, 1.0, 0.5, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0),
            process: g * g.transpose() * q,
            r,
        }
    }

    fn update(&mut self, y_c: f64, y_s: f64) {
        let x_p = self.a * self.x;
        let p_p = self.a * self.p * self.a.transpose() + self.process;
        let (s, c) = x_p[0].sin_cos();
        let h = Matrix3x2::new(-s, c, 0.0, 0.0, 0.0, 0.0).transpose();
        let innovation = Vector2::new(y_c - c, y_s - s);
        let covariance = h * p_p * h.transpose() + Matrix2::identity() * self.r;
        let gain = p_p * h.transpose() * covariance.try_inverse().expect("r > 0");
        self.x = x_p + gain * innovation;
        self.p = (Matrix3::identity() - gain * h) * p_p;
    }
}

#[test]
fn full_ekf_converges_to_the_time_invariant_kalman_ato() {
    let ts = 1e-4;
    let sigma = 0.01;
    let design = kalman_from_jerk_std(2e4, sigma, ts).unwrap();
    let solution = design.kalman.unwrap();
    let (q, r) = (solution.process_noise_q, solution.measurement_noise_r);
    let profile = MotionProfile::new(1.0, 30.0)
        .then(Motion::SCurve {
            distance_rad: 40.0,
            max_speed_rad_s: 200.0,
            max_acceleration_rad_s2: 2e3,
            max_jerk_rad_s3: 5e4,
        })
        .then(Motion::SpeedRipple {
            ripple_rad_s: 20.0,
            frequency_hz: 7.0,
            duration_s: 2.0,
        })
        .then(Motion::Reversal {
            acceleration_rad_s2: 500.0,
        });
    let scenario = Scenario::generate(&profile, &SensorModel::with_noise(sigma), ts, 11).unwrap();
    let chain: Chain<(), Gains<f64, 3>> = Chain::new((), design.gains);
    let mut state = ChainState::new();
    let mut ekf = ExtendedKalmanFilter::new(scenario.y_s[0].atan2(scenario.y_c[0]), q, r);
    let transient = 5_000;
    let mut largest = 0.0_f64;
    for (k, (&y_c, &y_s)) in scenario.y_c.iter().zip(&scenario.y_s).enumerate() {
        let ato = chain.update(&mut state, (y_c, y_s));
        if k > 0 {
            // The ATO's phase detector is normalised by the sample's magnitude (amplitude
            // invariance, docs/theory.md §12), so it is the steady state of the EKF on the
            // samples projected onto the unit circle, the EKF's own measurement model.
            let rho = y_c.hypot(y_s);
            ekf.update(y_c / rho, y_s / rho);
        }
        if k >= transient {
            largest = largest.max((ekf.x[0] - ato.position()).abs());
            let speed = (ekf.x[1] / ts - ato.speed).abs();
            assert!(
                speed < 1e-6 / ts,
                "sample {k}: speed differs by {speed} rad/s"
            );
        }
    }
    assert!(scenario.len() > 4 * transient);
    assert!(largest < 1e-6, "EKF and Kalman ATO differ by {largest} rad");
    // The EKF's covariance has converged to the DARE solution the design used.
    let filtered = Matrix3::from_fn(|i, j| solution.covariance[i][j]);
    let relative = (ekf.p - filtered).norm() / filtered.norm();
    assert!(
        relative < 1e-6,
        "EKF covariance off the DARE solution by {relative}"
    );
}
