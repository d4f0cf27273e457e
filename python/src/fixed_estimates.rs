//! `FixedEstimate` and `FixedEstimates`: what `FixedObserver` gives back, in the integers
//! the firmware holds (`docs/theory.md §14`) and in physical units.

use angletrack::FixedColumns;
use angletrack_core::FixedEstimate as CoreFixedEstimate;
use pyo3::prelude::*;

use crate::arrays::{as_slice_mut, writable};
use crate::errors::Result;
use crate::estimates::zeros;
use crate::getters::class_methods;

/// What a fixed-point observer knows after its last sample: its integers and the same in
/// physical units.
#[pyclass(module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct FixedEstimate {
    /// The integers, and the position (rad), speed (rad/s) and acceleration (rad/s^2).
    pub(crate) inner: (CoreFixedEstimate, [f64; 3]),
}

class_methods! {
    FixedEstimate {
        /// Binary angle (2^32 per turn, -2^31 is -pi).
        angle: i32 = |this, py| this.inner.0.angle;
        /// Whole turns since initialisation: the position is `turns + angle / 2^32` turns.
        turns: i64 = |this, py| this.inner.0.turns;
        /// Speed (2^-32 turn per sample).
        speed: i32 = |this, py| this.inner.0.speed;
        /// Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer.
        acceleration: i64 = |this, py| this.inner.0.acceleration;
        /// Normalised phase error (Q15: 2^15 is 1).
        phase_error: i32 = |this, py| this.inner.0.phase_error;
        /// Fault flags of the monitor's last window (bits, see `angletrack.Faults`).
        faults: u8 = |this, py| this.inner.0.faults.bits();
        /// Multi-turn position (rad).
        position_rad: f64 = |this, py| this.inner.1[0];
        /// Speed (rad/s).
        speed_rad_s: f64 = |this, py| this.inner.1[1];
        /// Acceleration (rad/s^2).
        acceleration_rad_s2: f64 = |this, py| this.inner.1[2];
    }
    methods {
        fn __repr__(&self) -> String {
            let (e, [position_rad, speed_rad_s, acceleration_rad_s2]) = &self.inner;
            format!(
                "FixedEstimate(angle={}, turns={}, speed={}, acceleration={}, phase_error={}, \
                 faults={}, position_rad={position_rad:.9}, speed_rad_s={speed_rad_s:.6}, \
                 acceleration_rad_s2={acceleration_rad_s2:.6})",
                e.angle,
                e.turns,
                e.speed,
                e.acceleration,
                e.phase_error,
                e.faults.bits(),
            )
        }
    }
}

/// `FixedEstimates` of the columns `name: element type` (in `FixedColumns`' order), and
/// [`run_fixed`], which allocates and fills them.
macro_rules! fixed_estimates {
    ($($(#[$doc:meta])* $field:ident: $t:ty,)*) => {
        /// The estimates of a `FixedObserver.update`, one numpy array per quantity, one element
        /// per sample: the firmware's integers (`angle` int32, `turns` int64, `speed` int32,
        /// `acceleration` int64, `phase_error` int32, `faults` uint8) and the same in physical
        /// units (float64).
        #[pyclass(module = "angletrack", frozen, get_all)]
        #[derive(Debug)]
        pub struct FixedEstimates {
            $($(#[$doc])* $field: Py<PyAny>,)*
            /// The number of samples.
            len: usize,
        }

        /// The estimates of `n` samples: the columns allocated by numpy (a `MemoryError`
        /// where they cannot be) and filled by `fill` with the GIL released.
        pub(crate) fn run_fixed(
            py: Python<'_>,
            n: usize,
            fill: impl FnOnce(FixedColumns<'_>) + Send,
        ) -> Result<FixedEstimates> {
            $(let $field = zeros::<$t>(py, n)?;)*
            {
                $(let mut $field = writable(&$field)?;)*
                let columns = FixedColumns { $($field: as_slice_mut(&mut $field)?,)* };
                py.detach(|| fill(columns));
            }
            Ok(FixedEstimates { $($field: $field.into_any().unbind(),)* len: n })
        }
    };
}

fixed_estimates! {
    /// Binary angle (int32, 2^32 per turn, -2^31 is -pi).
    angle: i32,
    /// Whole turns since initialisation (int64).
    turns: i64,
    /// Speed (int32, 2^-32 turn per sample).
    speed: i32,
    /// Acceleration (int64, 2^-63 turn per sample^2); 0 for a 2nd-order observer.
    acceleration: i64,
    /// Normalised phase error (int32, Q15: 2^15 is 1).
    phase_error: i32,
    /// Fault flags of the monitor's window each sample ends in (uint8 bits, see
    /// `angletrack.Faults`).
    faults: u8,
    /// Multi-turn position `2 pi (turns + angle / 2^32)` (rad, float64).
    position_rad: f64,
    /// Speed (rad/s, float64).
    speed_rad_s: f64,
    /// Acceleration (rad/s^2, float64).
    acceleration_rad_s2: f64,
}

#[pymethods]
impl FixedEstimates {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "FixedEstimates({} samples: angle, turns, speed, acceleration, phase_error, faults, \
             position_rad, speed_rad_s, acceleration_rad_s2)",
            self.len
        )
    }
}
