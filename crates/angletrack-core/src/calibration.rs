//! [`SensorCalibration`]: a real sensor's offsets, gain imbalance and quadrature error
//! (`docs/theory.md §12`), as a `Copy` value that firmware stores and loads, and the
//! correction it applies to each sample before the phase detector.

use crate::error::{ConfigError, Parameter, const_try};
use crate::real::Float;
use crate::real::check_positive;
use crate::real::saturate::{saturate_i16, saturated};

/// The sensor model `y_c = o_c + A_c cos(theta)`, `y_s = o_s + A_s sin(theta + phi)`: the
/// two offsets, the two channels' amplitudes (their ratio `g = A_s / A_c` is the gain
/// imbalance) and the quadrature (non-orthogonality) angle `phi`, in the input's units and
/// radians (`docs/theory.md §12`).
///
/// [`SensorCalibration::correct`] undoes them with the cosine channel as the reference for
/// both the angle and the scale:
///
/// ```text
/// c = y_c - o_c                                   = A_c cos(theta)
/// s = (y_s - o_s) A_c / (A_s cos phi) - c tan phi = A_c sin(theta)
/// ```
///
/// so the corrected signal keeps the cosine channel's amplitude and units: the
/// [`FaultThresholds`](crate::FaultThresholds) stay valid and a loss of signal stays
/// visible. The two coefficients are computed once, at construction. `Copy` and plain: store
/// [`SensorCalibration::parameters`] in flash and rebuild it with
/// [`SensorCalibration::new`] at start-up. The default corrects nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorCalibration<T> {
    pub(crate) offset_c: T,
    pub(crate) offset_s: T,
    pub(crate) amplitude_c: T,
    pub(crate) amplitude_s: T,
    pub(crate) quadrature_rad: T,
    /// `A_c / (A_s cos phi)`.
    pub(crate) sine_gain: T,
    /// `tan phi`.
    pub(crate) cross_gain: T,
}

impl<T: Float> Default for SensorCalibration<T> {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl<T: Float> SensorCalibration<T> {
    /// A calibration from the sensor model's parameters: offsets `offset_c`, `offset_s` and
    /// amplitudes `amplitude_c`, `amplitude_s` (input units), quadrature `quadrature_rad`.
    ///
    /// Refuses non-finite values, amplitudes that are not positive (or whose ratio
    /// overflows) and a quadrature beyond [`SensorCalibration::max_quadrature_rad`].
    ///
    /// ```
    /// use angletrack_core::{Parameter, SensorCalibration};
    /// let calibration = SensorCalibration::<f32>::new(0.05, -0.05, 1.0, 1.1, 0.05)?;
    /// let theta = 0.7_f32;
    /// let y_c = 0.05 + theta.cos();
    /// let y_s = -0.05 + 1.1 * (theta + 0.05).sin();
    /// let (c, s) = calibration.correct(y_c, y_s);
    /// assert!((c - theta.cos()).abs() < 1e-6 && (s - theta.sin()).abs() < 1e-6);
    /// let err = SensorCalibration::<f32>::new(0.0, 0.0, 1.0, -1.0, 0.0).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AmplitudeSin);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(
        offset_c: T,
        offset_s: T,
        amplitude_c: T,
        amplitude_s: T,
        quadrature_rad: T,
    ) -> Result<Self, ConfigError> {
        for (value, parameter) in [
            (offset_c, Parameter::OffsetCos),
            (offset_s, Parameter::OffsetSin),
            (quadrature_rad, Parameter::Quadrature),
        ] {
            if !value.is_finite() {
                return Err(ConfigError::NotFinite(parameter));
            }
        }
        let amplitude_c = check_positive(amplitude_c, Parameter::AmplitudeCos)?;
        let amplitude_s = check_positive(amplitude_s, Parameter::AmplitudeSin)?;
        if !(quadrature_rad.abs() < Self::max_quadrature_rad()) {
            return Err(ConfigError::OutOfRange(Parameter::Quadrature));
        }
        // The fast sin/cos polynomials (`docs/theory.md §11`, within 3e-7 in `f32`; `libm`'s
        // would compute in `f64`, which the `f32` path avoids), by Horner's rule: the same
        // operations as the `const` constructor's, so that both give the same calibration.
        let (sin, cos) = quadrature_sin_cos(quadrature_rad);
        let sine_gain = amplitude_c / (amplitude_s * cos);
        if !(sine_gain.is_finite() && sine_gain > T::ZERO) {
            return Err(ConfigError::OutOfRange(Parameter::AmplitudeSin));
        }
        Ok(Self {
            offset_c,
            offset_s,
            amplitude_c,
            amplitude_s,
            quadrature_rad,
            sine_gain,
            cross_gain: sin / cos,
        })
    }

    /// No correction: offsets 0, amplitudes 1, quadrature 0.
    pub const IDENTITY: Self = Self {
        offset_c: T::ZERO,
        offset_s: T::ZERO,
        amplitude_c: T::ONE,
        amplitude_s: T::ONE,
        quadrature_rad: T::ZERO,
        sine_gain: T::ONE,
        cross_gain: T::ZERO,
    };

    /// The largest quadrature angle a calibration may hold (rad): pi/4, beyond which the
    /// correction (a division by `cos phi`) would amplify the noise by more than `sqrt(2)`;
    /// real sensors are within a few degrees.
    pub fn max_quadrature_rad() -> T {
        T::FRAC_PI_2 * T::HALF
    }

    /// The calibration that only removes the offsets `(offset_c, offset_s)` (finite).
    pub(crate) fn with_offsets(offset_c: T, offset_s: T) -> Self {
        Self {
            offset_c,
            offset_s,
            ..Self::IDENTITY
        }
    }

    /// The calibration of the regression of one turn's samples on the observer's angle,
    /// `y_c = o_c + a1 cos p + b1 sin p`, `y_s = o_s + a2 cos p + b2 sin p`
    /// (`regression = [o_c, o_s, a1, b1, a2, b2]`): `A_c = |(a1, b1)|`,
    /// `A_s = |(a2, b2)|`, and `phi` from the angle between the two rows, which leaves out
    /// the rows' common rotation (the observer's own angle offset: the cosine channel is
    /// the reference). Checked as [`SensorCalibration::new`].
    pub(crate) fn from_regression(regression: &[T; 6]) -> Result<Self, ConfigError> {
        let [offset_c, offset_s, a1, b1, a2, b2] = *regression;
        let dot = a1 * a2 + b1 * b2; // A_c A_s sin(phi)
        let cross = a1 * b2 - b1 * a2; // A_c A_s cos(phi)
        let amplitude_c = (a1 * a1 + b1 * b1).sqrt();
        let amplitude_s = (a2 * a2 + b2 * b2).sqrt();
        Self::new(
            offset_c,
            offset_s,
            amplitude_c,
            amplitude_s,
            dot.atan2(cross),
        )
    }

    /// The regression `[o_c, o_s, a1, b1, a2, b2]` this calibration stands for, with no
    /// rotation (see [`SensorCalibration::from_regression`]).
    pub(crate) fn regression(&self) -> [T; 6] {
        let (sin, cos) = self.quadrature_rad.fast_sin_cos();
        [
            self.offset_c,
            self.offset_s,
            self.amplitude_c,
            T::ZERO,
            self.amplitude_s * sin,
            self.amplitude_s * cos,
        ]
    }

    /// The corrected pair `(c, s) = A_c (cos theta, sin theta)` of a sample (see the type's
    /// documentation): two subtractions and three multiplications.
    #[inline(always)]
    pub fn correct(&self, y_c: T, y_s: T) -> (T, T) {
        let c = y_c - self.offset_c;
        let s = (y_s - self.offset_s) * self.sine_gain - c * self.cross_gain;
        (c, s)
    }

    /// The parameters `(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)`, in
    /// the order [`SensorCalibration::new`] takes them.
    pub fn parameters(&self) -> (T, T, T, T, T) {
        (
            self.offset_c,
            self.offset_s,
            self.amplitude_c,
            self.amplitude_s,
            self.quadrature_rad,
        )
    }

    /// The offsets `(o_c, o_s)` (input units).
    pub fn offsets(&self) -> (T, T) {
        (self.offset_c, self.offset_s)
    }

    /// The amplitudes `(A_c, A_s)` (input units).
    pub fn amplitudes(&self) -> (T, T) {
        (self.amplitude_c, self.amplitude_s)
    }

    /// The gain imbalance `A_s / A_c`.
    pub fn amplitude_ratio(&self) -> T {
        self.amplitude_s / self.amplitude_c
    }

    /// The quadrature angle `phi` (rad).
    pub fn quadrature_rad(&self) -> T {
        self.quadrature_rad
    }
}

/// A [`SensorCalibration`] in the fixed-point observer's integers: the offsets in counts of
/// its 16-bit samples and the two coefficients in Q14, applied by
/// [`FixedCalibration::correct`] with no overflow and the result saturated to `i16`. Learned
/// in float (on the host, or by the online calibration on a core with an FPU) and loaded as
/// these constants; `const` to build from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedCalibration {
    offset_c: i16,
    offset_s: i16,
    /// `A_c / (A_s cos phi)` in Q14: below 2.
    sine_gain_q14: i16,
    /// `tan phi` in Q14: within +-1 (`|phi| <= pi/4`).
    cross_gain_q14: i16,
}

impl Default for FixedCalibration {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl FixedCalibration {
    /// No correction.
    pub const IDENTITY: Self = Self {
        offset_c: 0,
        offset_s: 0,
        sine_gain_q14: 1 << 14,
        cross_gain_q14: 0,
    };

    /// The integers of `calibration`, whose offsets are in counts of the fixed-point
    /// observer's 16-bit samples (what `calibrate` learns from a capture of those samples).
    /// Refuses offsets outside `i16` and a sine gain `A_c / (A_s cos phi)` of 2 or more
    /// (the sine channel less than half the cosine's), naming the parameter.
    ///
    /// ```
    /// use angletrack_core::{FixedCalibration, SensorCalibration};
    /// let learned = SensorCalibration::<f64>::new(300.0, -200.0, 16000.0, 17000.0, 0.02)?;
    /// let fixed = FixedCalibration::new(&learned)?;
    /// let theta = 0.7_f64;
    /// let y_c = (300.0 + 16000.0 * theta.cos()).round() as i16;
    /// let y_s = (-200.0 + 17000.0 * (theta + 0.02).sin()).round() as i16;
    /// let (c, s) = fixed.correct(y_c, y_s);
    /// assert!((f64::from(c) - 16000.0 * theta.cos()).abs() <= 1.0);
    /// assert!((f64::from(s) - 16000.0 * theta.sin()).abs() <= 2.0);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(calibration: &SensorCalibration<f64>) -> Result<Self, ConfigError> {
        Self::new_const(calibration)
    }

    /// [`FixedCalibration::new`] as a `const fn`: a firmware's stored calibration in a
    /// `static`, checked when it compiles.
    ///
    /// ```
    /// use angletrack_core::{FixedCalibration, SensorCalibration};
    /// const LEARNED: SensorCalibration<f64> =
    ///     match SensorCalibration::<f64>::new_const(300.0, -200.0, 16000.0, 17000.0, 0.02) {
    ///         Ok(calibration) => calibration,
    ///         Err(_) => panic!("bad calibration"),
    ///     };
    /// static FIXED: FixedCalibration = match FixedCalibration::new_const(&LEARNED) {
    ///     Ok(fixed) => fixed,
    ///     Err(_) => panic!("beyond the fixed-point ranges"),
    /// };
    /// assert_eq!(FIXED.correct(300, -200), (0, 0));
    /// ```
    pub const fn new_const(calibration: &SensorCalibration<f64>) -> Result<Self, ConfigError> {
        Ok(Self {
            offset_c: const_try!(attempt_i16(calibration.offset_c, Parameter::OffsetCos)),
            offset_s: const_try!(attempt_i16(calibration.offset_s, Parameter::OffsetSin)),
            sine_gain_q14: const_try!(attempt_i16(
                calibration.sine_gain * 16384.0,
                Parameter::AmplitudeSin
            )),
            cross_gain_q14: const_try!(attempt_i16(
                calibration.cross_gain * 16384.0,
                Parameter::Quadrature
            )),
        })
    }

    /// The calibration of its integers, as [`FixedCalibration::q14_words`] gives them
    /// (what `angletrack export --format c` writes for a firmware): the offsets (counts of
    /// the observer's 16-bit samples), the sine gain `A_c / (A_s cos phi)` in Q14 (positive)
    /// and the cross gain `tan phi` in Q14 (within +-16384, `|phi| <= pi/4`). Checked by
    /// integer comparisons only, naming the parameter.
    ///
    /// ```
    /// use angletrack_core::{FixedCalibration, Parameter, SensorCalibration};
    /// static STORED: FixedCalibration = match FixedCalibration::from_q14([300, -200, 15423, 328]) {
    ///     Ok(fixed) => fixed,
    ///     Err(_) => panic!("the calibration's words are refused"),
    /// };
    /// let learned = SensorCalibration::<f64>::new(300.0, -200.0, 16000.0, 17000.0, 0.02)?;
    /// assert_eq!(STORED, FixedCalibration::new(&learned)?);
    /// let err = FixedCalibration::from_q14([0, 0, 0, 0]).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AmplitudeSin);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn from_q14(words: [i16; 4]) -> Result<Self, ConfigError> {
        let [offset_c, offset_s, sine_gain_q14, cross_gain_q14] = words;
        if sine_gain_q14 <= 0 {
            return Err(ConfigError::OutOfRange(Parameter::AmplitudeSin));
        }
        if cross_gain_q14 < -(1 << 14) || cross_gain_q14 > 1 << 14 {
            return Err(ConfigError::OutOfRange(Parameter::Quadrature));
        }
        Ok(Self {
            offset_c,
            offset_s,
            sine_gain_q14,
            cross_gain_q14,
        })
    }

    /// The integers: the offsets, the sine gain and the cross gain in Q14 (for
    /// [`FixedCalibration::from_q14`]).
    pub const fn q14_words(&self) -> [i16; 4] {
        [
            self.offset_c,
            self.offset_s,
            self.sine_gain_q14,
            self.cross_gain_q14,
        ]
    }

    /// The corrected pair (see [`SensorCalibration::correct`]), saturated to `i16`:
    /// `c = y_c - o_c`, `s = ((y_s - o_s) g - c t) / 2^14` rounded, `g` and `t` the Q14
    /// coefficients (every product below 2^30 and their sum below 2^31: no overflow).
    #[inline(always)]
    pub fn correct(&self, y_c: i16, y_s: i16) -> (i16, i16) {
        let c = saturated(i32::from(y_c) - i32::from(self.offset_c));
        let s = saturated(i32::from(y_s) - i32::from(self.offset_s));
        let s = (s * i32::from(self.sine_gain_q14) - c * i32::from(self.cross_gain_q14)
            + (1 << 13))
            >> 14;
        // Both within i16 (saturated).
        (c as i16, saturate_i16(s))
    }
}

/// `v` (finite) rounded to the nearest integer, half away from zero (as `libm::round`),
/// if that fits an `i16`: exact, since `v` less its truncation is exact below 2^52.
const fn attempt_i16(v: f64, parameter: Parameter) -> Result<i16, ConfigError> {
    if !(v > -32769.0 && v < 32768.0) {
        return Err(ConfigError::OutOfRange(parameter));
    }
    let whole = v as i32;
    let fraction = v - whole as f64;
    let rounded = if fraction >= 0.5 {
        whole + 1
    } else if fraction <= -0.5 {
        whole - 1
    } else {
        whole
    };
    if rounded < -32768 || rounded > 32767 {
        return Err(ConfigError::OutOfRange(parameter));
    }
    Ok(rounded as i16)
}

/// `(sin x, cos x)` for `|x| <= pi/2` by the fast sin/cos polynomials (`T::SIN_POLY`,
/// `T::COS_POLY`) and Horner's rule, in the order of `const_config::stages`' `sin_cos`.
fn quadrature_sin_cos<T: Float>(x: T) -> (T, T) {
    let w = T::FRAC_PI_2 - x.abs();
    let w2 = w * w;
    let horner = |c: &[T]| c.iter().rev().fold(T::ZERO, |sum, &k| sum * w2 + k);
    let q = horner(T::COS_POLY);
    (if x < T::ZERO { -q } else { q }, w * horner(T::SIN_POLY))
}
