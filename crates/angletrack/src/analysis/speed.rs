//! Speed limits of the nonlinear loop (`docs/theory.md §9`).

use core::f64::consts::PI;

use angletrack_core::{Gains, ObserverState, Order, SupportedOrder};

/// The nonlinear loop (the core's observer) from rest at angle 0, fed `truth(k)`, returns the
/// unwrapped estimated angles.
pub(super) fn simulate_nonlinear<const N: usize>(
    gains: &Gains<f64, N>,
    samples: usize,
    truth: impl Fn(usize) -> f64,
) -> impl Iterator<Item = f64>
where
    Order<N>: SupportedOrder,
{
    let gains = *gains;
    let mut state = ObserverState::at(0.0, 0.0, 0.0, gains.sample_period());
    (0..samples).map(move |k| {
        let (s, c) = truth(k).sin_cos();
        gains.update(&mut state, c, s).position()
    })
}

/// The largest speed step acquired from rest without a cycle slip, see
/// [`DesignReport::acquisition_speed_rad_s`].
pub(super) fn acquisition_speed<const N: usize>(gains: &Gains<f64, N>, samples: usize) -> f64
where
    Order<N>: SupportedOrder,
{
    let ts = gains.sample_period();
    let acquires = |speed: f64| {
        let step = speed * ts;
        let last = simulate_nonlinear(gains, samples, |k| step * k as f64)
            .last()
            .unwrap_or(0.0);
        (last - step * (samples - 1) as f64).abs() < 0.1
    };
    let top = PI / ts;
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
