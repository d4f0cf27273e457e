//! The fixed-point chain from learned float values (`docs/theory.md §14`): counts of any
//! amplitude brought to the fixed-point observer's 16-bit range ([`fixed_input_shift`]), a
//! stored [`SensorCalibration`] applied in integers ([`FixedCalibration`]) and the learned
//! harmonics as a [`FixedAngleCorrectionTable`], before the [`FixedGains`] observer. What
//! `angletrack track --dtype fixed --calibration cal.json` and the Python `FixedObserver`'s
//! stages run: the learning is in float (`angletrack calibrate`), the tracking in integers.

use angletrack_core::{
    AdcCounts, AngleCorrection, AngleCorrectionTable, Chain, ChainState, ConfigError,
    FixedAngleCorrectionTable, FixedCalibration, FixedGains, FixedState, FrontEndCheck,
    FrontEndCheckState, HeldRailCheck, HeldRails, SensorCalibration,
};

use super::calibrated::{NOMINAL_AMPLITUDE_SAMPLES, nominal_amplitude};

/// Entries per electrical turn of the angle correction table the fixed-point chain builds
/// from learned harmonics: 1024 (the interpolation's error below 2e-7 rad for a 4 mrad 3rd
/// harmonic, far below the table's 2^-15 rad step).
pub const FIXED_TABLE_LENGTH: usize = 1024;

/// The clipping checks of the fixed-point chain, on its 16-bit samples: against the ADC's
/// stated range, or against the rails measured as the samples come (each absent when not
/// asked for).
pub type FixedClipping = (Option<FrontEndCheck<i16>>, Option<HeldRailCheck>);

/// The front end of the fixed-point chain: counts to 16-bit samples, the clipping checks, the
/// stored calibration, the angle correction table (each the identity when not given).
pub type FixedFrontEnd = (
    AdcCounts,
    (
        FixedClipping,
        (
            FixedCalibration,
            FixedAngleCorrectionTable<FIXED_TABLE_LENGTH>,
        ),
    ),
);

/// The fixed-point chain of order `N` with the [`FixedFrontEnd`].
pub type FixedChain<const N: usize> = Chain<FixedFrontEnd, FixedGains<N>>;

/// The state of the [`FixedFrontEnd`]: the clipping checks' (the other stages hold none).
pub type FixedFrontEndState = ((), (((FrontEndCheckState, ()), HeldRails<i16>), ((), ())));

/// The state of one channel of a [`FixedChain`].
pub type FixedChainState<const N: usize> = ChainState<FixedFrontEndState, FixedState<N>>;

/// The largest amplitude (16-bit counts) [`fixed_input_shift`] brings a signal to: a
/// quarter of headroom below `i16::MAX` for offsets, imbalance and noise.
const MAX_SHIFTED_AMPLITUDE: f64 = 32767.0 / 1.25;

/// The left shift (0 to 15 bits) that brings counts of `amplitude` (mid-scale removed) to
/// the fixed-point observer's 16-bit range: the largest with `amplitude 2^shift` at most
/// 26,214 (a quarter of headroom for offsets and imbalance): 1800 counts (a 12-bit ADC) are
/// shifted by 3 to 14,400 (by 4, 28,800 would leave less than a tenth). 0 for an amplitude
/// that is not positive and finite.
///
/// ```
/// use angletrack::fixed_input_shift;
/// assert_eq!(fixed_input_shift(1800.0), 3); // 14,400, the next (28,800) leaves no headroom
/// assert_eq!(fixed_input_shift(16384.0), 0);
/// assert_eq!(fixed_input_shift(0.0), 0);
/// ```
pub fn fixed_input_shift(amplitude: f64) -> u32 {
    if !(amplitude.is_finite() && amplitude > 0.0) {
        return 0;
    }
    (0..=15)
        .rev()
        .find(|&shift| amplitude * f64::from(1u32 << shift) <= MAX_SHIFTED_AMPLITUDE)
        .unwrap_or(0)
}

/// The fixed-point monitor's nominal amplitude for counts of `amplitude` shifted by
/// `shift`: their amplitude in 16-bit counts, brought within the monitor's 16,384 to 46,341
/// (its bands, 0.5 to 1.5 of the nominal amplitude, leave room for the difference).
pub fn fixed_monitor_amplitude(amplitude: f64, shift: u32) -> f64 {
    (amplitude * f64::from(1u32 << shift.min(15))).clamp(16384.0, 46341.0)
}

/// The front end of the fixed-point chain for counts with `mid_scale_counts` removed,
/// shifted left by `shift` bits, corrected by `sensor` (learned on the counts before the
/// shift, in their units: its offsets are scaled by `2^shift` here) and by the angle error
/// `correction` (a [`FIXED_TABLE_LENGTH`]-entry table of its harmonics); each the identity
/// when `None`; no clipping check ([`with_fixed_clipping`] adds one). Refuses (naming the
/// parameter) a mid-scale or shift out of range and a calibration whose integers do not fit.
///
/// ```
/// use angletrack::{fixed_front_end, core::{AngleCorrection, SensorCalibration}};
/// let sensor = SensorCalibration::new(36.0, -36.0, 1800.0, 1854.0, 0.0)?;
/// let correction = AngleCorrection::new([0.0; 8], [0.0, 0.0, 4e-3, 0.0, 0.0, 0.0, 0.0, 0.0])?;
/// let (adc, (_clipping, (calibration, _table))) =
///     fixed_front_end(0, 3, Some(&sensor), Some(&correction))?;
/// assert_eq!(adc.sample(1800i16, 0i16), (14_400, 0));
/// // The offsets in the shifted counts: 36 * 8.
/// assert_eq!(calibration.correct(288, -288), (0, 0));
/// # Ok::<(), angletrack::core::ConfigError>(())
/// ```
pub fn fixed_front_end(
    mid_scale_counts: i32,
    shift: u32,
    sensor: Option<&SensorCalibration<f64>>,
    correction: Option<&AngleCorrection<f64>>,
) -> Result<FixedFrontEnd, ConfigError> {
    let adc = AdcCounts::new(mid_scale_counts, shift)?;
    let calibration = match sensor {
        None => FixedCalibration::IDENTITY,
        Some(sensor) => {
            let scale = f64::from(1u32 << shift);
            let (o_c, o_s, a_c, a_s, phi) = sensor.parameters();
            let shifted =
                SensorCalibration::new(o_c * scale, o_s * scale, a_c * scale, a_s * scale, phi)?;
            FixedCalibration::new(&shifted)?
        }
    };
    let table = FixedAngleCorrectionTable::from_table(&AngleCorrectionTable::from_harmonics(
        correction.unwrap_or(&AngleCorrection::NONE),
    ));
    Ok((adc, ((None, None), (calibration, table))))
}

/// `front_end` with clipping flagged against the ADC's `adc_range` of codes `(min, max)`
/// (counts as the chain takes them, taken through its ADC stage to 16 bits: exact), or, with
/// `measure_rails` and no range, against the rails measured on the 16-bit samples as they
/// come (the core's `HeldRailCheck`). A sample clipped in both channels is coasted through.
/// Refuses a range that is not `min < max` ([`Parameter::AdcRange`]) and both at once
/// ([`Parameter::AdcRange`]).
///
/// ```
/// use angletrack::core::{Chain, Faults, FixedGains};
/// use angletrack::{FixedChain, FixedChainState, fixed_front_end, with_fixed_clipping};
/// let front_end = fixed_front_end(2048, 4, None, None)?;
/// let checked = with_fixed_clipping(front_end, Some((0, 4095)), false)?;
/// let chain: FixedChain<2> = Chain::new(checked, FixedGains::<2>::new([0.05, 0.0012], 1e-4)?);
/// let mut state = FixedChainState::new();
/// // A channel at the ADC's top code: flagged; inside: not.
/// assert!(chain.update(&mut state, (4095i16, 2048i16)).faults.contains(Faults::FRONT_END));
/// assert!(!chain.update(&mut state, (4000i16, 2048i16)).faults.contains(Faults::FRONT_END));
/// assert!(with_fixed_clipping(front_end, Some((4095, 0)), false).is_err());
/// # Ok::<(), angletrack::core::ConfigError>(())
/// ```
///
/// [`Parameter::AdcRange`]: angletrack_core::Parameter::AdcRange
pub fn with_fixed_clipping(
    front_end: FixedFrontEnd,
    adc_range: Option<(i32, i32)>,
    measure_rails: bool,
) -> Result<FixedFrontEnd, ConfigError> {
    let (adc, (_, stages)) = front_end;
    let stated = match adc_range {
        Some(_) if measure_rails => {
            return Err(ConfigError::OutOfRange(
                angletrack_core::Parameter::AdcRange,
            ));
        }
        Some((min, max)) => Some(FrontEndCheck::of_adc_codes(&adc, min, max)?),
        None => None,
    };
    let measured = (measure_rails && adc_range.is_none()).then_some(HeldRailCheck::new());
    Ok((adc, ((stated, measured), stages)))
}

/// How a capture's counts reach the fixed-point observer ([`fixed_input`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedInput {
    /// The mid-scale removed (decided by [`capture_counts`](crate::capture_counts); 0 for
    /// signed counts).
    pub mid_scale_counts: i32,
    /// The left shift to the 16-bit range ([`fixed_input_shift`]).
    pub shift: u32,
    /// The counts' amplitude, mid-scale removed ([`nominal_amplitude`]; 0 without signal).
    pub amplitude: f64,
    /// The monitor's nominal amplitude ([`fixed_monitor_amplitude`]).
    pub monitor_amplitude: f64,
}

/// The [`FixedInput`] of a capture of whole counts whose mid-scale is `mid_scale_counts`
/// (the capture's, by [`capture_counts`](crate::capture_counts): never guessed here), from
/// its first samples `y_c`, `y_s`: the amplitude of the centred samples, the shift and the
/// monitor's amplitude derived from it. A [`ConfigError`] naming the mid-scale when no
/// `i32` holds it.
///
/// ```
/// let theta: Vec<f64> = (0..1000).map(|k| 0.01 * k as f64).collect();
/// let y_c: Vec<f64> = theta.iter().map(|t| (2048.0 + 1800.0 * t.cos()).round()).collect();
/// let y_s: Vec<f64> = theta.iter().map(|t| (2048.0 + 1800.0 * t.sin()).round()).collect();
/// let input = angletrack::fixed_input(&y_c, &y_s, 2048)?;
/// assert_eq!((input.mid_scale_counts, input.shift), (2048, 3));
/// assert!((input.amplitude - 1800.0).abs() < 1.0);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
pub fn fixed_input(
    y_c: &[f64],
    y_s: &[f64],
    mid_scale_counts: u64,
) -> Result<FixedInput, ConfigError> {
    let mid = i32::try_from(mid_scale_counts)
        .map_err(|_| ConfigError::OutOfRange(angletrack_core::Parameter::MidScaleCounts))?;
    let n = y_c.len().min(y_s.len()).min(NOMINAL_AMPLITUDE_SAMPLES);
    let centred = |y: &[f64]| -> Vec<f64> { y[..n].iter().map(|v| v - f64::from(mid)).collect() };
    let amplitude = nominal_amplitude(&centred(y_c), &centred(y_s)).unwrap_or(0.0);
    let shift = fixed_input_shift(amplitude);
    Ok(FixedInput {
        mid_scale_counts: mid,
        shift,
        amplitude,
        monitor_amplitude: fixed_monitor_amplitude(amplitude, shift),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The issue's sensor in int16 counts of amplitude 1800 (offsets 2 %, imbalance 3 %, a
    /// 3rd harmonic of 4 mrad) through the chain with its stored calibration: the angle
    /// within the table's and the counts' resolution of the truth.
    #[test]
    fn the_chain_removes_a_stored_calibration_in_integers() {
        let sensor = SensorCalibration::new(36.0, -36.0, 1800.0, 1854.0, 0.0).unwrap();
        let mut b = [0.0; 8];
        b[2] = 4e-3;
        let correction = AngleCorrection::new([0.0; 8], b).unwrap();
        let shift = fixed_input_shift(1800.0);
        let front_end = fixed_front_end(0, shift, Some(&sensor), Some(&correction)).unwrap();
        let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
            .unwrap()
            .with_monitor(Some(fixed_monitor_amplitude(1800.0, shift)))
            .unwrap();
        let chain: FixedChain<3> = Chain::new(front_end, gains);
        let mut state = FixedChainState::new();
        let (mut squares, mut count) = (0.0, 0);
        for k in 0..20_000 {
            let theta = 0.3 + 0.02 * k as f64;
            let read = theta + 4e-3 * (3.0 * theta).sin();
            let y_c = (36.0 + 1800.0 * read.cos()).round() as i16;
            let y_s = (-36.0 + 1854.0 * read.sin()).round() as i16;
            let e = chain.update(&mut state, (y_c, y_s));
            if k >= 10_000 {
                let d = chain.observer.position_rad(&e) - theta;
                let d = d.sin().atan2(d.cos());
                squares += d * d;
                count += 1;
                assert!(e.faults.is_empty(), "{k}: {:?}", e.faults);
            }
        }
        let rms = (squares / f64::from(count)).sqrt();
        println!("fixed chain with the stored calibration: {rms:.3e} rad RMS");
        // Measured: 6.5e-5 rad RMS (the counts' quantisation at 1800 and the table's 2^-15
        // rad step).
        assert!(rms < 3e-4, "{rms}");
    }

    #[test]
    fn shifts_keep_a_quarter_of_headroom() {
        assert_eq!(fixed_input_shift(1800.0), 3);
        assert_eq!(fixed_input_shift(1e6), 0);
        assert_eq!(fixed_monitor_amplitude(1800.0, 3), 16384.0);
        assert_eq!(fixed_monitor_amplitude(3000.0, 3), 24000.0);
    }
}
