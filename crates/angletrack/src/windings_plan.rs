//! How a capture of a resolver's raw windings is demodulated (`docs/theory.md §13`): the ADC
//! rate and the samples per carrier period, the carrier amplitude and the ADC range, each as
//! stated or else measured on the capture's first samples; a declared carrier or sample
//! ratio the capture contradicts is refused, naming both values.

use core::fmt;

use crate::carrier::{centred_power, cycles_of_power, mean};
use crate::rails::measured_winding_range;

/// How far a declared carrier may be from the one measured in the capture (fraction).
pub const CARRIER_TOLERANCE: f64 = 0.02;

/// How far a stated `samples_per_period` may be from the capture's rate over the carrier
/// (fraction).
pub const SAMPLES_PER_PERIOD_TOLERANCE: f64 = 0.01;

/// What the caller states about a capture of raw windings; `None` fields are measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct WindingsSettings {
    /// The declared carrier frequency (Hz).
    pub carrier_hz: f64,
    /// The capture's sample rate (Hz) from its time column, if it has one.
    pub capture_hz: Option<f64>,
    /// ADC samples per carrier period, if stated (any ratio of at least 4).
    pub samples_per_period: Option<f64>,
    /// A winding's carrier amplitude at envelope 1 (counts, peak), if stated.
    pub carrier_amplitude_counts: Option<f64>,
    /// The ADC's codes `(min, max)`, if stated.
    pub adc_range: Option<(f64, f64)>,
}

impl WindingsSettings {
    /// A declared carrier (Hz), everything else measured.
    ///
    /// ```
    /// let settings = angletrack::WindingsSettings::new(10e3);
    /// assert_eq!((settings.carrier_hz, settings.capture_hz), (10e3, None));
    /// ```
    pub fn new(carrier_hz: f64) -> Self {
        Self {
            carrier_hz,
            ..Self::default()
        }
    }
}

/// Where a [`WindingsPlan`]'s ADC range comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum AdcRangeSource {
    /// As stated.
    Stated,
    /// The first samples' extremes held flat ([`measured_adc_range`](crate::measured_adc_range)'s
    /// rule on windings).
    Measured,
    /// A guess: the smallest power-of-two span holding the first samples (from 0 if none is
    /// negative). Measure the rails as the samples come
    /// ([`WindingRails`](crate::WindingRails)).
    Guessed,
}

impl fmt::Display for AdcRangeSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AdcRangeSource::Stated => "stated",
            AdcRangeSource::Measured => "measured: extremes held flat",
            AdcRangeSource::Guessed => "guessed",
        })
    }
}

/// How a capture of raw windings is demodulated: [`WindingsPlan::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindingsPlan {
    /// The ADC rate (Hz): the stated samples per period times the carrier, else the
    /// capture's rate.
    pub adc_rate_hz: f64,
    /// ADC samples per declared carrier period.
    pub samples_per_period: f64,
    /// A winding's carrier amplitude at envelope 1 (counts): as stated, else measured (the
    /// windings' variances sum to `A^2 / 2` at every shaft angle).
    pub carrier_amplitude_counts: f64,
    /// The ADC's codes `(min, max)` clipping is checked against.
    pub adc_range: (f64, f64),
    /// Where `adc_range` comes from.
    pub adc_range_source: AdcRangeSource,
}

/// The largest carrier amplitude a plan takes (counts): a 32-bit ADC's half range.
const LARGEST_CARRIER_AMPLITUDE_COUNTS: f64 = 2_147_483_648.0;

/// Why a capture of raw windings cannot be demodulated as declared. Each has its argument
/// ([`WindingsPlanError::argument`]) and names, where two values disagree, both (as the
/// command line's options: `--carrier-hz`, `--samples-per-period`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum WindingsPlanError {
    /// No ADC rate: the capture has no time column and no samples per period is stated.
    NoAdcRate,
    /// Fewer than 4 ADC samples per carrier period.
    TooFewSamplesPerPeriod {
        /// The ADC rate (Hz).
        adc_rate_hz: f64,
        /// The declared carrier (Hz).
        carrier_hz: f64,
    },
    /// The stated samples per period is more than 1 % from the capture's rate over the
    /// carrier.
    SamplesPerPeriodContradicted {
        /// As stated.
        stated: f64,
        /// The capture's rate (Hz).
        capture_hz: f64,
        /// The declared carrier (Hz).
        carrier_hz: f64,
    },
    /// The stated carrier amplitude is not a positive number of counts up to 2^31 (a
    /// 32-bit ADC's).
    CarrierAmplitude(f64),
    /// The declared carrier is more than 2 % from the one measured in the capture.
    CarrierContradicted {
        /// As declared (Hz).
        declared_hz: f64,
        /// As measured (Hz).
        measured_hz: f64,
        /// The sample rate the measurement is taken at (Hz).
        rate_hz: f64,
        /// Whether that rate is the capture's time column's (else the stated samples per
        /// period's).
        from_time_column: bool,
        /// The samples per declared period.
        samples_per_period: f64,
    },
}

impl WindingsPlanError {
    /// The argument at fault, as the Python API and the CLI's summary name it.
    pub const fn argument(&self) -> &'static str {
        match self {
            WindingsPlanError::CarrierContradicted { .. } => "carrier_hz",
            WindingsPlanError::CarrierAmplitude(_) => "carrier_amplitude_counts",
            _ => "samples_per_period",
        }
    }
}

impl fmt::Display for WindingsPlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let g = |x: f64| significant(x, 6);
        match *self {
            WindingsPlanError::CarrierAmplitude(a) => write!(
                f,
                "{a}: expected a positive number of counts up to 2^31 (a 32-bit ADC's)"
            ),
            WindingsPlanError::NoAdcRate => write!(
                f,
                "the capture has no time column: give --samples-per-period or \
                 --sample-rate (the ADC rate)"
            ),
            WindingsPlanError::TooFewSamplesPerPeriod {
                adc_rate_hz,
                carrier_hz,
            } => write!(
                f,
                "the ADC rate {} Hz over the carrier {} Hz is {} samples per \
                 period; at least 4 are needed",
                g(adc_rate_hz),
                g(carrier_hz),
                g(adc_rate_hz / carrier_hz)
            ),
            WindingsPlanError::SamplesPerPeriodContradicted {
                stated,
                capture_hz,
                carrier_hz,
            } => {
                write!(
                    f,
                    "--samples-per-period {} contradicts the capture's time \
                     column: {} Hz over --carrier-hz {} is {} samples per period",
                    g(stated),
                    g(capture_hz),
                    g(carrier_hz),
                    g(capture_hz / carrier_hz)
                )
            }
            WindingsPlanError::CarrierContradicted {
                declared_hz,
                measured_hz,
                rate_hz,
                from_time_column,
                samples_per_period,
            } => {
                let off = 100.0 * (declared_hz / measured_hz - 1.0);
                write!(
                    f,
                    "--carrier-hz {} is {}{} % from the carrier measured in the \
                     capture, {} Hz (at {} samples/s, ",
                    g(declared_hz),
                    if off >= 0.0 { "+" } else { "" },
                    significant(off, 3),
                    g(measured_hz),
                    g(rate_hz)
                )?;
                if from_time_column {
                    write!(f, "the capture's time column)")
                } else {
                    write!(f, "{} samples per declared period)", g(samples_per_period))
                }
            }
        }
    }
}

impl std::error::Error for WindingsPlanError {}

impl WindingsPlan {
    /// The plan of a capture whose first samples are `first_c`, `first_s` (raw windings,
    /// any offset): the ADC rate and samples per period (at least 4), refused if the time
    /// column contradicts a stated ratio by more than 1 % or the carrier measured in the
    /// samples ([`measured_carrier_cycles_per_sample`](crate::measured_carrier_cycles_per_sample))
    /// is more than 2 % from the declared one; the amplitude and ADC range as stated or
    /// measured.
    ///
    /// ```
    /// use angletrack::{AdcRangeSource, WindingsPlan, WindingsSettings};
    /// // 12-bit counts, a 10 kHz carrier at 160 kHz, amplitude 1800, the shaft turning.
    /// let (mut c, mut s) = (vec![0.0; 4000], vec![0.0; 4000]);
    /// for k in 0..4000 {
    ///     let carrier = (std::f64::consts::TAU * k as f64 / 16.0).sin();
    ///     let theta = 0.002 * k as f64;
    ///     (c[k], s[k]) = (2048.0 + 1800.0 * theta.cos() * carrier, 2048.0 + 1800.0 * theta.sin() * carrier);
    /// }
    /// let mut settings = WindingsSettings::new(10e3);
    /// settings.capture_hz = Some(160e3);
    /// let plan = WindingsPlan::new(&c, &s, &settings)?;
    /// assert_eq!((plan.adc_rate_hz, plan.samples_per_period), (160e3, 16.0));
    /// assert!((plan.carrier_amplitude_counts / 1800.0 - 1.0).abs() < 0.01);
    /// assert_eq!((plan.adc_range, plan.adc_range_source), ((0.0, 4095.0), AdcRangeSource::Guessed));
    /// // 10.5 kHz declared: refused, naming both.
    /// settings.carrier_hz = 10.5e3;
    /// let error = WindingsPlan::new(&c, &s, &settings).unwrap_err();
    /// assert!(error.to_string().starts_with("--carrier-hz 10500 is +5 % from the carrier measured"));
    /// # Ok::<(), angletrack::WindingsPlanError>(())
    /// ```
    pub fn new(
        first_c: &[f64],
        first_s: &[f64],
        settings: &WindingsSettings,
    ) -> Result<Self, WindingsPlanError> {
        if let Some(a) = settings.carrier_amplitude_counts
            && !(a.is_finite() && a > 0.0 && a <= LARGEST_CARRIER_AMPLITUDE_COUNTS)
        {
            return Err(WindingsPlanError::CarrierAmplitude(a));
        }
        let carrier_hz = settings.carrier_hz;
        let adc_rate_hz = match (settings.samples_per_period, settings.capture_hz) {
            (Some(n), _) => n * carrier_hz,
            (None, Some(rate)) => rate,
            (None, None) => return Err(WindingsPlanError::NoAdcRate),
        };
        let samples_per_period = adc_rate_hz / carrier_hz;
        if !(samples_per_period >= 4.0) {
            return Err(WindingsPlanError::TooFewSamplesPerPeriod {
                adc_rate_hz,
                carrier_hz,
            });
        }
        if let (Some(stated), Some(capture_hz)) = (settings.samples_per_period, settings.capture_hz)
            && ((capture_hz / carrier_hz) / stated - 1.0).abs() > SAMPLES_PER_PERIOD_TOLERANCE
        {
            return Err(WindingsPlanError::SamplesPerPeriodContradicted {
                stated,
                capture_hz,
                carrier_hz,
            });
        }
        // The windings' power about their means gives both the carrier and the amplitude.
        let power = centred_power(first_c, first_s);
        if let Some(cycles) = cycles_of_power(&power) {
            let rate_hz = settings.capture_hz.unwrap_or(adc_rate_hz);
            let measured_hz = cycles * rate_hz;
            if (measured_hz / carrier_hz - 1.0).abs() > CARRIER_TOLERANCE {
                return Err(WindingsPlanError::CarrierContradicted {
                    declared_hz: carrier_hz,
                    measured_hz,
                    rate_hz,
                    from_time_column: settings.capture_hz.is_some(),
                    samples_per_period,
                });
            }
        }
        // A measured amplitude from the power's mean, A^2 / 2.
        let carrier_amplitude_counts = settings
            .carrier_amplitude_counts
            .unwrap_or_else(|| (2.0 * mean(&power)).sqrt());
        let (adc_range, adc_range_source) = match settings.adc_range {
            Some(range) => (range, AdcRangeSource::Stated),
            None => match measured_winding_range(first_c, first_s) {
                Some(range) => (range, AdcRangeSource::Measured),
                None => (guessed_range(first_c, first_s), AdcRangeSource::Guessed),
            },
        };
        Ok(Self {
            adc_rate_hz,
            samples_per_period,
            carrier_amplitude_counts,
            adc_range,
            adc_range_source,
        })
    }
}

/// The smallest power-of-two span of codes holding the samples (at least 1 in magnitude):
/// from 0 if none is negative, else signed.
fn guessed_range(c: &[f64], s: &[f64]) -> (f64, f64) {
    let samples = || c.iter().chain(s).copied();
    let largest = samples().fold(1.0_f64, |m, v| m.max(v.abs()));
    let full = (largest + 1.0).log2().ceil().exp2();
    if samples().all(|v| v >= 0.0) {
        (0.0, full - 1.0)
    } else {
        (-full, full - 1.0)
    }
}

/// `x` to `digits` significant digits, as C's `%g` writes it (no trailing zeros).
fn significant(x: f64, digits: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let exponent = x.abs().log10().floor() as i32;
    if exponent < -4 || exponent >= digits {
        let text = format!("{:.*e}", (digits - 1) as usize, x);
        let (mantissa, power) = text.split_once('e').unwrap_or((&text, "0"));
        let power: i32 = power.parse().unwrap_or(0);
        let sign = if power < 0 { '-' } else { '+' };
        return format!("{}e{sign}{:02}", trimmed(mantissa), power.abs());
    }
    trimmed(&format!(
        "{:.*}",
        (digits - 1 - exponent).max(0) as usize,
        x
    ))
    .to_string()
}

/// A decimal number without trailing zeros after its point (nor the point).
fn trimmed(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

#[cfg(test)]
#[path = "windings_plan_tests.rs"]
mod tests;
