//! A tracker file run on a host: the core's [`Tracker`] the file describes, built once by
//! the same rules as its firmware export ([`TrackerFile::rust_tracker`]) and fed a capture
//! in as many chunks as the caller likes. Every door that tracks with a tracker file (the
//! command line, Python, a study) holds one [`TrackerRun`], so that the same file gives the
//! same numbers through each.
//!
//! What a firmware states, the file states; what it leaves open is measured on the
//! capture's first samples, as `angletrack track` measures it: the fault thresholds (the
//! signal's amplitude, [`capture_fault_thresholds`](crate::capture_fault_thresholds)) and,
//! for counts whose mid-scale is not stated, the mid-scale
//! ([`capture_counts`](crate::capture_counts)'s rule: refused where the counts' signedness
//! is ambiguous).
//!
//! ```
//! use angletrack::export::GainsFile;
//! use angletrack::tracker_file::{CaptureHead, NumberType, TrackerFile, TrackerRun};
//! let gains = GainsFile { gains: vec![0.06, 0.001], sample_period_s: 1e-4, design: None };
//! let file = TrackerFile { number_type: NumberType::F32, ..TrackerFile::new(gains) };
//! let theta: Vec<f64> = (0..4000).map(|k| 1e-3 * k as f64).collect();
//! let (y_c, y_s): (Vec<f64>, Vec<f64>) = theta.iter().map(|t| (t.cos(), t.sin())).unzip();
//! let head = CaptureHead { y_c: &y_c, y_s: &y_s, counts: None };
//! let mut run = TrackerRun::new(&file, "t.json", &head)?;
//! let rows = run.track(&y_c, &y_s);
//! assert!((rows.position_rad[3999] - 3.999).abs() < 1e-3);
//! # Ok::<(), angletrack::JsonFileError>(())
//! ```

use angletrack_core::{
    Exact, Fast, FaultThresholds, Faults, Float, FrontEndFaults, Gains, ObserverState, Order,
    SensorCalibration, SinCos, SupportedOrder, Tracker, TrackerState,
};

mod fixed;
mod float;

use super::{Calibration, Input, NumberType, SinCosKind, TrackerFile};
use crate::json_file::JsonFileError;

/// The estimates of the samples a [`TrackerRun`] was fed, one entry a sample, in the
/// columns `angletrack track` writes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackedRows {
    /// The electrical angle (rad, in `[-pi, pi)`), exact in the observer's number type.
    pub angle_rad: Vec<f64>,
    /// The multi-turn position (rad): the whole turns counted and the angle.
    pub position_rad: Vec<f64>,
    /// The speed (rad/s).
    pub speed_rad_s: Vec<f64>,
    /// The acceleration (rad/s^2; 0 at order 2).
    pub acceleration_rad_s2: Vec<f64>,
    /// The phase detector's normalised output (about the sine of the angle error).
    pub phase_error: Vec<f64>,
    /// The observer's faults ([`Faults`] bits).
    pub faults: Vec<u8>,
    /// The front end's faults of the sample ([`FrontEndFaults`] bits).
    pub front_end_faults: Vec<u8>,
    /// The fixed-point observer's binary angle (2^32 a turn; empty for the floats).
    pub angle_binary: Vec<i32>,
}

/// One sample's estimates, as a row of [`TrackedRows`] holds them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackedSample {
    /// The electrical angle (rad, in `[-pi, pi)`), exact in the observer's number type.
    pub angle_rad: f64,
    /// The multi-turn position (rad).
    pub position_rad: f64,
    /// The speed (rad/s).
    pub speed_rad_s: f64,
    /// The acceleration (rad/s^2; 0 at order 2).
    pub acceleration_rad_s2: f64,
    /// The phase detector's normalised output.
    pub phase_error: f64,
    /// The observer's faults ([`Faults`] bits).
    pub faults: u8,
    /// The front end's faults of the sample ([`FrontEndFaults`] bits).
    pub front_end_faults: u8,
    /// The fixed-point observer's binary angle (2^32 a turn; `None` for the floats).
    pub angle_binary: Option<i32>,
}

impl TrackedRows {
    /// Room for `samples` rows, the binary angle's only for the fixed-point chain.
    fn with_capacity(samples: usize, fixed: bool) -> Self {
        Self {
            angle_rad: Vec::with_capacity(samples),
            position_rad: Vec::with_capacity(samples),
            speed_rad_s: Vec::with_capacity(samples),
            acceleration_rad_s2: Vec::with_capacity(samples),
            phase_error: Vec::with_capacity(samples),
            faults: Vec::with_capacity(samples),
            front_end_faults: Vec::with_capacity(samples),
            angle_binary: Vec::with_capacity(if fixed { samples } else { 0 }),
        }
    }

    fn push(&mut self, e: TrackedSample) {
        self.angle_rad.push(e.angle_rad);
        self.position_rad.push(e.position_rad);
        self.speed_rad_s.push(e.speed_rad_s);
        self.acceleration_rad_s2.push(e.acceleration_rad_s2);
        self.phase_error.push(e.phase_error);
        self.faults.push(e.faults);
        self.front_end_faults.push(e.front_end_faults);
        self.angle_binary.extend(e.angle_binary);
    }
}

/// What a [`TrackerRun`] measures a setting on that its file leaves open: the capture's
/// first samples and, for counts whose mid-scale is measured, what
/// [`capture_counts`](crate::capture_counts) decided on the whole capture.
#[derive(Debug, Clone, Copy)]
pub struct CaptureHead<'a> {
    /// The cosine channel's first samples (any number; the first 4096 are read).
    pub y_c: &'a [f64],
    /// The sine channel's first samples.
    pub y_s: &'a [f64],
    /// The counts' signedness and mid-scale (`None`: not decided; needed only for
    /// `input.kind` `"counts"` without bits or mid-scale).
    pub counts: Option<crate::CaptureCounts>,
}

/// What the online calibration of a [`TrackerRun`] has learned so far.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Learning {
    /// The calibration applied now.
    pub calibration: SensorCalibration<f64>,
    /// The turns learned.
    pub turns_learned: u32,
    /// Its status ([`status_name`](crate::status_name): `"finding-centre"`, `"centred"`,
    /// `"stalled"`).
    pub status: &'static str,
}

/// One chain of a [`TrackerRun`], whatever its number type.
trait Run: Sized {
    fn new(file: &TrackerFile, name: &str, head: &CaptureHead<'_>) -> Result<Self, JsonFileError>;
    fn track_each(&mut self, y_c: &[f64], y_s: &[f64], each: impl FnMut(TrackedSample));
    fn latched_faults(&self) -> (Faults, FrontEndFaults);
    fn learning(&self) -> Option<Learning>;
    /// The observer and the fixed-point input's shift, for the summary.
    fn describe(&self) -> String;
}

#[derive(Debug, Clone)]
struct FloatChain<T: Float, const N: usize, S: SinCos<T>> {
    tracker: Tracker<T, Gains<T, N, S>>,
    state: TrackerState<T, ObserverState<T, N>>,
    counts: bool,
    calibration: Calibration,
    description: String,
}

#[derive(Debug, Clone)]
struct Fixed<const N: usize>
where
    Order<N>: SupportedOrder,
{
    tracker: Tracker<i16, angletrack_core::FixedGains<N>>,
    state: TrackerState<i16, angletrack_core::FixedState<N>>,
    description: String,
}

/// The chains, one variant a number type, order and sin/cos, and the dispatch of a
/// [`Run`] method over them.
macro_rules! chains {
    ($($variant:ident: $ty:ty,)*) => {
        #[derive(Debug, Clone)]
        enum Chain { $($variant($ty),)* }

        macro_rules! each {
            ($chain:expr, $c:ident => $body:expr) => {
                match $chain { $(Chain::$variant($c) => $body,)* }
            };
        }
    };
}

chains! {
    F32Fast2: FloatChain<f32, 2, Fast>,
    F32Exact2: FloatChain<f32, 2, Exact>,
    F32Fast3: FloatChain<f32, 3, Fast>,
    F32Exact3: FloatChain<f32, 3, Exact>,
    F64Fast2: FloatChain<f64, 2, Fast>,
    F64Exact2: FloatChain<f64, 2, Exact>,
    F64Fast3: FloatChain<f64, 3, Fast>,
    F64Exact3: FloatChain<f64, 3, Exact>,
    Fixed2: Fixed<2>,
    Fixed3: Fixed<3>,
}

/// A tracker file's chain and its state, fed a capture chunk by chunk: the result does not
/// depend on where the chunks end.
#[derive(Debug, Clone)]
pub struct TrackerRun {
    chain: Chain,
}

fn refuse(file: &str, field: &str, why: impl Into<String>) -> JsonFileError {
    JsonFileError::new(file, Some(field), why)
}

impl TrackerRun {
    /// The chain of `file` (named `name` in errors), its open settings measured on `head`.
    /// Refuses, naming the file's field, what the core's constructors refuse and what the
    /// number type cannot run.
    pub fn new(
        file: &TrackerFile,
        name: &str,
        head: &CaptureHead<'_>,
    ) -> Result<Self, JsonFileError> {
        let exact = match file.sin_cos {
            SinCosKind::Default => file.number_type == NumberType::F64,
            kind => kind == SinCosKind::Exact,
        };
        if !matches!(file.gains.gains.len(), 2 | 3) {
            return Err(refuse(name, "gains", "2 or 3 gains (the observer's order)"));
        }
        let two = file.gains.gains.len() == 2;
        let chain = match (file.number_type, two, exact) {
            (NumberType::Fixed, true, _) => Chain::Fixed2(Run::new(file, name, head)?),
            (NumberType::Fixed, false, _) => Chain::Fixed3(Run::new(file, name, head)?),
            (NumberType::F32, true, false) => Chain::F32Fast2(Run::new(file, name, head)?),
            (NumberType::F32, true, true) => Chain::F32Exact2(Run::new(file, name, head)?),
            (NumberType::F32, false, false) => Chain::F32Fast3(Run::new(file, name, head)?),
            (NumberType::F32, false, true) => Chain::F32Exact3(Run::new(file, name, head)?),
            (NumberType::F64, true, false) => Chain::F64Fast2(Run::new(file, name, head)?),
            (NumberType::F64, true, true) => Chain::F64Exact2(Run::new(file, name, head)?),
            (NumberType::F64, false, false) => Chain::F64Fast3(Run::new(file, name, head)?),
            (NumberType::F64, false, true) => Chain::F64Exact3(Run::new(file, name, head)?),
        };
        Ok(Self { chain })
    }

    /// Feeds the samples `(y_c, y_s)` (the shorter's length; counts as whole numbers) and
    /// returns their estimates. Never fails: a sample the front end or the observer cannot
    /// use is flagged and coasted through.
    pub fn track(&mut self, y_c: &[f64], y_s: &[f64]) -> TrackedRows {
        let mut rows = TrackedRows::with_capacity(y_c.len().min(y_s.len()), self.is_fixed());
        self.track_each(y_c, y_s, |e| rows.push(e));
        rows
    }

    /// Feeds the samples `(y_c, y_s)` as [`track`](Self::track) does and hands each
    /// sample's estimates to `each`, in order, keeping none: for a caller that reduces them
    /// as they come (a study's error statistics), whose memory then does not grow with the
    /// samples fed.
    ///
    /// ```
    /// use angletrack::export::GainsFile;
    /// use angletrack::tracker_file::{CaptureHead, TrackerFile, TrackerRun};
    /// let gains = GainsFile { gains: vec![0.06, 0.001], sample_period_s: 1e-4, design: None };
    /// let file = TrackerFile::new(gains);
    /// let theta: Vec<f64> = (0..4000).map(|k| 1e-3 * k as f64).collect();
    /// let (y_c, y_s): (Vec<f64>, Vec<f64>) = theta.iter().map(|t| (t.cos(), t.sin())).unzip();
    /// let head = CaptureHead { y_c: &y_c, y_s: &y_s, counts: None };
    /// let mut run = TrackerRun::new(&file, "t.json", &head)?;
    /// let mut last = 0.0;
    /// run.track_each(&y_c, &y_s, |e| last = e.position_rad);
    /// assert!((last - 3.999).abs() < 1e-3);
    /// # Ok::<(), angletrack::JsonFileError>(())
    /// ```
    pub fn track_each(&mut self, y_c: &[f64], y_s: &[f64], each: impl FnMut(TrackedSample)) {
        each!(&mut self.chain, c => c.track_each(y_c, y_s, each))
    }

    /// The observer's and the front end's faults latched since the start.
    pub fn latched_faults(&self) -> (Faults, FrontEndFaults) {
        each!(&self.chain, c => c.latched_faults())
    }

    /// What the online calibration learned (`None` without one).
    pub fn learning(&self) -> Option<Learning> {
        each!(&self.chain, c => c.learning())
    }

    /// Whether the chain is the fixed-point one (its rows carry the binary angle).
    pub fn is_fixed(&self) -> bool {
        matches!(self.chain, Chain::Fixed2(_) | Chain::Fixed3(_))
    }

    /// One line naming the chain: number type, order, sin/cos and stages.
    pub fn describe(&self) -> String {
        each!(&self.chain, c => c.describe())
    }
}

fn field<'a>(
    name: &'a str,
    f: &'static str,
) -> impl Fn(angletrack_core::ConfigError) -> JsonFileError + 'a {
    move |e| refuse(name, f, e.to_string())
}

fn file_error(name: &str, e: super::FirmwareError) -> JsonFileError {
    match e {
        super::FirmwareError::File(e) => e,
        super::FirmwareError::Export(e) => refuse(name, "adc_range", e.to_string()),
    }
}

/// `x` to 6 significant digits, for the summary.
fn significant(x: f64) -> String {
    let decimals = if x.is_finite() && x != 0.0 {
        (5 - x.abs().log10().floor() as i32).clamp(0, 17) as usize
    } else {
        0
    };
    format!("{x:.decimals$}")
}

/// The order's name, for the summary.
fn order_name(n: usize) -> &'static str {
    if n == 2 { "2nd order" } else { "3rd order" }
}

/// The calibration and correction stages of `file` in the core's names, for the summary.
fn stages(file: &TrackerFile, fixed: bool) -> String {
    let calibration = match (&file.calibration, fixed) {
        (Calibration::None, _) => "no calibration",
        (Calibration::Stored(_), false) => "stored calibration (SensorCalibration)",
        (Calibration::Stored(_), true) => "stored calibration (FixedCalibration)",
        (Calibration::Online { .. }, _) => "online calibration (OnlineCalibration)",
    };
    let correction = match (&file.correction, fixed) {
        (super::Correction::None, _) => "no angle correction".to_string(),
        (super::Correction::Harmonics(_), false) => {
            "angle correction (AngleCorrection, harmonics)".to_string()
        }
        (_, true) => format!(
            "angle correction (FixedAngleCorrectionTable, {} entries)",
            angletrack_core::TRACKER_TABLE_LENGTH
        ),
        (super::Correction::Table(_), false) => format!(
            "angle correction (AngleCorrectionTable, {} entries)",
            angletrack_core::TRACKER_TABLE_LENGTH
        ),
    };
    format!("{calibration} and {correction}")
}

/// The mid-scale removed from counts: stated by the file, or measured on `head`.
fn mid_scale(
    file: &TrackerFile,
    name: &str,
    head: &CaptureHead<'_>,
) -> Result<Option<i32>, JsonFileError> {
    Ok(match file.input {
        Input::Units => None,
        Input::Bits { bits, signed } => {
            if !(2..=31).contains(&bits) {
                return Err(refuse(name, "input.bits", "2 to 31 bits"));
            }
            Some(if signed { 0 } else { 1 << (bits - 1) })
        }
        Input::Scaled { mid_scale, .. } => Some(mid_scale),
        Input::Counts => {
            let Some(counts) = head.counts else {
                return Err(refuse(
                    name,
                    "input",
                    "counts whose mid-scale is measured need the capture's counts decided \
                     (capture_counts): state input.bits or input.mid_scale",
                ));
            };
            Some(
                i32::try_from(counts.mid_scale).map_err(|_| {
                    refuse(name, "input", "the counts' mid-scale is beyond 32 bits")
                })?,
            )
        }
    })
}

/// The fault thresholds: the file's, or scaled to the amplitude of `head` (mid-scale
/// removed, divided by the counts per unit, and corrected by a stored calibration: what the
/// monitor reads).
fn thresholds(
    file: &TrackerFile,
    head: &CaptureHead<'_>,
    mid: Option<i32>,
) -> FaultThresholds<f64> {
    if let Some(t) = file.fault_thresholds {
        return t;
    }
    let per_unit = match file.input {
        Input::Scaled {
            counts_per_unit, ..
        } => counts_per_unit,
        _ => 1.0,
    };
    let n = head
        .y_c
        .len()
        .min(head.y_s.len())
        .min(crate::NOMINAL_AMPLITUDE_SAMPLES);
    let mid = f64::from(mid.unwrap_or(0));
    let unit = |y: &[f64]| -> Vec<f64> { y[..n].iter().map(|v| (v - mid) / per_unit).collect() };
    let (mut y_c, mut y_s) = (unit(head.y_c), unit(head.y_s));
    // The monitor reads the calibrated signal: a stored calibration's is measured.
    if let Calibration::Stored(calibration) = &file.calibration {
        for (c, s) in y_c.iter_mut().zip(y_s.iter_mut()) {
            (*c, *s) = calibration.correct(*c, *s);
        }
    }
    crate::capture_fault_thresholds_for_pole_pairs(&y_c, &y_s, file.pole_pairs.unwrap_or(1))
}
