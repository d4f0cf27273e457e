//! The one place where errors become Python exceptions.
//!
//! Every fallible function of the binding returns [`Error`]; its `From<Error> for PyErr`
//! below is the only code that picks a Python exception type:
//!
//! * a refused configuration or design argument (the Rust crates' typed errors) and bad
//!   array shapes or lengths are `ValueError`s whose message names the parameter;
//! * an array of the wrong element type is a `TypeError` naming the parameter, the dtype
//!   given and the dtype expected;
//! * errors raised by Python itself while converting arguments pass through unchanged.

use angletrack_core::ConfigError;
use pyo3::PyErr;
use pyo3::exceptions::{PyTypeError, PyValueError};

/// Why a call into the binding failed.
#[derive(Debug)]
pub enum Error {
    /// The core refused a configuration (gains, sample period, thresholds).
    Config(ConfigError),
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
    /// An exception raised by Python (or numpy) while converting an argument.
    Python(PyErr),
}

impl Error {
    /// A `ValueError` about `parameter`.
    pub fn value(parameter: &'static str, message: impl Into<String>) -> Self {
        Error::Value {
            parameter,
            message: message.into(),
        }
    }
}

impl From<ConfigError> for Error {
    fn from(e: ConfigError) -> Self {
        Error::Config(e)
    }
}

impl From<angletrack::Error> for Error {
    fn from(e: angletrack::Error) -> Self {
        Error::Design(e)
    }
}

impl From<PyErr> for Error {
    fn from(e: PyErr) -> Self {
        Error::Python(e)
    }
}

impl From<Error> for PyErr {
    fn from(e: Error) -> Self {
        match e {
            // The core's message starts with the parameter's name.
            Error::Config(e) => PyValueError::new_err(e.to_string()),
            // Its message names the argument (or, for refused gains, the core's parameter).
            Error::Design(e) => PyValueError::new_err(e.to_string()),
            Error::Dtype {
                parameter,
                given,
                expected,
            } => PyTypeError::new_err(format!(
                "{parameter}: expected {expected}, got {given} (convert it with .astype(), no \
                 silent conversion is made)"
            )),
            Error::Value { parameter, message } => {
                PyValueError::new_err(format!("{parameter}: {message}"))
            }
            Error::Python(e) => e,
        }
    }
}

/// The result type of every fallible binding function.
pub type Result<T> = core::result::Result<T, Error>;
