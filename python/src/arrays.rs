//! Conversion of Python arguments into sample slices, and of result vectors into numpy arrays.
//!
//! Input rules (the same for every function that takes samples):
//! * a numpy array must be 1-D, non-empty, and of the expected float dtype (`TypeError`
//!   otherwise: no silent up- or down-cast), or for an observer raw ADC counts (int16,
//!   uint16, int32: `crate::counts`);
//! * a non-contiguous (strided, misaligned) array is copied, since that is what a user
//!   slicing `y[::2]` expects;
//! * anything else (a list, a tuple) is converted with `numpy.asarray(obj, dtype)` when
//!   it holds real numbers (`TypeError` for strings, complex numbers, booleans or objects;
//!   `ConfigError` for `None`).

use angletrack::ArgumentError;
use numpy::prelude::*;
use numpy::{
    Element, PyArray1, PyArrayDescr, PyReadonlyArray1, PyReadwriteArray1, PyUntypedArray, dtype,
};
use pyo3::prelude::*;

use crate::counts::counts_dtype;
use crate::errors::{Error, Result};

/// The float type of a run, chosen from the input's dtype or the user's `dtype` argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Float {
    /// `numpy.float32`.
    F32,
    /// `numpy.float64`.
    F64,
}

impl Float {
    /// The numpy name of the dtype.
    pub fn name(self) -> &'static str {
        match self {
            Float::F32 => "float32",
            Float::F64 => "float64",
        }
    }

    /// The float type of a dtype-like Python object (`numpy.float32`, `"float64"`, a
    /// `numpy.dtype`); `None` gives `float64`.
    pub fn from_dtype_like(
        obj: Option<&Bound<'_, PyAny>>,
        parameter: &'static str,
    ) -> Result<Self> {
        let Some(obj) = obj.filter(|o| !o.is_none()) else {
            return Ok(Float::F64);
        };
        let descr = PyArrayDescr::new(obj.py(), obj).ok();
        descr
            .as_ref()
            .and_then(Self::of_descr)
            .ok_or_else(|| Error::Dtype {
                parameter,
                given: descr.map_or_else(|| type_description(obj), |d| d.to_string()),
                expected: "numpy.float32 or numpy.float64".into(),
            })
    }

    /// The float type of the samples `obj`: the dtype of a numpy array (float32 or float64;
    /// float64 for raw ADC counts, int16, uint16, int32 or int64 (range-checked), which it
    /// holds exactly;
    /// `TypeError` otherwise), float64 for anything else (a list is converted as float64).
    pub fn of_samples(obj: &Bound<'_, PyAny>, parameter: &'static str) -> Result<Self> {
        match obj.cast::<PyUntypedArray>() {
            Ok(array) => {
                let descr = array.dtype();
                if counts_dtype(&descr).is_some() {
                    return Ok(Float::F64);
                }
                Self::of_descr(&descr).ok_or_else(|| Error::Dtype {
                    parameter,
                    given: format!("an array of dtype {descr}"),
                    expected:
                        "an array of dtype float32 or float64 (or raw ADC counts: int16, uint16, int32 or \
                               int64)"
                            .into(),
                })
            }
            Err(_) => Ok(Float::F64),
        }
    }

    fn of_descr(descr: &Bound<'_, PyArrayDescr>) -> Option<Self> {
        let py = descr.py();
        if descr.is_equiv_to(&dtype::<f32>(py)) {
            Some(Float::F32)
        } else if descr.is_equiv_to(&dtype::<f64>(py)) {
            Some(Float::F64)
        } else {
            None
        }
    }
}

fn type_description(obj: &Bound<'_, PyAny>) -> String {
    match obj.get_type().name() {
        Ok(name) => format!("an object of type {name}"),
        Err(_) => "an object of unknown type".into(),
    }
}

/// The samples of one argument: borrowed from a contiguous numpy array, or a copy.
#[derive(Debug)]
pub enum Samples<'py, T: Element> {
    /// A view of the caller's contiguous array (read-only borrow).
    Borrowed(PyReadonlyArray1<'py, T>),
    /// A contiguous copy of a strided array.
    Copied(Vec<T>),
}

impl<T: Element> Samples<'_, T> {
    /// The samples as a contiguous slice.
    pub fn as_slice(&self) -> &[T] {
        match self {
            // A borrowed view is only kept when it is contiguous (checked in `samples`).
            Samples::Borrowed(view) => view.as_slice().unwrap_or(&[]),
            Samples::Copied(v) => v,
        }
    }
}

/// An array as it is, or anything else (a list) converted to an array of `T`.
fn as_array<'py, T: Element>(
    obj: &Bound<'py, PyAny>,
    parameter: &'static str,
) -> Result<Bound<'py, PyUntypedArray>> {
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        return Ok(array.clone());
    }
    if obj.is_none() {
        return Err(Error::value(
            parameter,
            "expected an array of samples, got None",
        ));
    }
    let py = obj.py();
    let asarray = PyModule::import(py, "numpy")?.getattr("asarray")?;
    let unreadable = |e: PyErr| {
        Error::value(
            parameter,
            format!("cannot be read as an array of floats ({e})"),
        )
    };
    // Read as numpy reads it first: converted straight to floats, strings would be parsed
    // and complex numbers lose their imaginary part, silently.
    let read = asarray
        .call1((obj,))
        .map_err(unreadable)?
        .cast_into::<PyUntypedArray>()
        .map_err(|e| Error::Python(e.into()))?;
    let kind = read.dtype().kind();
    if read.len() > 0 && !matches!(kind, b'i' | b'u' | b'f') {
        return Err(Error::Dtype {
            parameter,
            given: format!("a sequence of dtype {}", read.dtype()),
            expected: "real numbers".into(),
        });
    }
    asarray
        .call1((read, dtype::<T>(py)))
        .map_err(unreadable)?
        .cast_into::<PyUntypedArray>()
        .map_err(|e| Error::Python(e.into()))
}

/// The samples of argument `parameter`, checked against the rules of this module.
pub fn samples<'py, T: Element + Copy>(
    obj: &Bound<'py, PyAny>,
    parameter: &'static str,
) -> Result<Samples<'py, T>> {
    let py = obj.py();
    let array = as_array::<T>(obj, parameter)?;
    if array.ndim() != 1 {
        return Err(Error::value(
            parameter,
            format!(
                "expected a 1-D array of samples, got {} dimension(s) (shape {:?})",
                array.ndim(),
                array.shape()
            ),
        ));
    }
    let expected = dtype::<T>(py);
    let given = array.dtype();
    if !given.is_equiv_to(&expected) {
        return Err(Error::Dtype {
            parameter,
            given: format!("an array of dtype {given}"),
            expected: format!("an array of dtype {expected}"),
        });
    }
    if array.len() == 0 {
        return Err(Error::value(
            parameter,
            "is empty: at least one sample is needed",
        ));
    }
    let typed = array
        .cast_into::<PyArray1<T>>()
        .map_err(|e| Error::Python(e.into()))?;
    let view = read_only(&typed, parameter)?;
    if view.as_slice().is_ok() {
        return Ok(Samples::Borrowed(view));
    }
    // A strided or broadcast view may stand for more samples than memory holds: the copy is
    // asked for first, and refused with a MemoryError rather than an abort.
    let len = view.len();
    let mut copy = Vec::new();
    copy.try_reserve_exact(len).map_err(|_| Error::Memory {
        parameter,
        bytes: len as u128 * core::mem::size_of::<T>() as u128,
    })?;
    copy.extend(view.as_array().iter().copied());
    Ok(Samples::Copied(copy))
}

/// The samples of argument `parameter` (float32 or float64, checked as by [`samples`]) as
/// float64, float32 widened exactly.
pub fn float64(obj: &Bound<'_, PyAny>, parameter: &'static str) -> Result<Vec<f64>> {
    Ok(match Float::of_samples(obj, parameter)? {
        Float::F64 => samples::<f64>(obj, parameter)?.as_slice().to_vec(),
        Float::F32 => samples::<f32>(obj, parameter)?
            .as_slice()
            .iter()
            .map(|&x| f64::from(x))
            .collect(),
    })
}

/// The samples of two paired arguments (a cosine and a sine channel), each checked as by
/// [`samples`], refused (naming the second) when their lengths differ.
pub fn paired_samples<'py, T: Element + Copy>(
    (a, a_name): (&Bound<'py, PyAny>, &'static str),
    (b, b_name): (&Bound<'py, PyAny>, &'static str),
) -> Result<(Samples<'py, T>, Samples<'py, T>)> {
    let (a, b) = (samples::<T>(a, a_name)?, samples::<T>(b, b_name)?);
    ArgumentError::check_equal_lengths((a_name, a.as_slice().len()), (b_name, b.as_slice().len()))?;
    Ok((a, b))
}

/// A numpy column of a result class.
pub type Column<T> = Py<PyArray1<T>>;

/// The array that takes over `values` (no copy: a whole capture is not held twice).
pub fn array<T: Element>(py: Python<'_>, values: Vec<T>) -> Py<PyArray1<T>> {
    PyArray1::from_vec(py, values).unbind()
}

/// A write borrow of an output array the binding has just created.
pub fn writable<'py, T: Element>(
    array: &Bound<'py, PyArray1<T>>,
) -> Result<PyReadwriteArray1<'py, T>> {
    array
        .try_readwrite()
        .map_err(|e| Error::value("output", format!("cannot be written ({e})")))
}

/// The contiguous slice of an output array the binding has just created.
pub fn as_slice_mut<'a, T: Element>(view: &'a mut PyReadwriteArray1<'_, T>) -> Result<&'a mut [T]> {
    view.as_slice_mut()
        .map_err(|e| Error::value("output", format!("is not contiguous ({e})")))
}

/// Samples of many channels: a 2-D array (`channels x samples`, any layout; a copy is made
/// only if it is not C-contiguous) flattened row-major, with the number of channels and of
/// samples per channel. An array of floats is checked like [`samples`]; raw ADC counts
/// (`crate::counts`) are refused (`TypeError`): a batch takes samples of amplitude about 1,
/// which counts are not.
pub fn channel_samples<'py, T: Element + Copy>(
    obj: &Bound<'py, PyAny>,
    parameter: &'static str,
) -> Result<(Bound<'py, PyAny>, usize, usize)> {
    let numpy = PyModule::import(obj.py(), "numpy")?;
    let array = as_array::<T>(obj, parameter)?;
    if array.ndim() != 2 {
        return Err(Error::value(
            parameter,
            format!(
                "expected a 2-D array (channels x samples), got {} dimension(s) (shape {:?})",
                array.ndim(),
                array.shape()
            ),
        ));
    }
    let (channels, per_channel) = (array.shape()[0], array.shape()[1]);
    if counts_dtype(&array.dtype()).is_some() {
        return Err(Error::Dtype {
            parameter,
            given: format!("raw ADC counts of dtype {}", array.dtype()),
            expected: "floats (float32 or float64) of amplitude about 1: a batch takes no \
                       raw counts, scale them first, (counts - mid_scale) / amplitude"
                .into(),
        });
    }
    let flat = numpy
        .getattr("ascontiguousarray")?
        .call1((array,))?
        .call_method1("reshape", (-1,))?;
    samples::<T>(&flat, parameter)?;
    Ok((flat, channels, per_channel))
}

/// A read-only view of `typed`, refused naming `parameter` while Python code writes to it.
pub(crate) fn read_only<'py, E: Element>(
    typed: &Bound<'py, PyArray1<E>>,
    parameter: &'static str,
) -> Result<PyReadonlyArray1<'py, E>> {
    typed.try_readonly().map_err(|e| {
        Error::value(
            parameter,
            format!("cannot be read while it is being written ({e})"),
        )
    })
}

/// A whole-number argument as given (a Python int or a numpy integer, e.g. numpy's default
/// int64; anything else kept for the message), checked where the argument's name is known
/// ([`Count::at_least`]): pyo3's own refusals (an `OverflowError` for `-1`) name no argument.
#[derive(Debug, Clone)]
pub enum Count {
    /// The value.
    Whole(i128),
    /// Not a whole number: what was given.
    Other(String),
}

impl Count {
    /// The count, at least `min`, or a `ConfigError` naming `parameter`.
    pub fn at_least(&self, parameter: &'static str, min: usize) -> Result<usize> {
        self.within(parameter, min as i128, usize::MAX as i128)
            .map(|n| n as usize)
    }

    /// The value as the integer type `I` the crates take, or a `ConfigError` naming
    /// `parameter` with `I`'s range.
    pub fn get<I: Whole>(&self, parameter: &'static str) -> Result<I> {
        let n = self.within(parameter, I::MIN, I::MAX)?;
        // Within `I`'s range, checked above.
        I::try_from(n).map_err(|_| Error::value(parameter, format!("{n} is out of range")))
    }

    /// The value from `min` to `max`, or a `ConfigError` naming `parameter` (a bound of 2^64
    /// or more is left out of the message as no bound).
    fn within(&self, parameter: &'static str, min: i128, max: i128) -> Result<i128> {
        match *self {
            Count::Whole(n) if (min..=max).contains(&n) => Ok(n),
            Count::Whole(n) => Err(Error::value(
                parameter,
                if n < min && max >= u64::MAX as i128 {
                    format!("{n}: expected a whole number of at least {min}")
                } else {
                    format!("{n}: expected a whole number from {min} to {max}")
                },
            )),
            Count::Other(ref given) => Err(Error::value(
                parameter,
                format!("expected a whole number, got {given}"),
            )),
        }
    }
}

/// An integer type a whole-number argument is converted to ([`Count::get`]).
pub trait Whole: TryFrom<i128> {
    /// The smallest value.
    const MIN: i128;
    /// The largest value.
    const MAX: i128;
}

macro_rules! whole {
    ($($t:ty),*) => {$(
        impl Whole for $t {
            const MIN: i128 = <$t>::MIN as i128;
            const MAX: i128 = <$t>::MAX as i128;
        }
    )*};
}
whole!(u8, u32, u64, usize, i32, i64);

impl<'a, 'py> FromPyObject<'a, 'py> for Count {
    type Error = PyErr;

    fn extract(obj: pyo3::Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let whole = (!obj.is_instance_of::<pyo3::types::PyBool>())
            .then(|| obj.call_method0("__index__").ok())
            .flatten()
            .and_then(|i| i.extract::<i128>().ok());
        Ok(match whole {
            Some(n) => Count::Whole(n),
            None => Count::Other(crate::gains::type_name(&obj)),
        })
    }
}
