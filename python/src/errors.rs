//! The one place where errors become Python exceptions, and where the Rust crates' parameter
//! names become the names of the Python arguments.
//!
//! Every fallible function of the binding returns [`Error`]; its `From<Error> for PyErr`
//! below is the only code that picks a Python exception type:
//!
//! * a refused argument (a configuration or design argument refused by the Rust crates, a
//!   bad array shape or length, an unknown name) is an `angletrack.ConfigError`, a subclass
//!   of `ValueError` whose `parameter` attribute is the argument's name as the caller
//!   spelled it, and whose message starts with that name;
//! * an array of the wrong element type is a `TypeError` naming the parameter, the dtype
//!   given and the dtype expected;
//! * a capture that cannot be read (or estimates not written) is an
//!   `angletrack.CaptureError`, a subclass of `ValueError` with `path`, `line` and `column`
//!   attributes (`None` where the fault has no line or column), whose message is
//!   `FILE:LINE:COLUMN: what`;
//! * a calibration file that cannot be read is a `ValueError` whose message is
//!   `FILE: FIELD: what is wrong`;
//! * an array larger than the memory left is a `MemoryError` naming the argument;
//! * errors raised by Python itself while converting arguments pass through unchanged.

use angletrack::Argument;
use angletrack::capture::CaptureError as CoreCaptureError;
use angletrack_core::{ConfigError as CoreConfigError, Parameter};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    angletrack,
    ConfigError,
    PyValueError,
    "An argument the extension refused. `parameter` is the argument's name as the caller \
     spelled it (`\"sample_period_s\"`, `\"gains\"`, `\"y_c\"`); the message starts with it."
);

pyo3::create_exception!(
    angletrack,
    CaptureError,
    PyValueError,
    "A capture that cannot be read, or estimates that cannot be written. `path` is the file, \
     `line` and `column` the 1-based place of the fault (`None` when the fault is not at one); \
     the message is `FILE:LINE:COLUMN: what is wrong`."
);

/// Why a call into the binding failed.
#[derive(Debug)]
pub enum Error {
    /// The core refused a configuration (gains, sample period, thresholds).
    Config(CoreConfigError),
    /// A design, analysis, scenario or metrics function of `angletrack` refused an argument.
    Design(angletrack::Error),
    /// An array (or another argument) has the wrong element type.
    Dtype {
        /// The argument's name.
        parameter: &'static str,
        /// The dtype (or type) given.
        given: String,
        /// What is accepted.
        expected: String,
    },
    /// An argument has a wrong value, shape or length; the message names it.
    Value {
        /// The argument's name.
        parameter: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// A capture could not be read, or estimates not written.
    Capture(CoreCaptureError),
    /// An argument needs more memory than can be had: `parameter` and the bytes asked for.
    Memory {
        /// The argument's name.
        parameter: &'static str,
        /// The bytes that could not be allocated.
        bytes: u128,
    },
    /// A firmware source generator refused its arguments.
    Export(angletrack::export::ExportError),
    /// A JSON file of the crate's (a calibration, gains) could not be read.
    JsonFile(angletrack::JsonFileError),
    /// An exception raised by Python (or numpy) while converting an argument.
    Python(PyErr),
}

impl From<angletrack::ArgumentError> for Error {
    fn from(e: angletrack::ArgumentError) -> Self {
        Error::value(e.argument, e.reason)
    }
}

impl From<angletrack::ChannelError> for Error {
    fn from(e: angletrack::ChannelError) -> Self {
        match e {
            angletrack::ChannelError::Config(e) => Error::Config(e),
            angletrack::ChannelError::Argument(e) => e.into(),
        }
    }
}

impl Error {
    /// A refused value of `parameter`.
    pub fn value(parameter: &'static str, message: impl Into<String>) -> Self {
        Error::Value {
            parameter,
            message: message.into(),
        }
    }
}

/// `From` each error of the crates (and Python's) into its variant of [`Error`].
macro_rules! from_errors {
    ($($error:ty => $variant:ident),* $(,)?) => {$(
        impl From<$error> for Error {
            fn from(e: $error) -> Self {
                Error::$variant(e.into())
            }
        }
    )*};
}

from_errors! {
    CoreConfigError => Config,
    angletrack::core::UnknownDiscretisation => Design,
    angletrack::Error => Design,
    CoreCaptureError => Capture,
    angletrack::export::ExportError => Export,
    angletrack::JsonFileError => JsonFile,
    PyErr => Python,
}

/// The Python argument a parameter of the core's configuration comes from: the core names
/// the Python arguments, except that the gains arrive as one sequence, `gains`, whose
/// element the core names (`gains[0] (l1)`), and the ADC's arguments carry an `adc_`
/// prefix.
fn python_parameter(p: Parameter) -> &'static str {
    match p {
        Parameter::AngleGain | Parameter::SpeedGain | Parameter::AccelerationGain => "gains",
        Parameter::MidScaleCounts => "adc_mid_scale",
        Parameter::CountsPerUnit => "adc_counts_per_unit",
        Parameter::SpeedFilter => "speed_cutoff_hz",
        other => other.name(),
    }
}

/// The Python argument a design, scenario or metrics argument comes from: the crate's name
/// without the symbol it adds in parentheses (`pole_ratio (K)` is the argument `pole_ratio`).
fn python_argument(a: Argument) -> &'static str {
    let name = a.name();
    name.split_once(" (").map_or(name, |(argument, _)| argument)
}

/// `message`, led by the name of the Python argument `python` if it does not start with it.
fn python_message(python: &str, message: String) -> String {
    if message.starts_with(python) {
        message
    } else {
        format!("{python}: {message}")
    }
}

/// `err` with the attributes `set` gives its value (or the error of setting them).
fn with_attributes(
    err: PyErr,
    set: impl FnOnce(&Bound<'_, pyo3::exceptions::PyBaseException>) -> PyResult<()>,
) -> PyErr {
    Python::attach(|py| set(err.value(py)).map_or_else(|setattr| setattr, |()| err))
}

/// The `ConfigError` of `parameter` with `message`.
fn config_error(parameter: &str, message: String) -> PyErr {
    with_attributes(ConfigError::new_err(message), |e| {
        e.setattr("parameter", parameter)
    })
}

/// The `ConfigError` of a core error, under the Python argument's name, `suffix` appended.
fn core_config_error(e: &CoreConfigError, suffix: &str) -> PyErr {
    let python = python_parameter(e.parameter());
    let message = python_message(python, e.to_string());
    config_error(python, format!("{message}{suffix}"))
}

/// The `CaptureError` of a capture reader's error, with its place as attributes.
fn capture_error(e: &CoreCaptureError) -> PyErr {
    with_attributes(CaptureError::new_err(e.to_string()), |err| {
        err.setattr("path", e.path.to_string_lossy().into_owned())?;
        err.setattr("line", e.line)?;
        err.setattr("column", e.column)
    })
}

impl From<Error> for PyErr {
    fn from(e: Error) -> Self {
        match e {
            Error::Config(e) => core_config_error(&e, ""),
            Error::Design(angletrack::Error::Gains(e)) => core_config_error(
                &e,
                " (the gains as designed, or rounded to the requested float type)",
            ),
            Error::Design(e) => match e.argument() {
                Some(a) => {
                    let python = python_argument(a);
                    config_error(python, python_message(python, e.to_string()))
                }
                None => PyValueError::new_err(e.to_string()),
            },
            Error::Dtype {
                parameter,
                given,
                expected,
            } => PyTypeError::new_err(format!(
                "{parameter}: expected {expected}, got {given} (convert it with .astype(), no \
                 silent conversion is made)"
            )),
            Error::Value { parameter, message } => {
                config_error(parameter, python_message(parameter, message))
            }
            Error::Capture(e) => capture_error(&e),
            Error::Memory { parameter, bytes } => PyMemoryError::new_err(format!(
                "{parameter}: {bytes} bytes are needed and cannot be allocated; process the \
                 samples in chunks (the observers keep their state between calls)"
            )),
            Error::Export(e) => config_error(e.field(), e.to_string()),
            Error::JsonFile(e) => PyValueError::new_err(e.to_string()),
            Error::Python(e) => e,
        }
    }
}

/// The result type of every fallible binding function.
pub type Result<T> = core::result::Result<T, Error>;
