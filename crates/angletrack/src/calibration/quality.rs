//! What a calibration learned from a capture, and how well: the method, each harmonic
//! order's measured amplitude with its uncertainty and whether it was learned, and why not.

use core::fmt;

use crate::ArgumentError;

pub use super::harmonic_fit::SPECTRUM_ORDERS;

/// How the angle error was measured ([`CaptureCalibration::method`](super::CaptureCalibration)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalibrationMethod {
    /// Against the capture's reference column (an encoder): every order, 1 and 2 included,
    /// whatever the speed profile.
    Reference,
    /// Self-calibration with a loop of the calibration's own, designed from the capture's
    /// speed so that every order lies above its bandwidth (the user's gains are not used).
    OwnLoop,
    /// Self-calibration with the user's gains: orders within their bandwidth at the
    /// capture's speed are not learned.
    Gains,
    /// Not recorded (a calibration file written before the method was).
    Unknown,
}

impl CalibrationMethod {
    /// The name in the calibration files and the Python package.
    pub fn name(self) -> &'static str {
        match self {
            CalibrationMethod::Reference => "reference",
            CalibrationMethod::OwnLoop => "self, own loop",
            CalibrationMethod::Gains => "self, the gains' loop",
            CalibrationMethod::Unknown => "unknown",
        }
    }

    /// The method of [`CalibrationMethod::name`]'s text (`Unknown` for any other).
    pub fn from_name(name: &str) -> Self {
        [Self::Reference, Self::OwnLoop, Self::Gains]
            .into_iter()
            .find(|m| m.name() == name)
            .unwrap_or(Self::Unknown)
    }
}

impl fmt::Display for CalibrationMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether a harmonic order was learned, and why not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrderStatus {
    /// In the correction.
    Learned,
    /// Measured below `min_significance` times its uncertainty: noise, not learned.
    NotSignificant,
    /// Within the loop's bandwidth at the capture's speed (self-calibration with the
    /// gains): the loop follows it, so the angle error does not show it.
    WithinLoopBandwidth,
    /// Outside `lowest_order..=highest_order` (or beyond the correction's 8 orders): only
    /// reported, part of the residual.
    NotRequested,
    /// Too close to the sample rate at the capture's speed to be measured.
    Unresolved,
    /// Not recorded (an older calibration file).
    Unknown,
}

impl OrderStatus {
    /// The name in the calibration files and the Python package.
    pub fn name(self) -> &'static str {
        match self {
            OrderStatus::Learned => "learned",
            OrderStatus::NotSignificant => "not significant",
            OrderStatus::WithinLoopBandwidth => "within the loop's bandwidth",
            OrderStatus::NotRequested => "not requested",
            OrderStatus::Unresolved => "not resolved",
            OrderStatus::Unknown => "unknown",
        }
    }

    /// The status of [`OrderStatus::name`]'s text (`Unknown` for any other).
    pub fn from_name(name: &str) -> Self {
        [
            Self::Learned,
            Self::NotSignificant,
            Self::WithinLoopBandwidth,
            Self::NotRequested,
            Self::Unresolved,
        ]
        .into_iter()
        .find(|s| s.name() == name)
        .unwrap_or(Self::Unknown)
    }
}

/// One harmonic order of the measured angle error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderQuality {
    /// The amplitude measured (rad), corrected for the loop's transfer; what the
    /// correction leaves at this order when it is not learned.
    pub amplitude_rad: f64,
    /// The standard deviation of each of its two coefficients (rad), from the residual's
    /// noise (`docs/theory.md §12`); NaN when not measured.
    pub uncertainty_rad: f64,
    /// Whether it was learned.
    pub status: OrderStatus,
}

impl OrderQuality {
    /// Nothing known (an older file).
    pub const UNKNOWN: Self = Self {
        amplitude_rad: f64::NAN,
        uncertainty_rad: f64::NAN,
        status: OrderStatus::Unknown,
    };

    /// Orders 1 to [`SPECTRUM_ORDERS`] (index `k - 1`) of `(order, amplitude_rad,
    /// uncertainty_rad, status)` each, the status by its name ([`OrderStatus::from_name`]),
    /// unknown for the orders not given; another order is refused naming `orders`.
    ///
    /// ```
    /// use angletrack::{OrderQuality, OrderStatus};
    /// let table = OrderQuality::table(&[(2, 1e-3, 1e-5, "learned".into())]).unwrap();
    /// assert_eq!((table[1].amplitude_rad, table[1].status), (1e-3, OrderStatus::Learned));
    /// assert!(table[0].amplitude_rad.is_nan());
    /// assert!(OrderQuality::table(&[(13, 0.0, 0.0, "learned".into())]).is_err());
    /// ```
    pub fn table(
        orders: &[(usize, f64, f64, String)],
    ) -> Result<[Self; SPECTRUM_ORDERS], ArgumentError> {
        let mut out = [Self::UNKNOWN; SPECTRUM_ORDERS];
        for (order, amplitude_rad, uncertainty_rad, status) in orders {
            let slot = order
                .checked_sub(1)
                .and_then(|i| out.get_mut(i))
                .ok_or_else(|| {
                    let reason = format!("order {order} is not in 1..={SPECTRUM_ORDERS}");
                    ArgumentError::new("orders", reason)
                })?;
            *slot = Self {
                amplitude_rad: *amplitude_rad,
                uncertainty_rad: *uncertainty_rad,
                status: OrderStatus::from_name(status),
            };
        }
        Ok(out)
    }

    /// A learned order whose amplitude is below its own uncertainty: most of it is noise.
    pub fn is_doubtful(&self) -> bool {
        self.status == OrderStatus::Learned && self.amplitude_rad < self.uncertainty_rad
    }
}

/// The warnings of a calibration's orders: one line per learned order below its own
/// uncertainty (see [`OrderQuality::is_doubtful`]).
pub fn order_warnings(orders: &[OrderQuality; SPECTRUM_ORDERS]) -> Vec<String> {
    orders
        .iter()
        .enumerate()
        .filter(|(_, q)| q.is_doubtful())
        .map(|(i, q)| {
            format!(
                "order {} learned at {:.3} mrad, below its uncertainty {:.3} mrad: mostly noise",
                i + 1,
                1e3 * q.amplitude_rad,
                1e3 * q.uncertainty_rad
            )
        })
        .collect()
}
