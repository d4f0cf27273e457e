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

/// The profile's methods: one per segment of the crate's `Motion`, of the same arguments
/// (floats, in the unit their names say), after `methods`; and `segment_text`, the call
/// that adds a segment as written in Python (the profile's `repr`).
macro_rules! segments {
    (methods { $($methods:tt)* } $($(#[$doc:meta])* $method:ident => $variant:ident { $($field:ident),* };)*) => {
        #[pymethods]
        impl PyMotionProfile {
            $(
                $(#[$doc])*
                #[pyo3(signature = ($($field),*))]
                fn $method(&self, $($field: f64),*) -> Self {
                    self.then(Motion::$variant { $($field),* })
                }
            )*
            $($methods)*
        }

        /// The Python call that adds segment `m`.
        fn segment_text(m: &Motion) -> String {
            match *m {
                $(Motion::$variant { $($field),* } => {
                    let arguments = [$(format!("{}={:?}", stringify!($field), $field)),*];
                    format!("{}({})", stringify!($method), arguments.join(", "))
                })*
            }
        }
    };
}

segments! {
    methods {
        #[new]
        #[pyo3(signature = (initial_angle_rad = 0.0, initial_speed_rad_s = 0.0))]
        fn py_new(initial_angle_rad: f64, initial_speed_rad_s: f64) -> Self {
            Self {
                inner: MotionProfile::new(initial_angle_rad, initial_speed_rad_s),
            }
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

    /// Constant speed `speed_rad_s` for `duration_s` (a speed step if it differs).
    constant_speed => ConstantSpeed { speed_rad_s, duration_s };
    /// Constant acceleration `acceleration_rad_s2` from the current speed for `duration_s`.
    constant_acceleration => ConstantAcceleration { acceleration_rad_s2, duration_s };
    /// A position step of `step_rad` at the segment's start, then the current speed held
    /// for `duration_s`.
    step => Step { step_rad, duration_s };
    /// A point-to-point move of `distance_rad` with a trapezoidal speed profile.
    trapezoidal => Trapezoidal { distance_rad, max_speed_rad_s, max_acceleration_rad_s2 };
    /// A point-to-point move of `distance_rad` with a jerk-limited S-curve speed profile.
    s_curve => SCurve { distance_rad, max_speed_rad_s, max_acceleration_rad_s2, max_jerk_rad_s3 };
    /// A sinusoidal speed ripple of amplitude `ripple_rad_s` at `frequency_hz` around the
    /// current speed, for `duration_s`.
    speed_ripple => SpeedRipple { ripple_rad_s, frequency_hz, duration_s };
    /// A reversal of the current speed at constant deceleration `acceleration_rad_s2`.
    reversal => Reversal { acceleration_rad_s2 };
}
