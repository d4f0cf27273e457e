//! A run's row of results, and the statistics of its angle error and faults gathered
//! sample by sample.

use angletrack_core::Faults;

use super::sensor::SENSOR_PARAMETERS;
use super::spec::Spec;
use crate::sim::wrap;

/// One value of a row.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyCell {
    /// A whole number.
    Integer(u64),
    /// A number (NaN: none, such as the time to lock of a run that never locked).
    Number(f64),
    /// A text (empty: none).
    Text(String),
}

/// The results of one run. The angle error is `truth - estimate` wrapped to [-pi, pi),
/// over the samples from the study's `skip_s` on (the start-up left out).
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRow {
    /// The run id.
    pub run: u64,
    /// The sensor's index (its parameters are the same in every profile and setup).
    pub sensor: u64,
    /// The motion profile's name.
    pub profile: String,
    /// The setup's name.
    pub setup: String,
    /// The setup's number type (`"f32"`, `"f64"`, `"fixed"`).
    pub number_type: &'static str,
    /// The sensor's parameters drawn, in the order of the specification's `sensor` fields
    /// (amplitude, offsets, imbalance, quadrature error (rad), 3rd harmonic, noise std).
    pub parameters: [f64; SENSOR_PARAMETERS.len()],
    /// The sensor's angle error harmonics drawn: order, amplitude (rad), phase (rad), in
    /// the order of the specification's `sensor.angle_error_harmonics`.
    pub angle_error_harmonics: Vec<(u32, f64, f64)>,
    /// Samples in the error statistics.
    pub samples: u64,
    /// RMS angle error (rad).
    pub rms_error_rad: f64,
    /// Largest angle error magnitude (rad).
    pub max_error_rad: f64,
    /// Mean angle error (rad).
    pub mean_error_rad: f64,
    /// Time (s) from which the angle error stays within the lock tolerance; NaN if it is
    /// outside at the end.
    pub time_to_lock_s: f64,
    /// Samples after the start-up whose estimate carries a fault.
    pub fault_samples: u64,
    /// The faults raised over the whole run, by name (`"none"`).
    pub faults: String,
    /// What the online calibration learned by the end (offset_c, offset_s, amplitude_c,
    /// amplitude_s, quadrature_rad); NaN for a setup without one.
    pub learned: [f64; 5],
    /// Seconds the run took (generation and tracking): the one value that differs between
    /// two computations of the same run.
    pub seconds: f64,
    /// Why the run has no results (empty row otherwise).
    pub error: Option<String>,
}

/// The names of [`StudyRow::learned`]'s columns.
const LEARNED: [&str; 5] = [
    "learned_offset_c",
    "learned_offset_s",
    "learned_amplitude_c",
    "learned_amplitude_s",
    "learned_quadrature_rad",
];

impl StudyRow {
    /// The row as named columns, in the order a table of runs holds them; each angle error
    /// harmonic of order K drawn gives `angle_error_hK_rad` and `angle_error_hK_phase_rad`
    /// after the other sensor parameters.
    pub fn columns(&self) -> Vec<(String, StudyCell)> {
        use StudyCell::{Integer, Number, Text};
        let mut out: Vec<(String, StudyCell)> = vec![
            ("run".into(), Integer(self.run)),
            ("sensor".into(), Integer(self.sensor)),
            ("profile".into(), Text(self.profile.clone())),
            ("setup".into(), Text(self.setup.clone())),
            ("number_type".into(), Text(self.number_type.to_string())),
        ];
        out.extend(
            SENSOR_PARAMETERS
                .iter()
                .zip(self.parameters)
                .map(|(n, v)| (n.to_string(), Number(v))),
        );
        for &(k, amplitude, phase) in &self.angle_error_harmonics {
            out.push((format!("angle_error_h{k}_rad"), Number(amplitude)));
            out.push((format!("angle_error_h{k}_phase_rad"), Number(phase)));
        }
        let results = [
            ("samples", Integer(self.samples)),
            ("rms_error_rad", Number(self.rms_error_rad)),
            ("max_error_rad", Number(self.max_error_rad)),
            ("mean_error_rad", Number(self.mean_error_rad)),
            ("time_to_lock_s", Number(self.time_to_lock_s)),
            ("fault_samples", Integer(self.fault_samples)),
            ("faults", Text(self.faults.clone())),
        ];
        out.extend(results.into_iter().map(|(n, v)| (n.to_string(), v)));
        out.extend(
            LEARNED
                .iter()
                .zip(self.learned)
                .map(|(n, v)| (n.to_string(), Number(v))),
        );
        out.push(("seconds".into(), Number(self.seconds)));
        out.push(("error".into(), Text(self.error.clone().unwrap_or_default())));
        out
    }
}

/// The statistics of a run's angle error and faults, sample by sample.
pub(super) struct Errors {
    /// The first sample in the statistics (after `skip_s`), the lock tolerance (rad).
    first: usize,
    tolerance: f64,
    sample_period_s: f64,
    samples: usize,
    sum: f64,
    squares: f64,
    largest: f64,
    faulty: u64,
    latched: Faults,
    last_outside: Option<usize>,
}

impl Errors {
    /// The statistics of a run of `samples` samples (every `spec.sample_period_s`).
    pub(super) fn new(spec: &Spec, samples: usize, row: &StudyRow) -> Result<Self, String> {
        let first = (spec.skip_s / spec.sample_period_s).ceil() as usize;
        if first >= samples {
            return Err(format!(
                "skip_s: {} s leaves no sample of profile {:?}",
                spec.skip_s, row.profile
            ));
        }
        Ok(Self {
            first,
            tolerance: spec.lock_tolerance_rad,
            sample_period_s: spec.sample_period_s,
            samples,
            sum: 0.0,
            squares: 0.0,
            largest: 0.0,
            faulty: 0,
            latched: Faults::NONE,
            last_outside: None,
        })
    }

    /// Sample `k`'s error `truth - estimate` (rad, wrapped here) and the faults its
    /// estimate carries.
    pub(super) fn add(&mut self, k: usize, error: f64, faults: Faults) {
        let error = wrap(error);
        self.latched = self.latched.union(faults);
        if !(error.abs() <= self.tolerance) {
            self.last_outside = Some(k);
        }
        if k >= self.first {
            self.sum += error;
            self.squares += error * error;
            self.largest = self.largest.max(error.abs());
            self.faulty += u64::from(!faults.is_empty());
        }
    }

    pub(super) fn write(self, row: &mut StudyRow) {
        let n = (self.samples - self.first) as f64;
        row.samples = (self.samples - self.first) as u64;
        row.rms_error_rad = (self.squares / n).sqrt();
        row.max_error_rad = self.largest;
        row.mean_error_rad = self.sum / n;
        row.time_to_lock_s = match self.last_outside {
            Some(k) if k + 1 == self.samples => f64::NAN,
            Some(k) => (k + 1) as f64 * self.sample_period_s,
            None => 0.0,
        };
        row.fault_samples = self.faulty;
        row.faults = self.latched.to_string();
    }
}
