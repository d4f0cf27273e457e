//! A bank of channels gives exactly what single observers give, lane by lane.

use crate::test_support::TS;
use crate::*;

/// Runs a bank of `L` lanes and, beside it, `L` single observers with the same gains but
/// without the fault monitor (the bank does not run it) over `samples` samples, lane `lane`
/// of sample `k` being `input(k, lane) = (y_c, y_s)`. Checks that every lane's estimate is
/// exactly its single observer's, and passes each single estimate to `check`. Returns the
/// bank.
fn run_bank_beside_single_observers<T: Real, S: SinCos<T>, const L: usize>(
    gains: Gains<T, 3, S>,
    samples: usize,
    input: impl Fn(usize, usize) -> (T, T),
    check: impl Fn(&Estimate<T>),
) -> ChannelBank<T, 3, L> {
    let single = gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    let mut bank = ChannelBank::<T, 3, L>::new();
    let mut states = [ObserverState::<T, 3>::new(); L];
    for k in 0..samples {
        let lanes: [(T, T); L] = core::array::from_fn(|lane| input(k, lane));
        let (y_c, y_s) = (lanes.map(|l| l.0), lanes.map(|l| l.1));
        gains.update_bank(&mut bank, &y_c, &y_s);
        for lane in 0..L {
            let e = single.update(&mut states[lane], y_c[lane], y_s[lane]);
            let b = gains.bank_estimate(&bank, lane).unwrap();
            assert_eq!(b, e, "lane {lane}, sample {k}");
            check(&e);
        }
    }
    bank
}

#[test]
fn a_channel_bank_gives_exactly_the_single_channel_results() {
    fn check<T: Real, S: SinCos<T>>() {
        let l = [T::from_f64(0.061), T::from_f64(0.0019), T::from_f64(3.1e-5)];
        let gains = Gains::<T, 3, S>::new(l, T::from_f64(TS)).unwrap();
        const L: usize = 8;
        let samples = if cfg!(miri) { 100 } else { 5000 };
        let bank = run_bank_beside_single_observers::<T, S, L>(
            gains,
            samples,
            |k, lane| {
                let theta = 0.3 * lane as f64 + (20.0 + 45.0 * lane as f64) * k as f64 * TS;
                let y_s = if k % 97 == lane {
                    f64::NAN
                } else {
                    theta.sin()
                };
                (T::from_f64(theta.cos()), T::from_f64(y_s))
            },
            |_| {},
        );
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
    let samples = if cfg!(miri) { 50 } else { 2000 };
    run_bank_beside_single_observers::<f32, Fast, 4>(
        gains,
        samples,
        |k, lane| {
            // Amplitude up to 3.9 (accepted: the bound is 4), angle jumping about.
            let theta = (k * (lane + 3)) as f32 * 0.77;
            let amplitude = 0.5 + 3.4 * ((k + lane) % 5) as f32 / 4.0;
            (amplitude * libm::cosf(theta), amplitude * libm::sinf(theta))
        },
        |e| assert!(e.angle >= -core::f32::consts::PI && e.angle < core::f32::consts::PI),
    );
}
