//! The jerk's standard deviation from the third differences of the angle
//! (`docs/theory.md §16.2`), the noise's share taken out.

use super::estimate::Uncertain;

/// `sum d_k^2` of the third difference at stride `h` of the scaled angle's response to one
/// sample of unit jerk (`G = (1/6, 1/2, 1)`): `var(third difference) = q * factor`.
pub(super) fn third_difference_factor(h: usize) -> f64 {
    // The angle after the jerk, zero before it: theta[1] = 1/6, then constant acceleration.
    let mut theta = vec![0.0; 3 * h + 1];
    let (mut angle, mut speed) = (1.0 / 6.0, 0.5);
    for value in theta.iter_mut().skip(1) {
        *value = angle;
        angle += speed + 0.5;
        speed += 1.0;
    }
    let at = |m: isize| if m < 1 { 0.0 } else { theta[m as usize] };
    let h = h as isize;
    (-3 * h..=0)
        .map(|k| at(k + 3 * h) - 3.0 * at(k + 2 * h) + 3.0 * at(k + h) - at(k))
        .map(|d| d * d)
        .sum()
}

/// The autocovariance at lag `m` of white (`white`) plus autoregressive noise.
fn noise_autocovariance(m: usize, white: f64, coloured: f64, pole: f64) -> f64 {
    coloured * pole.powi(m as i32) + if m == 0 { white } else { 0.0 }
}

/// The jerk's standard deviation from the third differences of `angle` at the stride where
/// they stand well above the angle's noise (`noise`: white, coloured variance and pole).
pub(super) fn jerk_std(angle: &[f64], ts: f64, noise: (f64, f64, f64)) -> Uncertain {
    let n = angle.len();
    let (white, coloured, pole) = noise;
    let mut h = 1;
    loop {
        let count = n - 3 * h;
        let mean_square = (0..count)
            .map(|k| angle[k + 3 * h] - 3.0 * angle[k + 2 * h] + 3.0 * angle[k + h] - angle[k])
            .map(|d| d * d)
            .sum::<f64>()
            / count as f64;
        let c = |m| noise_autocovariance(m, white, coloured, pole);
        let from_noise = 20.0 * c(0) - 30.0 * c(h) + 12.0 * c(2 * h) - 2.0 * c(3 * h);
        let enough = mean_square > 3.0 * from_noise;
        // Stop before the next stride leaves fewer than 16 independent differences.
        if enough || 3 * (2 * h) * 16 > n {
            // The mean square's sampling spread, over the independent differences.
            let independent = (count as f64 / (3 * h) as f64).max(1.0);
            let spread = (2.0 / independent).sqrt() * mean_square;
            let factor = third_difference_factor(h);
            let jerk = |variance: f64| (variance.max(0.0) / factor).sqrt() / ts.powi(3);
            let motion = mean_square - from_noise;
            let value = jerk(motion);
            // Where the motion hardly stands out of the spread, the jerk that would just
            // match the spread is the uncertainty: an upper bound, not a measure.
            let std = if motion > 2.0 * spread {
                0.5 * value * spread / motion
            } else {
                jerk(spread)
            };
            return Uncertain { value, std };
        }
        h *= 2;
    }
}
