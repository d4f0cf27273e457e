//! Tolerance studies: many simulated sensors, their parameters drawn from stated spreads,
//! each through every motion profile and every setup (a tracker file), one row of results
//! per run. A run is computed from the specification and its run id alone (the seeds are
//! derived from the specification's seed and the run's sensor and profile), so the results
//! do not depend on how many workers ran them or in which order.
//!
//! The specification is one JSON document (`docs/guide/studies.md` gives its schema):
//!
//! ```
//! use angletrack::study::{Study, StudyCell};
//! let spec = r#"{"format": "angletrack-study", "version": 1, "seed": 7, "sensors": 2,
//!   "sample_period_s": 5e-5, "skip_s": 0.02,
//!   "sensor": {"offset_cos": {"normal": {"mean": 0.0, "std": 0.01}}, "noise_std": 0.001},
//!   "profiles": {"cruise": {"initial_speed_rad_s": 300.0,
//!                "segments": [{"constant_speed": {"speed_rad_s": 300.0, "duration_s": 0.05}}]}},
//!   "setups": {"f64": {"tracker": {"format": "angletrack-tracker", "version": 1,
//!              "sample_period_s": 5e-5, "gains": [0.0487706, 0.0012192, 1.52392e-5]}}}}"#;
//! let study = Study::from_json(spec, "study.json", std::path::Path::new("."))?;
//! assert_eq!(study.runs(), 2);
//! let row = study.run(1);
//! assert_eq!(row.error, None);
//! assert!(row.rms_error_rad < 0.02);
//! assert_eq!(study.run(1).columns()[..4], row.columns()[..4]); // the same run, the same row
//! assert_eq!(row.columns()[0], ("run".to_string(), StudyCell::Integer(1)));
//! # Ok::<(), angletrack::JsonFileError>(())
//! ```

mod row;
mod run;
mod sensor;
mod spec;

use std::path::Path;

use crate::json_file::JsonFileError;

pub use row::{StudyCell, StudyRow};

/// The `format` of a study's specification.
pub const STUDY_FORMAT: &str = "angletrack-study";
/// The `version` of a specification read.
pub const STUDY_VERSION: u64 = 1;

/// A study's specification, checked, with its tracker files read: what every run needs.
#[derive(Debug, Clone)]
pub struct Study {
    spec: spec::Spec,
    resolved: String,
}

impl Study {
    /// The study of the JSON `text` (named `file` in errors), its setups' tracker files given
    /// as paths read relative to `base_dir` and checked. Every error names the file and the
    /// field (`study.json: sensor.offset_cos.normal.std: must be ...`).
    pub fn from_json(text: &str, file: &str, base_dir: &Path) -> Result<Self, JsonFileError> {
        let resolved = spec::resolve(text, file, base_dir)?;
        Ok(Self {
            spec: spec::Spec::parse(&resolved, file)?,
            resolved,
        })
    }

    /// The specification as one JSON text with its tracker files inline: what a worker
    /// elsewhere (without the files) reads with [`Study::from_json`].
    pub fn resolved_json(&self) -> &str {
        &self.resolved
    }

    /// The number of runs: sensors x profiles x setups. Run `r` is sensor `r / (P S)`,
    /// profile `(r / S) mod P` and setup `r mod S` (profiles and setups in the order of
    /// their names).
    pub fn runs(&self) -> u64 {
        self.spec.runs()
    }

    /// The row of run `run` (0 to [`Study::runs`] - 1): a run that cannot be computed (a
    /// drawn parameter out of the sensor model's range) is a row with its error.
    pub fn run(&self, run: u64) -> StudyRow {
        run::run(&self.spec, run)
    }
}

#[cfg(test)]
mod tests;
