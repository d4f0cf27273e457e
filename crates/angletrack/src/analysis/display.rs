//! The design report rendered as a Markdown table.

use core::fmt;

use nalgebra::Complex;

use super::report::DesignReport;
use super::step::StepResponse;

fn complex(z: &Complex<f64>) -> String {
    if z.im == 0.0 {
        format!("{:.6e}", z.re)
    } else {
        format!(
            "{:.6e} {} {:.6e}j",
            z.re,
            if z.im < 0.0 { '-' } else { '+' },
            z.im.abs()
        )
    }
}

fn optional(value: Option<f64>, unit: &str) -> String {
    value.map_or_else(|| "-".to_string(), |v| format!("{v:.6e} {unit}"))
}

fn step(s: &StepResponse) -> String {
    format!(
        "overshoot {:.3} %, 2 % settling {:.6e} s",
        100.0 * s.overshoot,
        s.settling_time_s
    )
}

impl fmt::Display for DesignReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let row = |f: &mut fmt::Formatter<'_>, name: &str, value: String| {
            writeln!(f, "| {name:<40} | {value} |")
        };
        row(f, "design", self.method.name().to_string())?;
        row(
            f,
            "discretisation",
            self.discretisation.map_or("-", |d| d.name()).to_string(),
        )?;
        row(
            f,
            "order, sample period",
            format!("{}, {:.6e} s", self.order, self.sample_period_s),
        )?;
        row(
            f,
            "gains l",
            self.gains
                .iter()
                .map(|g| format!("{g:.9e}"))
                .collect::<Vec<_>>()
                .join(", "),
        )?;
        for (i, (z, s)) in self
            .discrete_poles
            .iter()
            .zip(&self.continuous_equivalent_poles)
            .enumerate()
        {
            row(
                f,
                &format!("pole {} z (ln z / Ts, rad/s)", i + 1),
                format!("{} ({})", complex(z), complex(s)),
            )?;
        }
        for (i, s) in self.design_poles.iter().enumerate() {
            row(f, &format!("design pole {} (rad/s)", i + 1), complex(s))?;
        }
        row(
            f,
            "pole shift by the discretisation",
            self.pole_shift
                .map_or("-".to_string(), |v| format!("{:.3e} (relative)", v)),
        )?;
        row(f, "-3 dB bandwidth", optional(self.bandwidth_hz, "Hz"))?;
        if self.order == 2 {
            row(
                f,
                "Ka discrete (continuous)",
                format!(
                    "{} ({})",
                    optional(self.acceleration_constant_per_s2, "1/s^2"),
                    optional(self.continuous_acceleration_constant_per_s2, "1/s^2")
                ),
            )?;
        } else {
            row(
                f,
                "error per unit jerk discrete (continuous)",
                format!(
                    "{} ({})",
                    optional(self.error_per_unit_jerk_s3, "s^3"),
                    optional(self.continuous_error_per_unit_jerk_s3, "s^3")
                ),
            )?;
        }
        row(
            f,
            &format!("RMS error, sensor noise {:.3e} only", self.sensor_noise_std),
            format!(
                "angle {:.6e} rad, speed {:.6e} rad/s",
                self.angle_error_rms_rad, self.speed_error_rms_rad_s
            ),
        )?;
        if let (Some(a), Some(s)) = (self.kalman_angle_floor_rad, self.kalman_speed_floor_rad_s) {
            row(
                f,
                "Kalman floor sqrt(P11) (own q and r, random jerk)",
                format!("angle {a:.6e} rad, speed {s:.6e} rad/s"),
            )?;
        }
        row(f, "linear step", step(&self.linear_step))?;
        if let Some(c) = &self.continuous_step {
            row(f, "continuous design step", step(c))?;
        }
        row(
            f,
            "179 degree step (bare nonlinear loop)",
            format!(
                "{}, ends at {:.3} deg",
                step(&self.large_step),
                self.large_step_final_rad.to_degrees()
            ),
        )?;
        row(
            f,
            "179 degree step, with diagnostics",
            step(&self.large_step_with_diagnostics),
        )?;
        row(
            f,
            "max trackable speed (pi / Ts)",
            format!("{:.6e} rad/s", self.max_speed_rad_s),
        )?;
        row(
            f,
            "speed step acquired from rest",
            format!("{:.6e} rad/s", self.acquisition_speed_rad_s),
        )
    }
}
