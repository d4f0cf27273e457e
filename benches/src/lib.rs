//! The workload that the benchmarks (`benches/update.rs`) and the firmware test
//! (`tests/firmware`) share: the three observers of the paper with fixed discrete gains, a
//! simulated resolver (from the `angletrack` crate's scenario generator), and the
//! hand-written loop every report is compared with.
//!
//! Nothing here is published: it exists so that the host benchmark, the Cortex-M4F
//! instruction count and the firmware's reference data all run the very same observers on
//! the very same signal.

use angletrack::{Motion, MotionProfile, Scenario, SensorModel, paper};
use angletrack_core::{Gains, Order, Real, SinCos, SupportedOrder};
use num_traits::Float;

/// Sample period of every benchmark and of the firmware test (s): a 10 kHz loop.
pub const SAMPLE_PERIOD_S: f64 = paper::BENCHMARK_SAMPLE_PERIOD_S;

/// Discrete gains `(l1, l2)` of the classical 2nd-order ATO (see
/// [`paper::BENCHMARK_SECOND_ORDER_GAINS`]; the gains of the core's `track_resolver` example).
pub const SECOND_ORDER_GAINS: [f64; 2] = paper::BENCHMARK_SECOND_ORDER_GAINS;

/// Discrete gains `(l1, l2, l3)` of the 3rd-order ATO designed by pole placement (see
/// [`paper::BENCHMARK_THIRD_ORDER_GAINS`]).
pub const THIRD_ORDER_GAINS: [f64; 3] = paper::BENCHMARK_THIRD_ORDER_GAINS;

/// Discrete gains `(l1, l2, l3)` of the time-invariant Kalman ATO (see
/// [`paper::BENCHMARK_KALMAN_GAINS`]).
pub const KALMAN_GAINS: [f64; 3] = paper::BENCHMARK_KALMAN_GAINS;

/// The three observers, by the name used in benchmark ids and firmware output, with their
/// discrete gains (`l3 = 0` for the 2nd-order loop).
pub const OBSERVERS: [(&str, [f64; 3]); 3] = [
    (
        "second-order",
        [SECOND_ORDER_GAINS[0], SECOND_ORDER_GAINS[1], 0.0],
    ),
    ("third-order", THIRD_ORDER_GAINS),
    ("kalman", KALMAN_GAINS),
];

/// Checked [`Gains`] of order `N` for the discrete gains `l` at [`SAMPLE_PERIOD_S`].
///
/// # Panics
///
/// If `l` is outside the stability region: the constants of this crate are not (tested).
pub fn gains<T: Real, const N: usize, S: SinCos<T>>(l: [f64; N]) -> Gains<T, N, S>
where
    Order<N>: SupportedOrder,
{
    Gains::new(l.map(T::from_f64), T::from_f64(SAMPLE_PERIOD_S))
        .expect("the benchmark gains are inside the stability region")
}

/// The name of a float type as written in ids: `f32` or `f64`.
pub fn float_name<T: Real>() -> &'static str {
    core::any::type_name::<T>()
}

/// Seed of the sensor noise of [`benchmark_scenario`].
pub const SEED: u64 = 0x5eed_1234_abcd_0001;

/// The workload of the benchmarks and the firmware test, from the `angletrack` crate's
/// scenario generator: `samples` samples at [`SAMPLE_PERIOD_S`] of a shaft starting at
/// 0.3 rad and 300 rad/s and accelerating at 400 rad/s^2, read by a resolver with noise
/// 0.01 (standard deviation, per channel, amplitude 1).
///
/// ```
/// let scenario = angletrack_benches::benchmark_scenario(1000);
/// assert_eq!(scenario.len(), 1000);
/// assert!((scenario.speed_rad_s[999] - (300.0 + 400.0 * 999e-4)).abs() < 1e-9);
/// ```
///
/// # Panics
///
/// If `samples` is above [`angletrack::MAX_SAMPLES`].
pub fn benchmark_scenario(samples: usize) -> Scenario {
    let profile = MotionProfile::new(0.3, 300.0).then(Motion::ConstantAcceleration {
        acceleration_rad_s2: 400.0,
        duration_s: samples as f64 * SAMPLE_PERIOD_S,
    });
    let mut scenario = Scenario::generate(
        &profile,
        &SensorModel::with_noise(0.01),
        SAMPLE_PERIOD_S,
        SEED,
    )
    .expect("the benchmark scenario is valid");
    for v in [
        &mut scenario.time_s,
        &mut scenario.angle_rad,
        &mut scenario.speed_rad_s,
        &mut scenario.acceleration_rad_s2,
        &mut scenario.y_c,
        &mut scenario.y_s,
    ] {
        v.truncate(samples);
    }
    scenario
}

/// The two channels `(y_c, y_s)` of `scenario` converted to `T`.
pub fn channels<T: Real>(scenario: &Scenario) -> (Vec<T>, Vec<T>) {
    let convert = |v: &[f64]| v.iter().map(|&x| T::from_f64(x)).collect();
    (convert(&scenario.y_c), convert(&scenario.y_s))
}

/// The loop a user writes by hand for the same observer, the baseline of every benchmark:
/// one struct with the angle, speed and acceleration in physical units, the standard
/// library's `sin_cos`, and an explicit wrap of the angle (no turn count, no checks).
///
/// It is the same recursion as the core's (the gains are converted to physical units:
/// `k_theta = l1`, `k_omega = l2 / Ts`, `k_alpha = l3 / Ts^2`); for the 2nd-order loop
/// `l3 = 0` and the acceleration stays 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandWrittenObserver<T> {
    /// Angle (rad), wrapped to [-pi, pi).
    pub theta: T,
    /// Speed (rad/s).
    pub omega: T,
    /// Acceleration (rad/s^2).
    pub alpha: T,
    k_theta: T,
    k_omega: T,
    k_alpha: T,
    ts: T,
    half_ts2: T,
}

impl<T: Float> HandWrittenObserver<T> {
    /// The observer with discrete gains `l` at [`SAMPLE_PERIOD_S`], starting at `angle_rad`,
    /// `speed_rad_s` and `acceleration_rad_s2` (ignored by the 2nd-order loop, `l3 = 0`,
    /// whose model has no acceleration).
    pub fn new(l: [f64; 3], angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64) -> Self {
        let f = |v: f64| T::from(v).unwrap_or_else(T::nan);
        let ts = SAMPLE_PERIOD_S;
        let pi = core::f64::consts::PI;
        Self {
            theta: f((angle_rad + pi).rem_euclid(core::f64::consts::TAU) - pi),
            omega: f(speed_rad_s),
            alpha: f(if l[2] == 0.0 {
                0.0
            } else {
                acceleration_rad_s2
            }),
            k_theta: f(l[0]),
            k_omega: f(l[1] / ts),
            k_alpha: f(l[2] / (ts * ts)),
            ts: f(ts),
            half_ts2: f(0.5 * ts * ts),
        }
    }

    /// One sample: predict, phase detector (normalised by the sample's magnitude, as the
    /// core's amplitude-invariant loop is: docs/theory.md §12), correct, wrap. Returns
    /// `(angle, speed)`.
    #[inline]
    pub fn update(&mut self, y_c: T, y_s: T) -> (T, T) {
        let pi = T::from(core::f64::consts::PI).unwrap_or_else(T::nan);
        let theta_p = self.theta + self.omega * self.ts + self.alpha * self.half_ts2;
        let omega_p = self.omega + self.alpha * self.ts;
        let (sin, cos) = theta_p.sin_cos();
        let eps = (y_s * cos - y_c * sin) / (y_c * y_c + y_s * y_s).sqrt();
        self.theta = theta_p + self.k_theta * eps;
        self.omega = omega_p + self.k_omega * eps;
        self.alpha = self.alpha + self.k_alpha * eps;
        if self.theta >= pi {
            self.theta = self.theta - (pi + pi);
        } else if self.theta < -pi {
            self.theta = self.theta + (pi + pi);
        }
        (self.theta, self.omega)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::{Chain, ChainState, Exact, Fast, ObserverState};

    #[test]
    fn gains_are_inside_the_stability_region_in_both_float_types() {
        for l in [THIRD_ORDER_GAINS, KALMAN_GAINS] {
            assert!(Gains::<f32, 3, Fast>::new(l.map(|v| v as f32), 1e-4).is_ok());
            assert!(Gains::<f64, 3, Exact>::new(l, 1e-4).is_ok());
        }
        let l = SECOND_ORDER_GAINS;
        assert!(Gains::<f32, 2, Fast>::new(l.map(|v| v as f32), 1e-4).is_ok());
        assert!(Gains::<f64, 2, Exact>::new(l, 1e-4).is_ok());
    }

    /// The baseline computes what the core computes: same recursion, same numbers (to the
    /// rounding of the physical-unit form), so the benchmark ratio compares like with like.
    #[test]
    fn hand_written_baseline_tracks_like_the_core() {
        let signal = benchmark_scenario(4000);
        let (angle, speed) = (signal.angle_rad[0], signal.speed_rad_s[0]);
        let accel = signal.acceleration_rad_s2[0];
        for (name, l) in OBSERVERS {
            let mut hand = HandWrittenObserver::<f64>::new(l, angle, speed, accel);
            let (mut max_angle, mut max_speed) = (0.0f64, 0.0f64);
            let mut check = |e: angletrack_core::Estimate<f64>, (theta, omega): (f64, f64)| {
                let d = (e.angle - theta + 3.0 * core::f64::consts::PI)
                    .rem_euclid(core::f64::consts::TAU)
                    - core::f64::consts::PI;
                max_angle = max_angle.max(d.abs());
                max_speed = max_speed.max((e.speed - omega).abs());
            };
            if l[2] == 0.0 {
                let g: Gains<f64, 2, Exact> = gains([l[0], l[1]]);
                let observer = ObserverState::at(angle, speed, 0.0, SAMPLE_PERIOD_S).unwrap();
                let mut s = ChainState {
                    front_end: (),
                    observer,
                };
                for k in 0..signal.len() {
                    let e = Chain::new((), g).update(&mut s, (signal.y_c[k], signal.y_s[k]));
                    check(e, hand.update(signal.y_c[k], signal.y_s[k]));
                }
            } else {
                let g: Gains<f64, 3, Exact> = gains(l);
                let observer = ObserverState::at(angle, speed, accel, SAMPLE_PERIOD_S).unwrap();
                let mut s = ChainState {
                    front_end: (),
                    observer,
                };
                for k in 0..signal.len() {
                    let e = Chain::new((), g).update(&mut s, (signal.y_c[k], signal.y_s[k]));
                    check(e, hand.update(signal.y_c[k], signal.y_s[k]));
                }
            }
            assert!(max_angle < 1e-9, "{name}: angle differs by {max_angle} rad");
            assert!(
                max_speed < 1e-6,
                "{name}: speed differs by {max_speed} rad/s"
            );
        }
    }
}
