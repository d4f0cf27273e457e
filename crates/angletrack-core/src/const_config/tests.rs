//! The `const` constructors agree exactly with the generic ones and refuse the same
//! configurations, naming the same parameter.

use crate::*;

const PERIODS: [f64; 4] = [1e-6, 50e-6, 1e-3, 0.5];
const GAIN_SETS_3: [[f64; 3]; 5] = [
    [0.1578, 0.0126, 0.000_34],
    [0.3, 0.04, 0.002],
    [0.3, 0.04, -0.002],
    [1.9, 0.5, 0.9],
    [0.0, 0.01, 0.001],
];
const GAIN_SETS_2: [[f64; 2]; 4] = [[0.05, 0.0012], [1.5, 1.0 + 1e-9], [0.1, -0.01], [1.9, 0.3]];

#[test]
fn const_and_generic_constructors_agree_on_both_types_and_orders() {
    for ts in PERIODS.into_iter().chain([0.0, -1.0, f64::NAN, 1e-13, 1e4]) {
        for g in GAIN_SETS_3 {
            let g32 = g.map(|x| x as f32);
            assert_eq!(Gains::<f64, 3>::new_const(g, ts), Gains::new(g, ts));
            assert_eq!(
                Gains::<f32, 3>::new_const(g32, ts as f32),
                Gains::new(g32, ts as f32)
            );
            assert_eq!(
                Gains::<f64, 3>::from_loop_polynomial_const(g, ts),
                Gains::from_loop_polynomial(g, ts)
            );
        }
        for g in GAIN_SETS_2 {
            let g32 = g.map(|x| x as f32);
            assert_eq!(Gains::<f64, 2>::new_const(g, ts), Gains::new(g, ts));
            assert_eq!(
                Gains::<f32, 2>::new_const(g32, ts as f32),
                Gains::new(g32, ts as f32)
            );
            assert_eq!(
                Gains::<f32, 2>::from_loop_polynomial_const(g32, ts as f32),
                Gains::from_loop_polynomial(g32, ts as f32)
            );
        }
    }
}

#[test]
fn const_thresholds_and_settings_agree_with_the_generic_ones() {
    let gains = Gains::<f32, 3>::new_const([0.3, 0.04, 0.002], 1e-4).unwrap();
    for amplitude in [1e-30_f32, 1.0, 1800.0, 1e30, f32::NAN] {
        let t = FaultThresholds::<f32>::for_amplitude_const(amplitude);
        assert_eq!(
            t.loss_of_tracking,
            FaultThresholds::for_amplitude(amplitude).loss_of_tracking
        );
        for variant in [
            t,
            FaultThresholds {
                filter_factor: 1.5,
                ..t
            },
            FaultThresholds {
                false_lock: -2.0 * amplitude,
                ..t
            },
            FaultThresholds {
                max_speed: Some(-1.0),
                ..t
            },
        ] {
            assert_eq!(
                gains.with_fault_thresholds_const(variant),
                gains.with_fault_thresholds(variant)
            );
            assert_eq!(
                variant.check_const(1e-4).map(|_| ()),
                gains.with_fault_thresholds(variant).map(|_| ())
            );
        }
    }
    let t64 = FaultThresholds::<f64>::for_amplitude_const(3.0);
    assert_eq!(t64, FaultThresholds::for_amplitude(3.0));
    assert_eq!(
        CalibrationSettings::<f64>::default_const(),
        CalibrationSettings::default()
    );
    for speed in [None, Some(50.0), Some(1e-3), Some(f32::INFINITY)] {
        let s = CalibrationSettings {
            min_speed_rad_s: speed,
            ..CalibrationSettings::<f32>::default_const()
        };
        assert_eq!(
            gains.with_calibration_settings_const(s),
            gains.with_calibration_settings(s)
        );
    }
}

#[test]
fn square_root_of_the_smallest_normal_is_exact() {
    assert_eq!(f32::from_bits(0x2000_0000), libm::sqrtf(f32::MIN_POSITIVE));
    assert_eq!(
        f64::from_bits(0x2000_0000_0000_0000),
        libm::sqrt(f64::MIN_POSITIVE)
    );
}

/// A complete firmware configuration as a `static`, evaluated by the compiler.
static FIRMWARE_GAINS: Gains<f32, 3> =
    match Gains::<f32, 3>::new_const([0.1578, 0.0126, 0.000_34], 50e-6) {
        Ok(gains) => {
            match gains
                .with_fault_thresholds_const(FaultThresholds::<f32>::for_amplitude_const(0.88))
            {
                Ok(gains) => gains,
                Err(_) => panic!("bad thresholds"),
            }
        }
        Err(_) => panic!("unstable gains"),
    };

#[test]
fn a_static_configuration_runs() {
    let mut state = ObserverState::new();
    let estimate = FIRMWARE_GAINS.update(&mut state, 0.44, 0.762);
    assert!((estimate.angle - core::f32::consts::FRAC_PI_3).abs() < 1e-3);
    assert!(estimate.faults.is_empty());
}
