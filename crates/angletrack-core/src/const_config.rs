//! Configurations built in constant evaluation, for a `static` in firmware: the `const`
//! constructors of [`Gains`], [`FaultThresholds`] and [`CalibrationSettings`] on `f32` and
//! `f64`, and [`ConstChecks`], through which the generic constructors reach the same checks.
//!
//! Constant evaluation cannot call trait methods (the arithmetic of a generic `T: Real` is
//! one), so every check is a `const fn` on each concrete float type, defined once by a
//! macro next to its mathematics (`stability`, `monitor`, `calibration_settings`, `error`);
//! the `const` constructors call them directly and the generic ones through [`ConstChecks`],
//! a supertrait of [`Real`]. One implementation thus serves both, and an `f32` configuration
//! is checked in `f32` arithmetic only, at compile time or at run time.

use core::marker::PhantomData;

use crate::calibration_settings::{CalibrationSettings, CheckedCalibration};
use crate::error::{ConfigError, Parameter};
use crate::gains::{Gains, Order, SupportedOrder};
use crate::monitor::{CheckedThresholds, FaultThresholds};
use crate::real::Float;

/// A float type the observers run on and whose configurations are checked: `f32`
/// (firmware) or `f64` (host). Sealed: only those two implement it.
///
/// It is [`Float`] (the arithmetic, which the per-sample code needs) with the `const`
/// checks of the configurations (a sealed trait, not nameable outside the crate), which
/// the checked constructors ([`Gains::new`], [`FaultThresholds::for_amplitude`], ...) need.
/// Code generic over the float type bounds it by `Real`.
pub trait Real: Float + ConstChecks {}

impl<T: Float + ConstChecks> Real for T {}

mod sealed {
    /// The checks of [`ConstChecks`](super::ConstChecks), per float type: not nameable
    /// outside the crate, so that no other type can be a [`Real`](super::Real).
    pub trait ConstChecks: Sized {
        /// [`Gains::new`](crate::Gains::new).
        fn new_gains<const N: usize, S>(
            gains: [Self; N],
            sample_period_s: Self,
        ) -> Result<crate::Gains<Self, N, S>, crate::ConfigError>
        where
            Self: crate::Float,
            crate::Order<N>: crate::SupportedOrder;
        /// [`FaultThresholds::for_amplitude`](crate::FaultThresholds::for_amplitude).
        fn thresholds_for_amplitude(nominal_amplitude: Self) -> crate::FaultThresholds<Self>;
        /// The check of [`FaultThresholds`](crate::FaultThresholds).
        fn check_thresholds(
            thresholds: &crate::FaultThresholds<Self>,
            sample_period_s: Self,
        ) -> Result<crate::monitor::CheckedThresholds<Self>, crate::ConfigError>;
        /// [`CalibrationSettings::default`](crate::CalibrationSettings::default).
        fn default_calibration_settings() -> crate::CalibrationSettings<Self>;
        /// The check of [`CalibrationSettings`](crate::CalibrationSettings).
        fn check_calibration_settings(
            settings: &crate::CalibrationSettings<Self>,
            sample_period_s: Self,
        ) -> Result<crate::calibration_settings::CheckedCalibration<Self>, crate::ConfigError>;
    }
}
pub(crate) use sealed::ConstChecks;

/// Defines, for the float type `$t` (its functions in modules `$m`), the `const`
/// constructors and the [`ConstChecks`] implementation.
macro_rules! const_config {
    ($t:ident, $m:ident) => {
        /// [`Gains::new`] for `$t`, as a `const fn`.
        const fn new_gains<const N: usize, S>(
            gains: [$t; N],
            sample_period_s: $t,
        ) -> Result<Gains<$t, N, S>, ConfigError>
        where
            Order<N>: SupportedOrder,
        {
            use crate::error::const_try;
            let sample_period = const_try!(crate::error::$m::check_positive(
                sample_period_s,
                Parameter::SamplePeriod
            ));
            // A physical range (1 ps to 1000 s): speed and acceleration are the scaled state
            // times 1/Ts and 1/Ts^2, which must not overflow for any state the loop can
            // reach. The bounds are the `f32` values in both types.
            if !(sample_period >= 1e-12_f32 as $t && sample_period <= 1e3) {
                return Err(ConfigError::OutOfRange(Parameter::SamplePeriod));
            }
            let sample_rate = 1.0 / sample_period;
            let mut i = 0;
            while i < N {
                if !gains[i].is_finite() {
                    return Err(ConfigError::NotFinite(Parameter::gain(i)));
                }
                i += 1;
            }
            const_try!(crate::stability::$m::check_stability(&gains));
            let thresholds = crate::monitor::$m::unstated();
            let calibration = crate::calibration_settings::$m::default_settings();
            Ok(Gains {
                l: gains,
                sample_period,
                sample_rate,
                sample_rate_squared: sample_rate * sample_rate,
                next_angle_gain: crate::stability::$m::next_angle_gain(&gains),
                thresholds: const_try!(crate::monitor::$m::check(&thresholds, sample_period)),
                calibration: const_try!(crate::calibration_settings::$m::check(
                    &calibration,
                    sample_period
                )),
                sin_cos: PhantomData,
            })
        }

        impl<const N: usize, S: crate::SinCos<$t>> Gains<$t, N, S>
        where
            Order<N>: SupportedOrder,
        {
            /// [`Gains::new`] as a `const fn` (the same checks, the same result), so that
            /// a gain set can be a `static` checked at compile time: an invalid set is a
            /// compile error. With [`Gains::with_fault_thresholds_const`] and
            /// [`Gains::with_calibration_settings_const`] for the rest of the
            /// configuration.
            ///
            /// ```
            /// use angletrack_core::Gains;
            #[doc = concat!("static GAINS: Gains<", stringify!($t), ", 3> = match Gains::<", stringify!($t), ", 3>::new_const([0.1578, 0.0126, 0.000_34], 50e-6) {")]
            ///     Ok(gains) => gains,
            ///     Err(_) => panic!("unstable gains"),
            /// };
            /// assert_eq!(GAINS.sample_period(), 50e-6);
            #[doc = concat!("assert_eq!(Some(GAINS), Gains::<", stringify!($t), ", 3>::new([0.1578, 0.0126, 0.000_34], 50e-6).ok());")]
            /// ```
            ///
            /// An unstable set (here `l3 < 0`) does not compile:
            ///
            /// ```compile_fail,E0080
            /// use angletrack_core::Gains;
            #[doc = concat!("static GAINS: Gains<", stringify!($t), ", 3> = match Gains::<", stringify!($t), ", 3>::new_const([0.1578, 0.0126, -0.000_34], 50e-6) {")]
            ///     Ok(gains) => gains,
            ///     Err(_) => panic!("unstable gains"),
            /// };
            /// ```
            pub const fn new_const(
                gains: [$t; N],
                sample_period_s: $t,
            ) -> Result<Self, ConfigError> {
                new_gains(gains, sample_period_s)
            }

            /// [`Gains::from_loop_polynomial`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::Gains;
            /// // Triple pole at z = 0.9: (s + 0.1)^3 = s^3 + 0.3 s^2 + 0.03 s + 0.001.
            #[doc = concat!("const GAINS: Gains<", stringify!($t), ", 3> = match Gains::<", stringify!($t), ", 3>::from_loop_polynomial_const([0.001, 0.03, 0.3], 1e-4) {")]
            ///     Ok(gains) => gains,
            ///     Err(_) => panic!("unstable loop"),
            /// };
            /// assert_eq!(Ok(GAINS), Gains::from_loop_polynomial([0.001, 0.03, 0.3], 1e-4));
            /// ```
            pub const fn from_loop_polynomial_const(
                coefficients: [$t; N],
                sample_period_s: $t,
            ) -> Result<Self, ConfigError> {
                let gains = crate::stability::$m::gains_of_loop_polynomial(&coefficients);
                new_gains(gains, sample_period_s)
            }
        }

        impl<const N: usize, S: crate::SinCos<$t>> Gains<$t, N, S> {
            /// [`Gains::with_fault_thresholds`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::{FaultThresholds, Gains};
            #[doc = concat!("static GAINS: Gains<", stringify!($t), ", 2> = match Gains::<", stringify!($t), ", 2>::new_const([0.05, 0.0012], 1e-4) {")]
            ///     Ok(gains) => match gains
            #[doc = concat!("        .with_fault_thresholds_const(FaultThresholds::<", stringify!($t), ">::for_amplitude_const(2048.0))")]
            ///     {
            ///         Ok(gains) => gains,
            ///         Err(_) => panic!("bad thresholds"),
            ///     },
            ///     Err(_) => panic!("unstable gains"),
            /// };
            /// assert_eq!(GAINS.fault_thresholds().loss_of_signal, 512.0);
            /// ```
            pub const fn with_fault_thresholds_const(
                self,
                thresholds: FaultThresholds<$t>,
            ) -> Result<Self, ConfigError> {
                match crate::monitor::$m::check(&thresholds, self.sample_period) {
                    Ok(thresholds) => Ok(Self { thresholds, ..self }),
                    Err(error) => Err(error),
                }
            }

            /// [`Gains::with_calibration_settings`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::{CalibrationSettings, Gains};
            #[doc = concat!("const SETTINGS: CalibrationSettings<", stringify!($t), "> = {")]
            #[doc = concat!("    let mut s = CalibrationSettings::<", stringify!($t), ">::default_const();")]
            ///     s.min_speed_rad_s = Some(50.0);
            ///     s
            /// };
            #[doc = concat!("static GAINS: Gains<", stringify!($t), ", 2> = match Gains::<", stringify!($t), ", 2>::new_const([0.05, 0.0012], 1e-4) {")]
            ///     Ok(gains) => match gains.with_calibration_settings_const(SETTINGS) {
            ///         Ok(gains) => gains,
            ///         Err(_) => panic!("bad settings"),
            ///     },
            ///     Err(_) => panic!("unstable gains"),
            /// };
            /// assert_eq!(GAINS.calibration_settings().min_speed_rad_s, Some(50.0));
            /// ```
            pub const fn with_calibration_settings_const(
                self,
                settings: CalibrationSettings<$t>,
            ) -> Result<Self, ConfigError> {
                match crate::calibration_settings::$m::check(&settings, self.sample_period) {
                    Ok(calibration) => Ok(Self {
                        calibration,
                        ..self
                    }),
                    Err(error) => Err(error),
                }
            }
        }

        impl FaultThresholds<$t> {
            /// [`FaultThresholds::for_amplitude`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::FaultThresholds;
            #[doc = concat!("const THRESHOLDS: FaultThresholds<", stringify!($t), "> = FaultThresholds::<", stringify!($t), ">::for_amplitude_const(1800.0);")]
            /// assert_eq!(THRESHOLDS, FaultThresholds::for_amplitude(1800.0));
            /// ```
            pub const fn for_amplitude_const(nominal_amplitude: $t) -> Self {
                crate::monitor::$m::for_amplitude(nominal_amplitude)
            }

            /// Checks the thresholds as [`Gains::with_fault_thresholds`] does for the
            /// sample period `sample_period_s` (s), in a `const fn`: a `const` or `static`
            /// set of thresholds can be refused at compile time.
            ///
            /// ```
            /// use angletrack_core::{ConfigError, FaultThresholds, Parameter};
            #[doc = concat!("const BAD: FaultThresholds<", stringify!($t), "> = {")]
            #[doc = concat!("    let mut t = FaultThresholds::<", stringify!($t), ">::for_amplitude_const(1.0);")]
            ///     t.filter_factor = 1.5;
            ///     t
            /// };
            /// const CHECK: Result<(), ConfigError> = match BAD.check_const(50e-6) {
            ///     Ok(_) => Ok(()),
            ///     Err(error) => Err(error),
            /// };
            /// assert_eq!(CHECK, Err(ConfigError::OutOfRange(Parameter::FilterFactor)));
            /// ```
            ///
            /// A `static` of such thresholds does not compile:
            ///
            /// ```compile_fail,E0080
            /// use angletrack_core::FaultThresholds;
            #[doc = concat!("static THRESHOLDS: FaultThresholds<", stringify!($t), "> = match {")]
            #[doc = concat!("    let mut t = FaultThresholds::<", stringify!($t), ">::for_amplitude_const(1.0);")]
            ///     t.filter_factor = 1.5;
            ///     t
            /// }
            /// .check_const(50e-6)
            /// {
            ///     Ok(thresholds) => thresholds,
            ///     Err(_) => panic!("bad thresholds"),
            /// };
            /// ```
            pub const fn check_const(self, sample_period_s: $t) -> Result<Self, ConfigError> {
                match crate::monitor::$m::check(&self, sample_period_s) {
                    Ok(_) => Ok(self),
                    Err(error) => Err(error),
                }
            }
        }

        impl CalibrationSettings<$t> {
            /// [`CalibrationSettings::default`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::CalibrationSettings;
            #[doc = concat!("const SETTINGS: CalibrationSettings<", stringify!($t), "> = CalibrationSettings::<", stringify!($t), ">::default_const();")]
            /// assert_eq!(SETTINGS, CalibrationSettings::default());
            /// ```
            pub const fn default_const() -> Self {
                crate::calibration_settings::$m::default_settings()
            }
        }

        impl ConstChecks for $t {
            #[inline]
            fn new_gains<const N: usize, S>(
                gains: [Self; N],
                sample_period_s: Self,
            ) -> Result<Gains<Self, N, S>, ConfigError>
            where
                Order<N>: SupportedOrder,
            {
                new_gains(gains, sample_period_s)
            }
            #[inline]
            fn thresholds_for_amplitude(nominal_amplitude: Self) -> FaultThresholds<Self> {
                crate::monitor::$m::for_amplitude(nominal_amplitude)
            }
            #[inline]
            fn check_thresholds(
                thresholds: &FaultThresholds<Self>,
                sample_period_s: Self,
            ) -> Result<CheckedThresholds<Self>, ConfigError> {
                crate::monitor::$m::check(thresholds, sample_period_s)
            }
            #[inline]
            fn default_calibration_settings() -> CalibrationSettings<Self> {
                crate::calibration_settings::$m::default_settings()
            }
            #[inline]
            fn check_calibration_settings(
                settings: &CalibrationSettings<Self>,
                sample_period_s: Self,
            ) -> Result<CheckedCalibration<Self>, ConfigError> {
                crate::calibration_settings::$m::check(settings, sample_period_s)
            }
        }
    };
}

/// The `f32` constructors.
mod for_f32 {
    use super::*;
    const_config!(f32, for_f32);
}

/// The `f64` constructors.
mod for_f64 {
    use super::*;
    const_config!(f64, for_f64);
}

mod checked;
pub(crate) mod stages;

#[cfg(test)]
mod tests;
