//! The fixed-point standard chain (`Tracker<i16, FixedGains<N>>`, `docs/theory.md §14`) of
//! an order chosen at run time, 2 or 3, with its state: what the Python `FixedObserver` and
//! `angletrack track --dtype fixed` hold, built from float gains or from the integer
//! constants a firmware embeds.

use angletrack_core::fixed::FixedConstants;
use angletrack_core::{
    ConfigError, FixedEstimate, FixedGains, FixedState, Order, Parameter, SupportedOrder, Tracker,
    TrackerFrontEnd, TrackerState,
};

use super::FixedColumns;
use crate::FixedDesignConstants;

/// Why [`FixedTracker::of_constants`] refused the constants.
#[derive(Debug, Clone, PartialEq)]
pub enum FixedConstantsError {
    /// The sample period or the monitor's amplitude (the core names it).
    Config(ConfigError),
    /// The multipliers or the shift: what is wrong with them.
    Constants(String),
}

impl From<ConfigError> for FixedConstantsError {
    fn from(e: ConfigError) -> Self {
        FixedConstantsError::Config(e)
    }
}

/// The fixed-point standard chain of order 2 or 3 and its state.
///
/// ```
/// use angletrack::{FixedTracker, fixed_front_end};
/// use angletrack::core::Rails;
/// let front_end = fixed_front_end(0, 0, None, None, Rails::Unchecked)?;
/// let tracker = FixedTracker::of_gains(&[0.2, 0.02], 1e-4, front_end, Some(16384.0))?;
/// assert_eq!(tracker.gains().len(), 2);
/// let refused = FixedTracker::of_constants(&[1, 2, 3, 4], 0, 1e-4, front_end, None);
/// assert!(refused.is_err());
/// # Ok::<(), angletrack::core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub enum FixedTracker {
    /// Order 2.
    Second(
        Tracker<i16, FixedGains<2>>,
        TrackerState<i16, FixedState<2>>,
    ),
    /// Order 3.
    Third(
        Tracker<i16, FixedGains<3>>,
        TrackerState<i16, FixedState<3>>,
    ),
}

/// The chain of order `N` and its state.
type Order2Or3<const N: usize> = (
    Tracker<i16, FixedGains<N>>,
    TrackerState<i16, FixedState<N>>,
);

/// Runs `$body` with `$t` and `$s` bound to the tracker and state inside a [`FixedTracker`].
macro_rules! with_tracker {
    ($tracker:expr, $t:ident, $s:ident => $body:expr) => {
        match $tracker {
            FixedTracker::Second($t, $s) => $body,
            FixedTracker::Third($t, $s) => $body,
        }
    };
}

/// The chain of `gains` with the monitor for `nominal_amplitude` (`None`: off) behind
/// `front_end`, from its first sample.
fn chain<const N: usize>(
    gains: FixedGains<N>,
    front_end: TrackerFrontEnd<i16>,
    nominal_amplitude: Option<f64>,
) -> Result<Order2Or3<N>, ConfigError>
where
    Order<N>: SupportedOrder,
{
    // The Python observer has no argument for the roundness check yet: off.
    let tracker = Tracker::new(
        front_end,
        gains.with_monitor_tolerance(nominal_amplitude, None)?,
    );
    Ok((tracker, TrackerState::new()))
}

impl FixedTracker {
    /// The float `gains` (2 or 3) at `sample_period_s`, quantised by the core, behind
    /// `front_end`, with the monitor for `nominal_amplitude` counts (`None`: off); another
    /// number of gains is refused as out of range.
    pub fn of_gains(
        gains: &[f64],
        sample_period_s: f64,
        front_end: TrackerFrontEnd<i16>,
        nominal_amplitude: Option<f64>,
    ) -> Result<Self, ConfigError> {
        let a = nominal_amplitude;
        Ok(match *gains {
            [l1, l2] => {
                let (t, s) = chain(FixedGains::new([l1, l2], sample_period_s)?, front_end, a)?;
                FixedTracker::Second(t, s)
            }
            [l1, l2, l3] => {
                let (t, s) = chain(
                    FixedGains::new([l1, l2, l3], sample_period_s)?,
                    front_end,
                    a,
                )?;
                FixedTracker::Third(t, s)
            }
            // An observer has 2 or 3 gains: the angle gain stands for the set.
            _ => return Err(ConfigError::OutOfRange(Parameter::AngleGain)),
        })
    }

    /// The integer constants a firmware embeds (2 or 3 multipliers and the acceleration
    /// shift), checked again by the core, at `sample_period_s`, behind `front_end`, with the
    /// monitor for `nominal_amplitude`.
    pub fn of_constants(
        multiplier: &[i32],
        acceleration_shift: u32,
        sample_period_s: f64,
        front_end: TrackerFrontEnd<i16>,
        nominal_amplitude: Option<f64>,
    ) -> Result<Self, FixedConstantsError> {
        fn gains<const N: usize>(
            multiplier: [i32; N],
            acceleration_shift: u32,
            sample_period_s: f64,
        ) -> Result<FixedGains<N>, FixedConstantsError>
        where
            Order<N>: SupportedOrder,
        {
            let constants = FixedConstants {
                multiplier,
                acceleration_shift,
            };
            FixedGains::from_constants(constants, sample_period_s).map_err(|e| match e {
                ConfigError::NotFinite(_) | ConfigError::NotPositive(_) => e.into(),
                _ => FixedConstantsError::Constants(format!(
                    "{e} (multiplier {multiplier:?}, acceleration_shift {acceleration_shift})"
                )),
            })
        }
        let (shift, period, a) = (acceleration_shift, sample_period_s, nominal_amplitude);
        Ok(match *multiplier {
            [l1, l2] => {
                let (t, s) = chain(gains([l1, l2], shift, period)?, front_end, a)?;
                FixedTracker::Second(t, s)
            }
            [l1, l2, l3] => {
                let (t, s) = chain(gains([l1, l2, l3], shift, period)?, front_end, a)?;
                FixedTracker::Third(t, s)
            }
            _ => {
                return Err(FixedConstantsError::Constants(format!(
                    "'multiplier' has {} values: expected 2 (2nd-order observer) or 3 (3rd-order)",
                    multiplier.len()
                )));
            }
        })
    }

    /// Runs the chain over the counts `y_c`, `y_s` into `columns` (all of one length); the
    /// state carries over to the next call.
    pub fn run(&mut self, columns: FixedColumns<'_>, y_c: &[i16], y_s: &[i16]) -> usize {
        with_tracker!(self, t, s => columns.run_chain(t, s, y_c, y_s))
    }

    /// The estimate after the last sample, and its position (rad), speed (rad/s) and
    /// acceleration (rad/s^2).
    pub fn estimate(&self) -> (FixedEstimate, [f64; 3]) {
        with_tracker!(self, t, s => {
            let (g, e) = (&t.observer, FixedGains::estimate(&s.observer));
            (e, [g.position_rad(&e), g.speed_rad_s(&e), g.acceleration_rad_s2(&e)])
        })
    }

    /// The integer constants (what [`FixedTracker::of_constants`] takes back).
    pub fn constants(&self) -> FixedDesignConstants {
        with_tracker!(self, t, _s => FixedDesignConstants::of(&t.observer))
    }

    /// The gains the integers represent (float), `(l1, l2[, l3])`.
    pub fn gains(&self) -> Vec<f64> {
        with_tracker!(self, t, _s => t.observer.gains().to_vec())
    }

    /// The sample period (s).
    pub fn sample_period(&self) -> f64 {
        with_tracker!(self, t, _s => t.observer.sample_period())
    }

    /// The faults latched since they were last cleared (bits), and the front end's.
    pub fn latched_faults(&self) -> (u8, u8) {
        with_tracker!(self, _t, s => {
            (s.observer.latched_faults().bits(), s.front_end.latched_faults().bits())
        })
    }

    /// Forgets the observer's state: the next sample sets the angle from its `atan2`.
    pub fn reset(&mut self) {
        with_tracker!(self, _t, s => s.observer = FixedState::new());
    }

    /// Returns the latched faults (bits) and clears them.
    pub fn clear_faults(&mut self) -> u8 {
        with_tracker!(self, _t, s => {
            let latched = s.observer.latched_faults().bits();
            s.observer.clear_faults();
            latched
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed_front_end;
    use angletrack_core::Rails;

    fn front_end() -> TrackerFrontEnd<i16> {
        fixed_front_end(0, 0, None, None, Rails::Unchecked).unwrap()
    }

    #[test]
    fn the_constants_of_designed_gains_build_the_same_tracker() {
        for gains in [&[0.2, 0.02][..], &[0.3, 0.04, 0.002]] {
            let designed = FixedTracker::of_gains(gains, 1e-4, front_end(), None).unwrap();
            let c = designed.constants();
            let back = FixedTracker::of_constants(
                &c.multiplier,
                c.acceleration_shift,
                1e-4,
                front_end(),
                None,
            )
            .unwrap();
            assert_eq!(back.gains(), designed.gains());
            assert_eq!(back.sample_period(), 1e-4);
        }
    }

    #[test]
    fn refused_constants_name_what_is_wrong() {
        let refused =
            |m: &[i32], period| FixedTracker::of_constants(m, 0, period, front_end(), None);
        assert!(
            matches!(refused(&[1, 2, 3, 4], 1e-4), Err(FixedConstantsError::Constants(m)) if m.contains("4 values"))
        );
        assert!(matches!(
            refused(&[0, 0], 1e-4),
            Err(FixedConstantsError::Constants(_))
        ));
        assert!(matches!(
            refused(&[1000, 10], f64::NAN),
            Err(FixedConstantsError::Config(_))
        ));
    }

    #[test]
    fn faults_clear_and_reset_forgets_the_state() {
        let mut tracker =
            FixedTracker::of_gains(&[0.2, 0.02], 1e-4, front_end(), Some(16384.0)).unwrap();
        let n = 64;
        let (mut angle, mut turns, mut speed, mut acceleration, mut phase, mut faults) = (
            vec![0; n],
            vec![0; n],
            vec![0; n],
            vec![0; n],
            vec![0; n],
            vec![0; n],
        );
        let (mut p, mut v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let columns = FixedColumns {
            angle: &mut angle,
            turns: &mut turns,
            speed: &mut speed,
            acceleration: &mut acceleration,
            phase_error: &mut phase,
            faults: &mut faults,
            position_rad: &mut p,
            speed_rad_s: &mut v,
            acceleration_rad_s2: &mut a,
        };
        // A signal far below the monitor's amplitude: loss of signal is latched.
        assert_eq!(tracker.run(columns, &[100; 64], &[0; 64]), n);
        let (estimate, [position, _, _]) = tracker.estimate();
        // At rest at angle 0: the position in rad is the binary angle's.
        let expected = std::f64::consts::TAU * f64::from(estimate.angle) / 2f64.powi(32);
        assert!(
            (position - expected).abs() < 1e-12 && position.abs() < 1e-3,
            "{position}"
        );
        assert_ne!(estimate.angle, 0);
        let latched = tracker.clear_faults();
        assert_ne!(latched, 0);
        assert_eq!(tracker.latched_faults().0, 0);
        tracker.reset();
        assert_eq!(tracker.estimate().0.angle, 0);
    }
}
