//! Raw ADC counts as an observer's input: the mid-scale subtracted, divided by the counts
//! per unit (the core's [`AdcScaling`]).
//!
//! The mid-scale is stated, or follows from the counts' type and, for a whole capture, the
//! module [`capture_counts`]'s rule; it is never read from one chunk of a stream, which would
//! scale a capture fed in chunks otherwise than the same capture in one call
//! ([`CountsInput`]):
//! * a stated mid-scale is removed as stated;
//! * counts of a type the caller chose as signed (`i16`, `i32` arrays) have it removed already
//!   (0);
//! * otherwise a [`CountsInput::whole`] capture (every sample in one call) is decided by
//!   [`capture_counts`]: the signedness stated, else unsigned for an unsigned type (`u16`),
//!   signed for a negative sample, unsigned when both channels swing about one offset-binary
//!   mid-scale, else refused;
//! * a [`CountsInput::stream`] (chunks to come) refuses unsigned counts without a stated
//!   mid-scale, and counts of no stated signedness, as it cannot see the whole capture.
//!
//! ```
//! use angletrack::{CountsInput, CountsSettings, Signedness};
//! // A 12-bit offset-binary ADC, its mid-scale stated: a zero signal reads 2048.
//! let settings = CountsSettings::new(Some(2048), None, None)?;
//! let mut input = CountsInput::<f32>::stream(settings);
//! let (y_c, y_s) = input.scale(&[4000_u16, 2048, 96], &[2048_u16, 4000, 2048], None)?;
//! assert_eq!((y_c, y_s), (vec![1952.0, 0.0, -1952.0], vec![0.0, 1952.0, 0.0]));
//! // Not stated: a stream of unsigned counts is refused; a whole capture shows it.
//! let mut stream = CountsInput::<f32>::stream(CountsSettings::default());
//! assert!(stream.scale(&[4000_u16], &[2048_u16], None).is_err());
//! let mut whole = CountsInput::<f32>::whole(CountsSettings::default());
//! assert_eq!(whole.scale(&[4000_u16], &[2048_u16], None)?.0, vec![1952.0]);
//! // Signed counts: by their type, or stated.
//! assert_eq!(stream.scale(&[-7_i32], &[7_i32], Some(Signedness::Signed))?.0, vec![-7.0]);
//! # Ok::<(), angletrack::CountsInputError>(())
//! ```

use angletrack_core::{AdcSample, AdcScaling, ConfigError, Real};

use crate::capture_counts::{
    CountsError, CountsExtremes, Signedness, StatedCounts, capture_counts,
};

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

/// An integer type of raw ADC counts.
pub trait AdcCount: AdcSample {
    /// The signedness the type itself states: unsigned for `u16`, none for the others
    /// (whose caller states it, or not).
    const UNSIGNED: bool;
    /// The count as an `f64` (exact).
    fn count(self) -> f64;
}

impl AdcCount for i16 {
    const UNSIGNED: bool = false;
    fn count(self) -> f64 {
        f64::from(self)
    }
}

impl AdcCount for i32 {
    const UNSIGNED: bool = false;
    fn count(self) -> f64 {
        f64::from(self)
    }
}

impl AdcCount for u16 {
    const UNSIGNED: bool = true;
    fn count(self) -> f64 {
        f64::from(self)
    }
}

/// One channel's raw ADC counts, of an integer type an observer takes: `i16` and `i32` signed
/// by the caller's choice of type, `u16` unsigned, `i64` (numpy's default integer) read as
/// `i32` (range-checked), of no signedness of its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChannelCounts<'a> {
    /// Signed 16-bit counts.
    I16(&'a [i16]),
    /// Unsigned (offset-binary) 16-bit counts.
    U16(&'a [u16]),
    /// Signed 32-bit counts.
    I32(&'a [i32]),
    /// 64-bit counts, each within the `i32` range.
    I64(&'a [i64]),
}

macro_rules! channel_counts_from {
    ($($variant:ident: $t:ty),*) => {$(
        impl<'a> From<&'a [$t]> for ChannelCounts<'a> {
            fn from(counts: &'a [$t]) -> Self {
                ChannelCounts::$variant(counts)
            }
        }
    )*};
}
channel_counts_from!(I16: i16, U16: u16, I32: i32, I64: i64);

/// `counts` of channel `channel` as `i32`, or the first beyond its range.
fn narrowed(counts: &[i64], channel: &'static str) -> Result<Vec<i32>, CountsInputError> {
    let narrow = |(index, &count): (usize, &i64)| {
        i32::try_from(count).map_err(|_| CountsInputError::BeyondI32 {
            channel,
            index,
            count,
        })
    };
    counts.iter().enumerate().map(narrow).collect()
}

/// What the caller stated of the counts: the mid-scale, the counts per unit of the
/// observer's input (`None`: 1, the observer runs in counts) and the signedness. Checked
/// by the core.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CountsSettings {
    mid_scale: Option<i32>,
    counts_per_unit: Option<f64>,
    signedness: Option<Signedness>,
}

impl CountsSettings {
    /// The settings, checked as the core's [`AdcScaling::new`] checks them (a
    /// [`ConfigError`] naming the mid-scale or the counts per unit).
    pub fn new(
        mid_scale: Option<i32>,
        counts_per_unit: Option<f64>,
        signedness: Option<Signedness>,
    ) -> Result<Self, ConfigError> {
        AdcScaling::<f64>::new(mid_scale.unwrap_or(0), counts_per_unit.unwrap_or(1.0))?;
        Ok(Self {
            mid_scale,
            counts_per_unit,
            signedness,
        })
    }

    /// The mid-scale stated, if any.
    pub fn mid_scale(&self) -> Option<i32> {
        self.mid_scale
    }

    /// The counts per unit stated, if any (1 when not).
    pub fn counts_per_unit(&self) -> Option<f64> {
        self.counts_per_unit
    }

    /// The signedness stated, if any.
    pub fn signedness(&self) -> Option<Signedness> {
        self.signedness
    }
}

/// Why a [`CountsInput`] scales no counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CountsInputError {
    /// The scaling the core refuses.
    Scaling(ConfigError),
    /// A whole capture that [`capture_counts`] decides nothing for.
    Counts(CountsError),
    /// Unsigned counts of a stream without a stated mid-scale.
    StreamMidScale,
    /// Counts of a stream of no signedness stated (by the caller or the type).
    StreamSignedness,
    /// The two channels' counts of different types ([`ChannelCounts`]).
    MixedTypes,
    /// An `i64` count beyond the `i32` range, the first of its channel (`"y_c"` or `"y_s"`).
    BeyondI32 {
        /// The channel, `"y_c"` or `"y_s"`.
        channel: &'static str,
        /// The sample's index in the chunk.
        index: usize,
        /// The count.
        count: i64,
    },
}

impl core::fmt::Display for CountsInputError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CountsInputError::Scaling(e) => e.fmt(f),
            CountsInputError::Counts(e) => e.fmt(f),
            CountsInputError::StreamMidScale => f.write_str(
                "unsigned counts fed in chunks need their mid-scale stated (2048 for a 12-bit \
                 ADC): no chunk shows the whole capture's",
            ),
            CountsInputError::StreamSignedness => f.write_str(
                "counts fed in chunks need their signedness stated: no chunk shows the whole \
                 capture's",
            ),
            CountsInputError::MixedTypes => {
                f.write_str("the cosine and sine counts are of different types")
            }
            CountsInputError::BeyondI32 { index, count, .. } => {
                write!(f, "int64 count {count} at index {index} is beyond +-2^31")
            }
        }
    }
}

impl std::error::Error for CountsInputError {}

impl From<ConfigError> for CountsInputError {
    fn from(e: ConfigError) -> Self {
        CountsInputError::Scaling(e)
    }
}

/// The counts of one observer's input, scaled by the module's rule: the same scaling for
/// every call, decided without reading the samples ([`CountsInput::stream`]) or from the
/// one call that holds the whole capture ([`CountsInput::whole`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountsInput<T> {
    settings: CountsSettings,
    whole: bool,
    scaling: Option<AdcScaling<T>>,
}

impl<T: Real> CountsInput<T> {
    /// The input of a stream: chunks to come, none of which shows the whole capture.
    pub fn stream(settings: CountsSettings) -> Self {
        Self {
            settings,
            whole: false,
            scaling: None,
        }
    }

    /// The input of a whole capture, given in one call.
    pub fn whole(settings: CountsSettings) -> Self {
        Self {
            whole: true,
            ..Self::stream(settings)
        }
    }

    /// The settings stated.
    pub fn settings(&self) -> CountsSettings {
        self.settings
    }

    /// The scaling of the last chunk, `None` before the first.
    pub fn decided(&self) -> Option<AdcScaling<T>> {
        self.scaling
    }

    /// The scaling of the chunk `y_c`, `y_s` of counts of type `I`, `signedness` the one the
    /// caller's choice of type states (`None`: none; the settings' own comes first).
    pub fn scaling<I: AdcCount>(
        &mut self,
        y_c: &[I],
        y_s: &[I],
        signedness: Option<Signedness>,
    ) -> Result<AdcScaling<T>, CountsInputError> {
        let signedness = self.settings.signedness.or(signedness);
        let mid_scale = match (self.settings.mid_scale, signedness) {
            (Some(mid), _) => mid,
            (None, Some(Signedness::Signed)) => 0,
            (None, _) if self.whole => {
                let count = |y: &[I]| -> Vec<f64> { y.iter().map(|&v| v.count()).collect() };
                let extremes = CountsExtremes::of(&count(y_c), &count(y_s));
                let stated = StatedCounts {
                    signedness,
                    bits: None,
                };
                let decided = capture_counts(stated, I::UNSIGNED, &extremes)
                    .map_err(CountsInputError::Counts)?;
                i32::try_from(decided.mid_scale).map_err(|_| {
                    ConfigError::OutOfRange(angletrack_core::Parameter::MidScaleCounts)
                })?
            }
            (None, Some(Signedness::Unsigned)) => return Err(CountsInputError::StreamMidScale),
            (None, None) if I::UNSIGNED => return Err(CountsInputError::StreamMidScale),
            (None, None) => return Err(CountsInputError::StreamSignedness),
        };
        let per_unit = T::from_f64(self.settings.counts_per_unit.unwrap_or(1.0));
        Ok(*self.scaling.insert(AdcScaling::new(mid_scale, per_unit)?))
    }

    /// The chunk `y_c`, `y_s` in the observer's units ([`CountsInput::scaling`]).
    pub fn scale<I: AdcCount>(
        &mut self,
        y_c: &[I],
        y_s: &[I],
        signedness: Option<Signedness>,
    ) -> Result<(Vec<T>, Vec<T>), CountsInputError> {
        let scaling = self.scaling(y_c, y_s, signedness)?;
        let scale = |values: &[I]| values.iter().map(|&x| scaling.scale(x)).collect();
        Ok((scale(y_c), scale(y_s)))
    }

    /// The chunk `y_c`, `y_s`, counts of one type ([`ChannelCounts`]: its signedness, `i64`
    /// narrowed to `i32`, the cosine's first), in the observer's units
    /// ([`CountsInput::scale`]); channels of different types are refused.
    ///
    /// ```
    /// use angletrack::{ChannelCounts, CountsInput, CountsInputError, CountsSettings};
    /// let mut input = CountsInput::<f64>::stream(CountsSettings::default());
    /// let (c, s) = input.scale_channels(ChannelCounts::I16(&[-7]), ChannelCounts::I16(&[7]))?;
    /// assert_eq!((c, s), (vec![-7.0], vec![7.0]));
    /// let e = input.scale_channels(ChannelCounts::I64(&[0]), ChannelCounts::I64(&[1 << 40]));
    /// assert!(matches!(e, Err(CountsInputError::BeyondI32 { channel: "y_s", index: 0, .. })));
    /// let mixed = input.scale_channels(ChannelCounts::I16(&[0]), ChannelCounts::I32(&[0]));
    /// assert_eq!(mixed, Err(CountsInputError::MixedTypes));
    /// # Ok::<(), CountsInputError>(())
    /// ```
    pub fn scale_channels(
        &mut self,
        y_c: ChannelCounts<'_>,
        y_s: ChannelCounts<'_>,
    ) -> Result<(Vec<T>, Vec<T>), CountsInputError> {
        use ChannelCounts as C;
        let signed = Some(Signedness::Signed);
        match (y_c, y_s) {
            (C::I16(c), C::I16(s)) => self.scale(c, s, signed),
            (C::U16(c), C::U16(s)) => self.scale(c, s, None),
            (C::I32(c), C::I32(s)) => self.scale(c, s, signed),
            (C::I64(c), C::I64(s)) => self.scale(&narrowed(c, "y_c")?, &narrowed(s, "y_s")?, None),
            _ => Err(CountsInputError::MixedTypes),
        }
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
    fn a_given_mid_scale_and_counts_per_unit_are_used_as_they_are() {
        let settings = CountsSettings::new(Some(100), Some(2.0), None).unwrap();
        let mut input = CountsInput::<f64>::stream(settings);
        let (c, s) = input.scale(&[4000_u16], &[100_u16], None).unwrap();
        assert_eq!((c, s), (vec![1950.0], vec![0.0]));
        assert_eq!(
            (settings.mid_scale(), settings.counts_per_unit()),
            (Some(100), Some(2.0))
        );
    }

    #[test]
    fn settings_the_core_refuses_name_their_parameter() {
        let e = CountsSettings::new(None, Some(0.0), None).unwrap_err();
        assert_eq!(e.parameter(), Parameter::CountsPerUnit);
        let e = CountsSettings::new(Some((1 << 30) + 1), None, None).unwrap_err();
        assert_eq!(e.parameter(), Parameter::MidScaleCounts);
    }

    /// A 12-bit capture at rest at 200 degrees (every sample below 2048), then turning.
    fn resting_then_turning() -> (Vec<u16>, Vec<u16>) {
        let theta = |k: usize| {
            3.49 + if k < 100 {
                0.0
            } else {
                0.05 * (k - 100) as f64
            }
        };
        let count = |v: f64| (2048.0 + 1800.0 * v).round() as u16;
        (
            (0..400).map(|k| count(theta(k).cos())).collect(),
            (0..400).map(|k| count(theta(k).sin())).collect(),
        )
    }

    #[test]
    fn a_stream_scales_every_chunk_alike_or_refuses() {
        // Fed in chunks of 1, 7 or at once, a stream scales by what is stated only: the
        // same counts whatever the chunks (a first chunk's largest sample would give 1024
        // for this capture at rest below 2048).
        let (c, s) = resting_then_turning();
        let settings = CountsSettings::new(Some(2048), None, None).unwrap();
        let mut one = CountsInput::<f64>::stream(settings);
        let whole = one.scale(&c, &s, None).unwrap();
        for chunk in [1, 7] {
            let mut input = CountsInput::<f64>::stream(settings);
            let (mut cc, mut ss) = (vec![], vec![]);
            for (c, s) in c.chunks(chunk).zip(s.chunks(chunk)) {
                let (c, s) = input.scale(c, s, None).unwrap();
                cc.extend(c);
                ss.extend(s);
            }
            assert_eq!((cc, ss), whole, "chunks of {chunk}");
        }
        let mut unstated = CountsInput::<f64>::stream(CountsSettings::default());
        let e = unstated.scale(&c[..1], &s[..1], None).unwrap_err();
        assert_eq!(e, CountsInputError::StreamMidScale);
        let wide: Vec<i32> = c.iter().map(|&v| i32::from(v)).collect();
        let e = unstated.scale(&wide, &wide, None).unwrap_err();
        assert_eq!(e, CountsInputError::StreamSignedness);
        let signed = Some(Signedness::Signed);
        assert_eq!(
            unstated.scale(&[-5_i32], &[5], signed).unwrap().0,
            vec![-5.0]
        );
    }

    #[test]
    fn a_whole_capture_is_decided_by_the_capture_rule() {
        let (c, s) = resting_then_turning();
        let mut input = CountsInput::<f64>::whole(CountsSettings::default());
        input.scale(&c, &s, None).unwrap();
        assert_eq!(input.decided().unwrap().mid_scale_counts(), 2048);
        // int32 counts (no signedness of their own) at rest: refused, not guessed.
        let still = [2948_i32; 50];
        let e = input.scale(&still, &still, None).unwrap_err();
        assert!(matches!(
            e,
            CountsInputError::Counts(CountsError::Ambiguous { .. })
        ));
        let unsigned = CountsSettings::new(None, None, Some(Signedness::Unsigned)).unwrap();
        let mut input = CountsInput::<f64>::whole(unsigned);
        input.scale(&still, &[3607; 50], None).unwrap();
        assert_eq!(input.decided().unwrap().mid_scale_counts(), 2048);
    }
}
