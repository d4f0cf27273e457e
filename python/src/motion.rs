//! `MotionProfile`: the shaft's motion, segment after segment, from the `angletrack` crate.

use angletrack::{Motion, MotionProfile};
use pyo3::prelude::*;

/// A motion profile of the shaft: an initial angle (rad) and speed (rad/s), then segments
/// run one after the other. Each method returns a new profile with one more segment.
#[pyclass(name = "MotionProfile", module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct PyMotionProfile {
    pub(crate) inner: MotionProfile,
}

impl PyMotionProfile {
    fn then(&self, motion: Motion) -> Self {
        Self {
            inner: self.inner.clone().then(motion),
        }
    }
}

#[pymethods]
impl PyMotionProfile {
    #[new]
    #[pyo3(signature = (initial_angle_rad = 0.0, initial_speed_rad_s = 0.0))]
    fn py_new(initial_angle_rad: f64, initial_speed_rad_s: f64) -> Self {
        Self {
            inner: MotionProfile::new(initial_angle_rad, initial_speed_rad_s),
        }
    }

    /// Constant speed `speed_rad_s` for `duration_s` (a speed step if it differs).
    #[pyo3(signature = (speed_rad_s, duration_s))]
    fn constant_speed(&self, speed_rad_s: f64, duration_s: f64) -> Self {
        self.then(Motion::ConstantSpeed {
            speed_rad_s,
            duration_s,
        })
    }

    /// Constant acceleration `acceleration_rad_s2` from the current speed for `duration_s`.
    #[pyo3(signature = (acceleration_rad_s2, duration_s))]
    fn constant_acceleration(&self, acceleration_rad_s2: f64, duration_s: f64) -> Self {
        self.then(Motion::ConstantAcceleration {
            acceleration_rad_s2,
            duration_s,
        })
    }

    /// A position step of `step_rad` at the segment's start, then the current speed held
    /// for `duration_s`.
    #[pyo3(signature = (step_rad, duration_s))]
    fn step(&self, step_rad: f64, duration_s: f64) -> Self {
        self.then(Motion::Step {
            step_rad,
            duration_s,
        })
    }

    /// A point-to-point move of `distance_rad` with a trapezoidal speed profile.
    #[pyo3(signature = (distance_rad, max_speed_rad_s, max_acceleration_rad_s2))]
    fn trapezoidal(
        &self,
        distance_rad: f64,
        max_speed_rad_s: f64,
        max_acceleration_rad_s2: f64,
    ) -> Self {
        self.then(Motion::Trapezoidal {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
        })
    }

    /// A point-to-point move of `distance_rad` with a jerk-limited S-curve speed profile.
    #[pyo3(signature = (distance_rad, max_speed_rad_s, max_acceleration_rad_s2, max_jerk_rad_s3))]
    fn s_curve(
        &self,
        distance_rad: f64,
        max_speed_rad_s: f64,
        max_acceleration_rad_s2: f64,
        max_jerk_rad_s3: f64,
    ) -> Self {
        self.then(Motion::SCurve {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
            max_jerk_rad_s3,
        })
    }

    /// A sinusoidal speed ripple of amplitude `ripple_rad_s` at `frequency_hz` around the
    /// current speed, for `duration_s`.
    #[pyo3(signature = (ripple_rad_s, frequency_hz, duration_s))]
    fn speed_ripple(&self, ripple_rad_s: f64, frequency_hz: f64, duration_s: f64) -> Self {
        self.then(Motion::SpeedRipple {
            ripple_rad_s,
            frequency_hz,
            duration_s,
        })
    }

    /// A reversal of the current speed at constant deceleration `acceleration_rad_s2`.
    #[pyo3(signature = (acceleration_rad_s2))]
    fn reversal(&self, acceleration_rad_s2: f64) -> Self {
        self.then(Motion::Reversal {
            acceleration_rad_s2,
        })
    }

    /// This profile followed by the segments of `other` (its initial values are ignored).
    #[pyo3(signature = (other))]
    fn concat(&self, other: &PyMotionProfile) -> Self {
        let mut inner = self.inner.clone();
        inner.segments.extend(other.inner.segments.iter().copied());
        Self { inner }
    }

    /// Initial angle (rad).
    #[getter]
    fn initial_angle_rad(&self) -> f64 {
        self.inner.initial_angle_rad
    }

    /// Initial speed (rad/s).
    #[getter]
    fn initial_speed_rad_s(&self) -> f64 {
        self.inner.initial_speed_rad_s
    }

    /// Number of segments.
    fn __len__(&self) -> usize {
        self.inner.segments.len()
    }

    fn __repr__(&self) -> String {
        let segments: Vec<String> = self
            .inner
            .segments
            .iter()
            .map(|m| format!(".{}", segment_text(m)))
            .collect();
        format!(
            "MotionProfile(initial_angle_rad={:?}, initial_speed_rad_s={:?}){}",
            self.inner.initial_angle_rad,
            self.inner.initial_speed_rad_s,
            segments.join("")
        )
    }
}

fn segment_text(m: &Motion) -> String {
    match *m {
        Motion::ConstantSpeed {
            speed_rad_s,
            duration_s,
        } => format!("constant_speed(speed_rad_s={speed_rad_s:?}, duration_s={duration_s:?})"),
        Motion::ConstantAcceleration {
            acceleration_rad_s2,
            duration_s,
        } => format!(
            "constant_acceleration(acceleration_rad_s2={acceleration_rad_s2:?}, duration_s={duration_s:?})"
        ),
        Motion::Step {
            step_rad,
            duration_s,
        } => format!("step(step_rad={step_rad:?}, duration_s={duration_s:?})"),
        Motion::Trapezoidal {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
        } => format!(
            "trapezoidal(distance_rad={distance_rad:?}, max_speed_rad_s={max_speed_rad_s:?}, \
             max_acceleration_rad_s2={max_acceleration_rad_s2:?})"
        ),
        Motion::SCurve {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
            max_jerk_rad_s3,
        } => format!(
            "s_curve(distance_rad={distance_rad:?}, max_speed_rad_s={max_speed_rad_s:?}, \
             max_acceleration_rad_s2={max_acceleration_rad_s2:?}, max_jerk_rad_s3={max_jerk_rad_s3:?})"
        ),
        Motion::SpeedRipple {
            ripple_rad_s,
            frequency_hz,
            duration_s,
        } => format!(
            "speed_ripple(ripple_rad_s={ripple_rad_s:?}, frequency_hz={frequency_hz:?}, \
             duration_s={duration_s:?})"
        ),
        Motion::Reversal {
            acceleration_rad_s2,
        } => format!("reversal(acceleration_rad_s2={acceleration_rad_s2:?})"),
    }
}
