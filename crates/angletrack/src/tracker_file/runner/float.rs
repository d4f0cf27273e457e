//! The float chains of a [`TrackerRun`](super::TrackerRun): `f32` or `f64`, order 2 or 3,
//! the fast or exact sin/cos.

use angletrack_core::{
    AdcScaling, AngleCorrection, AngleCorrectionTable, CalibrationStage, Calibrator,
    CorrectionStage, FaultThresholds, Faults, Float, FrontEndFaults, Gains, Input as CoreInput,
    Order, Rails, SensorCalibration, SinCos, SupportedOrder, TRACKER_TABLE_LENGTH, Tracker,
    TrackerFrontEnd, TrackerSettings, TrackerState, WindingCheck,
};

use super::super::{Calibration, Correction, Input, TrackerFile};
use super::{
    CaptureHead, FloatChain, Learning, Run, TrackedRows, field, file_error, mid_scale, refuse,
    thresholds, typed,
};
use crate::Real;
use crate::json_file::JsonFileError;

impl<T: Float + Real, const N: usize, S: SinCos<T>> Run for FloatChain<T, N, S>
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
            .with_tracking_error(T::from_f64(t.tracking_error))
            .with_max_speed(t.max_speed.map(T::from_f64))
            .with_filter_factor(T::from_f64(t.filter_factor))
            .with_false_lock(T::from_f64(t.false_lock))
            .with_monitor(t.monitor)
            .with_re_acquire(t.re_acquire)
            .with_magnitude_tolerance(t.magnitude_tolerance.map(T::from_f64));
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
            description: format!(
                "the core's Tracker ({}, {}, {} sin/cos): {}, thresholds for an amplitude of \
                 {}; {}",
                core::any::type_name::<T>(),
                super::order_name(N),
                core::any::type_name::<S>()
                    .rsplit("::")
                    .next()
                    .unwrap_or("")
                    .to_lowercase(),
                match mid {
                    Some(mid) => format!("counts (AdcScaling, mid-scale {mid})"),
                    None => "samples in units".to_string(),
                },
                super::significant(t.nominal_amplitude),
                super::stages(file, false),
            ),
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
            rows.acceleration_rad_s2.push(e.acceleration.to_f64());
            rows.phase_error.push(e.phase_error.to_f64());
            rows.faults.push(e.faults.bits());
            rows.front_end_faults
                .push(self.state.front_end.faults().bits());
        }
    }

    fn latched_faults(&self) -> (Faults, FrontEndFaults) {
        (
            self.state.observer.latched_faults(),
            self.state.front_end.latched_faults(),
        )
    }

    fn learning(&self) -> Option<Learning> {
        if !matches!(self.calibration, Calibration::Online { .. }) {
            return None;
        }
        let calibrator = self.state.front_end.calibrator();
        let (o_c, o_s, a_c, a_s, phi) = calibrator.calibration().parameters();
        let [o_c, o_s, a_c, a_s, phi] = [o_c, o_s, a_c, a_s, phi].map(T::to_f64);
        Some(Learning {
            calibration: SensorCalibration::new(o_c, o_s, a_c, a_s, phi).ok()?,
            turns_learned: calibrator.turns_learned(),
            status: crate::status_name(calibrator.status()),
        })
    }

    fn describe(&self) -> String {
        self.description.clone()
    }
}
