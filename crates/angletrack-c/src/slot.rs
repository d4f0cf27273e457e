//! Rust values kept in C memory: the private `storage` words and `tag` of the C API's
//! structs (`at_gains_f32`, `at_state_f32`, ...), which C code sizes from the header and may
//! place anywhere (static memory, the stack), copy by assignment and zero.
//!
//! The words are `MaybeUninit<u64>` (plain `uint64_t` in C): a Rust value written there
//! leaves its padding bytes uninitialised, and a copy of the struct by value in Rust (C
//! copies bytes) must not read those as integers. Miri checks this in the crate's tests.
//!
//! A slot holds one of a few `Copy` types, told apart by a tag that only [`put`] writes,
//! right after it wrote a value of that type: [`get`] and [`get_mut`] read the words as the
//! type only when the tag is the type's. A zeroed or never-initialised struct has no
//! type's tag (tag 0, or garbage that does not match), so it is refused or started afresh
//! instead of being read as a Rust value. The tags are 32-bit values unlikely to appear
//! by chance; the guarantee holds as long as C code writes the structs only through the
//! API (or copies a whole struct), as the header says.
#![allow(unsafe_code)]

use core::mem::{MaybeUninit, align_of, size_of};

use angletrack_core::{AdcScaling, Calibrator, Gains, ObserverState};

/// A type a slot can hold, with its tag. `Copy` types only: overwriting one drops nothing,
/// and a C copy of the words (with the tag) is a copy of the value.
pub(crate) trait Stored: Copy {
    /// The tag [`put`] writes beside a value of this type; never 0 (a zeroed slot).
    const TAG: u32;
}

impl Stored for Gains<f32, 2> {
    const TAG: u32 = 0x4154_4702; // "ATG", order 2
}
impl Stored for Gains<f32, 3> {
    const TAG: u32 = 0x4154_4703; // "ATG", order 3
}
impl Stored for ObserverState<f32, 2> {
    const TAG: u32 = 0x4154_5302; // "ATS", order 2
}
impl Stored for ObserverState<f32, 3> {
    const TAG: u32 = 0x4154_5303; // "ATS", order 3
}
impl Stored for AdcScaling<f32> {
    const TAG: u32 = 0x4154_4101; // "ATA"
}
impl Stored for Calibrator<f32> {
    const TAG: u32 = 0x4154_4301; // "ATC"
}

/// Fails to compile unless a `T` fits in `W` words of 8 bytes with their alignment: the
/// header's storage sizes are checked against the Rust types at every build, on every
/// target.
const fn fits<T, const W: usize>() -> bool {
    size_of::<T>() <= W * size_of::<u64>() && align_of::<T>() <= align_of::<u64>()
}

/// The value in `words` if `tag` is `T`'s.
pub(crate) fn get<T: Stored, const W: usize>(
    words: &[MaybeUninit<u64>; W],
    tag: u32,
) -> Option<&T> {
    const { assert!(fits::<T, W>(), "a C API struct's storage is too small") };
    if tag != T::TAG {
        return None;
    }
    // SAFETY: `words` is aligned for `T` and large enough (checked at compile time above),
    // and with the tag `T::TAG` it holds a valid `T`: only `put::<T>` writes that tag, after
    // writing a `T` there, and whatever C does with the struct (copy it whole, as the header
    // allows) keeps the pair together. The borrow of `words` bounds the reference's life.
    Some(unsafe { &*words.as_ptr().cast::<T>() })
}

/// The value in `words` if `tag` is `T`'s, else `start()` stored there (and tagged).
pub(crate) fn get_or_put<'a, T: Stored, const W: usize>(
    words: &'a mut [MaybeUninit<u64>; W],
    tag: &mut u32,
    start: impl FnOnce() -> T,
) -> &'a mut T {
    const { assert!(fits::<T, W>(), "a C API struct's storage is too small") };
    let place = words.as_mut_ptr().cast::<T>();
    if *tag != T::TAG {
        // SAFETY: as in `put`.
        unsafe { place.write(start()) };
        *tag = T::TAG;
    }
    // SAFETY: the words hold a valid `T` (the tag is `T`'s: see `get`, or it was just
    // written); the exclusive borrow of `words` makes the reference unique.
    unsafe { &mut *place }
}

/// Stores `value` in `words` and tags them as `T`.
pub(crate) fn put<T: Stored, const W: usize>(
    words: &mut [MaybeUninit<u64>; W],
    tag: &mut u32,
    value: T,
) {
    const { assert!(fits::<T, W>(), "a C API struct's storage is too small") };
    // SAFETY: the words are aligned for `T` and hold a `T` (checked at compile time above);
    // `T` is `Copy`, so overwriting whatever the words held drops nothing.
    unsafe { words.as_mut_ptr().cast::<T>().write(value) };
    *tag = T::TAG;
}
