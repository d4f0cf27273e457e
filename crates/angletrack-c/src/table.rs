//! The angle correction as a table over the electrical turn (the core's
//! `AngleCorrectionTable` and `FixedAngleCorrectionTable`), as plain C structs that firmware
//! may fill once at start-up or keep `const` in flash: `at_angle_correction_table_f32` (the
//! error in rad at `AT_ANGLE_TABLE_LENGTH` angles, for the f32 chain) and
//! `at_angle_table_fixed` (the same in Q15 rad, for the fixed-point chain). Each is made from
//! the errors in rad, from the harmonics `angletrack calibrate` learns, or (the float one)
//! from a measured error curve; the chains check them again when they are built.

use angletrack_core::{
    AngleCorrection, AngleCorrectionTable, ConfigError, FixedAngleCorrectionTable, Parameter,
};

use crate::chain::at_angle_correction_f32;

/// The entries of an angle-correction table (`at_angle_correction_table_f32`,
/// `at_angle_table_fixed`): the error at the angles `-pi + 2 pi k / 256`, `k = 0..255`,
/// interpolated linearly between them at the observer's predicted angle.
pub const AT_ANGLE_TABLE_LENGTH: usize = 256;

/// The float table of the f32 chain.
pub(crate) type TableF32 = AngleCorrectionTable<f32, AT_ANGLE_TABLE_LENGTH>;
/// The fixed-point chain's table.
pub(crate) type TableFixed = FixedAngleCorrectionTable<AT_ANGLE_TABLE_LENGTH>;

/// The sensor's angle error `d` (rad) at the angles `-pi + 2 pi k / 256`: the f32 chain
/// rotates each sample by `-d` at the observer's predicted angle, `d` interpolated linearly
/// (an alternative to the harmonic `at_angle_correction_f32`: the same cost whatever the
/// error's shape). Each entry finite and within 0.25 rad; all zero corrects nothing. Made by
/// `at_angle_correction_table_f32_from_harmonics` or `_from_curve`, or written directly.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_angle_correction_table_f32 {
    /// `d` (rad) at the angle `-pi + 2 pi k / 256`, index `k`.
    pub errors_rad: [f32; AT_ANGLE_TABLE_LENGTH],
}

/// The sensor's angle error `d` in Q15 rad (2^-15 rad) at the angles `-pi + 2 pi k / 256`
/// (the top 8 bits of the binary angle, offset by half a turn), for the fixed-point chain,
/// which rotates each sample by `-d` in integers at the predicted binary angle. Each entry
/// within 8192 (0.25 rad); all zero corrects nothing. Made by
/// `at_angle_table_fixed_from_errors` or `_from_harmonics`, or kept `const`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct at_angle_table_fixed {
    /// `d` (Q15 rad) at the angle `-pi + 2 pi k / 256`, index `k`.
    pub errors_q15: [i16; AT_ANGLE_TABLE_LENGTH],
}

impl at_angle_correction_table_f32 {
    /// The core's table, checked.
    pub(crate) fn checked(&self) -> Result<TableF32, ConfigError> {
        AngleCorrectionTable::new(self.errors_rad)
    }

    /// The table of a core table.
    fn of(table: &TableF32) -> Self {
        Self {
            errors_rad: table.errors(),
        }
    }

    /// The table of checked harmonics.
    pub(crate) fn from_harmonics(h: &at_angle_correction_f32) -> Result<Self, ConfigError> {
        let harmonics = AngleCorrection::new(h.cos_coefficients, h.sin_coefficients)?;
        Ok(Self::of(&AngleCorrectionTable::from_harmonics(&harmonics)))
    }

    /// The table of a measured error curve (`curve[j]` at `-pi + 2 pi j / curve.len()`).
    pub(crate) fn from_curve(curve: &[f32]) -> Result<Self, ConfigError> {
        AngleCorrectionTable::from_curve(curve).map(|t| Self::of(&t))
    }
}

impl at_angle_table_fixed {
    /// The core's table, checked (every entry within 0.25 rad).
    pub(crate) fn checked(&self) -> Result<TableFixed, ConfigError> {
        FixedAngleCorrectionTable::new(self.errors_q15)
    }

    /// The table of errors in rad (each finite and within 0.25 rad), rounded to Q15: no
    /// float table in between (a Cortex-M0's stack is small).
    pub(crate) fn from_errors(errors: &[f32; AT_ANGLE_TABLE_LENGTH]) -> Result<Self, ConfigError> {
        let mut errors_q15 = [0; AT_ANGLE_TABLE_LENGTH];
        for (q, &d) in errors_q15.iter_mut().zip(errors) {
            if !d.is_finite() {
                return Err(ConfigError::NotFinite(Parameter::AngleCorrection));
            }
            if d.abs() > 0.25 {
                return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
            }
            // Within 8192, rounded half away from zero (as `round`): the truncation of the
            // value moved half a unit away from zero.
            let scaled = d * 32768.0;
            *q = (scaled + 0.5_f32.copysign(scaled)) as i16;
        }
        FixedAngleCorrectionTable::new(errors_q15).map(|t| Self {
            errors_q15: t.errors_q15(),
        })
    }

    /// The table of checked harmonics, rounded to Q15 (no float table in between).
    pub(crate) fn from_harmonics(h: &at_angle_correction_f32) -> Result<Self, ConfigError> {
        let (a, b) = (h.cos_coefficients, h.sin_coefficients);
        let harmonics = AngleCorrection::new(a.map(f64::from), b.map(f64::from))?;
        Ok(Self {
            errors_q15: FixedAngleCorrectionTable::from_harmonics(&harmonics).errors_q15(),
        })
    }
}
