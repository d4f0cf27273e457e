//! The variants (`variants.rs`: observers, entry points, baselines) on a Cortex-M (QEMU with
//! semihosting: `mps2-an386` for the Cortex-M4F build, thumbv7em-none-eabihf; `microbit` for
//! the Cortex-M0 build, thumbv6m-none-eabi), in modes chosen by the semihosting command line
//! (`-semihosting-config ...,arg=<program>,arg=<mode>,...`):
//!
//! * `check [tamper]`: runs every variant over the simulated resolver and compares every
//!   estimate with the host's reference, within `f32` tolerances (the fixed-point
//!   variants' integers exactly, over all samples); also `count` mode's
//!   inputs (converted before its runs) against the checked ones, the demodulator's
//!   pairs, and the baselines' fast arctangent against `atan2f` over a sweep. Exits with
//!   failure if any is out of tolerance. `tamper` first corrupts one input of each check:
//!   every check must then fail (this is how the test shows that each can).
//! * `variants`: prints the variants' names, one a line.
//! * `functions <variant>`: prints the addresses of the variant's out-of-line update (and
//!   block update, if it has one), which `run.sh` finds in the symbol table.
//! * `count <variant> <samples> [block]`: runs one variant over the first `samples` samples
//!   and nothing else (its inputs converted before the run, by the build script): one
//!   out-of-line update call per sample (variant `loop` runs the loop with an empty
//!   callee), or with `block` one block update call for all of them. The
//!   instruction count per update is the difference of two such runs of different lengths,
//!   counted by the TCG plugin in `plugin/`. Variants `demodulator-f32` and
//!   `demodulator-fixed` run the resolver front end's demodulator instead (in `f32`, in
//!   fixed point), one out-of-line `Demodulator::push` per ADC sample, or with `block` one
//!   `Demodulator::push_block` for all of them (`check` compares their pairs with the
//!   host's).
#![no_std]
#![no_main]

mod baseline;
mod chains;
mod demodulators;
mod trackers;
mod variants;

use core::hint::black_box;

use angletrack_core::Float;
use baseline::{Atan2, FAST_ATAN2_MAX_ERROR_RAD, FastAtan2, LibmAtan2};
use cortex_m_rt::entry;
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::{hprintln, nr};
use demodulators::{check_demodulator, count_demodulator, demodulator_functions};
use trackers::Inputs;
use variants::{
    DEMODULATORS, FNV_OFFSET, Job, LOOP_VARIANT, NAMES, Observers, RECORD_BYTES, Record, Tracker,
    fold_integers,
};

include!(concat!(env!("OUT_DIR"), "/scenario.rs"));

/// The signal in every form the trackers take, for `count` mode (converted by the build
/// script; `check` mode verifies them against [`Tracker::input`]).
static INPUTS: Inputs = Inputs {
    signal: [&Y_C, &Y_S],
    adc: [&ADC_C, &ADC_S],
    fixed: [&FIXED_C, &FIXED_S],
};

/// Largest accepted difference of the multi-turn position `turns * 2 pi + angle` from the
/// host's (rad): about 60 ulp of pi in `f32`.
const POSITION_TOLERANCE_RAD: f32 = 1.5e-5;
/// Largest accepted relative difference of speed and acceleration from the host's (about
/// 80 ulp), relative to the largest magnitude of the reference over the run.
const RELATIVE_TOLERANCE: f32 = 1e-5;
/// The corruption of `tamper` mode (the sensor noise is 0.01), added to one input of each
/// check: `y_s` of the middle sample of every variant, `y` of the middle point of the fast
/// arctangent's sweep, and (times the carrier amplitude, in counts) the middle raw sample of
/// the demodulator's sine winding.
const TAMPER: f32 = 0.05;

/// The corruption of input `k` of a check's `inputs` in `tamper` mode: [`TAMPER`] at the
/// middle one, else none.
fn corruption(tamper: bool, k: usize, inputs: usize) -> f32 {
    if tamper && k == inputs / 2 {
        TAMPER
    } else {
        0.0
    }
}

/// One update of a variant, kept out of line: the unit whose code size is reported and
/// whose instructions are counted.
#[inline(never)]
fn update<T: Tracker>(
    tracker: &T,
    state: &mut T::State,
    y_c: T::Input,
    y_s: T::Input,
) -> T::Output {
    tracker.update(state, y_c, y_s)
}

/// What `count` mode's loop calls instead of the update for variant `loop`: nothing but a
/// default output, so that its count is the loop's own cost (call, inputs, result).
#[inline(never)]
fn no_update<T: Tracker>(
    _tracker: &T,
    _state: &mut T::State,
    _y_c: T::Input,
    _y_s: T::Input,
) -> T::Output {
    T::Output::default()
}

/// A block of updates, kept out of line like [`update`].
#[inline(never)]
fn update_block<T: Tracker>(
    tracker: &T,
    state: &mut T::State,
    y_c: &[f32],
    y_s: &[f32],
    out: &mut [T::Output],
) -> usize {
    tracker.update_block(state, y_c, y_s, out)
}

/// Input sample `k` of `check` mode: `(Y_C[k], Y_S[k])`, the middle checked one corrupted
/// by [`TAMPER`] if `tamper`.
fn checked_input(k: usize, tamper: bool) -> (f32, f32) {
    (Y_C[k], Y_S[k] + corruption(tamper, k, CHECKED_SAMPLES))
}

/// `check` mode: every sample of a variant against the host's reference, within tolerances
/// (its record: position, speed, acceleration), and for a fixed-point variant its integers
/// exactly (over all samples, through their hash [`INTEGERS`]).
struct Check {
    tamper: bool,
    failures: usize,
}

impl Job for Check {
    fn run<T: Tracker>(&mut self, index: usize, tracker: T) {
        let base = index * CHECKED_SAMPLES * RECORD_BYTES;
        let records = &REFERENCE[base..base + CHECKED_SAMPLES * RECORD_BYTES];
        let (mut speed_scale, mut acceleration_scale) = (1.0f32, 1.0f32);
        for r in records.chunks_exact(RECORD_BYTES) {
            let r = Record::decode(r);
            speed_scale = speed_scale.max(r.speed.abs());
            acceleration_scale = acceleration_scale.max(r.acceleration.abs());
        }
        let mut state = tracker.new_state();
        let (mut position, mut speed, mut acceleration, mut worst) = (0.0f32, 0.0, 0.0, 0);
        let mut integers = None;
        let mut fold = |state: &T::State, output: &T::Output| {
            if let Some(words) = tracker.integers(state, output) {
                integers = Some(fold_integers(integers.unwrap_or(FNV_OFFSET), &words));
            }
        };
        for (k, r) in records.chunks_exact(RECORD_BYTES).enumerate() {
            let (y_c, y_s) = checked_input(k, self.tamper);
            let output = update(&tracker, &mut state, T::input(y_c), T::input(y_s));
            fold(&state, &output);
            let e = tracker.record(&state, &output);
            let r = Record::decode(r);
            // Position difference, exact in the split form: whole turns, then the angle.
            let turns = e.turns.wrapping_sub(r.turns) as f32;
            let d = (turns * core::f32::consts::TAU + (e.angle - r.angle)).abs();
            if worse(d, position) {
                (position, worst) = (d, k);
            }
            let d = (e.speed - r.speed).abs() / speed_scale;
            if worse(d, speed) {
                speed = d;
            }
            let d = (e.acceleration - r.acceleration).abs() / acceleration_scale;
            if worse(d, acceleration) {
                acceleration = d;
            }
        }
        // The integers of the samples beyond the records (on the Cortex-M0) too.
        if INTEGERS[index].is_some() {
            for k in (0..SAMPLES).skip(CHECKED_SAMPLES) {
                let (y_c, y_s) = checked_input(k, self.tamper);
                let output = update(&tracker, &mut state, T::input(y_c), T::input(y_s));
                fold(&state, &output);
            }
        }
        let same_integers = integers == INTEGERS[index];
        let ok = position <= POSITION_TOLERANCE_RAD
            && speed <= RELATIVE_TOLERANCE
            && acceleration <= RELATIVE_TOLERANCE
            && same_integers;
        hprintln!(
            "check {}: {} samples, max |position - host| {:e} rad (sample {}), \
             speed {:e}, acceleration {:e} (relative){}: {}",
            NAMES[index],
            CHECKED_SAMPLES,
            position,
            worst,
            speed,
            acceleration,
            match (INTEGERS[index], same_integers) {
                (None, _) => "",
                (Some(_), true) => "; integers of all samples identical",
                (Some(_), false) => "; integers DIFFER",
            },
            if ok { "ok" } else { "FAIL" }
        );
        self.failures += usize::from(!ok);
    }
}

/// `check` mode for `count` mode's inputs: every variant's [`Tracker::counted_inputs`] must
/// be [`Tracker::input`] of every sample of the signal (the sine winding's middle sample
/// corrupted by [`TAMPER`] if `tamper`), so that the counted runs track the checked inputs.
struct CheckInputs {
    tamper: bool,
    /// Variants checked, and those whose counted inputs differ.
    variants: usize,
    differ: usize,
}

impl Job for CheckInputs {
    fn run<T: Tracker>(&mut self, _index: usize, _tracker: T) {
        let [c, s] = T::counted_inputs(&INPUTS);
        let same = c.len() == SAMPLES
            && s.len() == SAMPLES
            && (0..SAMPLES).all(|k| {
                let y_s = Y_S[k] + corruption(self.tamper, k, SAMPLES);
                c[k] == T::input(Y_C[k]) && s[k] == T::input(y_s)
            });
        self.variants += 1;
        self.differ += usize::from(!same);
    }
}

/// Points of the fast arctangent's error sweep: a full turn at each of three magnitudes.
const ATAN2_SWEEP_POINTS: usize = 4096;

/// `check` mode for the baselines' fast arctangent: its largest error against `atan2f`
/// over [`ATAN2_SWEEP_POINTS`] angles at magnitudes 0.1, 1 and 3 (and the axes, where the
/// octants meet), with `y` of the middle point fed to the fast arctangent corrupted if
/// `tamper`. Returns `true` if within [`FAST_ATAN2_MAX_ERROR_RAD`].
fn check_fast_atan2(tamper: bool) -> bool {
    let mut worst = 0.0f32;
    for (m, magnitude) in [0.1f32, 1.0, 3.0].into_iter().enumerate() {
        for k in 0..ATAN2_SWEEP_POINTS {
            let angle = core::f32::consts::TAU * k as f32 / ATAN2_SWEEP_POINTS as f32;
            let (sin, cos) = Float::sin_cos(angle);
            let (y, x) = (magnitude * sin, magnitude * cos);
            let exact = LibmAtan2::atan2(y, x);
            let point = m * ATAN2_SWEEP_POINTS + k;
            let fed = y + corruption(tamper, point, 3 * ATAN2_SWEEP_POINTS);
            let mut d = (FastAtan2::atan2(fed, x) - exact).abs();
            // atan2 at pi and -pi are the same angle.
            d = d.min((d - core::f32::consts::TAU).abs());
            if worse(d, worst) {
                worst = d;
            }
        }
    }
    let ok = worst <= FAST_ATAN2_MAX_ERROR_RAD;
    hprintln!(
        "check fast-atan2: {} points, max |fast - atan2f| {:e} rad (bound {:e}): {}",
        3 * ATAN2_SWEEP_POINTS,
        worst,
        FAST_ATAN2_MAX_ERROR_RAD,
        if ok { "ok" } else { "FAIL" }
    );
    ok
}

/// `true` if the difference `d` is larger than `worst` so far, or NaN (which must fail).
fn worse(d: f32, worst: f32) -> bool {
    d > worst || d.is_nan()
}

/// `count` mode: `samples` updates of one variant (or of the loop alone) and nothing else.
struct Count {
    samples: usize,
    loop_only: bool,
    block: bool,
}

impl Job for Count {
    fn run<T: Tracker>(&mut self, _index: usize, tracker: T) {
        let n = self.samples.min(SAMPLES);
        let mut state = tracker.new_state();
        if self.block {
            count_block(&tracker, &mut state, n);
            return;
        }
        let step = if self.loop_only {
            no_update::<T>
        } else {
            update::<T>
        };
        let step = black_box(step);
        // The inputs as the tracker takes them, converted before the run: the counted range
        // holds the update alone.
        let [y_c, y_s] = T::counted_inputs(&INPUTS);
        for (&y_c, &y_s) in y_c[..n].iter().zip(&y_s[..n]) {
            black_box(&step(&tracker, &mut state, y_c, y_s));
        }
    }
}

/// `count ... block` mode: block updates over the first `n` samples, [`BLOCK_SAMPLES`] at
/// a time (one call on the Cortex-M4F; the Cortex-M0's 16 KiB of RAM hold fewer estimates).
/// Out of line, so that each variant's estimates take the stack in turn.
#[inline(never)]
fn count_block<T: Tracker>(tracker: &T, state: &mut T::State, n: usize) {
    let mut out = [T::Output::default(); BLOCK_SAMPLES];
    for start in (0..n).step_by(BLOCK_SAMPLES) {
        let end = n.min(start + BLOCK_SAMPLES);
        let (y_c, y_s) = (&Y_C[start..end], &Y_S[start..end]);
        black_box(update_block(tracker, state, y_c, y_s, &mut out));
        black_box(&out);
    }
}

/// `functions` mode: the addresses of the variant's out-of-line functions, for the
/// symbol table: `update 0x...` (what `count` calls), and `update_block 0x...` if the
/// variant has a block form.
struct Functions;

impl Job for Functions {
    fn run<T: Tracker>(&mut self, _index: usize, _tracker: T) {
        let update = update::<T> as fn(_, _, _, _) -> _;
        hprintln!("update {:#x}", update as usize);
        if T::BLOCK {
            let block = update_block::<T> as fn(_, _, _, _, _) -> _;
            hprintln!("update_block {:#x}", block as usize);
        }
    }
}

/// The index of variant `name` (`loop`: [`LOOP_VARIANT`]'s).
fn variant(name: &str) -> Result<usize, &'static str> {
    let name = if name == "loop" { LOOP_VARIANT } else { name };
    NAMES
        .iter()
        .position(|&n| n == name)
        .ok_or("unknown variant")
}

/// Runs `job` on variant `index`.
fn run_variant(index: usize, job: &mut impl Job) -> Result<(), &'static str> {
    match OBSERVERS.run(index, job) {
        Ok(true) => Ok(()),
        Ok(false) => Err("unknown variant"),
        Err(_) => Err("gains refused"),
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
    match args.next() {
        Some("check") => {
            let mut check = Check {
                tamper: args.next() == Some("tamper"),
                failures: 0,
            };
            let mut inputs = CheckInputs {
                tamper: check.tamper,
                variants: 0,
                differ: 0,
            };
            for index in 0..NAMES.len() {
                run_variant(index, &mut check)?;
                run_variant(index, &mut inputs)?;
            }
            let inputs_ok = inputs.variants > 0 && inputs.differ == 0;
            hprintln!(
                "check counted-inputs: {} variants, {} samples, {} with counted inputs other \
                 than the checked ones: {}",
                inputs.variants,
                SAMPLES,
                inputs.differ,
                if inputs_ok { "ok" } else { "FAIL" }
            );
            // The f32 demodulator's inputs are not in the Cortex-M0's image.
            let f32_ok =
                !F32_DEMODULATOR || check_demodulator::<f32>(DEMODULATORS[0], check.tamper)?;
            let demodulator_ok = f32_ok & check_demodulator::<i16>(DEMODULATORS[1], check.tamper)?;
            let atan2_ok = check_fast_atan2(check.tamper);
            if check.failures > 0 || !inputs_ok || !demodulator_ok || !atan2_ok {
                return Err("estimates differ from the host's");
            }
            Ok(())
        }
        Some("variants") => {
            for name in NAMES {
                hprintln!("{}", name);
            }
            Ok(())
        }
        Some("functions") => {
            let name = args.next().ok_or("functions needs a variant")?;
            if name == DEMODULATORS[0] {
                demodulator_functions::<f32>();
                return Ok(());
            }
            if name == DEMODULATORS[1] {
                demodulator_functions::<i16>();
                return Ok(());
            }
            run_variant(variant(name)?, &mut Functions)
        }
        Some("count") => {
            let name = args.next().ok_or("count needs a variant")?;
            let samples = args
                .next()
                .and_then(|n| n.parse().ok())
                .ok_or("count needs a sample count")?;
            let block = args.next() == Some("block");
            if name == DEMODULATORS[0] {
                return count_demodulator::<f32>(samples, block);
            }
            if name == DEMODULATORS[1] {
                return count_demodulator::<i16>(samples, block);
            }
            let mut count = Count {
                samples,
                loop_only: name == "loop",
                block,
            };
            run_variant(variant(name)?, &mut count)
        }
        _ => Err("usage: check [tamper] | variants | functions <variant> \
                  | count <variant|loop|demodulator-f32|demodulator-fixed> <samples> [block]"),
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
