//! The project's capture generator of issue 37 (item 4) and the check it serves: captures
//! of a known noise and motion, and a design chosen from one capture measured on a second
//! one of the same setup (another seed), against its prediction and a grid of designs.
//!
//! Shared by `tests/design_from_capture.rs` (a few setups, short captures) and
//! `examples/design_from_capture_check.rs` (the full grid, `scripts/design-from-capture-check.sh`).

use core::f64::consts::TAU;

use angletrack::design_capture::{
    CaptureSignals, DesignConstraints, SKIP_FRACTION, design_from_capture,
};
use angletrack::tracker_file::NumberType;
use angletrack::{AnyDesign, FaultThresholds, Run, Scenario, run};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The shaft's motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// A white jerk of standard deviation `jerk_std_rad_s3` (constant over each sample),
    /// around `mean_speed_rad_s`: the speed and acceleration drawn back towards it at
    /// `corner_rad_s` (well below the loops' bandwidths) so that they stay bounded.
    RandomJerk {
        /// The white jerk's standard deviation (rad/s^3).
        jerk_std_rad_s3: f64,
        /// The mean speed (rad/s).
        mean_speed_rad_s: f64,
        /// The corner frequency of the pull back to the mean speed (rad/s).
        corner_rad_s: f64,
    },
    /// A constant speed with a speed step up and down and a reversal (over
    /// `reversal_s`) each `period_s`.
    StepsAndReversals {
        /// The cruising speed (rad/s).
        speed_rad_s: f64,
        /// The speed step (rad/s), instantaneous.
        step_rad_s: f64,
        /// The time between events (s).
        period_s: f64,
        /// The reversal's duration (s), at constant acceleration.
        reversal_s: f64,
    },
}

/// One setup: the sensor and the motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// The sample period (s).
    pub sample_period_s: f64,
    /// The samples per capture.
    pub samples: usize,
    /// The noise's standard deviation per channel, relative to the amplitude.
    pub noise_std: f64,
    /// 0: white noise; else the pole of the first-order autoregression it is (coloured).
    pub noise_pole: f64,
    /// `Some(a)`: integer counts of amplitude `a` around mid-scale 2048; `None`: units.
    pub counts_amplitude: Option<f64>,
    /// The motion.
    pub motion: Motion,
}

/// A capture: the two channels and the true angle.
#[derive(Debug, Clone, PartialEq)]
pub struct Capture {
    /// Cosine channel.
    pub cos: Vec<f64>,
    /// Sine channel.
    pub sin: Vec<f64>,
    /// True angle (rad).
    pub angle_rad: Vec<f64>,
}

const MID_SCALE: f64 = 2048.0;

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

fn motion(setup: &Setup, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let ts = setup.sample_period_s;
    let mut angle = Vec::with_capacity(setup.samples);
    match setup.motion {
        Motion::RandomJerk {
            jerk_std_rad_s3,
            mean_speed_rad_s,
            corner_rad_s,
        } => {
            let (mut theta, mut speed, mut acceleration) = (0.0, mean_speed_rad_s, 0.0);
            for _ in 0..setup.samples {
                angle.push(theta);
                let jerk = jerk_std_rad_s3 * normal(rng)
                    - 2.0 * corner_rad_s * acceleration
                    - corner_rad_s * corner_rad_s * (speed - mean_speed_rad_s);
                theta += ts * speed + ts * ts / 2.0 * acceleration + ts.powi(3) / 6.0 * jerk;
                speed += ts * acceleration + ts * ts / 2.0 * jerk;
                acceleration += ts * jerk;
            }
        }
        Motion::StepsAndReversals {
            speed_rad_s,
            step_rad_s,
            period_s,
            reversal_s,
        } => {
            let mut theta = 0.0;
            for k in 0..setup.samples {
                angle.push(theta);
                let t = k as f64 * ts;
                let event = (t / period_s) as usize;
                let into = t - event as f64 * period_s;
                // Events cycle: step up, step down, reverse; the direction flips on each
                // reversal.
                let direction = if (event / 3).is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                let speed = match event % 3 {
                    0 => direction * (speed_rad_s + step_rad_s),
                    1 => direction * speed_rad_s,
                    _ if into < reversal_s => {
                        direction * speed_rad_s * (1.0 - 2.0 * into / reversal_s)
                    }
                    _ => -direction * speed_rad_s,
                };
                theta += speed * ts;
            }
        }
    }
    angle
}

/// A capture of `setup`, deterministic from `seed`.
pub fn generate(setup: &Setup, seed: u64) -> Capture {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let angle_rad = motion(setup, &mut rng);
    let a = setup.noise_pole;
    let innovation = setup.noise_std * (1.0 - a * a).sqrt();
    let (mut n_c, mut n_s) = (
        setup.noise_std * normal(&mut rng),
        setup.noise_std * normal(&mut rng),
    );
    let channel = |value: f64, noise: &mut f64, rng: &mut ChaCha8Rng| {
        *noise = a * *noise + innovation * normal(rng);
        let y = value + *noise;
        match setup.counts_amplitude {
            Some(amplitude) => (MID_SCALE + amplitude * y).round(),
            None => y,
        }
    };
    let mut cos = Vec::with_capacity(setup.samples);
    let mut sin = Vec::with_capacity(setup.samples);
    for &theta in &angle_rad {
        cos.push(channel(theta.cos(), &mut n_c, &mut rng));
        sin.push(channel(theta.sin(), &mut n_s, &mut rng));
    }
    Capture {
        cos,
        sin,
        angle_rad,
    }
}

/// The RMS of the angle error of `design` run (the observer itself, `f64`) on `capture`
/// after [`SKIP_FRACTION`] of it.
pub fn measured_error_rms_rad(design: &AnyDesign, setup: &Setup, capture: &Capture) -> f64 {
    let (mid, amplitude) = setup
        .counts_amplitude
        .map_or((0.0, 1.0), |a| (MID_SCALE, a));
    let scenario = Scenario {
        sample_period_s: setup.sample_period_s,
        y_c: capture.cos.iter().map(|c| (c - mid) / amplitude).collect(),
        y_s: capture.sin.iter().map(|s| (s - mid) / amplitude).collect(),
        ..Scenario::default()
    };
    let estimates: Run = match design {
        AnyDesign::Second(d) => run(&monitor_off(d.gains), &scenario),
        AnyDesign::Third(d) => run(&monitor_off(d.gains), &scenario),
    };
    let skip = (SKIP_FRACTION * capture.angle_rad.len() as f64).ceil() as usize;
    let squares: Vec<f64> = estimates.angle_rad[skip..]
        .iter()
        .zip(&capture.angle_rad[skip..])
        .map(|(e, t)| {
            let d = e - t;
            (d - TAU * (d / TAU).round()).powi(2)
        })
        .collect();
    (squares.iter().sum::<f64>() / squares.len() as f64).sqrt()
}

/// What the check found on one setup.
#[derive(Debug, Clone, PartialEq)]
pub struct Checked {
    /// The chosen design's family and bandwidth (Hz).
    pub chosen: (&'static str, f64),
    /// Its predicted RMS angle error (rad), from the first capture.
    pub predicted_rad: f64,
    /// Its measured RMS angle error (rad) on the second capture.
    pub measured_rad: f64,
    /// The least measured RMS angle error on the second capture of the grid's designs that
    /// meet the constraints (by default none: every design of the grid).
    pub best_of_grid_rad: f64,
    /// The same over the whole grid, the designs refused by a constraint too.
    pub best_of_whole_grid_rad: f64,
    /// The designs measured in the grid.
    pub grid_designs: usize,
    /// The estimated noise over the generator's.
    pub noise_ratio: f64,
    /// The estimated jerk over the generator's (random jerk only).
    pub jerk_ratio: Option<f64>,
}

/// Chooses a design on a capture of `setup` (seed `seed`), with the reference column or
/// without, and measures it and the choice's whole grid on a second capture (seed + 1).
pub fn check(setup: &Setup, seed: u64, with_reference: bool, grid_points: usize) -> Checked {
    let first = generate(setup, seed);
    let second = generate(setup, seed + 1);
    let signals = CaptureSignals {
        cos: &first.cos,
        sin: &first.sin,
        sample_period_s: setup.sample_period_s,
        reference_angle_rad: with_reference.then_some(first.angle_rad.as_slice()),
        quantisation_step: setup.counts_amplitude.map(|_| 1.0),
    };
    let constraints = DesignConstraints {
        number_type: NumberType::F64,
        grid_points,
        ..DesignConstraints::default()
    };
    let design = design_from_capture(&signals, &constraints).expect("a design");
    let measured_rad = measured_error_rms_rad(&design.chosen.design, setup, &second);
    let measured: Vec<(bool, f64)> = design
        .candidates
        .iter()
        .map(|c| {
            let error = measured_error_rms_rad(&c.design, setup, &second);
            (c.refused_by.is_none(), error)
        })
        .collect();
    let best = |admissible_only: bool| {
        measured
            .iter()
            .filter(|(admissible, _)| *admissible || !admissible_only)
            .map(|&(_, error)| error)
            .fold(f64::INFINITY, f64::min)
    };
    let jerk_ratio = match setup.motion {
        Motion::RandomJerk {
            jerk_std_rad_s3, ..
        } => Some(design.estimates.motion.jerk_std_rad_s3.value / jerk_std_rad_s3),
        Motion::StepsAndReversals { .. } => None,
    };
    let quantisation = setup.counts_amplitude.map_or(0.0, |a| 1.0 / (12.0 * a * a));
    Checked {
        chosen: (design.chosen.family.name(), design.chosen.bandwidth_hz),
        predicted_rad: design.chosen.predicted.total_rad,
        measured_rad,
        best_of_grid_rad: best(true),
        best_of_whole_grid_rad: best(false),
        grid_designs: design.candidates.len(),
        noise_ratio: design.estimates.noise.std.value
            / (setup.noise_std.powi(2) + quantisation).sqrt(),
        jerk_ratio,
    }
}

/// The setups of the ranges: noise 0.1 % to 5 % (white, coloured), counts, random
/// jerk from 1e2 to 1e7 rad/s^3, and steps and reversals.
pub fn setups(samples: usize) -> Vec<(String, Setup)> {
    let base = |noise_std, noise_pole, counts_amplitude, motion| Setup {
        sample_period_s: 1e-4,
        samples,
        noise_std,
        noise_pole,
        counts_amplitude,
        motion,
    };
    let jerk = |jerk_std_rad_s3: f64| Motion::RandomJerk {
        jerk_std_rad_s3,
        mean_speed_rad_s: 60.0,
        // The speed's spread near 1000 rad/s whatever the jerk (`q / corner^3`), the
        // corner well below the loops' bandwidths.
        corner_rad_s: (jerk_std_rad_s3.powi(2) * 1e-4 / 1e6).cbrt().max(0.5),
    };
    let steps = Motion::StepsAndReversals {
        speed_rad_s: 100.0,
        step_rad_s: 20.0,
        period_s: 0.25,
        reversal_s: 0.05,
    };
    let mut out = Vec::new();
    for &jerk_std in &[1e2, 1e4, 1e5, 1e7] {
        for &noise in &[1e-3, 1e-2, 5e-2] {
            out.push((
                format!("jerk {jerk_std:.0e}, white {noise}"),
                base(noise, 0.0, None, jerk(jerk_std)),
            ));
        }
        out.push((
            format!("jerk {jerk_std:.0e}, coloured 0.01 (pole 0.9)"),
            base(0.01, 0.9, None, jerk(jerk_std)),
        ));
        out.push((
            format!("jerk {jerk_std:.0e}, counts (amplitude 1800), white 0.002"),
            base(0.002, 0.0, Some(1800.0), jerk(jerk_std)),
        ));
    }
    for &noise in &[1e-3, 1e-2, 5e-2] {
        out.push((
            format!("steps and reversals, white {noise}"),
            base(noise, 0.0, None, steps),
        ));
    }
    out.push((
        "steps and reversals, coloured 0.01 (pole 0.9)".into(),
        base(0.01, 0.9, None, steps),
    ));
    out
}

/// The gains with the fault monitor off: the check measures the bare loop.
fn monitor_off<const N: usize>(gains: angletrack::Gains<f64, N>) -> angletrack::Gains<f64, N>
where
    angletrack::core::Order<N>: angletrack::core::SupportedOrder,
{
    gains
        .with_fault_thresholds(FaultThresholds::disabled())
        .expect("the disabled thresholds are valid")
}
