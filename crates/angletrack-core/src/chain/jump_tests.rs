//! The re-acquisition after a coast whose jump is implausible (a quarter turn or more
//! after a coast of at most 64 samples, `update.rs`): flagged [`Faults::LOSS_OF_TRACKING`]
//! and held for the window under way and the next 16, while a plausible one is not.

use crate::*;

/// 20 kHz pairs, the campaign's gains and amplitude.
const TS: f64 = 50e-6;
const GAINS: [f64; 3] = [0.1578, 0.0126, 0.000_34];
const AMPLITUDE: f64 = 0.8;
/// 50 Hz electrical (rad per pair).
const STEP: f64 = core::f64::consts::TAU * 50.0 * TS;

/// The f32 chain with the winding check and the monitor at the amplitude.
fn winding_chain() -> Chain<WindingCheck<f32>, Gains<f32, 3>> {
    let a = AMPLITUDE as f32;
    let gains = Gains::<f32, 3>::new(GAINS.map(|g| g as f32), TS as f32)
        .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(a)))
        .unwrap();
    Chain::new(WindingCheck::new(a).unwrap(), gains)
}

/// The f64 chain that takes the front end's faults with the pairs.
fn given_chain() -> Chain<FrontEndCheck<f64>, Gains<f64, 3>> {
    let gains = Gains::<f64, 3>::new(GAINS, TS)
        .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(AMPLITUDE)))
        .unwrap();
    Chain::new(FrontEndCheck::new(), gains)
}

fn error(angle: f64, theta: f64) -> f64 {
    libm::remainder(angle - theta, core::f64::consts::TAU).abs()
}

#[test]
fn a_dead_cosine_channel_from_the_start_is_flagged_once_the_healthy_winding_crosses_zero() {
    // The loop follows the faulty pair (0, A sin theta) at +-pi/2; at each zero crossing of
    // the sine winding the winding check coasts and the loop re-acquires half a turn away.
    let chain = winding_chain();
    let mut state = ChainState::new();
    let (mut wrong, mut missed) = (0, 0);
    for k in 0..8000 {
        let theta = 0.3 + STEP * k as f64;
        let pair = (0.0, (AMPLITUDE * libm::sin(theta)) as f32);
        let e = chain.update(&mut state, pair);
        // From the first crossing's re-acquisition (theta = pi, k = 182) on.
        if k > 250 && error(f64::from(e.angle), theta) > 0.05 {
            wrong += 1;
            missed += usize::from(e.faults.is_empty());
        }
    }
    assert!(wrong > 7000, "{wrong} wrong");
    assert_eq!(missed, 0, "{missed} of {wrong} wrong pairs unflagged");
    assert!(
        state
            .observer
            .latched_faults()
            .contains(Faults::LOSS_OF_TRACKING)
    );
}

#[test]
fn a_short_open_winding_on_a_tracking_loop_is_no_loss_of_tracking() {
    // The cosine winding opens for 5 pairs where it carries most of the signal: the check
    // coasts, the re-acquisition moves the angle by the coast's drift alone.
    let chain = winding_chain();
    let mut state = ChainState::new();
    let mut front_end = false;
    for k in 0..6000 {
        let theta = STEP * k as f64;
        let open = (4000..4005).contains(&k);
        let c = if open {
            0.0
        } else {
            AMPLITUDE * libm::cos(theta)
        };
        let e = chain.update(
            &mut state,
            (c as f32, (AMPLITUDE * libm::sin(theta)) as f32),
        );
        front_end |= e.faults.contains(Faults::FRONT_END);
        if k == 3000 {
            state.observer.clear_faults();
        }
        if k > 3000 {
            assert!(error(f64::from(e.angle), theta) < 0.05, "pair {k}");
        }
    }
    // theta at pair 4000 is 20 pi: the cosine winding carries all of it.
    assert!(front_end);
    let latched = state.observer.latched_faults();
    assert!(
        !latched.intersects(Faults::LOSS_OF_TRACKING | Faults::FALSE_LOCK),
        "{latched}"
    );
}

/// Runs the f64 chain at 50 Hz with the excitation lost for `coast` pairs from pair 3000,
/// the pair then half a turn from the shaft's angle (`theta + pi`); returns each pair's
/// faults from 3000 on.
fn jump_after_coast(coast: usize) -> [Faults; 1000] {
    let chain = given_chain();
    let mut state = ChainState::new();
    let mut faults = [Faults::NONE; 1000];
    for k in 0..4000 {
        let theta = STEP * k as f64;
        let lost = (3000..3000 + coast).contains(&k);
        let shifted = if k >= 3000 {
            theta + core::f64::consts::PI
        } else {
            theta
        };
        let (pair, given) = if lost {
            ((0.0, 0.0), FrontEndFaults::LOSS_OF_EXCITATION)
        } else {
            let pair = (libm::cos(shifted), libm::sin(shifted));
            (
                (AMPLITUDE * pair.0, AMPLITUDE * pair.1),
                FrontEndFaults::NONE,
            )
        };
        let e = chain.update(&mut state, (pair, given));
        if k >= 3000 {
            faults[k - 3000] = e.faults;
        }
    }
    faults
}

#[test]
fn a_jump_of_half_a_turn_after_a_short_coast_is_flagged_and_held() {
    let faults = jump_after_coast(3);
    // The pair after the coast and every one for the window under way and the next 16
    // (at most 16 + 16 x 16 pairs), then cleared: the pair is healthy again.
    for (i, f) in faults[3..3 + 16 * 17 - 15].iter().enumerate() {
        assert!(f.contains(Faults::LOSS_OF_TRACKING), "pair {i} after: {f}");
    }
    assert!(faults[3 + 16 * 18..].iter().all(|f| f.is_empty()));
    // Without the jump, no flag after the coast.
    let plausible = {
        let chain = given_chain();
        let mut state = ChainState::new();
        let mut after = Faults::NONE;
        for k in 0..4000 {
            let theta = STEP * k as f64;
            let lost = (3000..3003).contains(&k);
            let (pair, given) = if lost {
                ((0.0, 0.0), FrontEndFaults::LOSS_OF_EXCITATION)
            } else {
                let pair = (AMPLITUDE * libm::cos(theta), AMPLITUDE * libm::sin(theta));
                (pair, FrontEndFaults::NONE)
            };
            let e = chain.update(&mut state, (pair, given));
            if k >= 3003 {
                after |= e.faults;
            }
        }
        after
    };
    assert_eq!(plausible, Faults::NONE);
}

#[test]
fn a_jump_after_a_coast_of_up_to_64_pairs_is_flagged_beyond_the_refit() {
    // 40 pairs: the fit's 16 pairs carry loss of tracking anyway; the jump holds it on.
    let faults = jump_after_coast(40);
    assert!(faults[40 + 100].contains(Faults::LOSS_OF_TRACKING));
    // 100 pairs: a coast that long may drift anywhere; after the fit, no flag.
    let faults = jump_after_coast(100);
    assert!(faults[100 + 100..].iter().all(|f| f.is_empty()));
}
