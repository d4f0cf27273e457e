//! Discrete gains of the predictor-corrector recursion, checked once at construction.

use core::fmt;
use core::marker::PhantomData;

use crate::monitor::{CheckedThresholds, FaultThresholds};
use crate::real::Real;
use crate::sincos::SinCos;

/// The orders the recursion supports: 2 (type II loop) and 3 (type III loop).
///
/// Implemented for [`Order<2>`] and [`Order<3>`] only; an observer of any other order does
/// not compile.
pub trait SupportedOrder: sealed::Sealed {}

/// Marker for the observer order `N` (the number of states: angle, speed, acceleration).
#[derive(Debug, Clone, Copy)]
pub struct Order<const N: usize>;

impl SupportedOrder for Order<2> {}
impl SupportedOrder for Order<3> {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Order<2> {}
    impl Sealed for super::Order<3> {}
}

/// A parameter of an observer's configuration, named in [`ConfigError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Parameter {
    /// The sample period `Ts` (s).
    SamplePeriod,
    /// The angle gain `l1` (dimensionless).
    AngleGain,
    /// The speed gain `l2` (dimensionless, scaled by `Ts`).
    SpeedGain,
    /// The acceleration gain `l3` (dimensionless, scaled by `Ts^2`).
    AccelerationGain,
    /// The input amplitude above which a sample is rejected as absurd.
    MaxInputAmplitude,
    /// The amplitude below which loss of signal is flagged.
    LossOfSignalThreshold,
    /// The amplitude above which degradation of signal is flagged.
    DegradationHighThreshold,
    /// The amplitude below which degradation of signal is flagged.
    DegradationLowThreshold,
    /// The filtered phase-detector error above which loss of tracking is flagged.
    LossOfTrackingThreshold,
    /// The smoothing factor of the diagnostics' first-order filters.
    FilterFactor,
    /// The in-phase component below which a false lock is declared.
    FalseLockThreshold,
    /// The nominal amplitude of the input signals.
    NominalAmplitude,
    /// The largest trackable speed (rad/s) of the loss-of-tracking check.
    MaxSpeed,
}

impl Parameter {
    /// The parameter's name as written in the docs and the Python API.
    pub const fn name(self) -> &'static str {
        match self {
            Parameter::SamplePeriod => "sample_period",
            Parameter::AngleGain => "angle_gain (l1)",
            Parameter::SpeedGain => "speed_gain (l2)",
            Parameter::AccelerationGain => "acceleration_gain (l3)",
            Parameter::MaxInputAmplitude => "max_input_amplitude",
            Parameter::LossOfSignalThreshold => "loss_of_signal_threshold",
            Parameter::DegradationHighThreshold => "degradation_high_threshold",
            Parameter::DegradationLowThreshold => "degradation_low_threshold",
            Parameter::LossOfTrackingThreshold => "loss_of_tracking_threshold",
            Parameter::FilterFactor => "filter_factor",
            Parameter::FalseLockThreshold => "false_lock_threshold",
            Parameter::NominalAmplitude => "nominal_amplitude",
            Parameter::MaxSpeed => "max_speed",
        }
    }

    /// The parameter naming gain `l[index]` (0: angle, 1: speed, 2: acceleration).
    pub const fn gain(index: usize) -> Parameter {
        match index {
            0 => Parameter::AngleGain,
            1 => Parameter::SpeedGain,
            _ => Parameter::AccelerationGain,
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a configuration was refused. Returned once, at construction; the per-sample update
/// never fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ConfigError {
    /// The parameter is NaN or infinite.
    NotFinite(Parameter),
    /// The parameter must be strictly positive.
    NotPositive(Parameter),
    /// The parameter is outside its allowed range (see the parameter's documentation).
    OutOfRange(Parameter),
    /// The gains put a pole of the discrete loop `(I - L e1^T) A` on or outside the unit
    /// circle; the named gain is the one whose stability condition fails.
    Unstable {
        /// The gain whose stability condition fails.
        parameter: Parameter,
        /// The condition, in the gains `l1, l2, l3`, that must hold.
        condition: &'static str,
    },
}

impl ConfigError {
    /// The parameter the error names.
    pub const fn parameter(&self) -> Parameter {
        match *self {
            ConfigError::NotFinite(p)
            | ConfigError::NotPositive(p)
            | ConfigError::OutOfRange(p) => p,
            ConfigError::Unstable { parameter, .. } => parameter,
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigError::NotFinite(p) => write!(f, "{p} must be finite"),
            ConfigError::NotPositive(p) => write!(f, "{p} must be positive"),
            ConfigError::OutOfRange(p) => write!(f, "{p} is out of its allowed range"),
            ConfigError::Unstable {
                parameter,
                condition,
            } => write!(
                f,
                "{parameter} puts the discrete loop outside its stability region: {condition} must hold"
            ),
        }
    }
}

impl core::error::Error for ConfigError {}

/// Checks that a parameter is finite and strictly positive.
pub(crate) fn check_positive<T: Real>(value: T, parameter: Parameter) -> Result<T, ConfigError> {
    if !value.is_finite() {
        Err(ConfigError::NotFinite(parameter))
    } else if !(value > T::ZERO) {
        Err(ConfigError::NotPositive(parameter))
    } else {
        Ok(value)
    }
}

/// The prediction `A x` of the recursion: a Taylor step of the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`, `A[i][j] = 1/(j-i)!` for `j >= i`.
///
/// Each row adds left to right, `(x0 + x1) + x2/2`: in the loop every state is corrected at
/// the same time, so `x0 + x1` runs while `x2/2` is multiplied and the chain from one
/// sample's phase error to the next predicted angle is two additions after the correction
/// (`x0 + (x1 + x2/2)` would be three).
#[inline(always)]
pub(crate) fn predict<T: Real, const N: usize>(x: &[T; N]) -> [T; N] {
    let mut p = *x;
    let mut i = 0;
    while i < N {
        let mut sum = x[i];
        let mut j = i + 1;
        while j < N {
            sum += if j - i == 1 { x[j] } else { x[j] * T::HALF };
            j += 1;
        }
        p[i] = sum;
        i += 1;
    }
    p
}

/// Coefficients `c[k]` of the closed-loop characteristic polynomial in `s = z - 1`,
/// `s^N + c[N-1] s^(N-1) + ... + c[0]`, for gains `l`.
///
/// With `D = A - I` (nilpotent) and the rank-one correction, `det(s I - D + A L e1^T)`
/// `= s^N + sum_k s^(N-1-k) e1^T D^k A L`; the coefficients are linear in the gains.
pub(crate) fn characteristic_polynomial_in_s<T: Real, const N: usize>(l: &[T; N]) -> [T; N] {
    let mut v = predict(l);
    let mut c = [T::ZERO; N];
    let mut k = 0;
    while k < N {
        c[N - 1 - k] = v[0];
        let next = predict(&v);
        let mut i = 0;
        while i < N {
            v[i] = next[i] - v[i];
            i += 1;
        }
        k += 1;
    }
    c
}

/// Checks that every pole of the discrete loop is strictly inside the unit circle.
///
/// The bilinear map `z = (1 + w) / (1 - w)` (so `s = 2 w / (1 - w)`) sends the unit disc to
/// the left half plane; the Routh-Hurwitz (Lienard-Chipart) conditions on the mapped
/// polynomial are then polynomial in the gains, with no cancellation for small gains
/// (high sample rates), so they hold in `f32` as well as in `f64`:
///
/// * order 2: `l1 > 0`, `l2 > 0`, `2 l1 + l2 < 4`;
/// * order 3: `l3 > 0`, `l2 > 0`, `4 l1 > l3`, `4 l1 + 2 l2 < 8`,
///   `2 l2 (4 l1 - l3) > l3 (8 - 4 l1 - 2 l2)`.
pub(crate) fn check_stability<T: Real, const N: usize>(l: &[T; N]) -> Result<(), ConfigError> {
    let c = characteristic_polynomial_in_s(l);
    // w-polynomial: sum_k c_k (2w)^k (1-w)^(N-k), with c_N = 1; coefficients in w.
    let mut w = [T::ZERO; 4];
    let mut k = 0;
    while k <= N {
        let ck = if k == N { T::ONE } else { c[k] };
        // (2w)^k (1-w)^(N-k) = 2^k sum_j binom(N-k, j) (-1)^j w^(k+j)
        let mut scale = ck;
        let mut p = 0;
        while p < k {
            scale *= T::TWO;
            p += 1;
        }
        let m = N - k;
        let mut binom = T::ONE;
        let mut j = 0;
        while j <= m {
            let term = if j % 2 == 0 {
                scale * binom
            } else {
                -(scale * binom)
            };
            if k + j < 4 {
                w[k + j] += term;
            }
            binom = binom * from_usize::<T>(m - j) / from_usize::<T>(j + 1);
            j += 1;
        }
        k += 1;
    }
    let conditions: &[(Parameter, &str)] = if N == 2 {
        &[
            (Parameter::SpeedGain, "l2 > 0"),
            (Parameter::AngleGain, "l1 > 0"),
            (Parameter::AngleGain, "2 l1 + l2 < 4"),
        ]
    } else {
        &[
            (Parameter::AccelerationGain, "l3 > 0"),
            (Parameter::SpeedGain, "l2 > 0"),
            (Parameter::AngleGain, "4 l1 > l3"),
            (Parameter::AngleGain, "4 l1 + 2 l2 < 8"),
        ]
    };
    // All coefficients of the w-polynomial positive (w[0] .. w[N]).
    for (i, (parameter, condition)) in conditions.iter().enumerate() {
        if !(w[i] > T::ZERO) {
            return Err(ConfigError::Unstable {
                parameter: *parameter,
                condition,
            });
        }
    }
    // Cubic: the Hurwitz determinant w2 w1 - w3 w0 > 0.
    if N == 3 && !(w[2] * w[1] > w[3] * w[0]) {
        return Err(ConfigError::Unstable {
            parameter: Parameter::AccelerationGain,
            condition: "2 l2 (4 l1 - l3) > l3 (8 - 4 l1 - 2 l2)",
        });
    }
    Ok(())
}

#[inline(always)]
fn from_usize<T: Real>(n: usize) -> T {
    // n <= 3 here: exact in both types.
    T::from_f32(n as u8 as f32)
}

/// The immutable, checked configuration of an angle tracking observer of order `N`:
/// the discrete gains `L = (l1, l2[, l3])` of the recursion on the scaled state
/// `(theta, Ts Omega[, Ts^2 alpha])`, the sample period, and the sin/cos implementation `S`
/// of the phase detector.
///
/// `Copy`: one configuration can drive any number of [`ObserverState`](crate::ObserverState)s
/// (channels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains<T: Real, const N: usize, S = <T as Real>::DefaultSinCos>
where
    Order<N>: SupportedOrder,
{
    pub(crate) l: [T; N],
    pub(crate) sample_period: T,
    pub(crate) sample_rate: T,
    pub(crate) sample_rate_squared: T,
    /// `(A L)[0] = l1 + l2 + l3/2`: how much one sample's phase error moves the next
    /// sample's predicted angle.
    pub(crate) next_angle_gain: T,
    pub(crate) thresholds: CheckedThresholds<T>,
    pub(crate) sin_cos: PhantomData<S>,
}

impl<T: Real, const N: usize, S: SinCos<T>> Gains<T, N, S>
where
    Order<N>: SupportedOrder,
{
    /// Checks and wraps discrete gains `l` (dimensionless, for the scaled state) and the
    /// sample period `sample_period` (s).
    ///
    /// Refuses non-finite values, a non-positive sample period or one outside
    /// [1 ps, 1000 s], and gains outside the stability region of the discrete loop (see
    /// [`ConfigError`]).
    ///
    /// ```
    /// use angletrack_core::{Gains, ConfigError, Parameter};
    /// // A 3rd-order loop at 20 kHz (gains from `angletrack design`).
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 50e-6)?;
    /// assert_eq!(gains.sample_period(), 50e-6);
    /// // l3 <= 0 is outside the stability region:
    /// let err = Gains::<f32, 3>::new([0.3, 0.04, -0.002], 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), ConfigError>(())
    /// ```
    pub fn new(l: [T; N], sample_period: T) -> Result<Self, ConfigError> {
        let sample_period = check_positive(sample_period, Parameter::SamplePeriod)?;
        // A physical range (1 ps to 1000 s): speed and acceleration are the scaled state
        // times 1/Ts and 1/Ts^2, which must not overflow for any state the loop can reach.
        if !(sample_period >= T::from_f32(1e-12) && sample_period <= T::from_f32(1e3)) {
            return Err(ConfigError::OutOfRange(Parameter::SamplePeriod));
        }
        let sample_rate = T::ONE / sample_period;
        for (i, gain) in l.iter().enumerate() {
            if !gain.is_finite() {
                return Err(ConfigError::NotFinite(Parameter::gain(i)));
            }
        }
        check_stability(&l)?;
        Ok(Self {
            l,
            sample_period,
            sample_rate,
            sample_rate_squared: sample_rate * sample_rate,
            next_angle_gain: predict(&l)[0],
            thresholds: FaultThresholds::default().check(sample_period)?,
            sin_cos: PhantomData,
        })
    }

    /// The same gains with other diagnostics thresholds (checked: see
    /// [`FaultThresholds`]); the defaults assume a nominal amplitude of 1.
    ///
    /// ```
    /// use angletrack_core::{FaultThresholds, Gains, Parameter};
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?
    ///     .with_fault_thresholds(FaultThresholds::for_amplitude(2048.0))?;
    /// assert_eq!(gains.fault_thresholds().nominal_amplitude, 2048.0);
    /// let bad = FaultThresholds { filter_factor: 1.5, ..FaultThresholds::default() };
    /// let err = gains.with_fault_thresholds(bad).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::FilterFactor);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_fault_thresholds(
        self,
        thresholds: FaultThresholds<T>,
    ) -> Result<Self, ConfigError> {
        Ok(Self {
            thresholds: thresholds.check(self.sample_period)?,
            ..self
        })
    }

    /// The diagnostics thresholds.
    pub fn fault_thresholds(&self) -> FaultThresholds<T> {
        self.thresholds.thresholds
    }

    /// Gains that give the discrete loop `(I - L e1^T) A` a chosen characteristic polynomial,
    /// written in `s = z - 1` as `s^N + c[N-1] s^(N-1) + ... + c[0]` (for poles `z_i`,
    /// the coefficients of `prod (s - (z_i - 1))`). This is how pole matching
    /// (`z_i = exp(s_i Ts)`) reaches the recursion; writing the polynomial in `z - 1` keeps
    /// it accurate at high sample rates, where every `z_i` is close to 1.
    ///
    /// The map from gains to coefficients is linear and triangular; this solves it and then
    /// checks the result as [`Gains::new`] does.
    ///
    /// ```
    /// use angletrack_core::Gains;
    /// // Triple pole at z = 0.9: (s + 0.1)^3 = s^3 + 0.3 s^2 + 0.03 s + 0.001.
    /// let gains = Gains::<f64, 3>::from_loop_polynomial([0.001, 0.03, 0.3], 1e-4)?;
    /// let [l1, l2, l3] = gains.gains();
    /// assert!((l3 - 0.001).abs() < 1e-15 && (l2 - 0.0285).abs() < 1e-15);
    /// assert!((l1 - 0.271).abs() < 1e-15);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_loop_polynomial(c: [T; N], sample_period: T) -> Result<Self, ConfigError> {
        let mut columns = [[T::ZERO; N]; N];
        let mut j = 0;
        while j < N {
            let mut unit = [T::ZERO; N];
            unit[j] = T::ONE;
            columns[j] = characteristic_polynomial_in_s(&unit);
            j += 1;
        }
        // c[N-1-k] depends on l[k..N] only, with a unit coefficient on l[k].
        let mut l = [T::ZERO; N];
        let mut k = N;
        while k > 0 {
            k -= 1;
            let mut rest = c[N - 1 - k];
            let mut j = k + 1;
            while j < N {
                rest -= columns[j][N - 1 - k] * l[j];
                j += 1;
            }
            l[k] = rest / columns[k][N - 1 - k];
        }
        Self::new(l, sample_period)
    }

    /// The coefficients `c` of the loop's characteristic polynomial in `s = z - 1`
    /// (`s^N + c[N-1] s^(N-1) + ... + c[0]`): the inverse of [`Gains::from_loop_polynomial`].
    pub fn loop_polynomial(&self) -> [T; N] {
        characteristic_polynomial_in_s(&self.l)
    }

    /// The same gains with another sin/cos implementation in the phase detector.
    ///
    /// ```
    /// use angletrack_core::{Gains, Exact};
    /// let fast = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let exact: Gains<f32, 2, Exact> = fast.with_sin_cos();
    /// assert_eq!(exact.gains(), fast.gains());
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_sin_cos<S2: SinCos<T>>(self) -> Gains<T, N, S2> {
        Gains {
            l: self.l,
            sample_period: self.sample_period,
            sample_rate: self.sample_rate,
            sample_rate_squared: self.sample_rate_squared,
            next_angle_gain: self.next_angle_gain,
            thresholds: self.thresholds,
            sin_cos: PhantomData,
        }
    }

    /// The discrete gains `(l1, l2[, l3])`.
    pub fn gains(&self) -> [T; N] {
        self.l
    }

    /// The sample period `Ts` (s).
    pub fn sample_period(&self) -> T {
        self.sample_period
    }

    /// The observer order `N` (2 or 3).
    pub const fn order(&self) -> usize {
        N
    }
}
