//! Why a configuration is refused: [`ConfigError`], naming the [`Parameter`] by the name the
//! caller wrote. Gains and thresholds are checked once, at construction, so that the
//! per-sample update never fails.

use core::fmt;

/// A parameter of an observer's configuration, named in [`ConfigError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Parameter {
    /// The sample period `Ts` (s).
    SamplePeriod,
    /// The angle gain `l1` (dimensionless).
    AngleGain,
    /// The speed gain `l2` (dimensionless, scaled by `Ts`).
    SpeedGain,
    /// The acceleration gain `l3` (dimensionless, scaled by `Ts^2`).
    AccelerationGain,
    /// The input amplitude above which a sample is rejected as absurd.
    MaxInputAmplitude,
    /// The amplitude below which loss of signal is flagged.
    LossOfSignalThreshold,
    /// The amplitude above which degradation of signal is flagged.
    DegradationHighThreshold,
    /// The amplitude below which degradation of signal is flagged.
    DegradationLowThreshold,
    /// The filtered phase-detector error above which loss of tracking is flagged.
    LossOfTrackingThreshold,
    /// One sample's phase-detector error above which loss of tracking is flagged.
    TrackingErrorThreshold,
    /// The smoothing factor of the diagnostics' first-order filters.
    FilterFactor,
    /// The in-phase component below which a false lock is declared.
    FalseLockThreshold,
    /// The nominal amplitude of the input signals.
    NominalAmplitude,
    /// The estimated speed (rad/s) above which loss of tracking is flagged.
    MaxSpeed,
    /// The fraction of the nominal amplitude a sample's magnitude may depart from it.
    MagnitudeTolerance,
    /// The ADC reading of a zero signal (counts).
    MidScaleCounts,
    /// ADC counts per unit of the observer's input.
    CountsPerUnit,
    /// The ADC's resolution (bits).
    AdcBits,
    /// The left shift of ADC counts into the fixed-point observer's 16-bit samples (bits).
    AdcShift,
    /// A measured angle-error curve (rad), sampled over one electrical turn.
    AngleErrorCurve,
    /// The cosine channel's offset of a sensor calibration.
    OffsetCos,
    /// The sine channel's offset of a sensor calibration.
    OffsetSin,
    /// The cosine channel's amplitude of a sensor calibration.
    AmplitudeCos,
    /// The sine channel's amplitude of a sensor calibration.
    AmplitudeSin,
    /// The quadrature (non-orthogonality) angle of a sensor calibration (rad).
    Quadrature,
    /// The smallest speed (rad/s) at which the online calibration learns.
    MinSpeed,
    /// The largest offset (fraction of the amplitude) before a fault is flagged.
    MaxOffset,
    /// The largest amplitude mismatch between the channels (fraction) before a fault.
    MaxAmplitudeMismatch,
    /// The largest quadrature angle (rad) before a fault is flagged.
    MaxQuadrature,
    /// The excitation carrier frequency (Hz) of the resolver front end.
    CarrierFrequency,
    /// The rate (Hz) of the excitation's DAC/PWM updates or of the ADC samples.
    TickRate,
    /// The number of ADC samples per carrier period of the demodulator.
    SamplesPerPeriod,
    /// The nominal carrier amplitude at the ADC (counts) of the demodulator.
    CarrierAmplitude,
    /// The ADC's code range or the clipping margin inside it (counts).
    AdcRange,
    /// The relative carrier amplitude below which loss of excitation is flagged.
    LossOfExcitationThreshold,
    /// The carrier phase drift (rad) from its start-up value beyond which a fault is flagged.
    PhaseDriftBound,
    /// The carrier delay (rad) the start-up estimate is resolved around.
    ExpectedDelay,
    /// The carrier loop's bandwidth (its natural frequency times the carrier period, rad).
    CarrierLoopBandwidth,
    /// The ADC's sample rate (Hz) of the demodulator: at least 4 samples per carrier period.
    AdcRate,
    /// The relative carrier amplitude below which weak excitation is flagged.
    WeakExcitationThreshold,
    /// The largest relative carrier frequency error the demodulator tracks.
    MaxCarrierError,
    /// The number of carrier periods of the start-up delay estimate.
    StartupPeriods,
    /// The number of pole pairs of the motor.
    PolePairs,
    /// The resolver's speed ratio (electrical turns per mechanical turn).
    SpeedRatio,
    /// The latency (s) by which the drive's angle is extrapolated.
    Latency,
    /// The cut-off frequency (Hz) or time constant (s) of the speed output's low-pass.
    SpeedFilter,
    /// The closed-loop bandwidth (Hz) of a 2nd-order design.
    Bandwidth,
    /// The damping ratio of a 2nd-order design.
    Damping,
    /// The ratio `K` of the real pole to the complex pair's real part (3rd-order design).
    PoleRatio,
    /// The time constant `T` (s) of a 3rd-order design's poles.
    PoleTimeConstant,
    /// The ratio `psi` of the complex pair's imaginary to real part (3rd-order design).
    PoleFrequencyRatio,
    /// The scaled process noise `q` of a Kalman design.
    ProcessNoise,
    /// The measurement noise `r` of a Kalman design.
    MeasurementNoise,
    /// The coefficients of an [`AngleCorrection`](crate::AngleCorrection) (rad).
    AngleCorrection,
    /// The angle (rad) a state starts at ([`ObserverState::at`](crate::ObserverState::at)).
    InitialAngle,
    /// The speed (rad/s) a state starts at.
    InitialSpeed,
    /// The acceleration (rad/s^2) a state starts at.
    InitialAcceleration,
}

impl Parameter {
    /// The parameter's name as the caller writes it: the argument of [`Gains::new`]
    /// (`gains[i]`, `sample_period_s`), the field of
    /// [`FaultThresholds`](crate::FaultThresholds), and the keyword of the Python API
    /// (whose `max_speed_rad_s` carries the unit the Rust field `max_speed` documents).
    ///
    /// [`Gains::new`]: crate::Gains::new
    ///
    /// ```
    /// use angletrack_core::{Gains, Parameter};
    /// let err = Gains::<f32, 2>::new([0.05, 0.0012], 0.0).unwrap_err();
    /// assert_eq!(err.parameter().name(), "sample_period_s");
    /// assert_eq!(err.to_string(), "sample_period_s must be positive");
    /// assert_eq!(Parameter::SpeedGain.name(), "gains[1] (l2)");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Parameter::SamplePeriod => "sample_period_s",
            Parameter::AngleGain => "gains[0] (l1)",
            Parameter::SpeedGain => "gains[1] (l2)",
            Parameter::AccelerationGain => "gains[2] (l3)",
            Parameter::MaxInputAmplitude => "max_input_amplitude",
            Parameter::LossOfSignalThreshold => "loss_of_signal",
            Parameter::DegradationHighThreshold => "degradation_high",
            Parameter::DegradationLowThreshold => "degradation_low",
            Parameter::LossOfTrackingThreshold => "loss_of_tracking",
            Parameter::TrackingErrorThreshold => "tracking_error",
            Parameter::FilterFactor => "filter_factor",
            Parameter::FalseLockThreshold => "false_lock",
            Parameter::NominalAmplitude => "nominal_amplitude",
            Parameter::MaxSpeed => "max_speed_rad_s",
            Parameter::MagnitudeTolerance => "magnitude_tolerance",
            Parameter::MidScaleCounts => "mid_scale_counts",
            Parameter::CountsPerUnit => "counts_per_unit",
            Parameter::AdcBits => "bits",
            Parameter::AdcShift => "shift",
            Parameter::AngleErrorCurve => "curve",
            Parameter::OffsetCos => "offset_c",
            Parameter::OffsetSin => "offset_s",
            Parameter::AmplitudeCos => "amplitude_c",
            Parameter::AmplitudeSin => "amplitude_s",
            Parameter::Quadrature => "quadrature_rad",
            Parameter::MinSpeed => "min_speed_rad_s",
            Parameter::MaxOffset => "max_offset",
            Parameter::MaxAmplitudeMismatch => "max_amplitude_mismatch",
            Parameter::MaxQuadrature => "max_quadrature_rad",
            Parameter::CarrierFrequency => "carrier_hz",
            Parameter::TickRate => "tick_rate_hz",
            Parameter::SamplesPerPeriod => "samples_per_period",
            Parameter::CarrierAmplitude => "carrier_amplitude_counts",
            Parameter::AdcRange => "adc_range",
            Parameter::LossOfExcitationThreshold => "loss_of_excitation",
            Parameter::PhaseDriftBound => "phase_drift_bound_rad",
            Parameter::ExpectedDelay => "expected_delay_rad",
            Parameter::CarrierLoopBandwidth => "carrier_loop_bandwidth",
            Parameter::AdcRate => "adc_rate_hz",
            Parameter::WeakExcitationThreshold => "weak_excitation",
            Parameter::MaxCarrierError => "max_carrier_error",
            Parameter::StartupPeriods => "startup_periods",
            Parameter::PolePairs => "pole_pairs",
            Parameter::SpeedRatio => "speed_ratio",
            Parameter::Latency => "latency_s",
            Parameter::SpeedFilter => "speed_filter",
            Parameter::Bandwidth => "bandwidth_hz",
            Parameter::Damping => "damping",
            Parameter::PoleRatio => "pole_ratio (K)",
            Parameter::PoleTimeConstant => "pole_time_constant_s (T)",
            Parameter::PoleFrequencyRatio => "pole_frequency_ratio (psi)",
            Parameter::ProcessNoise => "process_noise_q",
            Parameter::MeasurementNoise => "measurement_noise_r",
            Parameter::AngleCorrection => "angle_correction",
            Parameter::InitialAngle => "angle_rad",
            Parameter::InitialSpeed => "speed_rad_s",
            Parameter::InitialAcceleration => "acceleration_rad_s2",
        }
    }

    /// The parameter naming gain `l[index]` (0: angle, 1: speed, 2: acceleration).
    pub const fn gain(index: usize) -> Parameter {
        match index {
            0 => Parameter::AngleGain,
            1 => Parameter::SpeedGain,
            _ => Parameter::AccelerationGain,
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a configuration was refused. Returned once, at construction; the per-sample update
/// never fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ConfigError {
    /// The parameter is NaN or infinite.
    NotFinite(Parameter),
    /// The parameter must be strictly positive.
    NotPositive(Parameter),
    /// The parameter is outside its allowed range (see the parameter's documentation).
    OutOfRange(Parameter),
    /// The gains put a pole of the discrete loop `(I - L e1^T) A` on or outside the unit
    /// circle; the named gain is the one whose stability condition fails
    /// (`docs/theory.md §6`).
    Unstable {
        /// The gain whose stability condition fails.
        parameter: Parameter,
        /// The condition, in the gains `l1, l2, l3`, that must hold.
        condition: &'static str,
    },
}

impl ConfigError {
    /// The parameter the error names.
    pub const fn parameter(&self) -> Parameter {
        match *self {
            ConfigError::NotFinite(p)
            | ConfigError::NotPositive(p)
            | ConfigError::OutOfRange(p) => p,
            ConfigError::Unstable { parameter, .. } => parameter,
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigError::NotFinite(p) => write!(f, "{p} must be finite"),
            ConfigError::NotPositive(p) => write!(f, "{p} must be positive"),
            ConfigError::OutOfRange(p) => write!(f, "{p} is out of its allowed range"),
            ConfigError::Unstable {
                parameter,
                condition,
            } => write!(
                f,
                "{parameter} puts the discrete loop outside its stability region: {condition} must hold"
            ),
        }
    }
}

impl core::error::Error for ConfigError {}

/// `?` for `const fn`s (the `?` operator is not available in constant evaluation).
macro_rules! const_try {
    ($result:expr) => {
        match $result {
            Ok(value) => value,
            Err(error) => return Err(error),
        }
    };
}
pub(crate) use const_try;

/// Defines, for the float type `$t`, the `const` check of a positive parameter.
macro_rules! positive_fns {
    ($t:ident) => {
        use super::{ConfigError, Parameter};

        /// Checks that a parameter is finite and strictly positive.
        pub(crate) const fn check_positive(
            value: $t,
            parameter: Parameter,
        ) -> Result<$t, ConfigError> {
            if !value.is_finite() {
                Err(ConfigError::NotFinite(parameter))
            } else if !(value > 0.0) {
                Err(ConfigError::NotPositive(parameter))
            } else {
                Ok(value)
            }
        }
    };
}

/// The `f32` check.
pub(crate) mod for_f32 {
    positive_fns!(f32);
}

/// The `f64` check.
pub(crate) mod for_f64 {
    positive_fns!(f64);
}
