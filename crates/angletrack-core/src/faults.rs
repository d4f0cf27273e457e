//! [`Faults`]: the fault register of a sample and of a channel (latched), a bit set with
//! the flags of `docs/theory.md §10` and their names.

use core::fmt;

/// A set of fault flags (a bit set, `Copy`), as in the AD2S1210's fault register.
///
/// Each [`Estimate`](crate::Estimate) carries the monitor's flags of its last window (held
/// until the next one ends, `docs/theory.md §10`) and the bad-sample flag of its own
/// sample; the observer state also latches them until the caller clears them
/// ([`ObserverState::clear_faults`](crate::ObserverState::clear_faults)).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Faults(u8);

impl Faults {
    /// No fault.
    pub const NONE: Faults = Faults(0);
    /// Loss of signal: the RMS amplitude `sqrt(y_c^2 + y_s^2)` over the monitor's window is
    /// below the loss-of-signal threshold (sensor disconnected, excitation lost).
    pub const LOSS_OF_SIGNAL: Faults = Faults(1);
    /// Degradation of signal: the window's RMS amplitude is outside
    /// [degradation low, degradation high] (gain drift, saturation, a broken winding).
    pub const DEGRADATION_OF_SIGNAL: Faults = Faults(1 << 1);
    /// Loss of tracking: the sample's own phase-detector residual `|eps|` is above
    /// [`FaultThresholds::tracking_error`](crate::FaultThresholds::tracking_error), held while
    /// it stays above half of it (at once, on that sample); the window's mean
    /// phase-detector error is above its threshold, or
    /// the estimated speed at the window's end is above the monitor's speed threshold
    /// ([`FaultThresholds::max_speed`](crate::FaultThresholds::max_speed): by default a
    /// quarter turn per sample, half the largest trackable speed, `docs/theory.md §9`); or
    /// (float observers) a re-acquisition after a front-end fault of at most 64 samples
    /// jumped a quarter turn or more, held for the window under way and the next 16
    /// (`docs/theory.md §10`).
    pub const LOSS_OF_TRACKING: Faults = Faults(1 << 2);
    /// The sample was rejected (NaN, infinite, or amplitude above the input bound): the
    /// observer coasted on its prediction.
    pub const BAD_SAMPLE: Faults = Faults(1 << 3);
    /// A lock about 180 degrees off was detected (the in-phase component
    /// `y_c cos + y_s sin` at the window's end went below its threshold); with `re_acquire`
    /// on, the angle is re-acquired from `atan2`.
    pub const FALSE_LOCK: Faults = Faults(1 << 4);
    /// Amplitude mismatch between the channels, as the AD2S1210's degradation check: the
    /// online calibration's amplitude ratio `A_s / A_c` is further from 1 than its bound
    /// ([`CalibrationSettings`](crate::CalibrationSettings); flagged only while a
    /// [`Calibrator`](crate::Calibrator) is on).
    pub const AMPLITUDE_MISMATCH: Faults = Faults(1 << 5);
    /// An offset or the quadrature angle of the online calibration is beyond its bound
    /// ([`CalibrationSettings`](crate::CalibrationSettings); flagged only while a
    /// [`Calibrator`](crate::Calibrator) is on).
    pub const OFFSET_OR_QUADRATURE: Faults = Faults(1 << 6);
    /// A front-end fault: a stage of the chain before the observer flagged the sample (its
    /// own register says which: [`FrontEndFaults`](crate::FrontEndFaults), or the clipping
    /// of a [`FrontEndCheck`](crate::FrontEndCheck)). While the fault invalidates the
    /// measurement (loss of excitation, a winding open or shorted, both channels clipped)
    /// the observer did not use the sample: it coasted on its prediction.
    pub const FRONT_END: Faults = Faults(1 << 7);

    /// Every flag with its name, in bit order: the names [`Display`](fmt::Display) writes
    /// (the constant's name in lower case, words apart), for code that lists the flags, such
    /// as a binding that builds its own flag type from them.
    ///
    /// ```
    /// use angletrack_core::Faults;
    /// let (flag, name) = Faults::NAMES[3];
    /// assert_eq!((flag, name), (Faults::BAD_SAMPLE, "bad sample"));
    /// assert_eq!(Faults::NAMES.iter().fold(Faults::NONE, |all, (f, _)| all | *f).bits(), 0xff);
    /// ```
    pub const NAMES: [(Faults, &'static str); 8] = [
        (Faults::LOSS_OF_SIGNAL, "loss of signal"),
        (Faults::DEGRADATION_OF_SIGNAL, "degradation of signal"),
        (Faults::LOSS_OF_TRACKING, "loss of tracking"),
        (Faults::BAD_SAMPLE, "bad sample"),
        (Faults::FALSE_LOCK, "false lock"),
        (Faults::AMPLITUDE_MISMATCH, "amplitude mismatch"),
        (Faults::OFFSET_OR_QUADRATURE, "offset or quadrature"),
        (Faults::FRONT_END, "front end"),
    ];

    /// The raw bits (bit 0 loss of signal, 1 degradation of signal, 2 loss of tracking,
    /// 3 bad sample, 4 false lock, 5 amplitude mismatch, 6 offset or quadrature, 7 front end).
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// The flags from raw bits (every bit of a `u8` is a flag).
    ///
    /// ```
    /// use angletrack_core::Faults;
    /// let faults = Faults::from_bits_truncate(0x88);
    /// assert_eq!(faults, Faults::BAD_SAMPLE | Faults::FRONT_END);
    /// ```
    pub const fn from_bits_truncate(bits: u8) -> Faults {
        Faults(bits)
    }

    /// `true` when `self` and `other` share a flag.
    pub const fn intersects(self, other: Faults) -> bool {
        self.0 & other.0 != 0
    }

    /// `true` when no flag is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// `true` when every flag of `other` is set in `self`.
    pub const fn contains(self, other: Faults) -> bool {
        self.0 & other.0 == other.0
    }

    /// The union of two sets.
    pub const fn union(self, other: Faults) -> Faults {
        Faults(self.0 | other.0)
    }

    /// `flag` if `condition` holds, else no fault.
    #[inline(always)]
    pub(crate) const fn when(condition: bool, flag: Faults) -> Faults {
        Faults(flag.0 * condition as u8)
    }
}

impl core::ops::BitOr for Faults {
    type Output = Faults;
    fn bitor(self, rhs: Faults) -> Faults {
        self.union(rhs)
    }
}

impl core::ops::BitOrAssign for Faults {
    fn bitor_assign(&mut self, rhs: Faults) {
        self.0 |= rhs.0;
    }
}

impl fmt::Debug for Faults {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Faults({self})")
    }
}

/// The flags by name, as [`Display`](fmt::Display) writes them (`none` when empty).
#[cfg(feature = "defmt")]
impl defmt::Format for Faults {
    fn format(&self, f: defmt::Formatter<'_>) {
        format_names(
            f,
            Faults::NAMES
                .iter()
                .filter(|(flag, _)| self.contains(*flag))
                .map(|(_, name)| *name),
        );
    }
}

/// `names` apart by commas, `none` if there are none: a fault register for `defmt`.
#[cfg(feature = "defmt")]
pub(crate) fn format_names<'a>(f: defmt::Formatter<'_>, names: impl Iterator<Item = &'a str>) {
    let mut first = true;
    for name in names {
        if !first {
            defmt::write!(f, ", ");
        }
        defmt::write!(f, "{=str}", name);
        first = false;
    }
    if first {
        defmt::write!(f, "none");
    }
}

/// `names` apart by commas, `none` if there are none: a fault register's
/// [`Display`](fmt::Display).
pub(crate) fn write_names<'a>(
    f: &mut fmt::Formatter<'_>,
    names: impl Iterator<Item = &'a str>,
) -> fmt::Result {
    let mut first = true;
    for name in names {
        if !first {
            f.write_str(", ")?;
        }
        f.write_str(name)?;
        first = false;
    }
    if first {
        f.write_str("none")?;
    }
    Ok(())
}

impl fmt::Display for Faults {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_names(
            f,
            Faults::NAMES
                .iter()
                .filter(|(flag, _)| self.contains(*flag))
                .map(|(_, name)| *name),
        )
    }
}
