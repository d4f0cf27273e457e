use super::*;

#[test]
fn literals_are_numpys_shortest_scientific_form() {
    // The expected texts are NumPy's format_float_scientific(unique=True, trim="-").
    let cases: [(f64, FloatType, &str); 12] = [
        (0.1, FloatType::F32, "1e-01"),
        (1e-4, FloatType::F64, "1e-04"),
        (1800.0, FloatType::F32, "1.8e+03"),
        (0.0, FloatType::F64, "0e+00"),
        (-0.0, FloatType::F32, "-0e+00"),
        (1.0, FloatType::F64, "1e+00"),
        (5e-5, FloatType::F32, "5e-05"),
        (123456789.0, FloatType::F32, "1.2345679e+08"),
        (123456789.0, FloatType::F64, "1.23456789e+08"),
        (1e300, FloatType::F64, "1e+300"),
        (1e-310, FloatType::F64, "1e-310"),
        (-2.5e-7, FloatType::F64, "-2.5e-07"),
    ];
    for (value, float_type, text) in cases {
        assert_eq!(
            literal(value, float_type, "gains").unwrap(),
            text,
            "{value:e}"
        );
    }
}

#[test]
fn every_f32_literal_rounds_back_to_the_same_float() {
    for k in 1..2000 {
        let value = (k as f64 * 0.7371).powi(3).recip();
        let text = literal(value, FloatType::F32, "gains").unwrap();
        assert_eq!(text.parse::<f32>().unwrap(), value as f32, "{text}");
    }
}

#[test]
fn a_value_beyond_the_float_type_is_refused_naming_its_field() {
    let e = literal(1e39, FloatType::F32, "sensor").unwrap_err();
    assert_eq!(e.field(), "sensor");
    assert_eq!(e.to_string(), "sensor: 1e39 is not finite in float32");
    assert!(literal(1e39, FloatType::F64, "sensor").is_ok());
    assert!(literal(f64::NAN, FloatType::F64, "gains").is_err());
}

#[test]
fn names_must_be_identifiers() {
    assert_eq!(identifier("rdc_1").unwrap(), "rdc_1");
    assert_eq!(identifier("_x").unwrap(), "_x");
    for bad in ["", "1rdc", "rdc-gains", "rdc gains", "é"] {
        let e = identifier(bad).unwrap_err();
        assert_eq!(e.field(), "name");
        assert!(e.to_string().starts_with("name: "), "{e}");
    }
}

#[test]
fn float_types_parse_by_their_python_names() {
    assert_eq!("float32".parse::<FloatType>().unwrap(), FloatType::F32);
    assert_eq!("float64".parse::<FloatType>().unwrap(), FloatType::F64);
    let e = "fixed".parse::<FloatType>().unwrap_err();
    assert_eq!(e.field(), "dtype");
    assert_eq!(FloatType::default(), FloatType::F32);
}

#[test]
fn descriptions_become_trimmed_comment_lines() {
    let lines: Vec<_> = comment_lines("\n  first  \r\nsecond\t\n\n").collect();
    assert_eq!(lines, ["first", "second"]);
    assert_eq!(comment_lines("  \n ").count(), 0);
    // Nothing a description holds ends the comment: a `*/` is broken, a lone carriage return
    // (a line's end to some compilers) starts a new comment line.
    let lines: Vec<_> = comment_lines("x */ int evil; /*\rint more;\n\nend").collect();
    assert_eq!(lines, ["x * / int evil; /*", "int more;", "", "end"]);
    let gains = angletrack_core::Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap();
    let header = gains_c_header(&gains, FloatType::F32, "motor", "a */ int evil; /*\rb").unwrap();
    // The header's first comment ends after the description's last line.
    let comment_end = header.find("*/").unwrap();
    assert!(header[..comment_end].contains(" * b\n"), "{header}");
}

#[test]
fn a_bad_name_is_refused_by_every_generator() {
    let gains = angletrack_core::Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap();
    assert!(gains_c_header(&gains, FloatType::F32, "a-b", "").is_err());
    assert!(gains_rust(&gains, FloatType::F32, "a b", "").is_err());
    let fixed = angletrack_core::FixedGains::<2>::new([0.05, 0.0012], 1e-4).unwrap();
    let constants = crate::FixedDesignConstants::of(&fixed);
    assert!(fixed_c_header(&constants, "", "").is_err());
    assert!(fixed_rust(&constants, "9", "").is_err());
    let sensor = angletrack_core::SensorCalibration::new(0.0, 0.0, 1.0, 1.0, 0.0).unwrap();
    let correction = angletrack_core::AngleCorrection::new([0.0; 8], [0.0; 8]).unwrap();
    assert!(calibration_c_header(&sensor, &correction, FloatType::F32, "x.y").is_err());
    assert!(calibration_rust(&sensor, &correction, FloatType::F32, "x.y").is_err());
}

#[test]
fn gains_beyond_f32_are_refused_in_f32_only() {
    let sensor = angletrack_core::SensorCalibration::new(0.0, 0.0, 1e39, 1e39, 0.0).unwrap();
    let correction = angletrack_core::AngleCorrection::new([0.0; 8], [0.0; 8]).unwrap();
    let e = calibration_c_header(&sensor, &correction, FloatType::F32, "rdc").unwrap_err();
    assert_eq!(e.field(), "sensor");
    assert!(calibration_c_header(&sensor, &correction, FloatType::F64, "rdc").is_ok());
}
