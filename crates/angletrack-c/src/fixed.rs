//! The fixed-point observer for cores without an FPU (the core's `FixedGains` and
//! `FixedState`): `at_fixed_gains` (the checked integer configuration of order 2 or 3, from
//! the integer constants `angletrack design --dtype fixed --format c` prints or from float
//! gains), `at_fixed_state` (one channel) and `at_fixed_estimate` (the integers the observer
//! reports: binary angle, turns, speed, acceleration, phase error, faults).

use core::mem::MaybeUninit;

use angletrack_core::fixed::FixedConstants;
use angletrack_core::{ConfigError, FixedEstimate, FixedGains, FixedState, Order, SupportedOrder};

use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::slot::{self, Refused, Stored};
use crate::status::{AT_ERR_ORDER, at_status, status_of_result};

/// The 8-byte words of an `at_fixed_gains`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_FIXED_GAINS_WORDS: usize = 8;
/// The 8-byte words of an `at_fixed_state`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_FIXED_STATE_WORDS: usize = 13;

/// The checked configuration of a fixed-point observer (order 2 or 3): the gains' integer
/// multipliers, the acceleration's shift, the sample period and the monitor's integer
/// thresholds. Made by `at_fixed_gains_from_constants` or `at_fixed_gains_new`; immutable
/// once made (but for `at_fixed_gains_set_monitor`), one serves any number of channels. Place
/// it anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_fixed_gains {
    /// Private: which Rust value `storage` holds (0: none).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_FIXED_GAINS_WORDS],
}

slot::slot_struct!(at_fixed_gains, AT_FIXED_GAINS_WORDS);

/// One fixed-point channel's mutable state: the integer state vector, the amplitude's
/// reciprocal, the turn count, the monitor's window and latched faults. A zeroed one (C
/// static memory) is a fresh state, as after `at_fixed_state_reset`: it initialises itself
/// from its first sample. It takes the order of the gains it is updated with (updated with
/// gains of another order than its last, it starts afresh). Place it anywhere; copy it by
/// assignment; never write its fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_fixed_state {
    /// Private: which Rust value `storage` holds (0: a fresh state).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_FIXED_STATE_WORDS],
}

slot::slot_struct!(at_fixed_state, AT_FIXED_STATE_WORDS);

/// What the fixed-point observer knows after a sample, in its integers.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct at_fixed_estimate {
    /// Binary angle: 2^32 per turn, `INT32_MIN` is -pi (rad = angle * 2 pi / 2^32).
    pub angle: i32,
    /// Whole turns since initialisation: the position is `turns + angle / 2^32` turns.
    pub turns: i64,
    /// Speed (2^-32 turn per sample).
    pub speed: i32,
    /// Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer.
    pub acceleration: i64,
    /// Normalised phase error (Q15: 32768 is 1), about the sine of the phase error.
    pub phase_error: i32,
    /// The monitor's last window's faults (`AT_FAULT_*` bits), or
    /// `AT_FAULT_INVALID_ARGUMENT` alone when the call's arguments were refused.
    pub faults: u32,
}

impl From<FixedEstimate> for at_fixed_estimate {
    fn from(e: FixedEstimate) -> Self {
        Self {
            angle: e.angle,
            turns: e.turns,
            speed: e.speed,
            acceleration: e.acceleration,
            phase_error: e.phase_error,
            faults: u32::from(e.faults.bits()),
        }
    }
}

impl at_fixed_estimate {
    /// The estimate of a call whose arguments were NULL, not made, or another build's.
    pub(crate) const INVALID: Self = Self {
        angle: 0,
        turns: 0,
        speed: 0,
        acceleration: 0,
        phase_error: 0,
        faults: AT_FAULT_INVALID_ARGUMENT,
    };
}

/// The fixed-point gains of either order, borrowed from an `at_fixed_gains`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum AnyFixed<'a> {
    /// A 2nd-order observer.
    Two(&'a FixedGains<2>),
    /// A 3rd-order observer.
    Three(&'a FixedGains<3>),
}

/// Evaluates `$body` with `$g` bound to the `&FixedGains<N>` of an [`AnyFixed`], whatever
/// its order.
macro_rules! with_fixed {
    ($any:expr, |$g:ident| $body:expr) => {
        match $any {
            $crate::fixed::AnyFixed::Two($g) => $body,
            $crate::fixed::AnyFixed::Three($g) => $body,
        }
    };
}
pub(crate) use with_fixed;

impl at_fixed_gains {
    /// The gains, if made by a constructor of this build.
    #[inline(always)]
    pub(crate) fn get(&self) -> Result<AnyFixed<'_>, Refused> {
        // One comparison selects the order; the checked read refuses the rest.
        if self.tag == <FixedGains<2> as Stored>::TAG {
            self.slot_get().map(AnyFixed::Two)
        } else {
            self.slot_get().map(AnyFixed::Three)
        }
    }

    /// Stores checked gains of either order; returns the status of the check (`self`
    /// unchanged on error).
    fn store<G: Stored>(&mut self, result: Result<G, ConfigError>) -> at_status {
        if let Ok(gains) = result {
            self.slot_put(gains);
        }
        status_of_result(result)
    }

    /// Checks the integer constants (`multiplier.len()` is the order) and stores them.
    pub(crate) fn set_constants(
        &mut self,
        multiplier: &[i32],
        acceleration_shift: u32,
        sample_period_s: f64,
    ) -> at_status {
        match *multiplier {
            [m1, m2] => self.store(FixedGains::<2>::from_constants(
                FixedConstants {
                    multiplier: [m1, m2],
                    acceleration_shift,
                },
                sample_period_s,
            )),
            [m1, m2, m3] => self.store(FixedGains::<3>::from_constants(
                FixedConstants {
                    multiplier: [m1, m2, m3],
                    acceleration_shift,
                },
                sample_period_s,
            )),
            _ => AT_ERR_ORDER,
        }
    }

    /// Quantises float gains (`gains.len()` is the order) and stores them.
    pub(crate) fn set_gains(&mut self, gains: &[f32], sample_period_s: f64) -> at_status {
        match *gains {
            [l1, l2] => self.store(FixedGains::<2>::new(
                [f64::from(l1), f64::from(l2)],
                sample_period_s,
            )),
            [l1, l2, l3] => self.store(FixedGains::<3>::new(
                [f64::from(l1), f64::from(l2), f64::from(l3)],
                sample_period_s,
            )),
            _ => AT_ERR_ORDER,
        }
    }

    /// The monitor's thresholds for `nominal_amplitude_counts`, or the monitor off for 0.
    pub(crate) fn set_monitor(&mut self, nominal_amplitude_counts: f64) -> at_status {
        let nominal = (nominal_amplitude_counts != 0.0).then_some(nominal_amplitude_counts);
        match self.get() {
            Ok(AnyFixed::Two(g)) => self.store(g.with_monitor(nominal)),
            Ok(AnyFixed::Three(g)) => self.store(g.with_monitor(nominal)),
            Err(refused) => refused.status(),
        }
    }
}

impl at_fixed_state {
    /// A fresh state (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The state of an observer of order `N`: the one held, or a fresh one if it held none
    /// or one of the other order; refused if another build's.
    #[inline(always)]
    pub(crate) fn of_order<const N: usize>(&mut self) -> Result<&mut FixedState<N>, Refused>
    where
        FixedState<N>: Stored,
    {
        self.slot_get_or_put(FixedState::new)
    }

    /// The estimate the state holds: a fresh state's (all zero) if it holds none, refused if
    /// another build's.
    pub(crate) fn estimate(&self) -> Result<at_fixed_estimate, Refused> {
        match self.slot_get::<FixedState<2>>() {
            Ok(s) => return Ok(FixedGains::estimate(s).into()),
            Err(Refused::OtherBuild) => return Err(Refused::OtherBuild),
            Err(Refused::NotInitialised) => {}
        }
        match self.slot_get::<FixedState<3>>() {
            Ok(s) => Ok(FixedGains::estimate(s).into()),
            Err(Refused::NotInitialised) => {
                Ok(FixedGains::<3>::estimate(&FixedState::new()).into())
            }
            Err(refused) => Err(refused),
        }
    }

    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        let faults = match self.tag {
            t if t == <FixedState<2> as Stored>::TAG => self.of_order::<2>().map(|s| {
                let f = s.latched_faults();
                s.clear_faults();
                f
            }),
            t if t == <FixedState<3> as Stored>::TAG => self.of_order::<3>().map(|s| {
                let f = s.latched_faults();
                s.clear_faults();
                f
            }),
            _ => return 0,
        };
        faults.map_or(0, |f| u32::from(f.bits()))
    }
}

/// One sample through `gains` on `state`, the state only: `false` if either was refused
/// (then nothing changed).
#[inline(always)]
pub(crate) fn track(
    gains: &at_fixed_gains,
    state: &mut at_fixed_state,
    y_c: i16,
    y_s: i16,
) -> bool {
    /// The sample through gains of order `N`.
    #[inline(always)]
    fn of<const N: usize>(g: &FixedGains<N>, state: &mut at_fixed_state, y_c: i16, y_s: i16) -> bool
    where
        Order<N>: SupportedOrder,
        FixedState<N>: Stored,
    {
        match state.of_order::<N>() {
            Ok(s) => {
                g.track(s, y_c, y_s);
                true
            }
            Err(_) => false,
        }
    }
    match gains.get() {
        Ok(any) => with_fixed!(any, |g| of(g, state, y_c, y_s)),
        Err(_) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::status::{AT_ERR_GAINS_2, AT_ERR_NOMINAL_AMPLITUDE, AT_ERR_SAMPLE_PERIOD_S, AT_OK};

    #[test]
    fn constants_and_gains_check_as_the_core() {
        let mut gains = at_fixed_gains::ZEROED;
        assert_eq!(gains.get().err(), Some(Refused::NotInitialised));
        assert_eq!(gains.set_gains(&[0.1578, 0.0126, 0.000_34], 50e-6), AT_OK);
        let designed = FixedGains::<3>::new(
            [0.1578f32.into(), 0.0126f32.into(), 0.000_34f32.into()],
            50e-6,
        )
        .unwrap()
        .constants();
        let mut again = at_fixed_gains::ZEROED;
        assert_eq!(
            again.set_constants(&designed.multiplier, designed.acceleration_shift, 50e-6),
            AT_OK
        );
        assert!(matches!(again.get(), Ok(AnyFixed::Three(g)) if g.constants() == designed));
        assert_eq!(
            again.set_constants(&[1, 1, 1], 0, 50e-6),
            AT_ERR_GAINS_2,
            "the shift of a 3rd-order observer is 1 to 15"
        );
        assert_eq!(again.set_constants(&[1, 1], 0, 0.0), AT_ERR_SAMPLE_PERIOD_S);
        assert_eq!(again.set_constants(&[1], 0, 1e-4), AT_ERR_ORDER);
        assert_eq!(again.set_monitor(2000.0), AT_ERR_NOMINAL_AMPLITUDE);
        assert_eq!(again.set_monitor(28_800.0), AT_OK);
        assert_eq!(again.set_monitor(0.0), AT_OK);
    }

    #[test]
    fn tracks_and_reads_the_estimate_on_demand() {
        let mut gains = at_fixed_gains::ZEROED;
        assert_eq!(gains.set_gains(&[0.05, 0.0012], 1e-4), AT_OK);
        let mut state = at_fixed_state::FRESH;
        assert_eq!(state.estimate(), Ok(at_fixed_estimate::default()));
        assert!(track(&gains, &mut state, 0, 16384));
        let e = state.estimate().unwrap();
        assert!((e.angle - (1 << 30)).abs() < 64, "{e:?}");
        assert!(!track(&at_fixed_gains::ZEROED, &mut state, 0, 16384));
        assert_eq!(state.clear_faults(), 0);
    }
}
