//! The fixed-point observer (`docs/theory.md §14`) against the `f64` observer on the
//! paper's scenarios: the settings of `docs/theory.md §2, §3` and the three compared
//! observers of `§4`, on the same simulated resolver signals (the fixed path's rounded to
//! 16-bit counts of amplitude 2^14): within 2^-16 of a turn RMS.

use angletrack::core::{FixedGains, FixedState};
use angletrack::paper::{ComparedObserver, OVERSHOOT_SAMPLE_PERIOD_S, PaperSetting};
use angletrack::{
    AnyDesign, Discretisation, Gains, Motion, MotionProfile, ObserverState, Scenario, SensorModel,
};

/// The accuracy the fixed-point path must reach (turns, RMS over the run).
const RMS_TOLERANCE_TURNS: f64 = 1.0 / 65536.0;

/// A move of the paper's time scale: 100 rad/s^2 (the acceleration the paper's tracking
/// error is specified at) up to 20 rad/s, a constant speed, a speed step down, with the
/// comparison's sensor noise (0.01 of the amplitude).
fn scenario(sample_period_s: f64) -> Scenario {
    let profile = MotionProfile::new(0.3, 0.0)
        .then(Motion::ConstantAcceleration {
            acceleration_rad_s2: 100.0,
            duration_s: 0.2,
        })
        .then(Motion::ConstantSpeed {
            speed_rad_s: 20.0,
            duration_s: 0.05,
        })
        .then(Motion::ConstantSpeed {
            speed_rad_s: 5.0,
            duration_s: 0.05,
        });
    Scenario::generate(
        &profile,
        &SensorModel::with_noise(0.01),
        sample_period_s,
        2026,
    )
    .expect("a valid scenario")
}

/// A sample in counts of amplitude 2^14, rounded.
fn counts(y: f64) -> i16 {
    (y * 16384.0).round() as i16
}

/// RMS (turns) of the difference of the fixed-point and the `f64` observers' positions.
fn rms_difference<const N: usize>(gains: [f64; N], scenario: &Scenario) -> f64
where
    angletrack::core::Order<N>: angletrack::core::SupportedOrder,
{
    let ts = scenario.sample_period_s;
    let float = Gains::<f64, N>::new(gains, ts).expect("the design's gains");
    let fixed = FixedGains::<N>::new(gains, ts).expect("the design's gains, quantised");
    let (mut float_state, mut fixed_state) = (ObserverState::new(), FixedState::new());
    let mut sum = 0.0;
    for (&c, &s) in scenario.y_c.iter().zip(&scenario.y_s) {
        let e = float.update(&mut float_state, c, s);
        let f = fixed.update(&mut fixed_state, counts(c), counts(s));
        let float_turns = e.position() / std::f64::consts::TAU;
        let fixed_turns = fixed.position_rad(&f) / std::f64::consts::TAU;
        sum += (fixed_turns - float_turns).powi(2);
    }
    (sum / scenario.y_c.len() as f64).sqrt()
}

/// [`rms_difference`] of a design of either order.
fn rms_of(design: &AnyDesign, scenario: &Scenario) -> f64 {
    match design {
        AnyDesign::Second(d) => rms_difference(d.gains.gains(), scenario),
        AnyDesign::Third(d) => rms_difference(d.gains.gains(), scenario),
    }
}

#[test]
fn fixed_point_follows_the_f64_observer_on_the_compared_observers() {
    for observer in ComparedObserver::ALL {
        let design = observer.design().unwrap();
        let rms = rms_of(&design, &scenario(design.sample_period()));
        println!(
            "{}: RMS {:.3e} turn ({:.3} of 2^-16)",
            observer.name(),
            rms,
            rms / RMS_TOLERANCE_TURNS
        );
        assert!(
            rms < RMS_TOLERANCE_TURNS,
            "{}: {rms:e} turn",
            observer.name()
        );
    }
}

#[test]
fn fixed_point_follows_the_f64_observer_on_the_paper_settings() {
    let scenario = scenario(OVERSHOOT_SAMPLE_PERIOD_S);
    for setting in PaperSetting::ALL {
        let design = setting
            .design(OVERSHOOT_SAMPLE_PERIOD_S, Discretisation::PoleMatching)
            .unwrap();
        let rms = rms_of(&design, &scenario);
        println!(
            "{}: RMS {:.3e} turn ({:.3} of 2^-16)",
            setting.name(),
            rms,
            rms / RMS_TOLERANCE_TURNS
        );
        assert!(
            rms < RMS_TOLERANCE_TURNS,
            "{}: {rms:e} turn",
            setting.name()
        );
    }
}

#[test]
fn fixed_point_follows_the_f64_observer_through_an_acquisition() {
    // The benchmarks' and the firmware test's signal: the observer starts at rest on a shaft
    // turning at 300 rad/s and accelerating (phase errors up to 0.3 for 100 samples).
    let profile = MotionProfile::new(0.3, 300.0).then(Motion::ConstantAcceleration {
        acceleration_rad_s2: 400.0,
        duration_s: 0.2,
    });
    let ts = angletrack::paper::BENCHMARK_SAMPLE_PERIOD_S;
    let scenario = Scenario::generate(&profile, &SensorModel::with_noise(0.01), ts, 7).unwrap();
    for gains in [
        angletrack::paper::BENCHMARK_KALMAN_GAINS,
        angletrack::paper::BENCHMARK_THIRD_ORDER_GAINS,
    ] {
        let rms = rms_difference(gains, &scenario);
        println!(
            "{gains:?}: RMS {rms:.3e} turn ({:.3} of 2^-16)",
            rms / RMS_TOLERANCE_TURNS
        );
        assert!(rms < RMS_TOLERANCE_TURNS, "{gains:?}: {rms:e} turn");
    }
}
