//! The recursion on one channel (`docs/theory.md §5`): tracking without bias where the
//! loop's type allows it, multi-turn resolution, float types, bad samples, and the kept next
//! predicted angle.

extern crate std;

use std::vec::Vec;

use proptest::prelude::*;

use crate::state::predict;
use crate::test_support::{
    Bits, TS, designs, largest_difference, mean, n, proptest_config, run, settling_samples, wrap,
};
use crate::*;

#[test]
fn constant_speed_gives_zero_mean_error_for_all_three_observers() {
    let (o2, o3, ok) = designs();
    let omega = 2.0 * core::f64::consts::PI * 37.0; // 37 rev/s, starts 0.3 rad off
    let theta = |t: f64| (0.3 + omega * t, omega);
    let check = |errors: Vec<(f64, f64)>, name: &str| {
        let tail = &errors[errors.len() / 2..];
        let mean_angle = mean(tail.iter().map(|e| e.0));
        let max_speed = tail.iter().map(|e| e.1.abs()).fold(0.0, f64::max);
        assert!(
            mean_angle.abs() < 1e-9,
            "{name}: mean angle error {mean_angle}"
        );
        assert!(max_speed < 1e-5, "{name}: speed error {max_speed}");
    };
    check(run(&o2, n(40_000), theta), "2nd order");
    check(run(&o3, n(40_000), theta), "3rd order");
    check(run(&ok, n(40_000), theta), "Kalman");
}

#[test]
fn constant_acceleration_biases_only_the_second_order() {
    let (o2, o3, ok) = designs();
    let alpha = 500.0; // rad/s^2
    let theta = |t: f64| (0.5 * alpha * t * t, alpha * t);
    let n = n(40_000);
    let tail = |errors: Vec<(f64, f64)>| mean(errors[n * 3 / 4..].iter().map(|e| e.0));
    // Discrete acceleration constant Ka = l2 / ((1 - l1) Ts^2): the bias is alpha / Ka.
    let [l1, l2] = o2.gains();
    let ka = l2 / ((1.0 - l1) * TS * TS);
    let bias = tail(run(&o2, n, theta));
    assert!(
        (bias / (alpha / ka) - 1.0).abs() < 0.01,
        "bias {bias} vs alpha/Ka {}",
        alpha / ka
    );
    assert!(tail(run(&o3, n, theta)).abs() < 1e-9);
    assert!(tail(run(&ok, n, theta)).abs() < 1e-9);
}

#[test]
fn multi_turn_f32_keeps_full_resolution_after_a_million_turns() {
    // Exact sin/cos isolates the wrapping: 8 samples a turn, 1e6 turns. A loop fast enough
    // that the f32 state quantisation (a limit cycle of a few ulps for slow loops) stays
    // below an ulp of the angle.
    let gains = Gains::<f32, 3, Exact>::new([0.3, 0.04, 0.002], TS as f32).unwrap();
    let per_turn = 8u64;
    let step = core::f64::consts::TAU / per_turn as f64;
    let mut state = ObserverState::<f32, 3>::at(0.0, (step / TS) as f32, 0.0, TS as f32).unwrap();
    let turns = if cfg!(miri) { 100 } else { 1_000_000u64 };
    let mut worst = 0.0f64;
    for k in 1..=turns * per_turn {
        let phase = (k % per_turn) as f64 * step; // exact truth, wrapped
        let e = gains.update(&mut state, phase.cos() as f32, phase.sin() as f32);
        if k > (turns - 10) * per_turn {
            worst = worst.max(wrap(phase - e.angle as f64).abs());
        }
        assert!(e.angle >= -core::f32::consts::PI && e.angle < core::f32::consts::PI);
    }
    let last = gains.estimate(&state);
    assert_eq!(last.turns, turns as i64);
    // Full f32 resolution: an ulp near pi is 2.4e-7 rad; a naive f32 multi-turn angle
    // (6.3e6 rad) would have an ulp of 0.5 rad. What remains is the f32 loop's own rounding
    // noise at 8 samples a turn: 0.87e-6 rad at worst over these last 10 turns, up to 1.0e-6
    // over 10^5 turns; keeping the next predicted angle in the state reorders one sum and
    // does not add to it. So the bound is 5 ulp. Miri perturbs std's f64 cos/sin (used for
    // the truth here) by a few ulps on purpose.
    let ulps = if cfg!(miri) { 6.0 } else { 5.0 };
    assert!(worst < ulps * 2.4e-7, "worst wrapped-angle error {worst}");
}

#[test]
fn f32_and_f64_agree_within_f32_precision() {
    let (_, _, ok) = designs();
    let g32 = Gains::<f32, 3, Exact>::new(ok.gains().map(|g| g as f32), TS as f32).unwrap();
    let theta = |t: f64| (1.0 + 200.0 * t + 300.0 * t * t, 200.0 + 600.0 * t);
    let e64 = run(&ok, n(20_000), theta);
    let e32 = run(&g32, n(20_000), theta);
    let angle = largest_difference(&e64, &e32, |e| e.0);
    let speed = largest_difference(&e64, &e32, |e| e.1);
    assert!(angle < 2e-5, "angle differs by {angle}");
    // Speed is x2 / Ts: f32 rounding of x2 (~1e-7 relative) times 1/Ts.
    assert!(speed < 0.05, "speed differs by {speed}");
}

#[test]
fn non_finite_samples_leave_the_state_finite() {
    let (_, _, ok) = designs();
    let mut state = ObserverState::new();
    for k in 0..1000 {
        let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][k % 3];
        let e = ok.update(&mut state, if k % 2 == 0 { bad } else { 1.0 }, bad);
        assert!(e.angle.is_finite() && e.speed.is_finite() && e.acceleration.is_finite());
    }
}

#[test]
fn first_sample_initialises_from_atan2_in_every_quadrant() {
    let (o2, _, _) = designs();
    for i in 0..16 {
        let theta = -3.0 + 0.4 * i as f64;
        let chain = Chain::new((), o2);
        let mut state = ChainState::new();
        let e = chain.update(&mut state, (theta.cos(), theta.sin()));
        assert!((e.angle - theta).abs() < 1e-12);
    }
}

fn junk_keeps_state_finite<T: Real, const N: usize>(gains: Gains<T, N>, samples: usize, seed: u64) {
    let mut bits = Bits(seed);
    let mut state = ObserverState::new();
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e30,
        -1e30,
        5.0,
        f64::MAX,
        1e-300,
    ];
    let mut bad = 0usize;
    for k in 0..samples {
        let theta = 0.001 * k as f64;
        let (mut c, mut s) = (theta.cos(), theta.sin());
        let r = bits.next();
        if r.is_multiple_of(4) {
            c = specials[(r >> 8) as usize % specials.len()];
        }
        if r.is_multiple_of(7) {
            s = specials[(r >> 16) as usize % specials.len()];
        }
        if r.is_multiple_of(11) {
            c = (bits.unit() - 0.5) * 1e6;
        }
        let e = gains.update(&mut state, T::from_f64(c), T::from_f64(s));
        bad += e.faults.contains(Faults::BAD_SAMPLE) as usize;
        for v in state.scaled_state() {
            assert!(
                v.is_finite(),
                "state {:?} at sample {k}",
                state.scaled_state()
            );
        }
        assert!(e.angle.is_finite() && e.speed.is_finite() && e.acceleration.is_finite());
        assert!(e.phase_error.is_finite() && state.next_angle.is_finite());
        assert!(e.angle >= -T::PI && e.angle < T::PI);
    }
    assert!(
        bad > samples / 5,
        "the junk was rejected: {bad} of {samples}"
    );
}

#[test]
fn a_million_junk_samples_keep_every_state_finite() {
    let samples = if cfg!(miri) { 800 } else { 1_000_000 };
    let (o2, o3, ok) = designs();
    junk_keeps_state_finite(o2, samples, 1);
    junk_keeps_state_finite(o3, samples / 4, 2);
    junk_keeps_state_finite(ok, samples / 4, 3);
    let f32_gains = Gains::<f32, 3>::new(ok.gains().map(|g| g as f32), TS as f32).unwrap();
    junk_keeps_state_finite(f32_gains, samples / 4, 4);
}

#[test]
fn observers_relock_within_their_settling_time_after_a_burst_of_bad_samples() {
    let (o2, o3, ok) = designs();
    fn check<const N: usize>(gains: Gains<f64, N>, name: &str) {
        let settling = settling_samples(&gains);
        let (speed, accel) = (120.0, 40.0);
        let theta = |k: usize| {
            let t = k as f64 * TS;
            0.2 + speed * t + 0.5 * accel * t * t
        };
        let mut state = ObserverState::new();
        let mut last_outside = 0;
        let (start, end) = (n(3000), n(3000) + n(200).max(5));
        for k in 0..2 * start + 4 * settling {
            let a = theta(k);
            let (c, s) = if (start..end).contains(&k) {
                (f64::NAN, 1e9)
            } else {
                (a.cos(), a.sin())
            };
            let e = gains.update(&mut state, c, s);
            if (start..end).contains(&k) {
                assert_eq!(e.faults, Faults::BAD_SAMPLE);
            } else if k > end && wrap(a - e.angle).abs() > 0.02 * core::f64::consts::PI {
                last_outside = k;
            }
        }
        assert!(
            last_outside < end + settling,
            "{name}: relocked {} samples after the burst, settling time {settling}",
            last_outside.saturating_sub(end)
        );
        assert!(state.latched_faults().contains(Faults::BAD_SAMPLE));
    }
    check(o2, "2nd order");
    check(o3, "3rd order");
    check(ok, "Kalman");
}

#[test]
fn a_state_at_the_largest_speed_and_acceleration_stays_finite_while_coasting() {
    // The largest float speed and acceleration, x = (0, 3.4e38, 1.9e38), would overflow in
    // the prediction: `at` refuses them, and holds half a turn per sample (and per
    // sample^2), the most a sampled loop represents.
    let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4).unwrap();
    let refused = ObserverState::<f32, 3>::at(0.0, f32::MAX, 0.0, 1e-4).unwrap_err();
    assert_eq!(refused.parameter(), Parameter::InitialSpeed);
    let refused = ObserverState::<f32, 3>::at(0.0, 0.0, f32::MAX, 1e-4).unwrap_err();
    assert_eq!(refused.parameter(), Parameter::InitialAcceleration);
    let pi = core::f32::consts::PI;
    let mut state = ObserverState::at(0.0, pi / 1e-4, pi / 1e-8, 1e-4).unwrap();
    assert!((state.scaled_state()[1] - pi).abs() < 1e-5);
    for _ in 0..n(10_000) {
        gains.update(&mut state, f32::NAN, 0.0);
        assert!(
            state.scaled_state().iter().all(|x| x.is_finite()),
            "{state:?}"
        );
    }
}

/// The predicted angle a state keeps for the next sample is the prediction of its corrected
/// state, `(A x)[0]`, in the same turn and to within rounding, after every kind of update:
/// initialisation, tracking across many turns, coasting over rejected samples, and the jump
/// of a false-lock re-acquisition (all of which the run is checked to go through).
#[test]
fn the_next_predicted_angle_is_the_prediction_of_the_corrected_state() {
    fn check<T: Real, const N: usize>(gains: Gains<T, N>, tolerance: f64) {
        let mut bits = Bits(0x5eed);
        let mut state = ObserverState::new();
        let mut latched = Faults::NONE;
        let mut turns = 0;
        let samples = n(20_000);
        for k in 0..samples {
            // 300 rad/s, then a 180 degree jump of the true angle half way (a false lock).
            let jump = if k >= samples / 2 {
                core::f64::consts::PI
            } else {
                0.0
            };
            let theta = 0.03 * k as f64 + jump;
            let noise = 0.01 * (bits.unit() - 0.5);
            let (mut c, s) = (theta.cos() + noise, theta.sin() - noise);
            if k % 1000 >= 990 {
                c = f64::NAN; // a burst of broken reads: the state coasts
            }
            let e = gains.update(&mut state, T::from_f64(c), T::from_f64(s));
            latched |= e.faults;
            turns = e.turns;
            let predicted = predict(&state.x)[0].to_f64();
            let kept = state.predicted_angle().to_f64();
            assert!(
                (kept - predicted).abs() <= tolerance,
                "sample {k}: next angle {kept}, prediction of the state {predicted}"
            );
        }
        assert!(
            latched.contains(Faults::BAD_SAMPLE | Faults::FALSE_LOCK),
            "{latched}"
        );
        assert!(turns.abs() > 5, "the run crossed {turns} turns");
    }
    // Discrete gains fixed per sample (not designed for TS, which Miri changes), so that the
    // loop's dynamics per sample, and so the false lock, are the same under Miri.
    check(Gains::<f64, 2>::new([0.06, 0.001], TS).unwrap(), 1e-13);
    check(
        Gains::<f64, 3>::new([0.094, 5.6e-4, 1.2e-5], TS).unwrap(),
        1e-13,
    );
    check(
        Gains::<f64, 3>::new([0.061, 0.0019, 3.1e-5], TS).unwrap(),
        1e-13,
    );
    check(
        Gains::<f32, 3>::new([0.061, 0.0019, 3.1e-5], TS as f32).unwrap(),
        2e-6,
    );
}

proptest! {
    #![proptest_config(proptest_config())]

    #[test]
    fn whole_turns_added_to_the_truth_change_only_the_turn_count(
        theta0 in -3.0..3.0f64, speed in -300.0..300.0f64, n in -1000i64..1000,
    ) {
        let (_, _, ok) = designs();
        let shifted = theta0 + n as f64 * core::f64::consts::TAU;
        let mut a = ObserverState::at(theta0, speed, 0.0, TS).unwrap();
        let mut b = ObserverState::at(shifted, speed, 0.0, TS).unwrap();
        prop_assert_eq!(b.turns() - a.turns(), n);
        for k in 1..crate::test_support::n(300).max(20) {
            let t = k as f64 * TS;
            let (ya, yb) = (theta0 + speed * t, shifted + speed * t);
            let ea = ok.update(&mut a, ya.cos(), ya.sin());
            let eb = ok.update(&mut b, yb.cos(), yb.sin());
            prop_assert_eq!(eb.turns - ea.turns, n);
            prop_assert!(wrap(ea.angle - eb.angle).abs() < 1e-9);
            prop_assert!((ea.speed - eb.speed).abs() < 1e-5);
        }
    }
}
