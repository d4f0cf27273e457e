//! A bank of channels gives exactly what single observers give, lane by lane.

use crate::test_support::TS;
use crate::*;

#[test]
fn a_channel_bank_gives_exactly_the_single_channel_results() {
    fn check<T: Real, S: SinCos<T>>() {
        let l = [T::from_f64(0.061), T::from_f64(0.0019), T::from_f64(3.1e-5)];
        let gains = Gains::<T, 3, S>::new(l, T::from_f64(TS)).unwrap();
        // Single observers without the fault monitor: the bank does not run it.
        let single = gains
            .with_fault_thresholds(FaultThresholds::disabled())
            .unwrap();
        const L: usize = 8;
        let mut bank = ChannelBank::<T, 3, L>::new();
        let mut states = [ObserverState::<T, 3>::new(); L];
        for k in 0..if cfg!(miri) { 100 } else { 5000 } {
            let mut y_c = [T::ZERO; L];
            let mut y_s = [T::ZERO; L];
            for lane in 0..L {
                let theta = 0.3 * lane as f64 + (20.0 + 45.0 * lane as f64) * k as f64 * TS;
                y_c[lane] = T::from_f64(theta.cos());
                y_s[lane] = T::from_f64(if k % 97 == lane {
                    f64::NAN
                } else {
                    theta.sin()
                });
            }
            gains.update_bank(&mut bank, &y_c, &y_s);
            for lane in 0..L {
                let e = single.update(&mut states[lane], y_c[lane], y_s[lane]);
                let b = gains.bank_estimate(&bank, lane).unwrap();
                assert_eq!(b, e, "lane {lane}, sample {k}");
            }
        }
        assert!(gains.bank_estimate(&bank, L).is_none());
        assert!(
            bank.turns().iter().any(|&t| t > 0),
            "the lanes turned: {:?}",
            bank.turns()
        );
    }
    check::<f32, Fast>();
    check::<f64, Exact>();
}

/// Gains so strong that one correction can move the angle by more than half a turn make the
/// bank run its lanes one by one with the full wrap: still exactly the single observers.
#[test]
fn a_bank_with_corrections_beyond_half_a_turn_gives_the_single_channel_results() {
    let gains = Gains::<f32, 3>::new([0.9, 0.3, 0.01], 1e-4).unwrap();
    let single = gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    const L: usize = 4;
    let mut bank = ChannelBank::<f32, 3, L>::new();
    let mut states = [ObserverState::<f32, 3>::new(); L];
    for k in 0..if cfg!(miri) { 50 } else { 2000 } {
        let mut y_c = [0.0f32; L];
        let mut y_s = [0.0f32; L];
        for lane in 0..L {
            // Amplitude up to 3.9 (accepted: the bound is 4), angle jumping about.
            let theta = (k * (lane + 3)) as f32 * 0.77;
            let amplitude = 0.5 + 3.4 * ((k + lane) % 5) as f32 / 4.0;
            y_c[lane] = amplitude * libm::cosf(theta);
            y_s[lane] = amplitude * libm::sinf(theta);
        }
        gains.update_bank(&mut bank, &y_c, &y_s);
        for lane in 0..L {
            let e = single.update(&mut states[lane], y_c[lane], y_s[lane]);
            assert_eq!(
                gains.bank_estimate(&bank, lane).unwrap(),
                e,
                "lane {lane}, sample {k}"
            );
            assert!(e.angle >= -core::f32::consts::PI && e.angle < core::f32::consts::PI);
        }
    }
}
