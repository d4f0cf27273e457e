//! The campaign's setups: a sensor kind on a number type, a chain as a user builds it for
//! the pairs (float units, 12-bit counts with their rails) or a resolver's windings.

use super::cases::FaultKind;
use super::resolver::ResolverKind;

/// How the pair reaches the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SensorKind {
    /// Pairs in float units (fractions of full scale), clipping looked for at the stated
    /// range of +-1.
    Units,
    /// 12-bit counts, offset binary (0 to 4095), through the core's `Input::Counts`.
    Unsigned(RailsKind),
    /// 12-bit counts, two's complement (-2048 to 2047).
    Signed(RailsKind),
    /// A resolver's raw carrier-modulated windings in 12-bit counts, through the crate's
    /// demodulator ([`super::resolver`]).
    Resolver(ResolverKind),
}

/// Where the chain looks for clipping (the core's `Rails`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RailsKind {
    /// `Rails::Stated`: the ADC's codes.
    Stated,
    /// `Rails::Measured`: the rails found on the samples.
    Measured,
}

/// The number type of the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NumberType {
    /// `Tracker<f32, Gains<f32, 3>>` with the winding check.
    F32,
    /// `Tracker<i16, FixedGains<3>>` (no winding check: the fixed-point chain has none).
    Fixed,
    /// `Tracker<f64, Gains<f64, 3>>` with the winding check, on the demodulated pairs with
    /// their front-end faults (as `angletrack track --carrier-hz` runs it).
    F64,
}

/// A sensor kind on a number type: a chain as a user builds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Setup {
    /// How the pair reaches the chain.
    pub sensor: SensorKind,
    /// The chain's number type.
    pub number: NumberType,
}

impl Setup {
    /// The campaign's setups: float units, and each pair of signedness and rails once per
    /// number type (the fixed-point chain takes counts only).
    pub const ALL: [Setup; 5] = [
        Setup {
            sensor: SensorKind::Units,
            number: NumberType::F32,
        },
        Setup {
            sensor: SensorKind::Unsigned(RailsKind::Stated),
            number: NumberType::F32,
        },
        Setup {
            sensor: SensorKind::Signed(RailsKind::Measured),
            number: NumberType::F32,
        },
        Setup {
            sensor: SensorKind::Unsigned(RailsKind::Measured),
            number: NumberType::Fixed,
        },
        Setup {
            sensor: SensorKind::Signed(RailsKind::Stated),
            number: NumberType::Fixed,
        },
    ];

    /// The resolver's setups: the excitation's samples recorded or not, the carrier delay
    /// stated (and, for the inverted excitation, not).
    pub const RESOLVER: [Setup; 3] = [
        Setup {
            sensor: SensorKind::Resolver(ResolverKind::ExcitationColumn),
            number: NumberType::F64,
        },
        Setup {
            sensor: SensorKind::Resolver(ResolverKind::DelayStated),
            number: NumberType::F64,
        },
        Setup {
            sensor: SensorKind::Resolver(ResolverKind::DelayNotStated),
            number: NumberType::F64,
        },
    ];

    /// The setup's name in the table.
    pub fn name(self) -> String {
        let number = match self.number {
            NumberType::F32 => "f32",
            NumberType::Fixed => "fixed",
            NumberType::F64 => "f64",
        };
        let rails = |r: RailsKind| match r {
            RailsKind::Stated => "stated",
            RailsKind::Measured => "measured",
        };
        match self.sensor {
            SensorKind::Units => format!("{number} units"),
            SensorKind::Unsigned(r) => format!("{number} unsigned counts, {} rails", rails(r)),
            SensorKind::Signed(r) => format!("{number} signed counts, {} rails", rails(r)),
            SensorKind::Resolver(kind) => format!("{number} resolver, {}", kind.name()),
        }
    }

    /// Whether `fault` can be fed to this setup (NaN only reaches float units; a carrier
    /// fault only a resolver, on the kinds [`CarrierFault::runs_on`](super::resolver::CarrierFault::runs_on) names).
    pub fn takes(self, fault: FaultKind) -> bool {
        match (self.sensor, fault) {
            (SensorKind::Resolver(kind), FaultKind::Carrier(fault)) => fault.runs_on(kind),
            (SensorKind::Resolver(_), _) | (_, FaultKind::Carrier(_)) => false,
            (sensor, fault) => fault != FaultKind::NotANumber || sensor == SensorKind::Units,
        }
    }
}
