//! What a design function returns: the discrete gains with what they were designed from,
//! and their conversion to the float type of the firmware.

use angletrack_core::{Gains, Order, Real, SupportedOrder};
use nalgebra::Complex;

use super::{Discretisation, KalmanSolution};
use crate::analysis::DesignReport;
use crate::error::Error;

/// Which design rule produced a gain set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DesignMethod {
    /// 2nd order from a tolerated error at an acceleration and a damping.
    SecondOrderTrackingError,
    /// 2nd order from a tolerated error at an acceleration and an overshoot, both met by
    /// the sampled loop itself.
    SecondOrderSampledTrackingError,
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
            DesignMethod::SecondOrderSampledTrackingError => {
                "2nd order, tracking error and overshoot of the sampled loop"
            }
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

/// A designed gain set (in `f64`) with what it was designed from.
///
/// Convert to the float type of the firmware with [`Design::to_gains`]; analyse with
/// [`DesignReport::new`](crate::DesignReport::new).
#[derive(Debug, Clone, PartialEq)]
pub struct Design<const N: usize> {
    /// The discrete gains, checked by the core.
    pub gains: Gains<f64, N>,
    /// The design rule.
    pub method: DesignMethod,
    /// The mapping used for a continuous design; `None` for Kalman and given gains.
    pub discretisation: Option<Discretisation>,
    /// The continuous closed-loop poles (rad/s) of a continuous design; empty otherwise.
    pub continuous_poles: Vec<Complex<f64>>,
    /// The continuous gains `(k_a, k_b[, k_c])` of a continuous design, in the order of the
    /// discrete gains `(l1, l2[, l3])`: the gain of the angle first (`l_i ~ k_i Ts^i` for a
    /// loop much slower than its sample rate). The loop polynomial they form, lowest power
    /// first as everywhere, is [`Design::continuous_loop_polynomial`].
    pub continuous_gains: Option<[f64; N]>,
    /// The steady-state Riccati solution of a Kalman design.
    pub kalman: Option<KalmanSolution>,
}

impl<const N: usize> Design<N> {
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
    pub fn to_gains<T: Real>(&self) -> Result<Gains<T, N>, Error>
    where
        Order<N>: SupportedOrder,
    {
        convert_gains(&self.gains)
    }

    /// The sample period (s).
    pub fn sample_period(&self) -> f64 {
        self.gains.sample_period()
    }

    /// The coefficients `(c0, .., c_{N-1})` of the continuous loop polynomial
    /// `s^N + c_{N-1} s^{N-1} + .. + c0` of a continuous design, lowest power first as
    /// [`Gains::loop_polynomial`]: the continuous gains in reverse order (`c0 = k_b` at
    /// order 2, `c0 = k_c` at order 3).
    ///
    /// ```
    /// use angletrack::{Discretisation, second_order_butterworth};
    /// let design = second_order_butterworth(1e-2, 1e-4, Discretisation::PoleMatching)?;
    /// let [k_a, k_b] = design.continuous_gains.unwrap();
    /// assert_eq!(design.continuous_loop_polynomial(), Some(vec![k_b, k_a]));
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn continuous_loop_polynomial(&self) -> Option<Vec<f64>> {
        self.continuous_gains
            .map(|k| k.iter().rev().copied().collect())
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
    pub fn report(&self, sensor_noise_std: f64) -> Result<DesignReport, Error> {
        match self {
            AnyDesign::Second(d) => DesignReport::new(d, sensor_noise_std),
            AnyDesign::Third(d) => DesignReport::new(d, sensor_noise_std),
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
