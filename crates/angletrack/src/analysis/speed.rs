//! Speed limits (`docs/theory.md §9`): the largest speed an observer tracks, stated once,
//! and the largest speed step the nonlinear loop acquires from rest.

use core::f64::consts::PI;

use angletrack_core::{Chain, ChainState, Gains, ObserverState};

use crate::error::{Argument, Error, positive};

/// The largest speed (rad/s) an observer sampled every `sample_period_s` (s) tracks: the
/// Nyquist speed `pi / Ts`, half a turn per sample (`docs/theory.md §9`).
///
/// Below it the samples `(cos theta_k, sin theta_k)` determine the speed: an observer
/// started at any speed up to it, or brought up to it by an acceleration its loop follows,
/// tracks without a cycle slip (tested for the three observers of
/// [`paper::ComparedObserver`](crate::paper::ComparedObserver)). Above it, `Omega` and
/// `Omega - 2 pi / Ts` give the same samples. A loop already locked still follows by
/// continuity, since its prediction carries the speed and the phase detector sees only the
/// prediction error (the same observers, ramped at 2000 rad/s^2, track to 2.5 `pi / Ts`),
/// but nothing in the samples confirms the speed any more: any acquisition with an unknown
/// speed locks onto an alias, and
/// [`ObserverState::at`](angletrack_core::ObserverState::at) limits a starting speed to
/// this one. It is an upper bound: how fast a given loop acquires a speed step from rest is
/// [`DesignReport::acquisition_speed_rad_s`](crate::DesignReport::acquisition_speed_rad_s),
/// and the monitor raises `LOSS_OF_TRACKING` from half of it by default, keeping a quarter
/// turn per sample of margin to the alias boundary (`§9`, the monitor's threshold).
///
/// A period that is not finite and positive is refused.
///
/// ```
/// let limit = angletrack::max_trackable_speed_rad_s(1e-4)?; // 10 kHz
/// assert!((limit - 31_415.926).abs() < 1e-3);               // 5000 turns per second
/// assert!(angletrack::max_trackable_speed_rad_s(0.0).is_err());
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn max_trackable_speed_rad_s(sample_period_s: f64) -> Result<f64, Error> {
    Ok(PI / positive(sample_period_s, Argument::SamplePeriod)?)
}

/// The nonlinear loop (the core's observer) from rest at angle 0, fed `truth(k)`, returns the
/// unwrapped estimated angles.
pub(super) fn simulate_nonlinear<const N: usize>(
    gains: &Gains<f64, N>,
    samples: usize,
    truth: impl Fn(usize) -> f64,
) -> impl Iterator<Item = f64> {
    let chain = Chain::new((), *gains);
    // At rest at angle 0: within every limit, for the gains' checked sample period.
    let observer = ObserverState::at(0.0, 0.0, 0.0, gains.sample_period())
        .unwrap_or_else(|e| unreachable!("a state at rest is valid: {e}"));
    let mut state = ChainState {
        front_end: (),
        observer,
    };
    (0..samples).map(move |k| {
        let (s, c) = truth(k).sin_cos();
        chain.update(&mut state, (c, s)).position()
    })
}

/// The largest speed step acquired from rest without a cycle slip, at most the largest
/// trackable speed `top` (rad/s), see [`DesignReport::acquisition_speed_rad_s`].
pub(super) fn acquisition_speed<const N: usize>(
    gains: &Gains<f64, N>,
    samples: usize,
    top: f64,
) -> f64 {
    let ts = gains.sample_period();
    let acquires = |speed: f64| {
        let step = speed * ts;
        let last = simulate_nonlinear(gains, samples, |k| step * k as f64)
            .last()
            .unwrap_or(0.0);
        (last - step * (samples - 1) as f64).abs() < 0.1
    };
    if acquires(top) {
        return top;
    }
    let (mut lo, mut hi) = (top * 1e-6, top);
    if !acquires(lo) {
        return 0.0;
    }
    // 16 halvings of the logarithmic interval: a relative resolution of 2e-4.
    for _ in 0..16 {
        let mid = (lo * hi).sqrt();
        if acquires(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}
