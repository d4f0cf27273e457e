//! The observers' configurations as plain C structs, which firmware may fill at start-up
//! or keep `const` in flash, checked by the chains' constructors: `at_gains_f32` (the float
//! observer's gains of order 2 or 3, sample period and fault thresholds
//! `at_fault_thresholds_f32`) and `at_fixed_gains` (the fixed-point observer's integer
//! constants). The core's `Gains<f32, N>` and `FixedGains<N>` are of one order each: the
//! order field chooses.

use angletrack_core::fixed::FixedConstants;
use angletrack_core::{ConfigError, FaultThresholds, FixedGains, Gains, Order, SupportedOrder};

use crate::mirror::mirror;
use crate::status::at_status;

/// `$body` (a `Result<_, ConfigError>`) with the constant `$n` the order `$order` (2 or
/// 3): the generic code is written once and instantiated for both; its error as a status,
/// `AT_ERR_ORDER` for another order.
macro_rules! with_order {
    ($order:expr, $n:ident => $body:expr) => {
        match $order {
            2 => {
                const $n: usize = 2;
                $body.map_err($crate::status::status_of)
            }
            3 => {
                const $n: usize = 3;
                $body.map_err($crate::status::status_of)
            }
            _ => Err($crate::status::AT_ERR_ORDER),
        }
    };
}
pub(crate) use with_order;

/// The gains, sample period and fault thresholds of an observer (order 2 or 3): filled by
/// `at_gains_f32_new` (checked, with the default fault thresholds) from the gains
/// `angletrack design --format c` writes, or written. Change `thresholds` as needed;
/// `at_chain_f32_new` checks it all (a zeroed one is refused: `AT_ERR_ORDER`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_gains_f32 {
    /// `l1`, `l2`, `l3` (dimensionless; `l3` unused at order 2).
    pub gains: [f32; 3],
    /// The observer's order, 2 or 3.
    pub order: u32,
    /// The sample period (s).
    pub sample_period_s: f32,
    /// The fault thresholds.
    pub thresholds: at_fault_thresholds_f32,
}

impl at_gains_f32 {
    /// The gains `l` (their number is the order) at `sample_period_s`, checked, with the
    /// core's default fault thresholds.
    pub(crate) fn of(l: &[f32], sample_period_s: f32) -> Result<Self, at_status> {
        let mut gains = [0.0; 3];
        gains[..l.len()].copy_from_slice(l);
        with_order!(l.len(), N => {
            let core = Gains::<f32, N>::new(core::array::from_fn(|i| l[i]), sample_period_s);
            core.map(|g| Self {
                gains,
                order: N as u32,
                sample_period_s,
                thresholds: g.fault_thresholds().into(),
            })
        })
    }

    /// The core's gains of order `N`, checked.
    pub(crate) fn core<const N: usize>(&self) -> Result<Gains<f32, N>, ConfigError>
    where
        Order<N>: SupportedOrder,
    {
        let gains = Gains::new(
            core::array::from_fn(|i| self.gains[i]),
            self.sample_period_s,
        )?;
        gains.with_fault_thresholds(self.thresholds.to_core())
    }
}

/// The integer constants of a fixed-point observer (order 2 or 3), as `angletrack design
/// --dtype fixed --format c` prints them: filled by `at_fixed_gains_from_constants`
/// (checked) or `at_fixed_gains_new` (quantised from float gains), or written;
/// `at_chain_fixed_new` checks them (a zeroed one is refused: `AT_ERR_ORDER`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_fixed_gains {
    /// The gains' integer multipliers (`m3` unused at order 2).
    pub multiplier: [i32; 3],
    /// The observer's order, 2 or 3.
    pub order: u32,
    /// The acceleration's shift (1 to 15 at order 3, 0 at order 2).
    pub acceleration_shift: u32,
    /// The sample period (s).
    pub sample_period_s: f64,
}

impl at_fixed_gains {
    /// The integer constants as the core's, of order `N`.
    pub(crate) fn constants<const N: usize>(&self) -> FixedConstants<N> {
        FixedConstants {
            multiplier: core::array::from_fn(|i| self.multiplier[i]),
            acceleration_shift: self.acceleration_shift,
        }
    }

    /// The constants `multiplier` (their number is the order), checked.
    pub(crate) fn checked(
        multiplier: &[i32],
        acceleration_shift: u32,
        sample_period_s: f64,
    ) -> Result<Self, at_status> {
        let mut out = Self {
            multiplier: [0; 3],
            order: multiplier.len() as u32,
            acceleration_shift,
            sample_period_s,
        };
        out.multiplier[..multiplier.len()].copy_from_slice(multiplier);
        with_order!(out.order, N => FixedGains::<N>::from_constants(out.constants(), sample_period_s).map(|_| out))
    }

    /// The float gains `l` (their number is the order) quantised, checked.
    pub(crate) fn quantised(l: &[f32], sample_period_s: f64) -> Result<Self, at_status> {
        with_order!(l.len(), N => {
            let gains = core::array::from_fn(|i| f64::from(l[i]));
            FixedGains::<N>::new(gains, sample_period_s).map(|g| {
                let constants = g.constants();
                let mut multiplier = [0; 3];
                multiplier[..N].copy_from_slice(&constants.multiplier);
                let (shift, sample_period_s) = (constants.acceleration_shift, g.sample_period());
                Self { multiplier, order: N as u32, acceleration_shift: shift, sample_period_s }
            })
        })
    }
}

mirror! {
    /// The thresholds of the diagnostics and of the input check, in the input's units
    /// (amplitudes) unless stated: the core's `FaultThresholds`. Start from
    /// `at_fault_thresholds_f32_for_amplitude(nominal)` (the defaults scaled to the nominal
    /// amplitude), change fields, and write it to `at_gains_f32::thresholds`.
    at_fault_thresholds_f32: FaultThresholds<f32> =
        |c: &Self| FaultThresholds::for_amplitude(c.nominal_amplitude);
    /// The amplitude of a healthy signal (default 1).
    nominal_amplitude: f32 = nominal_amplitude,
    /// A sample with `sqrt(y_c^2 + y_s^2)` above this is rejected (default 4 x nominal).
    max_input_amplitude: f32 = max_input_amplitude,
    /// A window's RMS amplitude below this: loss of signal (default 0.25 x nominal).
    loss_of_signal: f32 = loss_of_signal,
    /// A window's RMS amplitude below this: degradation of signal (default 0.5 x nominal).
    degradation_low: f32 = degradation_low,
    /// A window's RMS amplitude above this: degradation of signal (default 1.5 x nominal).
    degradation_high: f32 = degradation_high,
    /// A window's mean normalised phase error above this: loss of tracking (default 0.1).
    loss_of_tracking: f32 = loss_of_tracking,
    /// Estimated |speed| (rad/s) above this: loss of tracking; 0 for the default, a
    /// quarter turn per sample (`pi / (2 Ts)`).
    max_speed_rad_s: f32 = max_speed,
    /// 1 / W for the diagnostics' window of W used samples (1 / filter_factor rounded down
    /// to a power of two, at most 4096), in (0, 1] (default 1/16: a fault is flagged within
    /// 31 samples).
    filter_factor: f32 = filter_factor,
    /// The in-phase component at a window's end below this: false lock (default 0).
    false_lock: f32 = false_lock,
    /// Nonzero: compute the flags (loss of signal, degradation, loss of tracking, false
    /// lock); 0: only the input check runs (default 1).
    monitor: u32 = monitor,
    /// Nonzero: re-acquire the angle on a false lock (default 1).
    re_acquire: u32 = re_acquire,
    /// The roundness check's tolerance `r`: a window whose last pair's magnitude is outside
    /// `(1 +- r)` x nominal raises degradation of signal, held for
    /// `ROUNDNESS_HOLD_WINDOWS` windows (default 0.1); 0: no check.
    magnitude_tolerance: f32 = magnitude_tolerance,
    /// One sample's normalised phase error (about the sine of its angle error, electrical)
    /// above this: loss of tracking at once, on that sample, held while it stays above a
    /// fraction of this (the loop re-converging) and latched (default 0.05, positive).
    tracking_error: f32 = tracking_error,
}

impl at_fault_thresholds_f32 {
    /// The core's defaults scaled to `nominal_amplitude`.
    pub(crate) fn for_amplitude(nominal_amplitude: f32) -> Self {
        FaultThresholds::for_amplitude(nominal_amplitude).into()
    }
}
