//! The demodulator's outputs and mutable state (`docs/theory.md §13`): one demodulated pair
//! per tracked carrier period, and the carrier loop, the segments' sums and the faults kept
//! between samples.

use super::number::DemodulatorNumber;
use crate::front_end_faults::FrontEndFaults;

/// One demodulated pair: the windings' envelopes over one window, holding at its instant
/// ([`DemodulatedPair::instant_sample`]; the window's centroid,
/// [`DemodulatedPair::centre_sample`], at 4k samples a carrier period).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DemodulatedPair<V> {
    /// The cosine winding's envelope, `~ cos theta` (nominal amplitude 1; Q14 for `i16`).
    pub y_c: V,
    /// The sine winding's envelope, `~ sin theta`.
    pub y_s: V,
    /// The cosine winding's quadrature component (90 degrees from the tracked carrier):
    /// about 0 while the carrier loop is locked.
    pub quadrature_c: V,
    /// The sine winding's quadrature component.
    pub quadrature_s: V,
    /// The index of the window (0 for the first window, start-up included).
    pub window: u64,
    /// The index of the window's first ADC sample (0 for the first sample pushed).
    pub first_sample: u64,
    /// The window's weighted sample offset from its first sample, times `weight`.
    pub centre_offset_times_weight: u32,
    /// The window's weight (its samples counted twice in the middle segment, once at the
    /// two ends: `docs/theory.md §13`).
    pub weight: u32,
    /// The lengths (ADC samples) of the window's three segments: the period's first quarter,
    /// the rest of the period, the next period's first quarter.
    pub segment_samples: [u32; 3],
    /// The carrier loop's phase at the sample after the window (2^32 per turn).
    pub end_phase: u32,
    /// The carrier loop's phase step per ADC sample over the window (2^32 per turn).
    pub phase_step: u32,
    /// The front end's faults of this window.
    pub faults: FrontEndFaults,
}

impl<V> DemodulatedPair<V> {
    /// The (fractional) ADC sample index at which the pair holds: the centroid of its
    /// window's weights, `first_sample + centre_offset_times_weight / weight`. In `f64`, for
    /// host-side code.
    pub fn centre_sample(&self) -> f64 {
        self.first_sample as f64
            + f64::from(self.centre_offset_times_weight) / f64::from(self.weight.max(1))
    }

    /// The (fractional) ADC sample index at which the pair's envelopes hold: the window's
    /// samples weighted by what each contributes to the in-phase component, `w_k r_k (r_k -
    /// mean r)` for the window weight `w_k` and the carrier reference `r_k = sin phi_k`
    /// (its mean over the window removed with the windings' offsets). At a whole multiple of
    /// 4 samples a carrier period it is the centroid ([`DemodulatedPair::centre_sample`]);
    /// at other ratios the reference's samples fall unevenly across the window, and the
    /// centroid is off by up to a quarter of a sample, depending on the carrier's phase
    /// against the ADC's clock. The loop's phase is taken back from
    /// [`DemodulatedPair::end_phase`] at [`DemodulatedPair::phase_step`] (the window's first
    /// quarter ran at the step before the loop's last correction, a few ppm apart once
    /// locked). In `f64`, for host-side code: a rotation per sample of the window.
    pub fn instant_sample(&self) -> f64 {
        let [quarter, rest, last] = self.segment_samples;
        let length = quarter + rest + last;
        let turn = core::f64::consts::TAU / 4_294_967_296.0;
        let first = self
            .end_phase
            .wrapping_sub(self.phase_step.wrapping_mul(length));
        let (mut sin, mut cos) = libm::sincos(f64::from(first) * turn);
        let (step_sin, step_cos) = libm::sincos(f64::from(self.phase_step) * turn);
        // Sums of w, w r, w r k, w r^2, w r^2 k over the window's samples k.
        let (mut w_sum, mut r_sum, mut rk_sum, mut rr_sum, mut rrk_sum) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for k in 0..length {
            let w = if k < quarter || k >= quarter + rest {
                1.0
            } else {
                2.0
            };
            let k = f64::from(k);
            w_sum += w;
            r_sum += w * sin;
            rk_sum += w * sin * k;
            rr_sum += w * sin * sin;
            rrk_sum += w * sin * sin * k;
            (sin, cos) = (
                sin * step_cos + cos * step_sin,
                cos * step_cos - sin * step_sin,
            );
        }
        let weight = w_sum * rr_sum - r_sum * r_sum;
        if !(weight > 0.0) {
            return self.centre_sample();
        }
        self.first_sample as f64 + (w_sum * rrk_sum - r_sum * rk_sum) / weight
    }
}

/// The sums of the windings' samples over one segment (in `S`: a segment's type) or one
/// window (its wide type): per winding (cosine, sine) the samples times the reference `sin`
/// and `cos`, and the samples; and the reference's own sums.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Sums<S> {
    pub(super) xs: [S; 2],
    pub(super) xc: [S; 2],
    pub(super) x: [S; 2],
    pub(super) s: S,
    pub(super) c: S,
}

/// The same sums of the excitation's samples (with the reference's of [`Sums`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct ExcitationSums<S> {
    pub(super) xs: S,
    pub(super) xc: S,
    pub(super) x: S,
}

/// The segment being summed: its sums, its first sample, its length and its samples'
/// clipping words ORed (the sign bit set if one was clipped).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Segment<S> {
    pub(super) sums: Sums<S>,
    pub(super) excitation: ExcitationSums<S>,
    pub(super) first: u64,
    pub(super) length: u32,
    pub(super) clip: u32,
}

/// The window under way: a period's first quarter (weight 1) and the rest of the period
/// (weight 2) summed in the wide type; the next first quarter completes it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct PendingWindow<W> {
    pub(super) sums: Sums<W>,
    pub(super) excitation: ExcitationSums<W>,
    /// The window's first sample.
    pub(super) first: u64,
    /// The lengths of its first quarter and of the rest of its period.
    pub(super) quarter: u32,
    pub(super) rest: u32,
    /// Its samples' clipping words ORed.
    pub(super) clip: u32,
}

/// The mutable state of a [`Demodulator`](crate::Demodulator): the carrier loop's phase and
/// step, the segments' sums, the chosen sign of the carrier, the faults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemodulatorState<V: DemodulatorNumber> {
    /// The carrier loop's phase at the next sample (2^32 per turn).
    pub(super) phase: u32,
    /// The phase step per sample (2^32 per turn); 0 before the first sample.
    pub(super) step: u32,
    /// The step averaged over about 64 windows of full excitation: what the loop runs at
    /// through a loss of excitation (a window straddling the loss's onset measures a phase
    /// error that the fast loop would otherwise carry, as a wrong frequency, through the
    /// whole loss).
    pub(super) held_step: u32,
    /// The last window's carrier power (in-phase and quadrature, both windings) and whether
    /// it was below the loss threshold: a loss's onset and end are told from them.
    pub(super) last_power: V::Wide,
    pub(super) last_lost: bool,
    /// Whether the last window was out of lock: the loop's correction after it moves the
    /// next window's timing, so that window's pair is no measurement yet either.
    pub(super) last_drifted: bool,
    /// The next sample's index.
    pub(super) sample: u64,
    /// Samples left in the current segment.
    pub(super) left: u32,
    /// Whether the current segment is a period's first quarter.
    pub(super) in_first_quarter: bool,
    pub(super) current: Segment<V::Sum>,
    pub(super) pending: PendingWindow<V::Wide>,
    /// Rest segments completed (periods).
    pub(super) periods: u64,
    /// Windows completed.
    pub(super) windows: u64,
    /// Whether an excitation sample came with the samples.
    pub(super) excitation: bool,
    /// The last window's excitation components `(I, Q)` against the loop's phase.
    pub(super) excitation_iq: (V::Wide, V::Wide),
    /// Whether a usable window of the recorded excitation has resolved the half turn.
    pub(super) reference_resolved: bool,
    /// Whether the pairs are negated (the loop locked half a turn from the chosen carrier).
    pub(super) flip: bool,
    /// The carrier's phase at the first sample, as chosen at start-up (2^32 per turn).
    pub(super) startup_delay: u32,
    pub(super) delay_ready: bool,
    pub(super) latched: FrontEndFaults,
}

impl<V: DemodulatorNumber> Default for DemodulatorState<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: DemodulatorNumber> DemodulatorState<V> {
    /// A state at power-up: the next sample is the first, at excitation phase 0 of the
    /// declared carrier; the carrier not yet acquired.
    pub fn new() -> Self {
        Self {
            phase: 0,
            step: 0,
            held_step: 0,
            last_power: V::Wide::default(),
            last_lost: false,
            last_drifted: false,
            sample: 0,
            left: 0,
            in_first_quarter: true,
            current: Segment::default(),
            pending: PendingWindow::default(),
            periods: 0,
            windows: 0,
            excitation: false,
            excitation_iq: (V::Wide::default(), V::Wide::default()),
            reference_resolved: false,
            flip: false,
            startup_delay: 0,
            delay_ready: false,
            latched: FrontEndFaults::NONE,
        }
    }

    /// `true` once the start-up is done (pairs come out from then on).
    pub fn is_delay_ready(&self) -> bool {
        self.delay_ready
    }

    /// The carrier delay chosen (rad, in [-pi, pi), positive when the windings' carrier
    /// lags): with a recorded excitation the windings' carrier after it, as of its last
    /// usable window; without one (or before its first usable window), the windings' carrier
    /// after a carrier of phase 0 at the first sample (the declared carrier's), as chosen at
    /// start-up.
    /// The other half turn is the same signal with the shaft half a turn further
    /// (`docs/theory.md §13`). Meant for diagnostics (one `atan2`).
    pub fn carrier_delay_rad(&self) -> V::Real {
        use crate::real::Float;
        if self.reference_resolved {
            let (i, q) = self.excitation_iq;
            let (i, q) = (V::wide_to_real(i), V::wide_to_real(q));
            let half = if self.flip {
                V::Real::PI
            } else {
                V::Real::ZERO
            };
            // The excitation's phase ahead of the windings' carrier: the delay.
            let mut delay = q.atan2(i) - half;
            crate::wrap::wrap_angle(&mut delay);
            delay
        } else {
            self.startup_delay_rad()
        }
    }

    /// The windings' carrier delay after a carrier of phase 0 at the first sample (the
    /// negative of their carrier's phase there), chosen at start-up (rad, in [-pi, pi)).
    pub fn startup_delay_rad(&self) -> V::Real {
        use crate::real::Float;
        V::Real::from_i32((self.startup_delay as i32).wrapping_neg())
            * (V::Real::PI * V::Real::from_f32(1.0 / 2_147_483_648.0))
    }

    /// Whether the samples came with the excitation (the carrier's sign resolved from it).
    pub fn has_excitation(&self) -> bool {
        self.excitation
    }

    /// The ADC samples pushed so far.
    pub fn samples(&self) -> u64 {
        self.sample
    }

    /// The faults latched since they were last cleared.
    pub fn latched_faults(&self) -> FrontEndFaults {
        self.latched
    }

    /// Returns the latched faults and clears them.
    pub fn clear_faults(&mut self) -> FrontEndFaults {
        core::mem::take(&mut self.latched)
    }
}
