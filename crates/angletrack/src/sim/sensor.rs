//! The sensor model: what turns the shaft angle into the two signals `y_c`, `y_s`
//! (`docs/theory.md §1`).

use angletrack_core::SensorCalibration;

use crate::error::{Argument, Error, finite, non_negative, positive};

/// The most harmonics of the angle error a [`SensorModel`] holds.
pub const MAX_ANGLE_ERROR_HARMONICS: usize = 8;

/// The sensor: what turns the shaft angle into the two signals `y_c`, `y_s`.
///
/// ```text
/// y_c = A cos(theta) + A h3 cos(3 theta) + offset_cos + w_c
/// y_s = A (1 + imbalance) sin(theta + quadrature_error) + A h3 sin(3 theta) + offset_sin + w_s
/// ```
///
/// where, with `angle_error_harmonics` `(k, a_k, p_k)`, `theta` in the `cos` and `sin` of
/// the fundamental is the sensor's reading `theta + d(theta)`,
/// `d(theta) = sum_k a_k sin(k theta + p_k)`: the angle-dependent error that the
/// `angletrack` calibration learns ([`crate::learn_angle_correction`]).
///
/// then, with `adc_bits > 0`, rounding to the ADC grid of `2^adc_bits` levels over
/// `[-adc_full_scale, adc_full_scale)` (saturating). `w_c`, `w_s` are independent white
/// Gaussian noises of standard deviation `noise_std`.
///
/// Without the 3rd harmonic this is the core's calibration model (`docs/theory.md §12`),
/// `y_c = o_c + A_c cos(theta)`, `y_s = o_s + A_s sin(theta + phi)`, with `o_c =
/// offset_cos`, `o_s = offset_sin`, `A_c = amplitude`, `A_s = amplitude (1 +
/// amplitude_imbalance)` and `phi = quadrature_error_rad`: [`SensorModel::calibration`]
/// gives the [`SensorCalibration`] that undoes it exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorModel {
    /// Amplitude `A` of both signals (1 after normalisation).
    pub amplitude: f64,
    /// DC offset of `y_c`.
    pub offset_cos: f64,
    /// DC offset of `y_s`.
    pub offset_sin: f64,
    /// Relative amplitude imbalance of `y_s` against `y_c`.
    pub amplitude_imbalance: f64,
    /// Quadrature error (rad): the phase of `y_s` off 90 degrees from `y_c`.
    pub quadrature_error_rad: f64,
    /// Relative amplitude `h3` of the 3rd harmonic on both signals.
    pub third_harmonic: f64,
    /// Harmonics of the angle error, `(order k, amplitude a_k in rad, phase p_k in rad)`:
    /// `d(theta) = sum_k a_k sin(k theta + p_k)`; entries of amplitude 0 are unused.
    pub angle_error_harmonics: [(u32, f64, f64); MAX_ANGLE_ERROR_HARMONICS],
    /// Standard deviation of the white noise on each signal.
    pub noise_std: f64,
    /// ADC resolution in bits; 0 for no quantisation.
    pub adc_bits: u32,
    /// ADC full scale: the converter's range is `[-adc_full_scale, adc_full_scale)`.
    pub adc_full_scale: f64,
}

impl Default for SensorModel {
    /// An ideal sensor: amplitude 1, no error, no noise, no quantisation.
    fn default() -> Self {
        Self {
            amplitude: 1.0,
            offset_cos: 0.0,
            offset_sin: 0.0,
            amplitude_imbalance: 0.0,
            quadrature_error_rad: 0.0,
            third_harmonic: 0.0,
            angle_error_harmonics: [(0, 0.0, 0.0); MAX_ANGLE_ERROR_HARMONICS],
            noise_std: 0.0,
            adc_bits: 0,
            adc_full_scale: 1.25,
        }
    }
}

impl SensorModel {
    /// An ideal sensor of amplitude 1 with white noise of standard deviation `noise_std` on
    /// each signal.
    ///
    /// ```
    /// let sensor = angletrack::SensorModel::with_noise(0.01);
    /// assert_eq!((sensor.amplitude, sensor.noise_std), (1.0, 0.01));
    /// ```
    pub fn with_noise(noise_std: f64) -> Self {
        Self {
            noise_std,
            ..Self::default()
        }
    }

    /// The core's [`SensorCalibration`] of this sensor (see the type's documentation): the
    /// correction an online calibration should learn, for comparing with what it learned.
    /// Refuses an invalid model, and a quadrature error beyond the calibration's bound
    /// (`SensorCalibration::max_quadrature_rad`, pi/4).
    ///
    /// ```
    /// use angletrack::SensorModel;
    /// let sensor = SensorModel { amplitude: 1800.0, offset_cos: 90.0, amplitude_imbalance: 0.1,
    ///     quadrature_error_rad: 0.05, ..SensorModel::default() };
    /// let calibration = sensor.calibration()?;
    /// assert_eq!(calibration.offsets(), (90.0, 0.0));
    /// assert!((calibration.amplitude_ratio() - 1.1).abs() < 1e-12);
    /// assert_eq!(calibration.quadrature_rad(), 0.05);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn calibration(&self) -> Result<SensorCalibration<f64>, Error> {
        self.validate()?;
        let a = self.amplitude;
        SensorCalibration::new(
            self.offset_cos,
            self.offset_sin,
            a,
            a * (1.0 + self.amplitude_imbalance),
            self.quadrature_error_rad,
        )
        .map_err(|_| Error::OutOfRange {
            argument: Argument::QuadratureError,
            expected: "within +-pi/4 (the calibration's bound), amplitudes representable",
        })
    }

    pub(super) fn validate(&self) -> Result<(), Error> {
        positive(self.amplitude, Argument::Amplitude)?;
        finite(self.offset_cos, Argument::OffsetCos)?;
        finite(self.offset_sin, Argument::OffsetSin)?;
        finite(self.amplitude_imbalance, Argument::AmplitudeImbalance)?;
        if self.amplitude_imbalance <= -1.0 {
            return Err(Error::OutOfRange {
                argument: Argument::AmplitudeImbalance,
                expected: "> -1",
            });
        }
        finite(self.quadrature_error_rad, Argument::QuadratureError)?;
        finite(self.third_harmonic, Argument::ThirdHarmonic)?;
        for &(_, amplitude, phase) in &self.angle_error_harmonics {
            finite(amplitude, Argument::AngleErrorHarmonics)?;
            finite(phase, Argument::AngleErrorHarmonics)?;
        }
        non_negative(self.noise_std, Argument::NoiseStd)?;
        if self.adc_bits > 32 {
            return Err(Error::OutOfRange {
                argument: Argument::AdcBits,
                expected: "0 (no ADC) to 32",
            });
        }
        positive(self.adc_full_scale, Argument::AdcFullScale)?;
        Ok(())
    }

    /// Rounds to the ADC grid (saturating); unchanged without ADC.
    fn quantise(&self, y: f64) -> f64 {
        if self.adc_bits == 0 {
            return y;
        }
        let levels = (self.adc_bits as f64).exp2();
        let lsb = 2.0 * self.adc_full_scale / levels;
        let code = (y / lsb).round().clamp(-levels / 2.0, levels / 2.0 - 1.0);
        code * lsb
    }

    /// The angle error `d(theta)` (rad) of `angle_error_harmonics`.
    pub fn angle_error(&self, theta: f64) -> f64 {
        self.angle_error_harmonics
            .iter()
            .filter(|h| h.1 != 0.0)
            .map(|&(k, amplitude, phase)| amplitude * (k as f64 * theta + phase).sin())
            .sum()
    }

    /// `(y_c, y_s)` for the shaft angle `theta` (rad) and the noise samples.
    pub(super) fn signals(&self, theta: f64, noise_c: f64, noise_s: f64) -> (f64, f64) {
        let a = self.amplitude;
        let h = a * self.third_harmonic;
        let (s3, c3) = (3.0 * theta).sin_cos();
        let read = theta + self.angle_error(theta);
        let y_c = a * read.cos() + h * c3 + self.offset_cos + noise_c;
        let y_s = a * (1.0 + self.amplitude_imbalance) * (read + self.quadrature_error_rad).sin()
            + h * s3
            + self.offset_sin
            + noise_s;
        (self.quantise(y_c), self.quantise(y_s))
    }
}
