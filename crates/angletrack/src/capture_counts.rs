//! The signedness and mid-scale of a capture of whole ADC counts: stated by the caller, or
//! read from the whole capture, never guessed from its first samples.
//!
//! The rule ([`capture_counts`]), in order:
//! 1. signedness stated by the caller: taken as stated;
//! 2. counts of an unsigned type (a `.npy` capture of `uint8`, `uint16`, `uint32`):
//!    unsigned;
//! 3. a negative sample anywhere in the capture: signed;
//! 4. both channels swinging both above and below one mid-scale `2^(b-1)` (the smallest
//!    `b`-bit range that holds the largest sample, [`offset_binary_mid_scale`]): the
//!    Lissajous figure is centred on the mid-scale of an offset-binary ADC: unsigned;
//! 5. otherwise (every sample non-negative, a shaft at rest or turning little) the counts
//!    could be either: refused ([`CountsError::Ambiguous`]), for the caller to state.
//!
//! Unsigned counts are centred on `2^(b-1)` for the stated resolution `b`, else on
//! [`offset_binary_mid_scale`] of the capture's largest sample. All the rule reads of the
//! samples is each channel's extremes ([`CountsExtremes`]), which a capture read in
//! chunks gathers in one pass.
//!
//! ```
//! use angletrack::{CountsExtremes, Signedness, StatedCounts, capture_counts};
//! // 12-bit offset-binary counts of a turning shaft: unsigned, centred on 2048.
//! let whole = CountsExtremes::of(&[248.0, 3848.0, 2048.0], &[2048.0, 300.0, 3800.0]);
//! let counts = capture_counts(StatedCounts::default(), false, &whole)?;
//! assert_eq!((counts.signedness, counts.mid_scale), (Signedness::Unsigned, 2048));
//! // A shaft at rest at 60 degrees: signed or offset binary alike, refused unless stated.
//! let still = CountsExtremes::of(&[2948.0; 4], &[3607.0; 4]);
//! assert!(capture_counts(StatedCounts::default(), false, &still).is_err());
//! let stated = StatedCounts { signedness: Some(Signedness::Unsigned), bits: Some(12) };
//! assert_eq!(capture_counts(stated, false, &still)?.mid_scale, 2048);
//! # Ok::<(), angletrack::CountsError>(())
//! ```

use crate::counts::{UnsignedCountsError, offset_binary_mid_scale};

/// How integer ADC counts encode a signal's zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Signedness {
    /// Two's complement: a zero signal reads 0.
    Signed,
    /// Offset binary: a zero signal reads the mid-scale `2^(b-1)` of a `b`-bit ADC.
    Unsigned,
}

impl Signedness {
    /// Two's complement for `true`, offset binary for `false` (an `adc_signed` argument).
    ///
    /// ```
    /// use angletrack::Signedness;
    /// assert_eq!(Signedness::of_signed(false), Signedness::Unsigned);
    /// ```
    pub fn of_signed(signed: bool) -> Self {
        if signed { Self::Signed } else { Self::Unsigned }
    }
}

/// What the caller stated of a capture's counts (`None`: not stated).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StatedCounts {
    /// The counts' signedness.
    pub signedness: Option<Signedness>,
    /// The ADC's resolution (bits, 2 to 53): an unsigned capture's mid-scale is `2^(b-1)`.
    pub bits: Option<u32>,
}

/// Each channel's lowest and highest finite sample of a capture, gathered chunk by chunk
/// (non-finite samples are left out).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CountsExtremes {
    channels: [Option<(f64, f64)>; 2],
}

impl CountsExtremes {
    /// No sample yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The extremes of `y_c`, `y_s`.
    pub fn of(y_c: &[f64], y_s: &[f64]) -> Self {
        let mut extremes = Self::new();
        extremes.add(y_c, y_s);
        extremes
    }

    /// Adds the chunk `y_c`, `y_s`.
    pub fn add(&mut self, y_c: &[f64], y_s: &[f64]) {
        for (extremes, y) in self.channels.iter_mut().zip([y_c, y_s]) {
            for &v in y.iter().filter(|v| v.is_finite()) {
                *extremes = Some(match *extremes {
                    Some((low, high)) => (low.min(v), high.max(v)),
                    None => (v, v),
                });
            }
        }
    }

    /// `y_c`'s and `y_s`'s `(lowest, highest)`, `None` for a channel without a sample.
    pub fn channels(&self) -> [Option<(f64, f64)>; 2] {
        self.channels
    }

    fn lowest(&self) -> Option<f64> {
        self.channels.iter().flatten().map(|e| e.0).reduce(f64::min)
    }

    fn highest(&self) -> Option<f64> {
        self.channels.iter().flatten().map(|e| e.1).reduce(f64::max)
    }
}

/// The decision of [`capture_counts`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CaptureCounts {
    /// The counts' signedness.
    pub signedness: Signedness,
    /// The mid-scale to subtract (0 for signed counts).
    pub mid_scale: u64,
}

impl CaptureCounts {
    /// The counts whose mid-scale is `mid_scale`: signed (two's complement) at 0, offset
    /// binary otherwise, as [`capture_counts`] decides them.
    pub fn of_mid_scale(mid_scale: u64) -> Self {
        Self {
            signedness: Signedness::of_signed(mid_scale == 0),
            mid_scale,
        }
    }
}

/// Why [`capture_counts`] decides nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CountsError {
    /// No sample is negative and the channels do not swing about one mid-scale: the
    /// counts may be signed or offset binary; the caller must state which.
    Ambiguous {
        /// The capture's lowest and highest samples.
        lowest: f64,
        /// See `lowest`.
        highest: f64,
    },
    /// Unsigned counts whose largest sample no offset-binary ADC gives.
    NotCounts(UnsignedCountsError),
    /// A stated resolution outside 2 to 53 bits.
    Bits(u32),
}

impl core::fmt::Display for CountsError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CountsError::Ambiguous { lowest, highest } => write!(
                f,
                "the counts' signedness is not stated and the capture does not show it: its \
                 samples ({lowest} to {highest}) are all non-negative and do not swing about an \
                 offset-binary mid-scale, as signed counts of a shaft at rest or turning little \
                 and unsigned ones alike may; state it"
            ),
            CountsError::NotCounts(e) => e.fmt(f),
            CountsError::Bits(bits) => write!(f, "{bits} bits: expected 2 to 53"),
        }
    }
}

impl std::error::Error for CountsError {}

/// The signedness and mid-scale of a capture of whole counts by the module's rule, from
/// what the caller `stated`, whether the counts' type is unsigned (`unsigned_type`), and
/// the extremes of the `whole` capture.
pub fn capture_counts(
    stated: StatedCounts,
    unsigned_type: bool,
    whole: &CountsExtremes,
) -> Result<CaptureCounts, CountsError> {
    let signedness = match stated.signedness {
        Some(signedness) => signedness,
        None if unsigned_type => Signedness::Unsigned,
        None if whole.lowest().is_some_and(|low| low < 0.0) => Signedness::Signed,
        None if swings_about_mid_scale(whole) => Signedness::Unsigned,
        None => {
            return Err(CountsError::Ambiguous {
                lowest: whole.lowest().unwrap_or(0.0),
                highest: whole.highest().unwrap_or(0.0),
            });
        }
    };
    let mid_scale = match (signedness, stated.bits) {
        (Signedness::Signed, _) => 0,
        (Signedness::Unsigned, Some(bits)) if (2..=53).contains(&bits) => 1 << (bits - 1),
        (Signedness::Unsigned, Some(bits)) => return Err(CountsError::Bits(bits)),
        (Signedness::Unsigned, None) => largest_mid_scale(whole).map_err(CountsError::NotCounts)?,
    };
    Ok(CaptureCounts {
        signedness,
        mid_scale,
    })
}

/// Whether both channels swing both above and below the offset-binary mid-scale of the
/// capture's largest sample.
fn swings_about_mid_scale(whole: &CountsExtremes) -> bool {
    let Ok(mid) = largest_mid_scale(whole) else {
        return false;
    };
    let mid = mid as f64;
    whole
        .channels
        .iter()
        .all(|e| e.is_some_and(|(low, high)| low < mid && high > mid))
}

/// [`offset_binary_mid_scale`] of the capture's largest sample (0 for no sample or none
/// positive: nothing to centre), refused when it is no whole number from 0 to 2^53.
fn largest_mid_scale(whole: &CountsExtremes) -> Result<u64, UnsignedCountsError> {
    /// 2^53, below which every whole number is an `f64`.
    const LARGEST_EXACT_COUNT: f64 = 9_007_199_254_740_992.0;
    match whole.highest() {
        None => Ok(0),
        Some(largest) if largest <= 0.0 => Ok(0),
        Some(largest) if largest.fract() == 0.0 && largest <= LARGEST_EXACT_COUNT => {
            // Checked: a whole number from 1 to 2^53, exact as a u64.
            Ok(offset_binary_mid_scale(largest as u64))
        }
        Some(largest) => Err(UnsignedCountsError { largest }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decide(stated: StatedCounts, unsigned_type: bool, c: &[f64], s: &[f64]) -> String {
        match capture_counts(stated, unsigned_type, &CountsExtremes::of(c, s)) {
            Ok(CaptureCounts {
                signedness,
                mid_scale,
            }) => format!("{signedness:?} {mid_scale}"),
            Err(CountsError::Ambiguous { .. }) => "ambiguous".into(),
            Err(e) => e.to_string(),
        }
    }

    fn turn(offset: f64, from: f64, to: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let theta = |k: usize| from + (to - from) * k as f64 / n as f64;
        (
            (0..n)
                .map(|k| (offset + 1800.0 * theta(k).cos()).round())
                .collect(),
            (0..n)
                .map(|k| (offset + 1800.0 * theta(k).sin()).round())
                .collect(),
        )
    }

    #[test]
    fn signed_counts_at_rest_in_the_first_quadrant_are_refused_not_taken_unsigned() {
        // At rest at 0.5 rad for the first 70,000 samples, then turning: signed, read from
        // the whole capture (its first samples alone are all positive).
        let (mut c, mut s) = (vec![1580.0; 70_000], vec![863.0; 70_000]);
        let (tc, ts) = turn(0.0, 0.5, 20.0, 30_000);
        c.extend(tc);
        s.extend(ts);
        let none = StatedCounts::default();
        assert_eq!(decide(none, false, &c, &s), "Signed 0");
        assert_eq!(decide(none, false, &c[..70_000], &s[..70_000]), "ambiguous");
        let signed = StatedCounts {
            signedness: Some(Signedness::Signed),
            bits: None,
        };
        assert_eq!(
            decide(signed, false, &c[..70_000], &s[..70_000]),
            "Signed 0"
        );
    }

    #[test]
    fn offset_binary_is_read_from_the_whole_capture_or_the_type() {
        let none = StatedCounts::default();
        let (c, s) = turn(2048.0, 0.0, 7.0, 1000);
        assert_eq!(decide(none, false, &c, &s), "Unsigned 2048");
        // A quarter turn from 0.1 rad: y_s never goes below 2048.
        let (c, s) = turn(2048.0, 0.1, 1.5, 1000);
        assert_eq!(decide(none, false, &c, &s), "ambiguous");
        assert_eq!(decide(none, true, &c, &s), "Unsigned 2048");
        // A still shaft in 12-bit counts, at 60 degrees: stated, or refused.
        let (c, s) = (vec![2948.0; 20_000], vec![3607.0; 20_000]);
        assert_eq!(decide(none, false, &c, &s), "ambiguous");
        let unsigned = |bits| StatedCounts {
            signedness: Some(Signedness::Unsigned),
            bits,
        };
        assert_eq!(decide(unsigned(Some(12)), false, &c, &s), "Unsigned 2048");
        assert_eq!(decide(unsigned(None), false, &c, &s), "Unsigned 2048");
        // 16 bits stated though the samples stay within 12.
        assert_eq!(decide(unsigned(Some(16)), false, &c, &s), "Unsigned 32768");
        assert_eq!(
            decide(unsigned(Some(1)), false, &c, &s),
            "1 bits: expected 2 to 53"
        );
    }

    #[test]
    fn counts_no_adc_gives_are_refused_and_extremes_gather_by_chunk() {
        let unsigned = StatedCounts {
            signedness: Some(Signedness::Unsigned),
            bits: None,
        };
        for bad in [2.5, 2f64.powi(60)] {
            let e = decide(unsigned, false, &[1.0, bad], &[1.0]);
            assert!(e.starts_with("unsigned counts up to"), "{e}");
        }
        let mut chunked = CountsExtremes::new();
        chunked.add(&[3.0, f64::NAN], &[]);
        chunked.add(&[-1.0], &[7.0]);
        assert_eq!(chunked, CountsExtremes::of(&[3.0, -1.0], &[7.0]));
        assert_eq!(chunked.channels(), [Some((-1.0, 3.0)), Some((7.0, 7.0))]);
    }

    #[test]
    fn a_mid_scale_tells_the_signedness() {
        assert_eq!(
            CaptureCounts::of_mid_scale(0).signedness,
            Signedness::Signed
        );
        let offset_binary = CaptureCounts::of_mid_scale(2048);
        assert_eq!(offset_binary.signedness, Signedness::Unsigned);
        assert_eq!(offset_binary.mid_scale, 2048);
    }
}
