//! The one error type of the design, analysis, scenario and metrics functions.

use core::fmt;

use angletrack_core::{ConfigError, UnknownDiscretisation};

/// An argument of a design, analysis, scenario or metrics function, named in [`Error`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Argument {
    /// The sample period `Ts` (s).
    SamplePeriod,
    /// The tolerated angle error (rad) at a given acceleration.
    MaxError,
    /// An acceleration (rad/s^2).
    Acceleration,
    /// The damping ratio `m` of a 2nd-order loop.
    Damping,
    /// A bandwidth or natural frequency (Hz).
    Bandwidth,
    /// A time constant (s), e.g. the `Tc` of a Butterworth setting.
    TimeConstant,
    /// The ratio `K` of the real pole to the real part of the complex pair (3rd order).
    PoleRatio,
    /// The time constant `T` of the complex pair (s) (3rd order).
    PoleTimeConstant,
    /// The ratio `psi` of imaginary to real part of the complex pair (3rd order).
    PoleFrequencyRatio,
    /// A target overshoot of the step response (fraction, e.g. 0.1 for 10 %).
    Overshoot,
    /// A target 2 % settling time (s).
    SettlingTime,
    /// The process noise variance `q` of the scaled jerk `Ts^3 beta` (Kalman design).
    ProcessNoise,
    /// The measurement noise variance `r` of each channel (Kalman design).
    MeasurementNoise,
    /// The standard deviation of the jerk (rad/s^3).
    JerkStd,
    /// The power spectral density of the jerk (rad^2/s^5).
    JerkDensity,
    /// The standard deviation of the sensor noise on each channel (amplitude 1).
    SensorNoiseStd,
    /// A step size (rad).
    Step,
    /// A speed (rad/s).
    Speed,
    /// A duration (s).
    Duration,
    /// A distance of a move (rad).
    Distance,
    /// A frequency (Hz).
    Frequency,
    /// The signal amplitude of the sensor model.
    Amplitude,
    /// The relative amplitude imbalance of the sensor model.
    AmplitudeImbalance,
    /// The quadrature error (rad) of the sensor model.
    QuadratureError,
    /// The relative 3rd harmonic of the sensor model.
    ThirdHarmonic,
    /// The harmonics `(order, amplitude, phase)` of the sensor model's angle error.
    AngleErrorHarmonics,
    /// The harmonic orders an angle correction learns (`lowest_order`, `highest_order`).
    CorrectionOrder,
    /// The capture a calibration learns from (its speed, length or signals).
    CalibrationCapture,
    /// The number of bits of the ADC.
    AdcBits,
    /// The full scale of the ADC.
    AdcFullScale,
    /// Two input series of different lengths, or an empty series.
    SeriesLength,
    /// The name of a [`Discretisation`](crate::Discretisation).
    Discretisation,
    /// The number of channels of a [`ChannelBatch`](crate::ChannelBatch).
    Channels,
    /// The initial angle of a [`MotionProfile`](crate::MotionProfile) (rad).
    InitialAngle,
    /// The initial speed of a [`MotionProfile`](crate::MotionProfile) (rad/s).
    InitialSpeed,
    /// The speed limit of a trapezoidal or S-curve move (rad/s).
    MaxSpeed,
    /// The acceleration limit of a trapezoidal or S-curve move (rad/s^2).
    MaxAcceleration,
    /// The jerk limit of an S-curve move (rad/s^3).
    MaxJerk,
    /// The amplitude of a speed ripple (rad/s).
    Ripple,
    /// The DC offset of the cosine channel of the sensor model.
    OffsetCos,
    /// The DC offset of the sine channel of the sensor model.
    OffsetSin,
    /// The standard deviation of the sensor model's noise on each channel.
    NoiseStd,
    /// The whole motion profile, when only its total length is at fault.
    Profile,
    /// The time skipped before the metrics start (s).
    Skip,
    /// The angle error within which an observer counts as locked (rad).
    LockTolerance,
    /// The relative band of the settling time.
    SettlingBand,
    /// The number of ADC samples per carrier period of a resolver model.
    SamplesPerPeriod,
    /// The carrier delay (rad) of a resolver model.
    CarrierDelay,
    /// The carrier frequency (Hz) of a resolver model.
    CarrierFrequency,
    /// The excitation's amplitude (ADC counts) of a resolver model.
    ExcitationAmplitude,
    /// The transformation ratio of a resolver model.
    TransformationRatio,
    /// The DC common mode (ADC counts) of a resolver model's windings.
    CommonMode,
    /// The relative amplitude imbalance of a resolver model's sine winding.
    WindingImbalance,
    /// The noise standard deviation (ADC counts) of a resolver model's windings.
    NoiseStdCounts,
}

impl Argument {
    /// The argument's name as written in the function signatures and the Python API.
    pub const fn name(self) -> &'static str {
        match self {
            Argument::SamplePeriod => "sample_period_s",
            Argument::MaxError => "max_error_rad",
            Argument::Acceleration => "acceleration_rad_s2",
            Argument::Damping => "damping",
            Argument::Bandwidth => "bandwidth_hz",
            Argument::TimeConstant => "time_constant_s",
            Argument::PoleRatio => "pole_ratio (K)",
            Argument::PoleTimeConstant => "pole_time_constant_s (T)",
            Argument::PoleFrequencyRatio => "pole_frequency_ratio (psi)",
            Argument::Overshoot => "overshoot",
            Argument::SettlingTime => "settling_time_s",
            Argument::ProcessNoise => "process_noise_q",
            Argument::MeasurementNoise => "measurement_noise_r",
            Argument::JerkStd => "jerk_std_rad_s3",
            Argument::JerkDensity => "jerk_density_rad2_s5",
            Argument::SensorNoiseStd => "sensor_noise_std",
            Argument::Step => "step_rad",
            Argument::Speed => "speed_rad_s",
            Argument::Duration => "duration_s",
            Argument::Distance => "distance_rad",
            Argument::Frequency => "frequency_hz",
            Argument::Amplitude => "amplitude",
            Argument::AmplitudeImbalance => "amplitude_imbalance",
            Argument::QuadratureError => "quadrature_error_rad",
            Argument::ThirdHarmonic => "third_harmonic",
            Argument::AngleErrorHarmonics => "angle_error_harmonics",
            Argument::CorrectionOrder => "order",
            Argument::CalibrationCapture => "capture",
            Argument::AdcBits => "adc_bits",
            Argument::AdcFullScale => "adc_full_scale",
            Argument::SeriesLength => "series length",
            Argument::Discretisation => "discretisation",
            Argument::Channels => "channels",
            Argument::InitialAngle => "initial_angle_rad",
            Argument::InitialSpeed => "initial_speed_rad_s",
            Argument::MaxSpeed => "max_speed_rad_s",
            Argument::MaxAcceleration => "max_acceleration_rad_s2",
            Argument::MaxJerk => "max_jerk_rad_s3",
            Argument::Ripple => "ripple_rad_s",
            Argument::OffsetCos => "offset_cos",
            Argument::OffsetSin => "offset_sin",
            Argument::NoiseStd => "noise_std",
            Argument::Profile => "profile",
            Argument::Skip => "skip_s",
            Argument::LockTolerance => "lock_tolerance_rad",
            Argument::SettlingBand => "settling_band",
            Argument::SamplesPerPeriod => "samples_per_period",
            Argument::CarrierDelay => "carrier_delay_rad",
            Argument::CarrierFrequency => "carrier_hz",
            Argument::ExcitationAmplitude => "excitation_amplitude_counts",
            Argument::TransformationRatio => "transformation_ratio",
            Argument::CommonMode => "common_mode_counts",
            Argument::WindingImbalance => "winding_imbalance",
            Argument::NoiseStdCounts => "noise_std_counts",
        }
    }
}

impl fmt::Display for Argument {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An argument refused by a function that names its arguments as the caller writes them
/// (the Python API's names): the argument, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct ArgumentError {
    /// The argument (`samples_per_period`, `angle_rad`, `raw_s`, ...).
    pub argument: &'static str,
    /// What is wrong with it.
    pub reason: String,
}

impl ArgumentError {
    /// The refusal of `argument` for `reason`.
    pub fn new(argument: &'static str, reason: impl Into<String>) -> Self {
        Self {
            argument,
            reason: reason.into(),
        }
    }

    /// Refuses, naming the second, two series `(name, length)` of different lengths.
    ///
    /// ```
    /// use angletrack::ArgumentError;
    /// let e = ArgumentError::check_equal_lengths(("y_c", 3), ("y_s", 2)).unwrap_err();
    /// assert_eq!(e.to_string(), "y_s: has 2 samples but y_c has 3: they must be equal");
    /// ```
    pub fn check_equal_lengths(
        (a, a_len): (&'static str, usize),
        (b, b_len): (&'static str, usize),
    ) -> Result<(), Self> {
        if a_len == b_len {
            return Ok(());
        }
        let reason = format!("has {b_len} samples but {a} has {a_len}: they must be equal");
        Err(Self::new(b, reason))
    }
}

impl fmt::Display for ArgumentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.argument, self.reason)
    }
}

impl std::error::Error for ArgumentError {}

/// Why a design, analysis, scenario or metrics function refused its arguments.
///
/// Every variant names the argument at fault ([`Error::argument`]); the core's
/// [`ConfigError`] is wrapped when the designed gains themselves are refused.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The argument is NaN or infinite.
    NotFinite(Argument),
    /// The argument must be strictly positive.
    NotPositive(Argument),
    /// The argument is outside its allowed range.
    OutOfRange {
        /// The argument at fault.
        argument: Argument,
        /// The range it must lie in, in words.
        expected: &'static str,
    },
    /// The design is too fast for the sample rate: the largest `|s_i| Ts` of its continuous
    /// poles `s_i` (rad/s) times the sample period exceeds what the chosen discretisation
    /// carries over faithfully (or stably).
    TooFastForSampleRate {
        /// The design argument that sets the speed of the loop.
        argument: Argument,
        /// The largest `|s_i| Ts` of the design.
        pole_times_period: f64,
        /// The limit it must stay below.
        limit: f64,
    },
    /// No design meets the specification (e.g. an overshoot the pole family cannot give).
    NoSolution(Argument),
    /// The design's discrete gains are refused by the core although every argument is in
    /// range on its own: a loop so slow against the sample rate that its gains underflow,
    /// or whose gains round out of the stability region. `argument` is the design argument
    /// that sets the loop's speed; `gains` is the core's reason.
    GainsRefused {
        /// The design argument that sets the speed of the loop.
        argument: Argument,
        /// The core's reason for refusing the gains.
        gains: ConfigError,
    },
    /// The core refused the designed gains (outside the discrete stability region, or not
    /// representable in the requested float type).
    Gains(ConfigError),
}

impl Error {
    /// The argument the error names; `None` for [`Error::Gains`], whose
    /// [`ConfigError::parameter`] names the core's parameter instead.
    pub const fn argument(&self) -> Option<Argument> {
        match *self {
            Error::NotFinite(a) | Error::NotPositive(a) | Error::NoSolution(a) => Some(a),
            Error::OutOfRange { argument, .. }
            | Error::TooFastForSampleRate { argument, .. }
            | Error::GainsRefused { argument, .. } => Some(argument),
            Error::Gains(_) => None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NotFinite(a) => write!(f, "{a} must be finite"),
            Error::NotPositive(a) => write!(f, "{a} must be positive"),
            Error::OutOfRange { argument, expected } => {
                write!(f, "{argument} is out of range: expected {expected}")
            }
            Error::TooFastForSampleRate {
                argument,
                pole_times_period,
                ..
            } if pole_times_period.is_nan() => write!(
                f,
                "{argument} puts the loop's poles out of floating-point range"
            ),
            Error::TooFastForSampleRate {
                argument,
                pole_times_period,
                limit,
            } => write!(
                f,
                "{argument} makes the loop too fast for the sample rate: largest |s| Ts = \
                 {pole_times_period:.4} must stay below {limit}"
            ),
            Error::NoSolution(a) => write!(f, "no design meets the requested {a}"),
            Error::GainsRefused { argument, gains } => write!(
                f,
                "{argument} gives discrete gains the core refuses (the loop is too slow or \
                 too fast for the sample rate): {gains}"
            ),
            Error::Gains(e) => write!(f, "the designed gains are refused: {e}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Gains(e) | Error::GainsRefused { gains: e, .. } => Some(e),
            _ => None,
        }
    }
}

impl Error {
    /// The same error with `to` named wherever it names `from`: a design that passes its
    /// own arguments on under other names (`sensor_noise_std` becomes `r`) reports the
    /// caller's.
    pub(crate) fn renamed(self, from: Argument, to: Argument) -> Self {
        let swap = |a: Argument| if a == from { to } else { a };
        match self {
            Error::NotFinite(a) => Error::NotFinite(swap(a)),
            Error::NotPositive(a) => Error::NotPositive(swap(a)),
            Error::NoSolution(a) => Error::NoSolution(swap(a)),
            Error::OutOfRange { argument, expected } => Error::OutOfRange {
                argument: swap(argument),
                expected,
            },
            Error::TooFastForSampleRate {
                argument,
                pole_times_period,
                limit,
            } => Error::TooFastForSampleRate {
                argument: swap(argument),
                pole_times_period,
                limit,
            },
            Error::GainsRefused { argument, gains } => Error::GainsRefused {
                argument: swap(argument),
                gains,
            },
            Error::Gains(e) => Error::Gains(e),
        }
    }
}

impl From<ConfigError> for Error {
    fn from(e: ConfigError) -> Self {
        Error::Gains(e)
    }
}

/// A discretisation's name not understood, as the design arguments report it.
impl From<UnknownDiscretisation> for Error {
    fn from(_: UnknownDiscretisation) -> Self {
        Error::OutOfRange {
            argument: Argument::Discretisation,
            expected: "pole_matching, forward_euler or tustin",
        }
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(value: f64, argument: Argument) -> Result<f64, Error> {
    if !value.is_finite() {
        Err(Error::NotFinite(argument))
    } else if value <= 0.0 {
        Err(Error::NotPositive(argument))
    } else {
        Ok(value)
    }
}

/// Checks that `value` is finite.
pub(crate) fn finite(value: f64, argument: Argument) -> Result<f64, Error> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NotFinite(argument))
    }
}

/// Checks that `value` is finite and at least 0.
pub(crate) fn non_negative(value: f64, argument: Argument) -> Result<f64, Error> {
    finite(value, argument)?;
    if value < 0.0 {
        Err(Error::OutOfRange {
            argument,
            expected: ">= 0",
        })
    } else {
        Ok(value)
    }
}
