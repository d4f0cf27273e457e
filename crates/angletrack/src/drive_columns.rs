//! The core's drive outputs over a run's estimate columns (float64), as the Python
//! `DriveOutputs.update` returns them (`docs/theory.md §13`).

use core::f64::consts::TAU;

use angletrack_core::{DriveOutputs, DriveOutputsState, Estimate, Faults};

/// The drive's outputs of each sample, one column each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriveColumns {
    /// The electrical angle for the pole pairs (rad, wrapped).
    pub electrical_angle_rad: Vec<f64>,
    /// The filtered electrical speed (rad/s).
    pub electrical_speed_rad_s: Vec<f64>,
    /// The mechanical angle (rad, wrapped).
    pub mechanical_angle_rad: Vec<f64>,
    /// The whole mechanical turns.
    pub mechanical_turns: Vec<i64>,
    /// The filtered mechanical speed (rad/s).
    pub mechanical_speed_rad_s: Vec<f64>,
}

impl DriveColumns {
    /// `outputs` over the estimates `[angle_rad, position_rad, speed_rad_s,
    /// acceleration_rad_s2]` (the angle wrapped, the position multi-turn: the whole turns are
    /// `(position - angle) / 2 pi` rounded; the shortest column sets the count), from `state`,
    /// which carries over to the next call.
    ///
    /// ```
    /// use angletrack::DriveColumns;
    /// use angletrack::core::{DriveOutputs, DriveOutputsState};
    /// let outputs = DriveOutputs::new(4, 1, 0.0, 1e-4)?;
    /// let (angle, position) = ([0.5], [0.5 + 2.0 * std::f64::consts::TAU]);
    /// let d = DriveColumns::of_estimates(&outputs, &mut DriveOutputsState::default(),
    ///     [&angle, &position, &[10.0], &[0.0]]);
    /// assert_eq!(d.mechanical_turns, [2]);
    /// assert!((d.electrical_angle_rad[0] - 2.0).abs() < 1e-12);
    /// # Ok::<(), angletrack::core::ConfigError>(())
    /// ```
    pub fn of_estimates(
        outputs: &DriveOutputs<f64>,
        state: &mut DriveOutputsState<f64>,
        [angle, position, speed, acceleration]: [&[f64]; 4],
    ) -> Self {
        let mut out = Self::default();
        let estimates = angle.iter().zip(position).zip(speed).zip(acceleration);
        for (((&angle, &position), &speed), &acceleration) in estimates {
            let turns = ((position - angle) / TAU).round() as i64;
            let estimate = Estimate::new(angle, turns, speed, acceleration, 0.0, Faults::NONE);
            let drive = outputs.outputs(state, &estimate);
            out.electrical_angle_rad.push(drive.electrical_angle);
            out.electrical_speed_rad_s.push(drive.electrical_speed);
            out.mechanical_angle_rad.push(drive.mechanical_angle);
            out.mechanical_turns.push(drive.mechanical_turns);
            out.mechanical_speed_rad_s.push(drive.mechanical_speed);
        }
        out
    }
}
