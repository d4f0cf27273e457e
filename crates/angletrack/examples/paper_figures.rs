//! Prints the paper's step-response figures as this crate computes them: the overshoot of
//! the continuous design, of the discrete loop (pole matching) sampled at 200 and 400 times
//! its -3 dB bandwidth, and of the bare nonlinear loop for a 179 degree step
//! (`docs/theory.md §2` and `§3`).
//!
//! Run: `cargo run --release -p angletrack --example paper_figures`

use angletrack::paper::PaperSetting;
use angletrack::{DesignReport, Discretisation, Error};

/// The report of `setting` with the sample rate at `ratio` times its bandwidth.
fn at_ratio(setting: PaperSetting, ratio: f64) -> Result<DesignReport, Error> {
    let design = |ts| setting.design(ts, Discretisation::PoleMatching);
    let mut ts = 1e-6;
    for _ in 0..3 {
        let bandwidth = design(ts)?.report(0.0)?.bandwidth_hz.unwrap_or(1.0);
        ts = 1.0 / (ratio * bandwidth);
    }
    design(ts)?.report(0.0)
}

fn main() -> Result<(), Error> {
    println!(
        "| design                               | paper | continuous | fs=200bw | fs=400bw | 179 deg bare | 179 deg diag |"
    );
    println!(
        "| ------------------------------------ | ----- | ---------- | -------- | -------- | ------------ | ------------ |"
    );
    for setting in PaperSetting::ALL {
        let r200 = at_ratio(setting, 200.0)?;
        let r400 = at_ratio(setting, 400.0)?;
        println!(
            "| {:<36} | {:>5.1} | {:>10.3} | {:>8.3} | {:>8.3} | {:>12.3} | {:>12.3} |",
            setting.name(),
            setting.overshoot_percent(),
            100.0 * r400.continuous_step.map_or(f64::NAN, |s| s.overshoot),
            100.0 * r200.linear_step.overshoot,
            100.0 * r400.linear_step.overshoot,
            100.0 * r400.large_step.overshoot,
            100.0 * r400.large_step_with_diagnostics.overshoot,
        );
    }
    println!("(overshoot in percent of the step)");
    Ok(())
}
