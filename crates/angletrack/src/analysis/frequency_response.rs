//! The frequency response of the discrete loop (`docs/theory.md §5`, the linearised loop):
//! what a Bode plot of a design draws.

use angletrack_core::Gains;
use nalgebra::Complex;

use super::discrete_loop::DiscreteLoop;
use crate::error::{Argument, Error, non_negative};

/// The closed-loop angle transfer `H(z) = X1_e(z) / Theta(z)` of the linearised discrete
/// loop of `gains` at `z = exp(j 2 pi f Ts)`, for each frequency `f` of `frequencies_hz`
/// (Hz, finite and at least 0; the response repeats with period `1 / Ts` and is conjugate
/// symmetric about the Nyquist frequency `0.5 / Ts`). `H(1) = 1`: a type II or III loop
/// follows a constant angle without error. Its magnitude falls through `1 / sqrt(2)` at
/// [`DesignReport::bandwidth_hz`](crate::DesignReport::bandwidth_hz).
///
/// ```
/// use angletrack::closed_loop_response;
/// use angletrack::core::Gains;
/// let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4)?;
/// let h = closed_loop_response(&gains, &[0.0, 100.0, 5000.0])?;
/// assert!((h[0].re - 1.0).abs() < 1e-12 && h[0].im.abs() < 1e-12);
/// // Above the bandwidth the loop no longer follows the angle.
/// assert!(h[2].norm() < 0.1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn closed_loop_response<const N: usize>(
    gains: &Gains<f64, N>,
    frequencies_hz: &[f64],
) -> Result<Vec<Complex<f64>>, Error> {
    for &f in frequencies_hz {
        non_negative(f, Argument::Frequency)?;
    }
    let discrete = DiscreteLoop::new(&gains.gains(), gains.sample_period());
    Ok(frequencies_hz
        .iter()
        .map(|&f| discrete.response_at(f))
        .collect())
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::{DesignReport, Discretisation, third_order_from_poles};

    /// `H(z)` of `docs/theory.md §5`, evaluated from its coefficients in `z`.
    fn analytic<const N: usize>(l: [f64; N], z: Complex<f64>) -> Complex<f64> {
        match *l.as_slice() {
            [l1, l2] => (z * z * l1 + z * (l2 - l1)) / (z * z + z * (l1 + l2 - 2.0) + (1.0 - l1)),
            [l1, l2, l3] => {
                let num =
                    z * z * z * l1 + z * z * (l2 - 2.0 * l1 + l3 / 2.0) + z * (l1 - l2 + l3 / 2.0);
                let den = z * z * z
                    + z * z * (l1 + l2 + l3 / 2.0 - 3.0)
                    + z * (3.0 - 2.0 * l1 - l2 + l3 / 2.0)
                    + (l1 - 1.0);
                num / den
            }
            _ => unreachable!(),
        }
    }

    fn check_against_analytic<const N: usize>(gains: &Gains<f64, N>) {
        let ts = gains.sample_period();
        let freqs = [0.0, 3.0, 50.0, 400.0, 0.25 / ts, 0.5 / ts];
        let h = closed_loop_response(gains, &freqs).unwrap();
        assert!((h[0] - Complex::new(1.0, 0.0)).norm() < 1e-12, "{}", h[0]);
        for (&f, &hf) in freqs.iter().zip(&h) {
            let z = Complex::new(0.0, 2.0 * PI * f * ts).exp();
            let expected = analytic(gains.gains(), z);
            assert!(
                (hf - expected).norm() < 1e-9 * expected.norm().max(1e-3),
                "{f} Hz: {hf} vs {expected}"
            );
        }
    }

    #[test]
    fn equals_the_analytic_transfer_function() {
        check_against_analytic(&Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap());
        check_against_analytic(&Gains::<f64, 3>::new([0.271, 0.0285, 0.001], 1e-4).unwrap());
    }

    #[test]
    fn falls_through_minus_3_db_at_the_reported_bandwidth() {
        let design =
            third_order_from_poles(4.0, 2e-3, 2.0, 1e-4, Discretisation::PoleMatching).unwrap();
        let report = DesignReport::new(&design, 0.0).unwrap();
        let bandwidth = report.bandwidth_hz.unwrap();
        let h = closed_loop_response(&design.gains, &[bandwidth]).unwrap();
        assert!((h[0].norm() - core::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
    }

    #[test]
    fn refuses_a_negative_or_non_finite_frequency() {
        let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap();
        assert_eq!(
            closed_loop_response(&gains, &[-1.0])
                .unwrap_err()
                .argument(),
            Some(Argument::Frequency)
        );
        assert!(closed_loop_response(&gains, &[f64::NAN]).is_err());
    }
}
