//! The monitor's fault thresholds of an observer: stated, never measured on one chunk of a
//! stream, so that a capture fed in chunks is monitored exactly as in one call
//! (`docs/theory.md §12`).
//!
//! The rule ([`ThresholdPolicy`]):
//! * thresholds given by the caller are used as they are;
//! * a stream (chunks to come) without them runs with the core's defaults, those of a
//!   signal of amplitude 1 in the observer's units: floats of amplitude about 1, or counts
//!   whose counts per unit are stated (the signal's amplitude in counts makes the defaults
//!   fractions of it). Raw counts in counts without thresholds are refused: their amplitude
//!   is not known before the samples;
//! * a whole capture given in one call without them is measured on its first samples
//!   ([`capture_fault_thresholds`]).
//!
//! ```
//! use angletrack::{ThresholdInput, ThresholdPolicy};
//! use angletrack_core::FaultThresholds;
//! // A stream of floats: the defaults, whatever its chunks hold.
//! let mut stream = ThresholdPolicy::<f64>::stream(None);
//! assert_eq!(stream.thresholds(), Some(FaultThresholds::default()));
//! assert_eq!(stream.decide(ThresholdInput::Floats, &[1800.0], &[0.0]), Ok(None));
//! // Raw counts in counts: refused without thresholds.
//! let counts = ThresholdInput::Counts { counts_per_unit_stated: false };
//! assert!(stream.decide(counts, &[1800.0], &[0.0]).is_err());
//! // A whole capture in one call: measured on it (amplitude 1800 counts).
//! let mut whole = ThresholdPolicy::<f64>::whole(None);
//! let decided = whole.decide(counts, &[1800.0, 0.0, -1800.0], &[0.0, 1800.0, 0.0]);
//! assert_eq!(decided.unwrap().unwrap().nominal_amplitude, 1800.0);
//! ```

use angletrack_core::{FaultThresholds, Real};

use crate::capture_fault_thresholds;

/// `t` in the float type `U`, each threshold rounded to it (checked where an observer
/// takes them).
///
/// ```
/// use angletrack::{converted_thresholds, core::FaultThresholds};
/// let t = FaultThresholds::<f64>::for_amplitude(0.1).with_max_speed(Some(1e3));
/// let narrow: FaultThresholds<f32> = converted_thresholds(&t);
/// assert_eq!((narrow.nominal_amplitude, narrow.max_speed), (0.1f32, Some(1e3f32)));
/// ```
pub fn converted_thresholds<T: Real, U: Real>(t: &FaultThresholds<T>) -> FaultThresholds<U> {
    let f = |x: T| U::from_f64(x.to_f64());
    FaultThresholds::for_amplitude(f(t.nominal_amplitude))
        .with_max_input_amplitude(f(t.max_input_amplitude))
        .with_loss_of_signal(f(t.loss_of_signal))
        .with_degradation_low(f(t.degradation_low))
        .with_degradation_high(f(t.degradation_high))
        .with_loss_of_tracking(f(t.loss_of_tracking))
        .with_tracking_error(f(t.tracking_error))
        .with_max_speed(t.max_speed.map(f))
        .with_filter_factor(f(t.filter_factor))
        .with_false_lock(f(t.false_lock))
        .with_monitor(t.monitor)
        .with_re_acquire(t.re_acquire)
        .with_magnitude_tolerance(t.magnitude_tolerance.map(f))
}

/// What an observer's samples are, as far as its thresholds' rule is concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThresholdInput {
    /// Floats, taken as they are.
    Floats,
    /// Raw counts, scaled by a stated counts per unit or not.
    Counts {
        /// Whether the counts per unit were stated.
        counts_per_unit_stated: bool,
    },
}

/// Raw counts of a stream in counts, without thresholds: their amplitude is not known
/// before the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ThresholdsNotStated;

impl core::fmt::Display for ThresholdsNotStated {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(
            "raw counts fed in chunks need the signal's amplitude stated for the diagnostics \
             (no chunk shows the whole capture's)",
        )
    }
}

impl std::error::Error for ThresholdsNotStated {}

/// Where an observer's fault thresholds come from (the module's rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThresholdPolicy<T> {
    /// Given by the caller (or decided already): used as they are.
    Given(FaultThresholds<T>),
    /// A stream without thresholds: the defaults; raw counts in counts refused.
    Stream,
    /// A whole capture in one call without thresholds, not run yet:
    /// [`capture_fault_thresholds`] of its samples.
    Whole,
}

impl<T: Real> ThresholdPolicy<T> {
    /// The policy of a stream: the thresholds `given`, or the module's rule for a stream.
    pub fn stream(given: Option<FaultThresholds<T>>) -> Self {
        given.map_or(ThresholdPolicy::Stream, ThresholdPolicy::Given)
    }

    /// The policy of a whole capture given in one call: the thresholds `given`, or
    /// measured on it.
    pub fn whole(given: Option<FaultThresholds<T>>) -> Self {
        given.map_or(ThresholdPolicy::Whole, ThresholdPolicy::Given)
    }

    /// The thresholds the observer runs with; `None` for a whole capture not run yet.
    pub fn thresholds(&self) -> Option<FaultThresholds<T>> {
        match self {
            ThresholdPolicy::Given(thresholds) => Some(*thresholds),
            ThresholdPolicy::Stream => Some(FaultThresholds::default()),
            ThresholdPolicy::Whole => None,
        }
    }

    /// Before running the chunk `y_c`, `y_s` of `input`: the thresholds the observer's
    /// gains must take from this chunk on (`None`: those it has), or the refusal of raw
    /// counts of a stream without thresholds.
    pub fn decide(
        &mut self,
        input: ThresholdInput,
        y_c: &[T],
        y_s: &[T],
    ) -> Result<Option<FaultThresholds<T>>, ThresholdsNotStated> {
        match (*self, input) {
            (ThresholdPolicy::Given(_), _) => Ok(None),
            (
                ThresholdPolicy::Stream,
                ThresholdInput::Counts {
                    counts_per_unit_stated: false,
                },
            ) => Err(ThresholdsNotStated),
            (ThresholdPolicy::Stream, _) => Ok(None),
            (ThresholdPolicy::Whole, _) => {
                let thresholds = capture_fault_thresholds(y_c, y_s);
                *self = ThresholdPolicy::Given(thresholds);
                Ok(Some(thresholds))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_thresholds_are_kept_and_never_redecided() {
        let given = FaultThresholds::<f32>::for_amplitude(0.455);
        for mut policy in [
            ThresholdPolicy::stream(Some(given)),
            ThresholdPolicy::whole(Some(given)),
        ] {
            assert_eq!(policy.thresholds(), Some(given));
            let counts = ThresholdInput::Counts {
                counts_per_unit_stated: false,
            };
            assert_eq!(policy.decide(counts, &[1800.0], &[0.0]), Ok(None));
            assert_eq!(policy, ThresholdPolicy::Given(given));
        }
    }

    #[test]
    fn a_stream_is_monitored_alike_whatever_its_first_chunk() {
        // A biased signal: the magnitude of its first samples is not its amplitude, and a
        // first call's median magnitude would be one sample's in chunks of 1. A stream's
        // thresholds do not depend on them.
        let mut policy = ThresholdPolicy::<f64>::stream(None);
        for chunk in [[1.6], [0.3], [-0.4]] {
            assert_eq!(
                policy.decide(ThresholdInput::Floats, &chunk, &chunk),
                Ok(None)
            );
        }
        assert_eq!(policy.thresholds(), Some(FaultThresholds::default()));
        let stated = ThresholdInput::Counts {
            counts_per_unit_stated: true,
        };
        assert_eq!(policy.decide(stated, &[0.9], &[0.1]), Ok(None));
    }

    #[test]
    fn a_whole_capture_without_amplitude_gets_the_defaults() {
        let mut policy = ThresholdPolicy::<f64>::whole(None);
        assert_eq!(policy.thresholds(), None);
        let decided = policy.decide(ThresholdInput::Floats, &[0.0; 4], &[0.0; 4]);
        assert_eq!(decided, Ok(Some(FaultThresholds::default())));
        assert_eq!(policy.thresholds(), Some(FaultThresholds::default()));
    }
}
