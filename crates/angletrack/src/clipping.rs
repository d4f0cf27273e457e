//! The clipping arguments of a chain checked once for every door (`docs/theory.md §15`):
//! the ADC's stated range `adc_range` (two finite numbers, the first below the second), or
//! the rails measured as the samples come (`measure_adc_range`), or neither; both at once
//! are refused. Each refusal names the argument as the Python API and the command line
//! write it.

use angletrack_core::Rails;

use crate::ArgumentError;

/// `range` checked: two finite numbers, the first below the second (`None`: none stated).
///
/// ```
/// use angletrack::checked_adc_range;
/// assert_eq!(checked_adc_range(Some((0.0, 4095.0))), Ok(Some((0.0, 4095.0))));
/// assert_eq!(checked_adc_range(Some((1.0, 1.0))).unwrap_err().argument, "adc_range");
/// ```
pub fn checked_adc_range(range: Option<(f64, f64)>) -> Result<Option<(f64, f64)>, ArgumentError> {
    match range {
        Some((min, max)) if !(min.is_finite() && max.is_finite()) => Err(ArgumentError::new(
            "adc_range",
            format!("({min}, {max}): expected two finite numbers"),
        )),
        Some((min, max)) if min >= max => Err(ArgumentError::new(
            "adc_range",
            format!("({min}, {max}): the minimum must be below the maximum"),
        )),
        other => Ok(other),
    }
}

/// The core's rails of the clipping arguments: the stated `range`, else the rails measured
/// when `measure`, else none; both refused, naming `measure_adc_range`.
///
/// ```
/// use angletrack::clipping_rails;
/// use angletrack::core::Rails;
/// assert_eq!(clipping_rails(Some((0, 4095)), false), Ok(Rails::Stated { min: 0, max: 4095 }));
/// assert_eq!(clipping_rails::<i32>(None, true), Ok(Rails::Measured));
/// assert_eq!(clipping_rails(Some((0, 4095)), true).unwrap_err().argument, "measure_adc_range");
/// ```
pub fn clipping_rails<X>(range: Option<(X, X)>, measure: bool) -> Result<Rails<X>, ArgumentError> {
    Ok(match range {
        Some(_) if measure => {
            return Err(ArgumentError::new(
                "measure_adc_range",
                "give adc_range or measure_adc_range, not both",
            ));
        }
        Some((min, max)) => Rails::Stated { min, max },
        None if measure => Rails::Measured,
        None => Rails::Unchecked,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_not_finite_or_not_ordered_is_refused() {
        for range in [(f64::NAN, 1.0), (0.0, f64::INFINITY), (2.0, 1.0)] {
            let e = checked_adc_range(Some(range)).unwrap_err();
            assert_eq!(e.argument, "adc_range");
        }
        assert_eq!(checked_adc_range(None), Ok(None));
        assert_eq!(clipping_rails::<f64>(None, false), Ok(Rails::Unchecked));
    }
}
