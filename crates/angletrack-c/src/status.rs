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
/// `sample_period_s`: not finite, not positive, or outside [1 ps, 1000 s].
pub const AT_ERR_SAMPLE_PERIOD_S: at_status = 16;
/// `gains[0]` (l1): not finite, or outside the stability region of the discrete loop.
pub const AT_ERR_GAINS_0: at_status = 17;
/// `gains[1]` (l2): not finite, or outside the stability region of the discrete loop.
pub const AT_ERR_GAINS_1: at_status = 18;
/// `gains[2]` (l3): not finite, or outside the stability region of the discrete loop.
pub const AT_ERR_GAINS_2: at_status = 19;
/// Fault threshold `max_input_amplitude`.
pub const AT_ERR_MAX_INPUT_AMPLITUDE: at_status = 20;
/// Fault threshold `loss_of_signal`.
pub const AT_ERR_LOSS_OF_SIGNAL: at_status = 21;
/// Fault threshold `degradation_high`.
pub const AT_ERR_DEGRADATION_HIGH: at_status = 22;
/// Fault threshold `degradation_low`.
pub const AT_ERR_DEGRADATION_LOW: at_status = 23;
/// Fault threshold `loss_of_tracking`.
pub const AT_ERR_LOSS_OF_TRACKING: at_status = 24;
/// Fault threshold `filter_factor`.
pub const AT_ERR_FILTER_FACTOR: at_status = 25;
/// Fault threshold `false_lock`.
pub const AT_ERR_FALSE_LOCK: at_status = 26;
/// Fault threshold `nominal_amplitude`.
pub const AT_ERR_NOMINAL_AMPLITUDE: at_status = 27;
/// Fault threshold `max_speed_rad_s`.
pub const AT_ERR_MAX_SPEED_RAD_S: at_status = 28;
/// ADC `mid_scale_counts`.
pub const AT_ERR_MID_SCALE_COUNTS: at_status = 29;
/// ADC `counts_per_unit`.
pub const AT_ERR_COUNTS_PER_UNIT: at_status = 30;
/// ADC resolution `bits`.
pub const AT_ERR_BITS: at_status = 31;
/// Sensor calibration `offset_c`.
pub const AT_ERR_OFFSET_C: at_status = 32;
/// Sensor calibration `offset_s`.
pub const AT_ERR_OFFSET_S: at_status = 33;
/// Sensor calibration `amplitude_c`.
pub const AT_ERR_AMPLITUDE_C: at_status = 34;
/// Sensor calibration `amplitude_s`.
pub const AT_ERR_AMPLITUDE_S: at_status = 35;
/// Sensor calibration `quadrature_rad`.
pub const AT_ERR_QUADRATURE_RAD: at_status = 36;
/// Calibration setting `min_speed_rad_s`.
pub const AT_ERR_MIN_SPEED_RAD_S: at_status = 37;
/// Calibration setting `max_offset`.
pub const AT_ERR_MAX_OFFSET: at_status = 38;
/// Calibration setting `max_amplitude_mismatch`.
pub const AT_ERR_MAX_AMPLITUDE_MISMATCH: at_status = 39;
/// Calibration setting `max_quadrature_rad`.
pub const AT_ERR_MAX_QUADRATURE_RAD: at_status = 40;
/// Angle correction: a coefficient not finite, or their total `sum |a_k| + |b_k|` above
/// 0.25 rad.
pub const AT_ERR_ANGLE_CORRECTION: at_status = 41;
/// Demodulator setting `carrier_hz`.
pub const AT_ERR_CARRIER_HZ: at_status = 42;
/// Samples per carrier period (the excitation's schedule; the demodulator takes `adc_rate_hz`).
pub const AT_ERR_SAMPLES_PER_PERIOD: at_status = 43;
/// Demodulator setting `carrier_amplitude_counts`.
pub const AT_ERR_CARRIER_AMPLITUDE_COUNTS: at_status = 44;
/// Demodulator settings `adc_min_code`, `adc_max_code`, `clip_margin_counts`.
pub const AT_ERR_ADC_RANGE: at_status = 45;
/// Demodulator setting `loss_of_excitation`.
pub const AT_ERR_LOSS_OF_EXCITATION: at_status = 46;
/// Demodulator setting `phase_drift_bound_rad`.
pub const AT_ERR_PHASE_DRIFT_BOUND_RAD: at_status = 47;
/// Demodulator setting `expected_delay_rad`.
pub const AT_ERR_EXPECTED_DELAY_RAD: at_status = 48;
/// Demodulator setting `carrier_loop_bandwidth`.
pub const AT_ERR_CARRIER_LOOP_BANDWIDTH: at_status = 49;
/// Demodulator setting `startup_periods`.
pub const AT_ERR_STARTUP_PERIODS: at_status = 50;
/// ADC setting `shift` (0 to 15).
pub const AT_ERR_SHIFT: at_status = 51;
/// An angle error `curve` of fewer than 2 points.
pub const AT_ERR_CURVE: at_status = 52;
/// Demodulator setting `adc_rate_hz` (at least 4 times the carrier).
pub const AT_ERR_ADC_RATE_HZ: at_status = 53;
/// Demodulator setting `weak_excitation`.
pub const AT_ERR_WEAK_EXCITATION: at_status = 54;
/// Demodulator setting `max_carrier_error`.
pub const AT_ERR_MAX_CARRIER_ERROR: at_status = 55;
/// A parameter this version of the C API has no code for (a newer core's).
pub const AT_ERR_OTHER_PARAMETER: at_status = 63;

/// Every parameter with its status code and its name as the core names it
/// (`Parameter::name`, checked by the tests), NUL-terminated: the one table both
/// directions and the messages use.
#[rustfmt::skip]
pub(crate) const PARAMETERS: [(Parameter, at_status, &CStr); 40] = [
    (Parameter::SamplePeriod, AT_ERR_SAMPLE_PERIOD_S, c"sample_period_s"),
    (Parameter::AngleGain, AT_ERR_GAINS_0, c"gains[0] (l1)"),
    (Parameter::SpeedGain, AT_ERR_GAINS_1, c"gains[1] (l2)"),
    (Parameter::AccelerationGain, AT_ERR_GAINS_2, c"gains[2] (l3)"),
    (Parameter::MaxInputAmplitude, AT_ERR_MAX_INPUT_AMPLITUDE, c"max_input_amplitude"),
    (Parameter::LossOfSignalThreshold, AT_ERR_LOSS_OF_SIGNAL, c"loss_of_signal"),
    (Parameter::DegradationHighThreshold, AT_ERR_DEGRADATION_HIGH, c"degradation_high"),
    (Parameter::DegradationLowThreshold, AT_ERR_DEGRADATION_LOW, c"degradation_low"),
    (Parameter::LossOfTrackingThreshold, AT_ERR_LOSS_OF_TRACKING, c"loss_of_tracking"),
    (Parameter::FilterFactor, AT_ERR_FILTER_FACTOR, c"filter_factor"),
    (Parameter::FalseLockThreshold, AT_ERR_FALSE_LOCK, c"false_lock"),
    (Parameter::NominalAmplitude, AT_ERR_NOMINAL_AMPLITUDE, c"nominal_amplitude"),
    (Parameter::MaxSpeed, AT_ERR_MAX_SPEED_RAD_S, c"max_speed_rad_s"),
    (Parameter::MidScaleCounts, AT_ERR_MID_SCALE_COUNTS, c"mid_scale_counts"),
    (Parameter::CountsPerUnit, AT_ERR_COUNTS_PER_UNIT, c"counts_per_unit"),
    (Parameter::AdcBits, AT_ERR_BITS, c"bits"),
    (Parameter::OffsetCos, AT_ERR_OFFSET_C, c"offset_c"),
    (Parameter::OffsetSin, AT_ERR_OFFSET_S, c"offset_s"),
    (Parameter::AmplitudeCos, AT_ERR_AMPLITUDE_C, c"amplitude_c"),
    (Parameter::AmplitudeSin, AT_ERR_AMPLITUDE_S, c"amplitude_s"),
    (Parameter::Quadrature, AT_ERR_QUADRATURE_RAD, c"quadrature_rad"),
    (Parameter::MinSpeed, AT_ERR_MIN_SPEED_RAD_S, c"min_speed_rad_s"),
    (Parameter::MaxOffset, AT_ERR_MAX_OFFSET, c"max_offset"),
    (Parameter::MaxAmplitudeMismatch, AT_ERR_MAX_AMPLITUDE_MISMATCH, c"max_amplitude_mismatch"),
    (Parameter::MaxQuadrature, AT_ERR_MAX_QUADRATURE_RAD, c"max_quadrature_rad"),
    (Parameter::AngleCorrection, AT_ERR_ANGLE_CORRECTION, c"angle_correction"),
    (Parameter::CarrierFrequency, AT_ERR_CARRIER_HZ, c"carrier_hz"),
    (Parameter::SamplesPerPeriod, AT_ERR_SAMPLES_PER_PERIOD, c"samples_per_period"),
    (Parameter::CarrierAmplitude, AT_ERR_CARRIER_AMPLITUDE_COUNTS, c"carrier_amplitude_counts"),
    (Parameter::AdcRange, AT_ERR_ADC_RANGE, c"adc_range"),
    (Parameter::LossOfExcitationThreshold, AT_ERR_LOSS_OF_EXCITATION, c"loss_of_excitation"),
    (Parameter::PhaseDriftBound, AT_ERR_PHASE_DRIFT_BOUND_RAD, c"phase_drift_bound_rad"),
    (Parameter::ExpectedDelay, AT_ERR_EXPECTED_DELAY_RAD, c"expected_delay_rad"),
    (Parameter::CarrierLoopBandwidth, AT_ERR_CARRIER_LOOP_BANDWIDTH, c"carrier_loop_bandwidth"),
    (Parameter::AdcRate, AT_ERR_ADC_RATE_HZ, c"adc_rate_hz"),
    (Parameter::WeakExcitationThreshold, AT_ERR_WEAK_EXCITATION, c"weak_excitation"),
    (Parameter::MaxCarrierError, AT_ERR_MAX_CARRIER_ERROR, c"max_carrier_error"),
    (Parameter::StartupPeriods, AT_ERR_STARTUP_PERIODS, c"startup_periods"),
    (Parameter::AdcShift, AT_ERR_SHIFT, c"shift"),
    (Parameter::AngleErrorCurve, AT_ERR_CURVE, c"curve"),
];

/// The status naming the parameter a configuration error refused.
pub(crate) fn status_of(error: ConfigError) -> at_status {
    let parameter = error.parameter();
    PARAMETERS
        .iter()
        .find(|(p, _, _)| *p == parameter)
        .map_or(AT_ERR_OTHER_PARAMETER, |(_, status, _)| *status)
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
