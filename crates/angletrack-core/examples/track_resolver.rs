//! Tracks a simulated resolver from raw 12-bit ADC counts with the three observers of the
//! paper (f32, fast sin/cos) and prints the angle and speed errors of each; then a sensor
//! with offsets, gain imbalance and quadrature error, without and with the online
//! calibration.
//!
//! Run: `cargo run --release -p angletrack-core --example track_resolver`
//!
//! The gains are for a 10 kHz loop; `angletrack design` computes them for any specification:
//! the 2nd-order ATO with a 50 Hz natural frequency and damping 1 (pole matching), the
//! 3rd-order ATO with K = 39.04 and psi = 3 pi / 2 (pole matching), and the Kalman ATO for
//! q / r = 1e-9.

use angletrack_core::{
    AdcScaling, Calibrator, Chain, ChainState, Estimate, FaultThresholds, Gains, ObserverState,
    OnlineCalibration,
};

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

/// A sensor: offsets and the sine channel's gain (relative to the amplitude) and its
/// quadrature angle (rad).
struct Sensor {
    offsets: (f64, f64),
    gain: f64,
    quadrature_rad: f64,
}

/// A perfect sensor.
const IDEAL: Sensor = Sensor {
    offsets: (0.0, 0.0),
    gain: 1.0,
    quadrature_rad: 0.0,
};

/// The amplitude of the signals in ADC counts (12-bit offset binary ADC, mid-scale 2048).
const AMPLITUDE_COUNTS: f64 = 1800.0;

/// Tracks the shaft through `sensor` and a 12-bit ADC with `update` (raw counts in, estimate
/// out) and prints the errors over the last 0.25 s (constant speed).
fn report(name: &str, sensor: &Sensor, mut update: impl FnMut(u16, u16) -> Estimate<f32>) {
    let mut noise = Noise(0x1234_5678_9abc_def1);
    let sigma = 0.01; // sensor noise, per channel, relative to the amplitude
    let counts = |v: f64| (2048.0 + AMPLITUDE_COUNTS * v).round().clamp(0.0, 4095.0) as u16;
    let n = (1.0 / TS) as usize;
    let (mut sum_angle, mut sum_speed, mut max_angle, mut count) = (0.0, 0.0, 0.0f64, 0);
    for k in 0..n {
        let (theta, omega) = shaft(k as f64 * TS);
        let y_c = sensor.offsets.0 + theta.cos() + sigma * noise.gaussian();
        let y_s = sensor.offsets.1
            + sensor.gain * (theta + sensor.quadrature_rad).sin()
            + sigma * noise.gaussian();
        let e = update(counts(y_c), counts(y_s));
        if k >= 3 * n / 4 {
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
        "{name:<36} rms angle error {:>8.3} mrad   max {:>8.3} mrad   rms speed error {:>7.3} rad/s",
        1e3 * (sum_angle / count as f64).sqrt(),
        1e3 * max_angle,
        (sum_speed / count as f64).sqrt()
    );
}

fn main() -> Result<(), angletrack_core::ConfigError> {
    let ts = TS as f32;
    // The ADC: 12 bits, offset binary; full scale is +-1, the signal 1800 / 2048 of it,
    // which the diagnostics compare amplitudes with.
    let adc = AdcScaling::<f32>::offset_binary(12)?;
    let thresholds = FaultThresholds::for_amplitude((AMPLITUDE_COUNTS / 2048.0) as f32);
    let second = Gains::<f32, 2>::new([0.060_898_63, 0.000_956_514_8], ts)?
        .with_fault_thresholds(thresholds)?;
    let third = Gains::<f32, 3>::new([0.094_326_17, 0.000_562_075, 1.213_522e-5], ts)?
        .with_fault_thresholds(thresholds)?;
    let kalman = Gains::<f32, 3>::new([0.061_286_65, 0.001_937_879, 3.063_843e-5], ts)?
        .with_fault_thresholds(thresholds)?;
    println!(
        "Resolver at 10 kHz through a 12-bit ADC (amplitude 1800 counts), noise 0.01 per \
         channel, 0.5 s at 400 rad/s^2 then constant speed:"
    );
    let (mut s2, mut s3, mut sk) = (ChainState::new(), ChainState::new(), ChainState::new());
    let kalman_gains = kalman;
    let (second, third, kalman) = (
        Chain::new(adc, second),
        Chain::new(adc, third),
        Chain::new(adc, kalman),
    );
    report("2nd-order ATO (type II)", &IDEAL, |c, s| {
        second.update(&mut s2, (c, s))
    });
    report("3rd-order ATO (type III)", &IDEAL, |c, s| {
        third.update(&mut s3, (c, s))
    });
    report("3rd-order Kalman ATO", &IDEAL, |c, s| {
        kalman.update(&mut sk, (c, s))
    });
    let real = Sensor {
        offsets: (0.05, -0.05),
        gain: 1.1,
        quadrature_rad: 3f64.to_radians(),
    };
    println!("A sensor with offsets 5 %, gain imbalance 10 % and quadrature 3 degrees:");
    let mut state = ChainState::new();
    report("Kalman ATO, uncorrected", &real, |c, s| {
        kalman.update(&mut state, (c, s))
    });
    // The ADC, then the calibration that learns while the observer tracks.
    let online = OnlineCalibration::new(kalman_gains.calibration_settings(), ts)?;
    let calibrated = Chain::new((adc, online), kalman_gains);
    let mut state: ChainState<((), Calibrator<f32>), ObserverState<f32, 3>> = ChainState::new();
    state.front_end.1.enable();
    report("Kalman ATO, online calibration", &real, |c, s| {
        calibrated.update(&mut state, (c, s))
    });
    let calibrator = &state.front_end.1;
    let (o_c, o_s, a_c, a_s, phi) = calibrator.calibration().parameters();
    println!(
        "learned in {} turns: offsets {o_c:.4} {o_s:.4}, amplitudes {a_c:.4} {a_s:.4} \
         (full scale), quadrature {:.2} degrees",
        calibrator.turns_learned(),
        phi.to_degrees()
    );
    Ok(())
}
