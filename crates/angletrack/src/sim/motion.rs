//! The shaft's motion: a profile of segments (constant speed, acceleration, steps,
//! point-to-point moves, ripple, reversal), evaluated at any time.

use super::MAX_SAMPLES;
use crate::error::{Argument, Error, finite, non_negative, positive};

/// One segment of a motion profile. Each segment starts from the angle and speed at the end
/// of the previous one (the profile's initial values for the first); the acceleration is
/// the segment's own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Constant speed for a duration (a speed step if it differs from the current speed).
    ConstantSpeed {
        /// Speed (rad/s).
        speed_rad_s: f64,
        /// Duration (s).
        duration_s: f64,
    },
    /// Constant acceleration from the current speed.
    ConstantAcceleration {
        /// Acceleration (rad/s^2).
        acceleration_rad_s2: f64,
        /// Duration (s).
        duration_s: f64,
    },
    /// The angle jumps by `step_rad` at the start of the segment, then the current speed is
    /// held for the duration.
    Step {
        /// Position step (rad).
        step_rad: f64,
        /// Duration (s).
        duration_s: f64,
    },
    /// A point-to-point move with a trapezoidal speed profile (acceleration limited),
    /// superimposed on the speed held at its start (rest to rest if that speed is 0).
    Trapezoidal {
        /// Distance of the move (rad, either sign).
        distance_rad: f64,
        /// Speed limit (rad/s).
        max_speed_rad_s: f64,
        /// Acceleration limit (rad/s^2).
        max_acceleration_rad_s2: f64,
    },
    /// A point-to-point move with an S-curve (jerk limited, 7-phase) speed profile,
    /// superimposed on the speed held at its start.
    SCurve {
        /// Distance of the move (rad, either sign).
        distance_rad: f64,
        /// Speed limit (rad/s).
        max_speed_rad_s: f64,
        /// Acceleration limit (rad/s^2).
        max_acceleration_rad_s2: f64,
        /// Jerk limit (rad/s^3).
        max_jerk_rad_s3: f64,
    },
    /// A sinusoidal speed ripple around the current speed:
    /// `speed = speed_0 + ripple sin(2 pi f t)`.
    SpeedRipple {
        /// Ripple amplitude (rad/s).
        ripple_rad_s: f64,
        /// Ripple frequency (Hz).
        frequency_hz: f64,
        /// Duration (s).
        duration_s: f64,
    },
    /// A reversal: the current speed `v` goes to `-v` at constant deceleration
    /// (duration `2 |v| / acceleration`).
    Reversal {
        /// Magnitude of the deceleration (rad/s^2).
        acceleration_rad_s2: f64,
    },
}

/// The state of the shaft at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Kinematics {
    /// Angle (rad, unwrapped).
    pub angle_rad: f64,
    /// Speed (rad/s).
    pub speed_rad_s: f64,
    /// Acceleration (rad/s^2).
    pub acceleration_rad_s2: f64,
}

/// A phase of constant jerk: duration, acceleration at its start, jerk.
#[derive(Debug, Clone, Copy)]
struct Phase {
    duration: f64,
    acceleration: f64,
    jerk: f64,
}

/// The phases of a point-to-point move of `distance` (> 0) with speed, acceleration and
/// (optional) jerk limits: the S-curve, or the trapezoid without a jerk limit.
fn point_to_point(distance: f64, v_max: f64, a_max: f64, j_max: Option<f64>) -> Vec<Phase> {
    // Acceleration phase to peak speed v: (jerk time, constant-acceleration time, peak a).
    let ramp = |v: f64| -> (f64, f64, f64) {
        match j_max {
            Some(j) if v * j < a_max * a_max => {
                let tj = (v / j).sqrt();
                (tj, 0.0, j * tj)
            }
            Some(j) => (a_max / j, v / a_max - a_max / j, a_max),
            None => (0.0, v / a_max, a_max),
        }
    };
    let accel_time = |v: f64| {
        let (tj, ta, _) = ramp(v);
        2.0 * tj + ta
    };
    let mut v = v_max;
    let mut cruise = 0.0;
    if v * accel_time(v) <= distance {
        cruise = (distance - v * accel_time(v)) / v;
    } else {
        // v * accel_time(v) increases with v: bisect for the peak speed that covers the
        // distance without cruising.
        let (mut lo, mut hi) = (0.0, v_max);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid * accel_time(mid) < distance {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        v = 0.5 * (lo + hi);
    }
    let (tj, ta, a) = ramp(v);
    let jerk = j_max.unwrap_or(0.0);
    let half = |sign: f64| {
        [
            Phase {
                duration: tj,
                acceleration: 0.0,
                jerk: sign * jerk,
            },
            Phase {
                duration: ta,
                acceleration: sign * a,
                jerk: 0.0,
            },
            Phase {
                duration: tj,
                acceleration: sign * a,
                jerk: -sign * jerk,
            },
        ]
    };
    let mut phases = half(1.0).to_vec();
    phases.push(Phase {
        duration: cruise,
        acceleration: 0.0,
        jerk: 0.0,
    });
    phases.extend(half(-1.0));
    phases.retain(|p| p.duration > 0.0);
    phases
}

/// The displacement, speed and acceleration at time `t` of a sequence of phases.
fn along_phases(phases: &[Phase], t: f64) -> (f64, f64, f64) {
    let (mut p, mut v, mut remaining) = (0.0, 0.0, t);
    for phase in phases {
        let dt = remaining.min(phase.duration);
        let a = phase.acceleration + phase.jerk * dt;
        p += v * dt + phase.acceleration * dt * dt / 2.0 + phase.jerk * dt * dt * dt / 6.0;
        v += phase.acceleration * dt + phase.jerk * dt * dt / 2.0;
        remaining -= dt;
        if remaining <= 0.0 {
            return (p, v, a);
        }
    }
    (p, v, 0.0)
}

impl Motion {
    fn validate(&self) -> Result<(), Error> {
        match *self {
            Motion::ConstantSpeed {
                speed_rad_s,
                duration_s,
            } => {
                finite(speed_rad_s, Argument::Speed)?;
                non_negative(duration_s, Argument::Duration)?;
            }
            Motion::ConstantAcceleration {
                acceleration_rad_s2,
                duration_s,
            } => {
                finite(acceleration_rad_s2, Argument::Acceleration)?;
                non_negative(duration_s, Argument::Duration)?;
            }
            Motion::Step {
                step_rad,
                duration_s,
            } => {
                finite(step_rad, Argument::Step)?;
                non_negative(duration_s, Argument::Duration)?;
            }
            Motion::Trapezoidal {
                distance_rad,
                max_speed_rad_s,
                max_acceleration_rad_s2,
            } => {
                finite(distance_rad, Argument::Distance)?;
                positive(max_speed_rad_s, Argument::MaxSpeed)?;
                positive(max_acceleration_rad_s2, Argument::MaxAcceleration)?;
            }
            Motion::SCurve {
                distance_rad,
                max_speed_rad_s,
                max_acceleration_rad_s2,
                max_jerk_rad_s3,
            } => {
                finite(distance_rad, Argument::Distance)?;
                positive(max_speed_rad_s, Argument::MaxSpeed)?;
                positive(max_acceleration_rad_s2, Argument::MaxAcceleration)?;
                positive(max_jerk_rad_s3, Argument::MaxJerk)?;
            }
            Motion::SpeedRipple {
                ripple_rad_s,
                frequency_hz,
                duration_s,
            } => {
                finite(ripple_rad_s, Argument::Ripple)?;
                positive(frequency_hz, Argument::Frequency)?;
                non_negative(duration_s, Argument::Duration)?;
            }
            Motion::Reversal {
                acceleration_rad_s2,
            } => {
                positive(acceleration_rad_s2, Argument::Acceleration)?;
            }
        }
        Ok(())
    }

    /// The constant-jerk phases of a point-to-point move (empty for other segments).
    fn phases(&self) -> Vec<Phase> {
        let (distance, v, a, j) = match *self {
            Motion::Trapezoidal {
                distance_rad,
                max_speed_rad_s,
                max_acceleration_rad_s2,
            } => (distance_rad, max_speed_rad_s, max_acceleration_rad_s2, None),
            Motion::SCurve {
                distance_rad,
                max_speed_rad_s,
                max_acceleration_rad_s2,
                max_jerk_rad_s3,
            } => (
                distance_rad,
                max_speed_rad_s,
                max_acceleration_rad_s2,
                Some(max_jerk_rad_s3),
            ),
            _ => return Vec::new(),
        };
        if distance == 0.0 {
            return Vec::new();
        }
        let sign = distance.signum();
        let mut phases = point_to_point(distance.abs(), v, a, j);
        for p in &mut phases {
            p.acceleration *= sign;
            p.jerk *= sign;
        }
        phases
    }

    /// Duration of the segment (s) when it starts at speed `speed_rad_s`.
    fn duration(&self, phases: &[Phase], speed_rad_s: f64) -> f64 {
        match *self {
            Motion::ConstantSpeed { duration_s, .. }
            | Motion::ConstantAcceleration { duration_s, .. }
            | Motion::Step { duration_s, .. }
            | Motion::SpeedRipple { duration_s, .. } => duration_s,
            Motion::Trapezoidal { .. } | Motion::SCurve { .. } => {
                phases.iter().map(|p| p.duration).sum()
            }
            Motion::Reversal {
                acceleration_rad_s2,
            } => 2.0 * speed_rad_s.abs() / acceleration_rad_s2,
        }
    }

    /// The shaft at time `t` (s) into the segment, from `start`.
    fn at(&self, phases: &[Phase], start: Kinematics, t: f64) -> Kinematics {
        let (angle0, v0) = (start.angle_rad, start.speed_rad_s);
        let (angle, speed, acceleration) = match *self {
            Motion::ConstantSpeed { speed_rad_s, .. } => {
                (angle0 + speed_rad_s * t, speed_rad_s, 0.0)
            }
            Motion::ConstantAcceleration {
                acceleration_rad_s2: a,
                ..
            } => (angle0 + v0 * t + 0.5 * a * t * t, v0 + a * t, a),
            Motion::Step { step_rad, .. } => (angle0 + step_rad + v0 * t, v0, 0.0),
            Motion::Trapezoidal { .. } | Motion::SCurve { .. } => {
                let (p, v, a) = along_phases(phases, t);
                (angle0 + v0 * t + p, v0 + v, a)
            }
            Motion::SpeedRipple {
                ripple_rad_s,
                frequency_hz,
                ..
            } => {
                let w = 2.0 * core::f64::consts::PI * frequency_hz;
                let (s, c) = (w * t).sin_cos();
                (
                    angle0 + v0 * t + ripple_rad_s * (1.0 - c) / w,
                    v0 + ripple_rad_s * s,
                    ripple_rad_s * w * c,
                )
            }
            Motion::Reversal {
                acceleration_rad_s2,
            } => {
                let a = -v0.signum() * acceleration_rad_s2;
                (angle0 + v0 * t + 0.5 * a * t * t, v0 + a * t, a)
            }
        };
        Kinematics {
            angle_rad: angle,
            speed_rad_s: speed,
            acceleration_rad_s2: acceleration,
        }
    }
}

/// A motion profile: the shaft's initial angle and speed, then segments run one after the
/// other (their concatenation).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MotionProfile {
    /// Initial angle (rad).
    pub initial_angle_rad: f64,
    /// Initial speed (rad/s).
    pub initial_speed_rad_s: f64,
    /// The segments, in order.
    pub segments: Vec<Motion>,
}

impl MotionProfile {
    /// A profile starting at `initial_angle_rad` and `initial_speed_rad_s`, without segments
    /// (add them with [`MotionProfile::then`]).
    ///
    /// ```
    /// use angletrack::MotionProfile;
    /// let profile = MotionProfile::new(0.5, 20.0); // 0.5 rad, turning at 20 rad/s
    /// assert!(profile.segments.is_empty());
    /// ```
    pub fn new(initial_angle_rad: f64, initial_speed_rad_s: f64) -> Self {
        Self {
            initial_angle_rad,
            initial_speed_rad_s,
            segments: Vec::new(),
        }
    }

    /// The profile with one more segment at its end.
    ///
    /// ```
    /// use angletrack::{Motion, MotionProfile};
    /// let profile = MotionProfile::new(0.0, 0.0)
    ///     .then(Motion::ConstantAcceleration { acceleration_rad_s2: 100.0, duration_s: 1.0 })
    ///     .then(Motion::Reversal { acceleration_rad_s2: 400.0 });
    /// assert_eq!(profile.segments.len(), 2);
    /// ```
    pub fn then(mut self, motion: Motion) -> Self {
        self.segments.push(motion);
        self
    }

    /// The number of samples `k Ts` covering the profile's duration and the true shaft
    /// state at each (computed as they are taken).
    pub(super) fn sample(
        &self,
        sample_period_s: f64,
    ) -> Result<(usize, impl Iterator<Item = Kinematics>), Error> {
        finite(self.initial_angle_rad, Argument::InitialAngle)?;
        finite(self.initial_speed_rad_s, Argument::InitialSpeed)?;
        // Segment boundaries: start time, start state, phases.
        let mut start = Kinematics {
            angle_rad: self.initial_angle_rad,
            speed_rad_s: self.initial_speed_rad_s,
            acceleration_rad_s2: 0.0,
        };
        let mut t0 = 0.0;
        let mut pieces = Vec::with_capacity(self.segments.len());
        for motion in &self.segments {
            motion.validate()?;
            let phases = motion.phases();
            let duration = motion.duration(&phases, start.speed_rad_s);
            let end = motion.at(&phases, start, duration);
            pieces.push((t0, start, phases, *motion));
            t0 += duration;
            start = end;
        }
        let samples = (t0 / sample_period_s).floor() + 1.0;
        if !(samples <= MAX_SAMPLES as f64) {
            return Err(Error::OutOfRange {
                argument: Argument::Profile,
                expected: "a total duration of at most 10^8 sample periods",
            });
        }
        let samples = samples as usize;
        let mut index = 0;
        let states = (0..samples).map(move |k| {
            let t = k as f64 * sample_period_s;
            while index + 1 < pieces.len() && t >= pieces[index + 1].0 {
                index += 1;
            }
            match pieces.get(index) {
                Some((start_time, state, phases, motion)) => {
                    motion.at(phases, *state, (t - start_time).max(0.0))
                }
                None => start,
            }
        });
        Ok((samples, states))
    }
}
