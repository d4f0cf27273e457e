//! [`AnyChannel`] and [`AnyBatch`]: the float standard chain of one observer
//! ([`TrackerChannel`]) and a batch of observers ([`ChannelBatch`]) in the float type,
//! order and sin/cos a caller chooses at run time, built once from checked float64 gains
//! ([`AnyGains`]). What the Python `Observer`, `track` and `ObserverBatch` hold: the
//! choice of the concrete types is made here, once, and a door reaches the typed value
//! through [`with_any_channel!`](crate::with_any_channel) only to move samples in and out.

use angletrack_core::{
    Exact, Fast, Faults, Gains, ObserverState, Order, Real, SinCos, SupportedOrder,
};

use crate::export::FloatType;
use crate::tracker_file::SinCosKind;
use crate::{
    AnyGains, ChannelBatch, ChannelError, ChannelOptions, ChannelStatus, Error,
    OnlineCalibrationChoice, TrackerChannel, convert_gains,
};

/// Declares `$name`, one variant of `$inner` per float type, order and sin/cos.
macro_rules! typed_enum {
    ($(#[$doc:meta])* $name:ident($inner:ident)) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub enum $name {
            /// `f32`, 2nd order, the fast sin/cos.
            F32Fast2($inner<f32, 2, Fast>),
            /// `f32`, 2nd order, the exact sin/cos.
            F32Exact2($inner<f32, 2, Exact>),
            /// `f32`, 3rd order, the fast sin/cos.
            F32Fast3($inner<f32, 3, Fast>),
            /// `f32`, 3rd order, the exact sin/cos.
            F32Exact3($inner<f32, 3, Exact>),
            /// `f64`, 2nd order, the fast sin/cos.
            F64Fast2($inner<f64, 2, Fast>),
            /// `f64`, 2nd order, the exact sin/cos.
            F64Exact2($inner<f64, 2, Exact>),
            /// `f64`, 3rd order, the fast sin/cos.
            F64Fast3($inner<f64, 3, Fast>),
            /// `f64`, 3rd order, the exact sin/cos.
            F64Exact3($inner<f64, 3, Exact>),
        }
    };
}

typed_enum! {
    /// A [`TrackerChannel`] of the float type, order and sin/cos chosen at run time.
    ///
    /// ```
    /// use angletrack::{AnyChannel, AnyGains, ChannelOptions, export::FloatType};
    /// use angletrack::tracker_file::SinCosKind;
    /// let gains = AnyGains::new(&[0.2, 0.02], 1e-4)?;
    /// let options = ChannelOptions::default();
    /// let mut channel = AnyChannel::new(&gains, FloatType::F32, SinCosKind::Default, &options)??;
    /// assert!(matches!(channel, AnyChannel::F32Fast2(_)));
    /// channel.initialise(0.0, 1.0)?;
    /// assert!(channel.status().initialised);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    AnyChannel(TrackerChannel)
}

typed_enum! {
    /// A [`ChannelBatch`] of the float type, order and sin/cos chosen at run time.
    ///
    /// ```
    /// use angletrack::{AnyBatch, AnyGains, export::FloatType};
    /// use angletrack::tracker_file::SinCosKind;
    /// let gains = AnyGains::new(&[0.06, 0.0019, 3e-5], 1e-4)?;
    /// let batch = AnyBatch::new(&gains, FloatType::F64, SinCosKind::Fast, 10)?;
    /// assert!(matches!(batch, AnyBatch::F64Fast3(_)));
    /// assert!(AnyBatch::new(&gains, FloatType::F64, SinCosKind::Fast, 0).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    AnyBatch(ChannelBatch)
}

/// Runs `$body` with `$c` bound to the concrete value inside an [`AnyChannel`] or an
/// [`AnyBatch`] (`$kind`: the enum's name).
#[macro_export]
macro_rules! with_any_channel {
    ($kind:ident, $value:expr, $c:ident => $body:expr) => {
        match $value {
            $crate::$kind::F32Fast2($c) => $body,
            $crate::$kind::F32Exact2($c) => $body,
            $crate::$kind::F32Fast3($c) => $body,
            $crate::$kind::F32Exact3($c) => $body,
            $crate::$kind::F64Fast2($c) => $body,
            $crate::$kind::F64Exact2($c) => $body,
            $crate::$kind::F64Fast3($c) => $body,
            $crate::$kind::F64Exact3($c) => $body,
        }
    };
}

/// `gains` in float type `T` (checked again there: rounding to `f32` can leave the
/// stability region at its edge) with the sin/cos `S`.
fn typed<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<f64, N>,
) -> Result<Gains<T, N, S>, Error>
where
    Order<N>: SupportedOrder,
{
    Ok(convert_gains::<T, N>(gains)?.with_sin_cos::<S>())
}

/// `$name`'s variant of `gains` in `float` with `sin_cos`, `$make` making it of the typed
/// gains `$g`.
macro_rules! of_typed_gains {
    ($name:ident, ($gains:expr, $float:expr, $sin_cos:expr), |$g:ident| $make:expr) => {{
        let exact = $sin_cos.is_exact($float == FloatType::F64);
        match ($gains, $float, exact) {
            (AnyGains::Second(g), FloatType::F32, false) => {
                let $g = typed::<f32, 2, Fast>(g)?;
                $make.map($name::F32Fast2)
            }
            (AnyGains::Second(g), FloatType::F32, true) => {
                let $g = typed::<f32, 2, Exact>(g)?;
                $make.map($name::F32Exact2)
            }
            (AnyGains::Third(g), FloatType::F32, false) => {
                let $g = typed::<f32, 3, Fast>(g)?;
                $make.map($name::F32Fast3)
            }
            (AnyGains::Third(g), FloatType::F32, true) => {
                let $g = typed::<f32, 3, Exact>(g)?;
                $make.map($name::F32Exact3)
            }
            (AnyGains::Second(g), FloatType::F64, false) => {
                let $g = typed::<f64, 2, Fast>(g)?;
                $make.map($name::F64Fast2)
            }
            (AnyGains::Second(g), FloatType::F64, true) => {
                let $g = typed::<f64, 2, Exact>(g)?;
                $make.map($name::F64Exact2)
            }
            (AnyGains::Third(g), FloatType::F64, false) => {
                let $g = typed::<f64, 3, Fast>(g)?;
                $make.map($name::F64Fast3)
            }
            (AnyGains::Third(g), FloatType::F64, true) => {
                let $g = typed::<f64, 3, Exact>(g)?;
                $make.map($name::F64Exact3)
            }
        }
    }};
}

impl AnyChannel {
    /// The chain of `gains` in `float` with `sin_cos` and `options`. The outer error: the
    /// gains refused in `float` ([`convert_gains`]); the inner: the channel refused
    /// ([`TrackerChannel::new`]).
    pub fn new(
        gains: &AnyGains,
        float: FloatType,
        sin_cos: SinCosKind,
        options: &ChannelOptions,
    ) -> Result<Result<Self, ChannelError>, Error> {
        Ok(of_typed_gains!(AnyChannel, (gains, float, sin_cos), |g| {
            TrackerChannel::new(g, options)
        }))
    }

    /// The chain's state now, in float64 ([`TrackerChannel::status`]).
    pub fn status(&self) -> ChannelStatus {
        with_any_channel!(AnyChannel, self, c => c.status())
    }

    /// Forgets the observer's state: the next sample initialises it. Keeps the
    /// calibration.
    pub fn reset(&mut self) {
        with_any_channel!(AnyChannel, self, c => c.state.observer = ObserverState::new())
    }

    /// [`TrackerChannel::initialise`].
    pub fn initialise(&mut self, y_c: f64, y_s: f64) -> Result<(), ChannelError> {
        with_any_channel!(AnyChannel, self, c => c.initialise(y_c, y_s))
    }

    /// [`TrackerChannel::set_state`].
    pub fn set_state(
        &mut self,
        angle_rad: f64,
        speed_rad_s: f64,
        acceleration_rad_s2: f64,
    ) -> Result<(), ChannelError> {
        with_any_channel!(AnyChannel, self, c => c.set_state(angle_rad, speed_rad_s, acceleration_rad_s2))
    }

    /// Returns the observer's latched faults and clears them.
    pub fn clear_faults(&mut self) -> Faults {
        with_any_channel!(AnyChannel, self, c => c.state.observer.clear_faults())
    }

    /// Sets the calibration to `choice`'s, keeping the observer's state.
    pub fn set_calibration(
        &mut self,
        choice: &OnlineCalibrationChoice,
    ) -> Result<(), ChannelError> {
        with_any_channel!(AnyChannel, self, c => {
            *c.state.front_end.calibrator_mut() = choice.calibrator()?;
            Ok(())
        })
    }
}

impl AnyBatch {
    /// A batch of `channels` observers of `gains` in `float` with `sin_cos`
    /// ([`ChannelBatch::new`]).
    pub fn new(
        gains: &AnyGains,
        float: FloatType,
        sin_cos: SinCosKind,
        channels: usize,
    ) -> Result<Self, Error> {
        of_typed_gains!(AnyBatch, (gains, float, sin_cos), |g| ChannelBatch::new(
            g, channels
        ))
    }

    /// The number of channels.
    pub fn channels(&self) -> usize {
        with_any_channel!(AnyBatch, self, b => b.channels())
    }
}
