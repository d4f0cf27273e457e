//! Any number of channels on one gain set: several axes, or a Monte Carlo batch.

use angletrack_core::{ChannelBank, Gains, Real, SinCos};

use crate::error::{Argument, Error};

/// Lanes of each [`ChannelBank`] of a [`ChannelBatch`]: 8 channels run side by side.
pub const LANES: usize = 8;

/// Runs `channels` independent observers that share one gain set, [`LANES`] at a time in
/// the core's struct-of-arrays [`ChannelBank`]s. The state persists between calls, so a
/// batch fed in chunks gives exactly the result of one call; every channel gives exactly
/// what a single observer with the same gains and no fault monitor would.
///
/// Samples and outputs are `channels x samples` arrays in row-major order (channel `c`,
/// sample `k` at `c * samples + k`).
#[derive(Debug, Clone)]
pub struct ChannelBatch<T: Real, const N: usize, S = <T as Real>::DefaultSinCos> {
    gains: Gains<T, N, S>,
    channels: usize,
    banks: Vec<ChannelBank<T, N, LANES>>,
}

/// The outputs of [`ChannelBatch::run`]: one `channels x samples` row-major slice per
/// quantity, filled in place.
#[derive(Debug)]
pub struct BatchColumns<'a, T> {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    pub angle: &'a mut [T],
    /// Multi-turn position `turns * 2 pi + angle` (rad).
    pub position: &'a mut [f64],
    /// Estimated speed (rad/s).
    pub speed: &'a mut [T],
    /// Estimated acceleration (rad/s^2); 0 at order 2.
    pub acceleration: &'a mut [T],
    /// Phase-detector output.
    pub phase_error: &'a mut [T],
    /// Fault bits: [`Faults::BAD_SAMPLE`](angletrack_core::Faults::BAD_SAMPLE) for a rejected sample (the bank runs no monitor).
    pub faults: &'a mut [u8],
}

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
        banks.resize(channels.div_ceil(LANES), ChannelBank::new());
        Ok(Self {
            gains,
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
        &self.gains
    }

    /// Runs every channel over its samples: `y_c` and `y_s` hold `channels x samples`
    /// values (row-major), and so does each output column. Refuses (naming the series)
    /// inputs or outputs whose lengths are not `channels * samples`.
    ///
    /// ```
    /// use angletrack::{BatchColumns, ChannelBatch, Gains};
    /// let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4)?;
    /// let mut batch = ChannelBatch::new(gains, 3)?;
    /// let (samples, n) = (4, 12);
    /// let y_c: Vec<f64> = (0..n).map(|i| ((i / samples) as f64).cos()).collect();
    /// let y_s: Vec<f64> = (0..n).map(|i| ((i / samples) as f64).sin()).collect();
    /// let (mut angle, mut speed, mut accel, mut eps) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    /// let (mut position, mut faults) = (vec![0.0; n], vec![0u8; n]);
    /// batch.run(&y_c, &y_s, samples, BatchColumns {
    ///     angle: &mut angle, position: &mut position, speed: &mut speed,
    ///     acceleration: &mut accel, phase_error: &mut eps, faults: &mut faults,
    /// })?;
    /// assert!((angle[2 * samples] - 2.0).abs() < 1e-12); // channel 2 sits at 2 rad
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn run(
        &mut self,
        y_c: &[T],
        y_s: &[T],
        samples: usize,
        out: BatchColumns<'_, T>,
    ) -> Result<(), Error> {
        let total = self
            .channels
            .checked_mul(samples)
            .ok_or(Error::OutOfRange {
                argument: Argument::SeriesLength,
                expected: "channels * samples representable",
            })?;
        let lengths = [
            y_c.len(),
            y_s.len(),
            out.angle.len(),
            out.position.len(),
            out.speed.len(),
            out.acceleration.len(),
            out.phase_error.len(),
            out.faults.len(),
        ];
        if lengths.iter().any(|&len| len != total) {
            return Err(Error::OutOfRange {
                argument: Argument::SeriesLength,
                expected: "every input and output of channels * samples values",
            });
        }
        let gains = self.gains;
        for (b, bank) in self.banks.iter_mut().enumerate() {
            let first = b * LANES;
            let lanes = LANES.min(self.channels - first);
            // Unused lanes of the last bank run on a constant valid sample.
            let (mut c, mut s) = ([T::ONE; LANES], [T::ZERO; LANES]);
            for k in 0..samples {
                for lane in 0..lanes {
                    let i = (first + lane) * samples + k;
                    c[lane] = y_c[i];
                    s[lane] = y_s[i];
                }
                gains.update_bank(bank, &c, &s);
                for lane in 0..lanes {
                    let i = (first + lane) * samples + k;
                    if let Some(e) = gains.bank_estimate(bank, lane) {
                        out.angle[i] = e.angle;
                        out.position[i] = e.position();
                        out.speed[i] = e.speed;
                        out.acceleration[i] = e.acceleration;
                        out.phase_error[i] = e.phase_error;
                        out.faults[i] = e.faults.bits();
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use angletrack_core::{Fast, FaultThresholds, Faults, ObserverState};

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
        fn columns(&mut self) -> BatchColumns<'_, T> {
            BatchColumns {
                angle: &mut self.angle,
                position: &mut self.position,
                speed: &mut self.speed,
                acceleration: &mut self.acceleration,
                phase_error: &mut self.phase_error,
                faults: &mut self.faults,
            }
        }
    }

    /// 11 channels (one full bank and a partial one), each its own speed, with NaNs.
    fn inputs(channels: usize, samples: usize) -> (Vec<f32>, Vec<f32>) {
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

    #[test]
    fn a_batch_gives_each_channel_exactly_a_single_observer_and_streams() {
        let gains = Gains::<f32, 3, Fast>::new([0.061, 0.0019, 3.1e-5], 1e-4).unwrap();
        let (channels, samples) = (11, 3000);
        let (y_c, y_s) = inputs(channels, samples);
        let mut whole = Outputs::new(channels * samples);
        ChannelBatch::new(gains, channels)
            .unwrap()
            .run(&y_c, &y_s, samples, whole.columns())
            .unwrap();
        let single = gains
            .with_fault_thresholds(FaultThresholds::disabled())
            .unwrap();
        for c in 0..channels {
            let mut state = ObserverState::new();
            for k in 0..samples {
                let i = c * samples + k;
                let e = single.update(&mut state, y_c[i], y_s[i]);
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
    fn a_batch_refuses_mismatched_lengths_naming_them() {
        let gains = Gains::<f64, 2>::new([0.06, 0.001], 1e-4).unwrap();
        let mut batch = ChannelBatch::new(gains, 2).unwrap();
        let mut out = Outputs::new(6);
        let err = batch
            .run(&[1.0; 6], &[0.0; 5], 3, out.columns())
            .unwrap_err();
        assert_eq!(err.argument(), Some(Argument::SeriesLength));
        let err = ChannelBatch::new(gains, 0).unwrap_err();
        assert_eq!(err.argument(), Some(Argument::Channels));
        assert!(batch.run(&[1.0; 6], &[0.0; 6], 3, out.columns()).is_ok());
    }
}
