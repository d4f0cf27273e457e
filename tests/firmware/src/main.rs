//! The observers on a Cortex-M4F (QEMU `mps2-an386`, semihosting), in two modes chosen by
//! the semihosting command line (`-semihosting-config ...,arg=<program>,arg=<mode>,...`):
//!
//! * `check [tamper]`: runs every variant (2nd-order, 3rd-order and Kalman ATO, `f32`,
//!   exact and fast sin/cos) over the simulated resolver and compares every estimate with the
//!   host's reference, within `f32` tolerances; exits with failure if any sample is out of
//!   tolerance. `tamper` first corrupts one input sample: the check must then fail (this is
//!   how the test shows that it can).
//! * `count <variant> <samples> [block]`: runs one variant over the first `samples` samples
//!   and nothing else: one out-of-line `Gains::update` call per sample (variant `loop` runs
//!   the loop with an empty callee), or with `block` one `Gains::update_block` call for all
//!   of them. The instruction count per update is the difference of two such runs of
//!   different lengths, counted by the TCG plugin in `plugin/`. Variant `demodulator-f32`
//!   runs the resolver front end's synchronous demodulator instead, one out-of-line
//!   `Demodulator::push` per ADC sample pair, or with `block` one `Demodulator::push_block`
//!   for all of them (`check` compares its pairs with the host's).
#![no_std]
#![no_main]

mod fixed;
mod variants;

use core::hint::black_box;

use angletrack_core::{
    AdcScaling, Calibrator, DemodulatedPair, Demodulator, DemodulatorState, Estimate, Gains,
    ObserverState, SinCos,
};
use cortex_m_rt::entry;
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::{hprintln, nr};
use variants::{
    Channel, DEMODULATOR, Entry, Job, LOOP_VARIANT, NAMES, Observers, PAIR_BYTES, RECORD_BYTES,
    SAMPLE_BYTES, SAMPLES_PER_PERIOD, adc_counts, entry,
};

include!(concat!(env!("OUT_DIR"), "/scenario.rs"));

/// Largest accepted difference of the multi-turn position `turns * 2 pi + angle` from the
/// host's (rad): about 60 ulp of pi in `f32`.
const POSITION_TOLERANCE_RAD: f32 = 1.5e-5;
/// Largest accepted relative difference of speed and acceleration from the host's (about
/// 80 ulp), relative to the largest magnitude of the reference over the run.
const RELATIVE_TOLERANCE: f32 = 1e-5;
/// The corruption of `tamper` mode: added to `y_s` of the middle sample (the sensor noise
/// is 0.01).
const TAMPER: f32 = 0.05;

/// One observer update, kept out of line: the unit whose code size is reported and whose
/// instructions are counted.
#[inline(never)]
fn update<const N: usize, S: SinCos<f32>>(
    gains: &Gains<f32, N, S>,
    state: &mut ObserverState<f32, N>,
    y_c: f32,
    y_s: f32,
) -> Estimate<f32> {
    gains.update(state, y_c, y_s)
}

/// One update through the online calibration, kept out of line like [`update`].
#[inline(never)]
fn update_calibrated<const N: usize, S: SinCos<f32>>(
    gains: &Gains<f32, N, S>,
    state: &mut ObserverState<f32, N>,
    calibrator: &mut Calibrator<f32>,
    y_c: f32,
    y_s: f32,
) -> Estimate<f32> {
    gains.update_calibrated(state, calibrator, y_c, y_s)
}

/// One update from raw ADC counts, kept out of line like [`update`].
#[inline(never)]
fn update_adc<const N: usize, S: SinCos<f32>>(
    gains: &Gains<f32, N, S>,
    state: &mut ObserverState<f32, N>,
    adc: &AdcScaling<f32>,
    raw_c: i16,
    raw_s: i16,
) -> Estimate<f32> {
    gains.update_adc(state, adc, raw_c, raw_s)
}

/// One sample of variant `index` on `channel` through its entry point.
#[inline(always)]
fn update_entry<const N: usize, S: SinCos<f32>>(
    index: usize,
    gains: &Gains<f32, N, S>,
    channel: &mut Channel<N>,
    y_c: f32,
    y_s: f32,
) -> Estimate<f32> {
    let Channel {
        state,
        calibrator,
        adc,
    } = channel;
    match entry(index) {
        Entry::Plain => update(gains, state, y_c, y_s),
        Entry::Calibrated => update_calibrated(gains, state, calibrator, y_c, y_s),
        Entry::Adc => update_adc(gains, state, adc, adc_counts(y_c), adc_counts(y_s)),
    }
}

/// What `count` mode's loop calls instead of the update for variant `loop`: nothing but a
/// default estimate, so that its count is the loop's own cost (call, inputs, result).
#[inline(never)]
fn no_update<const N: usize, S: SinCos<f32>>(
    _gains: &Gains<f32, N, S>,
    _state: &mut ObserverState<f32, N>,
    _y_c: f32,
    _y_s: f32,
) -> Estimate<f32> {
    Estimate::default()
}

/// A block of updates, kept out of line like [`update`].
#[inline(never)]
fn update_block<const N: usize, S: SinCos<f32>>(
    gains: &Gains<f32, N, S>,
    state: &mut ObserverState<f32, N>,
    y_c: &[f32],
    y_s: &[f32],
    out: &mut [Estimate<f32>],
) -> usize {
    gains.update_block(state, y_c, y_s, out)
}

/// One ADC sample pair through the synchronous demodulator, kept out of line like
/// [`update`]: the unit whose instructions are counted per ADC sample pair.
#[inline(never)]
fn demodulate(
    demodulator: &Demodulator<f32, SAMPLES_PER_PERIOD>,
    state: &mut DemodulatorState<f32>,
    raw_c: f32,
    raw_s: f32,
) -> Option<DemodulatedPair<f32>> {
    demodulator.push(state, raw_c, raw_s)
}

/// A block of ADC sample pairs through the demodulator (`Demodulator::push_block`), kept out
/// of line: counted per sample pair of one call over all samples.
#[inline(never)]
fn demodulate_block(
    demodulator: &Demodulator<f32, SAMPLES_PER_PERIOD>,
    state: &mut DemodulatorState<f32>,
    raw_c: &[f32],
    raw_s: &[f32],
) -> usize {
    demodulator.push_block(state, raw_c, raw_s, |pair| {
        black_box(pair);
    })
}

/// Largest accepted difference of a demodulated pair from the host's (amplitude 1): the
/// same `f32` operations in the same order, so about an ulp.
const PAIR_TOLERANCE: f32 = 1e-6;

/// The raw ADC samples of the demodulator variant (counts).
fn raw_sample(k: usize) -> (f32, f32) {
    let r = &DEMODULATOR_REFERENCE[k * SAMPLE_BYTES..(k + 1) * SAMPLE_BYTES];
    let word = |i: usize| [r[i], r[i + 1], r[i + 2], r[i + 3]];
    (f32::from_le_bytes(word(0)), f32::from_le_bytes(word(4)))
}

/// `check` mode for the demodulator: every pair against the host's. Returns `true` if all
/// are within [`PAIR_TOLERANCE`].
fn check_demodulator() -> Result<bool, &'static str> {
    let demodulator = variants::demodulator().map_err(|_| "demodulator settings refused")?;
    let mut state = DemodulatorState::new();
    let mut pairs = DEMODULATOR_REFERENCE[SAMPLES * SAMPLE_BYTES..].chunks_exact(PAIR_BYTES);
    let (mut worst, mut count, mut missing) = (0.0f32, 0usize, false);
    for k in 0..SAMPLES {
        let (c, s) = raw_sample(k);
        if let Some(pair) = demodulate(&demodulator, &mut state, c, s) {
            let Some(r) = pairs.next() else {
                missing = true;
                break;
            };
            let word = |i: usize| f32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]]);
            for d in [(pair.y_c - word(0)).abs(), (pair.y_s - word(4)).abs()] {
                if worse(d, worst) {
                    worst = d;
                }
            }
            count += 1;
        }
    }
    let ok = !missing && pairs.next().is_none() && count > 0 && worst <= PAIR_TOLERANCE;
    hprintln!(
        "check {}: {} ADC sample pairs, {} pairs, max |pair - host| {:e}: {}",
        DEMODULATOR,
        SAMPLES,
        count,
        worst,
        if ok { "ok" } else { "FAIL" }
    );
    Ok(ok)
}

/// `count` mode for the demodulator: `samples` ADC sample pairs and nothing else, one
/// `push` call each, or with `block` one `push_block` call for all of them.
fn count_demodulator(samples: usize, block: bool) -> Result<(), &'static str> {
    let demodulator = variants::demodulator().map_err(|_| "demodulator settings refused")?;
    let mut state = DemodulatorState::new();
    let n = samples.min(SAMPLES);
    if block {
        let (mut raw_c, mut raw_s) = ([0.0f32; SAMPLES], [0.0f32; SAMPLES]);
        for k in 0..n {
            (raw_c[k], raw_s[k]) = raw_sample(k);
        }
        black_box(demodulate_block(
            &demodulator,
            &mut state,
            &raw_c[..n],
            &raw_s[..n],
        ));
        return Ok(());
    }
    let step = black_box(demodulate);
    for k in 0..n {
        let (c, s) = raw_sample(k);
        black_box(&step(&demodulator, &mut state, c, s));
    }
    Ok(())
}

/// The simulated resolver's samples, decoded from the reference data.
struct Inputs {
    y_c: [f32; SAMPLES],
    y_s: [f32; SAMPLES],
}

impl Inputs {
    fn load() -> Self {
        let mut inputs = Inputs {
            y_c: [0.0; SAMPLES],
            y_s: [0.0; SAMPLES],
        };
        for (k, sample) in REFERENCE[..SAMPLES * SAMPLE_BYTES]
            .chunks_exact(SAMPLE_BYTES)
            .enumerate()
        {
            let word = |i: usize| [sample[i], sample[i + 1], sample[i + 2], sample[i + 3]];
            inputs.y_c[k] = f32::from_le_bytes(word(0));
            inputs.y_s[k] = f32::from_le_bytes(word(4));
        }
        inputs
    }
}

/// `check` mode: every sample of a variant against the host's reference.
struct Check<'a> {
    inputs: &'a Inputs,
    failures: usize,
}

impl Job for Check<'_> {
    fn run<const N: usize, S: SinCos<f32>>(&mut self, index: usize, gains: Gains<f32, N, S>) {
        let base = SAMPLES * SAMPLE_BYTES + index * SAMPLES * RECORD_BYTES;
        let records = &REFERENCE[base..base + SAMPLES * RECORD_BYTES];
        let (mut speed_scale, mut acceleration_scale) = (1.0f32, 1.0f32);
        for r in records.chunks_exact(RECORD_BYTES) {
            let (_, _, speed, acceleration) = variants::decode(r);
            speed_scale = speed_scale.max(speed.abs());
            acceleration_scale = acceleration_scale.max(acceleration.abs());
        }
        let mut channel = Channel::new(entry(index));
        let (mut position, mut speed, mut acceleration, mut worst) = (0.0f32, 0.0, 0.0, 0);
        for (k, r) in records.chunks_exact(RECORD_BYTES).enumerate() {
            let (y_c, y_s) = (self.inputs.y_c[k], self.inputs.y_s[k]);
            let e = update_entry(index, &gains, &mut channel, y_c, y_s);
            let (angle_ref, turns_ref, speed_ref, acceleration_ref) = variants::decode(r);
            // Position difference, exact in the split form: whole turns, then the angle.
            let turns = (e.turns - i64::from(turns_ref)) as f32;
            let d = (turns * core::f32::consts::TAU + (e.angle - angle_ref)).abs();
            if worse(d, position) {
                (position, worst) = (d, k);
            }
            let d = (e.speed - speed_ref).abs() / speed_scale;
            if worse(d, speed) {
                speed = d;
            }
            let d = (e.acceleration - acceleration_ref).abs() / acceleration_scale;
            if worse(d, acceleration) {
                acceleration = d;
            }
        }
        let ok = position <= POSITION_TOLERANCE_RAD
            && speed <= RELATIVE_TOLERANCE
            && acceleration <= RELATIVE_TOLERANCE;
        hprintln!(
            "check {}: {} samples, max |position - host| {:e} rad (sample {}), \
             speed {:e}, acceleration {:e} (relative): {}",
            NAMES[index],
            SAMPLES,
            position,
            worst,
            speed,
            acceleration,
            if ok { "ok" } else { "FAIL" }
        );
        self.failures += usize::from(!ok);
    }
}

/// `true` if the difference `d` is larger than `worst` so far, or NaN (which must fail).
fn worse(d: f32, worst: f32) -> bool {
    d > worst || d.is_nan()
}

/// `count` mode: `samples` updates of one variant (or of the loop alone) and nothing else.
struct Count<'a> {
    inputs: &'a Inputs,
    samples: usize,
    loop_only: bool,
    block: bool,
}

impl Job for Count<'_> {
    fn run<const N: usize, S: SinCos<f32>>(&mut self, index: usize, gains: Gains<f32, N, S>) {
        let n = self.samples.min(SAMPLES);
        if !self.loop_only && entry(index) != Entry::Plain {
            let mut channel = Channel::new(entry(index));
            for k in 0..n {
                let (y_c, y_s) = (self.inputs.y_c[k], self.inputs.y_s[k]);
                black_box(&update_entry(index, &gains, &mut channel, y_c, y_s));
            }
            return;
        }
        if self.block {
            let mut state = ObserverState::new();
            let mut out = [Estimate::default(); SAMPLES];
            let (y_c, y_s) = (&self.inputs.y_c[..n], &self.inputs.y_s[..n]);
            black_box(update_block(&gains, &mut state, y_c, y_s, &mut out));
            black_box(&out);
            return;
        }
        let step = if self.loop_only {
            no_update::<N, S>
        } else {
            update::<N, S>
        };
        let step = black_box(step);
        let mut state = ObserverState::new();
        for k in 0..n {
            black_box(&step(
                &gains,
                &mut state,
                self.inputs.y_c[k],
                self.inputs.y_s[k],
            ));
        }
    }
}

/// The semihosting command line, split at spaces, without the program name.
fn command_line(buf: &mut [u8]) -> impl Iterator<Item = &str> {
    let mut block = [buf.as_mut_ptr() as usize, buf.len()];
    // SAFETY: SYS_GET_CMDLINE writes at most `block[1]` bytes to `block[0]` (our buffer) and
    // the length it wrote back into `block[1]`; both live until the call returns.
    let status =
        unsafe { cortex_m_semihosting::syscall1(nr::GET_CMDLINE, block.as_mut_ptr() as usize) };
    let len = if status == 0 {
        block[1].min(buf.len())
    } else {
        0
    };
    core::str::from_utf8(&buf[..len])
        .unwrap_or("")
        .split(' ')
        .filter(|w| !w.is_empty())
        .skip(1)
}

fn run() -> Result<(), &'static str> {
    let mut buf = [0u8; 128];
    let mut args = command_line(&mut buf);
    let mut inputs = Inputs::load();
    match args.next() {
        Some("check") => {
            let tamper = args.next() == Some("tamper");
            if tamper {
                inputs.y_s[SAMPLES / 2] += TAMPER;
            }
            let mut check = Check {
                inputs: &inputs,
                failures: 0,
            };
            for index in 0..NAMES.len() {
                if !OBSERVERS.run(index, &mut check) {
                    return Err("gains refused");
                }
            }
            let demodulator_ok = check_demodulator()?;
            let fixed_ok = fixed::check(
                &variants::fixed_gains(&OBSERVERS).map_err(|_| "fixed gains refused")?,
                &inputs.y_c,
                &inputs.y_s,
                &REFERENCE[SAMPLES * SAMPLE_BYTES + variants::FIXED_REFERENCE * SAMPLES * RECORD_BYTES..]
                    [..SAMPLES * RECORD_BYTES],
            );
            if check.failures > 0 || !demodulator_ok || !fixed_ok {
                return Err("estimates differ from the host's");
            }
            Ok(())
        }
        Some("count") => {
            let name = args.next().ok_or("count needs a variant")?;
            let samples = args
                .next()
                .and_then(|n| n.parse().ok())
                .ok_or("count needs a sample count")?;
            let block = args.next() == Some("block");
            if name == DEMODULATOR {
                return count_demodulator(samples, block);
            }
            if name == variants::FIXED {
                let gains = variants::fixed_gains(&OBSERVERS).map_err(|_| "fixed gains refused")?;
                let n = samples.min(SAMPLES);
                fixed::count(&gains, &inputs.y_c[..n], &inputs.y_s[..n]);
                return Ok(());
            }
            let loop_only = name == "loop";
            // The loop alone runs with the Kalman variant's types.
            let index = if loop_only {
                LOOP_VARIANT
            } else {
                NAMES
                    .iter()
                    .position(|&n| n == name)
                    .ok_or("unknown variant")?
            };
            let mut count = Count {
                inputs: &inputs,
                samples,
                loop_only,
                block,
            };
            if OBSERVERS.run(index, &mut count) {
                Ok(())
            } else {
                Err("gains refused")
            }
        }
        _ => Err("usage: check [tamper] | count <variant|loop|demodulator-f32> <samples> [block]"),
    }
}

#[entry]
fn main() -> ! {
    match run() {
        Ok(()) => debug::exit(EXIT_SUCCESS),
        Err(message) => {
            hprintln!("error: {}", message);
            debug::exit(EXIT_FAILURE);
        }
    }
    loop {
        cortex_m::asm::wfi();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("panic: {}", info);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
