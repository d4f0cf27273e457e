//! The synchronous demodulator in `f32` (the core's `Demodulator` and `DemodulatorState`):
//! ADC samples of a resolver's windings, `N` per carrier period, to one `(y_c, y_s)` pair
//! per period, which the signal chain (`at_chain_f32_track`) then takes.
//! `at_demodulator_f32` holds the checked configuration for `N` = 8, 16 or 32 (the core's
//! type has its reference tables by value, so each `N` is its own type, told apart by the
//! tag), `at_demodulator_state_f32` one channel's state; `at_demodulator_settings_f32` and
//! `at_demodulated_pair_f32` are the plain C mirrors of the core's settings and pairs.

use core::mem::MaybeUninit;

use angletrack_core::{
    ConfigError, DemodulatedPair, Demodulator, DemodulatorSettings, DemodulatorState,
};

use crate::slot::{self, Refused, Stored};
use crate::status::{AT_ERR_SAMPLES_PER_PERIOD, at_status, status_of_result};

/// The 8-byte words of an `at_demodulator_f32`'s storage (checked against the Rust types at
/// compile time, on every target).
pub const AT_DEMODULATOR_F32_WORDS: usize = 40;
/// The 8-byte words of an `at_demodulator_state_f32`'s storage (checked against the Rust
/// type at compile time, on every target).
pub const AT_DEMODULATOR_STATE_F32_WORDS: usize = 16;

/// A pair's front-end fault: loss of excitation (the carrier amplitude at the windings
/// below its threshold).
pub const AT_FRONT_END_FAULT_LOSS_OF_EXCITATION: u32 = 1;
/// A pair's front-end fault: the tracked carrier delay drifted beyond its bound.
pub const AT_FRONT_END_FAULT_PHASE_DRIFT: u32 = 1 << 1;
/// A pair's front-end fault: a raw sample of the window was within the margin of the ADC's
/// rails (or not a number).
pub const AT_FRONT_END_FAULT_CLIPPING: u32 = 1 << 2;

/// The checked configuration of a synchronous demodulator, made by `at_demodulator_f32_new`
/// (reference tables, scale, thresholds). Immutable once made; place it anywhere; copy it by
/// assignment; never write its fields. A zeroed one is refused.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_demodulator_f32 {
    /// Private: which Rust value `storage` holds (0: none).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_DEMODULATOR_F32_WORDS],
}

slot::slot_struct!(at_demodulator_f32, AT_DEMODULATOR_F32_WORDS);

/// One channel's demodulator state: partial sums, the carrier delay, latched front-end
/// faults. A zeroed one is fresh (as after `at_demodulator_state_f32_reset`): its next
/// sample is the first of a carrier period (excitation phase 0). Place it anywhere; copy it
/// by assignment; never write its fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_demodulator_state_f32 {
    /// Private: which Rust value `storage` holds (0: a fresh state).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_DEMODULATOR_STATE_F32_WORDS],
}

slot::slot_struct!(at_demodulator_state_f32, AT_DEMODULATOR_STATE_F32_WORDS);

/// The demodulator's settings (the core's `DemodulatorSettings`): start from
/// `at_demodulator_settings_f32_new`, which fills in the defaults.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_demodulator_settings_f32 {
    /// The excitation carrier frequency (Hz); the ADC samples `N` times per period.
    pub carrier_hz: f32,
    /// A winding's nominal carrier amplitude at the ADC (counts, peak): the pairs are
    /// divided by it (nominal amplitude 1).
    pub carrier_amplitude_counts: f32,
    /// The lowest ADC code.
    pub adc_min_code: f32,
    /// The highest ADC code.
    pub adc_max_code: f32,
    /// A raw sample within this many counts of a rail counts as clipped (default 1/256 of
    /// the range).
    pub clip_margin_counts: f32,
    /// Loss of excitation below this carrier amplitude, relative to nominal (default 0.25).
    pub loss_of_excitation: f32,
    /// Phase drift beyond this (rad) from the start-up delay (default 44 degrees).
    pub phase_drift_bound_rad: f32,
    /// The delay (rad) the start-up estimate is resolved around (default 0).
    pub expected_delay_rad: f32,
    /// The fraction of each period's delay error applied after start-up (default 0.01).
    pub delay_tracking_factor: f32,
    /// The carrier periods the start-up delay estimate averages (default 16).
    pub startup_periods: u32,
}

impl From<DemodulatorSettings<f32>> for at_demodulator_settings_f32 {
    fn from(s: DemodulatorSettings<f32>) -> Self {
        Self {
            carrier_hz: s.carrier_hz,
            carrier_amplitude_counts: s.carrier_amplitude_counts,
            adc_min_code: s.adc_min_code,
            adc_max_code: s.adc_max_code,
            clip_margin_counts: s.clip_margin_counts,
            loss_of_excitation: s.loss_of_excitation,
            phase_drift_bound_rad: s.phase_drift_bound_rad,
            expected_delay_rad: s.expected_delay_rad,
            delay_tracking_factor: s.delay_tracking_factor,
            startup_periods: s.startup_periods,
        }
    }
}

impl at_demodulator_settings_f32 {
    /// The core's settings, field by field (from the core's defaults for the same carrier
    /// and ADC, so that fields it may add keep them).
    fn to_core(self) -> DemodulatorSettings<f32> {
        let mut s = DemodulatorSettings::new(
            self.carrier_hz,
            self.carrier_amplitude_counts,
            self.adc_min_code,
            self.adc_max_code,
        );
        s.clip_margin_counts = self.clip_margin_counts;
        s.loss_of_excitation = self.loss_of_excitation;
        s.phase_drift_bound_rad = self.phase_drift_bound_rad;
        s.expected_delay_rad = self.expected_delay_rad;
        s.delay_tracking_factor = self.delay_tracking_factor;
        s.startup_periods = self.startup_periods;
        s
    }
}

/// One demodulated pair: the windings' envelopes at the centre of their window.
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
    /// The index of the window (window `p` starts at ADC sample `p N`).
    pub window: u64,
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
            faults: u32::from(p.faults.bits()),
        }
    }
}

impl Stored for Demodulator<f32, 8> {
    const TAG: u32 = 0x4154_4408; // "ATD", 8 samples per period
}
impl Stored for Demodulator<f32, 16> {
    const TAG: u32 = 0x4154_4410; // "ATD", 16
}
impl Stored for Demodulator<f32, 32> {
    const TAG: u32 = 0x4154_4420; // "ATD", 32
}
impl Stored for DemodulatorState<f32> {
    const TAG: u32 = 0x4154_6401; // "ATd"
}

/// A demodulator of any supported `N`, borrowed from an `at_demodulator_f32`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum AnyDemodulator<'a> {
    /// 8 samples per period.
    Eight(&'a Demodulator<f32, 8>),
    /// 16 samples per period.
    Sixteen(&'a Demodulator<f32, 16>),
    /// 32 samples per period.
    ThirtyTwo(&'a Demodulator<f32, 32>),
}

/// Evaluates `$body` with `$d` bound to the `&Demodulator<f32, N>` of an
/// [`AnyDemodulator`], whatever its `N`.
macro_rules! with_demodulator {
    ($any:expr, |$d:ident| $body:expr) => {
        match $any {
            $crate::demodulator::AnyDemodulator::Eight($d) => $body,
            $crate::demodulator::AnyDemodulator::Sixteen($d) => $body,
            $crate::demodulator::AnyDemodulator::ThirtyTwo($d) => $body,
        }
    };
}
pub(crate) use with_demodulator;

impl at_demodulator_f32 {
    /// Checks `settings` for `samples_per_period` (8, 16 or 32) and stores the
    /// demodulator (`self` unchanged on error).
    pub(crate) fn set(
        &mut self,
        settings: &at_demodulator_settings_f32,
        samples_per_period: u32,
    ) -> at_status {
        let settings = settings.to_core();
        match samples_per_period {
            8 => self.store(Demodulator::<f32, 8>::new(settings)),
            16 => self.store(Demodulator::<f32, 16>::new(settings)),
            32 => self.store(Demodulator::<f32, 32>::new(settings)),
            _ => AT_ERR_SAMPLES_PER_PERIOD,
        }
    }

    /// Stores a checked demodulator; returns the status of the check.
    fn store<D: Stored>(&mut self, result: Result<D, ConfigError>) -> at_status {
        if let Ok(demodulator) = result {
            self.slot_put(demodulator);
        }
        status_of_result(result)
    }

    /// The demodulator, if made by `at_demodulator_f32_new` of this build.
    #[inline(always)]
    pub(crate) fn get(&self) -> Result<AnyDemodulator<'_>, Refused> {
        match self.slot_get() {
            Ok(d) => return Ok(AnyDemodulator::Eight(d)),
            Err(Refused::OtherBuild) => return Err(Refused::OtherBuild),
            Err(Refused::NotInitialised) => {}
        }
        match self.slot_get() {
            Ok(d) => return Ok(AnyDemodulator::Sixteen(d)),
            Err(Refused::OtherBuild) => return Err(Refused::OtherBuild),
            Err(Refused::NotInitialised) => {}
        }
        self.slot_get().map(AnyDemodulator::ThirtyTwo)
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
