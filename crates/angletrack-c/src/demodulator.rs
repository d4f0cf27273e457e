//! The demodulator in `f32` (the core's `Demodulator` and `DemodulatorState`): ADC samples
//! of a resolver's windings (and optionally of the excitation) at any rate of at least 4 per
//! carrier period, to one `(y_c, y_s)` pair per tracked carrier period, which the signal
//! chain (`at_chain_f32_track`) then takes. `at_demodulator_f32` holds the checked
//! configuration, `at_demodulator_state_f32` one channel's state; `at_demodulator_settings_f32`
//! and `at_demodulated_pair_f32` are the plain C mirrors of the core's settings and pairs.

use angletrack_core::{DemodulatedPair, Demodulator, DemodulatorSettings, DemodulatorState};

use crate::chain::at_chain_f32;
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::mirror::mirror;
use crate::slot::{self, Refused, Slot, Stored, by_order};
use crate::status::{at_status, status_of_result};

/// The 8-byte words of an `at_demodulator_f32`'s storage (checked against the Rust types at
/// compile time, on every target).
pub const AT_DEMODULATOR_F32_WORDS: usize = 9;
/// The 8-byte words of an `at_demodulator_state_f32`'s storage (checked against the Rust
/// type at compile time, on every target).
pub const AT_DEMODULATOR_STATE_F32_WORDS: usize = 24;

/// A pair's front-end fault: loss of excitation (the carrier amplitude at the windings
/// below its threshold).
pub const AT_FRONT_END_FAULT_LOSS_OF_EXCITATION: u32 = 1;
/// A pair's front-end fault: the tracked carrier delay drifted beyond its bound.
pub const AT_FRONT_END_FAULT_PHASE_DRIFT: u32 = 1 << 1;
/// A pair's front-end fault: a raw sample of the window was within the margin of the ADC's
/// rails (or not a number).
pub const AT_FRONT_END_FAULT_CLIPPING: u32 = 1 << 2;
/// A pair's front-end fault: weak excitation (the carrier amplitude at the windings below
/// its threshold, above the loss of excitation's).
pub const AT_FRONT_END_FAULT_WEAK_EXCITATION: u32 = 1 << 3;

/// A front-end fault: a winding open or shorted (the chain's winding check,
/// `at_chain_f32_with_winding_check`).
pub const AT_FRONT_END_FAULT_WINDING: u32 = 1 << 4;

/// A pair's front-end fault: the recorded excitation (`at_demodulator_f32_push_with_excitation`)
/// unusable in this window (its carrier below an eighth of the windings' nominal amplitude,
/// or not a number), or none usable since the start-up: the carrier's half turn is not
/// checked against it.
pub const AT_FRONT_END_FAULT_EXCITATION_REFERENCE: u32 = 1 << 5;

slot::slot_struct! {
    /// The checked configuration of a synchronous demodulator, made by `at_demodulator_f32_new`
    /// (reference tables, scale, thresholds). Immutable once made; place it anywhere; copy it by
    /// assignment; never write its fields. A zeroed one is refused.
    at_demodulator_f32[AT_DEMODULATOR_F32_WORDS]
}

slot::slot_struct! {
    /// One channel's demodulator state: partial sums, the carrier delay, latched front-end
    /// faults. A zeroed one is fresh (as after `at_demodulator_state_f32_reset`): its next
    /// sample is the first of a carrier period (excitation phase 0). Place it anywhere; copy it
    /// by assignment; never write its fields.
    at_demodulator_state_f32[AT_DEMODULATOR_STATE_F32_WORDS]
}

mirror! {
    /// The demodulator's settings (the core's `DemodulatorSettings`): start from
    /// `at_demodulator_settings_f32_new`, which fills in the defaults.
    at_demodulator_settings_f32: DemodulatorSettings<f32> = |s: &Self| {
        let (amplitude, min, max) = (s.carrier_amplitude_counts, s.adc_min_code, s.adc_max_code);
        DemodulatorSettings::new(s.carrier_hz, s.adc_rate_hz, amplitude, min, max)
    };
    /// The declared excitation carrier frequency (Hz), tracked within `max_carrier_error`.
    carrier_hz: f32 = carrier_hz,
    /// The ADC's sample rate (Hz): at least 4 times the carrier, any ratio.
    adc_rate_hz: f32 = adc_rate_hz,
    /// A winding's nominal carrier amplitude at the ADC (counts, peak): the pairs are
    /// divided by it (nominal amplitude 1).
    carrier_amplitude_counts: f32 = carrier_amplitude_counts,
    /// The lowest ADC code.
    adc_min_code: f32 = adc_min_code,
    /// The highest ADC code.
    adc_max_code: f32 = adc_max_code,
    /// A raw sample within this many counts of a rail counts as clipped (default 1/256 of
    /// the range).
    clip_margin_counts: f32 = clip_margin_counts,
    /// Loss of excitation below this carrier amplitude, relative to nominal (default 0.25).
    loss_of_excitation: f32 = loss_of_excitation,
    /// Weak excitation below this carrier amplitude, relative to nominal (default 0.7).
    weak_excitation: f32 = weak_excitation,
    /// Phase drift (the carrier loop out of lock) beyond this phase error (rad, default
    /// 44 degrees, at most pi/2).
    phase_drift_bound_rad: f32 = phase_drift_bound_rad,
    /// The carrier delay (rad, positive when the windings lag) the half turn is resolved
    /// around (default 0): after the excitation when its samples are pushed, else after a
    /// carrier of phase 0 at the first sample.
    expected_delay_rad: f32 = expected_delay_rad,
    /// The carrier loop's natural frequency times the carrier period (rad, default 0.3).
    carrier_loop_bandwidth: f32 = carrier_loop_bandwidth,
    /// The largest relative carrier frequency error tracked (default 0.03).
    max_carrier_error: f32 = max_carrier_error,
    /// The carrier periods the loop acquires over before the first pair (default 24).
    startup_periods: u32 = startup_periods,
}

/// One demodulated pair: the windings' envelopes at the centroid of their window.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct at_demodulated_pair_f32 {
    /// The cosine winding's envelope, `~ cos theta` (nominal amplitude 1).
    pub y_c: f32,
    /// The sine winding's envelope, `~ sin theta`.
    pub y_s: f32,
    /// The cosine winding's quadrature component (about 0).
    pub quadrature_c: f32,
    /// The sine winding's quadrature component (about 0).
    pub quadrature_s: f32,
    /// The index of the window (start-up windows included).
    pub window: u64,
    /// The ADC sample index (from 0, the first sample pushed) at which the pair holds, its
    /// samples weighted by their share of it (the window's centroid at a multiple of 4
    /// samples a carrier period; exact at any ratio; divide by the ADC rate for seconds).
    pub centre_sample: f64,
    /// This window's front-end faults (`AT_FRONT_END_FAULT_*` bits).
    pub faults: u32,
}

impl From<DemodulatedPair<f32>> for at_demodulated_pair_f32 {
    fn from(p: DemodulatedPair<f32>) -> Self {
        Self {
            y_c: p.y_c,
            y_s: p.y_s,
            quadrature_c: p.quadrature_c,
            quadrature_s: p.quadrature_s,
            window: p.window,
            centre_sample: p.instant_sample(),
            faults: u32::from(p.faults.bits()),
        }
    }
}

// The storage is tight: the words the Rust values take, rounded up, on every target.
const _: () = assert!(size_of::<Demodulator<f32>>().div_ceil(8) == AT_DEMODULATOR_F32_WORDS);
const _: () =
    assert!(size_of::<DemodulatorState<f32>>().div_ceil(8) == AT_DEMODULATOR_STATE_F32_WORDS);

impl Stored for Demodulator<f32> {
    const TAG: u32 = 0x4154_4401; // "ATD"
}
impl Stored for DemodulatorState<f32> {
    const TAG: u32 = 0x4154_6401; // "ATd"
}

impl at_demodulator_f32 {
    /// Checks `settings` and stores the demodulator (`self` unchanged on error).
    pub(crate) fn set(&mut self, settings: &at_demodulator_settings_f32) -> at_status {
        let result = Demodulator::<f32>::new(settings.to_core());
        if let Ok(demodulator) = result {
            self.slot_put(demodulator);
        }
        status_of_result(result)
    }

    /// The demodulator, if made by `at_demodulator_f32_new` of this build.
    #[inline(always)]
    pub(crate) fn get(&self) -> Result<&Demodulator<f32>, Refused> {
        self.slot_get()
    }

    /// Whether `chain` runs at the pair rate: its observer's sample period is the declared
    /// carrier period (the core's `check_gains`).
    pub(crate) fn check_chain(&self, chain: &at_chain_f32) -> at_status {
        match (self.get(), chain.get()) {
            (Ok(d), Ok(c)) => by_order!(c, |c| status_of_result(d.check_gains(&c.observer))),
            (Err(refused), _) | (_, Err(refused)) => refused.status(),
        }
    }

    /// One sample of each winding (and of the excitation, if given) into `state`: 1 with
    /// the pair written to `out` once per tracked carrier period, else 0;
    /// `AT_FAULT_INVALID_ARGUMENT` for a demodulator not made or a struct of another build.
    #[inline(always)]
    pub(crate) fn push_to(
        &self,
        state: &mut at_demodulator_state_f32,
        raw_c: f32,
        raw_s: f32,
        excitation: Option<f32>,
        out: &mut at_demodulated_pair_f32,
    ) -> u32 {
        let (Ok(demodulator), Ok(state)) = (self.get(), state.get_mut()) else {
            return AT_FAULT_INVALID_ARGUMENT;
        };
        let pair = match excitation {
            Some(e) => demodulator.push_with_excitation(state, raw_c, raw_s, e),
            None => demodulator.push(state, raw_c, raw_s),
        };
        pair.map_or(0, |pair| {
            *out = pair.into();
            1
        })
    }
}

impl at_demodulator_state_f32 {
    /// A fresh state (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The state held, or a fresh one; refused if another build's.
    #[inline(always)]
    pub(crate) fn get_mut(&mut self) -> Result<&mut DemodulatorState<f32>, Refused> {
        self.slot_get_or_put(DemodulatorState::new)
    }
}
