//! The front end's stages as [`Stage`]s of a chain: the ADC ([`AdcScaling`], counts to
//! units), a stored sensor calibration ([`SensorCalibration`]: offsets, imbalance,
//! quadrature), the online calibration ([`OnlineCalibration`] with its [`Calibrator`], which
//! learns from the observer's feedback), the harmonic angle correction
//! ([`AngleCorrection`], which rotates each sample by the error at the observer's
//! prediction) and its table ([`AngleCorrectionTable`]); for the fixed-point observer,
//! the same in integers ([`AdcCounts`], [`FixedCalibration`], [`FixedAngleCorrectionTable`]).

use super::{Feedback, Prediction, Stage};
use crate::adc::{AdcCounts, AdcSample, AdcScaling};
use crate::angle_correction::AngleCorrection;
use crate::angle_table::{AngleCorrectionTable, FixedAngleCorrectionTable};
use crate::calibration::{FixedCalibration, SensorCalibration};
use crate::calibration_settings::{CalibrationSettings, CheckedCalibration};
use crate::faults::Faults;
use crate::gains::Gains;
use crate::learning::{CalibrationMode, Calibrator};
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::update::UsedSample;

/// A stage with no state and nothing to learn or flag (always quiet): `$doc`, for
/// `impl<$generics> Stage<$value, $input> for $stage`, whose forward pass is `$forward`
/// of the stage `$self`, the observer's prediction `$prediction` and the input `$x`.
macro_rules! memoryless_stage {
    ($(#[doc = $doc:literal])* [$($generics:tt)*] $stage:ty, $value:ty, $input:ty,
     |$self:ident, $prediction:ident, $x:pat_param| $forward:expr) => {
        $(#[doc = $doc])*
        impl<$($generics)*> Stage<$value, $input> for $stage {
            type State = ();
            type Memo = ();

            #[inline(always)]
            fn forward(
                &self,
                _: &mut (),
                $prediction: &impl Prediction<$value>,
                $x: $input,
            ) -> (($value, $value), ()) {
                let $self = self;
                ($forward, ())
            }

            #[inline(always)]
            fn quiet(&self, _: &()) -> bool {
                true
            }
        }
    };
}

memoryless_stage!(
    /// Raw ADC counts `(raw_c, raw_s)` to the pair in units ([`AdcScaling::sample`]).
    [T: Float, I: AdcSample] AdcScaling<T>, T, (I, I),
    |adc, _prediction, (raw_c, raw_s)| adc.sample(raw_c, raw_s)
);

memoryless_stage!(
    /// A stored calibration, applied to every sample ([`SensorCalibration::correct`]).
    [T: Float] SensorCalibration<T>, T, (T, T),
    |calibration, _prediction, (y_c, y_s)| calibration.correct(y_c, y_s)
);

memoryless_stage!(
    /// The harmonic angle error removed inside the phase detector: the sample rotated by
    /// `-d(p)` at the observer's predicted angle `p` (see [`AngleCorrection`]).
    [T: Float] AngleCorrection<T>, T, (T, T),
    |correction, prediction, (y_c, y_s)| if correction.order() == 0 {
        (y_c, y_s)
    } else {
        let (sin_p, cos_p) = prediction.sin_cos();
        correction.rotate(sin_p, cos_p, y_c, y_s)
    }
);

memoryless_stage!(
    /// The angle error's table, read at the observer's predicted angle.
    [T: Float, const L: usize] AngleCorrectionTable<T, L>, T, (T, T),
    |table, prediction, (y_c, y_s)| table.rotate(prediction.angle(), y_c, y_s)
);

memoryless_stage!(
    /// Raw ADC counts to the fixed-point observer's 16-bit samples.
    [I: AdcSample] AdcCounts, i16, (I, I),
    |adc, _prediction, (raw_c, raw_s)| adc.sample(raw_c, raw_s)
);

memoryless_stage!(
    /// A stored calibration in integers.
    [] FixedCalibration, i16, (i16, i16),
    |calibration, _prediction, (y_c, y_s)| calibration.correct(y_c, y_s)
);

memoryless_stage!(
    /// The angle error's table in integers, read at the predicted binary angle.
    [const L: usize] FixedAngleCorrectionTable<L>, i16, (i16, i16),
    |table, prediction, (y_c, y_s)| table.rotate(prediction.angle(), y_c, y_s)
);

/// The online calibration's configuration as a stage: its checked settings (when it learns,
/// the bounds of its faults). Its state is a [`Calibrator`], whose mode says whether it is
/// off, learning or frozen; it corrects each sample by its calibration unless off, and
/// while learning, learns from the raw sample and the observer's feedback (only while its
/// own lock test holds: `docs/theory.md §12`). A new estimate is applied once per completed
/// turn, and only if it passes the calibration's checks. Its faults
/// ([`Faults::AMPLITUDE_MISMATCH`], [`Faults::OFFSET_OR_QUADRATURE`]) are the
/// calibration's against the settings' bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnlineCalibration<T> {
    pub(crate) checked: CheckedCalibration<T>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// The online calibration with these gains' settings
    /// ([`Gains::with_calibration_settings`], checked then): a chain's stage.
    ///
    /// ```
    /// use angletrack_core::{Calibrator, Chain, ChainState, Gains, ObserverState};
    /// let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
    /// let chain = Chain::new(gains.online_calibration(), gains);
    /// let mut calibrator = Calibrator::new();
    /// calibrator.enable();
    /// let mut state = ChainState { front_end: calibrator, observer: ObserverState::new() };
    /// let speed = 2.0 * core::f32::consts::PI * 50.0; // rad/s, electrical
    /// for k in 0..6000 {
    ///     let theta = speed * k as f32 * 1e-4;
    ///     let (y_c, y_s) = (0.05 + theta.cos(), -0.05 + 1.1 * (theta + 0.05).sin());
    ///     chain.update(&mut state, (y_c, y_s));
    /// }
    /// let (o_c, o_s) = state.front_end.calibration().offsets();
    /// assert!((o_c - 0.05).abs() < 5e-3 && (o_s + 0.05).abs() < 5e-3);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn online_calibration(&self) -> OnlineCalibration<T> {
        OnlineCalibration {
            checked: self.calibration,
        }
    }
}

impl<T: Float> OnlineCalibration<T> {
    /// The settings.
    pub fn settings(&self) -> CalibrationSettings<T> {
        self.checked.settings
    }
}

impl<T: Float> Stage<T, (T, T)> for OnlineCalibration<T> {
    type State = Calibrator<T>;
    type Memo = (T, T);

    #[inline(always)]
    fn forward(
        &self,
        calibrator: &mut Calibrator<T>,
        _: &impl Prediction<T>,
        (y_c, y_s): (T, T),
    ) -> ((T, T), (T, T)) {
        let corrected = if calibrator.mode() == CalibrationMode::Off {
            (y_c, y_s)
        } else {
            calibrator.correct(y_c, y_s)
        };
        (corrected, (y_c, y_s))
    }

    #[inline(always)]
    fn feedback(&self, calibrator: &mut Calibrator<T>, raw: (T, T), used: Option<Feedback<T>>) {
        if calibrator.mode() == CalibrationMode::Learning {
            let used = used.map(|f| UsedSample {
                sin_cos: f.sin_cos,
                scaled_speed: f.scaled_speed,
                faults: f.faults,
                phase_error: f.phase_error,
            });
            calibrator.learn(&self.checked, used, raw);
        }
    }

    #[inline(always)]
    fn faults(&self, calibrator: &mut Calibrator<T>) -> Faults {
        if calibrator.mode() == CalibrationMode::Off {
            return Faults::NONE;
        }
        calibrator.sensor_faults(&self.checked)
    }

    #[inline(always)]
    fn quiet(&self, calibrator: &Calibrator<T>) -> bool {
        calibrator.mode() == CalibrationMode::Off
    }
}
