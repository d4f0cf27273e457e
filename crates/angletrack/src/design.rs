//! Gain design: from time-domain specifications, pole placement and noise variances to the
//! discrete gains of the core's recursion.
//!
//! Continuous designs give the closed-loop poles `s_i` (rad/s) of the continuous loop
//! `s^N + k_a s^(N-1) + k_b s^(N-2) [+ k_c]`; a [`Discretisation`] maps them to discrete poles
//! `z_i`, and [`Gains::from_loop_polynomial`] gives the gains whose loop
//! `(I - L e1^T) A` has exactly those poles. The polynomial is written in `z - 1`, computed
//! from `z_i - 1` directly (`exp_m1` for pole matching), so that a loop a million times
//! slower than its sample rate is designed to full precision.

use core::f64::consts::{PI, SQRT_2};

use angletrack_core::{Gains, Order, Real, SupportedOrder};
use nalgebra::{Complex, DMatrix};

use crate::error::{Argument, Error, positive};
use crate::linalg;

/// How a continuous design is carried over to the discrete recursion.
///
/// Each maps every continuous closed-loop pole `s_i` to a discrete pole `z_i`, and the gains
/// are chosen so that the discrete loop has exactly the poles `z_i`. The
/// [`DesignReport`](crate::DesignReport) shows how far the result moves from the continuous
/// design (continuous-equivalent poles `ln(z_i) / Ts`, overshoot of both step responses).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Discretisation {
    /// `z = exp(s Ts)`: the discrete poles are exactly the sampled continuous poles (the
    /// default). Stable for any stable continuous design.
    #[default]
    PoleMatching,
    /// `z = 1 + s Ts`: the explicit Euler step of the continuous loop. Unstable once
    /// `|1 + s Ts| >= 1` for some pole (lightly damped poles first); refused there.
    ForwardEuler,
    /// `z = (1 + s Ts/2) / (1 - s Ts/2)`: the bilinear (trapezoidal) map. Stable for any
    /// stable continuous design; compresses high frequencies.
    Tustin,
}

impl Discretisation {
    /// `z - 1` for the continuous pole `s` (rad/s) and the sample period `ts` (s).
    pub fn map_pole(self, s: Complex<f64>, ts: f64) -> Complex<f64> {
        let w = s * ts;
        match self {
            Discretisation::PoleMatching => linalg::exp_m1(w),
            Discretisation::ForwardEuler => w,
            Discretisation::Tustin => w / (Complex::new(1.0, 0.0) - w * 0.5),
        }
    }

    /// The name used in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Discretisation::PoleMatching => "pole matching",
            Discretisation::ForwardEuler => "forward Euler",
            Discretisation::Tustin => "Tustin",
        }
    }

    /// The identifier used on command lines and in the Python API: `pole_matching`,
    /// `forward_euler`, `tustin` (what [`str::parse`] accepts, with `-` or a space for
    /// `_`, in any case).
    pub const fn id(self) -> &'static str {
        match self {
            Discretisation::PoleMatching => "pole_matching",
            Discretisation::ForwardEuler => "forward_euler",
            Discretisation::Tustin => "tustin",
        }
    }
}

impl core::str::FromStr for Discretisation {
    type Err = Error;

    /// Parses [`Discretisation::id`] (case, `-` and spaces ignored).
    ///
    /// ```
    /// use angletrack::Discretisation;
    /// assert_eq!("Forward-Euler".parse(), Ok(Discretisation::ForwardEuler));
    /// assert!("zoh".parse::<Discretisation>().is_err());
    /// ```
    fn from_str(text: &str) -> Result<Self, Error> {
        let id: String = text
            .trim()
            .chars()
            .map(|c| match c {
                '-' | ' ' => '_',
                c => c.to_ascii_lowercase(),
            })
            .collect();
        [
            Discretisation::PoleMatching,
            Discretisation::ForwardEuler,
            Discretisation::Tustin,
        ]
        .into_iter()
        .find(|d| d.id() == id)
        .ok_or(Error::OutOfRange {
            argument: Argument::Discretisation,
            expected: "pole_matching, forward_euler or tustin",
        })
    }
}

/// The largest `|s_i| Ts` a continuous design may have: every continuous pole must lie
/// below the sample rate in rad/s (`|s_i| <= 1 / Ts`, i.e. pole frequencies below
/// `fs / (2 pi)`). Beyond it the discrete loop no longer behaves like the continuous design
/// whatever the mapping.
pub const MAX_POLE_TIMES_PERIOD: f64 = 1.0;

/// Which design rule produced a gain set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DesignMethod {
    /// 2nd order from a tolerated error at an acceleration and a damping.
    SecondOrderTrackingError,
    /// 2nd order from a -3 dB bandwidth and a damping.
    SecondOrderBandwidth,
    /// 2nd-order Butterworth setting (damping `sqrt(2)/2`).
    SecondOrderButterworth,
    /// 3rd order by pole placement `(K, T, psi)`.
    ThirdOrderPolePlacement,
    /// 3rd order from a target overshoot and settling time.
    ThirdOrderOvershoot,
    /// 3rd-order Butterworth setting (`Tc`).
    ThirdOrderButterworth,
    /// Steady-state Kalman gain (3rd order).
    Kalman,
    /// Gains given directly, not designed here.
    Given,
}

impl DesignMethod {
    /// A short description used in reports.
    pub const fn name(self) -> &'static str {
        match self {
            DesignMethod::SecondOrderTrackingError => "2nd order, tracking error at acceleration",
            DesignMethod::SecondOrderBandwidth => "2nd order, bandwidth and damping",
            DesignMethod::SecondOrderButterworth => "2nd order, Butterworth",
            DesignMethod::ThirdOrderPolePlacement => "3rd order, pole placement (K, T, psi)",
            DesignMethod::ThirdOrderOvershoot => "3rd order, overshoot and settling time",
            DesignMethod::ThirdOrderButterworth => "3rd order, Butterworth",
            DesignMethod::Kalman => "3rd order, steady-state Kalman",
            DesignMethod::Given => "given gains",
        }
    }
}

/// The steady-state solution of the Kalman design, on the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalmanSolution {
    /// Process noise variance `q` of the scaled jerk `v = Ts^3 beta` (rad^2).
    pub process_noise_q: f64,
    /// Measurement noise variance `r` of each channel (amplitude 1).
    pub measurement_noise_r: f64,
    /// The predicted (a priori) error covariance, solution of the DARE.
    pub predicted_covariance: [[f64; 3]; 3],
    /// The filtered (a posteriori) error covariance `P - P e1 e1^T P / (r + P11)`.
    pub covariance: [[f64; 3]; 3],
}

impl KalmanSolution {
    /// `sqrt(P11)` of the filtered covariance (rad): the smallest RMS angle error any linear
    /// estimator of the model reaches (for the design's own `q` and `r`).
    pub fn angle_floor_rad(&self) -> f64 {
        self.covariance[0][0].sqrt()
    }

    /// `sqrt(P22) / Ts` of the filtered covariance (rad/s): the matching speed floor.
    pub fn speed_floor_rad_s(&self, sample_period_s: f64) -> f64 {
        self.covariance[1][1].sqrt() / sample_period_s
    }
}

/// A designed gain set (in `f64`) with what it was designed from.
///
/// Convert to the float type of the firmware with [`Design::to_gains`]; analyse with
/// [`DesignReport::new`](crate::DesignReport::new).
#[derive(Debug, Clone, PartialEq)]
pub struct Design<const N: usize>
where
    Order<N>: SupportedOrder,
{
    /// The discrete gains, checked by the core.
    pub gains: Gains<f64, N>,
    /// The design rule.
    pub method: DesignMethod,
    /// The mapping used for a continuous design; `None` for Kalman and given gains.
    pub discretisation: Option<Discretisation>,
    /// The continuous closed-loop poles (rad/s) of a continuous design; empty otherwise.
    pub continuous_poles: Vec<Complex<f64>>,
    /// The continuous gains `(k_a, k_b[, k_c])` of a continuous design.
    pub continuous_gains: Option<[f64; N]>,
    /// The steady-state Riccati solution of a Kalman design.
    pub kalman: Option<KalmanSolution>,
}

impl<const N: usize> Design<N>
where
    Order<N>: SupportedOrder,
{
    /// Wraps gains designed elsewhere, to analyse them.
    ///
    /// ```
    /// use angletrack::{Design, DesignReport, Gains};
    /// let design = Design::from_gains(Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?);
    /// let report = DesignReport::new(&design, 0.01)?;
    /// assert!(report.bandwidth_hz.unwrap() > 0.0);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn from_gains(gains: Gains<f64, N>) -> Self {
        Self {
            gains,
            method: DesignMethod::Given,
            discretisation: None,
            continuous_poles: Vec::new(),
            continuous_gains: None,
            kalman: None,
        }
    }

    /// The gains in the float type `T` of the target (`f32` on a Cortex-M4F), with the
    /// default sin/cos of that type, checked again by the core after rounding.
    ///
    /// ```
    /// use angletrack::{Discretisation, second_order_from_bandwidth};
    /// let design = second_order_from_bandwidth(100.0, 1.0, 1e-4, Discretisation::PoleMatching)?;
    /// let gains = design.to_gains::<f32>()?;
    /// assert_eq!(gains.sample_period(), 1e-4_f32);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn to_gains<T: Real>(&self) -> Result<Gains<T, N>, Error> {
        convert_gains(&self.gains)
    }

    /// The sample period (s).
    pub fn sample_period(&self) -> f64 {
        self.gains.sample_period()
    }
}

/// A design of either order, for code that handles the 2nd- and 3rd-order observers
/// alike (tables of settings, the Python binding).
#[derive(Debug, Clone, PartialEq)]
pub enum AnyDesign {
    /// A 2nd-order design.
    Second(Design<2>),
    /// A 3rd-order design.
    Third(Design<3>),
}

impl From<Design<2>> for AnyDesign {
    fn from(design: Design<2>) -> Self {
        AnyDesign::Second(design)
    }
}

impl From<Design<3>> for AnyDesign {
    fn from(design: Design<3>) -> Self {
        AnyDesign::Third(design)
    }
}

impl AnyDesign {
    /// The loop order (2 or 3).
    pub fn order(&self) -> usize {
        match self {
            AnyDesign::Second(_) => 2,
            AnyDesign::Third(_) => 3,
        }
    }

    /// The discrete gains `(l1, l2[, l3])`.
    pub fn gains(&self) -> Vec<f64> {
        match self {
            AnyDesign::Second(d) => d.gains.gains().to_vec(),
            AnyDesign::Third(d) => d.gains.gains().to_vec(),
        }
    }

    /// The sample period (s).
    pub fn sample_period(&self) -> f64 {
        match self {
            AnyDesign::Second(d) => d.sample_period(),
            AnyDesign::Third(d) => d.sample_period(),
        }
    }

    /// [`DesignReport::new`](crate::DesignReport::new) of the design.
    ///
    /// ```
    /// use angletrack::{AnyDesign, Discretisation, second_order_butterworth};
    /// let design: AnyDesign =
    ///     second_order_butterworth(1e-2, 1e-5, Discretisation::PoleMatching)?.into();
    /// assert_eq!(design.report(0.0)?.order, 2);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn report(&self, sensor_noise_std: f64) -> Result<crate::DesignReport, Error> {
        match self {
            AnyDesign::Second(d) => crate::DesignReport::new(d, sensor_noise_std),
            AnyDesign::Third(d) => crate::DesignReport::new(d, sensor_noise_std),
        }
    }
}

/// Rounds `f64` gains to the float type `T` and checks them again with the core (a gain set
/// close to the edge of the stability region can leave it by rounding).
///
/// ```
/// use angletrack::{Gains, convert_gains};
/// let exact = Gains::<f64, 3>::new([0.3, 0.04, 0.002], 1e-4)?;
/// let single: Gains<f32, 3> = convert_gains(&exact)?;
/// assert_eq!(single.gains(), [0.3_f32, 0.04, 0.002]);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn convert_gains<T: Real, const N: usize>(gains: &Gains<f64, N>) -> Result<Gains<T, N>, Error>
where
    Order<N>: SupportedOrder,
{
    Ok(Gains::new(
        gains.gains().map(T::from_f64),
        T::from_f64(gains.sample_period()),
    )?)
}

/// Carries continuous closed-loop poles to discrete gains: the shared last step of every
/// continuous design.
fn discretise<const N: usize>(
    poles: Vec<Complex<f64>>,
    sample_period_s: f64,
    discretisation: Discretisation,
    speed_argument: Argument,
    method: DesignMethod,
) -> Result<Design<N>, Error>
where
    Order<N>: SupportedOrder,
{
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let fastest = poles.iter().map(|s| s.norm() * ts).fold(0.0, f64::max);
    if !(fastest <= MAX_POLE_TIMES_PERIOD) {
        return Err(Error::TooFastForSampleRate {
            argument: speed_argument,
            pole_times_period: fastest,
            limit: MAX_POLE_TIMES_PERIOD,
        });
    }
    let shifted: Vec<Complex<f64>> = poles
        .iter()
        .map(|&s| discretisation.map_pole(s, ts))
        .collect();
    if discretisation == Discretisation::ForwardEuler {
        // |z| = |1 + s Ts| must stay below 1.
        let largest = shifted
            .iter()
            .map(|u| (Complex::new(1.0, 0.0) + u).norm())
            .fold(0.0, f64::max);
        if !(largest < 1.0) {
            let limit = poles
                .iter()
                .map(|s| -2.0 * s.re / s.norm())
                .fold(f64::INFINITY, f64::min);
            return Err(Error::TooFastForSampleRate {
                argument: speed_argument,
                pole_times_period: fastest,
                limit,
            });
        }
    }
    let c = linalg::monic_from_roots(&shifted);
    let mut coefficients = [0.0; N];
    coefficients.copy_from_slice(&c);
    let gains = Gains::from_loop_polynomial(coefficients, ts)?;
    let continuous = linalg::monic_from_roots(&poles);
    let mut continuous_gains = [0.0; N];
    for (k, gain) in continuous_gains.iter_mut().enumerate() {
        *gain = continuous[N - 1 - k];
    }
    Ok(Design {
        gains,
        method,
        discretisation: Some(discretisation),
        continuous_poles: poles,
        continuous_gains: Some(continuous_gains),
        kalman: None,
    })
}

/// The roots of `s^2 + k_a s + k_b`.
fn second_order_poles(k_a: f64, k_b: f64) -> Vec<Complex<f64>> {
    linalg::roots(&[k_b, k_a])
}

fn check_damping(damping: f64) -> Result<f64, Error> {
    positive(damping, Argument::Damping)?;
    if damping > 1e3 {
        return Err(Error::OutOfRange {
            argument: Argument::Damping,
            expected: "0 < damping <= 1000",
        });
    }
    Ok(damping)
}

/// The classical 2nd-order ATO designed in the time domain (the paper's rule): the
/// tolerated angle error `max_error_rad` under constant acceleration `acceleration_rad_s2`
/// sets `k_b1 = acceleration / max_error` (the acceleration constant Ka), the damping `m`
/// sets `k_a1 = 2 m sqrt(k_b1)`.
///
/// `m = 1.945` gives 5 % overshoot, `m = sqrt(2)/2` (Butterworth) 20.8 %. The discrete
/// loop's acceleration constant differs from `k_b1` by the discretisation (see the report).
///
/// ```
/// use angletrack::{Discretisation, second_order_from_tracking_error};
/// // 1 mrad at 1000 rad/s^2, damping 1, 10 kHz:
/// let design =
///     second_order_from_tracking_error(1e-3, 1e3, 1.0, 1e-4, Discretisation::PoleMatching)?;
/// let [k_a1, k_b1] = design.continuous_gains.unwrap();
/// assert!((k_b1 - 1e6).abs() < 1e-6 && (k_a1 - 2e3).abs() < 1e-9);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_from_tracking_error(
    max_error_rad: f64,
    acceleration_rad_s2: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let max_error = positive(max_error_rad, Argument::MaxError)?;
    let acceleration = positive(acceleration_rad_s2, Argument::Acceleration)?;
    let m = check_damping(damping)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let k_b = acceleration / max_error;
    let k_a = 2.0 * m * k_b.sqrt();
    if !(k_a.is_finite() && k_b.is_finite()) {
        return Err(Error::OutOfRange {
            argument: Argument::MaxError,
            expected: "acceleration / max_error finite",
        });
    }
    discretise(
        second_order_poles(k_a, k_b),
        sample_period_s,
        discretisation,
        Argument::MaxError,
        DesignMethod::SecondOrderTrackingError,
    )
}

/// `omega_3dB / omega_n` of the continuous loop `(2 m wn s + wn^2) / (s^2 + 2 m wn s + wn^2)`:
/// `sqrt(1 + 2 m^2 + sqrt((1 + 2 m^2)^2 + 1))`.
///
/// ```
/// // Damping sqrt(2)/2: the -3 dB bandwidth is 2.06 times the natural frequency.
/// let ratio = angletrack::second_order_bandwidth_ratio(2f64.sqrt() / 2.0);
/// assert!((ratio - 2.058).abs() < 1e-3);
/// ```
pub fn second_order_bandwidth_ratio(damping: f64) -> f64 {
    let a = 1.0 + 2.0 * damping * damping;
    (a + (a * a + 1.0).sqrt()).sqrt()
}

/// The 2nd-order ATO with a given -3 dB bandwidth of the continuous closed loop
/// `(k_a1 s + k_b1) / (s^2 + k_a1 s + k_b1)` and damping `m`: natural frequency
/// `wn = 2 pi bandwidth / sqrt(1 + 2 m^2 + sqrt((1 + 2 m^2)^2 + 1))`, `k_b1 = wn^2`,
/// `k_a1 = 2 m wn`.
///
/// ```
/// use angletrack::{Discretisation, DesignReport, second_order_from_bandwidth};
/// let design = second_order_from_bandwidth(200.0, 0.8, 1e-5, Discretisation::PoleMatching)?;
/// let report = DesignReport::new(&design, 0.0)?;
/// assert!((report.bandwidth_hz.unwrap() - 200.0).abs() < 1.0);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_from_bandwidth(
    bandwidth_hz: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let bandwidth = positive(bandwidth_hz, Argument::Bandwidth)?;
    let m = check_damping(damping)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let wn = 2.0 * PI * bandwidth / second_order_bandwidth_ratio(m);
    discretise(
        second_order_poles(2.0 * m * wn, wn * wn),
        sample_period_s,
        discretisation,
        Argument::Bandwidth,
        DesignMethod::SecondOrderBandwidth,
    )
}

/// The 2nd-order Butterworth setting with time constant `Tc = 1 / wn`:
/// `k_a1 = sqrt(2) / Tc`, `k_b1 = 1 / Tc^2` (damping `sqrt(2)/2`, 20.8 % overshoot).
///
/// ```
/// use angletrack::{Discretisation, second_order_butterworth};
/// let design = second_order_butterworth(2e-3, 1e-4, Discretisation::PoleMatching)?;
/// let [k_a1, k_b1] = design.continuous_gains.unwrap();
/// assert!((k_a1 - 707.106_781).abs() < 1e-3 && (k_b1 - 2.5e5).abs() < 1e-6);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn second_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<2>, Error> {
    let tc = positive(time_constant_s, Argument::TimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    discretise(
        second_order_poles(SQRT_2 / tc, 1.0 / (tc * tc)),
        sample_period_s,
        discretisation,
        Argument::TimeConstant,
        DesignMethod::SecondOrderButterworth,
    )
}

/// The continuous poles `-K/T` and `(-1 +- j psi)/T` of the 3rd-order pole placement.
fn third_order_poles(k: f64, t: f64, psi: f64) -> Vec<Complex<f64>> {
    vec![
        Complex::new(-k / t, 0.0),
        Complex::new(-1.0 / t, -psi / t),
        Complex::new(-1.0 / t, psi / t),
    ]
}

fn check_pole_family(k: f64, psi: f64) -> Result<(), Error> {
    positive(k, Argument::PoleRatio)?;
    positive(psi, Argument::PoleFrequencyRatio)?;
    if k > 1e6 {
        return Err(Error::OutOfRange {
            argument: Argument::PoleRatio,
            expected: "0 < K <= 1e6",
        });
    }
    if psi > 1e3 {
        return Err(Error::OutOfRange {
            argument: Argument::PoleFrequencyRatio,
            expected: "0 < psi <= 1000",
        });
    }
    Ok(())
}

/// The 3rd-order ATO by pole placement (the paper's rule): a real pole at `-K/T` and a
/// complex pair at `(-1 +- j psi)/T` (rad/s), i.e.
/// `k_a2 = (K + 2)/T`, `k_b2 = (psi^2 + 2K + 1)/T^2`, `k_c2 = K (psi^2 + 1)/T^3`.
///
/// `K = 39.04`, `psi = 3 pi / 2` gives 10 % overshoot.
///
/// ```
/// use angletrack::{Discretisation, third_order_from_poles};
/// use std::f64::consts::PI;
/// let design = third_order_from_poles(39.04, 0.01, 1.5 * PI, 1e-5, Discretisation::PoleMatching)?;
/// let [k_a2, k_b2, k_c2] = design.continuous_gains.unwrap();
/// let psi2 = (1.5 * PI).powi(2);
/// assert!((k_a2 - 41.04 / 0.01).abs() < 1e-9);
/// assert!((k_b2 - (psi2 + 79.08) / 1e-4).abs() < 1e-6);
/// assert!((k_c2 / (39.04 * (psi2 + 1.0) / 1e-6) - 1.0).abs() < 1e-12);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_from_poles(
    pole_ratio: f64,
    pole_time_constant_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    check_pole_family(pole_ratio, pole_frequency_ratio)?;
    let t = positive(pole_time_constant_s, Argument::PoleTimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    discretise(
        third_order_poles(pole_ratio, t, pole_frequency_ratio),
        sample_period_s,
        discretisation,
        Argument::PoleTimeConstant,
        DesignMethod::ThirdOrderPolePlacement,
    )
}

/// The 3rd-order Butterworth setting with time constant `Tc`:
/// `k_a2 = 2/Tc`, `k_b2 = 2/Tc^2`, `k_c2 = 1/Tc^3` (poles `-1/Tc` and
/// `(-1 +- j sqrt(3)) / (2 Tc)`; 30.9 % overshoot).
///
/// ```
/// use angletrack::{Discretisation, third_order_butterworth};
/// let design = third_order_butterworth(1e-3, 1e-5, Discretisation::Tustin)?;
/// let [k_a2, k_b2, k_c2] = design.continuous_gains.unwrap();
/// assert!((k_a2 - 2e3).abs() < 1e-9 && (k_b2 - 2e6).abs() < 1e-6 && (k_c2 - 1e9).abs() < 1e-3);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    let tc = positive(time_constant_s, Argument::TimeConstant)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let half = 0.5 / tc;
    let poles = vec![
        Complex::new(-1.0 / tc, 0.0),
        Complex::new(-half, -3.0_f64.sqrt() * half),
        Complex::new(-half, 3.0_f64.sqrt() * half),
    ];
    discretise(
        poles,
        sample_period_s,
        discretisation,
        Argument::TimeConstant,
        DesignMethod::ThirdOrderButterworth,
    )
}

/// The smallest and largest `K` searched by [`third_order_from_overshoot`].
const POLE_RATIO_SEARCH: (f64, f64) = (0.05, 1e4);

/// The 3rd-order ATO from a target overshoot of the (linear, continuous) step response and
/// a target 2 % settling time, within the pole family `-K/T`, `(-1 +- j psi)/T` with `psi`
/// fixed (the paper uses `psi = 3 pi / 2`).
///
/// The overshoot depends on `K` and `psi` only (`T` scales time). The search: the overshoot
/// of the continuous step response (computed exactly by the matrix exponential) is
/// tabulated over `K` on a logarithmic grid from 0.05 to 10^4; the first bracket in which it
/// crosses the target (from above: small `K` gives large overshoot) is refined by bisection
/// to a relative 1e-10. Then `T` is the target settling time divided by the settling time
/// of the loop with `T = 1`. [`Error::NoSolution`] names the overshoot if no `K` in the range
/// gives it.
///
/// ```
/// use angletrack::{Discretisation, third_order_from_overshoot};
/// use std::f64::consts::PI;
/// // The paper's 10 % with psi = 3 pi / 2 gives K = 39.04.
/// let design = third_order_from_overshoot(0.10, 0.05, 1.5 * PI, 1e-5, Discretisation::PoleMatching)?;
/// let k_over_t = -design.continuous_poles.iter().map(|p| p.re).fold(0.0, f64::min);
/// let one_over_t = -design.continuous_poles.iter().map(|p| p.re).fold(f64::MIN, f64::max);
/// assert!((k_over_t / one_over_t - 39.04).abs() < 0.05);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn third_order_from_overshoot(
    overshoot: f64,
    settling_time_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: Discretisation,
) -> Result<Design<3>, Error> {
    let target = positive(overshoot, Argument::Overshoot)?;
    let settling = positive(settling_time_s, Argument::SettlingTime)?;
    check_pole_family(1.0, pole_frequency_ratio)?;
    positive(sample_period_s, Argument::SamplePeriod)?;
    let psi = pole_frequency_ratio;
    let overshoot_at = |k: f64| -> f64 {
        continuous_step(&linalg::monic_from_roots(&third_order_poles(k, 1.0, psi))).overshoot
    };
    let (lo, hi) = POLE_RATIO_SEARCH;
    let steps = 60;
    let ratio = (hi / lo).powf(1.0 / steps as f64);
    let mut bracket = None;
    let mut k_prev = lo;
    let mut o_prev = overshoot_at(lo);
    for i in 1..=steps {
        let k = lo * ratio.powi(i);
        let o = overshoot_at(k);
        if (o_prev - target) * (o - target) <= 0.0 {
            bracket = Some((k_prev, k, o_prev > target));
            break;
        }
        k_prev = k;
        o_prev = o;
    }
    let (mut a, mut b, decreasing) = bracket.ok_or(Error::NoSolution(Argument::Overshoot))?;
    while (b - a) > 1e-10 * b {
        let mid = 0.5 * (a + b);
        if (overshoot_at(mid) > target) == decreasing {
            a = mid;
        } else {
            b = mid;
        }
    }
    let k = 0.5 * (a + b);
    let unit = continuous_step(&linalg::monic_from_roots(&third_order_poles(k, 1.0, psi)));
    let t = settling / unit.settling_time_s;
    if !t.is_finite() || t <= 0.0 {
        return Err(Error::NoSolution(Argument::SettlingTime));
    }
    discretise(
        third_order_poles(k, t, psi),
        sample_period_s,
        discretisation,
        Argument::SettlingTime,
        DesignMethod::ThirdOrderOvershoot,
    )
}

/// Overshoot and settling time of a step response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepResponse {
    /// The overshoot, as a fraction of the step (0.1 for 10 %); 0 without overshoot.
    pub overshoot: f64,
    /// The 2 % settling time (s): from the step to the last time the response is outside
    /// 2 % of the step around its final value.
    pub settling_time_s: f64,
}

impl StepResponse {
    /// Overshoot and settling of `response` (one value per sample, the step at sample 0)
    /// toward `target` from `start`, with settling band `band` (a fraction of the step)
    /// and sample period `period_s`.
    pub(crate) fn from_samples(
        response: impl Iterator<Item = f64>,
        start: f64,
        target: f64,
        band: f64,
        period_s: f64,
    ) -> Self {
        let step = target - start;
        let mut peak: f64 = 0.0;
        let mut last_outside = None;
        for (k, y) in response.enumerate() {
            let excess = (y - target) / step;
            peak = peak.max(excess);
            if !(excess.abs() <= band) {
                last_outside = Some(k);
            }
        }
        StepResponse {
            overshoot: peak,
            settling_time_s: last_outside.map_or(0.0, |k| (k + 1) as f64 * period_s),
        }
    }
}

/// The step response of the continuous loop `(c_{N-1} s^{N-1} + .. + c_0) / (s^N + .. + c_0)`
/// (the ATO's angle transfer function), sampled exactly (matrix exponential of the loop
/// with the constant input appended to the state) on a grid fine enough for the overshoot
/// (1/40 of the fastest pole's time constant) and long enough to settle.
pub(crate) fn continuous_step(c: &[f64]) -> StepResponse {
    let n = c.len();
    let poles = linalg::roots(c);
    let fastest = poles.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let slowest = poles.iter().map(|p| -p.re).fold(f64::INFINITY, f64::min);
    let fastest_oscillation = poles.iter().map(|p| p.im.abs()).fold(0.0, f64::max);
    let h = (1.0 / (40.0 * fastest)).min(0.02 / fastest_oscillation.max(1e-300));
    let horizon = 16.0 / slowest;
    let steps = ((horizon / h).ceil() as usize).clamp(100, 1_000_000);
    let h = horizon / steps as f64;
    // State (x, u): dx = S x + k (u - x1), du = 0, with k the continuous gains; over one
    // step of h, x <- Phi x + Gamma u with Phi, Gamma blocks of exp(M h).
    let m = DMatrix::from_fn(n + 1, n + 1, |i, j| {
        let k_i = if i < n { c[n - 1 - i] } else { 0.0 };
        let mut v = 0.0;
        if i < n && j == i + 1 && j < n {
            v += 1.0;
        }
        if i < n && j == 0 {
            v -= k_i;
        }
        if i < n && j == n {
            v += k_i;
        }
        v
    });
    let step_matrix = (m * h).exp();
    let phi = step_matrix.view((0, 0), (n, n)).into_owned();
    let gamma: Vec<f64> = (0..n).map(|i| step_matrix[(i, n)]).collect();
    let response = core::iter::once(0.0).chain(linalg::affine_response(phi, gamma, steps));
    StepResponse::from_samples(response, 0.0, 1.0, 0.02, h)
}

/// The state transition `A` of the Kalman model and its process-noise input `G`.
fn kalman_model() -> (DMatrix<f64>, DMatrix<f64>) {
    let g = linalg::taylor_remainder(3);
    (linalg::transition(3), &g * g.transpose())
}

/// The time-invariant Kalman ATO (3rd order): the steady-state gain of the Kalman filter of
/// the triple integrator `X[k+1] = A3 X[k] + G v[k]` on the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`, `G = (1/6, 1/2, 1)`, `var(v) = q` (`v = Ts^3 beta`, the
/// scaled jerk), measured through the phase detector with noise variance `r` per channel.
///
/// Solves the discrete algebraic Riccati equation for the predicted covariance `P` (nalgebra,
/// doubling algorithm) and returns `K_lin = P e1 / (r + P11)`; the gains depend on `q / r`
/// only. The ratio must lie in `[1e-30, 1e6]`.
///
/// ```
/// use angletrack::kalman;
/// let design = kalman(1e-9, 1.0, 1e-4)?;
/// let [l1, l2, l3] = design.gains.gains();
/// assert!((l1 - 0.0613).abs() < 1e-3 && (l2 - 0.00194).abs() < 1e-5 && (l3 - 3.06e-5).abs() < 1e-7);
/// let floor = design.kalman.unwrap().angle_floor_rad();
/// assert!(floor > 0.0 && floor < 1.0);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman(
    process_noise_q: f64,
    measurement_noise_r: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let q = positive(process_noise_q, Argument::ProcessNoise)?;
    let r = positive(measurement_noise_r, Argument::MeasurementNoise)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let ratio = q / r;
    if !(1e-30..=1e6).contains(&ratio) {
        return Err(Error::OutOfRange {
            argument: Argument::ProcessNoise,
            expected: "1e-30 <= q / r <= 1e6",
        });
    }
    // Solve for r = 1 (well scaled), then scale the covariances by r.
    let (a, gg) = kalman_model();
    let h = linalg::e1(3);
    let p = linalg::discrete_riccati(&a, &h, &(gg * ratio), 1.0)
        .ok_or(Error::NoSolution(Argument::ProcessNoise))?;
    let denominator = 1.0 + p[(0, 0)];
    let l = [
        p[(0, 0)] / denominator,
        p[(1, 0)] / denominator,
        p[(2, 0)] / denominator,
    ];
    let filtered = &p - (p.column(0) * p.row(0)) / denominator;
    let to_array = |m: &DMatrix<f64>| -> [[f64; 3]; 3] {
        core::array::from_fn(|i| core::array::from_fn(|j| m[(i, j)] * r))
    };
    let gains = Gains::new(l, ts)?;
    Ok(Design {
        gains,
        method: DesignMethod::Kalman,
        discretisation: None,
        continuous_poles: Vec::new(),
        continuous_gains: None,
        kalman: Some(KalmanSolution {
            process_noise_q: q,
            measurement_noise_r: r,
            predicted_covariance: to_array(&p),
            covariance: to_array(&filtered),
        }),
    })
}

/// The Kalman ATO from physical units: the jerk as a white sequence of standard deviation
/// `jerk_std_rad_s3` (rad/s^3, constant over each sample), the sensor noise standard
/// deviation `sensor_noise_std` per channel (amplitude 1), sample period `Ts`:
/// `q = (Ts^3 jerk_std)^2`, `r = sensor_noise_std^2`.
///
/// ```
/// use angletrack::kalman_from_jerk_std;
/// let design = kalman_from_jerk_std(1e5, 0.01, 1e-4)?;
/// let solution = design.kalman.unwrap();
/// assert!((solution.process_noise_q / 1e-14 - 1.0).abs() < 1e-12); // (Ts^3 jerk_std)^2
/// assert!((solution.measurement_noise_r / 1e-4 - 1.0).abs() < 1e-12);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman_from_jerk_std(
    jerk_std_rad_s3: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let jerk = positive(jerk_std_rad_s3, Argument::JerkStd)?;
    let noise = positive(sensor_noise_std, Argument::SensorNoiseStd)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let scaled = jerk * ts * ts * ts;
    kalman(scaled * scaled, noise * noise, ts).map_err(|e| rename(e, Argument::JerkStd))
}

/// The Kalman ATO from the power spectral density `jerk_density_rad2_s5` (rad^2/s^5) of a
/// continuous white jerk: over one sample it integrates to a jerk of variance `S / Ts`, so
/// `q = S Ts^5`; `r = sensor_noise_std^2` per channel (amplitude 1).
///
/// ```
/// use angletrack::kalman_from_jerk_density;
/// let design = kalman_from_jerk_density(1e6, 0.01, 1e-4)?;
/// assert!((design.kalman.unwrap().process_noise_q / 1e-14 - 1.0).abs() < 1e-12); // S Ts^5
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman_from_jerk_density(
    jerk_density_rad2_s5: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let density = positive(jerk_density_rad2_s5, Argument::JerkDensity)?;
    let noise = positive(sensor_noise_std, Argument::SensorNoiseStd)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    kalman(density * ts.powi(5), noise * noise, ts).map_err(|e| rename(e, Argument::JerkDensity))
}

/// Names the caller's arguments instead of `q` and `r` in an error of [`kalman`].
fn rename(e: Error, argument: Argument) -> Error {
    match e {
        Error::NotPositive(Argument::MeasurementNoise) => {
            Error::NotPositive(Argument::SensorNoiseStd)
        }
        Error::NotPositive(Argument::ProcessNoise) => Error::NotPositive(argument),
        Error::NotFinite(Argument::ProcessNoise) => Error::NotFinite(argument),
        Error::OutOfRange {
            argument: Argument::ProcessNoise,
            expected,
        } => Error::OutOfRange { argument, expected },
        Error::NoSolution(Argument::ProcessNoise) => Error::NoSolution(argument),
        other => other,
    }
}
