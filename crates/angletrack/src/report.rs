//! Analysis of a gain set: the design's "datasheet".

use core::f64::consts::PI;
use core::fmt;

use angletrack_core::{FaultThresholds, Gains, ObserverState, Order, SupportedOrder};
use nalgebra::{Complex, DMatrix, DVector};

use crate::design::{Design, DesignMethod, Discretisation, StepResponse, continuous_step};
use crate::error::{Argument, Error, non_negative};
use crate::linalg;

/// The step size of the large-signal step response: 179 degrees (rad). A 180 degree step
/// would start on the loop's unstable equilibrium (`eps = 0`).
pub const LARGE_STEP_RAD: f64 = 179.0 * PI / 180.0;

/// The settling band of the reported settling times (fraction of the step).
pub const SETTLING_BAND: f64 = 0.02;

/// Longest simulation (samples) used for a step response or one acquisition trial.
const MAX_SIMULATION_SAMPLES: usize = 4_000_000;

/// Everything the analysis predicts about a gain set, in physical units.
///
/// Built by [`DesignReport::new`]; `Display` renders it as a table. All fields are public and
/// plain (`f64`, `Vec`, `Option`) for the Python bindings.
///
/// The linearised loop: for small errors the phase detector gives `eps = theta - x1_p + w`
/// (input amplitude 1), where `w = w_s cos x1_p - w_c sin x1_p` has variance
/// `r = sensor_noise_std^2` whatever the angle. The filtered estimate then follows
/// `x_e[k] = F x_e[k-1] + L theta[k]` with `F = (I - L e1^T) A`.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignReport {
    /// The design rule.
    pub method: DesignMethod,
    /// The mapping of a continuous design.
    pub discretisation: Option<Discretisation>,
    /// Loop order (2 or 3).
    pub order: usize,
    /// Sample period (s).
    pub sample_period_s: f64,
    /// The discrete gains `(l1, l2[, l3])`.
    pub gains: Vec<f64>,
    /// Poles `z_i` of the discrete loop `(I - L e1^T) A`.
    pub discrete_poles: Vec<Complex<f64>>,
    /// Their continuous equivalents `ln(z_i) / Ts` (rad/s).
    pub continuous_equivalent_poles: Vec<Complex<f64>>,
    /// The continuous design's poles (rad/s); empty for Kalman and given gains.
    pub design_poles: Vec<Complex<f64>>,
    /// Largest relative distance `|ln(z_i)/Ts - s_i| / |s_i|` between the continuous
    /// equivalent and the design's poles: 0 for pole matching, the mapping's error otherwise.
    pub pole_shift: Option<f64>,
    /// -3 dB bandwidth (Hz) of the closed-loop angle transfer function
    /// `X1_e(z) / Theta(z)`: the lowest frequency where its gain falls below `1/sqrt(2)`;
    /// `None` if it stays above up to the Nyquist frequency.
    pub bandwidth_hz: Option<f64>,
    /// Order 2: the discrete acceleration constant `Ka = l2 / ((1 - l1) Ts^2)` (1/s^2); the
    /// steady-state angle error under constant acceleration `alpha` is `alpha / Ka`.
    pub acceleration_constant_per_s2: Option<f64>,
    /// Order 2: the continuous `k_b1` of the design (or, for given gains, the product of the
    /// continuous-equivalent poles) (1/s^2).
    pub continuous_acceleration_constant_per_s2: Option<f64>,
    /// Order 3: steady-state angle error (rad) per unit constant jerk (rad/s^3) of the
    /// discrete loop (s^3).
    pub error_per_unit_jerk_s3: Option<f64>,
    /// Order 3: `1 / k_c2` of the continuous design (or the continuous equivalent) (s^3).
    pub continuous_error_per_unit_jerk_s3: Option<f64>,
    /// The sensor noise standard deviation per channel the noise figures are for
    /// (amplitude 1).
    pub sensor_noise_std: f64,
    /// Predicted steady-state RMS angle error (rad) from sensor noise alone (discrete
    /// Lyapunov equation of the linearised loop).
    pub angle_error_rms_rad: f64,
    /// Predicted steady-state RMS speed error (rad/s) from sensor noise alone.
    pub speed_error_rms_rad_s: f64,
    /// Kalman design: `sqrt(P11)` (rad), the smallest RMS angle error of any linear
    /// estimator for the design's model (its own `q` and `r`: random jerk and sensor noise
    /// together, whatever `sensor_noise_std` the report is for).
    pub kalman_angle_floor_rad: Option<f64>,
    /// Kalman design: `sqrt(P22) / Ts` (rad/s).
    pub kalman_speed_floor_rad_s: Option<f64>,
    /// Small-signal (linear) step response of the discrete loop.
    pub linear_step: StepResponse,
    /// Step response of the continuous design, for comparison with `linear_step`.
    pub continuous_step: Option<StepResponse>,
    /// Response of the bare nonlinear loop of the paper (the core's observer, `f64`, exact
    /// sin/cos, diagnostics and re-acquisition disabled) to a [`LARGE_STEP_RAD`]
    /// (179 degree) step from rest.
    pub large_step: StepResponse,
    /// The angle (rad, unwrapped) the bare nonlinear loop ends at after the 179 degree step.
    pub large_step_final_rad: f64,
    /// The same step with the gains' own diagnostics (by default the core's false-lock
    /// detection, which re-acquires the angle from `atan2` once the filtered in-phase
    /// component turns negative): what the firmware does.
    pub large_step_with_diagnostics: StepResponse,
    /// The largest speed (rad/s) the phase detector can follow: `pi / Ts`, half a turn per
    /// sample (beyond it the sampled angle aliases).
    pub max_speed_rad_s: f64,
    /// The largest speed step (rad/s) the bare nonlinear loop acquires from rest (estimate
    /// at the right angle, speed 0) without slipping a cycle: found by bisection on a
    /// logarithmic scale between `1e-6 pi/Ts` and `pi/Ts`, assuming acquisition fails
    /// above a single threshold.
    pub acquisition_speed_rad_s: f64,
}

/// The closed-loop matrices of a discrete gain set.
struct DiscreteLoop {
    l: Vec<f64>,
    ts: f64,
    f: DMatrix<f64>,
}

impl DiscreteLoop {
    fn new(l: &[f64], ts: f64) -> Self {
        Self {
            l: l.to_vec(),
            ts,
            f: linalg::closed_loop(l),
        }
    }

    fn order(&self) -> usize {
        self.l.len()
    }

    /// `I - F = -(A - I) + L e1^T A`, formed without cancellation.
    fn identity_minus_f(&self) -> DMatrix<f64> {
        let n = self.order();
        let d = linalg::transition(n) - DMatrix::identity(n, n);
        let l = DVector::from_column_slice(&self.l);
        -d + l * linalg::e1(n).transpose() * linalg::transition(n)
    }

    /// Steady-state angle error (rad) per unit constant `N`-th derivative of the angle:
    /// `e1^T (I - F)^-1 (I - L e1^T) g Ts^N`.
    fn error_per_unit_derivative(&self) -> Option<f64> {
        let n = self.order();
        let l = DVector::from_column_slice(&self.l);
        let correction = DMatrix::identity(n, n) - l * linalg::e1(n).transpose();
        let rhs = correction * linalg::taylor_remainder(n) * self.ts.powi(n as i32);
        let e = self.identity_minus_f().lu().solve(&rhs)?;
        Some(e[0])
    }

    /// `|X1_e / Theta|` at frequency `hz`: with `s = z - 1`,
    /// `(z I - F) = s I - (A - I) + L e1^T A`, `X_e = z (zI - F)^-1 L Theta`.
    fn gain_at(&self, hz: f64) -> f64 {
        let n = self.order();
        let s = linalg::exp_m1(Complex::new(0.0, 2.0 * PI * hz * self.ts));
        let z = s + 1.0;
        let m = self.identity_minus_f().map(|v| Complex::new(v, 0.0))
            + DMatrix::<Complex<f64>>::identity(n, n) * s;
        let rhs = DVector::from_iterator(n, self.l.iter().map(|&v| z * v));
        m.lu().solve(&rhs).map_or(f64::NAN, |x| x[0].norm())
    }

    /// The -3 dB bandwidth (Hz), see [`DesignReport::bandwidth_hz`].
    fn bandwidth_hz(&self) -> Option<f64> {
        let threshold = core::f64::consts::FRAC_1_SQRT_2;
        let nyquist = 0.5 / self.ts;
        let lowest = nyquist * 1e-9;
        let points = 2000;
        let mut previous = lowest;
        for i in 1..=points {
            let hz = lowest * (nyquist / lowest).powf(i as f64 / points as f64);
            if self.gain_at(hz) < threshold {
                let (mut a, mut b) = (previous, hz);
                for _ in 0..60 {
                    let mid = (a * b).sqrt();
                    if self.gain_at(mid) < threshold {
                        b = mid;
                    } else {
                        a = mid;
                    }
                }
                return Some((a * b).sqrt());
            }
            previous = hz;
        }
        None
    }

    /// The steady-state error covariance of the scaled state for sensor noise variance `r`
    /// and process noise variance `q` (of `Ts^N` times the `N`-th derivative).
    fn error_covariance(&self, r: f64, q: f64) -> Option<DMatrix<f64>> {
        let n = self.order();
        let l = DVector::from_column_slice(&self.l);
        let correction = DMatrix::identity(n, n) - &l * linalg::e1(n).transpose();
        let g = &correction * linalg::taylor_remainder(n);
        let source = &l * l.transpose() * r + &g * g.transpose() * q;
        linalg::discrete_lyapunov(&self.f, &source)
    }

    /// Samples until every transient has decayed by `exp(-16)`.
    fn horizon(&self, continuous_equivalent: &[Complex<f64>]) -> usize {
        let slowest = continuous_equivalent
            .iter()
            .map(|p| -p.re)
            .fold(f64::INFINITY, f64::min);
        let samples = 16.0 / (slowest * self.ts);
        if samples.is_finite() {
            (samples.ceil() as usize).clamp(64, MAX_SIMULATION_SAMPLES)
        } else {
            MAX_SIMULATION_SAMPLES
        }
    }

    /// The linear loop's response to a unit step at sample 0.
    fn linear_step(&self, samples: usize) -> StepResponse {
        let response = linalg::affine_response(self.f.clone(), self.l.clone(), samples);
        StepResponse::from_samples(response, 0.0, 1.0, SETTLING_BAND, self.ts)
    }
}

/// The nonlinear loop (the core's observer) from rest at angle 0, fed `truth(k)`, returns the
/// unwrapped estimated angles.
fn simulate_nonlinear<const N: usize>(
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
fn acquisition_speed<const N: usize>(gains: &Gains<f64, N>, samples: usize) -> f64
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

/// Pairs each design pole with the nearest continuous-equivalent pole and returns the
/// largest relative distance.
fn pole_shift(design: &[Complex<f64>], equivalent: &[Complex<f64>]) -> Option<f64> {
    if design.is_empty() {
        return None;
    }
    let shift = design
        .iter()
        .map(|s| {
            equivalent
                .iter()
                .map(|e| (e - s).norm() / s.norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    Some(shift)
}

/// The RMS angle (rad) and speed (rad/s) error of a gain set, predicted by the discrete
/// Lyapunov equation of the linearised loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedError {
    /// RMS angle error (rad).
    pub angle_rms_rad: f64,
    /// RMS speed error (rad/s).
    pub speed_rms_rad_s: f64,
}

/// The steady-state RMS errors of the linearised loop driven by white sensor noise of
/// standard deviation `sensor_noise_std` per channel (amplitude 1: the phase detector's
/// noise has variance `r = sensor_noise_std^2`) and, through `process_noise_q`, by a white
/// `N`-th derivative of the angle (acceleration at order 2, jerk at order 3) whose value
/// times `Ts^N` has variance `q` per sample (the Kalman model; 0 for a shaft at constant
/// speed).
///
/// Solves `S = F S F^T + r L L^T + q (I - L e1^T) G G^T (I - L e1^T)^T` with
/// `F = (I - L e1^T) A`. For a Kalman design and its own `q` and `r` this is the filtered
/// covariance of the Riccati solution.
///
/// ```
/// use angletrack::{kalman, predicted_error};
/// let design = kalman(1e-12, 1e-4, 1e-4)?;
/// let predicted = predicted_error(&design.gains, 1e-2, 1e-12)?;
/// let floor = design.kalman.unwrap().angle_floor_rad();
/// assert!((predicted.angle_rms_rad / floor - 1.0).abs() < 1e-6);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn predicted_error<const N: usize>(
    gains: &Gains<f64, N>,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<PredictedError, Error>
where
    Order<N>: SupportedOrder,
{
    let sigma = non_negative(sensor_noise_std, Argument::SensorNoiseStd)?;
    let q = non_negative(process_noise_q, Argument::ProcessNoise)?;
    let ts = gains.sample_period();
    let s = DiscreteLoop::new(&gains.gains(), ts)
        .error_covariance(sigma * sigma, q)
        .ok_or(Error::NoSolution(Argument::SensorNoiseStd))?;
    Ok(PredictedError {
        angle_rms_rad: s[(0, 0)].max(0.0).sqrt(),
        speed_rms_rad_s: s[(1, 1)].max(0.0).sqrt() / ts,
    })
}

impl DesignReport {
    /// Analyses a design for white sensor noise of standard deviation `sensor_noise_std` per
    /// channel (amplitude 1; 0 for a noise-free analysis).
    ///
    /// The step responses and the acquisition search simulate the loop (up to a few million
    /// samples for loops much slower than their sample rate).
    ///
    /// ```
    /// use angletrack::{DesignReport, Discretisation, second_order_from_tracking_error};
    /// let design = second_order_from_tracking_error(
    ///     1e-3, 1e3, 2f64.sqrt() / 2.0, 1e-5, Discretisation::PoleMatching)?;
    /// let report = DesignReport::new(&design, 0.01)?;
    /// assert!((report.linear_step.overshoot - 0.208).abs() < 0.003);
    /// assert!((report.acceleration_constant_per_s2.unwrap() / 1e6 - 1.0).abs() < 0.01);
    /// println!("{report}");
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn new<const N: usize>(design: &Design<N>, sensor_noise_std: f64) -> Result<Self, Error>
    where
        Order<N>: SupportedOrder,
    {
        let sigma = non_negative(sensor_noise_std, Argument::SensorNoiseStd)?;
        let gains = design.gains;
        let ts = gains.sample_period();
        let l = gains.gains();
        let discrete = DiscreteLoop::new(&l, ts);
        let bare = gains.with_fault_thresholds(FaultThresholds::disabled())?;
        let shifted = linalg::roots(&gains.loop_polynomial());
        let discrete_poles: Vec<Complex<f64>> = shifted.iter().map(|u| u + 1.0).collect();
        let equivalent: Vec<Complex<f64>> =
            shifted.iter().map(|&u| linalg::ln_1p(u) / ts).collect();
        let continuous_c = design
            .continuous_gains
            .map(|k| k.iter().rev().copied().collect::<Vec<f64>>())
            .unwrap_or_else(|| linalg::monic_from_roots(&equivalent));
        let per_unit = discrete
            .error_per_unit_derivative()
            .ok_or(Error::NoSolution(Argument::SamplePeriod))?;
        let noise = predicted_error(&gains, sigma, 0.0)?;
        let samples = discrete.horizon(&equivalent);
        let large_step = |gains: &Gains<f64, N>| {
            let mut last = 0.0;
            let step = StepResponse::from_samples(
                simulate_nonlinear(gains, samples, |_| LARGE_STEP_RAD).inspect(|&y| last = y),
                0.0,
                LARGE_STEP_RAD,
                SETTLING_BAND,
                ts,
            );
            (step, last)
        };
        let (bare_step, large_step_final_rad) = large_step(&bare);
        Ok(DesignReport {
            method: design.method,
            discretisation: design.discretisation,
            order: N,
            sample_period_s: ts,
            gains: l.to_vec(),
            discrete_poles,
            pole_shift: pole_shift(&design.continuous_poles, &equivalent),
            continuous_equivalent_poles: equivalent,
            design_poles: design.continuous_poles.clone(),
            bandwidth_hz: discrete.bandwidth_hz(),
            acceleration_constant_per_s2: (N == 2).then(|| 1.0 / per_unit),
            continuous_acceleration_constant_per_s2: (N == 2).then(|| continuous_c[0]),
            error_per_unit_jerk_s3: (N == 3).then_some(per_unit),
            continuous_error_per_unit_jerk_s3: (N == 3).then(|| 1.0 / continuous_c[0]),
            sensor_noise_std: sigma,
            angle_error_rms_rad: noise.angle_rms_rad,
            speed_error_rms_rad_s: noise.speed_rms_rad_s,
            kalman_angle_floor_rad: design.kalman.map(|k| k.angle_floor_rad()),
            kalman_speed_floor_rad_s: design.kalman.map(|k| k.speed_floor_rad_s(ts)),
            linear_step: discrete.linear_step(samples),
            continuous_step: design
                .continuous_gains
                .map(|_| continuous_step(&continuous_c)),
            large_step: bare_step,
            large_step_final_rad,
            large_step_with_diagnostics: large_step(&gains).0,
            max_speed_rad_s: PI / ts,
            acquisition_speed_rad_s: acquisition_speed(&bare, samples),
        })
    }
}

fn complex(z: &Complex<f64>) -> String {
    if z.im == 0.0 {
        format!("{:.6e}", z.re)
    } else {
        format!(
            "{:.6e} {} {:.6e}j",
            z.re,
            if z.im < 0.0 { '-' } else { '+' },
            z.im.abs()
        )
    }
}

fn optional(value: Option<f64>, unit: &str) -> String {
    value.map_or_else(|| "-".to_string(), |v| format!("{v:.6e} {unit}"))
}

fn step(s: &StepResponse) -> String {
    format!(
        "overshoot {:.3} %, 2 % settling {:.6e} s",
        100.0 * s.overshoot,
        s.settling_time_s
    )
}

impl fmt::Display for DesignReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let row = |f: &mut fmt::Formatter<'_>, name: &str, value: String| {
            writeln!(f, "| {name:<40} | {value} |")
        };
        row(f, "design", self.method.name().to_string())?;
        row(
            f,
            "discretisation",
            self.discretisation.map_or("-", |d| d.name()).to_string(),
        )?;
        row(
            f,
            "order, sample period",
            format!("{}, {:.6e} s", self.order, self.sample_period_s),
        )?;
        row(
            f,
            "gains l",
            self.gains
                .iter()
                .map(|g| format!("{g:.9e}"))
                .collect::<Vec<_>>()
                .join(", "),
        )?;
        for (i, (z, s)) in self
            .discrete_poles
            .iter()
            .zip(&self.continuous_equivalent_poles)
            .enumerate()
        {
            row(
                f,
                &format!("pole {} z (ln z / Ts, rad/s)", i + 1),
                format!("{} ({})", complex(z), complex(s)),
            )?;
        }
        for (i, s) in self.design_poles.iter().enumerate() {
            row(f, &format!("design pole {} (rad/s)", i + 1), complex(s))?;
        }
        row(
            f,
            "pole shift by the discretisation",
            self.pole_shift
                .map_or("-".to_string(), |v| format!("{:.3e} (relative)", v)),
        )?;
        row(f, "-3 dB bandwidth", optional(self.bandwidth_hz, "Hz"))?;
        if self.order == 2 {
            row(
                f,
                "Ka discrete (continuous)",
                format!(
                    "{} ({})",
                    optional(self.acceleration_constant_per_s2, "1/s^2"),
                    optional(self.continuous_acceleration_constant_per_s2, "1/s^2")
                ),
            )?;
        } else {
            row(
                f,
                "error per unit jerk discrete (continuous)",
                format!(
                    "{} ({})",
                    optional(self.error_per_unit_jerk_s3, "s^3"),
                    optional(self.continuous_error_per_unit_jerk_s3, "s^3")
                ),
            )?;
        }
        row(
            f,
            &format!("RMS error at sensor noise {:.3e}", self.sensor_noise_std),
            format!(
                "angle {:.6e} rad, speed {:.6e} rad/s",
                self.angle_error_rms_rad, self.speed_error_rms_rad_s
            ),
        )?;
        if let (Some(a), Some(s)) = (self.kalman_angle_floor_rad, self.kalman_speed_floor_rad_s) {
            row(
                f,
                "Kalman floor sqrt(P11), sqrt(P22)/Ts",
                format!("angle {a:.6e} rad, speed {s:.6e} rad/s"),
            )?;
        }
        row(f, "linear step", step(&self.linear_step))?;
        if let Some(c) = &self.continuous_step {
            row(f, "continuous design step", step(c))?;
        }
        row(
            f,
            "179 degree step (bare nonlinear loop)",
            format!(
                "{}, ends at {:.3} deg",
                step(&self.large_step),
                self.large_step_final_rad.to_degrees()
            ),
        )?;
        row(
            f,
            "179 degree step, with diagnostics",
            step(&self.large_step_with_diagnostics),
        )?;
        row(
            f,
            "max speed (pi / Ts)",
            format!("{:.6e} rad/s", self.max_speed_rad_s),
        )?;
        row(
            f,
            "speed step acquired from rest",
            format!("{:.6e} rad/s", self.acquisition_speed_rad_s),
        )
    }
}
