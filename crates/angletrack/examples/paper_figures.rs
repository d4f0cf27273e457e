//! Prints the paper's step-response figures as this crate computes them: the overshoot of
//! the continuous design, of the discrete loop (pole matching) sampled at 200 and 400 times
//! its -3 dB bandwidth, and of the bare nonlinear loop for a 179 degree step.
//!
//! Run: `cargo run --release -p angletrack --example paper_figures`

use std::f64::consts::{PI, SQRT_2};

use angletrack::{
    Design, DesignReport, Discretisation, Error, core::Order, core::SupportedOrder,
    second_order_from_tracking_error, third_order_butterworth, third_order_from_poles,
};

const PM: Discretisation = Discretisation::PoleMatching;

/// The report of `design(ts)` with the sample rate at `ratio` times its bandwidth.
fn at_ratio<const N: usize>(
    ratio: f64,
    design: &dyn Fn(f64) -> Result<Design<N>, Error>,
) -> Result<DesignReport, Error>
where
    Order<N>: SupportedOrder,
{
    let mut ts = 1e-6;
    for _ in 0..3 {
        let bandwidth = DesignReport::new(&design(ts)?, 0.0)?
            .bandwidth_hz
            .unwrap_or(1.0);
        ts = 1.0 / (ratio * bandwidth);
    }
    DesignReport::new(&design(ts)?, 0.0)
}

fn row<const N: usize>(
    name: &str,
    paper: f64,
    design: &dyn Fn(f64) -> Result<Design<N>, Error>,
) -> Result<(), Error>
where
    Order<N>: SupportedOrder,
{
    let r200 = at_ratio(200.0, design)?;
    let r400 = at_ratio(400.0, design)?;
    println!(
        "| {name:<30} | {paper:>5.1} | {:>10.3} | {:>9.3} | {:>9.3} | {:>12.3} | {:>10.3} |",
        100.0 * r400.continuous_step.map_or(f64::NAN, |s| s.overshoot),
        100.0 * r200.linear_step.overshoot,
        100.0 * r400.linear_step.overshoot,
        100.0 * r400.large_step.overshoot,
        100.0 * r400.large_step_with_diagnostics.overshoot,
    );
    Ok(())
}

fn main() -> Result<(), Error> {
    println!(
        "| design                         | paper | continuous | fs=200bw | fs=400bw | 179 deg bare | 179 deg diag |"
    );
    println!(
        "| ------------------------------ | ----- | ---------- | --------- | --------- | ------------ | ---------- |"
    );
    row("2nd order, m = 1.945", 5.0, &|ts| {
        second_order_from_tracking_error(1e-3, 1e3, 1.945, ts, PM)
    })?;
    row("2nd order, m = sqrt(2)/2", 20.8, &|ts| {
        second_order_from_tracking_error(1e-3, 1e3, SQRT_2 / 2.0, ts, PM)
    })?;
    row("3rd order, K = 39.04, 3pi/2", 10.0, &|ts| {
        third_order_from_poles(39.04, 0.01, 1.5 * PI, ts, PM)
    })?;
    row("3rd order, Butterworth", 30.9, &|ts| {
        third_order_butterworth(0.01, ts, PM)
    })?;
    println!("(overshoot in percent of the step)");
    Ok(())
}
