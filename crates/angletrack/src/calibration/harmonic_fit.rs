//! The least-squares fit of an angle error on the harmonics of the angle, sample by sample
//! in constant memory, with each coefficient's uncertainty (`docs/theory.md §12`).
//!
//! The model is `e = e_0 + sum_k a_k cos(k theta) + b_k sin(k theta)`, orders
//! `1..=SPECTRUM_ORDERS` (those the capture resolves). The normal equations are summed per
//! block of whole turns; the blocks give the uncertainty: the spread of the coefficients
//! fitted on each block, divided by the square root of their number (batch means), which
//! holds for noise of any colour (the loop's, a speed ripple's), and never less than the
//! white-noise bound `sigma^2 (A^T A)^-1` of the residual. There are at most
//! [`MAX_BLOCKS`] blocks: when one more would be needed, neighbours are merged and the block
//! length doubles, so a block holds between a half and all of `1/16` of the capture once it
//! is longer than 32 turns.

use nalgebra::{Complex, DMatrix, DVector};

/// The harmonic orders fitted, whether learned or only reported: twice the orders of a
/// correction table less 4, so that the residual's spectrum shows what lies beyond it.
pub const SPECTRUM_ORDERS: usize = 12;

/// The unknowns: the mean and the cosine and sine of each order.
const PARAMETERS: usize = 1 + 2 * SPECTRUM_ORDERS;

/// The most blocks kept (see the module's documentation).
const MAX_BLOCKS: usize = 32;

/// The normal equations `A^T A x = A^T e` of some samples, and `e^T e`.
#[derive(Debug, Clone)]
struct Normal {
    /// `A^T A`, upper triangle, row-major `PARAMETERS x PARAMETERS`.
    ata: Vec<f64>,
    atb: [f64; PARAMETERS],
    btb: f64,
    count: u64,
}

impl Normal {
    fn new() -> Self {
        Self {
            ata: vec![0.0; PARAMETERS * PARAMETERS],
            atb: [0.0; PARAMETERS],
            btb: 0.0,
            count: 0,
        }
    }

    fn add(&mut self, basis: &[f64; PARAMETERS], error: f64) {
        for (i, &bi) in basis.iter().enumerate() {
            let row = &mut self.ata[i * PARAMETERS..(i + 1) * PARAMETERS];
            for (slot, &bj) in row[i..].iter_mut().zip(&basis[i..]) {
                *slot += bi * bj;
            }
            self.atb[i] += bi * error;
        }
        self.btb += error * error;
        self.count += 1;
    }

    fn merge(&mut self, other: &Normal) {
        for (a, b) in self.ata.iter_mut().zip(&other.ata) {
            *a += b;
        }
        for (a, b) in self.atb.iter_mut().zip(&other.atb) {
            *a += b;
        }
        self.btb += other.btb;
        self.count += other.count;
    }

    /// `A^T A` of the `used` parameters (the others get an identity row, so that they solve
    /// to 0).
    fn matrix(&self, used: &[bool; PARAMETERS]) -> DMatrix<f64> {
        DMatrix::from_fn(PARAMETERS, PARAMETERS, |i, j| {
            if !(used[i] && used[j]) {
                return if i == j { 1.0 } else { 0.0 };
            }
            self.ata[i.min(j) * PARAMETERS + i.max(j)]
        })
    }

    /// The least-squares solution and the diagonal of `(A^T A)^-1`; `None` when singular.
    fn solve(&self, used: &[bool; PARAMETERS]) -> Option<(DVector<f64>, DVector<f64>)> {
        let cholesky = self.matrix(used).cholesky()?;
        let rhs = DVector::from_fn(PARAMETERS, |i, _| if used[i] { self.atb[i] } else { 0.0 });
        let x = cholesky.solve(&rhs);
        Some((x, cholesky.inverse().diagonal()))
    }

    /// `|e - A x|^2`.
    fn residual_squares(&self, x: &DVector<f64>) -> f64 {
        let a = self.matrix(&[true; PARAMETERS]);
        let atb = DVector::from_column_slice(&self.atb);
        (self.btb - 2.0 * x.dot(&atb) + x.dot(&(a * x))).max(0.0)
    }
}

/// The fit of an angle error on the harmonics of the angle (see the module's documentation).
#[derive(Debug, Clone)]
pub(crate) struct HarmonicFit {
    used: [bool; PARAMETERS],
    blocks: Vec<Normal>,
    block_turns: f64,
    start: Option<f64>,
}

/// What [`HarmonicFit::finish`] gives.
#[derive(Debug, Clone)]
pub(crate) struct FittedHarmonics {
    /// The mean `e_0` (rad).
    pub mean: f64,
    /// `C_k = a_k - j b_k`, index `k - 1` (0 for an order not fitted).
    pub coefficients: [Complex<f64>; SPECTRUM_ORDERS],
    /// The standard deviation of `a_k` and of `b_k` (rad, their quadratic mean).
    pub uncertainty: [f64; SPECTRUM_ORDERS],
    /// The samples fitted.
    pub count: u64,
    /// The RMS of `e - e_0` (rad).
    pub error_rms: f64,
    total: Normal,
    solution: DVector<f64>,
}

impl FittedHarmonics {
    /// The RMS (rad) of what the mean and the orders `kept` (index `k - 1`) leave of `e`.
    pub fn residual_rms(&self, kept: &[bool; SPECTRUM_ORDERS]) -> f64 {
        let mut x = self.solution.clone();
        for (k, &keep) in kept.iter().enumerate() {
            if !keep {
                x[2 * k + 1] = 0.0;
                x[2 * k + 2] = 0.0;
            }
        }
        (self.total.residual_squares(&x) / self.count.max(1) as f64).sqrt()
    }
}

impl HarmonicFit {
    /// A fit of the mean and the orders `1..=resolved` (at most [`SPECTRUM_ORDERS`]).
    pub(crate) fn new(resolved: usize) -> Self {
        let mut used = [false; PARAMETERS];
        used[0] = true;
        for k in 1..=resolved.min(SPECTRUM_ORDERS) {
            used[2 * k - 1] = true;
            used[2 * k] = true;
        }
        Self {
            used,
            blocks: Vec::new(),
            block_turns: 1.0,
            start: None,
        }
    }

    /// Adds the error `error` (rad) at the angle `angle` (rad), the angle with its whole
    /// turns being `position` (rad; it sets the sample's block).
    pub(crate) fn add(&mut self, angle: f64, position: f64, error: f64) {
        let start = *self.start.get_or_insert(position);
        let turns = (position - start).abs() / std::f64::consts::TAU;
        let mut index = (turns / self.block_turns) as usize;
        while index >= MAX_BLOCKS {
            let merged: Vec<Normal> = self
                .blocks
                .chunks(2)
                .map(|pair| {
                    let mut block = pair[0].clone();
                    if let Some(second) = pair.get(1) {
                        block.merge(second);
                    }
                    block
                })
                .collect();
            self.blocks = merged;
            self.block_turns *= 2.0;
            index = (turns / self.block_turns) as usize;
        }
        while self.blocks.len() <= index {
            self.blocks.push(Normal::new());
        }
        let mut basis = [0.0; PARAMETERS];
        basis[0] = 1.0;
        let first = Complex::from_polar(1.0, angle);
        let mut power = first;
        for k in 0..SPECTRUM_ORDERS {
            if self.used[2 * k + 1] {
                basis[2 * k + 1] = power.re;
                basis[2 * k + 2] = power.im;
            }
            power *= first;
        }
        self.blocks[index].add(&basis, error);
    }

    /// The coefficients and their uncertainties; `None` when the samples do not determine
    /// them (too few, or too short a stretch of the angle).
    pub(crate) fn finish(&self) -> Option<FittedHarmonics> {
        let mut total = Normal::new();
        for block in &self.blocks {
            total.merge(block);
        }
        let unknowns = self.used.iter().filter(|&&u| u).count();
        if total.count <= 2 * unknowns as u64 {
            return None;
        }
        let (x, inverse_diagonal) = total.solve(&self.used)?;
        let squares = total.residual_squares(&x);
        let white_variance = squares / (total.count as f64 - unknowns as f64);
        // Batch means over the blocks holding enough samples for their own fit.
        let solutions: Vec<DVector<f64>> = self
            .blocks
            .iter()
            .filter(|b| b.count > 4 * unknowns as u64)
            .filter_map(|b| b.solve(&self.used).map(|(x, _)| x))
            .collect();
        let m = solutions.len();
        let block_variance = |i: usize| {
            if m < 3 {
                return 0.0;
            }
            let mean = solutions.iter().map(|x| x[i]).sum::<f64>() / m as f64;
            let spread = solutions.iter().map(|x| (x[i] - mean).powi(2)).sum::<f64>();
            spread / ((m - 1) * m) as f64
        };
        let mut coefficients = [Complex::new(0.0, 0.0); SPECTRUM_ORDERS];
        let mut uncertainty = [0.0; SPECTRUM_ORDERS];
        for k in 0..SPECTRUM_ORDERS {
            let (ic, is) = (2 * k + 1, 2 * k + 2);
            if !self.used[ic] {
                uncertainty[k] = f64::NAN;
                continue;
            }
            coefficients[k] = Complex::new(x[ic], -x[is]);
            let white = 0.5 * white_variance * (inverse_diagonal[ic] + inverse_diagonal[is]);
            let batch = 0.5 * (block_variance(ic) + block_variance(is));
            uncertainty[k] = white.max(batch).sqrt();
        }
        let mean = x[0];
        let error_rms = ((total.btb / total.count as f64)
            - (total.atb[0] / total.count as f64).powi(2))
        .max(0.0)
        .sqrt();
        Some(FittedHarmonics {
            mean,
            coefficients,
            uncertainty,
            count: total.count,
            error_rms,
            total,
            solution: x,
        })
    }
}

/// The harmonics `C_k` of the error `e` against the true angle, from those `fitted` against
/// the estimate `x = theta + u(theta)` of a loop that follows part of the error: with
/// `transfer[k - 1]` the loop's `E/D` at order `k`, `u = sum_k (1 - T_k)/T_k e_k`, and
/// `F(x) = e(x - u)`, so `e = F + e' u` to first order, solved by three fixed-point steps
/// (`e = sum_k Re(C_k e^{jkx})`; products beyond [`SPECTRUM_ORDERS`] are dropped). Without
/// it, the loop's following of orders 3 and 4 puts their products at orders 6 to 8 and 1
/// to 2 (`docs/theory.md §12.4`).
pub(crate) fn undo_loop_following(
    fitted: &[Complex<f64>; SPECTRUM_ORDERS],
    transfer: &[Complex<f64>; SPECTRUM_ORDERS],
) -> [Complex<f64>; SPECTRUM_ORDERS] {
    const K: i64 = SPECTRUM_ORDERS as i64;
    // The exponential coefficient of order n (|n| <= K, n != 0) of the real series `c`.
    let at = |c: &[Complex<f64>; SPECTRUM_ORDERS], n: i64| -> Complex<f64> {
        let half = c[(n.unsigned_abs() - 1) as usize] * 0.5;
        if n > 0 { half } else { half.conj() }
    };
    let mut e = *fitted;
    for _ in 0..3 {
        let mut u = [Complex::new(0.0, 0.0); SPECTRUM_ORDERS];
        for (k, slot) in u.iter_mut().enumerate() {
            let t = transfer[k];
            if t.norm() > 0.0 {
                *slot = e[k] * ((Complex::new(1.0, 0.0) - t) / t);
            }
        }
        let mut next = *fitted;
        for (n, slot) in (1..=K).zip(next.iter_mut()) {
            let mut product = Complex::new(0.0, 0.0);
            for k in (-K..=K).filter(|&k| k != 0 && k != n && (n - k).abs() <= K) {
                product += Complex::new(0.0, k as f64) * at(&e, k) * at(&u, n - k);
            }
            *slot += product * 2.0;
        }
        e = next;
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic white-ish noise of standard deviation about `std`.
    fn noise(k: u64, std: f64) -> f64 {
        // splitmix64 of k.
        let mut z = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
        std * 3.0f64.sqrt() * (2.0 * u - 1.0)
    }

    #[test]
    fn harmonics_are_fitted_over_part_turns_with_the_uncertainty_of_the_noise() {
        // 40.3 turns of 500 samples, 2 mrad of order 3, 1 mrad of order 7, 0.1 rad offset,
        // 1 mrad of white noise: the uncertainty of each coefficient is 1e-3 sqrt(2/n).
        let n = 20_150;
        let mut fit = HarmonicFit::new(SPECTRUM_ORDERS);
        for i in 0..n {
            let position = std::f64::consts::TAU * i as f64 / 500.0;
            let angle = position.sin().atan2(position.cos());
            let e = 0.1
                + 2e-3 * (3.0 * angle + 0.4).sin()
                + 1e-3 * (7.0 * angle).cos()
                + noise(i, 1e-3);
            fit.add(angle, position, e);
        }
        let fitted = fit.finish().unwrap();
        assert!((fitted.mean - 0.1).abs() < 3e-5);
        // 2e-3 sin(3t + 0.4) = 2e-3 sin 0.4 cos 3t + 2e-3 cos 0.4 sin 3t; C = a - j b.
        let c3 = fitted.coefficients[2];
        assert!((c3.re - 2e-3 * 0.4f64.sin()).abs() < 5e-5, "{c3}");
        assert!((c3.im + 2e-3 * 0.4f64.cos()).abs() < 5e-5, "{c3}");
        assert!((fitted.coefficients[6].re - 1e-3).abs() < 5e-5);
        let expected = 1e-3 * (2.0 / n as f64).sqrt();
        for &u in &fitted.uncertainty {
            // The batch means' own spread: within a factor 1.6 with 20 blocks.
            assert!(u > 0.8 * expected && u < 1.6 * expected, "{u} {expected}");
        }
        let mut kept = [false; SPECTRUM_ORDERS];
        assert!((fitted.residual_rms(&kept) - (2e-6 + 0.5e-6 + 1e-6f64).sqrt()).abs() < 1e-4);
        kept[2] = true;
        kept[6] = true;
        assert!((fitted.residual_rms(&kept) - 1e-3).abs() < 5e-5);
    }

    #[test]
    fn the_loops_following_of_the_error_is_undone() {
        // e(theta) = 5e-3 cos 3 theta seen against x = theta + u, u = 0.4 e (T_3 = 1/1.4).
        let mut transfer = [Complex::new(1.0, 0.0); SPECTRUM_ORDERS];
        transfer[2] = Complex::new(1.0 / 1.4, 0.0);
        let mut fit = HarmonicFit::new(SPECTRUM_ORDERS);
        for i in 0..20_000 {
            let theta = std::f64::consts::TAU * i as f64 / 1000.0;
            let e = 5e-3 * (3.0 * theta).cos();
            let x = theta + 0.4 * e;
            fit.add(x.sin().atan2(x.cos()), x, e);
        }
        let fitted = fit.finish().unwrap().coefficients;
        // Against x, the product e' u shows at order 6: 0.4 * 3 * 25e-6 / 2 = 1.5e-5.
        assert!(fitted[5].norm() > 1e-5, "{}", fitted[5]);
        let undone = undo_loop_following(&fitted, &transfer);
        assert!(undone[5].norm() < 3e-7, "{}", undone[5]);
        assert!((undone[2].re - 5e-3).abs() < 1e-7, "{}", undone[2]);
    }

    #[test]
    fn orders_not_resolved_are_not_fitted_and_too_few_samples_fit_nothing() {
        let mut fit = HarmonicFit::new(2);
        for i in 0..10_000 {
            let angle = (0.01 * i as f64).sin().atan2((0.01 * i as f64).cos());
            fit.add(angle, 0.01 * i as f64, 1e-3 * (2.0 * angle).cos());
        }
        let fitted = fit.finish().unwrap();
        assert!((fitted.coefficients[1].re - 1e-3).abs() < 1e-9);
        assert_eq!(fitted.coefficients[2], Complex::new(0.0, 0.0));
        assert!(fitted.uncertainty[2].is_nan());
        let mut short = HarmonicFit::new(SPECTRUM_ORDERS);
        short.add(0.0, 0.0, 0.0);
        assert!(short.finish().is_none());
    }
}
