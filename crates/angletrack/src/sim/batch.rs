//! Any number of channels on one gain set: several axes, or a Monte Carlo batch.

use angletrack_core::{Chain, ChainState, ChannelBank, Float, Gains, Real, SinCos};

use super::columns::{EstimateColumns, Output};
use crate::error::{Argument, Error};

/// Lanes of each [`ChannelBank`] of a [`ChannelBatch`]: 8 channels run side by side.
pub const LANES: usize = 8;

/// Samples a bank runs between the gather of its inputs and the scatter of its outputs:
/// the block's lane-major copies (inputs and outputs, at most 57 KiB in `f64`) stay in the
/// cache while each channel's row is read and written in runs of this many samples.
const BLOCK: usize = 128;

/// Runs `channels` independent observers that share one gain set, [`LANES`] at a time in
/// the core's struct-of-arrays [`ChannelBank`]s (the bank form of a chain with no front
/// end, [`Chain::track_bank`]). The state persists between calls, so a
/// batch fed in chunks gives exactly the result of one call; every channel gives exactly
/// what a single observer with the same gains and no fault monitor would.
///
/// Samples and outputs are `channels x samples` arrays in row-major order (channel `c`,
/// sample `k` at `c * samples + k`).
#[derive(Debug, Clone)]
pub struct ChannelBatch<T: Real, const N: usize, S = <T as Float>::DefaultSinCos> {
    chain: Chain<(), Gains<T, N, S>>,
    channels: usize,
    banks: Vec<BankState<T, N>>,
}

/// The state of one bank: its lanes' observers side by side (no front end).
type BankState<T, const N: usize> = ChainState<[(); LANES], ChannelBank<T, N, LANES>>;

impl<T: Real, const N: usize, S: SinCos<T>> ChannelBatch<T, N, S> {
    /// A batch of `channels` observers, each initialised by its first valid sample.
    ///
    /// ```
    /// use angletrack::{ChannelBatch, Gains};
    /// let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
    /// let batch = ChannelBatch::new(gains, 10)?;
    /// assert_eq!(batch.channels(), 10);
    /// assert!(ChannelBatch::new(gains, 0).is_err());
    /// assert!(ChannelBatch::new(gains, 1 << 40).is_err()); // more state than memory
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn new(gains: Gains<T, N, S>, channels: usize) -> Result<Self, Error> {
        if channels == 0 {
            return Err(Error::OutOfRange {
                argument: Argument::Channels,
                expected: "at least 1",
            });
        }
        // A number of channels whose state does not fit in memory is refused, not an abort.
        let mut banks = Vec::new();
        banks
            .try_reserve_exact(channels.div_ceil(LANES))
            .map_err(|_| Error::OutOfRange {
                argument: Argument::Channels,
                expected: "a number of channels whose state fits in memory",
            })?;
        banks.resize(channels.div_ceil(LANES), ChainState::new_bank());
        Ok(Self {
            chain: Chain::new((), gains),
            channels,
            banks,
        })
    }

    /// The number of channels.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The gains every channel runs with.
    pub fn gains(&self) -> &Gains<T, N, S> {
        &self.chain.observer
    }

    /// Runs every channel over its samples: `y_c` and `y_s` hold `channels x samples`
    /// values (row-major), and so does each column of `out` present; the quantities whose
    /// column is `None` are neither written nor converted to physical units. Refuses
    /// (naming the series) inputs or columns whose lengths are not `channels * samples`.
    ///
    /// Each bank reads a block of samples of its channels' rows into a lane-major copy,
    /// runs it, and writes the block's outputs back into the rows: each row is read and
    /// written in runs of contiguous samples, and no allocation is made beyond that
    /// block's buffer (one per call).
    ///
    /// ```
    /// use angletrack::{ChannelBatch, EstimateColumns, Gains};
    /// let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4)?;
    /// let mut batch = ChannelBatch::new(gains, 3)?;
    /// let (samples, n) = (4, 12);
    /// let y_c: Vec<f64> = (0..n).map(|i| ((i / samples) as f64).cos()).collect();
    /// let y_s: Vec<f64> = (0..n).map(|i| ((i / samples) as f64).sin()).collect();
    /// let (mut angle, mut speed) = (vec![0.0; n], vec![0.0; n]);
    /// batch.run(&y_c, &y_s, samples, EstimateColumns {
    ///     angle: Some(&mut angle), speed: Some(&mut speed), ..Default::default()
    /// })?;
    /// assert!((angle[2 * samples] - 2.0).abs() < 1e-12); // channel 2 sits at 2 rad
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn run(
        &mut self,
        y_c: &[T],
        y_s: &[T],
        samples: usize,
        mut out: EstimateColumns<'_, T>,
    ) -> Result<(), Error> {
        let total = self
            .channels
            .checked_mul(samples)
            .ok_or(Error::OutOfRange {
                argument: Argument::SeriesLength,
                expected: "channels * samples representable",
            })?;
        if y_c.len() != total || y_s.len() != total || !out.all_of_len(total) {
            return Err(Error::OutOfRange {
                argument: Argument::SeriesLength,
                expected: "every input and output of channels * samples values",
            });
        }
        let mut block = Block::new(&out);
        for (b, bank) in self.banks.iter_mut().enumerate() {
            let rows = Rows {
                first: b * LANES,
                lanes: LANES.min(self.channels - b * LANES),
                samples,
            };
            // Unused lanes of the last bank run on a constant valid sample.
            block.inputs_from(rows.lanes);
            for start in (0..samples).step_by(BLOCK) {
                let len = BLOCK.min(samples - start);
                rows.gather(&mut block.inputs[..len], (y_c, y_s), start);
                block.run(&self.chain, bank, len, &out);
                block.scatter(&rows, start, len, &mut out);
            }
        }
        Ok(())
    }
}

/// The channels of one bank in the `channels x samples` arrays of a run.
struct Rows {
    /// The channel of lane 0.
    first: usize,
    /// The lanes holding a channel (the last bank's may be fewer than [`LANES`]).
    lanes: usize,
    /// Samples per channel (the rows' length).
    samples: usize,
}

impl Rows {
    /// The part of `lane`'s row from sample `start` on, `len` samples.
    fn range(&self, lane: usize, start: usize, len: usize) -> core::ops::Range<usize> {
        let from = (self.first + lane) * self.samples + start;
        from..from + len
    }

    /// Copies `block.len()` samples from `start` on of each lane's rows of `y_c` and `y_s`
    /// into the lane-major `block` of `(y_c, y_s)` pairs.
    fn gather<E: Copy>(
        &self,
        block: &mut [[(E, E); LANES]],
        (y_c, y_s): (&[E], &[E]),
        start: usize,
    ) {
        for lane in 0..self.lanes {
            let range = self.range(lane, start, block.len());
            for (to, (&c, &s)) in block
                .iter_mut()
                .zip(y_c[range.clone()].iter().zip(&y_s[range]))
            {
                to[lane] = (c, s);
            }
        }
    }

    /// Copies the lane-major `block` into each lane's row of `column` from `start` on.
    fn scatter<E: Copy>(&self, block: &[[E; LANES]], column: &mut [E], start: usize) {
        for lane in 0..self.lanes {
            let row = &mut column[self.range(lane, start, block.len())];
            for (to, from) in row.iter_mut().zip(block) {
                *to = from[lane];
            }
        }
    }
}

/// One bank's samples and estimates over [`BLOCK`] samples, lane-major (`[k][lane]`), as
/// the bank reads and writes them; empty for an output not asked for.
struct Block<T> {
    inputs: Vec<[(T, T); LANES]>,
    angle: Vec<[T; LANES]>,
    position: Vec<[f64; LANES]>,
    speed: Vec<[T; LANES]>,
    acceleration: Vec<[T; LANES]>,
    phase_error: Vec<[T; LANES]>,
    faults: Vec<[u8; LANES]>,
}

impl<T: Real> Block<T> {
    /// The buffers of the inputs and of the outputs `out` holds.
    fn new(out: &EstimateColumns<'_, T>) -> Self {
        fn lanes<E: Copy>(wanted: bool, value: E) -> Vec<[E; LANES]> {
            vec![[value; LANES]; if wanted { BLOCK } else { 0 }]
        }
        Self {
            inputs: lanes(true, (T::ONE, T::ZERO)),
            angle: lanes(out.has(Output::Angle), T::ZERO),
            position: lanes(out.has(Output::Position), 0.0),
            speed: lanes(out.has(Output::Speed), T::ZERO),
            acceleration: lanes(out.has(Output::Acceleration), T::ZERO),
            phase_error: lanes(out.has(Output::PhaseError), T::ZERO),
            faults: lanes(out.has(Output::Faults), 0),
        }
    }

    /// Sets the inputs of the lanes from `lanes` on to the constant valid sample (1, 0).
    fn inputs_from(&mut self, lanes: usize) {
        for pairs in &mut self.inputs {
            pairs[lanes..].fill((T::ONE, T::ZERO));
        }
    }

    /// Runs `bank` over the block's first `len` samples, keeping the estimates `out` holds.
    #[inline]
    fn run<const N: usize, S: SinCos<T>>(
        &mut self,
        chain: &Chain<(), Gains<T, N, S>>,
        bank: &mut BankState<T, N>,
        len: usize,
        out: &EstimateColumns<'_, T>,
    ) {
        let [angle, position, speed, acceleration, phase_error, faults] =
            Output::ALL.map(|output| out.has(output));
        for k in 0..len {
            chain.track_bank(bank, &self.inputs[k]);
            // One loop over the lanes per output asked for: each keeps only its part of
            // the estimate, and the branch-free ones run side by side.
            let estimate = |lane| {
                (chain.observer)
                    .bank_estimate(&bank.observer, lane)
                    .unwrap_or_default()
            };
            if angle {
                self.angle[k] = core::array::from_fn(|lane| estimate(lane).angle);
            }
            if position {
                self.position[k] = core::array::from_fn(|lane| estimate(lane).position());
            }
            if speed {
                self.speed[k] = core::array::from_fn(|lane| estimate(lane).speed);
            }
            if acceleration {
                self.acceleration[k] = core::array::from_fn(|lane| estimate(lane).acceleration);
            }
            if phase_error {
                self.phase_error[k] = core::array::from_fn(|lane| estimate(lane).phase_error);
            }
            if faults {
                self.faults[k] = core::array::from_fn(|lane| estimate(lane).faults.bits());
            }
        }
    }

    /// Writes the block's first `len` estimates into the columns `out` holds.
    fn scatter(&self, rows: &Rows, start: usize, len: usize, out: &mut EstimateColumns<'_, T>) {
        if let Some(column) = out.angle.as_deref_mut() {
            rows.scatter(&self.angle[..len], column, start);
        }
        if let Some(column) = out.position.as_deref_mut() {
            rows.scatter(&self.position[..len], column, start);
        }
        if let Some(column) = out.speed.as_deref_mut() {
            rows.scatter(&self.speed[..len], column, start);
        }
        if let Some(column) = out.acceleration.as_deref_mut() {
            rows.scatter(&self.acceleration[..len], column, start);
        }
        if let Some(column) = out.phase_error.as_deref_mut() {
            rows.scatter(&self.phase_error[..len], column, start);
        }
        if let Some(column) = out.faults.as_deref_mut() {
            rows.scatter(&self.faults[..len], column, start);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::{Fast, FaultThresholds, Faults};

    struct Outputs<T> {
        angle: Vec<T>,
        position: Vec<f64>,
        speed: Vec<T>,
        acceleration: Vec<T>,
        phase_error: Vec<T>,
        faults: Vec<u8>,
    }

    impl<T: Real> Outputs<T> {
        fn new(n: usize) -> Self {
            Self {
                angle: vec![T::ZERO; n],
                position: vec![0.0; n],
                speed: vec![T::ZERO; n],
                acceleration: vec![T::ZERO; n],
                phase_error: vec![T::ZERO; n],
                faults: vec![0; n],
            }
        }
        fn columns(&mut self) -> EstimateColumns<'_, T> {
            EstimateColumns {
                angle: Some(&mut self.angle),
                position: Some(&mut self.position),
                speed: Some(&mut self.speed),
                acceleration: Some(&mut self.acceleration),
                phase_error: Some(&mut self.phase_error),
                faults: Some(&mut self.faults),
            }
        }
    }

    /// Samples `y_c`, `y_s` of `channels x samples`.
    type Inputs = (Vec<f32>, Vec<f32>);

    /// Each channel its own speed, with NaNs.
    fn inputs(channels: usize, samples: usize) -> Inputs {
        let mut y_c = vec![0.0; channels * samples];
        let mut y_s = vec![0.0; channels * samples];
        for c in 0..channels {
            for k in 0..samples {
                let theta = 0.2 * c as f64 + (30.0 + 17.0 * c as f64) * k as f64 * 1e-4;
                y_c[c * samples + k] = theta.cos() as f32;
                y_s[c * samples + k] = if (k + c) % 211 == 0 {
                    f32::NAN
                } else {
                    theta.sin() as f32
                };
            }
        }
        (y_c, y_s)
    }

    /// The gains of the tests, and the inputs of `channels x samples` with a fresh batch's
    /// every output over them.
    fn full_run(channels: usize, samples: usize) -> (Gains<f32, 3, Fast>, Inputs, Outputs<f32>) {
        let gains = Gains::<f32, 3, Fast>::new([0.061, 0.0019, 3.1e-5], 1e-4).unwrap();
        let (y_c, y_s) = inputs(channels, samples);
        let mut whole = Outputs::new(channels * samples);
        ChannelBatch::new(gains, channels)
            .unwrap()
            .run(&y_c, &y_s, samples, whole.columns())
            .unwrap();
        (gains, (y_c, y_s), whole)
    }

    #[test]
    fn a_batch_gives_each_channel_exactly_a_single_observer_and_streams() {
        let (channels, samples) = (11, 3000);
        let (gains, (y_c, y_s), whole) = full_run(channels, samples);
        let single = Chain::new(
            (),
            gains
                .with_fault_thresholds(FaultThresholds::disabled())
                .unwrap(),
        );
        for c in 0..channels {
            let mut state = ChainState::new();
            for k in 0..samples {
                let i = c * samples + k;
                let e = single.update(&mut state, (y_c[i], y_s[i]));
                assert_eq!(
                    (
                        e.angle,
                        e.position(),
                        e.speed,
                        e.acceleration,
                        e.phase_error,
                        e.faults.bits()
                    ),
                    (
                        whole.angle[i],
                        whole.position[i],
                        whole.speed[i],
                        whole.acceleration[i],
                        whole.phase_error[i],
                        whole.faults[i]
                    ),
                    "channel {c}, sample {k}"
                );
            }
        }
        assert!(whole.faults.iter().any(|&f| f == Faults::BAD_SAMPLE.bits()));
        // In two chunks of 1000 and 2000 samples: the same.
        let mut batch = ChannelBatch::new(gains, channels).unwrap();
        for (start, len) in [(0, 1000), (1000, 2000)] {
            let pick = |v: &[f32]| -> Vec<f32> {
                (0..channels)
                    .flat_map(|c| v[c * samples + start..c * samples + start + len].to_vec())
                    .collect()
            };
            let mut part = Outputs::new(channels * len);
            batch
                .run(&pick(&y_c), &pick(&y_s), len, part.columns())
                .unwrap();
            for c in 0..channels {
                for k in 0..len {
                    assert_eq!(
                        part.angle[c * len + k],
                        whole.angle[c * samples + start + k]
                    );
                    assert_eq!(
                        part.position[c * len + k],
                        whole.position[c * samples + start + k]
                    );
                }
            }
        }
    }

    #[test]
    fn selected_outputs_are_exactly_those_of_a_full_run() {
        // Blocks of 128 samples: 300 ends inside one, 13 channels inside a bank.
        let (channels, samples) = (13, 300);
        let (gains, (y_c, y_s), whole) = full_run(channels, samples);
        let n = channels * samples;
        let (mut angle, mut speed) = (vec![7.0_f32; n], vec![7.0_f32; n]);
        ChannelBatch::new(gains, channels)
            .unwrap()
            .run(
                &y_c,
                &y_s,
                samples,
                EstimateColumns {
                    angle: Some(&mut angle),
                    speed: Some(&mut speed),
                    ..Default::default()
                },
            )
            .unwrap();
        assert_eq!((angle, speed), (whole.angle.clone(), whole.speed.clone()));
        let (mut position, mut faults) = (vec![7.0; n], vec![7_u8; n]);
        let mut batch = ChannelBatch::new(gains, channels).unwrap();
        let columns = EstimateColumns {
            position: Some(&mut position),
            faults: Some(&mut faults),
            ..Default::default()
        };
        assert!(!columns.has(Output::Angle) && columns.has(Output::Faults));
        batch.run(&y_c, &y_s, samples, columns).unwrap();
        assert_eq!((position, faults), (whole.position, whole.faults));
        // No output at all still runs the channels: the next call goes on from there.
        let mut quiet = ChannelBatch::new(gains, channels).unwrap();
        quiet
            .run(&y_c, &y_s, samples, EstimateColumns::default())
            .unwrap();
        let mut angle_quiet = vec![0.0; n];
        let mut angle_batch = vec![0.0; n];
        for (b, angle) in [
            (&mut quiet, &mut angle_quiet),
            (&mut batch, &mut angle_batch),
        ] {
            let columns = EstimateColumns {
                angle: Some(angle),
                ..Default::default()
            };
            b.run(&y_c, &y_s, samples, columns).unwrap();
        }
        assert_eq!(angle_quiet, angle_batch);
    }

    #[test]
    fn a_batch_refuses_mismatched_lengths_naming_them() {
        let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap();
        let mut batch = ChannelBatch::new(gains, 2).unwrap();
        let mut out = Outputs::new(6);
        let err = batch
            .run(&[1.0; 6], &[0.0; 5], 3, out.columns())
            .unwrap_err();
        assert_eq!(err.argument(), Some(Argument::SeriesLength));
        let mut short = [0.0; 5];
        let columns = EstimateColumns {
            speed: Some(&mut short),
            ..Default::default()
        };
        let err = batch.run(&[1.0; 6], &[0.0; 6], 3, columns).unwrap_err();
        assert_eq!(err.argument(), Some(Argument::SeriesLength));
        let err = ChannelBatch::new(gains, 0).unwrap_err();
        assert_eq!(err.argument(), Some(Argument::Channels));
        assert!(batch.run(&[1.0; 6], &[0.0; 6], 3, out.columns()).is_ok());
    }
}
