//! [`FixedGains`]: the checked configuration of the fixed-point observer, quantised from the
//! floating-point gains a design gives (`docs/theory.md §14`), and the integer thresholds of
//! its diagnostics.

use crate::error::{ConfigError, Parameter};
use crate::gains::{Order, SupportedOrder};
use crate::monitor::{AmplitudeMeasure, DEFAULT_TRACKING_ERROR, Limits, MonitorLimits};
use crate::stability::for_f64::check_stability;

/// Signal amplitudes (counts) the fixed-point path normalises exactly: from 4096 (below, the
/// loop gain falls with the amplitude and loss of signal is flagged) to any `i16` signal.
pub const MIN_NORMALISED_AMPLITUDE_COUNTS: i32 = 4096;

/// Turns per radian: the gains act on radians, the integer states count turns.
const TURNS_PER_RAD: f64 = 1.0 / core::f64::consts::TAU;

/// The checked, immutable configuration of the fixed-point angle tracking observer of order
/// `N` (2 or 3): each gain `l_i` as an integer multiplier of the phase error, and the
/// diagnostics' thresholds in the integers the update compares.
///
/// The state components are the binary angle (2^32 per turn), the speed in 2^-32 turn per
/// sample and, for `N = 3`, the acceleration in 2^-63 turn per sample^2 (`docs/theory.md
/// §14`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedGains<const N: usize> {
    /// `multiplier_i = round(l_i 2^s_i / (2 pi))`, `s = (33, 33, 48 - k)`: the correction
    /// of the angle and speed is `round(multiplier eps / 2^16)`, that of the acceleration
    /// `multiplier eps 2^k`, for `eps` in Q15.
    pub(crate) multiplier: [i32; N],
    /// `k` (1 to 15): the smallest that fits `l3`'s multiplier in 31 bits, so that it keeps
    /// the most bits (0 for a 2nd-order observer).
    pub(crate) acceleration_shift: u32,
    /// `2^k`, by which the update multiplies (a shift by a variable costs a Cortex-M an
    /// instruction more).
    pub(crate) acceleration_scale: i32,
    /// The sample period (s), for conversions to physical units.
    pub(crate) sample_period_s: f64,
    pub(crate) monitor: FixedThresholds,
}

/// The integer constants of a [`FixedGains`]: what a firmware embeds (the `angletrack`
/// crate's designs and `angletrack design --dtype fixed` print them) and gives back to
/// [`FixedGains::from_constants`], which checks them again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedConstants<const N: usize> {
    /// The gains' multipliers (1 to 2^31 - 1): `l_i = multiplier_i 2 pi / 2^s_i` with
    /// `s = (33, 33, 48 - acceleration_shift)`.
    pub multiplier: [i32; N],
    /// The left shift `k` of the phase error in the acceleration's correction (1 to 15;
    /// 0 for a 2nd-order observer).
    pub acceleration_shift: u32,
}

/// The fixed-point monitor's thresholds, as the update compares them
/// (`docs/theory.md §14`) in the floats' decision ([`MonitorLimits`]): half the square
/// amplitude of a window's last sample (`(y_c^2 + y_s^2) / 2`), the sum of `|eps|` (Q15)
/// over the window, `|speed|` in 2^-32 turn per sample and the last sample's in-phase
/// component (counts times 2^15).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FixedThresholds {
    /// Run the monitor's flags at all.
    pub(crate) enabled: bool,
    /// Half the square amplitude below this: loss of signal.
    pub(crate) loss_of_signal: u32,
    /// Half the square amplitude below `degradation_low` or above `degradation_high`:
    /// degradation of signal.
    pub(crate) degradation_low: u32,
    pub(crate) degradation_high: u32,
    /// Half the square amplitude of a window's last sample outside [`round_low`,
    /// `round_high`]: off the circle (`FaultThresholds::magnitude_tolerance`), degradation
    /// of signal, held.
    pub(crate) round_low: u32,
    pub(crate) round_high: u32,
    /// Sum of `|eps|` (Q15) over the window above this: loss of tracking.
    pub(crate) loss_of_tracking: u32,
    /// |speed| (2^-32 turn per sample) above this: loss of tracking (a quarter turn).
    pub(crate) max_speed: u32,
    /// One sample's `|eps|` (Q15) above this: loss of tracking, held down to half of it
    /// (`FaultThresholds::tracking_error`).
    pub(crate) tracking_error: i32,
}

impl MonitorLimits for FixedThresholds {
    type Amplitude2 = u32;
    type Error = u32;
    type Speed = u32;
    type InPhase = i32;

    /// The band as its lower edge and width (`high >= low`, by construction); false lock
    /// at a negative in-phase component (an error beyond a quarter turn).
    #[inline(always)]
    fn limits(&self) -> Limits<u32, u32, u32, i32> {
        Limits {
            loss_of_signal: self.loss_of_signal,
            degradation_low: self.degradation_low,
            degradation_high: self.degradation_high,
            band: (
                self.degradation_low,
                self.degradation_high - self.degradation_low,
            ),
            round: (self.round_low, self.round_high - self.round_low),
            loss_of_tracking: self.loss_of_tracking,
            max_speed: self.max_speed,
            false_lock: 0,
        }
    }
}

/// The band as its lower edge and width: `a - low <= width` in unsigned wrapping
/// arithmetic (an amplitude below `low` wraps above the width).
impl AmplitudeMeasure for u32 {
    #[inline(always)]
    fn in_band(self, (low, width): (u32, u32)) -> bool {
        self.wrapping_sub(low) <= width
    }
}

/// Half the square amplitude of a signal of `amplitude_counts`.
const fn amplitude2_half_of(amplitude_counts: f64) -> u32 {
    // Rounded to nearest (a non-negative value; `as` saturates at u32::MAX).
    (amplitude_counts * amplitude_counts / 2.0 + 0.5) as u32
}

impl FixedThresholds {
    /// The monitor off: thresholds no window exceeds (its error sum is at most 2^19) but
    /// the first (whose sum starts at 2^31), so that a window's end takes the healthy path
    /// but for the first sample and a false lock, which then see `enabled` false.
    /// The defaults for 2^14 counts without a roundness check (those of
    /// [`FixedGains::from_constants`]), evaluated when the crate compiles.
    pub(super) const DEFAULT: Self = Self::for_amplitude(16384.0, None);

    pub(super) const OFF: Self = Self {
        enabled: false,
        loss_of_signal: 0,
        degradation_low: 0,
        degradation_high: u32::MAX,
        round_low: 0,
        round_high: u32::MAX,
        loss_of_tracking: (1 << 31) - 1,
        max_speed: u32::MAX,
        tracking_error: i32::MAX,
    };

    /// The float monitor's default thresholds (`FaultThresholds`) for signals of
    /// `nominal_counts`: loss of signal below 1/4, degradation outside [1/2, 3/2], loss of
    /// tracking above a mean `|eps|` of 0.1, a quarter turn per sample or one sample's
    /// `|eps|` of 0.05 (held down to 0.025), and, with a
    /// `tolerance` (the caller gave the amplitude), a last sample's magnitude further than
    /// that fraction from the nominal one (`FaultThresholds::magnitude_tolerance`).
    const fn for_amplitude(nominal_counts: f64, tolerance: Option<f64>) -> Self {
        let (round_low, round_high) = match tolerance {
            Some(r) => (
                // A tolerance of 1 or more: no lower edge.
                if r < 1.0 {
                    amplitude2_half_of(nominal_counts * (1.0 - r))
                } else {
                    0
                },
                // Saturated at u32::MAX by `as`: no upper edge beyond.
                amplitude2_half_of(nominal_counts * (1.0 + r)),
            ),
            None => (0, u32::MAX),
        };
        Self {
            round_low,
            round_high,
            enabled: true,
            loss_of_signal: amplitude2_half_of(nominal_counts * 0.25),
            degradation_low: amplitude2_half_of(nominal_counts * 0.5),
            degradation_high: amplitude2_half_of(nominal_counts * 1.5),
            loss_of_tracking: 3277 * super::update::MONITOR_WINDOW,
            max_speed: 1 << 30,
            // The floats' default in Q15, rounded to nearest: 1638 (released at 819).
            tracking_error: (DEFAULT_TRACKING_ERROR as f64 * 32768.0 + 0.5) as i32,
        }
    }
}

/// The shifts of the phase error in the acceleration's correction: `eps 2^k` fits 32 bits
/// up to `k = 16`; 1 to 15 keep every shift of the Cortex-M0's 32-bit form below 32.
const ACCELERATION_SHIFTS: core::ops::RangeInclusive<u32> = 1..=15;

/// The binary exponent `s_i` of gain `i`'s multiplier: the angle and the speed are corrected
/// by `round(multiplier eps 2^-16)` in units of 2^-32 turn (per sample), so
/// `multiplier = l 2^-15 2^16 2^32 / (2 pi)`; the acceleration by `multiplier eps 2^k` in
/// units of 2^-63 turn per sample^2, so `multiplier = l 2^-15 2^-k 2^63 / (2 pi)`.
const fn multiplier_exponent(i: usize, acceleration_shift: u32) -> u32 {
    if i < 2 { 33 } else { 48 - acceleration_shift }
}

/// `2^s_i` ([`multiplier_exponent`], at most 2^48), exactly: the exponent field of an `f64`
/// (`const`, unlike `ldexp`).
const fn multiplier_scale(i: usize, acceleration_shift: u32) -> f64 {
    f64::from_bits((1023 + multiplier_exponent(i, acceleration_shift) as u64) << 52)
}

/// `round(gain 2^s_i / (2 pi))` if it is a multiplier (1 to 2^31 - 1).
fn quantise(gain: f64, i: usize, acceleration_shift: u32) -> Option<i32> {
    let scaled = libm::round(gain * TURNS_PER_RAD * multiplier_scale(i, acceleration_shift));
    (1.0..=f64::from(i32::MAX))
        .contains(&scaled)
        .then_some(scaled as i32)
}

/// The parameter naming gain `i`.
const fn gain_parameter(i: usize) -> Parameter {
    match i {
        0 => Parameter::AngleGain,
        1 => Parameter::SpeedGain,
        _ => Parameter::AccelerationGain,
    }
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
    /// to zero or does not fit its 31 bits (`ConfigError::OutOfRange`: `l1` and `l2` from
    /// about 3.7e-10 to below pi/2, `l3` from about 2.2e-14 to below pi/2), and gains whose
    /// quantised values
    /// leave the stability region (`ConfigError::Unstable`, the same check as
    /// [`Gains::new`] on the values the integers represent).
    ///
    /// [`Gains::new`]: crate::Gains::new
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let quantised = gains.gains();
    /// assert!((quantised[2] / 0.000_34 - 1.0).abs() < 1e-5);
    /// // 1e-30 rounds to zero:
    /// let err = FixedGains::<3>::new([0.1578, 0.0126, 1e-30], 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(gains: [f64; N], sample_period_s: f64) -> Result<Self, ConfigError> {
        let mut multiplier = [0; N];
        let mut acceleration_shift = if N > 2 {
            *ACCELERATION_SHIFTS.start()
        } else {
            0
        };
        for (i, &gain) in gains.iter().enumerate() {
            let parameter = gain_parameter(i);
            if !gain.is_finite() {
                return Err(ConfigError::NotFinite(parameter));
            }
            if gain <= 0.0 {
                return Err(ConfigError::NotPositive(parameter));
            }
            if i == 2 {
                // The smallest shift whose multiplier fits: the most bits of l3.
                while acceleration_shift < *ACCELERATION_SHIFTS.end()
                    && gain * TURNS_PER_RAD * multiplier_scale(2, acceleration_shift)
                        >= f64::from(i32::MAX)
                {
                    acceleration_shift += 1;
                }
            }
            multiplier[i] =
                quantise(gain, i, acceleration_shift).ok_or(ConfigError::OutOfRange(parameter))?;
        }
        Self::from_constants(
            FixedConstants {
                multiplier,
                acceleration_shift,
            },
            sample_period_s,
        )
    }

    /// The fixed-point gains from their integer constants (as [`FixedGains::constants`]
    /// gives them) and the sample period (s), checked again as [`FixedGains::new`] checks
    /// its quantised gains: each multiplier positive and the acceleration's shift from 1 to
    /// 15 (0 for a 2nd-order observer) (`ConfigError::OutOfRange` naming the gain), and the
    /// loop they represent inside the stability region.
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let designed = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let embedded = FixedGains::<3>::from_constants(designed.constants(), 50e-6)?;
    /// assert_eq!(embedded, designed);
    /// let mut broken = designed.constants();
    /// broken.multiplier[2] = 0;
    /// let err = FixedGains::<3>::from_constants(broken, 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    ///
    /// A `const fn`: a firmware checks its constants (as `angletrack design --dtype fixed
    /// --format rust` prints them) when it compiles, into a `static`:
    ///
    /// ```
    /// use angletrack_core::{FixedGains, fixed::FixedConstants};
    /// const KALMAN: FixedConstants<3> = FixedConstants {
    ///     multiplier: [215_733_201, 17_225_845, 1_903_920_691],
    ///     acceleration_shift: 3,
    /// };
    /// static GAINS: FixedGains<3> = match FixedGains::from_constants(KALMAN, 50e-6) {
    ///     Ok(gains) => gains,
    ///     Err(_) => panic!("the fixed-point gains are refused"),
    /// };
    /// let designed = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    /// assert_eq!(GAINS, designed);
    /// ```
    ///
    /// Refused constants fail the build:
    ///
    /// ```compile_fail
    /// use angletrack_core::{FixedGains, fixed::FixedConstants};
    /// const BROKEN: FixedConstants<2> = FixedConstants { multiplier: [0, 1], acceleration_shift: 0 };
    /// static GAINS: FixedGains<2> = match FixedGains::from_constants(BROKEN, 1e-4) {
    ///     Ok(gains) => gains,
    ///     Err(_) => panic!("the fixed-point gains are refused"),
    /// };
    /// ```
    pub const fn from_constants(
        constants: FixedConstants<N>,
        sample_period_s: f64,
    ) -> Result<Self, ConfigError> {
        let fixed = match Self::checked_constants(constants, sample_period_s) {
            Ok(fixed) => fixed,
            Err(e) => return Err(e),
        };
        match check_stability(&fixed.gains()) {
            Ok(()) => Ok(fixed),
            Err(e) => Err(e),
        }
    }

    /// The gains of `constants` at `sample_period_s` with the monitor's defaults for 2^14
    /// counts, their ranges checked by integer comparisons (not the loop's stability).
    pub(super) const fn checked_constants(
        constants: FixedConstants<N>,
        sample_period_s: f64,
    ) -> Result<Self, ConfigError> {
        if let Err(e) = super::words::check_sample_period(sample_period_s) {
            return Err(e);
        }
        let mut i = 0;
        while i < N {
            if constants.multiplier[i] < 1 {
                return Err(ConfigError::OutOfRange(gain_parameter(i)));
            }
            i += 1;
        }
        let shift = constants.acceleration_shift;
        let shift_in_range =
            *ACCELERATION_SHIFTS.start() <= shift && shift <= *ACCELERATION_SHIFTS.end();
        if (N > 2 && !shift_in_range) || (N < 3 && shift > 0) {
            return Err(ConfigError::OutOfRange(gain_parameter(2)));
        }
        Ok(Self {
            multiplier: constants.multiplier,
            acceleration_shift: shift,
            acceleration_scale: 1 << shift,
            sample_period_s,
            monitor: FixedThresholds::DEFAULT,
        })
    }
}

impl<const N: usize> FixedGains<N> {
    /// The gains the integers represent (`l_i = multiplier_i 2 pi / 2^s_i`,
    /// `s = (33, 33, 48 - k)`): the loop that runs, whose stability [`FixedGains::new`]
    /// checked.
    pub const fn gains(&self) -> [f64; N] {
        let mut gains = [0.0; N];
        let mut i = 0;
        while i < N {
            // Divided by a power of two: exact.
            let scale = multiplier_scale(i, self.acceleration_shift);
            gains[i] = self.multiplier[i] as f64 / scale * core::f64::consts::TAU;
            i += 1;
        }
        gains
    }

    /// The same gains with the diagnostics' thresholds for signals of
    /// `nominal_amplitude_counts` (from 16384 to 46341 counts: loss of signal, a quarter of
    /// it, must stay within the normalised range), or with the monitor off (`None`).
    /// A `const fn`, so that a firmware's `static` configuration carries its amplitude.
    ///
    /// ```
    /// use angletrack_core::fixed::FixedConstants;
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)?.with_monitor(Some(28_000.0))?;
    /// let err = gains.with_monitor(Some(2000.0)).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::NominalAmplitude);
    ///
    /// // A firmware's static, checked at compile time: 12-bit counts shifted by 4 (about
    /// // 28,800 counts of amplitude).
    /// static GAINS: FixedGains<2> = match FixedGains::<2>::from_constants(
    ///     FixedConstants { multiplier: [68_356_528, 1_640_557], acceleration_shift: 0 },
    ///     1e-4,
    /// ) {
    ///     Ok(gains) => match gains.with_monitor(Some(28_800.0)) {
    ///         Ok(gains) => gains,
    ///         Err(_) => panic!("bad amplitude"),
    ///     },
    ///     Err(_) => panic!("unstable gains"),
    /// };
    /// assert_eq!(GAINS.constants(), gains.constants());
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_monitor(
        self,
        nominal_amplitude_counts: Option<f64>,
    ) -> Result<Self, ConfigError> {
        self.with_monitor_tolerance(nominal_amplitude_counts, Some(0.1))
    }

    /// [`FixedGains::with_monitor`] with the roundness check's tolerance stated
    /// ([`FaultThresholds::magnitude_tolerance`](crate::FaultThresholds::magnitude_tolerance):
    /// a fraction of the nominal amplitude, 0.1 in `with_monitor`; `None`: no roundness
    /// check, for a nominal amplitude that is not the signal's, such as one brought up to
    /// the monitor's smallest).
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)?;
    /// let loose = gains.with_monitor_tolerance(Some(28_000.0), Some(0.3))?;
    /// let off = gains.with_monitor_tolerance(Some(16_384.0), None)?;
    /// let err = gains.with_monitor_tolerance(Some(28_000.0), Some(0.0)).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::MagnitudeTolerance);
    /// # let _ = (loose, off);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_monitor_tolerance(
        self,
        nominal_amplitude_counts: Option<f64>,
        magnitude_tolerance: Option<f64>,
    ) -> Result<Self, ConfigError> {
        let tolerance = match magnitude_tolerance {
            Some(r) if !r.is_finite() => {
                return Err(ConfigError::NotFinite(Parameter::MagnitudeTolerance));
            }
            Some(r) if r <= 0.0 => {
                return Err(ConfigError::NotPositive(Parameter::MagnitudeTolerance));
            }
            other => other,
        };
        let monitor = match nominal_amplitude_counts {
            None => FixedThresholds::OFF,
            Some(a) if !a.is_finite() => {
                return Err(ConfigError::NotFinite(Parameter::NominalAmplitude));
            }
            Some(a) if !(a >= 16384.0 && a <= 46341.0) => {
                return Err(ConfigError::OutOfRange(Parameter::NominalAmplitude));
            }
            Some(a) => FixedThresholds::for_amplitude(a, tolerance),
        };
        Ok(Self { monitor, ..self })
    }

    /// The integer constants (for [`FixedGains::from_constants`]).
    pub fn constants(&self) -> FixedConstants<N> {
        FixedConstants {
            multiplier: self.multiplier,
            acceleration_shift: self.acceleration_shift,
        }
    }

    /// The sample period `Ts` (s).
    pub fn sample_period(&self) -> f64 {
        self.sample_period_s
    }
}
