//! Whether a capture's reference column follows the sensor's angle, before the angle error
//! is fitted against it: a reference that runs the other way (an encoder counting the
//! other way round) or at another multiple of the turn (a mechanical reference with the
//! pole pairs left out, or stated wrongly) gives an "error" that grows without bound, which
//! no correction holds. The sensor's angle and the reference's are unwrapped side by side
//! and their travels compared. A constant offset between the two zeros is no contradiction:
//! the fit takes the mean error as the reference's zero (`docs/theory.md §12`).

use super::CalibrationError;
use super::tracker::Unwrap;

/// Within this fraction of a whole ratio, the travels are taken as that ratio.
const RATIO_TOLERANCE: f64 = 0.1;

/// The sensor's and the reference's unwrapped angles (rad, electrical) over the fit.
#[derive(Debug, Default)]
pub(super) struct ReferenceFollowing {
    sensor: Unwrap,
    first: Option<(f64, f64)>,
    last: (f64, f64),
}

impl ReferenceFollowing {
    /// One sample: the sensor's angle (rad) and the reference's unwrapped position (rad).
    pub(super) fn add(&mut self, sensor_angle: f64, reference_position: f64) {
        let position = (self.sensor.add(sensor_angle), reference_position);
        self.first.get_or_insert(position);
        self.last = position;
    }

    /// Refuses a reference that does not follow the sensor's angle one to one, naming the
    /// option (or the column) that states the relation.
    pub(super) fn check(&self) -> Result<(), CalibrationError> {
        let Some((sensor_first, reference_first)) = self.first else {
            return Ok(());
        };
        let sensor_turns = (self.last.0 - sensor_first) / core::f64::consts::TAU;
        let reference_turns = (self.last.1 - reference_first) / core::f64::consts::TAU;
        let ratio = sensor_turns / reference_turns;
        if !ratio.is_finite() || (ratio - 1.0).abs() <= RATIO_TOLERANCE {
            return Ok(());
        }
        let travels = format!(
            "the sensor's angle travelled {sensor_turns:.2} electrical turns while the reference \
             travelled {reference_turns:.2}"
        );
        let whole = ratio.abs().round();
        let near = |r: f64| (r - r.round()).abs() <= RATIO_TOLERANCE * r.round().max(1.0);
        let (way, sign) = if ratio < 0.0 {
            (", the other way", "-")
        } else {
            ("", "")
        };
        let reason = if ratio < 0.0 && (ratio + 1.0).abs() <= RATIO_TOLERANCE {
            format!(
                "it runs opposite to the sensor ({travels}): an encoder counting the other way? \
                 state it with --reference-ratio -1"
            )
        } else if ratio.abs() > 1.0 && near(ratio.abs()) {
            format!(
                "the sensor's angle turns {whole} times as fast as the reference{way} ({travels}): \
                 a mechanical reference? state its pole pairs with --reference-ratio {sign}{whole}"
            )
        } else if ratio.abs() < 1.0 && near(1.0 / ratio.abs()) {
            let k = (1.0 / ratio.abs()).round();
            format!(
                "the reference turns {k} times as fast as the sensor's angle{way} ({travels}): a \
                 --reference-ratio {k} times too large?"
            )
        } else {
            format!("it does not follow the sensor's angle ({travels})")
        };
        Err(CalibrationError {
            option: "reference",
            reason,
        })
    }
}
