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
    AdcCounts, AdcScaling, AngleCorrection, AngleCorrectionTable, CalibrationStage, Calibrator,
    CorrectionStage, Exact, Fast, FaultThresholds, FixedAngleCorrectionTable, FixedCalibration,
    FixedGains, Float, Gains, Input as CoreInput, ObserverState, Order, Rails, SensorCalibration,
    SinCos, SupportedOrder, TRACKER_TABLE_LENGTH, Tracker, TrackerFrontEnd, TrackerSettings,
    TrackerState, WindingCheck,
};

use super::{Calibration, Correction, Input, NumberType, SinCosKind, TrackerFile};
use crate::Real;
use crate::json_file::JsonFileError;

/// The estimates of the samples a [`TrackerRun`] was fed, one entry a sample.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackedRows {
    /// The electrical angle (rad, in `[-pi, pi)`), in the observer's number type.
    pub angle_rad: Vec<f64>,
    /// The unwrapped angle (rad): the angle plus the whole turns counted.
    pub position_rad: Vec<f64>,
    /// The speed (rad/s).
    pub speed_rad_s: Vec<f64>,
    /// The observer's faults ([`Faults`](angletrack_core::Faults) bits).
    pub faults: Vec<u8>,
    /// The front end's faults of the sample
    /// ([`FrontEndFaults`](angletrack_core::FrontEndFaults) bits).
    pub front_end_faults: Vec<u8>,
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

/// The chain of one number type, order and sin/cos, with its state.
#[derive(Debug, Clone)]
enum Chain {
    F32Fast2(Float2<f32, Fast>),
    F32Exact2(Float2<f32, Exact>),
    F32Fast3(Float3<f32, Fast>),
    F32Exact3(Float3<f32, Exact>),
    F64Fast2(Float2<f64, Fast>),
    F64Exact2(Float2<f64, Exact>),
    F64Fast3(Float3<f64, Fast>),
    F64Exact3(Float3<f64, Exact>),
    Fixed2(Fixed<2>),
    Fixed3(Fixed<3>),
}

type Float2<T, S> = FloatChain<T, 2, S>;
type Float3<T, S> = FloatChain<T, 3, S>;

#[derive(Debug, Clone)]
struct FloatChain<T: Float, const N: usize, S: SinCos<T>> {
    tracker: Tracker<T, Gains<T, N, S>>,
    state: TrackerState<T, ObserverState<T, N>>,
    counts: bool,
    calibration: Calibration,
}

#[derive(Debug, Clone)]
struct Fixed<const N: usize>
where
    Order<N>: SupportedOrder,
{
    tracker: Tracker<i16, FixedGains<N>>,
    state: TrackerState<i16, angletrack_core::FixedState<N>>,
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
        let order = file.gains.gains.len();
        let chain = match (file.number_type, order, exact) {
            (NumberType::Fixed, 2, _) => Chain::Fixed2(Fixed::new(file, name, head)?),
            (NumberType::Fixed, _, _) => Chain::Fixed3(Fixed::new(file, name, head)?),
            (NumberType::F32, 2, false) => Chain::F32Fast2(FloatChain::new(file, name, head)?),
            (NumberType::F32, 2, true) => Chain::F32Exact2(FloatChain::new(file, name, head)?),
            (NumberType::F32, _, false) => Chain::F32Fast3(FloatChain::new(file, name, head)?),
            (NumberType::F32, _, true) => Chain::F32Exact3(FloatChain::new(file, name, head)?),
            (_, 2, false) => Chain::F64Fast2(FloatChain::new(file, name, head)?),
            (_, 2, true) => Chain::F64Exact2(FloatChain::new(file, name, head)?),
            (_, _, false) => Chain::F64Fast3(FloatChain::new(file, name, head)?),
            (_, _, true) => Chain::F64Exact3(FloatChain::new(file, name, head)?),
        };
        Ok(Self { chain })
    }

    /// Feeds the samples `(y_c, y_s)` (the shorter's length; counts as whole numbers) and
    /// returns their estimates. Never fails: a sample the front end or the observer cannot
    /// use is flagged and coasted through.
    pub fn track(&mut self, y_c: &[f64], y_s: &[f64]) -> TrackedRows {
        let mut rows = TrackedRows::default();
        match &mut self.chain {
            Chain::F32Fast2(c) => c.track(y_c, y_s, &mut rows),
            Chain::F32Exact2(c) => c.track(y_c, y_s, &mut rows),
            Chain::F32Fast3(c) => c.track(y_c, y_s, &mut rows),
            Chain::F32Exact3(c) => c.track(y_c, y_s, &mut rows),
            Chain::F64Fast2(c) => c.track(y_c, y_s, &mut rows),
            Chain::F64Exact2(c) => c.track(y_c, y_s, &mut rows),
            Chain::F64Fast3(c) => c.track(y_c, y_s, &mut rows),
            Chain::F64Exact3(c) => c.track(y_c, y_s, &mut rows),
            Chain::Fixed2(c) => c.track(y_c, y_s, &mut rows),
            Chain::Fixed3(c) => c.track(y_c, y_s, &mut rows),
        }
        rows
    }

    /// The sensor calibration the chain applies at this point (learned, for an online
    /// calibration; stored; `None` without), in the observer's input units.
    pub fn calibration(&self) -> Option<SensorCalibration<f64>> {
        fn of<T: Float + Real, const N: usize, S: SinCos<T>>(
            c: &FloatChain<T, N, S>,
        ) -> Option<SensorCalibration<f64>> {
            let learned = |s: &SensorCalibration<T>| {
                let (o_c, o_s, a_c, a_s, phi) = s.parameters();
                let [o_c, o_s, a_c, a_s, phi] = [o_c, o_s, a_c, a_s, phi].map(T::to_f64);
                SensorCalibration::new(o_c, o_s, a_c, a_s, phi).ok()
            };
            match &c.calibration {
                Calibration::Online { .. } => {
                    learned(&c.state.front_end.calibrator().calibration())
                }
                Calibration::Stored(s) => Some(*s),
                Calibration::None => None,
            }
        }
        match &self.chain {
            Chain::F32Fast2(c) => of(c),
            Chain::F32Exact2(c) => of(c),
            Chain::F32Fast3(c) => of(c),
            Chain::F32Exact3(c) => of(c),
            Chain::F64Fast2(c) => of(c),
            Chain::F64Exact2(c) => of(c),
            Chain::F64Fast3(c) => of(c),
            Chain::F64Exact3(c) => of(c),
            Chain::Fixed2(_) | Chain::Fixed3(_) => None,
        }
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
/// removed, divided by the counts per unit).
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
    crate::capture_fault_thresholds(&unit(head.y_c), &unit(head.y_s))
}

fn typed<T: Float + Real>(s: &SensorCalibration<f64>) -> Option<SensorCalibration<T>> {
    let (o_c, o_s, a_c, a_s, phi) = s.parameters();
    let [o_c, o_s, a_c, a_s, phi] = [o_c, o_s, a_c, a_s, phi].map(T::from_f64);
    SensorCalibration::new(o_c, o_s, a_c, a_s, phi).ok()
}

impl<T: Float + Real, const N: usize, S: SinCos<T>> FloatChain<T, N, S>
where
    Order<N>: SupportedOrder,
{
    fn new(file: &TrackerFile, name: &str, head: &CaptureHead<'_>) -> Result<Self, JsonFileError> {
        let field = |f: &'static str| field(name, f);
        let mut values = [T::ZERO; N];
        if file.gains.gains.len() != N {
            return Err(refuse(name, "gains", "2 or 3 gains (the observer's order)"));
        }
        for (slot, &g) in values.iter_mut().zip(&file.gains.gains) {
            *slot = T::from_f64(g);
        }
        let mid = mid_scale(file, name, head)?;
        let t = thresholds(file, head, mid);
        let thresholds = FaultThresholds::for_amplitude(T::from_f64(t.nominal_amplitude))
            .with_max_input_amplitude(T::from_f64(t.max_input_amplitude))
            .with_loss_of_signal(T::from_f64(t.loss_of_signal))
            .with_degradation_low(T::from_f64(t.degradation_low))
            .with_degradation_high(T::from_f64(t.degradation_high))
            .with_loss_of_tracking(T::from_f64(t.loss_of_tracking))
            .with_max_speed(t.max_speed.map(T::from_f64))
            .with_filter_factor(T::from_f64(t.filter_factor))
            .with_false_lock(T::from_f64(t.false_lock))
            .with_monitor(t.monitor)
            .with_re_acquire(t.re_acquire);
        let mut gains = Gains::<T, N>::new(values, T::from_f64(file.gains.sample_period_s))
            .map_err(field("gains"))?
            .with_fault_thresholds(thresholds)
            .map_err(field("fault_thresholds"))?
            .with_sin_cos::<S>();
        let mut calibrator = Calibrator::new();
        let calibration = match &file.calibration {
            Calibration::None => CalibrationStage::None,
            Calibration::Stored(c) => CalibrationStage::Stored(
                typed(c)
                    .ok_or_else(|| refuse(name, "calibration.sensor", "beyond the number type"))?,
            ),
            Calibration::Online { initial, settings } => {
                let mut typed_settings = angletrack_core::CalibrationSettings::default();
                typed_settings.min_speed_rad_s = settings.min_speed_rad_s.map(T::from_f64);
                typed_settings.max_offset = T::from_f64(settings.max_offset);
                typed_settings.max_amplitude_mismatch =
                    T::from_f64(settings.max_amplitude_mismatch);
                typed_settings.max_quadrature_rad = T::from_f64(settings.max_quadrature_rad);
                gains = gains
                    .with_calibration_settings(typed_settings)
                    .map_err(field("calibration"))?;
                if let Some(c) = initial {
                    calibrator = Calibrator::from_calibration(typed(c).ok_or_else(|| {
                        refuse(name, "calibration.initial", "beyond the number type")
                    })?);
                }
                calibrator.enable();
                CalibrationStage::Online(gains.online_calibration())
            }
        };
        let correction = match &file.correction {
            Correction::None => CorrectionStage::None,
            Correction::Harmonics(h) => {
                let (cos, sin) = h.coefficients();
                CorrectionStage::Harmonics(
                    AngleCorrection::new(cos.map(T::from_f64), sin.map(T::from_f64))
                        .map_err(field("correction"))?,
                )
            }
            Correction::Table(curve) => {
                let curve: Vec<T> = curve.iter().map(|&v| T::from_f64(v)).collect();
                CorrectionStage::Table(
                    AngleCorrectionTable::<T, TRACKER_TABLE_LENGTH>::from_curve(&curve)
                        .map_err(field("correction.table"))?,
                )
            }
        };
        let (code_rails, unit_rails) = file
            .rails(name, mid.is_some())
            .map_err(|e| file_error(name, e))?;
        let input = match mid {
            Some(mid) => {
                let per_unit = match file.input {
                    Input::Scaled {
                        counts_per_unit, ..
                    } => counts_per_unit,
                    _ => 1.0,
                };
                let adc = AdcScaling::new(mid, T::from_f64(per_unit)).map_err(field("input"))?;
                CoreInput::Counts {
                    adc,
                    rails: code_rails,
                }
            }
            None => CoreInput::Units {
                rails: match unit_rails {
                    Rails::Stated { min, max } => Rails::Stated {
                        min: T::from_f64(min),
                        max: T::from_f64(max),
                    },
                    Rails::Measured => Rails::Measured,
                    Rails::Unchecked => Rails::Unchecked,
                },
            },
        };
        let winding = file
            .winding_amplitude
            .map(|a| WindingCheck::new(T::from_f64(a)))
            .transpose()
            .map_err(field("winding_check.amplitude"))?;
        let front_end = TrackerFrontEnd::new(TrackerSettings {
            input,
            winding,
            calibration,
            correction,
        })
        .map_err(field("adc_range"))?;
        let mut state = TrackerState::new();
        *state.front_end.calibrator_mut() = calibrator;
        Ok(Self {
            tracker: Tracker::new(front_end, gains),
            state,
            counts: mid.is_some(),
            calibration: file.calibration,
        })
    }

    fn track(&mut self, y_c: &[f64], y_s: &[f64], rows: &mut TrackedRows) {
        for (&c, &s) in y_c.iter().zip(y_s) {
            let e = if self.counts {
                self.tracker.update(&mut self.state, (c as i32, s as i32))
            } else {
                self.tracker
                    .update(&mut self.state, (T::from_f64(c), T::from_f64(s)))
            };
            rows.angle_rad.push(e.angle.to_f64());
            rows.position_rad.push(e.position());
            rows.speed_rad_s.push(e.speed.to_f64());
            rows.faults.push(e.faults.bits());
            rows.front_end_faults
                .push(self.state.front_end.faults().bits());
        }
    }
}

impl<const N: usize> Fixed<N>
where
    Order<N>: SupportedOrder,
{
    fn new(file: &TrackerFile, name: &str, head: &CaptureHead<'_>) -> Result<Self, JsonFileError> {
        let field = |f: &'static str| field(name, f);
        if file.winding_amplitude.is_some() {
            return Err(refuse(
                name,
                "winding_check",
                "the fixed-point chain has none: leave it null",
            ));
        }
        let mid = mid_scale(file, name, head)?;
        let Some(mid) = mid else {
            return Err(refuse(
                name,
                "input",
                "the fixed-point chain takes counts: give input.bits",
            ));
        };
        // The firmware's rule for a stated width (`AdcCounts::offset_binary`): shifted to 16
        // bits; for counts of another width, the shift that keeps the samples in 16 bits.
        let shift = match file.input {
            Input::Bits { bits, .. } if bits <= 16 => 16 - bits,
            Input::Scaled { .. } => {
                return Err(refuse(
                    name,
                    "input",
                    "the fixed-point chain takes counts of a stated width: give input.bits",
                ));
            }
            _ => {
                let n = head.y_c.len().min(head.y_s.len());
                crate::fixed_input(&head.y_c[..n], &head.y_s[..n], mid as u64)
                    .map_err(field("input"))?
                    .shift
            }
        };
        let nominal = match file.fault_thresholds {
            Some(t) if t != FaultThresholds::for_amplitude(t.nominal_amplitude) => {
                return Err(refuse(
                    name,
                    "fault_thresholds",
                    "the fixed-point monitor takes the nominal amplitude only: leave the others at their defaults for it",
                ));
            }
            _ => thresholds(file, head, Some(mid)).nominal_amplitude,
        };
        let (rails, _) = file.rails(name, true).map_err(|e| file_error(name, e))?;
        let calibration = match &file.calibration {
            Calibration::None => None,
            Calibration::Stored(s) => Some(
                crate::shifted_calibration(s, shift)
                    .and_then(|s| FixedCalibration::new(&s))
                    .map_err(field("calibration.sensor"))?,
            ),
            Calibration::Online { .. } => {
                return Err(refuse(
                    name,
                    "calibration.kind",
                    "the fixed-point chain has no online calibration: give \"stored\" or \"none\"",
                ));
            }
        };
        let correction = match &file.correction {
            Correction::None => None,
            Correction::Harmonics(h) => {
                Some(FixedAngleCorrectionTable::<TRACKER_TABLE_LENGTH>::from_harmonics(h))
            }
            Correction::Table(curve) => Some(FixedAngleCorrectionTable::from_table(
                &AngleCorrectionTable::<f64, TRACKER_TABLE_LENGTH>::from_curve(curve)
                    .map_err(field("correction.table"))?,
            )),
        };
        let adc = AdcCounts::new(mid, shift).map_err(field("input"))?;
        let front_end = TrackerFrontEnd::<i16>::new(TrackerSettings {
            input: CoreInput::Counts { adc, rails },
            winding: (),
            calibration,
            correction,
        })
        .map_err(field("adc_range"))?;
        let mut values = [0.0; N];
        if file.gains.gains.len() != N {
            return Err(refuse(name, "gains", "2 or 3 gains (the observer's order)"));
        }
        values.copy_from_slice(&file.gains.gains);
        let gains = FixedGains::<N>::new(values, file.gains.sample_period_s)
            .and_then(|g| g.with_monitor(Some(crate::fixed_monitor_amplitude(nominal, shift))))
            .map_err(field("gains"))?;
        Ok(Self {
            tracker: Tracker::new(front_end, gains),
            state: TrackerState::new(),
        })
    }

    fn track(&mut self, y_c: &[f64], y_s: &[f64], rows: &mut TrackedRows) {
        for (&c, &s) in y_c.iter().zip(y_s) {
            let e = self.tracker.update(&mut self.state, (c as i32, s as i32));
            let position = self.tracker.observer.position_rad(&e);
            rows.angle_rad.push(
                (position + core::f64::consts::PI).rem_euclid(core::f64::consts::TAU)
                    - core::f64::consts::PI,
            );
            rows.position_rad.push(position);
            rows.speed_rad_s.push(self.tracker.observer.speed_rad_s(&e));
            rows.faults.push(e.faults.bits());
            rows.front_end_faults
                .push(self.state.front_end.faults().bits());
        }
    }
}
