//! The campaign's cases: a fault (with its onset), a speed profile, a sensor kind and a
//! number type ([`super::setup`]). Every case runs on the same healthy sensor, so that what
//! differs between a case and its healthy twin is the fault alone.

use core::f64::consts::PI;

pub use super::setup::{NumberType, RailsKind, SensorKind, Setup};

use super::resolver::CarrierFault;
use super::{SAMPLE_PERIOD_S, SAMPLES};
use crate::sim::{Motion, MotionProfile};

/// One winding's channel of a sin/cos pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// The cosine channel `y_c`.
    Cos,
    /// The sine channel `y_s`.
    Sin,
}

/// When a fault starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Onset {
    /// On the first sample: the observer never sees the healthy sensor.
    Start,
    /// Half-way through the run ([`super::MID_RUN`]; a resolver's
    /// [`super::resolver::MID_RUN_PERIODS`]), the observer locked on the healthy sensor.
    MidRun,
}

impl Onset {
    /// The index of the first faulty sample.
    pub fn sample(self) -> usize {
        match self {
            Onset::Start => 0,
            Onset::MidRun => super::MID_RUN,
        }
    }
}

/// What goes wrong. The channel faults and the signal faults are injected on the samples
/// ([`super::injection`]); the motion faults are the shaft's (a healthy sensor on an
/// abnormal motion, [`Speed::profile`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FaultKind {
    /// No fault: the baseline of the false alarms.
    Healthy,
    /// The channel reads exactly zero (a dead amplifier: mid-scale for counts).
    Dead(Channel),
    /// The channel open: near zero, a small offset and noise picked up by the open input.
    Open(Channel),
    /// The channel shorted to the other one: both inputs read the other channel's signal.
    Shorted(Channel),
    /// The channel stuck at its last value before the onset (a frozen ADC or mux).
    Stuck(Channel),
    /// The channel's sign flipped (a winding connected backwards).
    Reversed(Channel),
    /// The amplitude raised to 1.3 of the ADC's full scale (a gain error): both channels
    /// clip at the ADC's rails for a large part of each turn.
    Clipping,
    /// Both channels lose their excitation: offsets and noise only.
    LossOfExcitation,
    /// The excitation browns out to 20 % of its amplitude on both channels.
    BrownOut,
    /// A carrier-like signal (9.7 kHz, 0.25 of full scale) coupled into both channels alike.
    CommonMode,
    /// The sine channel's amplitude drops to 0.6 of the cosine's, beyond the calibration's
    /// bound on the mismatch (0.2).
    Imbalance,
    /// The sine channel picks up 0.3 rad of quadrature, beyond the calibration's bound
    /// (0.1 rad).
    Quadrature,
    /// The shaft's acceleration steps to `10^n` rad/s^2 (`n` the field) for as long as
    /// it takes to gain 2000 rad/s.
    AccelerationStep(u8),
    /// The shaft is driven at 2e6 rad/s^2 to 1.3 times the monitor's speed limit (a quarter
    /// turn per sample), and held there.
    BeyondSpeedLimit,
    /// Single absurd samples: every 500th sample from the onset, one channel reads a
    /// random value (anywhere in the ADC's range for counts, 2 to 50 full scales in units).
    Outliers,
    /// Every 500th sample from the onset, one channel is NaN (float units only).
    NotANumber,
    /// A fault on a resolver's carrier path (the resolver setups only,
    /// [`super::resolver`]).
    Carrier(CarrierFault),
}

impl FaultKind {
    /// The fault's name in the table.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::Healthy => "healthy",
            FaultKind::Dead(_) => "dead channel",
            FaultKind::Open(_) => "open channel",
            FaultKind::Shorted(_) => "shorted channel",
            FaultKind::Stuck(_) => "stuck channel",
            FaultKind::Reversed(_) => "reversed channel",
            FaultKind::Clipping => "clipping (gain 1.3 FS)",
            FaultKind::LossOfExcitation => "loss of excitation",
            FaultKind::BrownOut => "brown-out (20 %)",
            FaultKind::CommonMode => "common-mode carrier",
            FaultKind::Imbalance => "imbalance (0.6)",
            FaultKind::Quadrature => "quadrature (0.3 rad)",
            FaultKind::AccelerationStep(5) => "acceleration step 1e5",
            FaultKind::AccelerationStep(6) => "acceleration step 1e6",
            FaultKind::AccelerationStep(_) => "acceleration step",
            FaultKind::BeyondSpeedLimit => "beyond the speed limit",
            FaultKind::Outliers => "outliers",
            FaultKind::NotANumber => "NaN samples",
            FaultKind::Carrier(fault) => fault.name(),
        }
    }

    /// Why the signals cannot reveal the fault, if they cannot: such a fault is listed, not
    /// measured.
    pub fn undetectable(self) -> Option<&'static str> {
        match self {
            FaultKind::Reversed(_) => Some(
                "a pair with one winding reversed is the pair of the mirrored angle: \
                 it reads as the opposite direction of rotation, a valid signal",
            ),
            _ => None,
        }
    }

    /// Whether this is a run without a fault (the baseline of the false alarms), on a pair
    /// or on a resolver's carrier.
    pub fn is_healthy(self) -> bool {
        matches!(
            self,
            FaultKind::Healthy | FaultKind::Carrier(CarrierFault::Healthy)
        )
    }

    /// Whether the fault is a disturbance the chain must track through unflagged (a
    /// carrier harmonic within a driver's distortion): its own flagged samples are its
    /// false alarms, not those of its healthy twins.
    pub fn is_benign(self) -> bool {
        self == FaultKind::Carrier(CarrierFault::SecondHarmonic)
    }

    /// Whether the fault is the shaft's motion (then only on the constant speeds, whose
    /// profile it continues).
    pub fn is_motion(self) -> bool {
        matches!(
            self,
            FaultKind::AccelerationStep(_) | FaultKind::BeyondSpeedLimit
        )
    }

    /// The onsets the fault is run with: a motion fault mid-run only (from the start it
    /// would be another healthy profile), the single-sample faults mid-run only.
    pub fn onsets(self) -> &'static [Onset] {
        match self {
            FaultKind::Healthy | FaultKind::Carrier(CarrierFault::Healthy) => &[Onset::Start],
            FaultKind::AccelerationStep(_)
            | FaultKind::BeyondSpeedLimit
            | FaultKind::Outliers
            | FaultKind::NotANumber => &[Onset::MidRun],
            _ => &[Onset::Start, Onset::MidRun],
        }
    }

    /// Every fault of the campaign, the healthy baseline first, the resolver's carrier
    /// faults last.
    pub fn all() -> Vec<FaultKind> {
        let mut all = vec![FaultKind::Healthy];
        for channel in [Channel::Cos, Channel::Sin] {
            all.extend([
                FaultKind::Dead(channel),
                FaultKind::Open(channel),
                FaultKind::Shorted(channel),
                FaultKind::Stuck(channel),
                FaultKind::Reversed(channel),
            ]);
        }
        all.extend([
            FaultKind::Clipping,
            FaultKind::LossOfExcitation,
            FaultKind::BrownOut,
            FaultKind::CommonMode,
            FaultKind::Imbalance,
            FaultKind::Quadrature,
            FaultKind::AccelerationStep(5),
            FaultKind::AccelerationStep(6),
            FaultKind::BeyondSpeedLimit,
            FaultKind::Outliers,
            FaultKind::NotANumber,
        ]);
        all.extend(CarrierFault::all().into_iter().map(FaultKind::Carrier));
        all
    }
}

/// The monitor's speed limit: a quarter turn per sample (`FaultThresholds::max_speed`'s
/// default), half the largest trackable speed.
pub fn speed_limit_rad_s() -> f64 {
    PI / (2.0 * SAMPLE_PERIOD_S)
}

/// The shaft's healthy motion (electrical angle; the observer starts at rest at 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Speed {
    /// Standing still at 1 rad.
    Standstill,
    /// 50 Hz electrical (314 rad/s).
    Slow,
    /// 1 kHz electrical (6283 rad/s).
    Fast,
    /// Accelerating at 5e4 rad/s^2 from rest to 0.9 of the speed limit (at 57 % of the
    /// run), then held: the brown-out mid-run falls in the acceleration.
    RampToLimit,
    /// 50 Hz electrical, stepping to 100 Hz at 30 % of the run.
    SpeedStep,
    /// 3000 rad/s reversed at 1e5 rad/s^2 (60 ms) from 30 % of the run.
    Reversal,
    /// Accelerating at 2e4 rad/s^2 from rest throughout (the resolver's ramp: 4000 rad/s at
    /// its mid-run onset, 8000 rad/s, half its monitor's speed limit, at its end), so that a
    /// fault mid-run falls in the acceleration.
    Accelerating,
}

impl Speed {
    /// Every speed profile of the campaign.
    pub const ALL: [Speed; 6] = [
        Speed::Standstill,
        Speed::Slow,
        Speed::Fast,
        Speed::RampToLimit,
        Speed::SpeedStep,
        Speed::Reversal,
    ];

    /// The profile's name in the table.
    pub fn name(self) -> &'static str {
        match self {
            Speed::Standstill => "standstill",
            Speed::Slow => "50 Hz",
            Speed::Fast => "1 kHz",
            Speed::RampToLimit => "ramp to 0.9 limit",
            Speed::SpeedStep => "speed step",
            Speed::Reversal => "reversal",
            Speed::Accelerating => "accelerating",
        }
    }

    /// The constant speed (rad/s) of a constant profile, whose motion a motion fault
    /// continues; `None` for the others.
    pub fn constant(self) -> Option<f64> {
        match self {
            Speed::Standstill => Some(0.0),
            Speed::Slow => Some(2.0 * PI * 50.0),
            Speed::Fast => Some(2.0 * PI * 1000.0),
            _ => None,
        }
    }

    /// The profile of this speed under `fault` (a motion fault changes it from mid-run
    /// on), `None` where the pair does not apply (a motion fault on a profile that is not
    /// constant). Long enough for [`SAMPLES`] samples.
    pub fn profile(self, fault: FaultKind) -> Option<MotionProfile> {
        let run = SAMPLES as f64 * SAMPLE_PERIOD_S;
        let mid = super::MID_RUN as f64 * SAMPLE_PERIOD_S;
        if fault.is_motion() {
            let v = self.constant()?;
            let start = MotionProfile::new(1.0, v).then(Motion::ConstantSpeed {
                speed_rad_s: v,
                duration_s: mid,
            });
            return Some(match fault {
                FaultKind::AccelerationStep(n) => start
                    .then(Motion::ConstantAcceleration {
                        acceleration_rad_s2: 10f64.powi(n.into()),
                        duration_s: 2e3 / 10f64.powi(n.into()),
                    })
                    .then(Motion::ConstantSpeed {
                        speed_rad_s: v + 2e3,
                        duration_s: run,
                    }),
                _ => {
                    let target = 1.3 * speed_limit_rad_s();
                    start
                        .then(Motion::ConstantAcceleration {
                            acceleration_rad_s2: 2e6,
                            duration_s: (target - v) / 2e6,
                        })
                        .then(Motion::ConstantSpeed {
                            speed_rad_s: target,
                            duration_s: run,
                        })
                }
            });
        }
        let slow = 2.0 * PI * 50.0;
        Some(match self {
            Speed::Standstill | Speed::Slow | Speed::Fast => {
                let v = self.constant().unwrap_or(0.0);
                MotionProfile::new(1.0, v).then(Motion::ConstantSpeed {
                    speed_rad_s: v,
                    duration_s: run,
                })
            }
            Speed::RampToLimit => {
                let target = 0.9 * speed_limit_rad_s();
                MotionProfile::new(1.0, 0.0)
                    .then(Motion::ConstantAcceleration {
                        acceleration_rad_s2: 5e4,
                        duration_s: target / 5e4,
                    })
                    .then(Motion::ConstantSpeed {
                        speed_rad_s: target,
                        duration_s: run,
                    })
            }
            Speed::SpeedStep => MotionProfile::new(1.0, slow)
                .then(Motion::ConstantSpeed {
                    speed_rad_s: slow,
                    duration_s: 0.3 * run,
                })
                .then(Motion::ConstantSpeed {
                    speed_rad_s: 2.0 * slow,
                    duration_s: run,
                }),
            Speed::Accelerating => {
                MotionProfile::new(1.0, 0.0).then(Motion::ConstantAcceleration {
                    acceleration_rad_s2: 2e4,
                    duration_s: run,
                })
            }
            Speed::Reversal => MotionProfile::new(1.0, 3000.0)
                .then(Motion::ConstantSpeed {
                    speed_rad_s: 3000.0,
                    duration_s: 0.3 * run,
                })
                .then(Motion::Reversal {
                    acceleration_rad_s2: 1e5,
                })
                .then(Motion::ConstantSpeed {
                    speed_rad_s: -3000.0,
                    duration_s: run,
                }),
        })
    }
}

/// One case of the campaign.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Case {
    /// The fault.
    pub fault: FaultKind,
    /// When it starts.
    pub onset: Onset,
    /// The shaft's motion.
    pub speed: Speed,
    /// The chain.
    pub setup: Setup,
}

impl Case {
    /// The name of the case's row in the table: its fault's, but for a carrier fault whose
    /// row is split by the resolver's kind ([`CarrierFault::row_name`]).
    pub fn row_name(self) -> &'static str {
        match (self.fault, self.setup.sensor) {
            (FaultKind::Carrier(fault), SensorKind::Resolver(kind)) => fault.row_name(kind),
            (fault, _) => fault.name(),
        }
    }
}

/// Every case of the campaign that applies (the undetectable faults included: they are
/// listed from them, not measured): the pairs' cases, the healthy ones first, then the
/// resolver's (on [`super::resolver::SPEEDS`]).
pub fn all_cases() -> Vec<Case> {
    // The pairs' speeds and setups, then the resolver's: a resolver's setups take only the
    // carrier faults, none of them a motion fault.
    let kinds: [(&[Speed], &[Setup]); 2] = [
        (&Speed::ALL, &Setup::ALL),
        (&super::resolver::SPEEDS, &Setup::RESOLVER),
    ];
    let mut cases = Vec::new();
    for (speeds, setups) in kinds {
        for fault in FaultKind::all() {
            for &onset in fault.onsets() {
                for &speed in speeds {
                    if fault.is_motion() && speed.constant().is_none() {
                        continue;
                    }
                    for &setup in setups {
                        if setup.takes(fault) {
                            cases.push(Case {
                                fault,
                                onset,
                                speed,
                                setup,
                            });
                        }
                    }
                }
            }
        }
    }
    cases
}
