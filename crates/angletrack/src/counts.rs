//! Raw ADC counts as an observer's input: the mid-scale subtracted, divided by the counts
//! per unit (the core's [`AdcScaling`]), with the mid-scale found from the counts when none
//! is given.
//!
//! The rule ([`AdcCount::default_mid_scale`]): signed counts (`i16`, `i32`) have had their
//! mid-scale removed already (0); unsigned counts (`u16`, an offset-binary ADC) are centred
//! on [`offset_binary_mid_scale`] of their largest sample, `2^(b-1)` for the smallest
//! `b`-bit range that holds it, since a signal centred on the mid-scale always exceeds it.
//! A capture fed in chunks is scaled alike throughout: [`CountsInput`] decides the scaling
//! at its first chunk and keeps it. The loop needs no more (its phase error is normalised);
//! the monitor's amplitudes follow the signal ([`ThresholdPolicy`](crate::ThresholdPolicy)).
//!
//! ```
//! use angletrack::{CountsInput, CountsSettings};
//! // A 12-bit offset-binary ADC: a zero signal reads 2048.
//! let mut input = CountsInput::<f32>::new(CountsSettings::default());
//! let (y_c, y_s) = input.scale(&[4000_u16, 2048, 96], &[2048_u16, 4000, 2048])?;
//! assert_eq!((y_c, y_s), (vec![1952.0, 0.0, -1952.0], vec![0.0, 1952.0, 0.0]));
//! // The next chunk keeps the first one's mid-scale, whatever its largest sample.
//! assert_eq!(input.scale(&[1000_u16], &[2048_u16])?.0, vec![-1048.0]);
//! # Ok::<(), angletrack::ConfigError>(())
//! ```

use angletrack_core::{AdcSample, AdcScaling, ConfigError, Real};

/// The mid-scale `2^(b-1)` (counts) of unsigned, offset-binary ADC counts (0 to `2^b - 1`,
/// a zero signal at `2^(b-1)`) whose largest sample is `largest_count`, for the smallest
/// `b`, at least 2, whose range `2^b` holds it.
///
/// ```
/// use angletrack::offset_binary_mid_scale;
/// assert_eq!(offset_binary_mid_scale(4095), 2048); // 12 bits
/// assert_eq!(offset_binary_mid_scale(4096), 4096); // 13 bits
/// assert_eq!(offset_binary_mid_scale(0), 2);
/// ```
pub fn offset_binary_mid_scale(largest_count: u64) -> u64 {
    let bits = (u64::BITS - largest_count.leading_zeros()).max(2);
    1 << (bits - 1)
}

/// A capture's counts that no offset-binary ADC gives: the largest sample is not a whole
/// number from 0 to 2^53.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnsignedCountsError {
    /// The largest sample.
    pub largest: f64,
}

impl core::fmt::Display for UnsignedCountsError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "unsigned counts up to {:.0}: expected whole numbers of counts from 0 to 2^53",
            self.largest
        )
    }
}

impl std::error::Error for UnsignedCountsError {}

/// An integer type of raw ADC counts, with the mid-scale it is centred on when none is
/// given (the module's rule).
pub trait AdcCount: AdcSample {
    /// The mid-scale of the first samples `y_c`, `y_s` of a capture of this type.
    fn default_mid_scale(y_c: &[Self], y_s: &[Self]) -> i32
    where
        Self: Sized;
}

impl AdcCount for i16 {
    /// 0: signed counts have their mid-scale removed.
    fn default_mid_scale(_: &[Self], _: &[Self]) -> i32 {
        0
    }
}

impl AdcCount for i32 {
    /// 0: signed counts have their mid-scale removed.
    fn default_mid_scale(_: &[Self], _: &[Self]) -> i32 {
        0
    }
}

impl AdcCount for u16 {
    /// [`offset_binary_mid_scale`] of the largest sample (2 for no sample).
    fn default_mid_scale(y_c: &[Self], y_s: &[Self]) -> i32 {
        let largest = y_c.iter().chain(y_s).copied().max().unwrap_or(0);
        // At most 2^15 for a u16's largest sample: an i32 holds it.
        i32::try_from(offset_binary_mid_scale(u64::from(largest))).unwrap_or(i32::MAX)
    }
}

/// How counts are scaled: the mid-scale (`None`: by the module's rule) and the counts per
/// unit of the observer's input (1: the observer runs in counts). Checked by the core.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountsSettings {
    mid_scale: Option<i32>,
    counts_per_unit: f64,
}

impl CountsSettings {
    /// The settings, checked as the core's [`AdcScaling::new`] checks them (a
    /// [`ConfigError`] naming the mid-scale or the counts per unit).
    pub fn new(mid_scale: Option<i32>, counts_per_unit: f64) -> Result<Self, ConfigError> {
        AdcScaling::<f64>::new(mid_scale.unwrap_or(0), counts_per_unit)?;
        Ok(Self {
            mid_scale,
            counts_per_unit,
        })
    }

    /// The mid-scale given, if any.
    pub fn mid_scale(&self) -> Option<i32> {
        self.mid_scale
    }

    /// The counts per unit.
    pub fn counts_per_unit(&self) -> f64 {
        self.counts_per_unit
    }

    /// The scaling of a capture whose first samples are `y_c`, `y_s`: the mid-scale given,
    /// else [`AdcCount::default_mid_scale`] of these samples.
    pub fn scaling<T: Real, I: AdcCount>(
        &self,
        y_c: &[I],
        y_s: &[I],
    ) -> Result<AdcScaling<T>, ConfigError> {
        let mid_scale = self
            .mid_scale
            .unwrap_or_else(|| I::default_mid_scale(y_c, y_s));
        AdcScaling::new(mid_scale, T::from_f64(self.counts_per_unit))
    }
}

impl Default for CountsSettings {
    /// The mid-scale by the module's rule, one count per unit.
    fn default() -> Self {
        Self {
            mid_scale: None,
            counts_per_unit: 1.0,
        }
    }
}

/// The counts of one observer's input: the scaling is decided at the first chunk of
/// counts ([`CountsSettings::scaling`]) and kept for the chunks after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountsInput<T> {
    settings: CountsSettings,
    scaling: Option<AdcScaling<T>>,
}

impl<T: Real> CountsInput<T> {
    /// An input that decides its scaling at its first chunk.
    pub fn new(settings: CountsSettings) -> Self {
        Self {
            settings,
            scaling: None,
        }
    }

    /// The scaling decided, `None` before the first chunk.
    pub fn decided(&self) -> Option<AdcScaling<T>> {
        self.scaling
    }

    /// The scaling of the chunk `y_c`, `y_s`: decided from it if it is the first.
    pub fn scaling<I: AdcCount>(
        &mut self,
        y_c: &[I],
        y_s: &[I],
    ) -> Result<AdcScaling<T>, ConfigError> {
        match self.scaling {
            Some(scaling) => Ok(scaling),
            None => Ok(*self.scaling.insert(self.settings.scaling(y_c, y_s)?)),
        }
    }

    /// The chunk `y_c`, `y_s` in the observer's units.
    pub fn scale<I: AdcCount>(
        &mut self,
        y_c: &[I],
        y_s: &[I],
    ) -> Result<(Vec<T>, Vec<T>), ConfigError> {
        let scaling = self.scaling(y_c, y_s)?;
        let scale = |values: &[I]| values.iter().map(|&x| scaling.scale(x)).collect();
        Ok((scale(y_c), scale(y_s)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::Parameter;

    #[test]
    fn the_offset_binary_mid_scale_is_the_smallest_range_holding_the_largest_sample() {
        for (largest, mid) in [
            (0, 2),
            (3, 2),
            (4, 4),
            (1023, 512),
            (4095, 2048),
            (65535, 32768),
        ] {
            assert_eq!(offset_binary_mid_scale(largest), mid, "{largest}");
        }
        assert_eq!(offset_binary_mid_scale(1 << 53), 1 << 53);
    }

    #[test]
    fn unsigned_counts_are_centred_by_the_largest_sample_of_either_channel() {
        assert_eq!(u16::default_mid_scale(&[10, 20], &[4000]), 2048);
        assert_eq!(u16::default_mid_scale(&[65535], &[]), 32768);
        assert_eq!(u16::default_mid_scale(&[], &[]), 2);
        assert_eq!(i16::default_mid_scale(&[4000], &[4000]), 0);
        assert_eq!(i32::default_mid_scale(&[1 << 20], &[0]), 0);
    }

    #[test]
    fn a_given_mid_scale_and_counts_per_unit_are_used_as_they_are() {
        let settings = CountsSettings::new(Some(100), 2.0).unwrap();
        let mut input = CountsInput::<f64>::new(settings);
        let (c, s) = input.scale(&[4000_u16], &[100_u16]).unwrap();
        assert_eq!((c, s), (vec![1950.0], vec![0.0]));
        assert_eq!(
            (settings.mid_scale(), settings.counts_per_unit()),
            (Some(100), 2.0)
        );
    }

    #[test]
    fn settings_the_core_refuses_name_their_parameter() {
        let e = CountsSettings::new(None, 0.0).unwrap_err();
        assert_eq!(e.parameter(), Parameter::CountsPerUnit);
        let e = CountsSettings::new(Some((1 << 30) + 1), 1.0).unwrap_err();
        assert_eq!(e.parameter(), Parameter::MidScaleCounts);
    }

    #[test]
    fn the_first_chunk_decides_the_scaling() {
        let mut input = CountsInput::<f32>::new(CountsSettings::default());
        assert_eq!(input.decided(), None);
        input.scale(&[4095_u16], &[0_u16]).unwrap();
        let first = input.decided().unwrap();
        // A later chunk with a larger sample keeps the first mid-scale.
        assert_eq!(
            input.scale(&[8000_u16], &[2048_u16]).unwrap().0,
            vec![5952.0]
        );
        assert_eq!(input.decided(), Some(first));
    }
}
