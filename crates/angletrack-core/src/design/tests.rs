//! The designs' refusals, naming the parameter. Their gains are checked across the crates
//! (`tests/design.rs` at the repository root): the `f32` designs against the `f64` ones, and
//! both against the eigenvalues of the designed loop and the Riccati residual.

use crate::*;

#[test]
fn designs_refuse_what_they_cannot_design_naming_the_parameter() {
    let parameter = |e: ConfigError| e.parameter();
    let second = Gains::<f32, 2>::second_order_from_bandwidth;
    assert_eq!(
        second(0.0, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    assert_eq!(
        second(100.0, f32::NAN, 1e-4).map_err(parameter),
        Err(Parameter::Damping)
    );
    assert_eq!(
        second(100.0, 2e3, 1e-4).map_err(parameter),
        Err(Parameter::Damping)
    );
    assert_eq!(
        second(100.0, 1.0, -1e-4).map_err(parameter),
        Err(Parameter::SamplePeriod)
    );
    assert_eq!(
        second(1e4, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    assert_eq!(
        second(f32::MAX, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::Bandwidth)
    );
    let third = Gains::<f64, 3>::third_order_from_poles;
    assert_eq!(
        third(0.0, 1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleRatio)
    );
    assert_eq!(
        third(2e6, 1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleRatio)
    );
    assert_eq!(
        third(1.0, 1e-2, 2e3, 1e-4).map_err(parameter),
        Err(Parameter::PoleFrequencyRatio)
    );
    assert_eq!(
        third(1.0, -1e-2, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleTimeConstant)
    );
    assert_eq!(
        third(100.0, 1e-3, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::PoleTimeConstant)
    );
    let kalman = Gains::<f32, 3>::kalman;
    assert_eq!(
        kalman(0.0, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
    assert_eq!(
        kalman(1.0, f32::INFINITY, 1e-4).map_err(parameter),
        Err(Parameter::MeasurementNoise)
    );
    assert_eq!(
        kalman(1e-32, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
    assert_eq!(
        kalman(1e7, 1.0, 1e-4).map_err(parameter),
        Err(Parameter::ProcessNoise)
    );
}

#[test]
fn continuous_poles_are_refused_beyond_the_sample_rate_and_outside_the_stability_region() {
    let pair = PolePair::second_order(2e3_f32, 0.05);
    let from_poles = Gains::<f32, 2>::from_continuous_poles;
    assert!(from_poles(pair, 1e-4, Discretisation::PoleMatching).is_ok());
    assert!(from_poles(pair, 1e-4, Discretisation::Tustin).is_ok());
    // |1 + s Ts| = |1 - 0.01 + 0.2 j| > 1: the Euler step leaves the unit circle.
    assert!(matches!(
        from_poles(pair, 1e-4, Discretisation::ForwardEuler),
        Err(ConfigError::Unstable { .. })
    ));
    assert_eq!(
        from_poles(pair, 1e-3, Discretisation::PoleMatching).map_err(|e| e.parameter()),
        Err(Parameter::SamplePeriod)
    );
    let third = Gains::<f64, 3>::from_continuous_poles;
    assert_eq!(
        third(
            -2e4,
            PolePair::second_order(2e3, 0.05),
            1e-4,
            Discretisation::Tustin
        )
        .map_err(|e| e.parameter()),
        Err(Parameter::SamplePeriod)
    );
}
