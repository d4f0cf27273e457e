//! The observer variants of the firmware test and the layout of the reference data: shared by
//! the build script (which computes the reference on the host) and the firmware (which checks
//! itself against it), so that both run the same list in the same order.

use angletrack_core::{Estimate, Exact, Fast, Gains, Order, SinCos, SupportedOrder};

/// The variants, as printed: `<observer>-<float>-<sincos>`.
pub const NAMES: [&str; 6] = [
    "second-order-f32-exact",
    "second-order-f32-fast",
    "third-order-f32-exact",
    "third-order-f32-fast",
    "kalman-f32-exact",
    "kalman-f32-fast",
];

/// Bytes of one reference record: angle (rad, f32), turns (i32), speed (rad/s, f32),
/// acceleration (rad/s^2, f32), little endian.
pub const RECORD_BYTES: usize = 16;

/// Bytes of one input sample: `y_c`, `y_s` (f32, little endian).
pub const SAMPLE_BYTES: usize = 8;

/// The discrete gains of the three observers and the sample period (s), in `f32`.
#[derive(Debug, Clone, Copy)]
pub struct Observers {
    /// `(l1, l2)` of the 2nd-order ATO.
    pub second_order: [f32; 2],
    /// `(l1, l2, l3)` of the 3rd-order ATO (pole placement).
    pub third_order: [f32; 3],
    /// `(l1, l2, l3)` of the Kalman ATO.
    pub kalman: [f32; 3],
    /// Sample period (s).
    pub sample_period_s: f32,
}

/// Something to do with one variant's checked gains.
pub trait Job {
    /// Runs on variant `index` (into [`NAMES`]) with its gains.
    fn run<const N: usize, S: SinCos<f32>>(&mut self, index: usize, gains: Gains<f32, N, S>)
    where
        Order<N>: SupportedOrder;
}

impl Observers {
    /// Runs `job` on variant `index`. Returns `false` (and runs nothing) if `index` is not a
    /// variant or its gains are refused.
    pub fn run(&self, index: usize, job: &mut impl Job) -> bool {
        let ts = self.sample_period_s;
        let (order, sin_cos) = (index / 2, index % 2);
        match (order, sin_cos) {
            (0, _) => match Gains::<f32, 2, Exact>::new(self.second_order, ts) {
                Ok(g) if sin_cos == 0 => job.run(index, g),
                Ok(g) => job.run(index, g.with_sin_cos::<Fast>()),
                Err(_) => return false,
            },
            (1 | 2, _) => {
                let l = if order == 1 {
                    self.third_order
                } else {
                    self.kalman
                };
                match Gains::<f32, 3, Exact>::new(l, ts) {
                    Ok(g) if sin_cos == 0 => job.run(index, g),
                    Ok(g) => job.run(index, g.with_sin_cos::<Fast>()),
                    Err(_) => return false,
                }
            }
            _ => return false,
        }
        true
    }
}

/// The reference record of one estimate (written by the build script only).
#[allow(dead_code)]
pub fn encode(estimate: &Estimate<f32>) -> [u8; RECORD_BYTES] {
    let mut r = [0; RECORD_BYTES];
    r[0..4].copy_from_slice(&estimate.angle.to_le_bytes());
    r[4..8].copy_from_slice(&(estimate.turns as i32).to_le_bytes());
    r[8..12].copy_from_slice(&estimate.speed.to_le_bytes());
    r[12..16].copy_from_slice(&estimate.acceleration.to_le_bytes());
    r
}

/// `(angle, turns, speed, acceleration)` of a reference record.
pub fn decode(r: &[u8]) -> (f32, i32, f32, f32) {
    let word = |i: usize| [r[i], r[i + 1], r[i + 2], r[i + 3]];
    (
        f32::from_le_bytes(word(0)),
        i32::from_le_bytes(word(4)),
        f32::from_le_bytes(word(8)),
        f32::from_le_bytes(word(12)),
    )
}
