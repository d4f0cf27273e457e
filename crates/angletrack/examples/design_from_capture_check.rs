//! The full grid of issue 37's check (item 4): for every setup of the generator, with and
//! without the reference column, the design chosen from one capture measured on a second
//! one; prints one row per case. Run by `scripts/design-from-capture-check.sh`.
//!
//! Arguments: the samples per capture (default 100000, 10 s at 10 kHz), the grid points
//! per family (default 31) and, optionally, a text the setups' names must contain.

#[path = "../tests/support/capture_generator.rs"]
mod capture_generator;

fn main() {
    let mut args = std::env::args().skip(1);
    let samples = args
        .next()
        .map_or(100_000, |a| a.parse().expect("samples: an integer"));
    let grid = args
        .next()
        .map_or(31, |a| a.parse().expect("grid points: an integer"));
    let only = args.next().unwrap_or_default();
    println!(
        "| setup | reference | chosen | predicted (rad) | measured (rad) | measured/predicted | best of grid (rad) | measured/best | measured/best of whole grid | noise est/true | jerk est/true |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (name, setup) in capture_generator::setups(samples) {
        if !name.contains(&only) {
            continue;
        }
        for with_reference in [true, false] {
            let c = capture_generator::check(&setup, 1, with_reference, grid);
            println!(
                "| {name} | {} | {} {:.3} Hz | {:.3e} | {:.3e} | {:.3} | {:.3e} | {:.3} | {:.3} | {:.3} | {} |",
                if with_reference { "yes" } else { "no" },
                c.chosen.0,
                c.chosen.1,
                c.predicted_rad,
                c.measured_rad,
                c.measured_rad / c.predicted_rad,
                c.best_of_grid_rad,
                c.measured_rad / c.best_of_grid_rad,
                c.measured_rad / c.best_of_whole_grid_rad,
                c.noise_ratio,
                c.jerk_ratio.map_or("-".into(), |r| format!("{r:.3}")),
            );
        }
    }
}
