//! The resolver front end on numpy arrays (`docs/theory.md §13`): `Demodulator` (the core's
//! demodulator: the carrier tracked, any ADC rate of 4 or more per period, optionally the
//! excitation's samples, one pair per carrier period from the raw windings), and
//! `ResolverModel` and `resolver_windings` (the scenario generator's carrier-modulated
//! windings); the drive's outputs are in `drive`.

use angletrack::{DemodulatorArguments, DemodulatorStream, PairColumns, ResolverModel};
use pyo3::prelude::*;

use crate::arrays::{Column, Count, samples};
use crate::errors::Result;
use crate::getters::{class_methods, result_class};
use crate::model_class::{ModelField, model_class};
use crate::motion::PyMotionProfile;
use crate::scenario::PyScenario;

result_class! {
    /// The demodulated pairs of one `Demodulator.push`: one element per carrier period (after the
    /// start-up), float64 unless stated.
    PyDemodulatedPairs = "DemodulatedPairs" of |py, p: PairColumns| {
        /// The time (s) at which each pair holds (its window's samples weighted by their share
        /// of the pair), counting from the first ADC sample pushed into the demodulator (at the
        /// ADC rate).
        time_s: Column<f64> = p.time_s,
        /// The cosine winding's envelope (nominal amplitude 1).
        y_c: Column<f64> = p.y_c,
        /// The sine winding's envelope.
        y_s: Column<f64> = p.y_s,
        /// The cosine winding's quadrature component (about 0).
        quadrature_c: Column<f64> = p.quadrature_c,
        /// The sine winding's quadrature component.
        quadrature_s: Column<f64> = p.quadrature_s,
        /// The index of each pair's window (uint64, start-up windows counted).
        window: Column<u64> = p.window,
        /// The front end's faults of each window (uint8 bits: 1 loss of excitation, 2 phase
        /// drift, 4 clipping, 8 weak excitation).
        faults: Column<u8> = p.faults,
        /// Whether each pair's half turn rests on nothing stated (bool): every pair without
        /// `expected_delay_rad`, and with the excitation those whose window's excitation resolved
        /// nothing. Not a fault: the angle is right or half a turn off.
        half_turn_unresolved: Column<bool> = p.half_turn_unresolved,
    }
    len time_s;
}

/// The demodulator of a resolver front end (float64): ADC samples of both windings at
/// `adc_rate_hz` (at least 4 per period of the `carrier_hz` excitation, any ratio; or
/// `samples_per_period` times the carrier), optionally with the excitation's samples, in;
/// one `(y_c, y_s)` pair per tracked carrier period out. The carrier's phase and frequency
/// are tracked; its half-turn ambiguity is resolved around `expected_delay_rad`: the
/// windings' delay after the excitation when its samples are given, else the carrier's phase
/// at the first sample; without it (`None`), around 0 and every pair marked
/// `half_turn_unresolved`. Clipping is
/// checked against `adc_min_code` to `adc_max_code`; with `measure_adc_range=True` also
/// against the rails measured on each pushed block (for a range that is only a guess: every
/// pair whose window holds a sample at a rail is flagged clipping). The state carries over
/// between `push` calls.
#[pyclass(name = "Demodulator", module = "angletrack")]
#[derive(Debug)]
pub struct PyDemodulator {
    stream: DemodulatorStream,
}

class_methods! {
    PyDemodulator {
        /// ADC samples per declared carrier period (any ratio of at least 4).
        samples_per_period: f64 = |this, py| this.stream.demodulator().samples_per_period();
        /// The declared carrier period (s), the sample period the gains must have.
        pair_period_s: f64 = |this, py| this.stream.demodulator().pair_period_s();
        /// The time (s) from a pair's centre to its window's last sample.
        centre_to_end_s: f64 = |this, py| this.stream.demodulator().centre_to_end_s();
        /// The carrier frequency (Hz) the carrier loop tracks now.
        tracked_carrier_hz: f64 = |this, py| this.stream.demodulator().tracked_carrier_hz(this.stream.state());
        /// `True` once the start-up is done (pairs come out from then on).
        is_delay_ready: bool = |this, py| this.stream.state().is_delay_ready();
        /// `True` if the excitation's samples were pushed (the delay after it measured from
        /// them, within a half turn).
        has_excitation: bool = |this, py| this.stream.state().has_excitation();
        /// `True` if `expected_delay_rad` was given (the half turn resolved around it).
        is_delay_stated: bool = |this, py| this.stream.is_delay_stated();
        /// The carrier delay chosen (rad, in [-pi, pi), positive when the windings lag): after
        /// the excitation if pushed, else after a carrier of phase 0 at the first sample,
        /// resolved around `expected_delay_rad` (the
        /// other half turn would give the shaft half a turn further).
        carrier_delay_rad: f64 = |this, py| this.stream.state().carrier_delay_rad();
        /// The windings' delay after a carrier of phase 0 at the first sample, chosen at
        /// start-up (rad, in [-pi, pi)).
        startup_delay_rad: f64 = |this, py| this.stream.state().startup_delay_rad();
        /// The front-end faults latched so far (bits, as `DemodulatedPairs.faults`), the
        /// clipping against the measured rails included.
        latched_faults: u8 = |this, py| this.stream.latched_faults().bits();
        /// With `measure_adc_range=True`: the rails measured so far, `(low, high)` (a side
        /// without a rail one span beyond the samples), or `None` before the first; `None`
        /// without it.
        measured_adc_range: Option<(f64, f64)> = |this, py| this.stream.measured_adc_range();
        /// With `measure_adc_range=True`: the samples found at a measured rail so far; 0
        /// without it.
        clipped_samples: u64 = |this, py| this.stream.clipped_samples();
    }
    methods {
        #[new]
        #[pyo3(signature = (*, carrier_hz, carrier_amplitude_counts, adc_rate_hz = None,
            samples_per_period = None, adc_min_code = 0.0, adc_max_code = 4095.0,
            expected_delay_rad = None, startup_periods = None, phase_drift_bound_rad = None,
            loss_of_excitation = None, weak_excitation = None, carrier_loop_bandwidth = None,
            max_carrier_error = None, measure_adc_range = false))]
        #[allow(clippy::too_many_arguments)]
        fn py_new(
            carrier_hz: f64,
            carrier_amplitude_counts: f64,
            adc_rate_hz: Option<f64>,
            samples_per_period: Option<f64>,
            adc_min_code: f64,
            adc_max_code: f64,
            expected_delay_rad: Option<f64>,
            startup_periods: Option<Count>,
            phase_drift_bound_rad: Option<f64>,
            loss_of_excitation: Option<f64>,
            weak_excitation: Option<f64>,
            carrier_loop_bandwidth: Option<f64>,
            max_carrier_error: Option<f64>,
            measure_adc_range: bool,
        ) -> Result<Self> {
            let arguments = DemodulatorArguments {
                carrier_hz,
                carrier_amplitude_counts,
                adc_rate_hz,
                samples_per_period,
                adc_range: (adc_min_code, adc_max_code),
                expected_delay_rad,
                startup_periods: startup_periods.map(|n| n.get("startup_periods")).transpose()?,
                phase_drift_bound_rad,
                loss_of_excitation,
                weak_excitation,
                carrier_loop_bandwidth,
                max_carrier_error,
                measure_adc_range,
            };
            Ok(Self {
                stream: DemodulatorStream::new(&arguments)?,
            })
        }

        /// Pushes ADC samples of the cosine (`raw_c`) and sine (`raw_s`) windings (counts, 1-D
        /// float64 arrays of one length), and of the excitation if given (the same length; give
        /// it on every push of a run or on none), and returns the pairs that complete.
        #[pyo3(signature = (raw_c, raw_s, excitation = None))]
        fn push(
            &mut self,
            py: Python<'_>,
            raw_c: &Bound<'_, PyAny>,
            raw_s: &Bound<'_, PyAny>,
            excitation: Option<&Bound<'_, PyAny>>,
        ) -> Result<PyDemodulatedPairs> {
            let (c, s) = (samples::<f64>(raw_c, "raw_c")?, samples::<f64>(raw_s, "raw_s")?);
            let e = excitation.map(|e| samples::<f64>(e, "excitation")).transpose()?;
            let (stream, c, s, e) = (&mut self.stream, c.as_slice(), s.as_slice(), e.as_ref().map(|e| e.as_slice()));
            let p = py.detach(|| stream.push(c, s, e))?;
            PyDemodulatedPairs::of(py, p)
        }

        fn __repr__(&self) -> String {
            format!(
                "Demodulator(samples_per_period={}, pair_period_s={:e})",
                self.stream.demodulator().samples_per_period(),
                self.stream.demodulator().pair_period_s()
            )
        }
    }
}

model_class! {
    /// A carrier-excited resolver sampled by an ADC clocked with the excitation (the std crate's
    /// `ResolverModel`; defaults: 10 kHz carrier, 16 samples per period, 12-bit ADC, amplitude
    /// 1800 counts, noise 1 LSB, no delay). Checked when windings are generated.
    PyResolverModel = "ResolverModel" of ResolverModel {
        /// The excitation carrier frequency (Hz).
        carrier_hz: f64,
        /// ADC samples of each winding per carrier period.
        samples_per_period: usize,
        /// The carrier's phase delay from the excitation to the ADC (rad).
        carrier_delay_rad: f64,
        /// The excitation's amplitude (counts, as the windings would show it at ratio 1).
        excitation_amplitude_counts: f64,
        /// Winding amplitude over excitation amplitude.
        transformation_ratio: f64,
        /// The sine winding's relative amplitude error.
        winding_imbalance: f64,
        /// A DC common mode on both windings (counts).
        common_mode_counts: f64,
        /// The ADC's resolution (bits); 0 for no quantisation.
        adc_bits: u32,
        /// The noise's standard deviation on each sample (counts).
        noise_std_counts: f64,
    }
    methods {
        /// The carrier amplitude of a winding at the ADC (counts) at envelope 1.
        #[getter]
        fn amplitude_counts(&self) -> f64 {
            self.model().amplitude_counts()
        }

        /// The ADC sample period (s).
        #[getter]
        fn adc_sample_period_s(&self) -> f64 {
            self.model().adc_sample_period_s()
        }

        /// The ADC's mid-scale code (0 without an ADC).
        #[getter]
        fn mid_scale_counts(&self) -> f64 {
            self.model().mid_scale_counts()
        }
    }
}

/// The windings of a carrier-excited resolver following `profile`, as an ADC samples them:
/// a `Scenario` at the ADC rate whose `y_c`, `y_s` are the raw samples (counts) beside the
/// truth; the noise from a ChaCha8 generator seeded with `seed`.
#[pyfunction]
#[pyo3(signature = (profile, model = None, *, seed = Count::Whole(0)),
    text_signature = "(profile, model=None, *, seed=0)")]
pub fn resolver_windings(
    py: Python<'_>,
    profile: &PyMotionProfile,
    model: Option<&PyResolverModel>,
    seed: Count,
) -> Result<PyScenario> {
    let seed: u64 = seed.get("seed")?;
    let model = model.map_or_else(ResolverModel::default, PyResolverModel::model);
    let profile = profile.inner.clone();
    let s = py.detach(move || angletrack::Scenario::resolver_windings(&profile, &model, seed))?;
    PyScenario::of(py, s)
}
