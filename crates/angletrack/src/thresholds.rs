//! The monitor's fault thresholds of an observer run over a capture: given, or scaled to
//! the amplitude of the first samples it sees, so that a capture in raw counts or in volts
//! is monitored without its units being stated (`docs/theory.md §12`).
//!
//! ```
//! use angletrack::ThresholdPolicy;
//! let mut policy = ThresholdPolicy::<f64>::new(None);
//! assert_eq!(policy.thresholds(), None); // nothing seen yet
//! // The first chunk decides: amplitude 1800 (counts).
//! let decided = policy.decide(&[1800.0, 0.0, -1800.0], &[0.0, 1800.0, 0.0]).unwrap();
//! assert_eq!(decided.nominal_amplitude, 1800.0);
//! // Later chunks keep it.
//! assert_eq!(policy.decide(&[0.5], &[0.0]), None);
//! assert_eq!(policy.thresholds(), Some(decided));
//! ```

use angletrack_core::{FaultThresholds, Real};

use crate::capture_fault_thresholds;

/// Where an observer's fault thresholds come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThresholdPolicy<T> {
    /// Given by the caller (or decided already): used as they are.
    Given(FaultThresholds<T>),
    /// Not decided yet: [`capture_fault_thresholds`] of the first samples seen (the
    /// defaults for amplitude 1 if they have no positive amplitude).
    FromFirstSamples,
}

impl<T: Real> ThresholdPolicy<T> {
    /// The thresholds `given`, or `None` to take them from the first samples.
    pub fn new(given: Option<FaultThresholds<T>>) -> Self {
        given.map_or(ThresholdPolicy::FromFirstSamples, ThresholdPolicy::Given)
    }

    /// The thresholds the observer runs with; `None` until the first samples decide them.
    pub fn thresholds(&self) -> Option<FaultThresholds<T>> {
        match self {
            ThresholdPolicy::Given(thresholds) => Some(*thresholds),
            ThresholdPolicy::FromFirstSamples => None,
        }
    }

    /// Before running the chunk `y_c`, `y_s`: the thresholds this chunk decides if none
    /// were decided yet (the observer's gains must then take them), `None` otherwise (the
    /// observer keeps the ones it has).
    pub fn decide(&mut self, y_c: &[T], y_s: &[T]) -> Option<FaultThresholds<T>> {
        match self {
            ThresholdPolicy::Given(_) => None,
            ThresholdPolicy::FromFirstSamples => {
                let thresholds = capture_fault_thresholds(y_c, y_s);
                *self = ThresholdPolicy::Given(thresholds);
                Some(thresholds)
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
        let mut policy = ThresholdPolicy::new(Some(given));
        assert_eq!(policy.thresholds(), Some(given));
        assert_eq!(policy.decide(&[1800.0], &[0.0]), None);
        assert_eq!(policy, ThresholdPolicy::Given(given));
    }

    #[test]
    fn first_samples_without_amplitude_give_the_defaults() {
        let mut policy = ThresholdPolicy::<f64>::new(None);
        assert_eq!(policy, ThresholdPolicy::FromFirstSamples);
        let decided = policy.decide(&[0.0; 4], &[0.0; 4]).unwrap();
        assert_eq!(decided, FaultThresholds::default());
        assert_eq!(policy.thresholds(), Some(decided));
    }
}
