//! The demodulator of a resolver front end (`docs/theory.md §13`): ADC samples of both
//! windings at any rate of at least 4 per carrier period, and optionally of the excitation,
//! in; one `(y_c, y_s)` pair per carrier period out, with the carrier tracked in phase and
//! frequency and the front end's diagnostics.
//!
//! Per sample: a phase accumulator (the carrier loop's oscillator) indexes a sine table,
//! and each winding's sample is multiplied by the reference `sin` and `cos` and summed,
//! with the samples and the reference themselves (eight sums; three more with the
//! excitation). The sums are cut into segments where the tracked carrier phase crosses a
//! quarter and a whole turn; a window is a period and the two quarters around it at half
//! weight (a trapezoid): its weights have a double zero at twice the carrier, so that the
//! product's component there leaves no bias however fast the envelope moves. Each
//! window's components have the windings' means over the window removed (offsets and any
//! non-whole number of samples per period leave no bias) and are divided by its weight.
//!
//! The carrier loop locks the oscillator to the windings' own carrier (modulo half a turn):
//! its phase detector is `sum I Q / sum (I^2 + Q^2)` over both windings, `sin(2e)/2` for a
//! phase error `e` at every shaft angle; a proportional-integral correction of the phase
//! and the step once per window. The pair is then the in-phase component. The half turn
//! is resolved from the recorded excitation when there is one, else from the expected
//! delay at the end of the start-up; the delay chosen is exposed.

use crate::error::{ConfigError, Parameter};
use crate::front_end_faults::FrontEndFaults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};

mod number;
mod settings;
mod state;

pub use number::{DemodulatorNumber, FIXED_PAIR_UNIT};
pub use settings::DemodulatorSettings;
pub use state::{DemodulatedPair, DemodulatorState};
use state::{Segment, Sums};

/// A quarter turn of the carrier loop's phase.
const QUARTER: u32 = 1 << 30;
/// The largest phase correction per window (a sixteenth of a turn).
const MAX_CORRECTION: i64 = 1 << 28;

/// The immutable, checked configuration of a demodulator in the number type `V` (`f32`,
/// `f64`, or `i16` for fixed point): the carrier loop's nominal step and gains, the
/// scale, the thresholds. `Copy`; the mutable part is a [`DemodulatorState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Demodulator<V: DemodulatorNumber> {
    step: u32,
    step_min: u32,
    step_max: u32,
    /// The proportional gain in phase units per Q31 detector unit, Q16.
    phase_gain: i64,
    /// The integral gain in step units per Q31 detector unit, Q24.
    step_gain: i64,
    clip_centre: V,
    clip_half_span: V,
    pair_gain: V::Wide,
    loss_power: V::Wide,
    weak_power: V::Wide,
    /// `cos(2 bound)`: the loop is out of lock where `cos 2e` is below it.
    drift_cos2: V::Wide,
    /// 3/4, as [`DemodulatorNumber::times_fraction`] takes it: a weak window with less of
    /// the last window's power holds a loss's onset.
    transient_drop: V::Wide,
    expected: u32,
    expected_cos: V::Wide,
    expected_sin: V::Wide,
    startup_periods: u32,
    carrier_hz: V::Real,
    adc_rate_hz: V::Real,
}

/// `v` if it is finite and within `[low, high]`, else the error naming `parameter`.
fn in_range<T: Float>(v: T, low: T, high: T, parameter: Parameter) -> Result<T, ConfigError> {
    if !v.is_finite() {
        Err(ConfigError::NotFinite(parameter))
    } else if !(v >= low && v <= high) {
        Err(ConfigError::OutOfRange(parameter))
    } else {
        Ok(v)
    }
}

/// A turn fraction in [-1/2, 1/2) as phase units (2^32 per turn).
fn turn_fraction_to_phase<T: Float>(fraction: T) -> u32 {
    // 2^31 times a fraction below 1/2 in magnitude fits an i32.
    ((fraction * T::from_f32(2_147_483_648.0)).floor_to_i32() as u32).wrapping_mul(2)
}

impl<V: DemodulatorNumber> Demodulator<V> {
    /// Checks `settings` and builds the configuration.
    ///
    /// Refuses a non-positive carrier frequency or amplitude, an ADC rate below 4 samples
    /// per carrier period or above the type's maximum, an empty ADC range or a margin
    /// covering it, a loss-of-excitation threshold outside [0, 1), a weak-excitation
    /// threshold outside [loss, 1], a drift bound outside (0, pi/2], a carrier loop
    /// bandwidth outside (0, 0.5], a carrier error outside (0, 0.2], and no start-up
    /// period, naming the setting.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, Parameter};
    /// // 10 kHz carrier, 48 kHz ADC (4.8 samples per period).
    /// let settings = DemodulatorSettings::<f32>::new(10e3, 48e3, 1800.0, 0.0, 4095.0);
    /// let demodulator = Demodulator::<f32>::new(settings)?;
    /// assert!((demodulator.pair_period_s() - 1e-4).abs() < 1e-10);
    /// let slow = DemodulatorSettings { adc_rate_hz: 30e3, ..settings };
    /// assert_eq!(Demodulator::<f32>::new(slow).unwrap_err().parameter(), Parameter::AdcRate);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(settings: DemodulatorSettings<V::Real>) -> Result<Self, ConfigError> {
        type R<V> = <V as DemodulatorNumber>::Real;
        let carrier = R::<V>::check_positive(settings.carrier_hz, Parameter::CarrierFrequency)?;
        let adc_rate = R::<V>::check_positive(settings.adc_rate_hz, Parameter::AdcRate)?;
        let ratio = in_range(
            adc_rate / carrier,
            R::<V>::from_f32(4.0),
            R::<V>::from_i32(V::MAX_SAMPLES_PER_PERIOD as i32),
            Parameter::AdcRate,
        )?;
        let amplitude = R::<V>::check_positive(
            settings.carrier_amplitude_counts,
            Parameter::CarrierAmplitude,
        )?;
        let pair_gain =
            V::pair_gain(amplitude).ok_or(ConfigError::OutOfRange(Parameter::CarrierAmplitude))?;
        let (low, high, margin) = (
            settings.adc_min_code,
            settings.adc_max_code,
            settings.clip_margin_counts,
        );
        if !(low.is_finite() && high.is_finite() && margin.is_finite()) {
            return Err(ConfigError::NotFinite(Parameter::AdcRange));
        }
        if !(margin >= R::<V>::ZERO && high - low > margin + margin) {
            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
        }
        let half = R::<V>::HALF;
        let clip_centre = V::from_counts((low + high) * half)
            .ok_or(ConfigError::NotFinite(Parameter::AdcRange))?;
        let clip_half_span = V::from_counts((high - low) * half - margin)
            .ok_or(ConfigError::NotFinite(Parameter::AdcRange))?;
        let one = R::<V>::ONE;
        let loss = in_range(
            settings.loss_of_excitation,
            R::<V>::ZERO,
            one,
            Parameter::LossOfExcitationThreshold,
        )?;
        if loss == one {
            return Err(ConfigError::OutOfRange(
                Parameter::LossOfExcitationThreshold,
            ));
        }
        let weak = in_range(
            settings.weak_excitation,
            loss,
            one,
            Parameter::WeakExcitationThreshold,
        )?;
        let drift =
            R::<V>::check_positive(settings.phase_drift_bound_rad, Parameter::PhaseDriftBound)?;
        let drift = in_range(
            drift,
            R::<V>::ZERO,
            R::<V>::FRAC_PI_2,
            Parameter::PhaseDriftBound,
        )?;
        let expected = in_range(
            settings.expected_delay_rad,
            R::<V>::from_f32(-1e3),
            R::<V>::from_f32(1e3),
            Parameter::ExpectedDelay,
        )?;
        let bandwidth = R::<V>::check_positive(
            settings.carrier_loop_bandwidth,
            Parameter::CarrierLoopBandwidth,
        )?;
        let bandwidth = in_range(
            bandwidth,
            R::<V>::ZERO,
            R::<V>::HALF,
            Parameter::CarrierLoopBandwidth,
        )?;
        let error = R::<V>::check_positive(settings.max_carrier_error, Parameter::MaxCarrierError)?;
        let error = in_range(
            error,
            R::<V>::ZERO,
            R::<V>::from_f32(0.2),
            Parameter::MaxCarrierError,
        )?;
        if settings.startup_periods == 0 {
            return Err(ConfigError::NotPositive(Parameter::StartupPeriods));
        }
        let fraction = one / ratio;
        let step_at = |f: R<V>| turn_fraction_to_phase(f.min(R::<V>::from_f32(0.499_999)));
        let mut expected_wrapped = expected;
        crate::wrap::wrap_angle(&mut expected_wrapped);
        let (sin_expected, cos_expected) = expected_wrapped.fast_sin_cos();
        let (_, cos2) = (drift + drift).fast_sin_cos();
        // The phase detector's Q31 unit is 2^-31 rad of carrier phase, 2^32 / (2 pi) phase
        // units per rad: a gain k per rad is k / pi phase units per detector unit.
        let per_unit = one / R::<V>::PI;
        let phase_gain = (R::<V>::from_f32(core::f32::consts::SQRT_2)
            * bandwidth
            * per_unit
            * R::<V>::from_f32(65_536.0))
        .floor_to_i32();
        // The integral gain acts on the step, per sample: divided by the samples per period.
        let step_gain =
            (bandwidth * bandwidth * per_unit * fraction * R::<V>::from_f32(16_777_216.0))
                .floor_to_i32();
        Ok(Self {
            step: step_at(fraction),
            step_min: step_at(fraction * (one - error)),
            step_max: step_at(fraction * (one + error)),
            phase_gain: i64::from(phase_gain),
            step_gain: i64::from(step_gain),
            clip_centre,
            clip_half_span,
            pair_gain,
            loss_power: V::unit_power(loss),
            weak_power: V::unit_power(weak),
            drift_cos2: V::fraction(cos2),
            transient_drop: V::fraction(R::<V>::from_f32(0.75)),
            expected: turn_fraction_to_phase(expected_wrapped * R::<V>::FRAC_1_TAU),
            expected_cos: V::fraction(cos_expected),
            expected_sin: V::fraction(sin_expected),
            startup_periods: settings.startup_periods,
            carrier_hz: carrier,
            adc_rate_hz: adc_rate,
        })
    }

    /// One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
    /// winding, in counts, any offset). Returns a pair once per tracked carrier period,
    /// after the start-up; never panics. A NaN sample gives NaN pairs for the windows that
    /// hold it, flagged [`FrontEndFaults::CLIPPING`] and
    /// [`FrontEndFaults::LOSS_OF_EXCITATION`], and does not reach the carrier loop.
    #[inline]
    pub fn push(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
    ) -> Option<DemodulatedPair<V>> {
        self.push_one::<false>(state, raw_c, raw_s, V::default())
    }

    /// [`Demodulator::push`] with the excitation's sample taken at the same instant (any
    /// offset and amplitude): the carrier's half-turn ambiguity is resolved from it, every
    /// window. Push all samples of a run one way or the other.
    #[inline]
    pub fn push_with_excitation(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) -> Option<DemodulatedPair<V>> {
        self.push_one::<true>(state, raw_c, raw_s, excitation)
    }

    #[inline(always)]
    fn push_one<const E: bool>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) -> Option<DemodulatedPair<V>> {
        if state.left == 0 {
            self.start(state, E);
        }
        let mut segment = state.current;
        let mut phase = state.phase;
        self.accumulate::<E>(
            &mut segment,
            &mut phase,
            state.step,
            raw_c,
            raw_s,
            excitation,
        );
        state.current = segment;
        state.phase = phase;
        state.sample = state.sample.wrapping_add(1);
        state.left -= 1;
        if state.left == 0 {
            self.end_of_segment(state)
        } else {
            None
        }
    }

    /// One sample into a segment's sums, at the loop's `phase`, which it advances.
    #[inline(always)]
    fn accumulate<const E: bool>(
        &self,
        segment: &mut Segment<V::Sum>,
        phase: &mut u32,
        step: u32,
        raw_c: V,
        raw_s: V,
        excitation: V,
    ) {
        let table = V::sine_table();
        let index = (*phase >> 24) as usize;
        let (sin, cos) = (table[index], table[index + 64]);
        *phase = phase.wrapping_add(step);
        let sums = &mut segment.sums;
        V::mac(&mut sums.xs[0], raw_c, sin);
        V::mac(&mut sums.xc[0], raw_c, cos);
        V::mac(&mut sums.xs[1], raw_s, sin);
        V::mac(&mut sums.xc[1], raw_s, cos);
        V::accumulate(&mut sums.x[0], raw_c);
        V::accumulate(&mut sums.x[1], raw_s);
        V::accumulate(&mut sums.s, sin);
        V::accumulate(&mut sums.c, cos);
        if E {
            V::mac(&mut sums.xs[2], excitation, sin);
            V::mac(&mut sums.xc[2], excitation, cos);
            V::accumulate(&mut sums.x[2], excitation);
        }
        segment.clip |= V::clip_word(raw_c, self.clip_centre, self.clip_half_span)
            | V::clip_word(raw_s, self.clip_centre, self.clip_half_span);
    }

    /// [`Demodulator::push`] over a block of ADC samples (a DMA buffer), calling
    /// `sink(pair)` for each pair that completes; no allocation. Processes
    /// `min(raw_c.len(), raw_s.len())` samples and returns that count, the same pairs as
    /// [`Demodulator::push`] on each sample.
    ///
    /// ```
    /// use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState};
    /// // 10 kHz carrier at 150 kHz (15 samples per period), delay 0, shaft at 0.
    /// let demodulator = Demodulator::<f32>::new(DemodulatorSettings::new(10e3, 150e3, 1800.0, 0.0, 4095.0))?;
    /// let mut state = DemodulatorState::new();
    /// let raw_c: [f32; 15 * 40] = core::array::from_fn(|j| {
    ///     2048.0 + 1800.0 * (core::f32::consts::TAU * (j % 15) as f32 / 15.0).sin()
    /// });
    /// let raw_s = [2048.0_f32; 15 * 40];
    /// let mut pairs = 0;
    /// let n = demodulator.push_block(&mut state, &raw_c, &raw_s, |pair| {
    ///     assert!((pair.y_c - 1.0).abs() < 1e-2 && pair.y_s.abs() < 1e-3);
    ///     pairs += 1;
    /// });
    /// // 39 windows (each a period and the quarter after it), the first 23 for the start-up.
    /// assert_eq!((n, pairs), (600, 16));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn push_block<F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        sink: F,
    ) -> usize {
        self.run::<false, F>(state, raw_c, raw_s, &[], sink)
    }

    /// [`Demodulator::push_block`] with the excitation's samples (see
    /// [`Demodulator::push_with_excitation`]): `min` of the three lengths.
    #[inline]
    pub fn push_block_with_excitation<F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        excitation: &[V],
        sink: F,
    ) -> usize {
        self.run::<true, F>(state, raw_c, raw_s, excitation, sink)
    }

    #[inline(always)]
    fn run<const E: bool, F: FnMut(DemodulatedPair<V>)>(
        &self,
        state: &mut DemodulatorState<V>,
        raw_c: &[V],
        raw_s: &[V],
        excitation: &[V],
        mut sink: F,
    ) -> usize {
        let mut n = raw_c.len().min(raw_s.len());
        if E {
            n = n.min(excitation.len());
        }
        let mut done = 0;
        while done < n {
            if state.left == 0 {
                self.start(state, E);
            }
            // One segment (or what the block holds of it) at a time, its sums in locals: the
            // inner loop touches no memory but the samples and the reference table.
            let count = (state.left as usize).min(n - done);
            let (mut segment, mut phase, step) = (state.current, state.phase, state.step);
            let c = raw_c.get(done..done + count).unwrap_or(&[]);
            let s = raw_s.get(done..done + count).unwrap_or(&[]);
            let mut e = excitation.get(done..done + count).unwrap_or(&[]).iter();
            for (&c, &s) in c.iter().zip(s) {
                let x = if E {
                    e.next().copied().unwrap_or_default()
                } else {
                    V::default()
                };
                self.accumulate::<E>(&mut segment, &mut phase, step, c, s, x);
            }
            (state.current, state.phase) = (segment, phase);
            state.sample = state.sample.wrapping_add(count as u64);
            state.left -= count as u32;
            done += count;
            if state.left == 0
                && let Some(pair) = self.end_of_segment(state)
            {
                sink(pair);
            }
        }
        n
    }

    /// Before a run's first sample: the loop at the declared carrier, phase 0.
    #[cold]
    #[inline(never)]
    fn start(&self, state: &mut DemodulatorState<V>, excitation: bool) {
        state.step = self.step;
        state.held_step = self.step;
        state.excitation = excitation;
        state.in_first_quarter = true;
        self.begin_segment(state);
    }

    /// The next segment starts at the next sample: its length from the loop's phase and
    /// step (at least one sample).
    #[inline(always)]
    fn begin_segment(&self, state: &mut DemodulatorState<V>) {
        let end = if state.in_first_quarter { QUARTER } else { 0 };
        let distance = end.wrapping_sub(state.phase);
        // A phase already past the end (a correction, or a step above a quarter turn)
        // leaves a segment of one sample.
        let limit = if state.in_first_quarter {
            QUARTER
        } else {
            3 * QUARTER + QUARTER / 2
        };
        let distance = if distance > limit { 1 } else { distance.max(1) };
        let step = state.step.max(1);
        let length = (distance - 1) / step + 1;
        state.current = Segment {
            sums: Sums::default(),
            first: state.sample,
            length,
            clip: 0,
        };
        state.left = length;
    }

    /// A segment is complete: after a first quarter, a window.
    #[inline(never)]
    fn end_of_segment(&self, state: &mut DemodulatorState<V>) -> Option<DemodulatedPair<V>> {
        let pair = if state.in_first_quarter {
            let pair = if state.periods > 0 {
                self.window(state)
            } else {
                None
            };
            state.first_quarter = state.current;
            pair
        } else {
            state.rest = state.current;
            state.periods = state.periods.wrapping_add(1);
            None
        };
        state.in_first_quarter = !state.in_first_quarter;
        self.begin_segment(state);
        pair
    }

    /// The window of the previous period and the first quarters around it: components,
    /// the carrier loop's correction, the faults, the pair.
    fn window(&self, state: &mut DemodulatorState<V>) -> Option<DemodulatedPair<V>> {
        let (first, rest, last) = (&state.first_quarter, &state.rest, &state.current);
        let weight = 2 * rest.length + first.length + last.length;
        let per_weight = V::per_weight(weight);
        let combine = |f: fn(&Sums<V::Sum>) -> V::Sum| {
            V::combine(f(&rest.sums), f(&first.sums), f(&last.sums))
        };
        let r_s = combine(|s| s.s);
        let r_c = combine(|s| s.c);
        let components = |channel: usize| {
            let x = V::combine(
                rest.sums.x[channel],
                first.sums.x[channel],
                last.sums.x[channel],
            );
            let xs = V::combine(
                rest.sums.xs[channel],
                first.sums.xs[channel],
                last.sums.xs[channel],
            );
            let xc = V::combine(
                rest.sums.xc[channel],
                first.sums.xc[channel],
                last.sums.xc[channel],
            );
            (
                V::component(xs, x, r_s, per_weight),
                V::component(xc, x, r_c, per_weight),
            )
        };
        let ((i_c, q_c), (i_s, q_s)) = (components(0), components(1));
        let clip = first.clip | rest.clip | last.clip;
        // The centroid of the weights, from the window's first sample.
        let (a, b, c) = (first.length, rest.length, last.length);
        let centre = (a * a.wrapping_sub(1)) / 2
            + 2 * (b * a + b * b.wrapping_sub(1) / 2)
            + c * (a + b)
            + c * c.wrapping_sub(1) / 2;
        let first_sample = first.first;
        let excitation = if state.excitation {
            Some(components(2))
        } else {
            None
        };

        let g = self.pair_gain;
        let (mut y_c, mut q_yc, mut y_s, mut q_ys) = (
            V::to_pair(i_c, g),
            V::to_pair(q_c, g),
            V::to_pair(i_s, g),
            V::to_pair(q_s, g),
        );
        let in_phase = V::add(V::product(y_c, y_c), V::product(y_s, y_s));
        let quadrature = V::add(V::product(q_yc, q_yc), V::product(q_ys, q_ys));
        let power = V::add(in_phase, quadrature);
        let weak = !(power >= self.weak_power);
        // A weak window right after one without carrier, or with under 3/4 of the last window's
        // power, holds a loss's end or onset: part of it has no carrier, so its pair
        // (stamped at the window's centroid, not at its carrier's) is no measurement. A
        // steady or slowly fading weak excitation is not lost.
        let gone = !(power >= self.loss_power);
        let lost = gone
            || (weak
                && (state.last_lost
                    || power < V::times_fraction(state.last_power, self.transient_drop)));
        (state.last_power, state.last_lost) = (power, gone);
        let clipped = clip >> 31 != 0 || !V::is_finite(power);
        // cos 2e (times the power) below cos(2 bound): out of lock.
        let drifted =
            !lost && V::sub(in_phase, quadrature) < V::times_fraction(power, self.drift_cos2);
        if !lost && !state.delay_ready && state.windows.is_multiple_of(2) && in_phase < quadrature {
            // Acquiring a quarter turn off, where the detector's error vanishes too
            // (unstably): a quarter turn on (not on the next window, which holds samples
            // from before).
            state.phase = state.phase.wrapping_add(QUARTER);
        } else if !lost {
            let cross = V::add(V::product(y_c, q_yc), V::product(y_s, q_ys));
            // sum I Q / sum (I^2 + Q^2) = sin(2e) / 2, about e (rad), in Q31.
            let error = i64::from(V::ratio_q31(cross, power));
            self.correct(state, error, !weak);
        }
        if lost {
            // Through the loss, at the frequency the loop held before it.
            state.step = state.held_step;
        }
        state.windows = state.windows.wrapping_add(1);
        if let Some((i, q)) = excitation {
            state.excitation_iq = (i, q);
            // cos(delay after the excitation - expected) < 0: the loop holds the other half turn.
            let along = V::sub(
                V::times_fraction(i, self.expected_cos),
                V::times_fraction(q, self.expected_sin),
            );
            if state.delay_ready || state.windows >= u64::from(self.startup_periods) {
                state.flip = along < V::Wide::default();
            }
        }
        if !state.delay_ready {
            if state.windows < u64::from(self.startup_periods) {
                return None;
            }
            self.resolve(state);
        }
        if state.flip {
            (y_c, q_yc, y_s, q_ys) = (
                V::negate(y_c),
                V::negate(q_yc),
                V::negate(y_s),
                V::negate(q_ys),
            );
        }
        let faults = FrontEndFaults::when(lost, FrontEndFaults::LOSS_OF_EXCITATION)
            | FrontEndFaults::when(weak, FrontEndFaults::WEAK_EXCITATION)
            | FrontEndFaults::when(drifted, FrontEndFaults::PHASE_DRIFT)
            | FrontEndFaults::when(clipped, FrontEndFaults::CLIPPING);
        state.latched |= faults;
        Some(DemodulatedPair {
            y_c,
            y_s,
            quadrature_c: q_yc,
            quadrature_s: q_ys,
            window: state.windows - 1,
            first_sample,
            centre_offset_times_weight: centre,
            weight,
            faults,
        })
    }

    /// The carrier loop's correction for a phase error `error` (Q31 rad): the phase now,
    /// the step (within the carrier error allowed) from the next sample on.
    ///
    /// A window of weak excitation (one that straddles the onset or the end of a loss, or a
    /// carrier fading) corrects the phase only: its error is too unsure for the frequency.
    /// A window of full excitation also moves the held step (the frequency the loop keeps
    /// through a loss) 1/64 of the way to the loop's.
    #[inline(always)]
    fn correct(&self, state: &mut DemodulatorState<V>, error: i64, full: bool) {
        let phase = ((error * self.phase_gain) >> 16).clamp(-MAX_CORRECTION, MAX_CORRECTION);
        state.phase = state.phase.wrapping_add(phase as i32 as u32);
        if full {
            let step = i64::from(state.step) + ((error * self.step_gain) >> 24);
            state.step = step
                .max(i64::from(self.step_min))
                .min(i64::from(self.step_max)) as u32;
            let held = i64::from(state.held_step);
            state.held_step = (held + ((i64::from(state.step) - held) >> 6)) as u32;
        }
    }

    /// The end of the start-up: without an excitation, the half turn whose phase at the
    /// first sample (the loop's phase taken back at its step) is within a quarter turn of the
    /// expected delay.
    #[cold]
    #[inline(never)]
    fn resolve(&self, state: &mut DemodulatorState<V>) {
        let back = state.sample.wrapping_mul(u64::from(state.step)) as u32;
        let mut delay = state.phase.wrapping_sub(back);
        if !state.excitation {
            state.flip = (delay.wrapping_sub(self.expected) as i32).unsigned_abs() > QUARTER;
        }
        if state.flip {
            delay = delay.wrapping_add(2 * QUARTER);
        }
        state.startup_delay = delay;
        state.delay_ready = true;
    }

    /// [`Demodulator::push`] and, when a pair comes out, the observer's update on it: the
    /// whole chain from ADC samples to the angle in one call per sample pair. `gains` must be
    /// designed for the declared carrier period ([`Demodulator::check_gains`]).
    pub fn feed<const M: usize, S: SinCos<V>>(
        &self,
        state: &mut DemodulatorState<V>,
        gains: &Gains<V, M, S>,
        observer: &mut ObserverState<V, M>,
        raw_c: V,
        raw_s: V,
    ) -> Option<(DemodulatedPair<V>, Estimate<V>)>
    where
        V: Float,
    {
        let pair = self.push(state, raw_c, raw_s)?;
        Some((pair, gains.update(observer, pair.y_c, pair.y_s)))
    }

    /// Checks that `gains` run at the pair rate: their sample period must be the declared
    /// carrier period (to a relative 1e-4), else [`ConfigError::OutOfRange`] naming the
    /// sample period.
    pub fn check_gains<const M: usize, S: SinCos<V>>(
        &self,
        gains: &Gains<V, M, S>,
    ) -> Result<(), ConfigError>
    where
        V: Float + DemodulatorNumber<Real = V>,
    {
        let period = self.pair_period_s();
        if ((gains.sample_period() - period) / period).abs() <= V::from_f32(1e-4) {
            Ok(())
        } else {
            Err(ConfigError::OutOfRange(Parameter::SamplePeriod))
        }
    }

    /// The time (s) at which `pair` holds, counting from the first ADC sample pushed (at
    /// time 0), from the ADC rate. In `f64`, for host-side code.
    pub fn centre_s(&self, pair: &DemodulatedPair<V>) -> f64 {
        pair.centre_sample() / self.adc_rate_hz.to_f64()
    }

    /// The carrier frequency (Hz) the loop tracks now (the declared one before the first
    /// sample); for diagnostics.
    pub fn tracked_carrier_hz(&self, state: &DemodulatorState<V>) -> V::Real {
        let step = if state.step == 0 {
            self.step
        } else {
            state.step
        };
        // step / 2^32 turns per sample, as two factors of 2^16 to stay within f32's range.
        let per = V::Real::from_f32(1.0 / 65_536.0);
        V::Real::from_i32((step >> 16) as i32) * per * self.adc_rate_hz
            + V::Real::from_i32((step & 0xffff) as i32) * per * per * self.adc_rate_hz
    }

    /// The time (s) from a pair's centre to its window's last sample, at the declared
    /// carrier: 5/8 of a period (the window's middle, 5/8 of a period before the quarter
    /// period after its period ends) less half an ADC sample (the last sample stands for
    /// the half sample before it). Add the time to the output for a drive's latency.
    pub fn centre_to_end_s(&self) -> V::Real {
        V::Real::from_f32(0.625) / self.carrier_hz - V::Real::HALF / self.adc_rate_hz
    }

    /// The declared carrier period (s): the sample period the observer's gains are designed
    /// for.
    pub fn pair_period_s(&self) -> V::Real {
        V::Real::ONE / self.carrier_hz
    }

    /// The ADC sample period (s).
    pub fn adc_sample_period_s(&self) -> V::Real {
        V::Real::ONE / self.adc_rate_hz
    }

    /// The declared ADC samples per carrier period (any ratio of at least 4).
    pub fn samples_per_period(&self) -> V::Real {
        self.adc_rate_hz / self.carrier_hz
    }
}

#[cfg(test)]
mod tests;
