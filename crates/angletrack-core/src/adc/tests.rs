//! The ADC front end: exact, overflow-free conversion of every integer sample type, and
//! tracking from quantised 12- and 16-bit signals within the quantisation noise's bound
//! (`docs/theory.md §12`).

extern crate std;

use proptest::prelude::*;

use crate::test_support::{TS, designs, n, proptest_config, wrap};
use crate::*;

proptest! {
    #![proptest_config(proptest_config())]

    /// Every i32 sample and mid-scale in range: exact in f64 (the difference is below 2^53),
    /// within the one rounding of f32 (two roundings of at most half an ulp each).
    #[test]
    fn i32_counts_never_overflow(raw in any::<i32>(), mid in -(1i32 << 30)..=(1i32 << 30)) {
        let exact = i64::from(raw) - i64::from(mid);
        prop_assert_eq!(raw.counts_from::<f64>(mid), exact as f64);
        let single = raw.counts_from::<f32>(mid) as f64;
        prop_assert!((single - exact as f64).abs() <= (exact as f64).abs() * f32::EPSILON as f64);
    }

    /// 16-bit samples are exact in both types for every mid-scale in range.
    #[test]
    fn sixteen_bit_counts_are_exact(raw in any::<i16>(), unsigned in any::<u16>(),
                                    mid in -(1i32 << 30)..=(1i32 << 30)) {
        let exact = i64::from(raw) - i64::from(mid);
        prop_assert_eq!(raw.counts_from::<f64>(mid), exact as f64);
        let exact_u = i64::from(unsigned) - i64::from(mid);
        prop_assert_eq!(unsigned.counts_from::<f64>(mid), exact_u as f64);
        if exact.abs() < 1 << 24 {
            prop_assert_eq!(raw.counts_from::<f32>(mid), exact as f32);
        }
    }
}

#[test]
fn configuration_is_checked_once() {
    let refused = [
        (
            AdcScaling::<f32>::new(i32::MIN, 1.0),
            Parameter::MidScaleCounts,
        ),
        (
            AdcScaling::<f32>::new(0, f32::NAN),
            Parameter::CountsPerUnit,
        ),
        (AdcScaling::<f32>::new(0, -2.0), Parameter::CountsPerUnit),
        (AdcScaling::<f32>::new(0, 1e-45), Parameter::CountsPerUnit),
        (AdcScaling::<f32>::offset_binary(32), Parameter::AdcBits),
        (AdcScaling::<f32>::twos_complement(1), Parameter::AdcBits),
    ];
    for (result, parameter) in refused {
        assert_eq!(result.unwrap_err().parameter(), parameter);
    }
    let adc = AdcScaling::<f64>::twos_complement(32).unwrap();
    // Exact powers of two written out: Miri perturbs `powi`, which is not correctly rounded.
    assert_eq!(
        adc.sample(i32::MIN, i32::MAX),
        (-1.0, 1.0 - 1.0 / 2_147_483_648.0)
    );
    let adc = AdcScaling::<f32>::offset_binary(31).unwrap();
    assert_eq!(adc.mid_scale_counts(), 1 << 30);
    assert_eq!(adc.counts_per_unit(), 1_073_741_824.0);
}

/// Tracks a signal of `amplitude_counts` quantised by an ADC of `bits` bits (offset binary,
/// f32 path) at constant speed and returns the RMS angle error after settling.
fn quantised_rms_error(bits: u32, amplitude_counts: f64) -> f64 {
    let (_, _, kalman) = designs();
    let gains = Gains::<f32, 3>::new(kalman.gains().map(|g| g as f32), TS as f32).unwrap();
    let adc = AdcScaling::<f32>::offset_binary(bits).unwrap();
    let mid = f64::from(adc.mid_scale_counts());
    let speed = 2.0 * core::f64::consts::PI * 7.3; // rad/s
    let chain = Chain::new(adc, gains);
    let mut state = ChainState::new();
    let (mut sum2, mut count) = (0.0, 0);
    let samples = n(20_000);
    for k in 0..samples {
        let theta = 0.4 + speed * k as f64 * TS;
        let raw = |v: f64| (mid + amplitude_counts * v).round() as u16;
        let e = chain.update(&mut state, (raw(theta.cos()), raw(theta.sin())));
        if k > samples / 2 {
            sum2 += wrap(theta - e.angle as f64).powi(2);
            count += 1;
        }
    }
    (sum2 / count as f64).sqrt()
}

/// The angle error's RMS stays below the quantisation noise of one sample, one LSB over
/// `sqrt(12)` relative to the amplitude (the angle noise of `atan2` on a single sample): the
/// loop only filters it further.
#[test]
#[cfg_attr(miri, ignore)]
fn tracks_quantised_12_and_16_bit_signals_within_the_quantisation_bound() {
    for (bits, amplitude) in [(12, 1800.0), (16, 30_000.0)] {
        let rms = quantised_rms_error(bits, amplitude);
        let bound = 1.0 / (amplitude * 12f64.sqrt());
        std::println!(
            "{bits} bits, amplitude {amplitude} counts: RMS {rms:e} rad, bound {bound:e}"
        );
        assert!(rms < bound, "{bits} bits: RMS {rms:e} rad, bound {bound:e}");
    }
}
