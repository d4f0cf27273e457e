//! The time column: its unit, and the checks of its order and spacing across chunks.

use core::str::FromStr;

/// The unit of a capture's time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimeUnit {
    /// Seconds.
    #[default]
    Seconds,
    /// Milliseconds.
    Milliseconds,
    /// Microseconds.
    Microseconds,
    /// Nanoseconds.
    Nanoseconds,
}

impl TimeUnit {
    /// Seconds per unit.
    pub const fn seconds(self) -> f64 {
        match self {
            TimeUnit::Seconds => 1.0,
            TimeUnit::Milliseconds => 1e-3,
            TimeUnit::Microseconds => 1e-6,
            TimeUnit::Nanoseconds => 1e-9,
        }
    }

    /// `value` in this unit, in seconds (divided, not multiplied by a rounded factor, so that
    /// whole numbers of microseconds give the nearest `f64` of their seconds).
    pub fn to_seconds(self, value: f64) -> f64 {
        match self {
            TimeUnit::Seconds => value,
            TimeUnit::Milliseconds => value / 1e3,
            TimeUnit::Microseconds => value / 1e6,
            TimeUnit::Nanoseconds => value / 1e9,
        }
    }

    /// Its symbol: `s`, `ms`, `us`, `ns`.
    pub const fn symbol(self) -> &'static str {
        match self {
            TimeUnit::Seconds => "s",
            TimeUnit::Milliseconds => "ms",
            TimeUnit::Microseconds => "us",
            TimeUnit::Nanoseconds => "ns",
        }
    }
}

impl FromStr for TimeUnit {
    type Err = String;

    /// `s`, `ms`, `us` (or `µs`) or `ns`.
    fn from_str(text: &str) -> Result<Self, String> {
        match text.trim() {
            "s" => Ok(TimeUnit::Seconds),
            "ms" => Ok(TimeUnit::Milliseconds),
            "us" | "µs" => Ok(TimeUnit::Microseconds),
            "ns" => Ok(TimeUnit::Nanoseconds),
            other => Err(format!(
                "time_unit: expected s, ms, us or ns, got {other:?}"
            )),
        }
    }
}

/// The spacing of time stamps tolerated around the capture's step: 1 %.
pub const SPACING_TOLERANCE: f64 = 0.01;

/// The steps a time column spans before its mean is held against a stated rate: over 100
/// steps, stamps rounded to a whole step move the mean by at most 1 %.
pub const STATED_RATE_STEPS: u64 = 100;

/// The order and spacing checks of a time column read in chunks: each stamp after the one
/// before it, and (unless the rate was stated) each step within [`SPACING_TOLERANCE`] of
/// the first chunk's median step. With the rate stated, a stamp equal to the one before
/// (rounded stamps) is accepted; one before it never is; and once the column spans
/// [`STATED_RATE_STEPS`] steps, its mean step must be the stated rate's within
/// [`SPACING_TOLERANCE`] (a rate that contradicts the time stamps is refused, naming both).
#[derive(Debug, Clone, PartialEq)]
pub struct SpacingCheck {
    check_spacing: bool,
    stated_rate_hz: Option<f64>,
    nominal_step_s: Option<f64>,
    first_s: Option<f64>,
    last_s: Option<f64>,
    count: u64,
}

/// `x` to 12 significant digits, as short as they allow: a step of 1 / 20 kHz computed from
/// stamps is 0.00005, not 0.000049999999999999996.
fn significant(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// A rate (Hz) as the messages show it: to a micro-hertz, trailing zeros dropped.
fn format_rate(rate_hz: f64) -> String {
    format!("{:.6}", rate_hz)
        .trim_end_matches('0')
        .trim_end_matches('.')
        .to_string()
}

impl SpacingCheck {
    /// A check of a new column, with the sample rate (Hz) the user stated, if any.
    pub fn new(stated_rate_hz: Option<f64>) -> Self {
        Self {
            check_spacing: stated_rate_hz.is_none(),
            stated_rate_hz,
            nominal_step_s: None,
            first_s: None,
            last_s: None,
            count: 0,
        }
    }

    /// Checks the next chunk's stamps (s); the error is the index in the chunk and what is
    /// wrong.
    pub fn check(&mut self, time_s: &[f64], unit: TimeUnit) -> Result<(), (usize, String)> {
        let (Some(&first), Some(&last)) = (time_s.first(), time_s.last()) else {
            return Ok(());
        };
        let shown = |t: f64| format!("{} {}", significant(t / unit.seconds()), unit.symbol());
        let mut previous = self.last_s;
        for (k, &t) in time_s.iter().enumerate() {
            // With the rate stated, rounded stamps may repeat; they never go back.
            let in_order = |t: f64, p: f64| t > p || (!self.check_spacing && t == p);
            if let Some(p) = previous
                && !in_order(t, p)
            {
                let what = if t == p { "duplicated" } else { "unsorted" };
                let hint = if t == p {
                    " (rounded time stamps? state the sample rate, --sample-rate, to accept them)"
                } else {
                    ""
                };
                return Err((
                    k,
                    format!(
                        "{what} time: {} after {} on the row before; the time must increase{hint}",
                        shown(t),
                        shown(p)
                    ),
                ));
            }
            previous = Some(t);
        }
        if self.nominal_step_s.is_none() && time_s.len() >= 2 {
            // The median step: one odd step of the first chunk neither sets nor hides it.
            let mut steps: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
            let middle = steps.len() / 2;
            steps.select_nth_unstable_by(middle, f64::total_cmp);
            self.nominal_step_s = Some(steps[middle]);
        }
        if let (true, Some(step)) = (self.check_spacing, self.nominal_step_s) {
            let mut previous = self.last_s.unwrap_or(first);
            for (k, &t) in time_s.iter().enumerate() {
                let dt = t - previous;
                // Stamps far from zero (an epoch's nanoseconds) hold their seconds to an f64's
                // resolution there, a step to twice it: that much is the stamps', not the
                // samples'.
                let resolution = 2.0 * t.abs().max(previous.abs()) * f64::EPSILON;
                if (k > 0 || self.last_s.is_some())
                    && (dt - step).abs() > SPACING_TOLERANCE * step + resolution
                {
                    return Err((
                        k,
                        format!(
                            "time step {} differs from the capture's {} by more than 1 %: the \
                             samples are not evenly spaced (rounded or jittered time stamps? \
                             state the sample rate, --sample-rate, to skip this check)",
                            shown(dt),
                            shown(step)
                        ),
                    ));
                }
                previous = t;
            }
        }
        self.first_s.get_or_insert(first);
        self.last_s = Some(last);
        self.count += time_s.len() as u64;
        if let (Some(rate), Some(step)) = (self.stated_rate_hz, self.mean_step_s())
            && self.count > STATED_RATE_STEPS
            && (step * rate - 1.0).abs() > SPACING_TOLERANCE
        {
            return Err((
                time_s.len() - 1,
                format!(
                    "sample_rate: --sample-rate {rate} Hz contradicts the time column, whose \
                     mean step {} is {} Hz (more than 1 % apart): leave out --sample-rate, or \
                     the time column (--columns time=-), or give its unit (--time-unit)",
                    shown(step),
                    format_rate(1.0 / step)
                ),
            ));
        }
        Ok(())
    }

    /// The mean step (s) over the stamps checked so far.
    pub fn mean_step_s(&self) -> Option<f64> {
        match (self.first_s, self.last_s) {
            (Some(a), Some(b)) if self.count >= 2 => Some((b - a) / (self.count - 1) as f64),
            _ => None,
        }
    }
}
