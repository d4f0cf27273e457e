//! Reading a tracker file: each section parsed, its unknown fields refused, and every value
//! checked by the core's constructor of it, the error naming the field as written.

use angletrack_core::{
    AdcScaling, AngleCorrection, AngleCorrectionTable, CalibrationSettings, ConfigError,
    DriveOutputs, FaultThresholds, Gains, MAX_CORRECTION_ORDER, Order, Parameter,
    SensorCalibration, SupportedOrder, WindingCheck,
};
use serde_json::Value;

use super::{
    AdcRange, Calibration, Correction, Input, NumberType, SinCosKind, TRACKER_FILE_FORMAT,
    TRACKER_FILE_VERSION, TrackerFile,
};
use crate::calibration::file::SENSOR_FIELDS;
use crate::export::GainsFile;
use crate::json_file::{Document, JsonFileError};

/// The top level's fields.
const FIELDS: [&str; 15] = [
    "format",
    "version",
    "sample_period_s",
    "gains",
    "design",
    "number_type",
    "sin_cos",
    "input",
    "adc_range",
    "winding_check",
    "fault_thresholds",
    "calibration",
    "correction",
    "pole_pairs",
    "predicted_error_rms_rad",
];

/// The length of the table a `"table"` correction's curve is checked as (the fixed-point
/// chain's, [`angletrack_core::TRACKER_TABLE_LENGTH`]).
const TABLE_LENGTH: usize = angletrack_core::TRACKER_TABLE_LENGTH;

impl Document<'_> {
    /// The core's refusal `e` of a value of this section: the field its parameter names,
    /// else `field`.
    fn refused(&self, field: &str, e: ConfigError, fields: &[&str]) -> JsonFileError {
        let name = e.parameter().name();
        let at = if fields.contains(&name) { name } else { field };
        self.error(at, e.to_string())
    }

    /// The `kind` (or `rule`) of a section, one of `kinds`.
    fn kind<'k>(&self, key: &str, kinds: &[&'k str]) -> Result<&'k str, JsonFileError> {
        let given = self.string(key)?;
        kinds.iter().find(|&&k| k == given).copied().ok_or_else(|| {
            let names: Vec<String> = kinds.iter().map(|k| format!("{k:?}")).collect();
            let expected = match names.split_last() {
                Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
                _ => names.concat(),
            };
            self.error(key, format!("expected {expected}, got {given:?}"))
        })
    }

    /// The whole number under `field`, within `range` (refused: missing, other).
    fn integer(&self, field: &str, low: i64, high: i64) -> Result<i64, JsonFileError> {
        match self.object.get(field) {
            None => Err(self.error(field, "missing")),
            Some(v) => v
                .as_i64()
                .filter(|i| (low..=high).contains(i))
                .ok_or_else(|| {
                    self.error(
                        field,
                        format!("must be a whole number from {low} to {high}, got {v}"),
                    )
                }),
        }
    }

    fn boolean(&self, field: &str, default: bool) -> Result<bool, JsonFileError> {
        match self.object.get(field) {
            None => Ok(default),
            Some(Value::Bool(b)) => Ok(*b),
            Some(v) => Err(self.error(field, format!("must be true or false, got {v}"))),
        }
    }

    /// The number under `field`, `None` when it is `null`, `default` when missing.
    fn maybe(&self, field: &str, default: Option<f64>) -> Result<Option<f64>, JsonFileError> {
        match self.object.get(field) {
            None => Ok(default),
            Some(Value::Null) => Ok(None),
            Some(_) => self.number(field).map(Some),
        }
    }

    /// `predicted_error_rms_rad`: a non-negative number, or missing or `null`.
    fn predicted_error(&self) -> Result<Option<f64>, JsonFileError> {
        let field = "predicted_error_rms_rad";
        match self.maybe(field, None)? {
            Some(v) if !(v >= 0.0) => Err(self.error(field, "a number of at least 0 (rad)")),
            value => Ok(value),
        }
    }

    /// The list of numbers under `field`.
    fn list(&self, field: &str) -> Result<Vec<f64>, JsonFileError> {
        match self.object.get(field) {
            Some(Value::Array(items)) => items
                .iter()
                .map(|v| {
                    v.as_f64()
                        .ok_or_else(|| self.error(field, format!("must be numbers, got {v}")))
                })
                .collect(),
            Some(v) => Err(self.error(field, format!("must be a list of numbers, got {v}"))),
            None => Err(self.error(field, "missing")),
        }
    }

    /// A sensor calibration: an object of its five fields.
    fn sensor_object(&self, field: &str) -> Result<SensorCalibration<f64>, JsonFileError> {
        let doc = self
            .section(field)?
            .ok_or_else(|| self.error(field, "missing"))?;
        doc.refuse_unknown(&SENSOR_FIELDS)?;
        let mut v = [0.0; 5];
        for (value, name) in v.iter_mut().zip(SENSOR_FIELDS) {
            *value = doc.number(name)?;
        }
        SensorCalibration::new(v[0], v[1], v[2], v[3], v[4])
            .map_err(|e| doc.refused(field, e, &SENSOR_FIELDS))
    }

    fn input(&self) -> Result<Input, JsonFileError> {
        let Some(doc) = self.section("input")? else {
            return Ok(Input::Units);
        };
        if doc.kind("kind", &["units", "counts"])? == "units" {
            doc.refuse_unknown(&["kind"])?;
            return Ok(Input::Units);
        }
        if doc.object.contains_key("bits") {
            doc.refuse_unknown(&["kind", "bits", "signed"])?;
            let bits = doc.integer("bits", 2, 32)? as u32;
            let signed = match doc.object.get("signed") {
                Some(Value::Bool(b)) => *b,
                _ => return Err(doc.error("signed", "must be true or false")),
            };
            let checked = if signed {
                AdcScaling::<f64>::twos_complement(bits).map(|_| ())
            } else {
                AdcScaling::<f64>::offset_binary(bits).map(|_| ())
            };
            checked.map_err(|e| doc.error("bits", e.to_string()))?;
            return Ok(Input::Bits { bits, signed });
        }
        if !doc.object.contains_key("mid_scale") && !doc.object.contains_key("counts_per_unit") {
            doc.refuse_unknown(&["kind", "bits", "mid_scale"])?;
            return Ok(Input::Counts);
        }
        doc.refuse_unknown(&["kind", "mid_scale", "counts_per_unit"])?;
        let mid_scale = doc.integer("mid_scale", i32::MIN.into(), i32::MAX.into())? as i32;
        let counts_per_unit = doc.number("counts_per_unit")?;
        AdcScaling::<f64>::new(mid_scale, counts_per_unit)
            .map_err(|e| doc.refused("mid_scale", e, &["counts_per_unit"]))?;
        Ok(Input::Scaled {
            mid_scale,
            counts_per_unit,
        })
    }

    fn adc_range(&self, input: &Input) -> Result<AdcRange, JsonFileError> {
        let Some(doc) = self.section("adc_range")? else {
            return Ok(AdcRange::Measured);
        };
        match doc.kind("rule", &["measured", "full_scale", "stated"])? {
            "measured" => doc.refuse_unknown(&["rule"]).map(|()| AdcRange::Measured),
            "full_scale" => {
                doc.refuse_unknown(&["rule"])?;
                match input {
                    Input::Bits { .. } => Ok(AdcRange::FullScale),
                    _ => Err(doc.error(
                        "rule",
                        "\"full_scale\" is the range of counts of stated bits: give input.bits and input.signed",
                    )),
                }
            }
            _ => {
                doc.refuse_unknown(&["rule", "min", "max"])?;
                let (min, max) = (doc.number("min")?, doc.number("max")?);
                if !(min.is_finite() && max.is_finite() && min < max) {
                    return Err(doc.error(
                        "max",
                        format!("expected finite min < max, got {min} to {max}"),
                    ));
                }
                Ok(AdcRange::Stated { min, max })
            }
        }
    }

    fn winding_amplitude(&self) -> Result<Option<f64>, JsonFileError> {
        let Some(doc) = self.section("winding_check")? else {
            return Ok(None);
        };
        doc.refuse_unknown(&["amplitude"])?;
        let amplitude = doc.number("amplitude")?;
        WindingCheck::new(amplitude).map_err(|e| doc.error("amplitude", e.to_string()))?;
        Ok(Some(amplitude))
    }

    /// The thresholds (each field missing: [`FaultThresholds::for_amplitude`]'s; `null`
    /// for `max_speed_rad_s` and `magnitude_tolerance`: `None`).
    fn thresholds(&self) -> Result<Option<FaultThresholds<f64>>, JsonFileError> {
        let Some(doc) = self.section("fault_thresholds")? else {
            return Ok(None);
        };
        doc.refuse_unknown(&THRESHOLD_FIELDS)?;
        let t = FaultThresholds::for_amplitude(doc.number("nominal_amplitude")?);
        let or = |field: &str, default: f64| -> Result<f64, JsonFileError> {
            Ok(doc.maybe(field, Some(default))?.unwrap_or(f64::NAN))
        };
        Ok(Some(
            t.with_max_input_amplitude(or("max_input_amplitude", t.max_input_amplitude)?)
                .with_loss_of_signal(or("loss_of_signal", t.loss_of_signal)?)
                .with_degradation_low(or("degradation_low", t.degradation_low)?)
                .with_degradation_high(or("degradation_high", t.degradation_high)?)
                .with_loss_of_tracking(or("loss_of_tracking", t.loss_of_tracking)?)
                .with_tracking_error(or("tracking_error", t.tracking_error)?)
                .with_max_speed(doc.maybe("max_speed_rad_s", t.max_speed)?)
                .with_filter_factor(or("filter_factor", t.filter_factor)?)
                .with_false_lock(or("false_lock", t.false_lock)?)
                .with_magnitude_tolerance(doc.maybe("magnitude_tolerance", t.magnitude_tolerance)?)
                .with_monitor(doc.boolean("monitor", t.monitor)?)
                .with_re_acquire(doc.boolean("re_acquire", t.re_acquire)?),
        ))
    }

    fn calibration(&self) -> Result<Calibration, JsonFileError> {
        let Some(doc) = self.section("calibration")? else {
            return Ok(Calibration::None);
        };
        match doc.kind("kind", &["none", "stored", "online"])? {
            "none" => doc.refuse_unknown(&["kind"]).map(|()| Calibration::None),
            "stored" => {
                doc.refuse_unknown(&["kind", "sensor"])?;
                Ok(Calibration::Stored(doc.sensor_object("sensor")?))
            }
            _ => {
                doc.refuse_unknown(&ONLINE_FIELDS)?;
                let initial = match doc.object.get("initial") {
                    None | Some(Value::Null) => None,
                    Some(_) => Some(doc.sensor_object("initial")?),
                };
                let mut settings = CalibrationSettings::default();
                settings.min_speed_rad_s = doc.maybe("min_speed_rad_s", None)?;
                for (field, slot) in [
                    ("max_offset", &mut settings.max_offset),
                    (
                        "max_amplitude_mismatch",
                        &mut settings.max_amplitude_mismatch,
                    ),
                    ("max_quadrature_rad", &mut settings.max_quadrature_rad),
                ] {
                    *slot = doc.maybe(field, Some(*slot))?.unwrap_or(f64::NAN);
                }
                Ok(Calibration::Online { initial, settings })
            }
        }
    }

    fn correction(&self) -> Result<Correction, JsonFileError> {
        let Some(doc) = self.section("correction")? else {
            return Ok(Correction::None);
        };
        match doc.kind("kind", &["none", "harmonics", "table"])? {
            "none" => doc.refuse_unknown(&["kind"]).map(|()| Correction::None),
            "harmonics" => {
                doc.refuse_unknown(&["kind", "cos", "sin"])?;
                let cos = doc.numbers::<MAX_CORRECTION_ORDER>("cos")?;
                let sin = doc.numbers::<MAX_CORRECTION_ORDER>("sin")?;
                AngleCorrection::new(cos, sin)
                    .map(Correction::Harmonics)
                    .map_err(|e| doc.error("cos", e.to_string()))
            }
            _ => {
                doc.refuse_unknown(&["kind", "errors_rad"])?;
                let errors = doc.list("errors_rad")?;
                AngleCorrectionTable::<f64, TABLE_LENGTH>::from_curve(&errors)
                    .map_err(|e| doc.error("errors_rad", e.to_string()))?;
                Ok(Correction::Table(errors))
            }
        }
    }

    fn pole_pairs(&self) -> Result<Option<u32>, JsonFileError> {
        match self.object.get("pole_pairs") {
            None | Some(Value::Null) => Ok(None),
            Some(v) => {
                let refused = || {
                    self.error(
                        "pole_pairs",
                        format!("must be a whole number from 1 to 65536, got {v}"),
                    )
                };
                let p = v
                    .as_u64()
                    .and_then(|p| u32::try_from(p).ok())
                    .ok_or_else(refused)?;
                DriveOutputs::<f64>::new(p, 1, 0.0, 1.0).map_err(|_| refused())?;
                Ok(Some(p))
            }
        }
    }
}

/// The fault thresholds' fields (the core's names).
const THRESHOLD_FIELDS: [&str; 13] = [
    "nominal_amplitude",
    "max_input_amplitude",
    "loss_of_signal",
    "degradation_low",
    "degradation_high",
    "loss_of_tracking",
    "tracking_error",
    "max_speed_rad_s",
    "filter_factor",
    "false_lock",
    "magnitude_tolerance",
    "monitor",
    "re_acquire",
];

/// An online calibration's fields.
const ONLINE_FIELDS: [&str; 6] = [
    "kind",
    "initial",
    "min_speed_rad_s",
    "max_offset",
    "max_amplitude_mismatch",
    "max_quadrature_rad",
];

/// The core's checks of the gains, and of the thresholds and the calibration settings as the
/// gains take them: the refusal and the section whose field it names.
fn check_gains<const N: usize>(
    gains: [f64; N],
    sample_period_s: f64,
    thresholds: Option<FaultThresholds<f64>>,
    settings: Option<CalibrationSettings<f64>>,
) -> Result<(), (&'static str, ConfigError)>
where
    Order<N>: SupportedOrder,
{
    let g = Gains::<f64, N>::new(gains, sample_period_s).map_err(|e| ("", e))?;
    if let Some(t) = thresholds {
        g.with_fault_thresholds(t)
            .map_err(|e| ("fault_thresholds", e))?;
    }
    if let Some(s) = settings {
        g.with_calibration_settings(s)
            .map_err(|e| ("calibration", e))?;
    }
    Ok(())
}

impl TrackerFile {
    /// The setup of JSON `text` of [`TRACKER_FILE_FORMAT`]; `file` names it in errors.
    /// Refuses another format (naming it: a gains or calibration file), another version,
    /// an unknown field, and a value the core refuses.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        let doc = Document::parse(text, file)?;
        doc.check_format(TRACKER_FILE_FORMAT)?;
        doc.check_version(TRACKER_FILE_VERSION)?;
        doc.refuse_unknown(&FIELDS)?;
        let gains = doc.list("gains")?;
        let sample_period_s = doc.number("sample_period_s")?;
        let number_type = match doc.object.get("number_type") {
            None => NumberType::F64,
            Some(_) => match doc.kind("number_type", &["f32", "f64", "fixed"])? {
                "f32" => NumberType::F32,
                "f64" => NumberType::F64,
                _ => NumberType::Fixed,
            },
        };
        let sin_cos = match doc.object.get("sin_cos") {
            None | Some(Value::Null) => SinCosKind::Default,
            Some(_) => match doc.kind("sin_cos", &["fast", "exact"])? {
                "fast" => SinCosKind::Fast,
                _ => SinCosKind::Exact,
            },
        };
        let input = doc.input()?;
        let fault_thresholds = doc.thresholds()?;
        let calibration = doc.calibration()?;
        let settings = match calibration {
            Calibration::Online { settings, .. } => Some(settings),
            _ => None,
        };
        let checked = match *gains.as_slice() {
            [a, b] => check_gains([a, b], sample_period_s, fault_thresholds, settings),
            [a, b, c] => check_gains([a, b, c], sample_period_s, fault_thresholds, settings),
            _ => {
                return Err(doc.error(
                    "gains",
                    format!("2 or 3 (the observer's order), got {}", gains.len()),
                ));
            }
        };
        if let Err((section, e)) = checked {
            let field = match (section, e.parameter()) {
                ("", Parameter::SamplePeriod) => "sample_period_s".to_string(),
                ("", _) => "gains".to_string(),
                (section, p) => format!("{section}.{}", p.name()),
            };
            return Err(doc.error(&field, e.to_string()));
        }
        let tracker = TrackerFile {
            gains: GainsFile {
                gains,
                sample_period_s,
                design: doc.object.get("design").cloned(),
            },
            number_type,
            sin_cos,
            adc_range: doc.adc_range(&input)?,
            input,
            winding_amplitude: doc.winding_amplitude()?,
            fault_thresholds,
            calibration,
            correction: doc.correction()?,
            pole_pairs: doc.pole_pairs()?,
            predicted_error_rms_rad: doc.predicted_error()?,
        };
        if number_type == NumberType::Fixed {
            if tracker.input == Input::Units {
                return Err(doc.error(
                    "number_type",
                    "\"fixed\" runs on integer counts: input.kind must be \"counts\"",
                ));
            }
            if matches!(tracker.calibration, Calibration::Online { .. }) {
                return Err(doc.error(
                    "calibration.kind",
                    "\"online\" learns in float: with number_type \"fixed\" store the calibration (\"stored\")",
                ));
            }
        }
        Ok(tracker)
    }
}
