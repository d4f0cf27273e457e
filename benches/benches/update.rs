//! Per-sample cost of every observer against the loop a user writes by hand.
//!
//! One criterion group per observer and float type (`kalman-f32`, ...), each with the
//! hand-written baseline (`baseline`: one struct, the standard library's `sin_cos`) and the
//! core's observer (a chain with no front end) with both phase-detector sin/cos (`exact`,
//! `fast`) through the per-sample API (`update-*`, a loop over `Chain::update`) and the
//! block API (`block-*`, `Chain::update_block`), and the fast one with the diagnostics off
//! (`update-fast-unmonitored`, `FaultThresholds::disabled()`: the bare loop), and
//! `ChannelBank`s of 16 and 64 channels sharing the gains (`bank-fast-16`, `bank-fast-64`,
//! throughput in channel-samples: `Chain::track_bank` with no front end, one `(y_c, y_s)`
//! pair per lane, the observers' step side by side on struct-of-arrays states). The single
//! stream's throughput (`update-fast-unmonitored`, the work a bank lane does) over a
//! bank's is the bank's gain per channel-sample.
//! Throughput is in samples, so every report reads as time per sample and the ratio to
//! `baseline` is the ratio of the reported times.
//!
//! Run: `cargo bench -p angletrack-benches` (or `bash scripts/perf-table.sh` for the guide's
//! tables).

use std::hint::black_box;

use angletrack_benches::{
    HandWrittenObserver, OBSERVERS, SAMPLE_PERIOD_S, benchmark_scenario, channels, float_name,
    gains,
};
use angletrack_core::{
    Chain, ChainState, ChannelBank, Estimate, Exact, Fast, FaultThresholds, Gains, ObserverState,
    Order, Real, SinCos, SupportedOrder,
};
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use num_traits::Float;

/// Samples per benchmark iteration (one block).
const BLOCK: usize = 1024;

/// Lanes of the multi-channel benchmarks: a bank of 16 (the axes of a machine; one sample of
/// the bank is a few vector registers, so it waits on the recursion's latency) and one of
/// 64 (a Monte Carlo batch; enough independent work per sample to be throughput-bound).
const LANES: [usize; 2] = [16, 64];

/// The block of samples and the true initial state every iteration starts from.
struct Workload<T> {
    y_c: Vec<T>,
    y_s: Vec<T>,
    angle_rad: f64,
    speed_rad_s: f64,
    acceleration_rad_s2: f64,
}

impl<T: Real> Workload<T> {
    fn new() -> Self {
        let signal = benchmark_scenario(BLOCK);
        let (y_c, y_s) = channels(&signal);
        Self {
            y_c,
            y_s,
            angle_rad: signal.angle_rad[0],
            speed_rad_s: signal.speed_rad_s[0],
            acceleration_rad_s2: signal.acceleration_rad_s2[0],
        }
    }

    /// The state of a chain with no front end at the workload's true initial state.
    fn initial_state<const N: usize>(&self) -> ChainState<(), ObserverState<T, N>> {
        // An order without an acceleration state starts without one.
        let acceleration = if N > 2 { self.acceleration_rad_s2 } else { 0.0 };
        let observer = ObserverState::at(
            T::from_f64(self.angle_rad),
            T::from_f64(self.speed_rad_s),
            T::from_f64(acceleration),
            T::from_f64(SAMPLE_PERIOD_S),
        )
        .unwrap();
        ChainState {
            front_end: (),
            observer,
        }
    }
}

/// The core's observer with sin/cos `S`, through the per-sample and the block API.
fn bench_core<T: Real, const N: usize, S: SinCos<T>>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    workload: &Workload<T>,
    l: [f64; N],
    sin_cos: &str,
) where
    Order<N>: SupportedOrder,
{
    let gains: Gains<T, N, S> = gains(l);
    bench_update(group, workload, gains, &format!("update-{sin_cos}"));
    let chain = Chain::new((), gains);
    let start = workload.initial_state::<N>();
    let mut out = vec![Estimate::default(); BLOCK];
    group.bench_function(format!("block-{sin_cos}"), |b| {
        b.iter(|| {
            let mut state = start;
            let inputs = workload
                .y_c
                .iter()
                .copied()
                .zip(workload.y_s.iter().copied());
            let n = chain.update_block(&mut state, inputs, &mut out);
            black_box(&out);
            (n, state)
        })
    });
}

/// The per-sample API: a loop over `Chain::update` (no front end).
fn bench_update<T: Real, const N: usize, S: SinCos<T>>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    workload: &Workload<T>,
    gains: Gains<T, N, S>,
    id: &str,
) {
    let chain = Chain::new((), gains);
    let start = workload.initial_state::<N>();
    group.bench_function(id, |b| {
        b.iter(|| {
            let mut state = start;
            for (&c, &s) in workload.y_c.iter().zip(&workload.y_s) {
                black_box(chain.update(&mut state, (c, s)));
            }
            state
        })
    });
}

/// `L` channels in a [`ChannelBank`] (a chain's bank form), lane `j` reading the
/// workload's samples from `j` on; the bank is initialised by its first sample outside the
/// timed loop.
fn bench_bank<T: Real, const N: usize, const L: usize>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    gains: Gains<T, N, Fast>,
    id: &str,
) {
    let signal = benchmark_scenario(BLOCK + L);
    let (c, s) = channels::<T>(&signal);
    let pairs: Vec<[(T, T); L]> = (0..=BLOCK)
        .map(|k| core::array::from_fn(|j| (c[k + j], s[k + j])))
        .collect();
    let chain = Chain::new((), gains);
    let mut start: ChainState<[(); L], ChannelBank<T, N, L>> = ChainState::new_bank();
    chain.track_bank(&mut start, &pairs[0]);
    group.throughput(Throughput::Elements((BLOCK * L) as u64));
    group.bench_function(id, |b| {
        b.iter(|| {
            let mut bank = start;
            for inputs in &pairs[1..] {
                chain.track_bank(&mut bank, inputs);
            }
            bank
        })
    });
    group.throughput(Throughput::Elements(BLOCK as u64));
}

/// One group: the hand-written baseline, then the core's observer with both sin/cos.
fn bench_observer<T: Real + Float, const N: usize>(c: &mut Criterion, name: &str, l: [f64; 3])
where
    Order<N>: SupportedOrder,
{
    let workload = Workload::<T>::new();
    let mut group = c.benchmark_group(format!("{name}-{}", float_name::<T>()));
    group.throughput(Throughput::Elements(BLOCK as u64));
    let start = HandWrittenObserver::<T>::new(
        l,
        workload.angle_rad,
        workload.speed_rad_s,
        workload.acceleration_rad_s2,
    );
    group.bench_function("baseline", |b| {
        b.iter(|| {
            let mut observer = start;
            for (&c, &s) in workload.y_c.iter().zip(&workload.y_s) {
                black_box(observer.update(c, s));
            }
            observer
        })
    });
    let l: [f64; N] = core::array::from_fn(|i| l[i]);
    bench_core::<T, N, Exact>(&mut group, &workload, l, "exact");
    bench_core::<T, N, Fast>(&mut group, &workload, l, "fast");
    let bare = gains::<T, N, Fast>(l)
        .with_fault_thresholds(FaultThresholds::disabled())
        .expect("the default thresholds are valid");
    bench_update(&mut group, &workload, bare, "update-fast-unmonitored");
    bench_bank::<T, N, { LANES[0] }>(&mut group, gains(l), &format!("bank-fast-{}", LANES[0]));
    bench_bank::<T, N, { LANES[1] }>(&mut group, gains(l), &format!("bank-fast-{}", LANES[1]));
    group.finish();
}

fn observers(c: &mut Criterion) {
    for (name, l) in OBSERVERS {
        if l[2] == 0.0 {
            bench_observer::<f32, 2>(c, name, l);
            bench_observer::<f64, 2>(c, name, l);
        } else {
            bench_observer::<f32, 3>(c, name, l);
            bench_observer::<f64, 3>(c, name, l);
        }
    }
}

criterion_group!(benches, observers);
criterion_main!(benches);
