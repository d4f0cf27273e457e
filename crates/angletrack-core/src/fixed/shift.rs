//! [`Shift`]: a right shift of 0 to 31 bits whose range the compiler knows, so that a shift
//! by a configured amount is one instruction (an `i32 >> u32` is otherwise masked to 5 bits
//! first: one or two more instructions per shift on a Cortex-M0, `docs/theory.md §14`).

/// A shift of 0 to 31 bits: `Shift::new(bits)` then [`Shift::bits`], stored in the
/// fixed-point gains in place of a `u32`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Shift {
    S0,
    S1,
    S2,
    S3,
    S4,
    S5,
    S6,
    S7,
    S8,
    S9,
    S10,
    S11,
    S12,
    S13,
    S14,
    S15,
    S16,
    S17,
    S18,
    S19,
    S20,
    S21,
    S22,
    S23,
    S24,
    S25,
    S26,
    S27,
    S28,
    S29,
    S30,
    S31,
}

use Shift::*;

/// Every shift, in order of its bits.
const ALL: [Shift; 32] = [
    S0, S1, S2, S3, S4, S5, S6, S7, S8, S9, S10, S11, S12, S13, S14, S15, S16, S17, S18, S19, S20,
    S21, S22, S23, S24, S25, S26, S27, S28, S29, S30, S31,
];

impl Shift {
    /// The shift by `bits` modulo 32 (the callers check `bits <= 31` first).
    pub(crate) const fn new(bits: u32) -> Self {
        ALL[(bits % 32) as usize]
    }

    /// The number of bits, known to the compiler to be below 32.
    #[inline(always)]
    pub(crate) const fn bits(self) -> u32 {
        self as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shift_keeps_its_bits() {
        for bits in 0..32 {
            assert_eq!(Shift::new(bits).bits(), bits);
        }
        assert_eq!(Shift::new(33).bits(), 1);
    }
}
