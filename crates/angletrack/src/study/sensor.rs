//! A study's sensors: the spread of each parameter of the sensor model (a value or a
//! distribution), and one sensor's values drawn from them.

use rand::Rng;
use rand_distr::{Distribution, Normal};
use serde_json::Value;

use super::spec::optional;
use crate::json_file::{Document, JsonFileError};
use crate::{MAX_ANGLE_ERROR_HARMONICS, SensorModel};

/// The sensor parameters a study draws, in the order they are drawn and written.
pub(super) const SENSOR_PARAMETERS: [&str; 7] = [
    "amplitude",
    "offset_cos",
    "offset_sin",
    "amplitude_imbalance",
    "quadrature_error_rad",
    "third_harmonic",
    "noise_std",
];

/// One sensor parameter: a value, or a distribution it is drawn from per sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Spread {
    /// The same value for every sensor.
    Fixed(f64),
    /// Normal, of mean and standard deviation.
    Normal(f64, f64),
    /// Uniform over `[low, high)`.
    Uniform(f64, f64),
}

impl Spread {
    /// One draw (the generator advances for every kind, so that a parameter's draws do not
    /// depend on whether another one is spread).
    pub(super) fn draw(self, rng: &mut impl Rng) -> f64 {
        let unit: f64 = rng.random();
        let gaussian: f64 = Normal::new(0.0, 1.0).map_or(0.0, |n| n.sample(rng));
        match self {
            Spread::Fixed(value) => value,
            Spread::Normal(mean, std) => mean + std * gaussian,
            Spread::Uniform(low, high) => low + (high - low) * unit,
        }
    }
}

/// A parameter's value or distribution: a number, `{"normal": {"mean", "std"}}` or
/// `{"uniform": {"low", "high"}}`.
fn spread(doc: &Document<'_>, field: &str, default: f64) -> Result<Spread, JsonFileError> {
    let Some(value) = doc.object.get(field) else {
        return Ok(Spread::Fixed(default));
    };
    if let Some(v) = value.as_f64() {
        return finite(doc, field, v).map(Spread::Fixed);
    }
    let expected = "a number, {\"normal\": {\"mean\": M, \"std\": S}} or {\"uniform\": {\"low\": L, \"high\": H}}";
    let distribution = doc
        .section(field)?
        .ok_or_else(|| doc.error(field, format!("must be {expected}, got {value}")))?;
    let kind = distribution
        .object
        .keys()
        .next()
        .cloned()
        .unwrap_or_default();
    distribution.refuse_unknown(&["normal", "uniform"])?;
    if distribution.object.len() != 1 {
        return Err(doc.error(field, format!("must be {expected}")));
    }
    let inner = distribution
        .section(&kind)?
        .ok_or_else(|| distribution.error(&kind, "must be an object"))?;
    if kind == "normal" {
        inner.refuse_unknown(&["mean", "std"])?;
        let (mean, std) = (inner.number("mean")?, inner.number("std")?);
        finite(&inner, "mean", mean)?;
        if !(std >= 0.0 && std.is_finite()) {
            return Err(inner.error(
                "std",
                format!("must be a finite number of at least 0, got {std}"),
            ));
        }
        Ok(Spread::Normal(mean, std))
    } else {
        inner.refuse_unknown(&["low", "high"])?;
        let (low, high) = (inner.number("low")?, inner.number("high")?);
        if !(low.is_finite() && high.is_finite() && low <= high) {
            return Err(inner.error(
                "high",
                format!("expected finite low <= high, got {low} to {high}"),
            ));
        }
        Ok(Spread::Uniform(low, high))
    }
}

fn finite(doc: &Document<'_>, field: &str, v: f64) -> Result<f64, JsonFileError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(doc.error(field, format!("must be finite, got {v}")))
    }
}

/// The most harmonics of the angle error a sensor holds.
const HARMONICS: usize = MAX_ANGLE_ERROR_HARMONICS;

/// The spreads of a study's sensors: the `sensor` table.
#[derive(Debug, Clone)]
pub(super) struct SensorSpread {
    /// The spread of each of [`SENSOR_PARAMETERS`].
    parameters: [Spread; SENSOR_PARAMETERS.len()],
    /// The angle error's harmonics: order, amplitude (rad) and phase (rad).
    harmonics: Vec<(u32, Spread, Spread)>,
    /// The ADC's resolution (0: none) and full scale, the same for every sensor.
    pub(super) adc_bits: u32,
    pub(super) adc_full_scale: f64,
}

/// One sensor's drawn values.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct DrawnSensor {
    /// The values of [`SENSOR_PARAMETERS`].
    pub(super) parameters: [f64; SENSOR_PARAMETERS.len()],
    /// The angle error's harmonics: order, amplitude (rad), phase (rad).
    pub(super) harmonics: Vec<(u32, f64, f64)>,
}

impl SensorSpread {
    /// One sensor's values, drawn in a fixed order: the parameters, then each harmonic's
    /// amplitude and phase.
    pub(super) fn draw(&self, rng: &mut impl Rng) -> DrawnSensor {
        DrawnSensor {
            parameters: self.parameters.map(|p| p.draw(rng)),
            harmonics: self
                .harmonics
                .iter()
                .map(|&(k, a, p)| (k, a.draw(rng), p.draw(rng)))
                .collect(),
        }
    }

    /// The sensor model of the drawn values `d`.
    pub(super) fn model(&self, d: &DrawnSensor) -> SensorModel {
        let [
            amplitude,
            offset_cos,
            offset_sin,
            amplitude_imbalance,
            quadrature_error_rad,
            third_harmonic,
            noise_std,
        ] = d.parameters;
        let mut angle_error_harmonics = [(0, 0.0, 0.0); HARMONICS];
        for (slot, &h) in angle_error_harmonics.iter_mut().zip(&d.harmonics) {
            *slot = h;
        }
        SensorModel {
            amplitude,
            offset_cos,
            offset_sin,
            amplitude_imbalance,
            quadrature_error_rad,
            third_harmonic,
            angle_error_harmonics,
            noise_std,
            adc_bits: self.adc_bits,
            adc_full_scale: self.adc_full_scale,
        }
    }

    /// The `sensor` table: the spread of each of [`SENSOR_PARAMETERS`] (missing: the ideal
    /// sensor's value), the angle error's harmonics (`angle_error_harmonics`, a list of
    /// `{"order": K, "amplitude_rad": SPREAD, "phase_rad": SPREAD}`, orders distinct, 1 to
    /// 32) and the ADC's `adc_bits` and `adc_full_scale`.
    pub(super) fn parse(doc: &Document<'_>) -> Result<Self, JsonFileError> {
        let mut known = SENSOR_PARAMETERS.to_vec();
        known.extend(["angle_error_harmonics", "adc_bits", "adc_full_scale"]);
        doc.refuse_unknown(&known)?;
        let ideal = SensorModel::default();
        let defaults = [ideal.amplitude, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut parameters = [Spread::Fixed(0.0); SENSOR_PARAMETERS.len()];
        for ((slot, name), default) in parameters.iter_mut().zip(SENSOR_PARAMETERS).zip(defaults) {
            *slot = spread(doc, name, default)?;
        }
        let harmonics = harmonics(doc)?;
        let adc_bits = match doc.object.get("adc_bits") {
            None => 0,
            Some(v) => v.as_u64().filter(|&b| b <= 32).ok_or_else(|| {
                doc.error(
                    "adc_bits",
                    format!("must be a whole number from 0 (no ADC) to 32, got {v}"),
                )
            })? as u32,
        };
        let adc_full_scale = optional(doc, "adc_full_scale", ideal.adc_full_scale)?;
        Ok(Self {
            parameters,
            harmonics,
            adc_bits,
            adc_full_scale,
        })
    }
}

/// The list `angle_error_harmonics` (none when missing).
fn harmonics(doc: &Document<'_>) -> Result<Vec<(u32, Spread, Spread)>, JsonFileError> {
    let field = "angle_error_harmonics";
    let items = match doc.object.get(field) {
        None => return Ok(Vec::new()),
        Some(Value::Array(items)) if items.len() <= HARMONICS => items,
        Some(_) => {
            return Err(doc.error(
                field,
                format!("must be a list of at most {HARMONICS} harmonics"),
            ));
        }
    };
    let mut out: Vec<(u32, Spread, Spread)> = Vec::new();
    for (k, item) in items.iter().enumerate() {
        let at = format!("{field}[{k}]");
        let Value::Object(object) = item else {
            return Err(doc.error(
                &at,
                "must be {\"order\": K, \"amplitude_rad\": ..., \"phase_rad\": ...}",
            ));
        };
        let entry = Document {
            object: object.clone(),
            file: doc.file,
            prefix: format!("{}{at}.", doc.prefix),
        };
        entry.refuse_unknown(&["order", "amplitude_rad", "phase_rad"])?;
        let order = entry
            .object
            .get("order")
            .and_then(Value::as_u64)
            .filter(|o| (1..=32).contains(o) && !out.iter().any(|h| u64::from(h.0) == *o))
            .ok_or_else(|| {
                entry.error(
                    "order",
                    "must be a whole number from 1 to 32, each order once",
                )
            })?;
        out.push((
            order as u32,
            spread(&entry, "amplitude_rad", 0.0)?,
            spread(&entry, "phase_rad", 0.0)?,
        ));
    }
    Ok(out)
}
