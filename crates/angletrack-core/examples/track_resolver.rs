//! Tracks a simulated resolver with the three observers of the paper (f32, fast sin/cos) and
//! prints the angle and speed errors of each.
//!
//! Run: `cargo run --release -p angletrack-core --example track_resolver`
//!
//! The gains are for a 10 kHz loop; `angletrack design` computes them for any specification:
//! the 2nd-order ATO with a 50 Hz natural frequency and damping 1 (pole matching), the
//! 3rd-order ATO with K = 39.04 and psi = 3 pi / 2 (pole matching), and the Kalman ATO for
//! q / r = 1e-9.

use angletrack_core::{AngleTrackingObserver, Gains, Observer};

const TS: f64 = 1e-4;

/// A small deterministic Gaussian noise source (xorshift64* and Box-Muller).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn gaussian(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (core::f64::consts::TAU * v).cos()
    }
}

/// The shaft: 0.5 s at 400 rad/s^2 from rest, then 0.5 s at constant speed (rad, rad/s).
fn shaft(t: f64) -> (f64, f64) {
    let (alpha, t1) = (400.0, 0.5);
    if t < t1 {
        (0.5 * alpha * t * t, alpha * t)
    } else {
        (0.5 * alpha * t1 * t1 + alpha * t1 * (t - t1), alpha * t1)
    }
}

fn report(name: &str, mut observer: impl AngleTrackingObserver<f32>) {
    let mut noise = Noise(0x1234_5678_9abc_def1);
    let sigma = 0.01; // sensor noise, per channel, amplitude 1
    let n = (1.0 / TS) as usize;
    let (mut sum_angle, mut sum_speed, mut max_angle, mut count) = (0.0, 0.0, 0.0f64, 0);
    for k in 0..n {
        let (theta, omega) = shaft(k as f64 * TS);
        let y_c = theta.cos() + sigma * noise.gaussian();
        let y_s = theta.sin() + sigma * noise.gaussian();
        let e = observer.update(y_c as f32, y_s as f32);
        if k >= n / 10 {
            let err = (theta - e.position() + core::f64::consts::PI)
                .rem_euclid(core::f64::consts::TAU)
                - core::f64::consts::PI;
            sum_angle += err * err;
            sum_speed += (omega - e.speed as f64).powi(2);
            max_angle = max_angle.max(err.abs());
            count += 1;
        }
    }
    println!(
        "{name:<28} rms angle error {:>8.3} mrad   max {:>8.3} mrad   rms speed error {:>7.3} rad/s",
        1e3 * (sum_angle / count as f64).sqrt(),
        1e3 * max_angle,
        (sum_speed / count as f64).sqrt()
    );
}

fn main() -> Result<(), angletrack_core::ConfigError> {
    let ts = TS as f32;
    let second = Gains::<f32, 2>::new([0.060_898_63, 0.000_956_514_8], ts)?;
    let third = Gains::<f32, 3>::new([0.094_326_17, 0.000_562_075, 1.213_522e-5], ts)?;
    let kalman = Gains::<f32, 3>::new([0.061_286_65, 0.001_937_879, 3.063_843e-5], ts)?;
    println!(
        "Resolver at 10 kHz, noise 0.01 per channel, 0.5 s at 400 rad/s^2 then constant speed:"
    );
    report("2nd-order ATO (type II)", Observer::new(second));
    report("3rd-order ATO (type III)", Observer::new(third));
    report("3rd-order Kalman ATO", Observer::new(kalman));
    Ok(())
}
