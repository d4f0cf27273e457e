//! [`FrontEndFaults`]: the resolver front end's own fault register (`docs/theory.md §13`),
//! apart from the observer's [`Faults`](crate::Faults): the excitation and the ADC, as the
//! AD2S1210 and the AM263Px resolver block report them.

/// A set of front-end fault flags (a bit set, `Copy`), carried by each
/// [`DemodulatedPair`](crate::DemodulatedPair) and latched by the
/// [`DemodulatorState`](crate::DemodulatorState).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FrontEndFaults(u8);

impl FrontEndFaults {
    /// No fault.
    pub const NONE: FrontEndFaults = FrontEndFaults(0);
    /// Loss of excitation: the carrier amplitude at the windings (in-phase and quadrature,
    /// both windings) is below its threshold: the excitation, a winding or the ADC is gone.
    pub const LOSS_OF_EXCITATION: FrontEndFaults = FrontEndFaults(1);
    /// Carrier phase drift: the carrier loop is out of lock, its phase error beyond its
    /// bound (44 degrees by default, the AD2S1210's lock range), or its frequency held at
    /// the bound of the carrier error allowed (the carrier beyond it).
    pub const PHASE_DRIFT: FrontEndFaults = FrontEndFaults(1 << 1);
    /// Clipping: a raw sample of the window was within the margin of the ADC's rails (or
    /// not a number).
    pub const CLIPPING: FrontEndFaults = FrontEndFaults(1 << 2);
    /// A winding open or shorted: one winding reads near zero where the observer's
    /// prediction puts at least half the amplitude on it, while the other winding agrees
    /// with the prediction ([`WindingCheck`](crate::WindingCheck)).
    pub const WINDING: FrontEndFaults = FrontEndFaults(1 << 4);

    /// Weak excitation: the carrier amplitude at the windings is below its threshold (0.7
    /// of nominal by default) though above the loss of excitation's.
    pub const WEAK_EXCITATION: FrontEndFaults = FrontEndFaults(1 << 3);

    /// The recorded excitation unusable: with samples of the excitation
    /// ([`Demodulator::push_with_excitation`](crate::Demodulator::push_with_excitation)), its
    /// carrier in this window is below an eighth of the windings' nominal amplitude (a flat
    /// or missing reference) or not a number, or the windings' delay after it is within 14
    /// degrees of a quarter turn from the expected delay (the half turn undecided), or none
    /// has been usable since the start-up.
    /// The carrier's half turn is then not checked against it: the one last resolved from
    /// it is kept, and before any, the expected delay's is taken.
    pub const EXCITATION_REFERENCE: FrontEndFaults = FrontEndFaults(1 << 5);

    /// The faults that invalidate a sample's measurement: the observer of a chain coasts on
    /// its prediction while one holds ([`FrontEndCheck`](crate::FrontEndCheck)). Clipping
    /// of one channel does not (the pair is distorted, not lost); both channels clipped is
    /// the [`FrontEndCheck`](crate::FrontEndCheck)'s own test. A weak excitation does not
    /// either: the pair is a measurement, with less margin.
    pub const INVALIDATING: FrontEndFaults =
        FrontEndFaults(Self::LOSS_OF_EXCITATION.0 | Self::WINDING.0);

    /// Every flag with its name, in bit order: the names [`Display`](core::fmt::Display)
    /// writes (the constant's name in lower case, words apart), for code that lists the
    /// flags, such as a binding that builds its own flag type from them.
    ///
    /// ```
    /// use angletrack_core::FrontEndFaults;
    /// assert_eq!(FrontEndFaults::NAMES[2], (FrontEndFaults::CLIPPING, "clipping"));
    /// let all = FrontEndFaults::NAMES.iter().fold(FrontEndFaults::NONE, |all, (f, _)| all | *f);
    /// assert_eq!(all.bits(), 0x3f);
    /// assert_eq!((FrontEndFaults::CLIPPING | FrontEndFaults::WINDING).to_string(), "clipping, winding");
    /// ```
    pub const NAMES: [(FrontEndFaults, &'static str); 6] = [
        (FrontEndFaults::LOSS_OF_EXCITATION, "loss of excitation"),
        (FrontEndFaults::PHASE_DRIFT, "phase drift"),
        (FrontEndFaults::CLIPPING, "clipping"),
        (FrontEndFaults::WEAK_EXCITATION, "weak excitation"),
        (FrontEndFaults::WINDING, "winding"),
        (FrontEndFaults::EXCITATION_REFERENCE, "excitation reference"),
    ];

    /// The raw bits (bit 0 loss of excitation, 1 phase drift, 2 clipping, 3 weak
    /// excitation, 4 winding, 5 excitation reference).
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// The flags from raw bits (unknown bits are kept: a newer front end's flags pass
    /// through).
    pub const fn from_bits(bits: u8) -> FrontEndFaults {
        FrontEndFaults(bits)
    }

    /// `true` when `self` and `other` share a flag.
    pub const fn intersects(self, other: FrontEndFaults) -> bool {
        self.0 & other.0 != 0
    }

    /// `true` when no flag is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// `true` when every flag of `other` is set in `self`.
    ///
    /// ```
    /// use angletrack_core::FrontEndFaults;
    /// let faults = FrontEndFaults::CLIPPING | FrontEndFaults::PHASE_DRIFT;
    /// assert!(faults.contains(FrontEndFaults::CLIPPING));
    /// assert!(!faults.contains(FrontEndFaults::LOSS_OF_EXCITATION));
    /// ```
    pub const fn contains(self, other: FrontEndFaults) -> bool {
        self.0 & other.0 == other.0
    }

    /// `flag` if `condition` holds, else no fault.
    #[inline(always)]
    pub(crate) const fn when(condition: bool, flag: FrontEndFaults) -> FrontEndFaults {
        FrontEndFaults(flag.0 * condition as u8)
    }
}

/// The flags by name (`none` when empty); unknown bits are not named.
impl core::fmt::Display for FrontEndFaults {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let set = FrontEndFaults::NAMES
            .iter()
            .filter(|(flag, _)| self.contains(*flag));
        crate::faults::write_names(f, set.map(|(_, name)| *name))
    }
}

/// The flags by name, as [`Display`](core::fmt::Display) writes them (`none` when empty).
#[cfg(feature = "defmt")]
impl defmt::Format for FrontEndFaults {
    fn format(&self, f: defmt::Formatter<'_>) {
        let set = FrontEndFaults::NAMES
            .iter()
            .filter(|(flag, _)| self.contains(*flag));
        crate::faults::format_names(f, set.map(|(_, name)| *name));
    }
}

impl core::ops::BitOr for FrontEndFaults {
    type Output = FrontEndFaults;
    fn bitor(self, rhs: FrontEndFaults) -> FrontEndFaults {
        FrontEndFaults(self.0 | rhs.0)
    }
}

impl core::ops::BitOrAssign for FrontEndFaults {
    fn bitor_assign(&mut self, rhs: FrontEndFaults) {
        self.0 |= rhs.0;
    }
}
