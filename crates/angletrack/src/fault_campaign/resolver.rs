//! The resolver's raw windings for the campaign: the healthy sensor's envelopes on an
//! excitation carrier, sampled by a 12-bit ADC a whole number of times per carrier period,
//! with the carrier faults injected on the carrier path (the excitation, its harmonics, its
//! delay, a winding), and the excitation's own samples for the setups that record them.
//! The demodulation and the tracking are the crate's ([`super::resolver_run`]).

use core::f64::consts::{PI, TAU};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::cases::{Channel, Onset, Speed};
use super::{HEALTHY_SENSOR, SEED};
use crate::sim::{MAX_ANGLE_ERROR_HARMONICS, Scenario, SensorModel};

/// The excitation carrier's frequency (Hz): the pairs, one per carrier period, come at it.
pub const CARRIER_HZ: f64 = 10e3;

/// ADC samples per carrier period: few, so that a case is cheap, with the 2nd harmonic
/// (twice the carrier) well below the Nyquist frequency (4 times it); the demodulator takes
/// any ratio of at least 4.
pub const SAMPLES_PER_PERIOD: usize = 8;

/// Carrier periods per case: 0.4 s, about 4000 pairs.
pub const PERIODS: usize = 4_000;

/// The onset of the carrier faults that start mid-run, in carrier periods (0.2 s): on the
/// ramp, while the shaft accelerates.
pub const MID_RUN_PERIODS: usize = 2_000;

/// Pairs not judged at the start of each run: the demodulator's start-up and the loop's
/// acquisition from rest (0.1 s, as for the pairs' cases).
pub const START_UP_PAIRS: usize = 1_000;

/// The speed profiles of the resolver's cases: standing still, a constant 1 kHz electrical
/// and accelerating (the brown-out and the loss of excitation mid-run fall in the ramp).
pub const SPEEDS: [Speed; 3] = [Speed::Standstill, Speed::Fast, Speed::Accelerating];

/// The ADC's mid-scale code, where a winding without carrier reads.
pub const MID_SCALE: f64 = 2048.0;

/// A winding's carrier amplitude at envelope 1 (counts): the healthy sensor's amplitude
/// (0.8 of full scale). The demodulator is told it, so that its pairs' nominal amplitude is
/// 1.
pub const CARRIER_AMPLITUDE_COUNTS: f64 = HEALTHY_SENSOR.amplitude * MID_SCALE;

/// The excitation's carrier amplitude in its own column (counts).
pub const EXCITATION_COUNTS: f64 = 1500.0;

/// The windings' carrier delay after the excitation (rad), the one the user states: 20
/// degrees (the resolver's own phase shift, the windings behind the excitation).
pub const WINDING_DELAY_RAD: f64 = 20.0 * PI / 180.0;

/// The noise of each raw sample (counts RMS): about the healthy pair's 0.002 of full scale.
pub const NOISE_COUNTS: f64 = 4.0;

/// The 2nd harmonic's amplitude relative to the carrier (a driver's distortion).
pub const SECOND_HARMONIC: f64 = 0.15;

/// The carrier delay the delay fault adds beyond the stated one (rad): 60 degrees, within
/// the quarter turn the half turn is resolved in.
pub const ADDED_DELAY_RAD: f64 = 60.0 * PI / 180.0;

/// The healthy sensor's envelopes in the pairs' unit (its amplitude 1): the offsets,
/// imbalance and quadrature of [`HEALTHY_SENSOR`], its noise left to the raw samples.
pub const HEALTHY_ENVELOPES: SensorModel = SensorModel {
    amplitude: 1.0,
    offset_cos: HEALTHY_SENSOR.offset_cos / HEALTHY_SENSOR.amplitude,
    offset_sin: HEALTHY_SENSOR.offset_sin / HEALTHY_SENSOR.amplitude,
    amplitude_imbalance: HEALTHY_SENSOR.amplitude_imbalance,
    quadrature_error_rad: HEALTHY_SENSOR.quadrature_error_rad,
    third_harmonic: 0.0,
    angle_error_harmonics: [(0, 0.0, 0.0); MAX_ANGLE_ERROR_HARMONICS],
    noise_std: 0.0,
    adc_bits: 0,
    adc_full_scale: 1.25,
};

/// How the resolver's windings reach the demodulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ResolverKind {
    /// With the excitation's samples in their own column: the demodulator measures the
    /// windings' delay after it, the half turn taken within a quarter turn of the stated
    /// [`WINDING_DELAY_RAD`].
    ExcitationColumn,
    /// Without them: the windings' delay after a carrier of phase 0 at the first sample
    /// stated ([`WINDING_DELAY_RAD`]).
    DelayStated,
    /// Without them and without a stated delay: every pair carries the half turn
    /// unresolved status (the angle right or half a turn off), and its angle is judged
    /// modulo a half turn.
    DelayNotStated,
}

impl ResolverKind {
    /// The kind's name in the table.
    pub fn name(self) -> &'static str {
        match self {
            ResolverKind::ExcitationColumn => "excitation column",
            ResolverKind::DelayStated => "no excitation column, delay stated",
            ResolverKind::DelayNotStated => "no excitation column, no delay stated",
        }
    }
}

/// What goes wrong on a resolver's carrier path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CarrierFault {
    /// No fault: the resolver's baseline of the false alarms.
    Healthy,
    /// The excitation gone: both windings (and the excitation's column) read mid-scale and
    /// noise.
    LossOfExcitation,
    /// The excitation browns out to 20 % of its amplitude.
    BrownOut,
    /// The excitation carries a 2nd harmonic of [`SECOND_HARMONIC`] of its amplitude: within
    /// a driver's distortion, to be tracked through unflagged (not a wrong carrier
    /// frequency).
    SecondHarmonic,
    /// The excitation applied to the resolver inverted (its leads swapped), its column
    /// recording it as applied.
    InvertedExcitation,
    /// The windings' carrier delayed [`ADDED_DELAY_RAD`] beyond the stated delay (a filter
    /// between the resolver and the ADC).
    DelayBeyondStated,
    /// The winding reads mid-scale and noise (an open winding or a dead amplifier).
    DeadWinding(Channel),
}

/// The carrier faults that cannot be revealed, listed with their reason, not run.
pub const UNDETECTABLE: [(&str, &str); 3] = [
    (
        "resolver: inverted excitation, no column, delay stated",
        "the windings' carrier half a turn from the stated delay is that of the shaft half a \
         turn further (the same pairs negated): a valid signal",
    ),
    (
        "resolver: inverted excitation probe (the column alone)",
        "the windings half a turn after the recorded excitation are those of the shaft half a \
         turn further: state the probe's 180 degrees as the delay",
    ),
    (
        "resolver: carrier delay > 90 deg beyond the stated",
        "the delay is measured modulo a half turn and the half turn taken within a quarter turn \
         of the stated delay: the pairs are those of the shaft half a turn further",
    ),
];

impl CarrierFault {
    /// The fault's name in the table.
    pub fn name(self) -> &'static str {
        match self {
            CarrierFault::Healthy => "resolver: healthy",
            CarrierFault::LossOfExcitation => "resolver: loss of excitation",
            CarrierFault::BrownOut => "resolver: brown-out (20 %)",
            CarrierFault::SecondHarmonic => "resolver: carrier 2nd harmonic (15 %)",
            CarrierFault::InvertedExcitation => "resolver: inverted excitation",
            CarrierFault::DelayBeyondStated => "resolver: carrier delay 60 deg beyond the stated",
            CarrierFault::DeadWinding(_) => "resolver: dead winding",
        }
    }

    /// The name of the fault's row on `kind`: the inverted excitation's rows apart with the
    /// excitation column (measured) and without a stated delay (the half turn a status).
    pub fn row_name(self, kind: ResolverKind) -> &'static str {
        match (self, kind) {
            (CarrierFault::InvertedExcitation, ResolverKind::DelayNotStated) => {
                "resolver: inverted excitation, no column, no delay stated"
            }
            (CarrierFault::InvertedExcitation, _) => {
                "resolver: inverted excitation, excitation column"
            }
            (fault, _) => fault.name(),
        }
    }

    /// Every carrier fault, the healthy baseline first.
    pub fn all() -> Vec<CarrierFault> {
        vec![
            CarrierFault::Healthy,
            CarrierFault::LossOfExcitation,
            CarrierFault::BrownOut,
            CarrierFault::SecondHarmonic,
            CarrierFault::InvertedExcitation,
            CarrierFault::DelayBeyondStated,
            CarrierFault::DeadWinding(Channel::Cos),
            CarrierFault::DeadWinding(Channel::Sin),
        ]
    }

    /// Whether the fault runs on `kind`: without a stated delay only the healthy baseline
    /// and the inverted excitation (whose status that kind shows); the inverted excitation
    /// not on a stated delay without the column ([`UNDETECTABLE`]).
    pub fn runs_on(self, kind: ResolverKind) -> bool {
        match (self, kind) {
            (CarrierFault::Healthy, _) => true,
            (CarrierFault::InvertedExcitation, kind) => kind != ResolverKind::DelayStated,
            (_, kind) => kind != ResolverKind::DelayNotStated,
        }
    }
}

/// One speed's healthy resolver, shared by its cases: the true electrical angle and the
/// envelopes at each ADC sample, and the noise of each raw sample (the same for every case,
/// so that a case differs from its healthy twin by the fault alone).
#[derive(Debug, Clone)]
pub struct ResolverScenario {
    /// The true electrical angle (rad) at each ADC sample.
    pub angle_rad: Vec<f64>,
    /// The cosine winding's envelope (pairs' unit).
    pub envelope_c: Vec<f64>,
    /// The sine winding's envelope.
    pub envelope_s: Vec<f64>,
    /// The noise (counts) of the cosine winding, the sine winding and the excitation.
    pub noise: [Vec<f64>; 3],
}

/// The ADC's sample period (s).
pub fn adc_period_s() -> f64 {
    1.0 / (CARRIER_HZ * SAMPLES_PER_PERIOD as f64)
}

impl ResolverScenario {
    /// The healthy resolver following `speed`'s profile, over [`PERIODS`] carrier periods.
    pub fn generate(speed: Speed) -> Self {
        let profile = speed
            .profile(super::FaultKind::Healthy)
            .expect("a healthy profile");
        let n = PERIODS * SAMPLES_PER_PERIOD;
        let mut scenario = Scenario::generate(&profile, &HEALTHY_ENVELOPES, adc_period_s(), SEED)
            .expect("a valid scenario");
        for column in [
            &mut scenario.angle_rad,
            &mut scenario.y_c,
            &mut scenario.y_s,
        ] {
            column.truncate(n);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(SEED);
        let normal = Normal::new(0.0, NOISE_COUNTS).expect("a finite deviation");
        let mut noise = || {
            (0..n)
                .map(|_| normal.sample(&mut rng))
                .collect::<Vec<f64>>()
        };
        let noise = [noise(), noise(), noise()];
        Self {
            angle_rad: scenario.angle_rad,
            envelope_c: scenario.y_c,
            envelope_s: scenario.y_s,
            noise,
        }
    }

    /// The true electrical angle (rad) at `sample` (fractional ADC samples, linearly
    /// between two).
    pub fn angle_at(&self, sample: f64) -> f64 {
        let last = self.angle_rad.len() - 1;
        let k = (sample.max(0.0).floor() as usize).min(last - 1);
        let f = (sample - k as f64).clamp(0.0, 1.0);
        self.angle_rad[k] + f * (self.angle_rad[k + 1] - self.angle_rad[k])
    }
}

/// The raw samples of one case (counts, rounded and saturated at the 12-bit ADC's codes).
#[derive(Debug, Clone)]
pub struct Windings {
    /// The cosine winding.
    pub raw_c: Vec<f64>,
    /// The sine winding.
    pub raw_s: Vec<f64>,
    /// The excitation as its column records it.
    pub excitation: Vec<f64>,
}

/// A 12-bit ADC's code of `x` (counts about mid-scale).
fn code(x: f64) -> f64 {
    x.round().clamp(0.0, 4095.0)
}

/// The windings of `scenario` with `fault` from `onset` on.
pub fn windings(scenario: &ResolverScenario, fault: CarrierFault, onset: Onset) -> Windings {
    delayed_windings(scenario, fault, onset, ADDED_DELAY_RAD)
}

/// [`windings`] with `added_delay_rad` as the delay fault's added carrier delay.
pub fn delayed_windings(
    scenario: &ResolverScenario,
    fault: CarrierFault,
    onset: Onset,
    added_delay_rad: f64,
) -> Windings {
    let onset = match onset {
        Onset::Start => 0,
        Onset::MidRun => MID_RUN_PERIODS * SAMPLES_PER_PERIOD,
    };
    let n = scenario.angle_rad.len();
    let mut out = Windings {
        raw_c: Vec::with_capacity(n),
        raw_s: Vec::with_capacity(n),
        excitation: Vec::with_capacity(n),
    };
    let [noise_c, noise_s, noise_e] = &scenario.noise;
    for k in 0..n {
        let on = k >= onset;
        let faulty = |f: CarrierFault| on && fault == f;
        // The excitation's phase at the sample, clocked with the ADC.
        let psi = TAU * (k % SAMPLES_PER_PERIOD) as f64 / SAMPLES_PER_PERIOD as f64;
        let gain = if faulty(CarrierFault::LossOfExcitation) {
            0.0
        } else if faulty(CarrierFault::BrownOut) {
            0.2
        } else if faulty(CarrierFault::InvertedExcitation) {
            -1.0
        } else {
            1.0
        };
        let harmonic = if faulty(CarrierFault::SecondHarmonic) {
            SECOND_HARMONIC
        } else {
            0.0
        };
        // The excitation's waveform at phase `x`: its 2nd harmonic at an arbitrary phase.
        let carrier = |x: f64| gain * (x.sin() + harmonic * (2.0 * x + 0.5).sin());
        let delay = WINDING_DELAY_RAD
            + if faulty(CarrierFault::DelayBeyondStated) {
                added_delay_rad
            } else {
                0.0
            };
        let at_windings = CARRIER_AMPLITUDE_COUNTS * carrier(psi - delay);
        let dead = |channel: Channel| faulty(CarrierFault::DeadWinding(channel));
        let winding = |envelope: f64, channel: Channel| {
            if dead(channel) {
                0.0
            } else {
                envelope * at_windings
            }
        };
        let c = winding(scenario.envelope_c[k], Channel::Cos);
        let s = winding(scenario.envelope_s[k], Channel::Sin);
        out.raw_c.push(code(MID_SCALE + c + noise_c[k]));
        out.raw_s.push(code(MID_SCALE + s + noise_s[k]));
        let e = EXCITATION_COUNTS * carrier(psi);
        out.excitation.push(code(MID_SCALE + e + noise_e[k]));
    }
    out
}
