//! What the two chains' C doors share: the inputs they take ([`ChainInput`]), the chain
//! structs' per-sample forms ([`CChain`]), and the bodies of their per-sample `extern "C"`
//! functions ([`track_input`], [`update_input`], [`estimate_of`]), which check the
//! pointers. The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use angletrack_core::{FrontEndFaults, TrackerInput, TrackerNumber};

use crate::demodulator::at_demodulated_pair_f32;
use crate::faults::AT_FAULT_INVALID_ARGUMENT;

/// An input of a chain on the numbers `V` (`f32`, or `i16` for fixed point).
pub(crate) trait ChainInput<V: TrackerNumber>: Copy {
    /// The core's input.
    type Core: TrackerInput<V>;
    /// Whether a chain with (`counts`) or without an ADC stage takes it.
    fn taken(counts: bool) -> bool;
    /// The input as the core's chain takes it.
    fn core(self) -> Self::Core;
}

/// A `(y_c, y_s)` pair in the observer's units (the ADC stage, if any, is for counts).
impl ChainInput<f32> for (f32, f32) {
    type Core = Self;
    #[inline(always)]
    fn taken(_: bool) -> bool {
        true
    }
    #[inline(always)]
    fn core(self) -> Self {
        self
    }
}

/// A demodulator's pair with the front-end faults of its window (`AT_FRONT_END_FAULT_*`
/// bits, the core's `FrontEndFaults`), for a chain without an ADC stage: the demodulator
/// took the counts, and the ADC's range, in counts, says nothing of a pair.
impl ChainInput<f32> for &at_demodulated_pair_f32 {
    type Core = ((f32, f32), FrontEndFaults);
    #[inline(always)]
    fn taken(counts: bool) -> bool {
        !counts
    }
    #[inline(always)]
    fn core(self) -> Self::Core {
        // The core's flags fit 8 bits; higher bits are none of its.
        let faults = FrontEndFaults::from_bits((self.faults & 0xff) as u8);
        ((self.y_c, self.y_s), faults)
    }
}

/// Raw counts `(raw_c, raw_s)` of the integer types C passes: for a chain with an ADC stage
/// (and `int16` samples, as they are, for a fixed-point chain without one).
macro_rules! counts {
    ($($number:ty: $($int:ty),* => $without_adc:expr;)*) => {$($(
        impl ChainInput<$number> for ($int, $int) {
            type Core = Self;
            #[inline(always)]
            fn taken(counts: bool) -> bool {
                counts || $without_adc
            }
            #[inline(always)]
            fn core(self) -> Self {
                self
            }
        }
    )*)*};
}

counts! {
    f32: i16, u16, i32 => false;
    i16: u16, i32 => false;
    i16: i16 => true;
}

/// A chain struct of the C API (`at_chain_f32`, `at_chain_fixed`), of either order, with
/// its state struct and its estimate.
pub(crate) trait CChain {
    /// The observer's numbers.
    type Number: TrackerNumber;
    /// One channel's state.
    type State;
    /// What an update reports.
    type Estimate;
    /// The estimate of a call whose arguments were refused.
    const INVALID: Self::Estimate;
    /// One sample through the chain on `state`, the state only: 0, or
    /// `AT_FAULT_INVALID_ARGUMENT` if refused (a chain not made, another build's state, an
    /// input the chain does not take), nothing changed.
    fn track<I: ChainInput<Self::Number>>(&self, state: &mut Self::State, input: I) -> u32;
    /// One sample, then the estimate; `INVALID` if refused.
    fn update<I: ChainInput<Self::Number>>(
        &self,
        state: &mut Self::State,
        input: I,
    ) -> Self::Estimate;
    /// The estimate `state` holds (a fresh state's for a fresh state); `INVALID` if refused.
    fn estimate(&self, state: &Self::State) -> Self::Estimate;
}

/// `$body` with `$c` the chain of the order `$chain` holds, `$s` the state of that order in
/// `$state` (the one held, or a fresh one) and `$x` the core's input of `$input` (of type
/// `$i`); `None`, nothing changed, if refused.
macro_rules! through {
    ($chain:expr, $state:expr, $i:ident, $input:expr, |$c:ident, $s:ident, $x:ident| $body:expr) => {
        match $chain.get() {
            Ok($crate::slot::ByOrder::Two($c)) if $i::taken($c.front_end.adc().is_some()) => {
                $state.of_order::<2>().ok().map(|$s| {
                    let $x = $input.core();
                    $body
                })
            }
            Ok($crate::slot::ByOrder::Three($c)) if $i::taken($c.front_end.adc().is_some()) => {
                $state.of_order::<3>().ok().map(|$s| {
                    let $x = $input.core();
                    $body
                })
            }
            _ => None,
        }
    };
}
pub(crate) use through;

/// The methods of a chain struct `$chain` holding the core's `$tracker<N>` of either order
/// and of its state struct `$state` holding `$tracker_state<N>`: the chain's `get` and
/// [`CChain`] (with the estimate `$estimate` on the numbers `$number`), the state's
/// `FRESH`, `of_order`, `held` and `clear_front_end_faults`. The per-sample forms check
/// the arguments (a chain not made, another build's state, an input the chain does not
/// take: `None`, nothing changed) and run the core's chain of the order held.
macro_rules! c_chain {
    ($chain:ty, $state:ty, $estimate:ty, $number:ty, $tracker:ident, $tracker_state:ident) => {
        impl $chain {
            /// The chain, if made by its constructor of this build.
            #[inline(always)]
            pub(crate) fn get(
                &self,
            ) -> Result<$crate::slot::ByOrder<&$tracker<2>, &$tracker<3>>, $crate::slot::Refused>
            {
                $crate::slot::Slot::either(self)
            }
        }

        impl $state {
            /// A fresh state (all zero, as C static memory holds).
            pub(crate) const FRESH: Self = Self::ZEROED;

            /// The state of a chain of order `N`: the one held, or a fresh one; refused if
            /// another build's.
            #[inline(always)]
            pub(crate) fn of_order<const N: usize>(
                &mut self,
            ) -> Result<&mut $tracker_state<N>, $crate::slot::Refused>
            where
                $tracker_state<N>: $crate::slot::Stored,
            {
                $crate::slot::Slot::slot_get_or_put(self, angletrack_core::ChainState::new)
            }

            /// The state held, of either order (none for a fresh state or another build's).
            pub(crate) fn held(
                &mut self,
            ) -> Option<$crate::slot::ByOrder<&mut $tracker_state<2>, &mut $tracker_state<3>>> {
                $crate::slot::Slot::either_mut(self)
            }

            /// Returns the front-end faults latched by the front-end checks
            /// (`AT_FRONT_END_FAULT_*` bits) and clears them; 0 for a fresh state (or
            /// another build's).
            pub(crate) fn clear_front_end_faults(&mut self) -> u32 {
                self.held().map_or(0, |s| {
                    u32::from($crate::slot::by_order!(s, |s| s.front_end.clear_faults()).bits())
                })
            }
        }

        impl $crate::door::CChain for $chain {
            type Number = $number;
            type State = $state;
            type Estimate = $estimate;
            const INVALID: $estimate = <$estimate>::INVALID;

            #[inline(always)]
            fn track<I: $crate::door::ChainInput<$number>>(
                &self,
                state: &mut $state,
                input: I,
            ) -> u32 {
                let tracked = $crate::door::through!(self, state, I, input, |c, s, x| {
                    $crate::door::out_of_line(c, s, x, |c, s, x| {
                        c.track(s, x);
                        0
                    })
                });
                tracked.unwrap_or($crate::faults::AT_FAULT_INVALID_ARGUMENT)
            }

            #[inline(always)]
            fn update<I: $crate::door::ChainInput<$number>>(
                &self,
                state: &mut $state,
                input: I,
            ) -> $estimate {
                let estimate = $crate::door::through!(self, state, I, input, |c, s, x| {
                    $crate::door::out_of_line(c, s, x, |c, s, x| c.update(s, x).into())
                });
                estimate.unwrap_or(Self::INVALID)
            }

            fn estimate(&self, state: &$state) -> $estimate {
                /// The estimate of a chain of order `N`.
                fn of<const N: usize>(c: &$tracker<N>, state: &$state) -> $estimate
                where
                    angletrack_core::Order<N>: angletrack_core::SupportedOrder,
                    $tracker_state<N>: $crate::slot::Stored,
                {
                    match $crate::slot::Slot::slot_get::<$tracker_state<N>>(state) {
                        Ok(s) => c.estimate(s).into(),
                        Err($crate::slot::Refused::NotInitialised) => {
                            c.estimate(&$tracker_state::<N>::new()).into()
                        }
                        Err($crate::slot::Refused::OtherBuild) => <$estimate>::INVALID,
                    }
                }
                self.get().map_or(Self::INVALID, |c| {
                    $crate::slot::by_order!(c, |c| of(c, state))
                })
            }
        }
    };
}
pub(crate) use c_chain;

/// `f(chain, state, input)` in a function of its own: the chain's body out of the door's
/// order dispatch, so that the compiler does not hoist both orders' set-up above the checks.
#[inline(never)]
pub(crate) fn out_of_line<C, S, X, R>(
    chain: &C,
    state: &mut S,
    input: X,
    f: impl FnOnce(&C, &mut S, X) -> R,
) -> R {
    f(chain, state, input)
}

/// The body of the `track` functions: 0, or `AT_FAULT_INVALID_ARGUMENT` (nothing changed)
/// for a NULL pointer or a refused argument.
///
/// # Safety
/// The header's contract.
#[inline(always)]
pub(crate) unsafe fn track_input<C: CChain, I: ChainInput<C::Number>>(
    chain: *const C,
    state: *mut C::State,
    input: I,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (chain.as_ref(), state.as_mut()) } {
        (Some(chain), Some(state)) => chain.track(state, input),
        _ => AT_FAULT_INVALID_ARGUMENT,
    }
}

/// The body of the `update` functions: the estimate, or `INVALID` (nothing changed) for a
/// NULL pointer or a refused argument.
///
/// # Safety
/// The header's contract.
#[inline(always)]
pub(crate) unsafe fn update_input<C: CChain, I: ChainInput<C::Number>>(
    chain: *const C,
    state: *mut C::State,
    input: I,
) -> C::Estimate {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (chain.as_ref(), state.as_mut()) } {
        (Some(chain), Some(state)) => chain.update(state, input),
        _ => C::INVALID,
    }
}

/// The body of the `estimate` functions.
///
/// # Safety
/// The header's contract.
pub(crate) unsafe fn estimate_of<C: CChain>(
    chain: *const C,
    state: *const C::State,
) -> C::Estimate {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    match unsafe { (chain.as_ref(), state.as_ref()) } {
        (Some(chain), Some(state)) => chain.estimate(state),
        _ => C::INVALID,
    }
}
