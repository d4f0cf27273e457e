//! [`FixedGains`]: the checked configuration of the fixed-point observer, quantised from the
//! floating-point gains a design gives (`docs/theory.md §14`), and the integer thresholds of
//! its diagnostics.

use super::shift::Shift;
use crate::error::{ConfigError, Parameter};
use crate::gains::{Order, SupportedOrder};
use crate::stability::for_f64::check_stability;

/// The most fraction bits the acceleration state may have below the binary angle's unit.
const MAX_ACCELERATION_FRACTION_BITS: u32 = 16;

/// The largest gain mantissa: `mantissa * eps` plus the rounding (at most 2^30) stays below
/// 2^31 for `|eps| <= 2^15`.
const MAX_MANTISSA: i64 = 32_767;

/// Signal amplitudes (counts) the fixed-point path normalises exactly: from 4096 (below, the
/// loop gain falls with the amplitude and loss of signal is flagged) to any `i16` signal.
pub const MIN_NORMALISED_AMPLITUDE_COUNTS: i32 = 4096;

/// The checked, immutable configuration of the fixed-point angle tracking observer of order
/// `N` (2 or 3): each gain `l_i` as a 15-bit mantissa and a right shift, the fraction bits
/// of each state, and the diagnostics' thresholds in the integers the update compares.
///
/// The state components are the binary angle (2^32 per turn), the speed in 2^-32 turn per
/// sample and, for `N = 3`, the acceleration in 2^-(32 + F) turn per sample^2, `F` chosen
/// here from `l3` for range and resolution (`docs/theory.md §14`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedGains<const N: usize> {
    /// `l_i 2^(17 + F_i) / (2 pi) = mantissa_i 2^-shift_i`, the mantissa of 15 bits: the
    /// correction of state `i` is `mantissa_i eps 2^-shift_i` for `eps` in Q15.
    pub(crate) mantissa: [i32; N],
    pub(crate) shift: [Shift; N],
    /// Half a unit of each shift (`2^(shift_i - 1)`, 0 for no shift): the corrections round
    /// to nearest.
    pub(crate) rounding: [i32; N],
    /// Fraction bits `F` of the acceleration state below 2^-32 turn per sample^2 (the angle
    /// and the speed have none).
    pub(crate) acceleration_bits: u32,
    /// The shifts of the acceleration's terms in the predicted angle and speed (`F + 1`
    /// and `F`).
    pub(crate) acceleration_shift: [Shift; 2],
    /// The sample period (s), for conversions to physical units.
    pub(crate) sample_period_s: f64,
    pub(crate) monitor: FixedThresholds,
}

/// The integer constants of a [`FixedGains`]: what a firmware embeds (the `angletrack`
/// crate's designs and `angletrack design --dtype fixed` print them) and gives back to
/// [`FixedGains::from_constants`], which checks them again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedConstants<const N: usize> {
    /// The gains' mantissas (1 to 32767): `l_i = mantissa_i 2^-shift_i 2 pi / 2^(17 + F_i)`.
    pub mantissa: [i32; N],
    /// The gains' right shifts (0 to 31).
    pub shift: [u32; N],
    /// Fraction bits `F` of the acceleration state (0 to 16; 0 for a 2nd-order observer).
    pub acceleration_bits: u32,
}

/// The fixed-point monitor's thresholds, as the update compares them
/// (`docs/theory.md §14`): amplitudes as the reciprocal tracker's values, the phase error
/// and in-phase component in Q15.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FixedThresholds {
    /// Run the monitor at all.
    pub(crate) enabled: bool,
    /// Reciprocal at or above this: loss of signal.
    pub(crate) loss_of_signal: i32,
    /// Reciprocal above this (amplitude below the band) or below `degradation_high`:
    /// degradation of signal.
    pub(crate) degradation_low: i32,
    pub(crate) degradation_high: i32,
    /// Filtered `|eps|` (Q15) above this: loss of tracking.
    pub(crate) loss_of_tracking: i32,
    /// |speed| (2^-32 turn per sample) above this: loss of tracking (a quarter turn).
    pub(crate) max_speed: i32,
}

/// The reciprocal `2^27 / amplitude` a signal of `amplitude_counts` leaves in the tracker,
/// within the tracker's range.
fn reciprocal_of(amplitude_counts: f64) -> i32 {
    let r = libm::round(134_217_728.0 / amplitude_counts);
    r.clamp(
        f64::from(super::update::MIN_RECIPROCAL),
        f64::from(super::update::MAX_RECIPROCAL),
    ) as i32
}

impl FixedThresholds {
    /// The float monitor's default thresholds (`FaultThresholds`) for signals of
    /// `nominal_counts`: loss of signal below 1/4, degradation outside [1/2, 3/2], loss of
    /// tracking above 0.1, a quarter turn per sample.
    fn for_amplitude(nominal_counts: f64) -> Self {
        Self {
            enabled: true,
            loss_of_signal: reciprocal_of(nominal_counts * 0.25),
            degradation_low: reciprocal_of(nominal_counts * 0.5),
            degradation_high: reciprocal_of(nominal_counts * 1.5),
            loss_of_tracking: 3277,
            max_speed: 1 << 30,
        }
    }
}

/// Fraction bits of the acceleration state for the gain `l3`: the most (at most 16) that
/// leave room for 1024 of the largest corrections (`l3` times a phase error of 1) before
/// the state saturates, `2^31 >= 1024 l3 2^(32 + F) / (2 pi)`: an acquisition transient
/// (tens of samples at large phase errors) stays far inside the range, and one unit of
/// the phase error (2^-15) still moves the state by at least 32 units (below 16 bits)
/// (`docs/theory.md §14`).
fn acceleration_fraction_bits(l3: f64) -> u32 {
    let bits = libm::floor(libm::log2(core::f64::consts::PI / (1024.0 * l3)));
    bits.clamp(0.0, f64::from(MAX_ACCELERATION_FRACTION_BITS)) as u32
}

/// Fraction bits of state `i` below 2^-32 turn per sample^i: none for the angle and the
/// speed, `acceleration_bits` for the acceleration.
pub(crate) const fn fraction_bits(i: usize, acceleration_bits: u32) -> u32 {
    if i < 2 { 0 } else { acceleration_bits }
}

/// The parameter naming gain `i`.
const fn gain_parameter(i: usize) -> Parameter {
    match i {
        0 => Parameter::AngleGain,
        1 => Parameter::SpeedGain,
        _ => Parameter::AccelerationGain,
    }
}

/// `gain 2^bits / (2 pi)` as a mantissa below 2^15 and a right shift, or `None` if it does
/// not fit with a shift of 0.
fn quantise(gain: f64, bits: u32) -> Option<(i32, u32)> {
    let scaled = gain * libm::ldexp(1.0, bits as i32) / core::f64::consts::TAU;
    let mut shift = 0;
    while shift < 31 && libm::round(libm::ldexp(scaled, shift as i32 + 1)) <= MAX_MANTISSA as f64 {
        shift += 1;
    }
    let mantissa = libm::round(libm::ldexp(scaled, shift as i32));
    (mantissa <= MAX_MANTISSA as f64).then_some((mantissa as i32, shift))
}

impl<const N: usize> FixedGains<N>
where
    Order<N>: SupportedOrder,
{
    /// Quantises the discrete gains `gains` (`l1, l2[, l3]`, as [`Gains::new`] takes them:
    /// the designs of the `angletrack` crate give them in `f64`) at the sample period
    /// `sample_period_s` (s), with the diagnostics' defaults for a nominal amplitude of
    /// 2^14 counts.
    ///
    /// Refused, naming the gain: a gain that is not finite or not positive, one that rounds
    /// to zero or does not fit its format (`ConfigError::OutOfRange`), and gains whose
    /// quantised values leave the stability region (`ConfigError::Unstable`, the same check
    /// as [`Gains::new`] on the values the integers represent).
    ///
    /// [`Gains::new`]: crate::Gains::new
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let quantised = gains.gains();
    /// assert!((quantised[2] / 0.000_34 - 1.0).abs() < 1e-4);
    /// // 1e-30 rounds to zero in every format:
    /// let err = FixedGains::<3>::new([0.1578, 0.0126, 1e-30], 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(gains: [f64; N], sample_period_s: f64) -> Result<Self, ConfigError> {
        if !sample_period_s.is_finite() {
            return Err(ConfigError::NotFinite(Parameter::SamplePeriod));
        }
        if sample_period_s <= 0.0 {
            return Err(ConfigError::NotPositive(Parameter::SamplePeriod));
        }
        let mut acceleration_bits = 0;
        let mut mantissa = [0; N];
        let mut shift = [0; N];
        for (i, &gain) in gains.iter().enumerate() {
            let parameter = gain_parameter(i);
            if !gain.is_finite() {
                return Err(ConfigError::NotFinite(parameter));
            }
            if gain <= 0.0 {
                return Err(ConfigError::NotPositive(parameter));
            }
            if i == 2 {
                acceleration_bits = acceleration_fraction_bits(gain);
            }
            let (m, s) = quantise(gain, 17 + fraction_bits(i, acceleration_bits))
                .ok_or(ConfigError::OutOfRange(parameter))?;
            if m == 0 {
                return Err(ConfigError::OutOfRange(parameter));
            }
            mantissa[i] = m;
            shift[i] = s;
        }
        Self::from_constants(
            FixedConstants {
                mantissa,
                shift,
                acceleration_bits,
            },
            sample_period_s,
        )
    }

    /// The fixed-point gains from their integer constants (as [`FixedGains::constants`]
    /// gives them) and the sample period (s), checked again as [`FixedGains::new`] checks
    /// its quantised gains: each mantissa in 1 to 32767 and shift at most 31
    /// (`ConfigError::OutOfRange` naming the gain), the acceleration's fraction bits at
    /// most 16, and the loop they represent inside the stability region.
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let designed = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let embedded = FixedGains::<3>::from_constants(designed.constants(), 50e-6)?;
    /// assert_eq!(embedded, designed);
    /// let mut broken = designed.constants();
    /// broken.mantissa[2] = 0;
    /// let err = FixedGains::<3>::from_constants(broken, 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_constants(
        constants: FixedConstants<N>,
        sample_period_s: f64,
    ) -> Result<Self, ConfigError> {
        if !sample_period_s.is_finite() {
            return Err(ConfigError::NotFinite(Parameter::SamplePeriod));
        }
        if sample_period_s <= 0.0 {
            return Err(ConfigError::NotPositive(Parameter::SamplePeriod));
        }
        let FixedConstants {
            mantissa,
            shift,
            acceleration_bits,
        } = constants;
        for i in 0..N {
            if !(1..=MAX_MANTISSA as i32).contains(&mantissa[i]) || shift[i] > 31 {
                return Err(ConfigError::OutOfRange(gain_parameter(i)));
            }
        }
        if acceleration_bits > MAX_ACCELERATION_FRACTION_BITS || (N < 3 && acceleration_bits > 0) {
            return Err(ConfigError::OutOfRange(gain_parameter(2)));
        }
        let fixed = Self {
            mantissa,
            shift: shift.map(Shift::new),
            rounding: shift.map(|s| if s == 0 { 0 } else { 1 << (s - 1) }),
            acceleration_bits,
            acceleration_shift: [
                Shift::new(acceleration_bits + 1),
                Shift::new(acceleration_bits),
            ],
            sample_period_s,
            monitor: FixedThresholds::for_amplitude(16384.0),
        };
        check_stability(&fixed.gains())?;
        Ok(fixed)
    }
}

impl<const N: usize> FixedGains<N> {
    /// The gains the integers represent (`l_i = mantissa_i 2^-shift_i 2 pi / 2^(17 + F_i)`):
    /// the loop that runs, whose stability [`FixedGains::new`] checked.
    pub fn gains(&self) -> [f64; N] {
        core::array::from_fn(|i| {
            let exponent = -(self.shift[i].bits() as i32)
                - 17
                - fraction_bits(i, self.acceleration_bits) as i32;
            libm::ldexp(f64::from(self.mantissa[i]), exponent) * core::f64::consts::TAU
        })
    }

    /// The same gains with the diagnostics' thresholds for signals of
    /// `nominal_amplitude_counts` (from 16384 to 46341 counts: loss of signal, a quarter of
    /// it, must stay within the tracker's range), or with the monitor off (`None`).
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)?.with_monitor(Some(28_000.0))?;
    /// let err = gains.with_monitor(Some(2000.0)).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::NominalAmplitude);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_monitor(self, nominal_amplitude_counts: Option<f64>) -> Result<Self, ConfigError> {
        let monitor = match nominal_amplitude_counts {
            None => FixedThresholds {
                enabled: false,
                ..self.monitor
            },
            Some(a) if !a.is_finite() => {
                return Err(ConfigError::NotFinite(Parameter::NominalAmplitude));
            }
            Some(a) if !(16384.0..=46341.0).contains(&a) => {
                return Err(ConfigError::OutOfRange(Parameter::NominalAmplitude));
            }
            Some(a) => FixedThresholds::for_amplitude(a),
        };
        Ok(Self { monitor, ..self })
    }

    /// The integer constants (for [`FixedGains::from_constants`]).
    pub fn constants(&self) -> FixedConstants<N> {
        FixedConstants {
            mantissa: self.mantissa,
            shift: self.shift.map(Shift::bits),
            acceleration_bits: self.acceleration_bits,
        }
    }

    /// The sample period `Ts` (s).
    pub fn sample_period(&self) -> f64 {
        self.sample_period_s
    }

    /// Fraction bits of the acceleration state below 2^-32 turn per sample^2 (0 for `N = 2`).
    pub fn acceleration_fraction_bits(&self) -> u32 {
        self.acceleration_bits
    }
}
