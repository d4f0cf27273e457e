//! The noise of a capture's angle, as the per-sample tracking check sees it: the scatter of
//! one sample's angle about a smooth motion, measured from the second differences of the
//! angles of consecutive samples (`crate::angle_noise`, which applies it to a capture's
//! first samples). A smooth motion's second difference is its acceleration times `Ts^2`,
//! about the same from one sample to the next; white noise of standard deviation `s` gives
//! second differences of standard deviation `sqrt(6) s`. Their median absolute deviation
//! (1.4826 times it estimates a Gaussian's standard deviation) ignores an outlier, a few
//! samples of a fault and the acceleration's own change.

use super::wrap;
use crate::lot::{MAD_TO_STD, median_of};

/// The fewest consecutive pairs the noise is measured on.
const MIN_PAIRS: usize = 16;

/// The standard deviation (rad) of the angle of `pairs` (consecutive samples `(y_c, y_s)`)
/// about a smooth motion, their angles taken about `centre`; `None` with fewer than
/// [`MIN_PAIRS`] pairs.
pub(crate) fn angle_noise_about(pairs: &[(f64, f64)], centre: (f64, f64)) -> Option<f64> {
    if pairs.len() < MIN_PAIRS {
        return None;
    }
    let angles: Vec<f64> = pairs
        .iter()
        .map(|&(c, s)| (s - centre.1).atan2(c - centre.0))
        .collect();
    // Wrapped at each step, so that a turn (or a speed up to half a turn per sample) adds
    // nothing.
    let steps: Vec<f64> = angles.windows(2).map(|w| wrap(w[1] - w[0])).collect();
    let mut second: Vec<f64> = steps.windows(2).map(|w| wrap(w[1] - w[0])).collect();
    let middle = median_of(&mut second);
    let mut deviations: Vec<f64> = second.iter().map(|d| (d - middle).abs()).collect();
    Some(MAD_TO_STD * median_of(&mut deviations) / 6f64.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// `n` pairs of amplitude 1 at `speed` rad per sample from angle 0.3, with Gaussian
    /// noise of `noise` per channel and one absurd sample.
    fn pairs(n: usize, speed: f64, noise: f64) -> Vec<(f64, f64)> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(35);
        let normal = Normal::new(0.0, noise).unwrap();
        let mut pairs: Vec<(f64, f64)> = (0..n)
            .map(|k| {
                let theta = 0.3 + speed * k as f64;
                (
                    theta.cos() + normal.sample(&mut rng),
                    theta.sin() + normal.sample(&mut rng),
                )
            })
            .collect();
        pairs[n / 2] = (-40.0, 3.0);
        pairs
    }

    #[test]
    fn the_angle_noise_is_the_channels_noise_over_the_amplitude_at_any_speed() {
        for speed in [0.0, 0.006, 0.3, 1.2] {
            for noise in [0.002, 0.01, 0.03] {
                let measured = angle_noise_about(&pairs(4096, speed, noise), (0.0, 0.0)).unwrap();
                assert!(
                    (measured / noise - 1.0).abs() < 0.1,
                    "speed {speed}, noise {noise}: {measured}"
                );
            }
        }
        let noise_free = pairs(64, 0.01, 0.0);
        assert!(angle_noise_about(&noise_free[..20], (0.0, 0.0)).unwrap() < 1e-12);
        assert_eq!(angle_noise_about(&noise_free[..15], (0.0, 0.0)), None);
    }
}
