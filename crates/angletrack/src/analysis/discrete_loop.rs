//! The linearised discrete loop `F = (I - L e1^T) A` of a gain set (`docs/theory.md §5`,
//! `§6`, `§7`, `§8`): steady-state errors (§5), poles (§6), frequency response and step
//! response (§7), noise covariance (§8).

use core::f64::consts::PI;

use angletrack_core::Gains;
use nalgebra::{Complex, DMatrix, DVector};

use super::step::{SETTLING_BAND, StepResponse};
use crate::linalg;

/// Longest simulation (samples) used for a step response or one acquisition trial.
const MAX_SIMULATION_SAMPLES: usize = 4_000_000;

/// The poles of the discrete loop of `gains`: `z_i - 1` (computed without cancellation from
/// the loop polynomial in `z - 1`) and their continuous equivalents `ln(z_i) / Ts` (rad/s).
pub(super) fn loop_poles<const N: usize>(
    gains: &Gains<f64, N>,
) -> (Vec<Complex<f64>>, Vec<Complex<f64>>) {
    let ts = gains.sample_period();
    let shifted = linalg::roots(&gains.loop_polynomial());
    let equivalent = shifted.iter().map(|&u| linalg::ln_1p(u) / ts).collect();
    (shifted, equivalent)
}

/// The small-signal (linear) step response of the discrete loop of `gains`, simulated until
/// every transient has decayed; `None` if that takes more than the longest simulation.
pub(crate) fn small_signal_step<const N: usize>(gains: &Gains<f64, N>) -> Option<StepResponse> {
    let discrete = DiscreteLoop::new(&gains.gains(), gains.sample_period());
    let (_, equivalent) = loop_poles(gains);
    let samples = discrete.horizon(&equivalent);
    (samples < MAX_SIMULATION_SAMPLES).then(|| discrete.linear_step(samples))
}

/// The -3 dB bandwidth (Hz) of the discrete loop of gains `l` at sample period `ts`, see
/// [`DesignReport::bandwidth_hz`](crate::DesignReport::bandwidth_hz).
pub(crate) fn loop_bandwidth_hz(l: &[f64], ts: f64) -> Option<f64> {
    DiscreteLoop::new(l, ts).bandwidth_hz()
}

/// The closed-loop matrices of a discrete gain set.
pub(super) struct DiscreteLoop {
    l: Vec<f64>,
    ts: f64,
    f: DMatrix<f64>,
}

impl DiscreteLoop {
    pub(super) fn new(l: &[f64], ts: f64) -> Self {
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
    pub(super) fn error_per_unit_derivative(&self) -> Option<f64> {
        let n = self.order();
        let l = DVector::from_column_slice(&self.l);
        let correction = DMatrix::identity(n, n) - l * linalg::e1(n).transpose();
        let rhs = correction * linalg::taylor_remainder(n) * self.ts.powi(n as i32);
        let e = self.identity_minus_f().lu().solve(&rhs)?;
        Some(e[0])
    }

    /// `X1_e / Theta` at frequency `hz`, `z = e^(j 2 pi hz Ts)`: with `s = z - 1`,
    /// `(z I - F) = s I - (A - I) + L e1^T A`, `X_e = z (zI - F)^-1 L Theta`. Formed in
    /// `s` so that low frequencies keep their relative precision (`docs/theory.md §6`).
    pub(super) fn response_at(&self, hz: f64) -> Complex<f64> {
        let n = self.order();
        let s = linalg::exp_m1(Complex::new(0.0, 2.0 * PI * hz * self.ts));
        let z = s + 1.0;
        let m = self.identity_minus_f().map(|v| Complex::new(v, 0.0))
            + DMatrix::<Complex<f64>>::identity(n, n) * s;
        let rhs = DVector::from_iterator(n, self.l.iter().map(|&v| z * v));
        m.lu()
            .solve(&rhs)
            .map_or(Complex::new(f64::NAN, f64::NAN), |x| x[0])
    }

    /// `|X1_e / Theta|` at frequency `hz`.
    fn gain_at(&self, hz: f64) -> f64 {
        self.response_at(hz).norm()
    }

    /// The -3 dB bandwidth (Hz), see [`DesignReport::bandwidth_hz`].
    pub(super) fn bandwidth_hz(&self) -> Option<f64> {
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
    pub(super) fn error_covariance(&self, r: f64, q: f64) -> Option<DMatrix<f64>> {
        let n = self.order();
        let l = DVector::from_column_slice(&self.l);
        let correction = DMatrix::identity(n, n) - &l * linalg::e1(n).transpose();
        let g = &correction * linalg::taylor_remainder(n);
        let source = &l * l.transpose() * r + &g * g.transpose() * q;
        linalg::discrete_lyapunov(&self.f, &source)
    }

    /// Samples until every transient has decayed by `exp(-16)`.
    pub(super) fn horizon(&self, continuous_equivalent: &[Complex<f64>]) -> usize {
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
    pub(super) fn linear_step(&self, samples: usize) -> StepResponse {
        let response = linalg::affine_response(self.f.clone(), self.l.clone(), samples);
        StepResponse::from_samples(response, 0.0, 1.0, SETTLING_BAND, self.ts)
    }
}
