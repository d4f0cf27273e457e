//! `at_gains_f32`: the checked configuration of an observer of order 2 or 3 (the core's
//! `Gains<f32, 2>` or `Gains<f32, 3>`, which a tag tells apart: the core refuses `l3 = 0`,
//! so order 2 is its own type, not order 3 with a zero gain), and its fault thresholds as
//! the plain C struct `at_fault_thresholds_f32`.

use core::mem::MaybeUninit;

use angletrack_core::{FaultThresholds, Gains};

use crate::slot::{self, ByOrder, Refused, Slot, by_order};
use crate::status::{AT_ERR_ORDER, at_status};

/// The 8-byte words of an `at_gains_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_GAINS_F32_WORDS: usize = 18;

/// The checked gains, sample period and fault thresholds of an observer (order 2 or 3),
/// made by `at_gains_f32_new`. Immutable once made: one serves any number of channels
/// (`at_chain_f32`). Place it anywhere (static memory, the stack); copy it by assignment;
/// never write its fields. A zeroed one is refused by every call (`AT_ERR_NOT_INITIALISED`,
/// or `AT_FAULT_INVALID_ARGUMENT` from an update).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_gains_f32 {
    /// Private: which Rust value `storage` holds.
    pub(crate) tag: u32,
    /// Private: the layout of the build that wrote it.
    pub(crate) layout: u32,
    /// Private: the Rust value.
    pub(crate) storage: [MaybeUninit<u64>; AT_GAINS_F32_WORDS],
}

slot::slot_struct!(at_gains_f32, AT_GAINS_F32_WORDS);

/// The gains of either order held by an `at_gains_f32`.
pub(crate) type AnyGains<'a> = ByOrder<&'a Gains<f32, 2>, &'a Gains<f32, 3>>;

impl at_gains_f32 {
    /// The gains, if made by `at_gains_f32_new` of this build.
    pub(crate) fn get(&self) -> Result<AnyGains<'_>, Refused> {
        self.either()
    }

    /// Checks `gains` (`order` of them) and the sample period, and stores them with the
    /// default fault thresholds; on error `self` is left as it was.
    pub(crate) fn set(&mut self, gains: &[f32], sample_period_s: f32) -> at_status {
        match *gains {
            [l1, l2] => self.slot_store(Gains::<f32, 2>::new([l1, l2], sample_period_s)),
            [l1, l2, l3] => self.slot_store(Gains::<f32, 3>::new([l1, l2, l3], sample_period_s)),
            _ => AT_ERR_ORDER,
        }
    }

    /// Replaces the fault thresholds (checked as the core does).
    pub(crate) fn set_fault_thresholds(
        &mut self,
        thresholds: &at_fault_thresholds_f32,
    ) -> at_status {
        let thresholds = (*thresholds).to_core();
        match self.get() {
            Ok(ByOrder::Two(g)) => self.slot_store(g.with_fault_thresholds(thresholds)),
            Ok(ByOrder::Three(g)) => self.slot_store(g.with_fault_thresholds(thresholds)),
            Err(refused) => refused.status(),
        }
    }

    /// The fault thresholds, if the gains were made.
    pub(crate) fn fault_thresholds(&self) -> Result<at_fault_thresholds_f32, Refused> {
        let thresholds = by_order!(self.get()?, |g| g.fault_thresholds());
        Ok(at_fault_thresholds_f32::from_core(&thresholds))
    }
}

/// The thresholds of the diagnostics and of the input check, in the input's units
/// (amplitudes) unless stated: the core's `FaultThresholds`. Start from
/// `at_fault_thresholds_f32_for_amplitude(nominal)` (the defaults scaled to the nominal
/// amplitude), change fields, then `at_gains_f32_set_fault_thresholds`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_fault_thresholds_f32 {
    /// The amplitude of a healthy signal (default 1).
    pub nominal_amplitude: f32,
    /// A sample with `sqrt(y_c^2 + y_s^2)` above this is rejected (default 4 x nominal).
    pub max_input_amplitude: f32,
    /// A window's RMS amplitude below this: loss of signal (default 0.25 x nominal).
    pub loss_of_signal: f32,
    /// A window's RMS amplitude below this: degradation of signal (default 0.5 x nominal).
    pub degradation_low: f32,
    /// A window's RMS amplitude above this: degradation of signal (default 1.5 x nominal).
    pub degradation_high: f32,
    /// A window's mean normalised phase error above this: loss of tracking (default 0.1).
    pub loss_of_tracking: f32,
    /// Estimated |speed| (rad/s) above this: loss of tracking; 0 for the default, a
    /// quarter turn per sample (`pi / (2 Ts)`).
    pub max_speed_rad_s: f32,
    /// 1 / W for the diagnostics' window of W used samples (1 / filter_factor rounded down
    /// to a power of two, at most 4096), in (0, 1] (default 1/16: a fault is flagged within
    /// 31 samples).
    pub filter_factor: f32,
    /// The in-phase component at a window's end below this: false lock (default 0).
    pub false_lock: f32,
    /// Nonzero: compute the flags (loss of signal, degradation, loss of tracking, false
    /// lock); 0: only the input check runs (default 1).
    pub monitor: u32,
    /// Nonzero: re-acquire the angle on a false lock (default 1).
    pub re_acquire: u32,
}

impl at_fault_thresholds_f32 {
    /// The core's defaults scaled to `nominal_amplitude`.
    pub(crate) fn for_amplitude(nominal_amplitude: f32) -> Self {
        Self::from_core(&FaultThresholds::for_amplitude(nominal_amplitude))
    }

    pub(crate) fn from_core(t: &FaultThresholds<f32>) -> Self {
        Self {
            nominal_amplitude: t.nominal_amplitude,
            max_input_amplitude: t.max_input_amplitude,
            loss_of_signal: t.loss_of_signal,
            degradation_low: t.degradation_low,
            degradation_high: t.degradation_high,
            loss_of_tracking: t.loss_of_tracking,
            max_speed_rad_s: t.max_speed.unwrap_or(0.0),
            filter_factor: t.filter_factor,
            false_lock: t.false_lock,
            monitor: u32::from(t.monitor),
            re_acquire: u32::from(t.re_acquire),
        }
    }

    /// The core's thresholds, field by field (assigned to the core's defaults, so that
    /// fields the core may add keep their defaults).
    fn to_core(self) -> FaultThresholds<f32> {
        let mut t = FaultThresholds::for_amplitude(self.nominal_amplitude);
        t.max_input_amplitude = self.max_input_amplitude;
        t.loss_of_signal = self.loss_of_signal;
        t.degradation_low = self.degradation_low;
        t.degradation_high = self.degradation_high;
        t.loss_of_tracking = self.loss_of_tracking;
        t.max_speed = (self.max_speed_rad_s != 0.0).then_some(self.max_speed_rad_s);
        t.filter_factor = self.filter_factor;
        t.false_lock = self.false_lock;
        t.monitor = self.monitor != 0;
        t.re_acquire = self.re_acquire != 0;
        t
    }
}
