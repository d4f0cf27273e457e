//! Rust values kept in C memory: the private `tag`, `layout` and `storage` words of the C
//! API's structs (`at_chain_f32`, `at_chain_state_f32`, `at_adc_f32`, ...), which C code sizes
//! from the header and may place anywhere (static memory, the stack), copy by assignment
//! and zero.
//!
//! The words are `MaybeUninit<u64>` (plain `uint64_t` in C): a Rust value written there
//! leaves its padding bytes uninitialised, and a copy of the struct by value in Rust (C
//! copies bytes) must not read those as integers. Miri checks this in the crate's tests.
//!
//! A slot holds one of a few `Copy` types. Only [`Slot::slot_put`] writes a struct's tag
//! (the type's: 32 bits starting with the bytes "AT", `0x4154` in the high half) and its
//! layout word, right after it wrote a value of that type. The layout word is a fingerprint
//! of this build's layouts ([`layout_of`]: the C API's layout version `AT_LAYOUT_VERSION`,
//! the crate's version, the C struct's size and the size and alignment of every stored Rust
//! type) hashed with the type's tag ([`typed`]): one word names the build, the struct and
//! the type, so that the per-sample reads ([`Slot::either`], [`Slot::slot_get_or_put`])
//! compare that one word per struct, and the others ([`Slot::slot_get`]) the tag too,
//! before they read the words as the type. A zeroed or never-initialised struct has no such word (0, never
//! written, or garbage that matches one 32-bit value by chance), so it is refused or started
//! afresh instead of being read as a Rust value. A struct written by another build of the
//! library (another version, a header of another size, another target) carries an "AT" tag
//! with another layout word: it is refused as such ([`Refused::OtherBuild`]), never read.
//! The tag and the layout word are the struct's first two fields, at the same offsets in
//! every build. The guarantee holds as long as C code writes the structs only through the
//! API (or copies a whole struct), as the header says.
#![allow(unsafe_code)]

use core::mem::{MaybeUninit, align_of, size_of};

use angletrack_core::ConfigError;

use crate::status::{AT_ERR_NOT_INITIALISED, AT_ERR_OTHER_BUILD, at_status, status_of_result};

/// The version of the C structs' layout, bumped whenever a struct of the header or a Rust
/// value the library stores in one changes; part of every struct's layout word (with the
/// crate's version and the sizes, which change it without a bump). `at_layout_version()`
/// returns the library's, to compare with the header's at start-up.
pub const AT_LAYOUT_VERSION: u32 = 10;

/// A type a slot can hold, with its tag. `Copy` types only: overwriting one drops nothing,
/// and a C copy of the words (with the tag) is a copy of the value.
pub(crate) trait Stored: Copy {
    /// The tag [`Slot::slot_put`] writes beside a value of this type; "AT" in its high half, never 0.
    const TAG: u32;
}

/// The high half of every tag: "AT".
const TAG_FAMILY: u32 = 0x4154;

/// Why a slot's words are not read as a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Refused {
    /// Zeroed, never made, or holding another type: no value of the type asked for.
    NotInitialised,
    /// Made by another build of the library (its layout word is not this build's).
    OtherBuild,
}

impl Refused {
    /// The status a call refusing the struct returns.
    pub(crate) const fn status(self) -> at_status {
        match self {
            Refused::NotInitialised => AT_ERR_NOT_INITIALISED,
            Refused::OtherBuild => AT_ERR_OTHER_BUILD,
        }
    }
}

/// One step of the 32-bit FNV-1a hash over `value`'s four bytes.
pub(crate) const fn hash(mut h: u32, value: u32) -> u32 {
    let bytes = value.to_le_bytes();
    let mut i = 0;
    while i < 4 {
        h = (h ^ bytes[i] as u32).wrapping_mul(0x0100_0193);
        i += 1;
    }
    h
}

/// The size and alignment of `T` hashed into `h`.
const fn hash_type<T>(h: u32) -> u32 {
    hash(hash(h, size_of::<T>() as u32), align_of::<T>() as u32)
}

/// This build's fingerprint of the layouts: the layout version, the crate's version and
/// every stored type's size and alignment.
const BUILD: u32 = build_of(AT_LAYOUT_VERSION);

/// The fingerprint of this build's layouts under the layout version `version` (a build of
/// another version differs in its `version` at least).
pub(crate) const fn build_of(version: u32) -> u32 {
    let mut h = hash(0x811c_9dc5, version);
    let crate_version = env!("CARGO_PKG_VERSION").as_bytes();
    let mut i = 0;
    while i < crate_version.len() {
        h = hash(h, crate_version[i] as u32);
        i += 1;
    }
    h = hash_type::<crate::adc::AdcF32>(h);
    h = hash_type::<crate::chain::ChainF32<2>>(h);
    h = hash_type::<crate::chain::ChainF32<3>>(h);
    h = hash_type::<crate::chain::StateF32<2>>(h);
    h = hash_type::<crate::chain::StateF32<3>>(h);
    h = hash_type::<crate::chain_fixed::ChainFixed<2>>(h);
    h = hash_type::<crate::chain_fixed::ChainFixed<3>>(h);
    h = hash_type::<crate::chain_fixed::StateFixed<2>>(h);
    h = hash_type::<crate::chain_fixed::StateFixed<3>>(h);
    h = hash_type::<angletrack_core::Demodulator<f32>>(h);
    hash_type::<angletrack_core::DemodulatorState<f32>>(h)
}

/// The layout word of a C struct of `size` bytes in this build (never 0).
pub(crate) const fn layout_of(size: usize) -> u32 {
    hash(BUILD, size as u32) | 1
}

/// The layout word written beside a value tagged `tag` in a struct of the layout word
/// `layout` (never 0): one word names the build, the struct and the type, so that the
/// per-sample calls compare one word per struct.
const fn typed(layout: u32, tag: u32) -> u32 {
    hash(layout, tag) | 1
}

/// Fails to compile unless a `T` fits in `words` words of 8 bytes with their alignment: the
/// header's storage sizes are checked against the Rust types at every build, on every
/// target.
const fn assert_fits<T>(words: usize) {
    assert!(
        size_of::<T>() <= words * size_of::<u64>() && align_of::<T>() <= align_of::<u64>(),
        "a C API struct's storage is too small"
    );
}

/// Why a struct of this build's layout word `expected` holds no value of the type whose
/// layout word is `word`: another build's (an "AT" tag beside a layout word that is not this
/// build's, for that tag or that type), or none (out of line: the per-sample paths take the
/// other branch).
#[cold]
#[inline(never)]
fn refusal(tag: u32, layout: u32, expected: u32, word: u32) -> Refused {
    if tag >> 16 == TAG_FAMILY && layout != typed(expected, tag) && layout != word {
        Refused::OtherBuild
    } else {
        Refused::NotInitialised
    }
}

/// A C struct with the fields `tag`, `layout` and `storage` (of [`Slot::WORDS`] words),
/// which holds a [`Stored`] value (`slot_struct!` implements it).
///
/// The reads' safety: the storage is read as a `T` only when the struct's layout word is
/// this build's for `T`. The words are aligned for `T` and large enough (checked at compile
/// time), and with that word they hold a valid `T`, since only `slot_put::<T>` writes it,
/// after writing a `T` there, and whatever C does with the struct (copy it whole, as the
/// header allows) keeps them together. The borrow of `self` bounds the reference's life
/// (and, exclusive, makes a mutable one unique).
pub(crate) trait Slot {
    /// The words of its storage.
    const WORDS: usize;
    /// This build's layout word for the struct.
    const LAYOUT: u32;
    /// The tag, the layout word and the storage.
    fn words(&self) -> (u32, u32, &[MaybeUninit<u64>]);
    /// The same, to write.
    fn words_mut(&mut self) -> (&mut u32, &mut u32, &mut [MaybeUninit<u64>]);

    /// This build's layout word for a `T` in the struct.
    #[inline(always)]
    fn typed<T: Stored>() -> u32 {
        const { typed(Self::LAYOUT, T::TAG) }
    }

    /// Whether the struct holds a `T` of this build: its layout word (which names the
    /// type), and unless `per_sample` its tag too.
    #[inline(always)]
    fn holds<T: Stored>(&self, per_sample: bool) -> Result<(), Refused> {
        const { assert_fits::<T>(Self::WORDS) };
        let (tag, layout, _) = self.words();
        if layout == Self::typed::<T>() && (per_sample || tag == T::TAG) {
            return Ok(());
        }
        Err(refusal(tag, layout, Self::LAYOUT, Self::typed::<T>()))
    }

    /// The value held, if it is a `T` of this build.
    #[inline(always)]
    fn slot_get<T: Stored>(&self) -> Result<&T, Refused> {
        self.holds::<T>(false)?;
        // SAFETY: checked above (the trait's reads' safety).
        Ok(unsafe { &*self.words().2.as_ptr().cast::<T>() })
    }

    /// [`Slot::slot_get`], to write.
    #[inline(always)]
    fn slot_get_mut<T: Stored>(&mut self) -> Result<&mut T, Refused> {
        self.holds::<T>(false)?;
        // SAFETY: checked above (the trait's reads' safety).
        Ok(unsafe { &mut *self.words_mut().2.as_mut_ptr().cast::<T>() })
    }

    /// The value held, if it is a `T` of this build, for the per-sample calls.
    #[inline(always)]
    fn slot_layout<T: Stored>(&self) -> Option<&T> {
        self.holds::<T>(true).ok()?;
        // SAFETY: checked above (the trait's reads' safety).
        Some(unsafe { &*self.words().2.as_ptr().cast::<T>() })
    }

    /// The `T` held, or `start()` stored (and tagged); refused only when the struct is
    /// another build's. For the per-sample calls: the layout word alone is compared.
    #[inline(always)]
    fn slot_get_or_put<T: Stored>(&mut self, start: fn() -> T) -> Result<&mut T, Refused> {
        if self.holds::<T>(true).is_err() {
            self.slot_start(start)?;
        }
        // SAFETY: the layout word is `T`'s, as compared above or written by `slot_start`.
        Ok(unsafe { &mut *self.words_mut().2.as_mut_ptr().cast::<T>() })
    }

    /// `start()` stored (and tagged) unless the struct is another build's: out of line, so
    /// that the per-sample calls carry no fresh value.
    #[cold]
    #[inline(never)]
    fn slot_start<T: Stored>(&mut self, start: fn() -> T) -> Result<(), Refused> {
        if self.holds::<T>(true) == Err(Refused::OtherBuild) {
            return Err(Refused::OtherBuild);
        }
        self.slot_put(start());
        Ok(())
    }

    /// Stores `value` and tags it as a `T` of this build.
    fn slot_put<T: Stored>(&mut self, value: T) {
        const { assert_fits::<T>(Self::WORDS) };
        let (tag, layout, words) = self.words_mut();
        // SAFETY: the words are aligned for `T` and hold a `T` (checked at compile time
        // above); `T` is `Copy`, so overwriting whatever they held drops nothing.
        unsafe { words.as_mut_ptr().cast::<T>().write(value) };
        *tag = T::TAG;
        *layout = Self::typed::<T>();
    }

    /// Stores the value of a check, if it passed; the check's status (`self` unchanged on
    /// error).
    fn slot_store<T: Stored>(&mut self, result: Result<T, ConfigError>) -> at_status {
        status_of_result(result.map(|value| self.slot_put(value)))
    }

    /// The value held, of order 2 (`A`) or 3 (`B`), if this build's: for the per-sample
    /// calls, the layout word alone is compared (it names the type).
    #[inline(always)]
    fn either<A: Stored, B: Stored>(&self) -> Result<ByOrder<&A, &B>, Refused> {
        const { assert!(typed(Self::LAYOUT, A::TAG) != typed(Self::LAYOUT, B::TAG)) };
        if let Some(a) = self.slot_layout::<A>() {
            return Ok(ByOrder::Two(a));
        }
        self.holds::<B>(true)?;
        // SAFETY: checked above (the trait's reads' safety).
        Ok(ByOrder::Three(unsafe {
            &*self.words().2.as_ptr().cast::<B>()
        }))
    }

    /// The value held, of order 2 (`A`) or 3 (`B`), if any of this build's.
    fn either_mut<A: Stored, B: Stored>(&mut self) -> Option<ByOrder<&mut A, &mut B>> {
        if self.holds::<A>(false).is_ok() {
            self.slot_get_mut().ok().map(ByOrder::Two)
        } else {
            self.slot_get_mut().ok().map(ByOrder::Three)
        }
    }
}

/// The C struct `$name` of `$words` words of storage (its docs `$doc`), with [`Slot`]
/// and its `ZEROED` value (as C static memory holds).
macro_rules! slot_struct {
    ($(#[$doc:meta])* $name:ident[$words:ident]) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(Debug, Clone, Copy)]
        pub struct $name {
            /// Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
            pub(crate) tag: u32,
            /// Private: the layout of the build that wrote it.
            pub(crate) layout: u32,
            /// Private: the Rust value.
            pub(crate) storage: [core::mem::MaybeUninit<u64>; $words],
        }

        impl $name {
            /// A zeroed struct, as C static memory holds.
            #[allow(dead_code)]
            pub(crate) const ZEROED: Self = Self {
                tag: 0,
                layout: 0,
                storage: [core::mem::MaybeUninit::new(0); $words],
            };
        }

        impl $crate::slot::Slot for $name {
            const WORDS: usize = $words;
            const LAYOUT: u32 = $crate::slot::layout_of(core::mem::size_of::<Self>());
            #[inline(always)]
            fn words(&self) -> (u32, u32, &[core::mem::MaybeUninit<u64>]) {
                (self.tag, self.layout, &self.storage)
            }
            #[inline(always)]
            fn words_mut(&mut self) -> (&mut u32, &mut u32, &mut [core::mem::MaybeUninit<u64>]) {
                (&mut self.tag, &mut self.layout, &mut self.storage)
            }
        }
    };
}
pub(crate) use slot_struct;

/// A value of the observer's order 2 or 3 (gains, a chain, a state), borrowed from a C
/// struct: the core's types are generic over the order, the C structs hold either.
#[derive(Debug)]
pub(crate) enum ByOrder<A, B> {
    /// Order 2.
    Two(A),
    /// Order 3.
    Three(B),
}

/// Evaluates `$body` with `$x` bound to the value of a [`ByOrder`], whatever its order: the
/// generic code is written once and instantiated for both.
macro_rules! by_order {
    ($any:expr, |$x:ident| $body:expr) => {
        match $any {
            $crate::slot::ByOrder::Two($x) => $body,
            $crate::slot::ByOrder::Three($x) => $body,
        }
    };
}
pub(crate) use by_order;
