//! Raw ADC counts as the observer's input (`docs/theory.md §12`): [`AdcScaling`], the
//! front-end stage that removes the mid-scale and scales counts to units of full scale, for
//! the integer samples an ADC gives ([`AdcSample`]: `i16`, `u16`, `i32`), a stage of a
//! [`Chain`](crate::Chain) in front of the observer.

use crate::error::{ConfigError, Parameter};
use crate::real::Float;
use crate::real::check_positive;

/// The largest mid-scale (in counts, either sign) an [`AdcScaling`] accepts: `2^30`, so that
/// a sample minus the mid-scale never overflows (see [`AdcSample`]).
pub const MAX_MID_SCALE_COUNTS: i32 = 1 << 30;

mod sealed {
    pub trait Sealed {}
    impl Sealed for i16 {}
    impl Sealed for u16 {}
    impl Sealed for i32 {}
}

/// An integer ADC sample: `i16`, `u16` or `i32` (sealed).
///
/// [`AdcSample::counts_from`] gives the sample minus a mid-scale (at most
/// [`MAX_MID_SCALE_COUNTS`] in magnitude) as a float, without overflow for any sample: `i16`
/// and `u16` subtract in `i32` (`|sample| < 2^16`, so the difference stays below `2^31`);
/// `i32` subtracts in `i64` and converts the two halves of the difference (`d >> 1` and
/// `d & 1`) from `i32`, so that the `f32` path needs no 64-bit conversion routine. The
/// result is exact while the difference fits the float's mantissa (`2^24` counts in `f32`:
/// any ADC of up to 24 bits), and rounded to the type beyond.
pub trait AdcSample: sealed::Sealed + Copy {
    /// `self - mid_scale_counts` as `T` (`|mid_scale_counts| <= 2^30`).
    fn counts_from<T: Float>(self, mid_scale_counts: i32) -> T;
    /// `self - mid_scale_counts` in `i32`, saturated (exact for `i16` and `u16`).
    #[doc(hidden)]
    fn difference_from(self, mid_scale_counts: i32) -> i32;
}

impl AdcSample for i16 {
    #[inline(always)]
    fn counts_from<T: Float>(self, mid_scale_counts: i32) -> T {
        T::from_i32(i32::from(self) - mid_scale_counts)
    }
    #[inline(always)]
    fn difference_from(self, mid_scale_counts: i32) -> i32 {
        i32::from(self) - mid_scale_counts
    }
}

impl AdcSample for u16 {
    #[inline(always)]
    fn counts_from<T: Float>(self, mid_scale_counts: i32) -> T {
        T::from_i32(i32::from(self) - mid_scale_counts)
    }
    #[inline(always)]
    fn difference_from(self, mid_scale_counts: i32) -> i32 {
        i32::from(self) - mid_scale_counts
    }
}

impl AdcSample for i32 {
    #[inline(always)]
    fn counts_from<T: Float>(self, mid_scale_counts: i32) -> T {
        // |d| < 2^31 + 2^30: d >> 1 fits an i32.
        let d = i64::from(self) - i64::from(mid_scale_counts);
        T::from_i32((d >> 1) as i32) * T::TWO + T::from_i32((d & 1) as i32)
    }
    #[inline(always)]
    fn difference_from(self, mid_scale_counts: i32) -> i32 {
        self.saturating_sub(mid_scale_counts)
    }
}

/// The ADC front end: `y = (sample - mid_scale) / counts_per_unit`, configured once.
///
/// With `counts_per_unit` half the ADC's range (what [`AdcScaling::offset_binary`] and
/// [`AdcScaling::twos_complement`] choose) the signals are in units of full scale, so the
/// default [`FaultThresholds`](crate::FaultThresholds) (nominal amplitude 1) become
/// fractions of full scale; give a nominal amplitude below 1
/// ([`FaultThresholds::for_amplitude`](crate::FaultThresholds::for_amplitude)) for a
/// signal that does not fill the range. The loop itself does not care (its phase error is
/// normalised, `docs/theory.md §12`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdcScaling<T> {
    pub(crate) mid_scale_counts: i32,
    pub(crate) units_per_count: T,
}

impl<T: Float> Default for AdcScaling<T> {
    /// No scaling: mid-scale 0, one count per unit.
    fn default() -> Self {
        Self::UNSCALED
    }
}

/// `2^(bits-1)` for `bits` in [2, `max_bits`] (capped at `2^30`), else the error.
pub(crate) const fn half_range(bits: u32, max_bits: u32) -> Result<i32, ConfigError> {
    if bits < 2 || bits > max_bits {
        return Err(ConfigError::OutOfRange(Parameter::AdcBits));
    }
    Ok(1 << if bits - 1 < 30 { bits - 1 } else { 30 })
}

impl<T: Float> AdcScaling<T> {
    /// No scaling: mid-scale 0, one count per unit.
    pub(crate) const UNSCALED: Self = Self {
        mid_scale_counts: 0,
        units_per_count: T::ONE,
    };
}

impl<T: Float> AdcScaling<T> {
    /// An ADC front end removing `mid_scale_counts` (the reading of a zero signal, at most
    /// [`MAX_MID_SCALE_COUNTS`] in magnitude) and dividing by `counts_per_unit` (counts per
    /// unit of the observer's input, finite and positive).
    ///
    /// ```
    /// use angletrack_core::{AdcScaling, Parameter};
    /// // A 12-bit ADC, offset binary, mid-scale 2048: units of full scale.
    /// let adc = AdcScaling::<f32>::new(2048, 2048.0)?;
    /// assert_eq!(adc.sample(3848u16, 2048u16), (1800.0 / 2048.0, 0.0));
    /// let err = AdcScaling::<f32>::new(2048, 0.0).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::CountsPerUnit);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(mid_scale_counts: i32, counts_per_unit: T) -> Result<Self, ConfigError> {
        if mid_scale_counts.unsigned_abs() > MAX_MID_SCALE_COUNTS as u32 {
            return Err(ConfigError::OutOfRange(Parameter::MidScaleCounts));
        }
        let counts = check_positive(counts_per_unit, Parameter::CountsPerUnit)?;
        let units_per_count = T::ONE / counts;
        if !(units_per_count.is_finite() && units_per_count > T::ZERO) {
            return Err(ConfigError::OutOfRange(Parameter::CountsPerUnit));
        }
        Ok(Self {
            mid_scale_counts,
            units_per_count,
        })
    }

    /// An unsigned (offset binary) ADC of `bits` bits (2 to 31): mid-scale `2^(bits-1)`,
    /// `2^(bits-1)` counts per unit (full scale is +-1).
    ///
    /// ```
    /// use angletrack_core::AdcScaling;
    /// let adc = AdcScaling::<f32>::offset_binary(12)?;
    /// assert_eq!(adc.sample(4095u16, 0u16), (2047.0 / 2048.0, -1.0));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn offset_binary(bits: u32) -> Result<Self, ConfigError> {
        let half = half_range(bits, 31)?;
        Self::new(half, T::from_i32(half))
    }

    /// A signed (two's complement) ADC of `bits` bits (2 to 32): mid-scale 0, `2^(bits-1)`
    /// counts per unit (full scale is +-1).
    ///
    /// ```
    /// use angletrack_core::AdcScaling;
    /// let adc = AdcScaling::<f64>::twos_complement(16)?;
    /// assert_eq!(adc.sample(-32768i16, 16384i16), (-1.0, 0.5));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn twos_complement(bits: u32) -> Result<Self, ConfigError> {
        let half = half_range(bits, 32)?;
        // 2^31 counts per unit for 32 bits: 2^30 times 2, exact.
        let counts = if bits == 32 {
            T::from_i32(MAX_MID_SCALE_COUNTS) * T::TWO
        } else {
            T::from_i32(half)
        };
        Self::new(0, counts)
    }

    /// The mid-scale (counts).
    pub fn mid_scale_counts(&self) -> i32 {
        self.mid_scale_counts
    }

    /// The counts per unit of the observer's input.
    pub fn counts_per_unit(&self) -> T {
        T::ONE / self.units_per_count
    }

    /// One channel's sample in the observer's units.
    #[inline(always)]
    pub fn scale<I: AdcSample>(&self, raw: I) -> T {
        raw.counts_from::<T>(self.mid_scale_counts) * self.units_per_count
    }

    /// The pair `(y_c, y_s)` in the observer's units, from the raw samples of the cosine
    /// and sine channels.
    #[inline(always)]
    pub fn sample<I: AdcSample>(&self, raw_c: I, raw_s: I) -> (T, T) {
        (self.scale(raw_c), self.scale(raw_s))
    }
}

/// ADC counts to the fixed-point observer's 16-bit samples: `(sample - mid_scale) 2^shift`,
/// saturated to `i16` (`docs/theory.md §14`). The fixed-point observer normalises the
/// amplitude itself (4096 to 46341 counts are exact), so the shift only brings the ADC's
/// range to 16 bits: a 12-bit ADC is shifted by 4. Configured once, `const`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdcCounts {
    mid_scale_counts: i32,
    shift: u32,
    /// The differences that do not saturate once shifted: `[-2^15, 2^15 - 1] >> shift`.
    low: i32,
    high: i32,
}

impl AdcCounts {
    /// Counts as they come: mid-scale 0, no shift.
    pub(crate) const UNSCALED: Self = Self {
        mid_scale_counts: 0,
        shift: 0,
        low: -(1 << 15),
        high: (1 << 15) - 1,
    };

    /// Counts with `mid_scale_counts` (at most [`MAX_MID_SCALE_COUNTS`] in magnitude)
    /// removed, shifted left by `shift` (0 to 15) bits.
    ///
    /// ```
    /// use angletrack_core::{AdcCounts, Parameter};
    /// let adc = AdcCounts::new(2048, 4)?;
    /// assert_eq!(adc.sample(3848u16, 2048u16), (1800 * 16, 0));
    /// assert_eq!(AdcCounts::new(0, 16).unwrap_err().parameter(), Parameter::AdcShift);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new(mid_scale_counts: i32, shift: u32) -> Result<Self, ConfigError> {
        if mid_scale_counts.unsigned_abs() > MAX_MID_SCALE_COUNTS as u32 {
            return Err(ConfigError::OutOfRange(Parameter::MidScaleCounts));
        }
        if shift > 15 {
            return Err(ConfigError::OutOfRange(Parameter::AdcShift));
        }
        Ok(Self {
            mid_scale_counts,
            shift,
            low: -(1 << 15) >> shift,
            high: ((1 << 15) - 1) >> shift,
        })
    }

    /// An unsigned (offset binary) ADC of `bits` bits (2 to 16): mid-scale `2^(bits-1)`,
    /// shifted by `16 - bits` (full scale is +-32768).
    ///
    /// ```
    /// use angletrack_core::AdcCounts;
    /// static ADC: AdcCounts = match AdcCounts::offset_binary(12) {
    ///     Ok(adc) => adc,
    ///     Err(_) => panic!("bad ADC"),
    /// };
    /// assert_eq!(ADC.sample(4095u16, 0u16), (2047 * 16, -32768));
    /// ```
    pub const fn offset_binary(bits: u32) -> Result<Self, ConfigError> {
        if bits < 2 || bits > 16 {
            return Err(ConfigError::OutOfRange(Parameter::AdcBits));
        }
        Self::new(1 << (bits - 1), 16 - bits)
    }

    /// A signed (two's complement) ADC of `bits` bits (2 to 16): mid-scale 0, shifted by
    /// `16 - bits`.
    ///
    /// ```
    /// use angletrack_core::AdcCounts;
    /// let adc = AdcCounts::twos_complement(16)?;
    /// assert_eq!(adc.sample(-32768i16, 16384i16), (-32768, 16384));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn twos_complement(bits: u32) -> Result<Self, ConfigError> {
        if bits < 2 || bits > 16 {
            return Err(ConfigError::OutOfRange(Parameter::AdcBits));
        }
        Self::new(0, 16 - bits)
    }

    /// One channel's sample for the fixed-point observer.
    #[inline(always)]
    pub fn scale<I: AdcSample>(&self, raw: I) -> i16 {
        let difference = raw.difference_from(self.mid_scale_counts);
        // `max` then `min`, not `clamp`, whose check of its bounds' order would be a panic
        // path for a configuration the optimiser cannot see (one from C memory, say).
        (difference.max(self.low).min(self.high) << self.shift) as i16
    }

    /// The code `code` as [`AdcCounts::scale`] takes it, in a `const fn` (for the range
    /// of a chain built in constant evaluation): the same saturation and shift.
    pub(crate) const fn code_sample(&self, code: i32) -> i16 {
        let difference = code.saturating_sub(self.mid_scale_counts);
        let low = if difference < self.low {
            self.low
        } else {
            difference
        };
        let saturated = if low > self.high { self.high } else { low };
        (saturated << self.shift) as i16
    }

    /// The pair `(y_c, y_s)` for the fixed-point observer, from the raw samples of the
    /// cosine and sine channels.
    #[inline(always)]
    pub fn sample<I: AdcSample>(&self, raw_c: I, raw_s: I) -> (i16, i16) {
        (self.scale(raw_c), self.scale(raw_s))
    }
}

#[cfg(test)]
mod tests;
