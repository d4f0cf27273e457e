use super::*;

/// Raw windings: 12-bit counts about 2048, amplitude 1800, `n` samples of a carrier at
/// `cycles` cycles per sample, the shaft turning 0.002 rad a sample.
fn windings(n: usize, cycles: f64) -> (Vec<f64>, Vec<f64>) {
    let at = |k: usize, angle: fn(f64) -> f64| {
        let carrier = (std::f64::consts::TAU * cycles * k as f64).sin();
        2048.0 + 1800.0 * angle(0.002 * k as f64) * carrier
    };
    (
        (0..n).map(|k| at(k, f64::cos)).collect(),
        (0..n).map(|k| at(k, f64::sin)).collect(),
    )
}

fn settings(
    carrier_hz: f64,
    capture_hz: Option<f64>,
    samples_per_period: Option<f64>,
) -> WindingsSettings {
    WindingsSettings {
        capture_hz,
        samples_per_period,
        ..WindingsSettings::new(carrier_hz)
    }
}

#[test]
fn the_rate_comes_from_the_stated_ratio_else_the_capture() {
    let (c, s) = windings(4000, 1.0 / 15.0);
    let plan = WindingsPlan::new(&c, &s, &settings(10e3, Some(150e3), None)).unwrap();
    assert_eq!((plan.adc_rate_hz, plan.samples_per_period), (150e3, 15.0));
    // A stated ratio within 1 % of the time column's is taken as stated.
    let plan = WindingsPlan::new(&c, &s, &settings(10e3, Some(150e3), Some(15.1))).unwrap();
    assert_eq!(plan.adc_rate_hz, 151e3);
    // Without a time column the ratio must be stated.
    let plan = WindingsPlan::new(&c, &s, &settings(10e3, None, Some(15.0))).unwrap();
    assert_eq!(plan.adc_rate_hz, 150e3);
    assert_eq!(
        WindingsPlan::new(&c, &s, &settings(10e3, None, None)),
        Err(WindingsPlanError::NoAdcRate)
    );
}

#[test]
fn contradictions_are_refused_naming_both_values() {
    let (c, s) = windings(4000, 1.0 / 15.0);
    let error = WindingsPlan::new(&c, &s, &settings(10e3, Some(150e3), Some(16.0))).unwrap_err();
    assert_eq!(error.argument(), "samples_per_period");
    assert_eq!(
        error.to_string(),
        "--samples-per-period 16 contradicts the capture's time column: 150000 Hz \
         over --carrier-hz 10000 is 15 samples per period"
    );
    // 3 % off the 10 kHz measured at the capture's rate; then at the stated ratio.
    let error = WindingsPlan::new(&c, &s, &settings(10.3e3, Some(150e3), None)).unwrap_err();
    assert_eq!(error.argument(), "carrier_hz");
    let text = error.to_string();
    assert!(
        text.starts_with(
            "--carrier-hz 10300 is +3 % from the carrier measured in the capture, 10000"
        ),
        "{text}"
    );
    assert!(
        text.ends_with("(at 150000 samples/s, the capture's time column)"),
        "{text}"
    );
    let error = WindingsPlan::new(&c, &s, &settings(10e3, None, Some(15.5))).unwrap_err();
    assert!(
        error
            .to_string()
            .ends_with("(at 155000 samples/s, 15.5 samples per declared period)"),
        "{error}"
    );
    // 2 % is tolerated; fewer than 4 samples a period are not.
    assert!(WindingsPlan::new(&c, &s, &settings(10.19e3, Some(150e3), None)).is_ok());
    let error = WindingsPlan::new(&c, &s, &settings(50e3, Some(150e3), None)).unwrap_err();
    assert_eq!(
        error.to_string(),
        "the ADC rate 150000 Hz over the carrier 50000 Hz is 3 samples per period; at \
         least 4 are needed"
    );
}

#[test]
fn a_stated_amplitude_no_adc_gives_is_refused_naming_it() {
    let (c, s) = windings(4000, 1.0 / 16.0);
    for amplitude in [f64::NAN, 0.0, -1.0, 4_294_967_296.0] {
        let stated = WindingsSettings {
            carrier_amplitude_counts: Some(amplitude),
            ..settings(10e3, Some(160e3), None)
        };
        let e = WindingsPlan::new(&c, &s, &stated).unwrap_err();
        assert!(matches!(e, WindingsPlanError::CarrierAmplitude(_)), "{e}");
        assert_eq!(e.argument(), "carrier_amplitude_counts");
    }
}

#[test]
fn the_amplitude_and_the_range_are_measured_or_guessed_unless_stated() {
    let (c, s) = windings(4000, 1.0 / 16.0);
    let plan = WindingsPlan::new(&c, &s, &settings(10e3, Some(160e3), None)).unwrap();
    assert!(
        (plan.carrier_amplitude_counts / 1800.0 - 1.0).abs() < 0.01,
        "{}",
        plan.carrier_amplitude_counts
    );
    assert_eq!(
        (plan.adc_range, plan.adc_range_source),
        ((0.0, 4095.0), AdcRangeSource::Guessed)
    );
    // Centred windings (signed) guess a signed range; clipped ones measure their rails.
    let centred: Vec<f64> = c.iter().map(|v| v - 2048.0).collect();
    let plan = WindingsPlan::new(&centred, &centred, &settings(10e3, Some(160e3), None)).unwrap();
    assert_eq!(plan.adc_range, (-2048.0, 2047.0));
    let clipped: Vec<f64> = centred
        .iter()
        .map(|v| (v * 2.0).clamp(-2048.0, 2047.0))
        .collect();
    let plan = WindingsPlan::new(&clipped, &clipped, &settings(10e3, Some(160e3), None)).unwrap();
    assert_eq!(
        (plan.adc_range, plan.adc_range_source),
        ((-2048.0, 2047.0), AdcRangeSource::Measured)
    );
    let mut stated = settings(10e3, Some(160e3), None);
    (stated.adc_range, stated.carrier_amplitude_counts) = (Some((-1.0, 1.0)), Some(0.5));
    let plan = WindingsPlan::new(&c, &s, &stated).unwrap();
    assert_eq!(
        (
            plan.adc_range,
            plan.adc_range_source,
            plan.carrier_amplitude_counts
        ),
        ((-1.0, 1.0), AdcRangeSource::Stated, 0.5)
    );
}

#[test]
fn numbers_are_written_as_percent_g_writes_them() {
    for (x, digits, text) in [
        (10000.0, 6, "10000"),
        (150000.0, 6, "150000"),
        (10300.123456, 6, "10300.1"),
        (-2.9126, 3, "-2.91"),
        (5.0, 3, "5"),
        (1234567.0, 6, "1.23457e+06"),
        (0.00001234, 3, "1.23e-05"),
        (0.0, 6, "0"),
        (15.5, 6, "15.5"),
    ] {
        assert_eq!(significant(x, digits), text, "{x}");
    }
}
