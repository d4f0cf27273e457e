//! Construction refuses what it cannot run, naming the parameter as the caller wrote it.

extern crate std;

use crate::*;

#[test]
fn bad_configuration_is_refused_naming_the_parameter() {
    let e = Gains::<f32, 2>::new([0.1, 0.01], 0.0).unwrap_err();
    assert_eq!(e, ConfigError::NotPositive(Parameter::SamplePeriod));
    let e = Gains::<f32, 2>::new([0.1, 0.01], f32::NAN).unwrap_err();
    assert_eq!(e, ConfigError::NotFinite(Parameter::SamplePeriod));
    let e = Gains::<f32, 3>::new([0.1, f32::INFINITY, 0.001], 1e-4).unwrap_err();
    assert_eq!(e, ConfigError::NotFinite(Parameter::SpeedGain));
    let e = Gains::<f32, 2>::new([0.1, 0.01], 1e-39).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    let e = Gains::<f64, 2>::new([0.1, 0.01], 1.4e-148).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    let e = Gains::<f64, 2>::new([0.1, 0.01], 1e4).unwrap_err();
    assert_eq!(e, ConfigError::OutOfRange(Parameter::SamplePeriod));
    assert!(Gains::<f32, 2>::new([0.1, 0.01], 1e-12).is_ok());
    // The names are those the caller wrote: the arguments of `Gains::new`, the fields of
    // `FaultThresholds` (the keywords of the Python API).
    let text = std::format!("{}", ConfigError::NotFinite(Parameter::SpeedGain));
    assert_eq!(text, "gains[1] (l2) must be finite");
    let e = Gains::<f32, 2>::new([0.1, 0.01], -1.0).unwrap_err();
    assert_eq!(std::format!("{e}"), "sample_period_s must be positive");
    let e = ConfigError::OutOfRange(Parameter::LossOfSignalThreshold);
    assert_eq!(
        std::format!("{e}"),
        "loss_of_signal is out of its allowed range"
    );
}
