//! `at_status`: what a C API call that can fail returns, `AT_OK` or an error naming the
//! refused parameter (the core's [`Parameter`]), and its message.

use core::ffi::CStr;

use angletrack_core::{ConfigError, Parameter};

/// What a call that can fail returns: `AT_OK` (0), or the `AT_ERR_*` code of what was
/// refused. `at_status_message` gives its text.
pub type at_status = i32;

/// Success.
pub const AT_OK: at_status = 0;
/// A pointer argument was NULL; nothing was written.
pub const AT_ERR_NULL_POINTER: at_status = 1;
/// The observer order was not 2 or 3.
pub const AT_ERR_ORDER: at_status = 2;
/// A struct argument was not made by its constructor (`at_chain_f32_new`, `at_adc_f32_new`, ...).
pub const AT_ERR_NOT_INITIALISED: at_status = 3;
/// The calibration mode was not one of `AT_CALIBRATION_*`.
pub const AT_ERR_MODE: at_status = 4;
/// A struct argument was made by another build of the library (its layout word, written
/// with its tag, is not this build's: another layout version `AT_LAYOUT_VERSION`, library
/// version, struct size or target); it was not read. Make it again with this build.
pub const AT_ERR_OTHER_BUILD: at_status = 5;
/// `at_chain_f32_new` was given both a stored calibration and the online calibration's
/// settings (a chain has one calibration stage), or both the harmonic angle correction and
/// its table (one angle correction).
pub const AT_ERR_STAGES: at_status = 6;
/// A parameter this version of the C API has no code for (a newer core's).
pub const AT_ERR_OTHER_PARAMETER: at_status = 63;

/// The parameters' status codes `AT_ERR_*` (with their docs), [`PARAMETERS`] and
/// [`status_of`], from one list: each `NAME = code: Parameter, c"name";`.
macro_rules! parameters {
    ($($(#[$doc:meta])* $name:ident = $code:literal: $parameter:ident, $text:literal;)*) => {
        $($(#[$doc])* pub const $name: at_status = $code;)*

        /// Every parameter with its status code and its name as the core names it
        /// (`Parameter::name`, checked by the tests), NUL-terminated: the table of the
        /// messages.
        pub(crate) const PARAMETERS: &[(Parameter, at_status, &CStr)] =
            &[$((Parameter::$parameter, $name, $text)),*];

        /// The status naming the parameter a configuration error refused. A `match`, not a
        /// search of [`PARAMETERS`]: a firmware that builds a chain and never asks for a
        /// message links no names (on a Cortex-M0, the table and its strings are 1.7 KB).
        pub(crate) fn status_of(error: ConfigError) -> at_status {
            match error.parameter() {
                $(Parameter::$parameter => $name,)*
                _ => AT_ERR_OTHER_PARAMETER,
            }
        }
    };
}

parameters! {
    /// `sample_period_s`: not finite, not positive, or outside [1 ps, 1000 s].
    AT_ERR_SAMPLE_PERIOD_S = 16: SamplePeriod, c"sample_period_s";
    /// `gains[0]` (l1): not finite, or outside the stability region of the discrete loop.
    AT_ERR_GAINS_0 = 17: AngleGain, c"gains[0] (l1)";
    /// `gains[1]` (l2): not finite, or outside the stability region of the discrete loop.
    AT_ERR_GAINS_1 = 18: SpeedGain, c"gains[1] (l2)";
    /// `gains[2]` (l3): not finite, or outside the stability region of the discrete loop.
    AT_ERR_GAINS_2 = 19: AccelerationGain, c"gains[2] (l3)";
    /// Fault threshold `max_input_amplitude`.
    AT_ERR_MAX_INPUT_AMPLITUDE = 20: MaxInputAmplitude, c"max_input_amplitude";
    /// Fault threshold `loss_of_signal`.
    AT_ERR_LOSS_OF_SIGNAL = 21: LossOfSignalThreshold, c"loss_of_signal";
    /// Fault threshold `degradation_high`.
    AT_ERR_DEGRADATION_HIGH = 22: DegradationHighThreshold, c"degradation_high";
    /// Fault threshold `degradation_low`.
    AT_ERR_DEGRADATION_LOW = 23: DegradationLowThreshold, c"degradation_low";
    /// Fault threshold `loss_of_tracking`.
    AT_ERR_LOSS_OF_TRACKING = 24: LossOfTrackingThreshold, c"loss_of_tracking";
    /// Fault threshold `filter_factor`.
    AT_ERR_FILTER_FACTOR = 25: FilterFactor, c"filter_factor";
    /// Fault threshold `false_lock`.
    AT_ERR_FALSE_LOCK = 26: FalseLockThreshold, c"false_lock";
    /// Fault threshold `nominal_amplitude`.
    AT_ERR_NOMINAL_AMPLITUDE = 27: NominalAmplitude, c"nominal_amplitude";
    /// Fault threshold `max_speed_rad_s`.
    AT_ERR_MAX_SPEED_RAD_S = 28: MaxSpeed, c"max_speed_rad_s";
    /// ADC `mid_scale_counts`.
    AT_ERR_MID_SCALE_COUNTS = 29: MidScaleCounts, c"mid_scale_counts";
    /// ADC `counts_per_unit`.
    AT_ERR_COUNTS_PER_UNIT = 30: CountsPerUnit, c"counts_per_unit";
    /// ADC resolution `bits`.
    AT_ERR_BITS = 31: AdcBits, c"bits";
    /// Sensor calibration `offset_c`.
    AT_ERR_OFFSET_C = 32: OffsetCos, c"offset_c";
    /// Sensor calibration `offset_s`.
    AT_ERR_OFFSET_S = 33: OffsetSin, c"offset_s";
    /// Sensor calibration `amplitude_c`.
    AT_ERR_AMPLITUDE_C = 34: AmplitudeCos, c"amplitude_c";
    /// Sensor calibration `amplitude_s`.
    AT_ERR_AMPLITUDE_S = 35: AmplitudeSin, c"amplitude_s";
    /// Sensor calibration `quadrature_rad`.
    AT_ERR_QUADRATURE_RAD = 36: Quadrature, c"quadrature_rad";
    /// Calibration setting `min_speed_rad_s`.
    AT_ERR_MIN_SPEED_RAD_S = 37: MinSpeed, c"min_speed_rad_s";
    /// Calibration setting `max_offset`.
    AT_ERR_MAX_OFFSET = 38: MaxOffset, c"max_offset";
    /// Calibration setting `max_amplitude_mismatch`.
    AT_ERR_MAX_AMPLITUDE_MISMATCH = 39: MaxAmplitudeMismatch, c"max_amplitude_mismatch";
    /// Calibration setting `max_quadrature_rad`.
    AT_ERR_MAX_QUADRATURE_RAD = 40: MaxQuadrature, c"max_quadrature_rad";
    /// Angle correction: a coefficient not finite, or their total `sum |a_k| + |b_k|` above
    /// 0.25 rad.
    AT_ERR_ANGLE_CORRECTION = 41: AngleCorrection, c"angle_correction";
    /// Demodulator setting `carrier_hz`.
    AT_ERR_CARRIER_HZ = 42: CarrierFrequency, c"carrier_hz";
    /// Samples per carrier period (the excitation's schedule; the demodulator takes `adc_rate_hz`).
    AT_ERR_SAMPLES_PER_PERIOD = 43: SamplesPerPeriod, c"samples_per_period";
    /// Demodulator setting `carrier_amplitude_counts`.
    AT_ERR_CARRIER_AMPLITUDE_COUNTS = 44: CarrierAmplitude, c"carrier_amplitude_counts";
    /// Demodulator settings `adc_min_code`, `adc_max_code`, `clip_margin_counts`.
    AT_ERR_ADC_RANGE = 45: AdcRange, c"adc_range";
    /// Demodulator setting `loss_of_excitation`.
    AT_ERR_LOSS_OF_EXCITATION = 46: LossOfExcitationThreshold, c"loss_of_excitation";
    /// Demodulator setting `phase_drift_bound_rad`.
    AT_ERR_PHASE_DRIFT_BOUND_RAD = 47: PhaseDriftBound, c"phase_drift_bound_rad";
    /// Demodulator setting `expected_delay_rad`.
    AT_ERR_EXPECTED_DELAY_RAD = 48: ExpectedDelay, c"expected_delay_rad";
    /// Demodulator setting `carrier_loop_bandwidth`.
    AT_ERR_CARRIER_LOOP_BANDWIDTH = 49: CarrierLoopBandwidth, c"carrier_loop_bandwidth";
    /// Demodulator setting `adc_rate_hz` (at least 4 times the carrier).
    AT_ERR_ADC_RATE_HZ = 53: AdcRate, c"adc_rate_hz";
    /// Demodulator setting `weak_excitation`.
    AT_ERR_WEAK_EXCITATION = 54: WeakExcitationThreshold, c"weak_excitation";
    /// Demodulator setting `max_carrier_error`.
    AT_ERR_MAX_CARRIER_ERROR = 55: MaxCarrierError, c"max_carrier_error";
    /// Demodulator setting `startup_periods`.
    AT_ERR_STARTUP_PERIODS = 50: StartupPeriods, c"startup_periods";
    /// ADC setting `shift` (0 to 15).
    AT_ERR_SHIFT = 51: AdcShift, c"shift";
    /// An angle error `curve` of fewer than 2 points.
    AT_ERR_CURVE = 52: AngleErrorCurve, c"curve";
    /// Fault threshold `tracking_error`.
    AT_ERR_TRACKING_ERROR = 56: TrackingErrorThreshold, c"tracking_error";
    /// Fault threshold `magnitude_tolerance`.
    AT_ERR_MAGNITUDE_TOLERANCE = 57: MagnitudeTolerance, c"magnitude_tolerance";
}

/// `AT_OK`, or the status of the error.
pub(crate) fn status_of_result<T>(result: Result<T, ConfigError>) -> at_status {
    result.err().map_or(AT_OK, status_of)
}

/// The text of a status: the name of the refused parameter as the core names it
/// (`Parameter::name`, e.g. `"gains[2] (l3)"`, `"sample_period_s"`), or what went wrong.
pub(crate) fn message(status: at_status) -> &'static CStr {
    match status {
        AT_OK => c"ok",
        AT_ERR_NULL_POINTER => c"a pointer argument is NULL",
        AT_ERR_ORDER => c"order must be 2 or 3",
        AT_ERR_NOT_INITIALISED => c"a struct argument was not made by its constructor",
        AT_ERR_MODE => c"mode must be AT_CALIBRATION_OFF, _LEARNING or _FROZEN",
        AT_ERR_OTHER_BUILD => {
            c"a struct argument was made by another build of the library (layout version or size differs)"
        }
        AT_ERR_STAGES => {
            c"a chain takes one calibration (stored or online) and one angle correction (harmonics or table)"
        }
        AT_ERR_OTHER_PARAMETER => c"a parameter of a newer core",
        _ => PARAMETERS
            .iter()
            .find(|(_, s, _)| *s == status)
            .map_or(c"unknown status", |(_, _, name)| name),
    }
}
