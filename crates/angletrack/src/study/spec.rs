//! Reading a study's specification: its sensors' parameters (each a value or a
//! distribution), its motion profiles and its setups (tracker files), every field checked
//! and every error naming the field as written.

use std::path::Path;

use serde_json::Value;

use super::sensor::SensorSpread;
use super::{STUDY_FORMAT, STUDY_VERSION};
use crate::json_file::{Document, JsonFileError};
use crate::tracker_file::{AdcRange, Correction, Input, NumberType, TrackerFile};
use crate::{Motion, MotionProfile};

/// The top level's fields.
const FIELDS: [&str; 10] = [
    "format",
    "version",
    "seed",
    "sensors",
    "sample_period_s",
    "skip_s",
    "lock_tolerance_rad",
    "sensor",
    "profiles",
    "setups",
];

/// The most sensors of one study (10^9: run ids stay exact in every table's integers).
const MAX_SENSORS: i64 = 1_000_000_000;

/// A study's specification, checked.
#[derive(Debug, Clone)]
pub(super) struct Spec {
    pub(super) seed: u64,
    pub(super) sensors: u64,
    pub(super) sample_period_s: f64,
    pub(super) skip_s: f64,
    pub(super) lock_tolerance_rad: f64,
    pub(super) sensor: SensorSpread,
    pub(super) profiles: Vec<(String, MotionProfile)>,
    pub(super) setups: Vec<(String, TrackerFile)>,
}

/// `text` (a study document, named `file` in errors) with each setup's `tracker` given as a
/// path replaced by that file's document, read relative to `base_dir`: what every run needs,
/// in one text that runs anywhere.
pub(super) fn resolve(text: &str, file: &str, base_dir: &Path) -> Result<String, JsonFileError> {
    let mut value: Value = serde_json::from_str(text)
        .map_err(|e| JsonFileError::new(file, None, format!("not JSON ({e})")))?;
    if let Some(Value::Object(setups)) = value.get_mut("setups") {
        for (name, setup) in setups.iter_mut() {
            let Some(Value::String(path)) = setup.get("tracker") else {
                continue;
            };
            let field = format!("setups.{name}.tracker");
            let path = base_dir.join(path.as_str());
            let tracker = std::fs::read_to_string(&path).map_err(|e| {
                JsonFileError::new(file, Some(&field), format!("{}: {e}", path.display()))
            })?;
            let document: Value = serde_json::from_str(&tracker).map_err(|e| {
                JsonFileError::new(&path.display().to_string(), None, format!("not JSON ({e})"))
            })?;
            // Checked here, so that a bad tracker file is named by its path, not the spec.
            TrackerFile::from_json(&tracker, &path.display().to_string())?;
            setup["tracker"] = document;
        }
    }
    let resolved = value.to_string();
    Spec::parse(&resolved, file)?;
    Ok(resolved)
}

impl Spec {
    /// The specification of `text` (named `file` in errors), its trackers inline.
    pub(super) fn parse(text: &str, file: &str) -> Result<Self, JsonFileError> {
        let doc = Document::parse(text, file)?;
        doc.refuse_unknown(&FIELDS)?;
        doc.check_format(STUDY_FORMAT)?;
        doc.check_version(STUDY_VERSION)?;
        let seed = doc
            .object
            .get("seed")
            .and_then(Value::as_u64)
            .ok_or_else(|| doc.error("seed", "must be a whole number of at least 0"))?;
        let sensors = doc
            .object
            .get("sensors")
            .and_then(Value::as_i64)
            .filter(|n| (1..=MAX_SENSORS).contains(n))
            .ok_or_else(|| {
                doc.error(
                    "sensors",
                    format!("must be a whole number from 1 to {MAX_SENSORS}"),
                )
            })? as u64;
        let sample_period_s = doc.number("sample_period_s")?;
        if !(sample_period_s > 0.0 && sample_period_s.is_finite()) {
            return Err(doc.error("sample_period_s", "must be a positive number of seconds"));
        }
        let skip_s = optional(&doc, "skip_s", 0.0)?;
        if !(skip_s >= 0.0 && skip_s.is_finite()) {
            return Err(doc.error("skip_s", "must be a number of seconds of at least 0"));
        }
        let lock_tolerance_rad = optional(&doc, "lock_tolerance_rad", 0.01)?;
        if !(lock_tolerance_rad > 0.0 && lock_tolerance_rad.is_finite()) {
            return Err(doc.error("lock_tolerance_rad", "must be a positive angle (rad)"));
        }
        let sensor = doc
            .section("sensor")?
            .ok_or_else(|| doc.error("sensor", "missing"))?;
        let sensor = SensorSpread::parse(&sensor)?;
        let adc_bits = sensor.adc_bits;
        let profiles = named(&doc, "profiles", |d, _| profile(d))?;
        let setups = named(&doc, "setups", |d, name| {
            setup(d, name, sample_period_s, adc_bits)
        })?;
        Ok(Spec {
            seed,
            sensors,
            sample_period_s,
            skip_s,
            lock_tolerance_rad,
            sensor,
            profiles,
            setups,
        })
    }

    /// The number of runs: every sensor through every profile and every setup.
    pub(super) fn runs(&self) -> u64 {
        self.sensors * self.profiles.len() as u64 * self.setups.len() as u64
    }
}

/// The number under `field`, `default` when missing.
pub(super) fn optional(
    doc: &Document<'_>,
    field: &str,
    default: f64,
) -> Result<f64, JsonFileError> {
    match doc.object.get(field) {
        None => Ok(default),
        Some(_) => doc.number(field),
    }
}

/// The entries of the table `field` (name to object), each read by `read`, in the order
/// written; at least one.
fn named<T>(
    doc: &Document<'_>,
    field: &str,
    read: impl Fn(&Document<'_>, &str) -> Result<T, JsonFileError>,
) -> Result<Vec<(String, T)>, JsonFileError> {
    let section = doc
        .section(field)?
        .ok_or_else(|| doc.error(field, "missing"))?;
    if section.object.is_empty() {
        return Err(doc.error(field, "must name at least one"));
    }
    let names: Vec<String> = section.object.keys().cloned().collect();
    names
        .into_iter()
        .map(|name| {
            let entry = section
                .section(&name)?
                .ok_or_else(|| section.error(&name, "must be an object"))?;
            Ok((name.clone(), read(&entry, &name)?))
        })
        .collect()
}

/// The fields of each kind of motion segment (the crate's [`Motion`]'s, as written).
const SEGMENTS: [(&str, &[&str]); 7] = [
    ("constant_speed", &["speed_rad_s", "duration_s"]),
    (
        "constant_acceleration",
        &["acceleration_rad_s2", "duration_s"],
    ),
    ("step", &["step_rad", "duration_s"]),
    (
        "trapezoidal",
        &["distance_rad", "max_speed_rad_s", "max_acceleration_rad_s2"],
    ),
    (
        "s_curve",
        &[
            "distance_rad",
            "max_speed_rad_s",
            "max_acceleration_rad_s2",
            "max_jerk_rad_s3",
        ],
    ),
    (
        "speed_ripple",
        &["ripple_rad_s", "frequency_hz", "duration_s"],
    ),
    ("reversal", &["acceleration_rad_s2"]),
];

/// A motion profile: `initial_angle_rad`, `initial_speed_rad_s` and `segments`, a list of
/// one-key objects `{"constant_speed": {"speed_rad_s": ..., "duration_s": ...}}`.
fn profile(doc: &Document<'_>) -> Result<MotionProfile, JsonFileError> {
    doc.refuse_unknown(&["initial_angle_rad", "initial_speed_rad_s", "segments"])?;
    let mut profile = MotionProfile::new(
        optional(doc, "initial_angle_rad", 0.0)?,
        optional(doc, "initial_speed_rad_s", 0.0)?,
    );
    let Some(Value::Array(segments)) = doc.object.get("segments") else {
        return Err(doc.error("segments", "must be a list of segments, such as [{\"constant_speed\": {\"speed_rad_s\": 300.0, \"duration_s\": 0.5}}]"));
    };
    let kinds: Vec<&str> = SEGMENTS.iter().map(|(k, _)| *k).collect();
    for (k, segment) in segments.iter().enumerate() {
        let field = format!("segments[{k}]");
        let one = match segment {
            Value::Object(o) if o.len() == 1 => o,
            _ => {
                return Err(doc.error(
                    &field,
                    format!("must be one of {{{}: {{...}}}}", kinds.join(", ")),
                ));
            }
        };
        let (kind, values) = one.iter().next().expect("one entry");
        let holder = Document {
            object: one.clone(),
            file: doc.file,
            prefix: format!("{}{field}.", doc.prefix),
        };
        let Some(&(_, names)) = SEGMENTS.iter().find(|(k, _)| k == kind) else {
            return Err(holder.error(
                kind,
                format!("unknown segment (expected one of: {})", kinds.join(", ")),
            ));
        };
        let Value::Object(values) = values else {
            return Err(holder.error(kind, "must be an object"));
        };
        let fields = Document {
            object: values.clone(),
            file: doc.file,
            prefix: format!("{}{field}.{kind}.", doc.prefix),
        };
        fields.refuse_unknown(names)?;
        let mut v = [0.0; 4];
        for (slot, name) in v.iter_mut().zip(names) {
            *slot = fields.number(name)?;
        }
        profile = profile.then(match kind.as_str() {
            "constant_speed" => Motion::ConstantSpeed {
                speed_rad_s: v[0],
                duration_s: v[1],
            },
            "constant_acceleration" => Motion::ConstantAcceleration {
                acceleration_rad_s2: v[0],
                duration_s: v[1],
            },
            "step" => Motion::Step {
                step_rad: v[0],
                duration_s: v[1],
            },
            "trapezoidal" => Motion::Trapezoidal {
                distance_rad: v[0],
                max_speed_rad_s: v[1],
                max_acceleration_rad_s2: v[2],
            },
            "s_curve" => Motion::SCurve {
                distance_rad: v[0],
                max_speed_rad_s: v[1],
                max_acceleration_rad_s2: v[2],
                max_jerk_rad_s3: v[3],
            },
            "speed_ripple" => Motion::SpeedRipple {
                ripple_rad_s: v[0],
                frequency_hz: v[1],
                duration_s: v[2],
            },
            _ => Motion::Reversal {
                acceleration_rad_s2: v[0],
            },
        });
    }
    Ok(profile)
}

/// A setup: `{"tracker": DOCUMENT}` (a path was replaced by its document by [`resolve`]);
/// its samples are the simulated sensor's at the study's sample period, so its gains must
/// be of that period, and its input units (f32, f64) or the sensor's ADC codes (fixed).
fn setup(
    doc: &Document<'_>,
    name: &str,
    sample_period_s: f64,
    adc_bits: u32,
) -> Result<TrackerFile, JsonFileError> {
    doc.refuse_unknown(&["tracker"])?;
    let text = match doc.object.get("tracker") {
        Some(v @ Value::Object(_)) => v.to_string(),
        _ => return Err(doc.error("tracker", "must be a tracker file's path or document")),
    };
    let field = format!("setups.{name}.tracker");
    // Named as the spec's field: `study.toml: setups.f32.tracker.calibration.max_offset`.
    let tracker = TrackerFile::from_json(&text, doc.file).map_err(|e| {
        let at = e
            .field
            .as_ref()
            .map_or(field.clone(), |f| format!("{field}.{f}"));
        JsonFileError::new(doc.file, Some(&at), e.reason)
    })?;
    let refuse = |what: &str, why: &str| {
        Err(JsonFileError::new(
            doc.file,
            Some(&format!("{field}.{what}")),
            why,
        ))
    };
    let period = tracker.gains.sample_period_s;
    if (period / sample_period_s - 1.0).abs() > 1e-9 {
        return Err(JsonFileError::new(
            doc.file,
            Some(&format!("{field}.sample_period_s")),
            format!(
                "{period} s, but the study samples every {sample_period_s} s (sample_period_s): design the gains for the study's rate"
            ),
        ));
    }
    if tracker.number_type == NumberType::Fixed {
        // The fixed-point chain takes the sensor's ADC codes: the same ADC on both sides.
        let bits_ok = matches!(tracker.input, Input::Bits { bits, signed } if bits == adc_bits && bits <= if signed { 16 } else { 15 });
        if !bits_ok {
            return refuse(
                "input",
                &format!(
                    "number_type \"fixed\" tracks the sensor's ADC codes as int16 counts: give input.bits \
                     the study's sensor.adc_bits ({adc_bits}; 1 to 15 unsigned, 16 signed) and input.signed"
                ),
            );
        }
        if tracker.fault_thresholds.is_some() {
            return refuse(
                "fault_thresholds",
                "the fixed-point monitor is scaled to the signal's counts: leave it null",
            );
        }
    } else if tracker.input != Input::Units {
        return refuse(
            "input",
            "a study's simulated sensor gives f32 and f64 trackers samples in units: give input {\"kind\": \"units\"}",
        );
    }
    if tracker.adc_range == AdcRange::FullScale && tracker.number_type != NumberType::Fixed {
        return refuse(
            "adc_range",
            "\"full_scale\" is for counts: give \"measured\" or \"stated\" in units",
        );
    }
    if matches!(tracker.correction, Correction::Table(_)) {
        return refuse(
            "correction",
            "studies apply a correction of harmonics (\"kind\": \"harmonics\"), not a table yet",
        );
    }
    Ok(tracker)
}
