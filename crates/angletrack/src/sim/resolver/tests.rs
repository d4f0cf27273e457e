use super::*;
use crate::Motion;

fn profile() -> MotionProfile {
    MotionProfile::new(0.2, 100.0).then(Motion::ConstantSpeed {
        speed_rad_s: 100.0,
        duration_s: 2e-3,
    })
}

#[test]
fn deterministic_from_the_seed() {
    let model = ResolverModel::default();
    let a = Scenario::resolver_windings(&profile(), &model, 1).unwrap();
    assert_eq!(
        a,
        Scenario::resolver_windings(&profile(), &model, 1).unwrap()
    );
    assert_ne!(
        a.y_c,
        Scenario::resolver_windings(&profile(), &model, 2)
            .unwrap()
            .y_c
    );
}

#[test]
fn windings_carry_the_envelopes_on_the_delayed_carrier() {
    let model = ResolverModel {
        carrier_delay_rad: 0.9,
        winding_imbalance: 0.1,
        common_mode_counts: 25.0,
        noise_std_counts: 0.0,
        adc_bits: 0,
        ..ResolverModel::default()
    };
    let s = Scenario::resolver_windings(&profile(), &model, 1).unwrap();
    for k in [0, 5, 17, 200] {
        let carrier = (std::f64::consts::TAU * (k % 16) as f64 / 16.0 - 0.9).sin();
        let theta = s.angle_rad[k];
        assert!((s.y_c[k] - (25.0 + 1800.0 * theta.cos() * carrier)).abs() < 1e-9);
        assert!((s.y_s[k] - (25.0 + 1980.0 * theta.sin() * carrier)).abs() < 1e-9);
    }
    assert!((s.sample_period_s - 1.0 / 160e3).abs() < 1e-18);
}

#[test]
fn the_adc_rounds_and_saturates() {
    let model = ResolverModel {
        excitation_amplitude_counts: 9000.0,
        ..ResolverModel::default()
    };
    let s = Scenario::resolver_windings(&profile(), &model, 1).unwrap();
    assert!(
        s.y_c
            .iter()
            .chain(&s.y_s)
            .all(|&v| v.fract() == 0.0 && (0.0..=4095.0).contains(&v))
    );
    assert!(s.y_c.contains(&4095.0));
}

#[test]
fn refuses_bad_models_by_name() {
    let refused = |m: ResolverModel| {
        Scenario::resolver_windings(&profile(), &m, 1)
            .unwrap_err()
            .argument()
            .unwrap()
    };
    let d = ResolverModel::default();
    assert_eq!(
        refused(ResolverModel {
            samples_per_period: 1,
            ..d
        }),
        Argument::SamplesPerPeriod
    );
    assert_eq!(
        refused(ResolverModel {
            carrier_delay_rad: f64::NAN,
            ..d
        }),
        Argument::CarrierDelay
    );
    assert_eq!(
        refused(ResolverModel {
            transformation_ratio: 0.0,
            ..d
        }),
        Argument::TransformationRatio
    );
    assert_eq!(
        refused(ResolverModel {
            common_mode_counts: f64::INFINITY,
            ..d
        }),
        Argument::CommonMode
    );
    assert_eq!(
        refused(ResolverModel {
            carrier_hz: -1.0,
            ..d
        }),
        Argument::CarrierFrequency
    );
    assert_eq!(
        refused(ResolverModel {
            excitation_amplitude_counts: f64::NAN,
            ..d
        }),
        Argument::ExcitationAmplitude
    );
    assert_eq!(
        refused(ResolverModel { adc_bits: 30, ..d }),
        Argument::AdcBits
    );
    // Each named as the model's field is (the sensor model's are spelt otherwise), and a
    // delay whose turns f64 no longer resolves refused.
    let named = [
        (
            ResolverModel {
                winding_imbalance: -2.0,
                ..d
            },
            "winding_imbalance",
        ),
        (
            ResolverModel {
                noise_std_counts: -1.0,
                ..d
            },
            "noise_std_counts",
        ),
        (
            ResolverModel {
                carrier_delay_rad: 1e18,
                ..d
            },
            "carrier_delay_rad",
        ),
    ];
    for (model, name) in named {
        assert_eq!(refused(model).name(), name);
    }
    assert!(
        Scenario::resolver_windings(
            &profile(),
            &ResolverModel {
                carrier_delay_rad: -999.0,
                ..d
            },
            1
        )
        .is_ok()
    );
}
