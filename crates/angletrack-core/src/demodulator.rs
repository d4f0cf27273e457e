//! The synchronous demodulator of a resolver front end (`docs/theory.md §13`): from ADC
//! samples of both windings, `N` per carrier period on the excitation's clock, one
//! `(y_c, y_s)` pair per carrier period with the carrier delay compensated, the delay
//! measured at start-up and tracked, and the front end's diagnostics.
//!
//! Per sample, four multiply-adds: each winding's sample times the reference `sin` and
//! `cos` of the excitation phase `2 pi k / N` (a table of `N` entries, built once). The sums
//! over a window give each winding's in-phase and quadrature components `(I, Q)`, about
//! `E env (N/2) (cos d, sin d)` for the envelope `env` (`cos theta` or `sin theta`) and the
//! carrier delay `d`; a DC offset or common mode sums to zero against `sin` and `cos` over a
//! whole period. The pair is the projection of `(I, Q)` on the delay,
//! `y = I cos d + Q sin d`, so no table is recomputed when `d` moves.
//!
//! The window is two one-period windows a quarter period apart, averaged (a trapezoid of
//! `5N/4` samples): the product of the carrier with the reference has a component at twice
//! the carrier which one window leaves as a bias proportional to the envelope's slope (a
//! delay-dependent time shift of up to 1.3 samples at `N = 16`); a quarter period later
//! that component has the opposite sign, so the average cancels it for any delay, and the
//! pair holds at the centre of the window.

use crate::error::{ConfigError, Parameter};
use crate::front_end_faults::FrontEndFaults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::check_positive;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};

mod settings;
mod state;

pub use settings::DemodulatorSettings;
pub use state::{DemodulatedPair, DemodulatorState};

/// The immutable, checked configuration of a synchronous demodulator with `N` ADC samples
/// per carrier period (a multiple of 4): reference tables, scale and thresholds. `Copy`;
/// the mutable part is a [`DemodulatorState`].
///
/// The carrier delay is measured modulo pi (a delay off by pi flips the sign of both
/// windings' envelopes, which is the same signal as a shaft turned by half a turn), from
/// the doubled angle of each winding's `(I, Q)`, whose sum over both windings has the same
/// length at every shaft angle. The start-up estimate is taken within 90 degrees of
/// [`DemodulatorSettings::expected_delay_rad`], so that it is the same at every power-up;
/// after that the delay is tracked continuously, without jumps of pi.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Demodulator<T, const N: usize> {
    sin_table: [T; N],
    cos_table: [T; N],
    scale: T,
    sample_period: T,
    /// The middle of the unclipped codes and half their span: a sample is clipped unless
    /// `|raw - clip_centre| < clip_half_span` (one comparison per winding, false for NaN).
    clip_centre: T,
    clip_half_span: T,
    loss_of_excitation2: T,
    drift_cos: T,
    expected: (T, T),
    tracking: T,
    startup_periods: u32,
}

impl<T: Float, const N: usize> Demodulator<T, N> {
    /// Checks `settings` and builds the reference tables for `N` samples per period.
    ///
    /// Refuses `N` not a positive multiple of 4, a non-positive carrier or amplitude, an
    /// empty ADC range or a margin covering it, a loss-of-excitation threshold outside
    /// [0, 1), a drift bound outside (0, pi], a tracking factor outside [0, 1], and no
    /// start-up period, naming the setting.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, Parameter};
    /// let settings = DemodulatorSettings::<f32>::new(10e3, 1800.0, 0.0, 4095.0);
    /// let demodulator = Demodulator::<f32, 16>::new(settings)?;
    /// assert!((demodulator.pair_period_s() - 1e-4).abs() < 1e-10);
    /// let err = Demodulator::<f32, 10>::new(settings).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::SamplesPerPeriod);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(settings: DemodulatorSettings<T>) -> Result<Self, ConfigError> {
        if N == 0 || !N.is_multiple_of(4) || N > 1 << 16 {
            return Err(ConfigError::OutOfRange(Parameter::SamplesPerPeriod));
        }
        let carrier = check_positive(settings.carrier_hz, Parameter::CarrierFrequency)?;
        let amplitude = check_positive(
            settings.carrier_amplitude_counts,
            Parameter::CarrierAmplitude,
        )?;
        let (low, high, margin) = (
            settings.adc_min_code,
            settings.adc_max_code,
            settings.clip_margin_counts,
        );
        if !(low.is_finite() && high.is_finite() && margin.is_finite()) {
            return Err(ConfigError::NotFinite(Parameter::AdcRange));
        }
        if !(margin >= T::ZERO && high - low > margin + margin) {
            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
        }
        let in_range = |v: T, lo: T, hi: T, parameter| {
            if !v.is_finite() {
                Err(ConfigError::NotFinite(parameter))
            } else if !(v >= lo && v <= hi) {
                Err(ConfigError::OutOfRange(parameter))
            } else {
                Ok(v)
            }
        };
        let loss = in_range(
            settings.loss_of_excitation,
            T::ZERO,
            T::ONE,
            Parameter::LossOfExcitationThreshold,
        )?;
        if loss == T::ONE {
            return Err(ConfigError::OutOfRange(
                Parameter::LossOfExcitationThreshold,
            ));
        }
        let drift = check_positive(settings.phase_drift_bound_rad, Parameter::PhaseDriftBound)?;
        let drift = in_range(drift, T::ZERO, T::PI, Parameter::PhaseDriftBound)?;
        let expected = in_range(
            settings.expected_delay_rad,
            T::from_f32(-1e3),
            T::from_f32(1e3),
            Parameter::ExpectedDelay,
        )?;
        let tracking = in_range(
            settings.delay_tracking_factor,
            T::ZERO,
            T::ONE,
            Parameter::DelayTrackingFactor,
        )?;
        if settings.startup_periods == 0 {
            return Err(ConfigError::NotPositive(Parameter::StartupPeriods));
        }
        let mut sin_table = [T::ZERO; N];
        let mut cos_table = [T::ZERO; N];
        let n = T::from_i32(N as i32);
        for k in 0..N {
            let mut phase = T::TAU * T::from_i32(k as i32) / n;
            crate::wrap::wrap_angle(&mut phase);
            (sin_table[k], cos_table[k]) = phase.fast_sin_cos();
        }
        let mut expected_wrapped = expected;
        crate::wrap::wrap_angle(&mut expected_wrapped);
        Ok(Self {
            sin_table,
            cos_table,
            scale: T::TWO / (n * amplitude),
            sample_period: T::ONE / (carrier * n),
            clip_centre: (low + high) * T::HALF,
            clip_half_span: (high - low) * T::HALF - margin,
            loss_of_excitation2: loss * loss,
            drift_cos: drift.fast_sin_cos().1,
            expected: expected_wrapped.fast_sin_cos(),
            tracking,
            startup_periods: settings.startup_periods,
        })
    }

    /// One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
    /// winding, in counts, any offset), taken at the excitation phase `2 pi k / N` of the
    /// `k`-th sample of the period. Returns a pair once per carrier period, after the
    /// start-up delay estimate; never panics. A NaN sample gives NaN pairs for the two
    /// windows that hold it, flagged [`FrontEndFaults::CLIPPING`] and
    /// [`FrontEndFaults::LOSS_OF_EXCITATION`] (the observer rejects them as bad samples), and
    /// does not reach the delay estimate.
    #[inline]
    pub fn push(
        &self,
        state: &mut DemodulatorState<T>,
        raw_c: T,
        raw_s: T,
    ) -> Option<DemodulatedPair<T>> {
        let k = state.index.min(N - 1);
        let (sin, cos) = (self.sin_table[k], self.cos_table[k]);
        self.accumulate(
            &mut state.sums,
            &mut state.clipped,
            (sin, cos),
            raw_c,
            raw_s,
        );
        state.index = k + 1;
        self.end_of_segment(state)
    }

    /// One sample pair into a segment's partial sums `(I_c, Q_c, I_s, Q_s)` and its clipping
    /// flag, with the reference `(sin, cos)` of its excitation phase.
    #[inline(always)]
    fn accumulate(
        &self,
        sums: &mut [T; 4],
        clipped: &mut bool,
        (sin, cos): (T, T),
        raw_c: T,
        raw_s: T,
    ) {
        sums[0] += raw_c * sin;
        sums[1] += raw_c * cos;
        sums[2] += raw_s * sin;
        sums[3] += raw_s * cos;
        let inside = |v: T| (v - self.clip_centre).abs() < self.clip_half_span;
        *clipped |= !(inside(raw_c) && inside(raw_s));
    }

    /// After a sample: the end of the first quarter (a window completes) or of the period,
    /// when the index has reached it.
    #[inline(always)]
    fn end_of_segment(&self, state: &mut DemodulatorState<T>) -> Option<DemodulatedPair<T>> {
        if state.index == N / 4 {
            self.end_of_first_quarter(state)
        } else {
            if state.index == N {
                self.end_of_period(state);
            }
            None
        }
    }

    /// [`Demodulator::push`] over a block of ADC samples (a DMA buffer), calling
    /// `sink(pair)` for each pair that completes; no allocation. Processes
    /// `min(raw_c.len(), raw_s.len())` sample pairs and returns that count, the same pairs
    /// as [`Demodulator::push`] on each sample.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState};
    /// let demodulator = Demodulator::<f32, 16>::new(DemodulatorSettings::new(10e3, 1800.0, 0.0, 4095.0))?;
    /// let mut state = DemodulatorState::new();
    /// let raw_c: [f32; 16 * 20] = core::array::from_fn(|j| {
    ///     2048.0 + 1800.0 * (core::f32::consts::TAU * (j % 16) as f32 / 16.0).sin()
    /// });
    /// let raw_s = [2048.0_f32; 16 * 20];
    /// let mut pairs = 0;
    /// let n = demodulator.push_block(&mut state, &raw_c, &raw_s, |pair| {
    ///     assert!((pair.y_c - 1.0).abs() < 1e-3 && pair.y_s.abs() < 1e-3);
    ///     pairs += 1;
    /// });
    /// assert_eq!((n, pairs), (320, 3)); // 16 windows for the delay, then one per period
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn push_block<F: FnMut(DemodulatedPair<T>)>(
        &self,
        state: &mut DemodulatorState<T>,
        raw_c: &[T],
        raw_s: &[T],
        mut sink: F,
    ) -> usize {
        let n = raw_c.len().min(raw_s.len());
        let mut done = 0;
        while done < n {
            // One segment (to the end of the first quarter or of the period) at a time, its
            // partial sums in locals: the inner loop touches no memory but the samples and
            // the reference table.
            let k0 = state.index.min(N - 1);
            let end = if k0 < N / 4 { N / 4 } else { N };
            let count = (end - k0).min(n - done);
            let (mut sums, mut clipped) = (state.sums, state.clipped);
            let reference = self.sin_table[k0..end].iter().zip(&self.cos_table[k0..end]);
            let samples = raw_c[done..n].iter().zip(&raw_s[done..n]);
            for ((&sin, &cos), (&c, &s)) in reference.zip(samples) {
                self.accumulate(&mut sums, &mut clipped, (sin, cos), c, s);
            }
            (state.sums, state.clipped) = (sums, clipped);
            state.index = k0 + count;
            done += count;
            if let Some(pair) = self.end_of_segment(state) {
                sink(pair);
            }
        }
        n
    }

    /// The partial sums of the rest of a period are kept; the next period starts.
    #[inline(never)]
    fn end_of_period(&self, state: &mut DemodulatorState<T>) {
        state.previous_first_quarter = state.first_quarter;
        state.previous_rest = (state.sums, state.clipped);
        state.sums = [T::ZERO; 4];
        state.clipped = false;
        state.index = 0;
        state.periods = state.periods.wrapping_add(1);
    }

    /// A window is complete: the previous period and this period's first quarter.
    #[inline(never)]
    fn end_of_first_quarter(&self, state: &mut DemodulatorState<T>) -> Option<DemodulatedPair<T>> {
        state.first_quarter = (state.sums, state.clipped);
        state.sums = [T::ZERO; 4];
        state.clipped = false;
        if state.periods == 0 {
            return None;
        }
        let (rest, rest_clipped) = state.previous_rest;
        let (q0, q0_clipped) = state.previous_first_quarter;
        let (q1, q1_clipped) = state.first_quarter;
        let mut w = [T::ZERO; 4];
        for i in 0..4 {
            w[i] = (rest[i] + (q0[i] + q1[i]) * T::HALF) * self.scale;
        }
        let [i_c, q_c, i_s, q_s] = w;
        let window = state.periods - 1;
        if !state.delay_ready {
            self.startup(state, i_c, q_c, i_s, q_s);
            return None;
        }
        let (cd, sd) = state.delay;
        let pair_c = (i_c * cd + q_c * sd, q_c * cd - i_c * sd);
        let pair_s = (i_s * cd + q_s * sd, q_s * cd - i_s * sd);
        let power = pair_c.0 * pair_c.0 + pair_c.1 * pair_c.1 + pair_s.0 * pair_s.0;
        let power = power + pair_s.1 * pair_s.1;
        let lost = !(power >= self.loss_of_excitation2);
        if !lost && power.is_finite() {
            // sin(2 (d_true - d)) from both windings, weighted by their power.
            let error = T::TWO * (pair_c.0 * pair_c.1 + pair_s.0 * pair_s.1) / power;
            let step = self.tracking * error * T::HALF;
            let (c, s) = (cd - step * sd, sd + step * cd);
            // One Newton step of 1/sqrt near 1 keeps (cos d, sin d) on the unit circle.
            let g = (T::from_f32(3.0) - (c * c + s * s)) * T::HALF;
            state.delay = (c * g, s * g);
        }
        let (cd0, sd0) = state.startup_delay;
        let drifted = !(state.delay.0 * cd0 + state.delay.1 * sd0 >= self.drift_cos);
        let faults = FrontEndFaults::when(lost, FrontEndFaults::LOSS_OF_EXCITATION)
            | FrontEndFaults::when(drifted, FrontEndFaults::PHASE_DRIFT)
            | FrontEndFaults::when(
                rest_clipped || q0_clipped || q1_clipped,
                FrontEndFaults::CLIPPING,
            );
        state.latched |= faults;
        Some(DemodulatedPair {
            y_c: pair_c.0,
            y_s: pair_s.0,
            quadrature_c: pair_c.1,
            quadrature_s: pair_s.1,
            window,
            faults,
        })
    }

    /// [`Demodulator::push`] and, when a pair comes out, the observer's update on it: the
    /// whole chain from ADC samples to the angle in one call per sample pair. `gains` must be
    /// designed for the pair period ([`Demodulator::check_gains`]).
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState, Gains, ObserverState};
    /// let demodulator = Demodulator::<f32, 16>::new(DemodulatorSettings::new(10e3, 1800.0, 0.0, 4095.0))?;
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], demodulator.pair_period_s())?;
    /// demodulator.check_gains(&gains)?;
    /// let (mut front_end, mut observer) = (DemodulatorState::new(), ObserverState::new());
    /// let mut last = None;
    /// for k in 0..16 * 40 {
    ///     // theta = 30 degrees, carrier delay 0, ADC mid-scale 2048.
    ///     let carrier = 1800.0 * (core::f32::consts::TAU * (k % 16) as f32 / 16.0).sin();
    ///     let (raw_c, raw_s) = (2048.0 + 0.866 * carrier, 2048.0 + 0.5 * carrier);
    ///     if let Some((_pair, estimate)) = demodulator.feed(&mut front_end, &gains, &mut observer, raw_c, raw_s) {
    ///         last = Some(estimate);
    ///     }
    /// }
    /// assert!((last.unwrap().angle - 0.5236).abs() < 1e-3);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn feed<const M: usize, S: SinCos<T>>(
        &self,
        state: &mut DemodulatorState<T>,
        gains: &Gains<T, M, S>,
        observer: &mut ObserverState<T, M>,
        raw_c: T,
        raw_s: T,
    ) -> Option<(DemodulatedPair<T>, Estimate<T>)> {
        let pair = self.push(state, raw_c, raw_s)?;
        Some((pair, gains.update(observer, pair.y_c, pair.y_s)))
    }

    /// Checks that `gains` run at the pair rate: their sample period must be the carrier
    /// period (to a relative 1e-4), else [`ConfigError::OutOfRange`] naming the sample period.
    pub fn check_gains<const M: usize, S: SinCos<T>>(
        &self,
        gains: &Gains<T, M, S>,
    ) -> Result<(), ConfigError> {
        let period = self.pair_period_s();
        if ((gains.sample_period() - period) / period).abs() <= T::from_f32(1e-4) {
            Ok(())
        } else {
            Err(ConfigError::OutOfRange(Parameter::SamplePeriod))
        }
    }

    /// The start-up delay estimate: the doubled angles `(I + i Q)^2` of both windings summed
    /// over the start-up periods, then halved within 90 degrees of the expected delay.
    #[cold]
    #[inline(never)]
    fn startup(&self, state: &mut DemodulatorState<T>, i_c: T, q_c: T, i_s: T, q_s: T) {
        let re = i_c * i_c - q_c * q_c + i_s * i_s - q_s * q_s;
        let im = T::TWO * (i_c * q_c + i_s * q_s);
        if re.is_finite() && im.is_finite() {
            state.startup_sum.0 += re;
            state.startup_sum.1 += im;
        }
        if state.periods < u64::from(self.startup_periods) {
            return;
        }
        let mut delay = state.startup_sum.1.atan2(state.startup_sum.0) * T::HALF;
        let (mut sd, mut cd) = delay.fast_sin_cos();
        if cd * self.expected.1 + sd * self.expected.0 < T::ZERO {
            delay += T::PI;
            crate::wrap::wrap_angle(&mut delay);
            (sd, cd) = delay.fast_sin_cos();
        }
        state.delay = (cd, sd);
        state.startup_delay = (cd, sd);
        state.delay_ready = true;
    }

    /// The time (s) at which pair `window` holds, the centre of its window, counting from the
    /// first ADC sample pushed: `(window N + (5N/4 - 1)/2) Ts_adc`. In `f64`, for host-side
    /// code (exact to `f64` rounding however long the run).
    pub fn window_centre_s(&self, window: u64) -> f64 {
        let n = N as f64;
        (window as f64 * n + (1.25 * n - 1.0) * 0.5) * self.sample_period.to_f64()
    }

    /// The delay (s) from the start of a window to its centre, where its pair holds.
    pub fn window_centre_offset_s(&self) -> T {
        let n = T::from_i32(N as i32);
        (n * T::from_f32(1.25) - T::ONE) * T::HALF * self.sample_period
    }

    /// The period (s) of the pairs: one carrier period, the sample period the observer's
    /// gains must be designed for.
    pub fn pair_period_s(&self) -> T {
        self.sample_period * T::from_i32(N as i32)
    }

    /// The ADC sample period (s).
    pub fn adc_sample_period_s(&self) -> T {
        self.sample_period
    }
}

#[cfg(test)]
mod tests;
