//! Raw ADC counts as an observer's input: integer numpy arrays (int16, uint16, int32, and
//! numpy's default int64, range-checked as int32) converted through the core's
//! `AdcScaling`, with no conversion by the caller.
//!
//! The rule is `angletrack::CountsInput`'s (the crate's `counts` module): the counts minus a
//! mid-scale, divided by `adc_counts_per_unit` (default 1: the observer runs in counts). The
//! mid-scale is `adc_mid_scale`, else 0 for signed counts (int16 and int32 arrays, or
//! `adc_signed=True`); `track` (the whole capture in one call) reads the rest from its
//! samples by `angletrack::capture_counts`, while `Observer` (a stream) refuses unsigned or
//! int64 counts whose mid-scale or signedness is not stated, naming the argument. This
//! module only moves numpy arrays in and out and names the arguments.

use angletrack::{
    ChannelCounts, CountsError, CountsInput, CountsInputError, CountsSettings, Signedness,
};
use numpy::prelude::*;
use numpy::{Element, PyArray1, PyArrayDescr, PyUntypedArray};
use pyo3::prelude::*;

use crate::arrays::{Count, Samples, paired_samples, read_only, samples};
use crate::dispatch::Sample;
use crate::errors::{Error, Result};

/// The numpy names of the integer dtypes of raw ADC counts: int16, uint16 (offset binary),
/// int32 and int64 (numpy's default integer, converted to one of the others).
const COUNTS_DTYPES: [&str; 4] = ["int16", "uint16", "int32", "int64"];

/// The counts dtype's name of a dtype (native byte order), `None` for any other.
pub fn counts_dtype(descr: &Bound<'_, PyArrayDescr>) -> Option<&'static str> {
    let name = descr.to_string();
    COUNTS_DTYPES.into_iter().find(|&n| n == name)
}

/// The counts dtype's name of an argument, `None` unless it is an array of integer counts.
fn counts_array<'py>(
    obj: &Bound<'py, PyAny>,
) -> Option<(&'static str, Bound<'py, PyUntypedArray>)> {
    let array = obj.cast::<PyUntypedArray>().ok()?;
    Some((counts_dtype(&array.dtype())?, array.clone()))
}

/// The ADC arguments of an observer as given: the settings, and the name of the first one
/// the caller stated (`None`: none), refused when the samples turn out to be floats.
#[derive(Debug, Clone, Copy, Default)]
pub struct AdcSettings {
    /// The scaling of integer counts.
    pub counts: CountsSettings,
    /// The first ADC argument the caller gave.
    pub stated: Option<&'static str>,
}

/// The ADC arguments of an observer: `adc_mid_scale` (counts), `adc_counts_per_unit` and
/// `adc_signed` (`None`: not stated), checked by the core (a `ConfigError` naming either
/// of the first two).
pub fn adc_settings(
    mid_scale: Option<crate::arrays::Count>,
    counts_per_unit: Option<f64>,
    signed: Option<bool>,
) -> Result<AdcSettings> {
    let stated = [
        mid_scale.is_some().then_some("adc_mid_scale"),
        counts_per_unit.map(|_| "adc_counts_per_unit"),
        signed.map(|_| "adc_signed"),
    ]
    .into_iter()
    .flatten()
    .next();
    let mid_scale = mid_scale
        .map(|m| m.get::<i32>("adc_mid_scale"))
        .transpose()?;
    let signedness = signed.map(Signedness::of_signed);
    Ok(AdcSettings {
        counts: CountsSettings::new(mid_scale, counts_per_unit, signedness)?,
        stated,
    })
}

/// A `CountsInputError` as the Python caller wrote the arguments.
fn named(e: CountsInputError) -> Error {
    const STATE: &str =
        "give adc_signed=True (two's complement) or adc_signed=False (offset binary)";
    match e {
        CountsInputError::Scaling(e) => Error::Config(e),
        CountsInputError::Counts(e @ CountsError::Ambiguous { .. }) => {
            Error::value("adc_signed", format!("{e}: {STATE}"))
        }
        CountsInputError::Counts(_) => Error::value("y_c", e.to_string()),
        CountsInputError::BeyondI32 { channel, .. } => Error::value(channel, e.to_string()),
        CountsInputError::MixedTypes => Error::value("y_s", e.to_string()),
        CountsInputError::StreamMidScale => Error::value(
            "adc_mid_scale",
            format!("{e}; give adc_mid_scale, or track the whole capture in one call with track()"),
        ),
        CountsInputError::StreamSignedness => Error::value(
            "adc_signed",
            format!("{e}; {STATE}, or give int16 or int32 arrays, which are signed"),
        ),
    }
}

/// Whether `samples` are raw counts (an array of an integer dtype the observer takes).
pub fn is_counts(samples: &Bound<'_, PyAny>) -> bool {
    counts_array(samples).is_some()
}

/// The samples of `y_c` and `y_s`: arrays of the observer's float type as they are,
/// arrays of counts scaled by `input` (`y_s` then of `y_c`'s counts type). `y_c` is checked
/// first, then `y_s`, each as `crate::arrays::samples` checks floats. Floats are refused
/// (naming `stated`, the first ADC argument given) when an ADC argument was given: it
/// applies to counts only, and ignoring it would track other samples than the caller asked
/// for.
pub fn signals<'py, T: Sample>(
    input: &mut CountsInput<T>,
    stated: Option<&'static str>,
    y_c: &Bound<'py, PyAny>,
    y_s: &Bound<'py, PyAny>,
) -> Result<(Samples<'py, T>, Samples<'py, T>)> {
    let Some((kind, c)) = counts_array(y_c) else {
        let pair = (samples::<T>(y_c, "y_c")?, samples::<T>(y_s, "y_s")?);
        if let Some(stated) = stated {
            return Err(Error::value(
                stated,
                "applies to raw ADC counts (int16, uint16, int32 or int64 arrays) but the \
                 samples are floats: scale floats before the call, or leave it out",
            ));
        }
        return Ok(pair);
    };
    match counts_array(y_s) {
        Some((ks, s)) if ks == kind => match kind {
            "int16" => scaled::<T, i16>(input, (&c, &s)),
            "uint16" => scaled::<T, u16>(input, (&c, &s)),
            "int32" => scaled::<T, i32>(input, (&c, &s)),
            _ => scaled::<T, i64>(input, (&c, &s)),
        },
        other => {
            // `y_c`'s own shape first, as for floats, then `y_s`'s.
            one_dimensional(&c, "y_c")?;
            if let Ok(array) = y_s.cast::<PyUntypedArray>()
                && array.ndim() != 1
            {
                one_dimensional(array, "y_s")?;
            }
            Err(Error::Dtype {
                parameter: "y_s",
                given: other.map_or("another dtype", |k| k.0).into(),
                expected: format!("raw counts of y_c's dtype, {kind}"),
            })
        }
    }
}

/// The counts `c`, `s` of element type `I` (both shapes checked first), scaled by `input`.
fn scaled<'py, T: Sample, I: Element + Copy>(
    input: &mut CountsInput<T>,
    (c, s): (&Bound<'_, PyUntypedArray>, &Bound<'_, PyUntypedArray>),
) -> Result<(Samples<'py, T>, Samples<'py, T>)>
where
    for<'a> ChannelCounts<'a>: From<&'a [I]>,
{
    let (c, s) = (counts::<I>(c, "y_c")?, counts::<I>(s, "y_s")?);
    let (c, s) = input
        .scale_channels(c.as_slice().into(), s.as_slice().into())
        .map_err(named)?;
    Ok((Samples::Copied(c), Samples::Copied(s)))
}

/// Each channel's extremes of a capture of whole counts, gathered chunk by chunk
/// (`angletrack::CountsExtremes`): what `capture_counts` reads of the whole capture.
#[pyclass(name = "CountsExtremes", module = "angletrack")]
#[derive(Debug, Clone, Default)]
pub struct PyCountsExtremes {
    inner: angletrack::CountsExtremes,
}

#[pymethods]
impl PyCountsExtremes {
    /// No sample yet.
    #[new]
    fn py_new() -> Self {
        Self::default()
    }

    /// Adds the chunk `y_c`, `y_s` (1-D arrays of equal lengths).
    fn add(&mut self, y_c: &Bound<'_, PyAny>, y_s: &Bound<'_, PyAny>) -> Result<()> {
        let (c, s) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
        self.inner.add(c.as_slice(), s.as_slice());
        Ok(())
    }

    /// `y_c`'s and `y_s`'s `(lowest, highest)`, `None` for a channel without a sample.
    #[getter]
    fn channels(&self) -> [Option<(f64, f64)>; 2] {
        self.inner.channels()
    }
}

/// The signedness and mid-scale of a whole capture of counts (`angletrack::capture_counts`):
/// `(signed, mid_scale)` from the signedness and resolution stated (`None`: not stated),
/// whether the counts' type is unsigned, and the capture's `extremes`. A `ConfigError`
/// naming `adc_signed` when the capture does not show its signedness (its message ends with
/// `state_with`, how the caller states it), naming `adc_bits` for a resolution outside 2 to
/// 53, naming `capture` for counts no ADC gives.
#[pyfunction]
#[pyo3(signature = (extremes, *, signed = None, bits = None, unsigned_type = false,
    state_with = "give adc_signed=True or adc_signed=False"))]
pub fn capture_counts(
    extremes: &PyCountsExtremes,
    signed: Option<bool>,
    bits: Option<u32>,
    unsigned_type: bool,
    state_with: &str,
) -> Result<(bool, u64)> {
    use angletrack::{CountsError, Signedness, StatedCounts};
    let stated = StatedCounts {
        signedness: signed.map(Signedness::of_signed),
        bits,
    };
    match angletrack::capture_counts(stated, unsigned_type, &extremes.inner) {
        Ok(c) => Ok((c.signedness == Signedness::Signed, c.mid_scale)),
        Err(e @ CountsError::Ambiguous { .. }) => {
            Err(Error::value("adc_signed", format!("{e}: {state_with}")))
        }
        Err(e @ CountsError::Bits(_)) => Err(Error::value("adc_bits", e.to_string())),
        Err(e @ CountsError::NotCounts(_)) => Err(Error::value("capture", e.to_string())),
    }
}

/// The diagnostics' thresholds of a whole capture whose first samples are `y_c`, `y_s`
/// (`angletrack::capture_fault_thresholds`): `FaultThresholds(nominal_amplitude=A)` with
/// `A` the median magnitude of the first 4096 samples (the defaults when it is not
/// positive), and the tracking-error level above their angle noise (8 times it, at least
/// 0.05: `FaultThresholds::with_tracking_error_above_noise`), the roundness check on the
/// circle they show; with `pole_pairs` (a motor's, the drive's electrical angle that many
/// times the tracked one) the angle-error levels divided by them
/// (`angletrack::capture_fault_thresholds_for_pole_pairs`). What `track` measures, and what
/// a caller feeding the capture to an `Observer` in chunks states with `fault_thresholds=`.
#[pyfunction]
#[pyo3(signature = (y_c, y_s, *, pole_pairs = Count::Whole(1)),
    text_signature = "(y_c, y_s, *, pole_pairs=1)")]
pub fn capture_fault_thresholds(
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    pole_pairs: Count,
) -> Result<crate::diagnostics::PyFaultThresholds> {
    let (c, s) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
    let pole_pairs = pole_pairs.get::<u32>("pole_pairs")?;
    let t =
        angletrack::capture_fault_thresholds_for_pole_pairs(c.as_slice(), s.as_slice(), pole_pairs);
    Ok(crate::diagnostics::PyFaultThresholds::from_typed(&t))
}

/// Refuses (naming `parameter`) an array of samples that is not 1-D and non-empty.
fn one_dimensional(array: &Bound<'_, PyUntypedArray>, parameter: &'static str) -> Result<()> {
    if array.ndim() == 1 && array.len() > 0 {
        return Ok(());
    }
    Err(Error::value(
        parameter,
        format!(
            "expected a non-empty 1-D array of samples, got shape {:?}",
            array.shape()
        ),
    ))
}

/// The counts of a 1-D, non-empty array of `I`, copied.
fn counts<I: Element + Copy>(
    array: &Bound<'_, PyUntypedArray>,
    parameter: &'static str,
) -> Result<Vec<I>> {
    one_dimensional(array, parameter)?;
    let typed = array
        .cast::<PyArray1<I>>()
        .map_err(|e| Error::Python(e.into()))?;
    let view = read_only(typed, parameter)?;
    Ok(view.as_array().iter().copied().collect())
}
