//! What the two chains' C doors share: the inputs they take ([`ChainInput`], [`Arg`]), the
//! chain structs' per-sample forms of either order or of one (written once for both chains
//! by `c_chain!`), and their per-sample `extern "C"` functions (`per_sample!`), which check
//! the pointers. The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use angletrack_core::{FrontEndFaults, TrackerInput, TrackerNumber};

use crate::chain::{ChainF32, StateF32, at_chain_f32, at_chain_state_f32, at_estimate_f32};
use crate::chain_fixed::{
    ChainFixed, StateFixed, at_chain_fixed, at_chain_state_fixed, at_fixed_estimate,
};
use crate::demodulator::at_demodulated_pair_f32;

/// An input of a chain on the numbers `V` (`f32`, or `i16` for fixed point).
pub(crate) trait ChainInput<V: TrackerNumber>: Copy {
    /// The core's input.
    type Core: TrackerInput<V>;
    /// Whether a chain with (`counts`) or without an ADC stage takes it.
    fn taken(counts: bool) -> bool;
    /// The input as the core's chain takes it.
    fn core(self) -> Self::Core;
}

/// An argument of a per-sample `extern "C"` function: the input, or a pointer to it.
pub(crate) trait Arg: Copy {
    /// The input.
    type Input;
    /// The input; `None` if refused (a NULL pointer).
    ///
    /// # Safety
    /// A pointer is NULL or valid for reads (the header's contract).
    unsafe fn input(self) -> Option<Self::Input>;
}

impl<T: Copy> Arg for (T, T) {
    type Input = Self;
    #[inline(always)]
    unsafe fn input(self) -> Option<Self> {
        Some(self)
    }
}

impl Arg for *const at_demodulated_pair_f32 {
    type Input = at_demodulated_pair_f32;
    #[inline(always)]
    unsafe fn input(self) -> Option<Self::Input> {
        // SAFETY: the caller's contract; NULL is checked by `as_ref`.
        unsafe { self.as_ref() }.copied()
    }
}

/// A demodulator's pair with the front-end faults of its window (`AT_FRONT_END_FAULT_*`
/// bits, the core's `FrontEndFaults`), for a chain without an ADC stage: the demodulator
/// took the counts, and the ADC's range, in counts, says nothing of a pair.
impl ChainInput<f32> for at_demodulated_pair_f32 {
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

/// Pairs `(c, s)` of the types C passes: floats in the observer's units for any float chain
/// (the ADC stage, if any, is for counts), raw counts for a chain with an ADC stage (and
/// `int16` samples, as they are, for a fixed-point chain without one).
macro_rules! pairs {
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

pairs! {
    f32: f32 => true;
    f32: i16, u16, i32 => false;
    i16: u16, i32 => false;
    i16: i16 => true;
}

/// The methods of a chain struct `$chain` holding the core's `$tracker<N>` of either order
/// and of its state struct `$state` holding `$tracker_state<N>`, with the estimate
/// `$estimate` on the numbers `$number`: the chain's `get` and the bodies of its per-sample
/// `extern "C"` functions (`track`, `update`, `estimate` of either order, `track_order` of
/// one), which check the pointers and return `AT_FAULT_INVALID_ARGUMENT` (an estimate with
/// it), nothing changed, when refused: a NULL pointer, a chain not made (or of another
/// order), a state of another build, an input the chain does not take; the state's `FRESH`,
/// `of_order`, `held` and `clear_front_end_faults`.
macro_rules! c_chain {
    ($chain:ty, $state:ty, $estimate:ty, $number:ty, $tracker:ident, $tracker_state:ident) => {
        impl $chain {
            /// The chain, if made by its constructor of this build.
            pub(crate) fn get(
                &self,
            ) -> Result<$crate::slot::ByOrder<&$tracker<2>, &$tracker<3>>, $crate::slot::Refused>
            {
                $crate::slot::Slot::either(self)
            }

            /// The chain of order `N` held, with the input `I` it takes, and the state of
            /// that order in `state` (the one held, or a fresh one).
            #[inline(always)]
            fn with<'a, const N: usize, I: $crate::door::ChainInput<$number>>(
                &'a self,
                state: &'a mut $state,
                input: I,
            ) -> Option<(&'a $tracker<N>, &'a mut $tracker_state<N>, I::Core)> {
                let chain = $crate::slot::Slot::slot_layout::<$tracker<N>>(self)?;
                if !I::taken(chain.front_end.adc().is_some()) {
                    return None;
                }
                Some((chain, state.of_order::<N>().ok()?, input.core()))
            }

            /// One sample through the chain of order `N`, the state only: 0.
            #[inline(always)]
            fn track_n<const N: usize, I: $crate::door::ChainInput<$number>>(
                &self,
                state: &mut $state,
                input: I,
            ) -> Option<u32> {
                let (chain, state, input) = self.with::<N, I>(state, input)?;
                // The core's body out of line: the one a Rust firmware compiles, its
                // registers allocated without the door's checks (inlined below them, it
                // spilled the pointers they hold).
                Some($crate::door::out_of_line(chain, state, input, |c, s, x| {
                    c.track(s, x);
                    0
                }))
            }

            /// One sample through the chain of order `N`, then the estimate.
            #[inline(always)]
            fn update_n<const N: usize, I: $crate::door::ChainInput<$number>>(
                &self,
                state: &mut $state,
                input: I,
            ) -> Option<$estimate> {
                let (chain, state, input) = self.with::<N, I>(state, input)?;
                Some(chain.update(state, input).into())
            }

            /// The estimate `state` holds for the chain of order `N` (a fresh state's for a
            /// fresh state).
            fn estimate_n<const N: usize>(&self, state: &$state, _: ()) -> Option<$estimate> {
                let chain = $crate::slot::Slot::slot_layout::<$tracker<N>>(self)?;
                match $crate::slot::Slot::slot_get::<$tracker_state<N>>(state) {
                    Ok(s) => Some(chain.estimate(s).into()),
                    Err($crate::slot::Refused::NotInitialised) => {
                        Some(chain.estimate(&$tracker_state::<N>::new()).into())
                    }
                    Err($crate::slot::Refused::OtherBuild) => None,
                }
            }

            /// `two` or `three`, by the order of the chain held, in a function of its own
            /// (`out_of_line`); `None` for a chain not made.
            #[inline(always)]
            fn either_order<S, X, R>(
                &self,
                state: S,
                input: X,
                two: fn(&Self, S, X) -> Option<R>,
                three: fn(&Self, S, X) -> Option<R>,
            ) -> Option<R> {
                match self.get() {
                    Ok($crate::slot::ByOrder::Two(_)) => {
                        $crate::door::out_of_line(self, state, input, two)
                    }
                    Ok($crate::slot::ByOrder::Three(_)) => {
                        $crate::door::out_of_line(self, state, input, three)
                    }
                    Err(_) => None,
                }
            }

            /// The body of the `track` functions of either order.
            ///
            /// # Safety
            /// The header's contract.
            #[inline(always)]
            pub(crate) unsafe fn track<
                A: $crate::door::Arg<Input: $crate::door::ChainInput<$number>>,
            >(
                chain: *const Self,
                state: *mut $state,
                input: A,
            ) -> u32 {
                // SAFETY: the caller's contract; NULL is checked by `as_ref`, `as_mut` and `input`.
                match unsafe { (chain.as_ref(), state.as_mut(), input.input()) } {
                    (Some(c), Some(s), Some(x)) => c.either_order(
                        s,
                        x,
                        Self::track_n::<2, A::Input>,
                        Self::track_n::<3, A::Input>,
                    ),
                    _ => None,
                }
                .unwrap_or_else($crate::door::refused)
            }

            /// The body of the `track` functions of order `N`: the checks, then the chain's
            /// body, no dispatch.
            ///
            /// # Safety
            /// The header's contract.
            #[inline(always)]
            #[allow(dead_code, reason = "the float chain has no per-order functions")]
            pub(crate) unsafe fn track_order<
                const N: usize,
                A: $crate::door::Arg<Input: $crate::door::ChainInput<$number>>,
            >(
                chain: *const Self,
                state: *mut $state,
                input: A,
            ) -> u32 {
                // SAFETY: the caller's contract; NULL is checked by `as_ref`, `as_mut` and `input`.
                match unsafe { (chain.as_ref(), state.as_mut(), input.input()) } {
                    (Some(c), Some(s), Some(x)) => c.track_n::<N, A::Input>(s, x),
                    _ => None,
                }
                .unwrap_or_else($crate::door::refused)
            }

            /// The body of the `update` functions: the estimate.
            ///
            /// # Safety
            /// The header's contract.
            #[inline(always)]
            pub(crate) unsafe fn update<
                A: $crate::door::Arg<Input: $crate::door::ChainInput<$number>>,
            >(
                chain: *const Self,
                state: *mut $state,
                input: A,
            ) -> $estimate {
                // SAFETY: the caller's contract; NULL is checked by `as_ref`, `as_mut` and `input`.
                match unsafe { (chain.as_ref(), state.as_mut(), input.input()) } {
                    (Some(c), Some(s), Some(x)) => c.either_order(
                        s,
                        x,
                        Self::update_n::<2, A::Input>,
                        Self::update_n::<3, A::Input>,
                    ),
                    _ => None,
                }
                .unwrap_or_else(<$estimate>::invalid)
            }

            /// The body of the `estimate` functions: the estimate `state` holds (a fresh
            /// state's for a fresh state).
            pub(crate) fn estimate(&self, state: &$state) -> $estimate {
                self.either_order(state, (), Self::estimate_n::<2>, Self::estimate_n::<3>)
                    .unwrap_or_else(<$estimate>::invalid)
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
            ) -> Result<&mut $tracker_state<N>, $crate::slot::Refused> {
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
    };
}

// Here, at the boundary: the bodies check raw pointers.
c_chain!(
    at_chain_f32,
    at_chain_state_f32,
    at_estimate_f32,
    f32,
    ChainF32,
    StateF32
);
c_chain!(
    at_chain_fixed,
    at_chain_state_fixed,
    at_fixed_estimate,
    i16,
    ChainFixed,
    StateFixed
);

/// `f(chain, state, input)` in a function of its own: the body of one order out of the
/// door's order dispatch, so that the compiler does not hoist both orders' set-up above the
/// checks.
#[inline(never)]
pub(crate) fn out_of_line<C, S, X, R>(chain: &C, state: S, input: X, f: fn(&C, S, X) -> R) -> R {
    f(chain, state, input)
}

/// `AT_FAULT_INVALID_ARGUMENT`, out of line: the per-sample path holds no constant for it
/// (opaque to the optimiser, which would otherwise load the constant before the checks).
#[cold]
#[inline(never)]
pub(crate) fn refused() -> u32 {
    core::hint::black_box(crate::faults::AT_FAULT_INVALID_ARGUMENT)
}

/// The per-sample `extern "C"` functions of the chain `$chain` with its state `$state`:
/// each `$name(args) -> ret = body(input)` is a function of the chain, the state and
/// `args`, whose body is the chain's `body` (`track`, `update`, or `track_order` with the
/// order `$n`) on `input`.
macro_rules! per_sample {
    ($chain:ident, $state:ty; $(
        $(#[$doc:meta])*
        $name:ident($($arg:ident: $t:ty),*) -> $ret:ty = $body:ident$(::<$n:literal>)?($input:expr);
    )*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// See the header's introduction.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            chain: *const $chain,
            state: *mut $state,
            $($arg: $t),*
        ) -> $ret {
            // SAFETY: the same contract.
            unsafe { $chain::$body::<$($n,)? _>(chain, state, $input) }
        }
    )*};
}
pub(crate) use per_sample;
