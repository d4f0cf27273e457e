//! [`AnyGains`]: checked float64 gains of an observer whose order is chosen at run time (by
//! the number of gains a caller gives), as the Python `Gains` holds them.

use angletrack_core::{ConfigError, Gains};

use crate::{ArgumentError, ChannelError};

/// Checked discrete gains of order 2 or 3, in `f64`.
///
/// ```
/// use angletrack::AnyGains;
/// let gains = AnyGains::new(&[0.06, 0.001], 1e-4)?;
/// assert_eq!((gains.order(), gains.gains()), (2, vec![0.06, 0.001]));
/// let e = AnyGains::new(&[0.06], 1e-4).unwrap_err();
/// assert!(e.to_string().starts_with("gains: expected 2 values"));
/// # Ok::<(), angletrack::ChannelError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyGains {
    /// Order 2: `(l1, l2)`.
    Second(Gains<f64, 2>),
    /// Order 3: `(l1, l2, l3)`.
    Third(Gains<f64, 3>),
}

/// Runs `$body` with `$g` bound to the concrete core gains inside an [`AnyGains`].
#[macro_export]
macro_rules! with_any_gains {
    ($set:expr, $g:ident => $body:expr) => {
        match $set {
            $crate::AnyGains::Second($g) => $body,
            $crate::AnyGains::Third($g) => $body,
        }
    };
}

impl AnyGains {
    /// Checks gains `l` (2 or 3 of them, else refused naming `gains`) and the sample period
    /// (s) with the core.
    pub fn new(l: &[f64], sample_period_s: f64) -> Result<Self, ChannelError> {
        Self::of_order(
            l,
            "gains",
            |l| Gains::new(l, sample_period_s),
            |l| Gains::new(l, sample_period_s),
        )
    }

    /// Gains from the closed-loop characteristic polynomial in `s = z - 1` (coefficients,
    /// lowest first, leading 1 omitted; 2 or 3 of them, else refused naming
    /// `coefficients`).
    pub fn from_loop_polynomial(c: &[f64], sample_period_s: f64) -> Result<Self, ChannelError> {
        Self::of_order(
            c,
            "coefficients",
            |c| Gains::from_loop_polynomial(c, sample_period_s),
            |c| Gains::from_loop_polynomial(c, sample_period_s),
        )
    }

    /// Calls `second` or `third` with the 2 or 3 `values` of argument `argument`.
    fn of_order(
        values: &[f64],
        argument: &'static str,
        second: impl FnOnce([f64; 2]) -> Result<Gains<f64, 2>, ConfigError>,
        third: impl FnOnce([f64; 3]) -> Result<Gains<f64, 3>, ConfigError>,
    ) -> Result<Self, ChannelError> {
        match *values {
            [a, b] => Ok(AnyGains::Second(second([a, b])?)),
            [a, b, c] => Ok(AnyGains::Third(third([a, b, c])?)),
            _ => Err(ArgumentError::new(
                argument,
                format!(
                    "expected 2 values (2nd-order observer) or 3 (3rd-order), got {}",
                    values.len()
                ),
            )
            .into()),
        }
    }

    /// The discrete gains `(l1, l2[, l3])`.
    pub fn gains(&self) -> Vec<f64> {
        with_any_gains!(self, g => g.gains().to_vec())
    }

    /// The coefficients of the closed-loop characteristic polynomial in `s = z - 1`.
    pub fn loop_polynomial(&self) -> Vec<f64> {
        with_any_gains!(self, g => g.loop_polynomial().to_vec())
    }

    /// The sample period (s).
    pub fn sample_period(&self) -> f64 {
        with_any_gains!(self, g => g.sample_period())
    }

    /// The observer order (2 or 3).
    pub fn order(&self) -> usize {
        with_any_gains!(self, g => g.order())
    }
}
