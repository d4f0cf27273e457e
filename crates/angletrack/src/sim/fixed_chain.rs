//! The fixed-point chain's front end from learned float values (`docs/theory.md §14`):
//! counts of any amplitude brought to the fixed-point observer's 16-bit range
//! ([`fixed_input_shift`]), a stored [`SensorCalibration`] applied in integers
//! ([`FixedCalibration`]) and the learned harmonics as the core's fixed-point angle
//! correction table, as the core's [`TrackerFrontEnd`] before the [`FixedGains`] observer
//! (the core's `Tracker<i16, FixedGains<N>>`). What `angletrack track --dtype fixed
//! --calibration cal.json` and the Python `FixedObserver` run: the learning is in float
//! (`angletrack calibrate`), the tracking in integers.

use angletrack_core::{
    AdcCounts, AngleCorrection, ConfigError, FixedAngleCorrectionTable, FixedCalibration, Input,
    Rails, SensorCalibration, TrackerFrontEnd, TrackerSettings,
};

use super::calibrated::{NOMINAL_AMPLITUDE_SAMPLES, nominal_amplitude};

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

/// The fixed-point monitor's roundness tolerance for counts of `amplitude` shifted by
/// `shift` (`FixedGains::with_monitor_tolerance`): 0.1, the float default, where
/// [`fixed_monitor_amplitude`] is their amplitude; `None` (no roundness check) where it
/// brought it within the monitor's range, since the signal's magnitude is then not the
/// nominal one.
///
/// ```
/// use angletrack::fixed_magnitude_tolerance;
/// assert_eq!(fixed_magnitude_tolerance(3000.0, 3), Some(0.1));
/// assert_eq!(fixed_magnitude_tolerance(1800.0, 3), None);
/// ```
pub fn fixed_magnitude_tolerance(amplitude: f64, shift: u32) -> Option<f64> {
    let samples = amplitude * f64::from(1u32 << shift.min(15));
    (samples == fixed_monitor_amplitude(amplitude, shift)).then_some(0.1)
}

/// The core's front end of the fixed-point chain for counts with `mid_scale_counts`
/// removed, shifted left by `shift` bits, checked for clipping at `rails` (in codes, as the
/// counts come: [`TrackerFrontEnd::new`]'s rule), corrected by `sensor` (learned on the
/// counts before the shift, in their units: its offsets are scaled by `2^shift` here) and by
/// the angle error `correction` (the core's table of its harmonics); each absent when
/// `None`. Refuses (naming the parameter) a mid-scale or shift out of range, a range that is
/// not ordered through the ADC ([`Parameter::AdcRange`]) and a calibration whose integers
/// do not fit.
///
/// ```
/// use angletrack::core::{AngleCorrection, Faults, FixedGains, Rails, SensorCalibration};
/// use angletrack::core::{Tracker, TrackerState};
/// use angletrack::fixed_front_end;
/// let sensor = SensorCalibration::new(36.0, -36.0, 1800.0, 1854.0, 0.0)?;
/// let correction = AngleCorrection::new([0.0; 8], [0.0, 0.0, 4e-3, 0.0, 0.0, 0.0, 0.0, 0.0])?;
/// let front_end = fixed_front_end(0, 3, Some(&sensor), Some(&correction), Rails::Unchecked)?;
/// assert_eq!(front_end.adc().map(|adc| adc.sample(1800i16, 0i16)), Some((14_400, 0)));
/// // The offsets in the shifted counts: 36 * 8.
/// assert_eq!(front_end.calibration().map(|c| c.correct(288, -288)), Some((0, 0)));
/// // A channel at the ADC's top code: flagged; inside: not.
/// let checked = fixed_front_end(2048, 4, None, None, Rails::Stated { min: 0, max: 4095 })?;
/// let tracker = Tracker::new(checked, FixedGains::<2>::new([0.05, 0.0012], 1e-4)?);
/// let mut state = TrackerState::new();
/// assert!(tracker.update(&mut state, (4095i16, 2048i16)).faults.contains(Faults::FRONT_END));
/// assert!(!tracker.update(&mut state, (4000i16, 2048i16)).faults.contains(Faults::FRONT_END));
/// assert!(fixed_front_end(2048, 4, None, None, Rails::Stated { min: 4095, max: 0 }).is_err());
/// # Ok::<(), angletrack::core::ConfigError>(())
/// ```
///
/// [`Parameter::AdcRange`]: angletrack_core::Parameter::AdcRange
pub fn fixed_front_end(
    mid_scale_counts: i32,
    shift: u32,
    sensor: Option<&SensorCalibration<f64>>,
    correction: Option<&AngleCorrection<f64>>,
    rails: Rails<i32>,
) -> Result<TrackerFrontEnd<i16>, ConfigError> {
    let adc = AdcCounts::new(mid_scale_counts, shift)?;
    let calibration = match sensor {
        None => None,
        Some(sensor) => Some(FixedCalibration::new(&shifted_calibration(sensor, shift)?)?),
    };
    TrackerFrontEnd::new(TrackerSettings {
        input: Input::Counts { adc, rails },
        winding: (),
        calibration,
        correction: correction.map(FixedAngleCorrectionTable::from_harmonics),
    })
}

/// `sensor` (learned on counts before the shift) in the counts shifted left by `shift`
/// bits, as the fixed-point chain's calibration takes it (its offsets and amplitudes times
/// `2^shift`).
pub fn shifted_calibration(
    sensor: &SensorCalibration<f64>,
    shift: u32,
) -> Result<SensorCalibration<f64>, ConfigError> {
    let scale = f64::from(1u32 << shift.min(15));
    let (o_c, o_s, a_c, a_s, phi) = sensor.parameters();
    SensorCalibration::new(o_c * scale, o_s * scale, a_c * scale, a_s * scale, phi)
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
    /// The monitor's roundness tolerance ([`fixed_magnitude_tolerance`]).
    pub magnitude_tolerance: Option<f64>,
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
    let (y_c, y_s) = (centred(y_c), centred(y_s));
    let amplitude = nominal_amplitude(&y_c, &y_s).unwrap_or(0.0);
    // The shift that keeps the samples themselves in 16 bits: their extent (the 99th
    // percentile of each pair's larger magnitude), which a bias adds to the amplitude.
    let mut extents: Vec<f64> = y_c
        .iter()
        .zip(&y_s)
        .map(|(c, s)| c.abs().max(s.abs()))
        .filter(|e| e.is_finite())
        .collect();
    extents.sort_unstable_by(f64::total_cmp);
    let extent = extents
        .get(extents.len().saturating_sub(1) * 99 / 100)
        .copied()
        .unwrap_or(0.0);
    let shift = fixed_input_shift(extent.max(amplitude));
    Ok(FixedInput {
        mid_scale_counts: mid,
        shift,
        amplitude,
        monitor_amplitude: fixed_monitor_amplitude(amplitude, shift),
        magnitude_tolerance: fixed_magnitude_tolerance(amplitude, shift),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::FixedGains;

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
        let front_end =
            fixed_front_end(0, shift, Some(&sensor), Some(&correction), Rails::Unchecked).unwrap();
        let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
            .unwrap()
            .with_monitor_tolerance(
                Some(fixed_monitor_amplitude(1800.0, shift)),
                fixed_magnitude_tolerance(1800.0, shift),
            )
            .unwrap();
        let chain = angletrack_core::Tracker::new(front_end, gains);
        let mut state = angletrack_core::TrackerState::new();
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
