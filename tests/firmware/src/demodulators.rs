//! The resolver front end's demodulator on the core (variants `demodulator-f32` and
//! `demodulator-fixed`): `check` mode compares its pairs with the host's, `count` mode runs
//! it alone over the raw samples, one `Demodulator::push` per ADC sample or one
//! `Demodulator::push_block` for all of them, and `functions` prints where those are.

use core::hint::black_box;

use angletrack_core::{DemodulatedPair, Demodulator, DemodulatorNumber, DemodulatorState};
use cortex_m_semihosting::hprintln;

use crate::variants::{self, CARRIER_AMPLITUDE_COUNTS, PAIR_BYTES};
use crate::{
    DEMODULATOR_FIXED_PAIRS, DEMODULATOR_PAIRS, RAW_C, RAW_C16, RAW_S, RAW_S16, SAMPLES,
    corruption, worse,
};

/// One ADC sample of both windings through the demodulator, kept out of line like
/// [`update`]: the unit whose instructions are counted per ADC sample.
#[inline(never)]
fn demodulate<V: DemodulatorNumber>(
    demodulator: &Demodulator<V>,
    state: &mut DemodulatorState<V>,
    raw_c: V,
    raw_s: V,
) -> Option<DemodulatedPair<V>> {
    demodulator.push(state, raw_c, raw_s)
}

/// A block of ADC samples through the demodulator (`Demodulator::push_block`), kept out
/// of line: counted per ADC sample of one call over all samples.
#[inline(never)]
fn demodulate_block<V: DemodulatorNumber>(
    demodulator: &Demodulator<V>,
    state: &mut DemodulatorState<V>,
    raw_c: &[V],
    raw_s: &[V],
) -> usize {
    demodulator.push_block(state, raw_c, raw_s, |pair| {
        black_box(pair);
    })
}

/// Largest accepted difference of a demodulated pair from the host's (amplitude 1): the
/// same operations in the same order, so about an ulp in `f32`, none in fixed point.
const PAIR_TOLERANCE: f32 = 1e-6;

/// A demodulator variant's number type, inputs and reference pairs.
pub(crate) trait DemodulatorVariant: DemodulatorNumber<Real = f32> {
    /// The raw samples of both windings (none for `f32` on the Cortex-M0).
    fn raw() -> (&'static [Self], &'static [Self]);
    /// The host's pairs.
    fn reference() -> &'static [u8];
    /// A raw sample corrupted by `corruption` times the carrier amplitude.
    fn corrupt(x: Self, corruption: f32) -> Self;
}

impl DemodulatorVariant for f32 {
    fn raw() -> (&'static [f32], &'static [f32]) {
        (&RAW_C, &RAW_S)
    }
    fn reference() -> &'static [u8] {
        DEMODULATOR_PAIRS
    }
    fn corrupt(x: f32, corruption: f32) -> f32 {
        x + corruption * CARRIER_AMPLITUDE_COUNTS
    }
}

impl DemodulatorVariant for i16 {
    fn raw() -> (&'static [i16], &'static [i16]) {
        (&RAW_C16, &RAW_S16)
    }
    fn reference() -> &'static [u8] {
        DEMODULATOR_FIXED_PAIRS
    }
    fn corrupt(x: i16, corruption: f32) -> i16 {
        x.saturating_add((corruption * CARRIER_AMPLITUDE_COUNTS) as i16)
    }
}

/// `check` mode for a demodulator variant: every pair against the host's (with one raw
/// sample corrupted if `tamper`). Returns `true` if all are within [`PAIR_TOLERANCE`].
pub(crate) fn check_demodulator<V: DemodulatorVariant>(
    name: &str,
    tamper: bool,
) -> Result<bool, &'static str> {
    let demodulator = variants::demodulator::<V>().map_err(|_| "demodulator settings refused")?;
    let mut state = DemodulatorState::new();
    let mut pairs = V::reference().chunks_exact(PAIR_BYTES);
    let (mut worst, mut count, mut missing) = (0.0f32, 0usize, false);
    let (raw_c, raw_s) = V::raw();
    for (k, (&c, &s)) in raw_c.iter().zip(raw_s).enumerate() {
        let s = V::corrupt(s, corruption(tamper, k, SAMPLES));
        if let Some(pair) = demodulate(&demodulator, &mut state, c, s) {
            let Some(r) = pairs.next() else {
                missing = true;
                break;
            };
            let word = |i: usize| f32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]]);
            for d in [
                (V::to_real(pair.y_c) - word(0)).abs(),
                (V::to_real(pair.y_s) - word(4)).abs(),
            ] {
                if worse(d, worst) {
                    worst = d;
                }
            }
            count += 1;
        }
    }
    let ok = !missing && pairs.next().is_none() && count > 0 && worst <= PAIR_TOLERANCE;
    hprintln!(
        "check {}: {} ADC samples, {} pairs, max |pair - host| {:e}: {}",
        name,
        SAMPLES,
        count,
        worst,
        if ok { "ok" } else { "FAIL" }
    );
    Ok(ok)
}

/// `count` mode for a demodulator variant: `samples` ADC samples and nothing else, one
/// `push` call each, or with `block` one `push_block` call for all of them.
pub(crate) fn count_demodulator<V: DemodulatorVariant>(
    samples: usize,
    block: bool,
) -> Result<(), &'static str> {
    let demodulator = variants::demodulator::<V>().map_err(|_| "demodulator settings refused")?;
    let mut state = DemodulatorState::new();
    let (raw_c, raw_s) = V::raw();
    let n = samples.min(raw_c.len()).min(raw_s.len());
    if block {
        black_box(demodulate_block(
            &demodulator,
            &mut state,
            &raw_c[..n],
            &raw_s[..n],
        ));
        return Ok(());
    }
    let step = black_box(demodulate::<V>);
    for (&c, &s) in raw_c[..n].iter().zip(&raw_s[..n]) {
        black_box(&step(&demodulator, &mut state, c, s));
    }
    Ok(())
}

/// Prints the addresses of a demodulator variant's out-of-line functions.
pub(crate) fn demodulator_functions<V: DemodulatorVariant>() {
    let push = demodulate::<V> as fn(_, _, _, _) -> _;
    hprintln!("update {:#x}", push as usize);
    let block = demodulate_block::<V> as fn(_, _, _, _) -> _;
    hprintln!("update_block {:#x}", block as usize);
}
