//! Gains and calibrations as source code for firmware: a C header or a block of Rust
//! `const`s, the text `angletrack design --format c|rust` and `angletrack calibrate --format
//! c|rust` write; and the gains files of `angletrack design --format json` ([`GainsFile`],
//! [`FixedGainsFile`]).
//!
//! Float constants are written in the firmware's float type ([`FloatType`]): each as the
//! shortest decimal that rounds back to the same `f32` (or `f64`), in scientific notation
//! (`1.2345679e-01`), so that the firmware holds exactly the value rounded here. The
//! fixed-point constants ([`fixed_c_header`], [`fixed_rust`]) are integers, their sample
//! period an `f64`.
//!
//! ```
//! use angletrack::export::{FloatType, gains_c_header};
//! let gains = angletrack::Gains::<f64, 2>::new([0.06, 0.001], 1e-4)?;
//! let header = gains_c_header(&gains, FloatType::F32, "rdc", "")?;
//! assert!(header.contains("static const float rdc_gains[RDC_ORDER] = {6e-02f, 1e-03f};"));
//! assert!(header.contains("#define RDC_SAMPLE_RATE_HZ (1e+04f)"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use core::fmt;
use core::str::FromStr;

mod calibration;
mod gains;
pub(crate) mod gains_file;
#[cfg(test)]
mod tests;

pub use calibration::{calibration_c_header, calibration_rust};
pub use gains::{fixed_c_header, fixed_rust, gains_c_header, gains_rust};
pub use gains_file::{
    FIXED_GAINS_FILE_FORMAT, FixedGainsFile, GAINS_FILE_FORMAT, GAINS_FILE_VERSION, GainsFile,
};

/// The float type of the constants written for firmware.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FloatType {
    /// `float` in C, `f32` in Rust (a Cortex-M4F's single-precision FPU).
    #[default]
    F32,
    /// `double` in C, `f64` in Rust.
    F64,
}

impl FloatType {
    /// The C type: `float` or `double`.
    pub const fn c_type(self) -> &'static str {
        match self {
            FloatType::F32 => "float",
            FloatType::F64 => "double",
        }
    }

    /// The suffix of a C literal of this type: `f` for `float`, none for `double`.
    pub const fn c_suffix(self) -> &'static str {
        match self {
            FloatType::F32 => "f",
            FloatType::F64 => "",
        }
    }

    /// The Rust type: `f32` or `f64`.
    pub const fn rust_type(self) -> &'static str {
        match self {
            FloatType::F32 => "f32",
            FloatType::F64 => "f64",
        }
    }

    /// The name the command line and the Python API give it: `float32` or `float64`.
    pub const fn name(self) -> &'static str {
        match self {
            FloatType::F32 => "float32",
            FloatType::F64 => "float64",
        }
    }
}

impl fmt::Display for FloatType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FloatType {
    type Err = ExportError;

    /// `float32` or `float64` ([`FloatType::name`]).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "float32" => Ok(FloatType::F32),
            "float64" => Ok(FloatType::F64),
            other => Err(ExportError::FloatType(other.to_string())),
        }
    }
}

/// Why a generator refused its arguments; [`ExportError::field`] names the one at fault.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ExportError {
    /// The name prefixing every identifier is not a C/Rust identifier
    /// (`[A-Za-z_][A-Za-z0-9_]*`).
    Name(String),
    /// A float type's name other than `float32` or `float64`.
    FloatType(String),
    /// A value is NaN or infinite once rounded to the firmware's float type (a gain beyond
    /// `f32`'s range, for example).
    NotFinite {
        /// What holds the value (`gains`, `sample_period_s`, `sensor`, ...).
        field: &'static str,
        /// The value before the rounding.
        value: f64,
        /// The float type it was rounded to.
        float_type: FloatType,
    },
}

impl ExportError {
    /// The argument at fault: `name`, `dtype` or the field of the value.
    pub const fn field(&self) -> &'static str {
        match self {
            ExportError::Name(_) => "name",
            ExportError::FloatType(_) => "dtype",
            ExportError::NotFinite { field, .. } => field,
        }
    }
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExportError::Name(name) => write!(f, "name: {name:?} is not a C/Rust identifier"),
            ExportError::FloatType(name) => {
                write!(f, "dtype: expected float32 or float64, got {name:?}")
            }
            ExportError::NotFinite {
                field,
                value,
                float_type,
            } => write!(f, "{field}: {value:?} is not finite in {float_type}"),
        }
    }
}

impl std::error::Error for ExportError {}

/// The shortest decimal that rounds back to `value` in `float_type`, in scientific
/// notation with an exponent of at least two digits (`1.8e+03`, `5e-05`, `-0e+00`): the
/// form of NumPy's `format_float_scientific(unique=True, trim="-")`, so that a header
/// generated by NumPy and checked into a firmware project regenerates unchanged.
///
/// ```
/// use angletrack::export::{FloatType, literal};
/// assert_eq!(literal(0.1, FloatType::F64, "gains")?, "1e-01");
/// assert_eq!(literal(123456789.0, FloatType::F32, "gains")?, "1.2345679e+08");
/// assert!(literal(1e39, FloatType::F32, "gains").is_err()); // beyond f32
/// # Ok::<(), angletrack::export::ExportError>(())
/// ```
pub fn literal(
    value: f64,
    float_type: FloatType,
    field: &'static str,
) -> Result<String, ExportError> {
    // Rust's `{:e}` of a float is its shortest round-trip decimal (`1.8e3`, `1e-5`).
    let shortest = match float_type {
        FloatType::F32 => {
            // Rounding to the firmware's type is the point: the literal is that float.
            let x = value as f32;
            x.is_finite().then(|| format!("{x:e}"))
        }
        FloatType::F64 => value.is_finite().then(|| format!("{value:e}")),
    };
    let Some(shortest) = shortest else {
        return Err(ExportError::NotFinite {
            field,
            value,
            float_type,
        });
    };
    let (mantissa, exponent) = shortest.split_once('e').unwrap_or((&shortest, "0"));
    let (sign, digits) = match exponent.strip_prefix('-') {
        Some(digits) => ('-', digits),
        None => ('+', exponent),
    };
    Ok(format!("{mantissa}e{sign}{digits:0>2}"))
}

/// `name` if it is a C/Rust identifier, else [`ExportError::Name`].
pub fn identifier(name: &str) -> Result<&str, ExportError> {
    let mut chars = name.chars();
    let first_ok = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if first_ok && chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        Ok(name)
    } else {
        Err(ExportError::Name(name.to_string()))
    }
}

/// The lines of a description for a comment: trimmed, each without trailing blanks (none
/// for an empty description), split at every line break (`\n`, `\r\n` or a lone `\r`,
/// which some compilers end a line at), and any `*/` written `* /`: a description never
/// closes the C header's block comment, whatever its text.
fn comment_lines(description: &str) -> impl Iterator<Item = String> {
    let text = description.trim().replace("\r\n", "\n");
    let lines: Vec<String> = if text.is_empty() {
        Vec::new()
    } else {
        text.split(['\n', '\r'])
            .map(|line| line.trim_end().replace("*/", "* /"))
            .collect()
    };
    lines.into_iter()
}

/// `values` as literals of `float_type` with `suffix`, comma-separated.
fn literals(
    values: &[f64],
    float_type: FloatType,
    suffix: &str,
    field: &'static str,
) -> Result<String, ExportError> {
    let texts = values
        .iter()
        .map(|&v| literal(v, float_type, field).map(|text| text + suffix))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(texts.join(", "))
}
