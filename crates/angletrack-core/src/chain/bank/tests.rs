//! A chain's bank form gives exactly what single chains give, lane by lane: with a front
//! end (ADC counts, a stored calibration, the clipping check), with an online calibration
//! that learns, and with a lane whose samples are bad while the others track.

use crate::*;

const L: usize = 4;
const TS: f64 = 1e-4;

/// Lane `lane`'s shaft angle at sample `k` (rad): each lane at its own speed and phase.
fn theta(k: usize, lane: usize) -> f64 {
    0.4 * lane as f64 + (60.0 + 70.0 * lane as f64) * k as f64 * TS
}

/// Runs `chain`'s bank form beside `L` single chains of the same front end and the gains
/// without the monitor (a bank runs none) over `samples` samples, lane `lane` of sample `k`
/// being `input(k, lane)`; checks that every lane's estimate is exactly its single chain's
/// and returns the bank's state with the last estimates.
#[allow(clippy::type_complexity)]
fn run_beside_single_chains<F, X, T, const N: usize>(
    chain: Chain<F, Gains<T, N>>,
    front_end: F::State,
    samples: usize,
    input: impl Fn(usize, usize) -> X,
) -> (
    ChainState<[F::State; L], ChannelBank<T, N, L>>,
    [Estimate<T>; L],
)
where
    F: Stage<T, X> + Copy,
    F::State: Copy,
    X: Copy,
    T: Real,
{
    let single = Chain::new(
        chain.front_end,
        chain
            .observer
            .with_fault_thresholds(FaultThresholds::disabled())
            .unwrap(),
    );
    let mut bank = ChainState {
        front_end: [front_end; L],
        observer: ChannelBank::new(),
    };
    let mut states = [ChainState {
        front_end,
        observer: ObserverState::new(),
    }; L];
    let mut last = [Estimate::default(); L];
    for k in 0..samples {
        let inputs: [X; L] = core::array::from_fn(|lane| input(k, lane));
        last = chain.update_bank(&mut bank, &inputs);
        for lane in 0..L {
            let e = single.update(&mut states[lane], inputs[lane]);
            assert_eq!(last[lane], e, "lane {lane}, sample {k}");
        }
    }
    for (lane, single) in states.iter().enumerate() {
        assert_eq!(
            bank.observer.latched_faults()[lane],
            Faults::from_bits_truncate(
                single.observer.latched_faults().bits() & !Faults::BAD_SAMPLE.bits()
            ),
            "lane {lane}"
        );
    }
    (bank, last)
}

/// 12-bit offset-binary counts of a sensor with offsets and imbalance; lane 2 clipped on
/// both channels (0 counts) for samples 600 to 649.
fn counts(k: usize, lane: usize) -> (u16, u16) {
    if lane == 2 && (600..650).contains(&k) {
        return (0, 0);
    }
    let t = theta(k, lane);
    let count = |v: f64| libm::round(2048.0 + 2048.0 * v) as u16;
    (
        count(0.8 * (0.02 + libm::cos(t))),
        count(0.8 * (-0.01 + 1.05 * libm::sin(t))),
    )
}

#[test]
fn a_bank_of_adc_calibration_and_clipping_chains_gives_the_single_chains_results() {
    fn check<T: Real>() {
        let gains = Gains::<T, 3>::new(
            [T::from_f64(0.06), T::from_f64(0.0019), T::from_f64(3e-5)],
            T::from_f64(TS),
        )
        .unwrap();
        let adc = AdcScaling::<T>::offset_binary(12).unwrap();
        let stored = SensorCalibration::new(
            T::from_f64(0.016),
            T::from_f64(-0.008),
            T::from_f64(0.8),
            T::from_f64(0.84),
            T::ZERO,
        )
        .unwrap();
        let check = FrontEndCheck::around((adc, stored), Some((0u16, 4095u16))).unwrap();
        let chain = Chain::new(check, gains);
        let (bank, last) = run_beside_single_chains(chain, Default::default(), 2000, counts);
        // The clipped lane coasted through its fault and tracks again, as the others.
        assert!(bank.observer.latched_faults()[2].contains(Faults::FRONT_END));
        for (lane, e) in last.iter().enumerate() {
            let error = libm::sin(e.angle.to_f64() - theta(1999, lane)).abs();
            assert!(error < 2e-3, "lane {lane}: {error}");
        }
    }
    check::<f32>();
    check::<f64>();
}

#[test]
fn a_bank_of_learning_calibrations_gives_the_single_chains_results() {
    let gains = Gains::<f64, 3>::new([0.06, 0.0019, 3e-5], TS).unwrap();
    let online = OnlineCalibration::new(CalibrationSettings::default(), TS).unwrap();
    let chain = Chain::new(online, gains);
    let mut learning = Calibrator::default();
    learning.enable();
    let (bank, _) = run_beside_single_chains(chain, learning, 4000, |k, lane| {
        let t = theta(k, lane);
        (0.05 + libm::cos(t), -0.05 + 1.1 * libm::sin(t + 0.05))
    });
    // Every lane learned its sensor's offsets.
    for (lane, front_end) in bank.front_end.iter().enumerate() {
        let (o_c, o_s) = front_end.calibration().offsets();
        assert!(
            (o_c - 0.05).abs() < 5e-3 && (o_s + 0.05).abs() < 5e-3,
            "lane {lane}"
        );
    }
}

#[test]
fn a_lane_of_bad_samples_is_rejected_and_coasts_while_the_others_track() {
    let gains = Gains::<f64, 3>::new([0.06, 0.0019, 3e-5], TS).unwrap();
    let stored = SensorCalibration::new(0.02, -0.01, 1.0, 1.05, 0.0).unwrap();
    let chain = Chain::new(stored, gains);
    let bad = |k: usize, lane: usize| lane == 1 && (500..520).contains(&k);
    let (bank, last) = run_beside_single_chains(chain, (), 1000, |k, lane| {
        let t = theta(k, lane);
        let y_c = 0.02 + libm::cos(t);
        let y_s = -0.01 + 1.05 * libm::sin(t);
        match (bad(k, lane), k % 2) {
            (true, 0) => (f64::NAN, y_s),
            (true, _) => (y_c, 9.0), // above the input bound
            _ => (y_c, y_s),
        }
    });
    for (lane, e) in last.iter().enumerate() {
        let error = libm::sin(e.angle - theta(999, lane)).abs();
        assert!(error < 1e-3, "lane {lane}: {error}");
    }
    assert_eq!(bank.observer.rejected(), [false; L]);

    // On a bad sample the lane is rejected and coasts: its angle moves by its speed.
    let mut bank = bank;
    let before = bank.observer.angles();
    let inputs: [(f64, f64); L] = core::array::from_fn(|lane| {
        let t = theta(1000, lane);
        if lane == 1 {
            (f64::NAN, 0.0)
        } else {
            (0.02 + libm::cos(t), -0.01 + 1.05 * libm::sin(t))
        }
    });
    let e = chain.update_bank(&mut bank, &inputs);
    assert_eq!(bank.observer.rejected(), [false, true, false, false]);
    assert!(e[1].faults.contains(Faults::BAD_SAMPLE));
    let moved = e[1].angle - before[1];
    assert!((moved - e[1].speed * TS).abs() < 1e-6, "{moved}");
}
