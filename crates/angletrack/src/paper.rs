//! The settings of Auger, Mansouri-Toudert and Chibah, *Design of advanced resolver-to-digital
//! converters* (2011), and the reference observers built from them: one place for the
//! figures that the cross-crate tests, the `paper_figures` example, the benchmarks, the
//! firmware test and the Python report all use.
//!
//! * [`PaperSetting`]: the four settings whose step-response overshoot the paper quotes
//!   (`docs/theory.md §2` and `§3`).
//! * [`ComparedObserver`]: the three observers the report compares on the same signals, each
//!   about [`COMPARISON_BANDWIDTH_HZ`] wide at [`COMPARISON_SAMPLE_PERIOD_S`] (`§2` to `§4`).
//! * [`BENCHMARK_SECOND_ORDER_GAINS`], [`BENCHMARK_THIRD_ORDER_GAINS`],
//!   [`BENCHMARK_KALMAN_GAINS`]: the fixed discrete gains of the benchmarks and of the
//!   firmware test at [`BENCHMARK_SAMPLE_PERIOD_S`], written out to the digits the `f32`
//!   firmware embeds.

use core::f64::consts::{FRAC_1_SQRT_2, PI};

use crate::design::{
    AnyDesign, Discretisation, kalman, kalman_from_jerk_std, second_order_from_bandwidth,
    second_order_from_tracking_error, third_order_butterworth, third_order_from_poles,
};
use crate::error::Error;

/// The damping `m` of the 2nd-order ATO that overshoots by 5 % (continuous loop).
pub const FIVE_PERCENT_DAMPING: f64 = 1.945;

/// The Butterworth damping `m = sqrt(2)/2` of the 2nd-order ATO (20.8 % overshoot).
pub const BUTTERWORTH_DAMPING: f64 = FRAC_1_SQRT_2;

/// The ratio `K` of the 3rd-order pole placement (real pole at `-K/T`) that overshoots by
/// 10 % with [`POLE_FREQUENCY_RATIO`].
pub const POLE_RATIO: f64 = 39.04;

/// The ratio `psi = 3 pi / 2` of the 3rd-order pole placement (complex pair at
/// `(-1 +- j psi)/T`).
pub const POLE_FREQUENCY_RATIO: f64 = 1.5 * PI;

/// The sample period (s) at which [`PaperSetting::design`] is usually evaluated (100 kHz):
/// at least 200 times each setting's -3 dB bandwidth, so that the sampled loop's overshoot
/// is within a few tenths of a point of the continuous figure.
pub const OVERSHOOT_SAMPLE_PERIOD_S: f64 = 1e-5;

/// One of the four settings whose overshoot the paper quotes.
///
/// The overshoot depends on the shape of the loop only; the time scale of each setting
/// (the tolerated error of 1 mrad at 100 rad/s^2, `T = 20 ms`, `Tc = 5 ms`) puts every
/// -3 dB bandwidth between 90 and 350 Hz, at least 250 times below 100 kHz.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PaperSetting {
    /// 2nd-order ATO with damping [`FIVE_PERCENT_DAMPING`]: 5 %.
    SecondOrderFivePercent,
    /// 2nd-order ATO with damping [`BUTTERWORTH_DAMPING`]: 20.8 %.
    SecondOrderButterworth,
    /// 3rd-order ATO with [`POLE_RATIO`] and [`POLE_FREQUENCY_RATIO`]: 10 %.
    ThirdOrderTenPercent,
    /// 3rd-order Butterworth setting: 30.9 %.
    ThirdOrderButterworth,
}

impl PaperSetting {
    /// The four settings, in the paper's order.
    pub const ALL: [PaperSetting; 4] = [
        PaperSetting::SecondOrderFivePercent,
        PaperSetting::SecondOrderButterworth,
        PaperSetting::ThirdOrderTenPercent,
        PaperSetting::ThirdOrderButterworth,
    ];

    /// The name used in tables.
    pub const fn name(self) -> &'static str {
        match self {
            PaperSetting::SecondOrderFivePercent => "2nd order, m = 1.945",
            PaperSetting::SecondOrderButterworth => "2nd order, Butterworth m = sqrt(2)/2",
            PaperSetting::ThirdOrderTenPercent => "3rd order, K = 39.04, psi = 3 pi/2",
            PaperSetting::ThirdOrderButterworth => "3rd order, Butterworth",
        }
    }

    /// The overshoot (percent of the step) the paper quotes for the continuous loop.
    pub const fn overshoot_percent(self) -> f64 {
        match self {
            PaperSetting::SecondOrderFivePercent => 5.0,
            PaperSetting::SecondOrderButterworth => 20.8,
            PaperSetting::ThirdOrderTenPercent => 10.0,
            PaperSetting::ThirdOrderButterworth => 30.9,
        }
    }

    /// The setting designed at `sample_period_s` and carried to the discrete loop by
    /// `discretisation`.
    ///
    /// ```
    /// use angletrack::{DesignReport, Discretisation};
    /// use angletrack::paper::{OVERSHOOT_SAMPLE_PERIOD_S, PaperSetting};
    /// let design = PaperSetting::ThirdOrderTenPercent
    ///     .design(OVERSHOOT_SAMPLE_PERIOD_S, Discretisation::PoleMatching)?;
    /// let overshoot = design.report(0.0)?.continuous_step.unwrap().overshoot;
    /// assert!((overshoot - 0.10).abs() < 0.002);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn design(
        self,
        sample_period_s: f64,
        discretisation: Discretisation,
    ) -> Result<AnyDesign, Error> {
        let ts = sample_period_s;
        Ok(match self {
            PaperSetting::SecondOrderFivePercent => second_order_from_tracking_error(
                1e-3,
                100.0,
                FIVE_PERCENT_DAMPING,
                ts,
                discretisation,
            )?
            .into(),
            PaperSetting::SecondOrderButterworth => second_order_from_tracking_error(
                1e-3,
                100.0,
                BUTTERWORTH_DAMPING,
                ts,
                discretisation,
            )?
            .into(),
            PaperSetting::ThirdOrderTenPercent => {
                third_order_from_poles(POLE_RATIO, 0.02, POLE_FREQUENCY_RATIO, ts, discretisation)?
                    .into()
            }
            PaperSetting::ThirdOrderButterworth => {
                third_order_butterworth(5e-3, ts, discretisation)?.into()
            }
        })
    }
}

/// The sample period (s) of the observers' comparison: 10 kHz.
pub const COMPARISON_SAMPLE_PERIOD_S: f64 = 1e-4;

/// The -3 dB bandwidth (Hz) the compared observers have, to within a few percent.
pub const COMPARISON_BANDWIDTH_HZ: f64 = 100.0;

/// The sensor noise (standard deviation per channel, amplitude 1) of the comparison, and
/// the one the Kalman ATO is designed for.
pub const COMPARISON_SENSOR_NOISE_STD: f64 = 0.01;

/// One of the three observers the report compares on the same signals, at
/// [`COMPARISON_SAMPLE_PERIOD_S`] with about [`COMPARISON_BANDWIDTH_HZ`] of bandwidth each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ComparedObserver {
    /// The 2nd-order ATO with damping [`FIVE_PERCENT_DAMPING`], 100 Hz wide.
    SecondOrder,
    /// The 3rd-order ATO with [`POLE_RATIO`], [`POLE_FREQUENCY_RATIO`] and `T = 68 ms`.
    ThirdOrder,
    /// The time-invariant Kalman ATO for a jerk of 1e5 rad/s^3 (standard deviation) and the
    /// comparison's sensor noise.
    Kalman,
}

impl ComparedObserver {
    /// The three observers, in the paper's order.
    pub const ALL: [ComparedObserver; 3] = [
        ComparedObserver::SecondOrder,
        ComparedObserver::ThirdOrder,
        ComparedObserver::Kalman,
    ];

    /// The name used in tables.
    pub const fn name(self) -> &'static str {
        match self {
            ComparedObserver::SecondOrder => "2nd-order ATO",
            ComparedObserver::ThirdOrder => "3rd-order ATO",
            ComparedObserver::Kalman => "Kalman ATO",
        }
    }

    /// The observer's design (pole matching for the continuous ones).
    ///
    /// ```
    /// use angletrack::paper::{COMPARISON_BANDWIDTH_HZ, ComparedObserver};
    /// for observer in ComparedObserver::ALL {
    ///     let bandwidth = observer.design()?.report(0.0)?.bandwidth_hz.unwrap();
    ///     assert!((bandwidth / COMPARISON_BANDWIDTH_HZ - 1.0).abs() < 0.15, "{bandwidth}");
    /// }
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn design(self) -> Result<AnyDesign, Error> {
        let ts = COMPARISON_SAMPLE_PERIOD_S;
        let pm = Discretisation::PoleMatching;
        Ok(match self {
            ComparedObserver::SecondOrder => {
                second_order_from_bandwidth(COMPARISON_BANDWIDTH_HZ, FIVE_PERCENT_DAMPING, ts, pm)?
                    .into()
            }
            ComparedObserver::ThirdOrder => {
                third_order_from_poles(POLE_RATIO, 0.068, POLE_FREQUENCY_RATIO, ts, pm)?.into()
            }
            ComparedObserver::Kalman => {
                kalman_from_jerk_std(1e5, COMPARISON_SENSOR_NOISE_STD, ts)?.into()
            }
        })
    }
}

/// The sample period (s) of the benchmark gains: 10 kHz.
pub const BENCHMARK_SAMPLE_PERIOD_S: f64 = 1e-4;

/// Discrete gains `(l1, l2)` of the benchmarks' 2nd-order ATO: natural frequency 50 Hz,
/// damping 1, pole matching at [`BENCHMARK_SAMPLE_PERIOD_S`].
pub const BENCHMARK_SECOND_ORDER_GAINS: [f64; 2] = [0.060_898_63, 0.000_956_514_8];

/// Discrete gains `(l1, l2, l3)` of the benchmarks' 3rd-order ATO: pole placement with
/// [`POLE_RATIO`], [`POLE_FREQUENCY_RATIO`] and `T = 41.42 ms`, pole matching at
/// [`BENCHMARK_SAMPLE_PERIOD_S`].
pub const BENCHMARK_THIRD_ORDER_GAINS: [f64; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];

/// Discrete gains `(l1, l2, l3)` of the benchmarks' Kalman ATO: `q / r = 1e-9`.
pub const BENCHMARK_KALMAN_GAINS: [f64; 3] = [0.061_286_65, 0.001_937_879, 3.063_843e-5];

/// The benchmark gains of the three observers recomputed by their designs, in the order
/// 2nd order, 3rd order, Kalman (`l3 = 0` for the 2nd order): what the written-out
/// constants round.
pub fn benchmark_designs() -> Result<[AnyDesign; 3], Error> {
    let ts = BENCHMARK_SAMPLE_PERIOD_S;
    let pm = Discretisation::PoleMatching;
    // Damping 1: bandwidth = natural frequency times the 2nd-order bandwidth ratio.
    let bandwidth_hz = 50.0 * crate::design::second_order_bandwidth_ratio(1.0)?;
    Ok([
        second_order_from_bandwidth(bandwidth_hz, 1.0, ts, pm)?.into(),
        third_order_from_poles(POLE_RATIO, 41.42e-3, POLE_FREQUENCY_RATIO, ts, pm)?.into(),
        kalman(1e-9, 1.0, ts)?.into(),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The written-out benchmark gains are their designs' gains to the digits written
    /// (the 3rd order's `T` to four digits: 2e-4 relative).
    #[test]
    fn benchmark_gains_round_their_designs() {
        let [second, third, kalman] = benchmark_designs().unwrap();
        let close = |written: &[f64], designed: &[f64], relative: f64| {
            for (w, d) in written.iter().zip(designed) {
                assert!(
                    (w / d - 1.0).abs() < relative,
                    "{written:?} vs {designed:?}"
                );
            }
        };
        close(&BENCHMARK_SECOND_ORDER_GAINS, &second.gains(), 1e-7);
        close(&BENCHMARK_KALMAN_GAINS, &kalman.gains(), 1e-6);
        close(&BENCHMARK_THIRD_ORDER_GAINS, &third.gains(), 1e-3);
    }

    /// Every setting and compared observer is designed at its documented sample period.
    #[test]
    fn settings_and_compared_observers_are_designed() {
        for setting in PaperSetting::ALL {
            let design = setting
                .design(OVERSHOOT_SAMPLE_PERIOD_S, Discretisation::PoleMatching)
                .unwrap();
            let report = design.report(0.0).unwrap();
            let ratio = 1.0 / (report.sample_period_s * report.bandwidth_hz.unwrap());
            assert!(ratio > 250.0, "{}: {ratio}", setting.name());
        }
        for observer in ComparedObserver::ALL {
            assert_eq!(
                observer.design().unwrap().sample_period(),
                COMPARISON_SAMPLE_PERIOD_S
            );
        }
    }
}
