//! The variants of the firmware test and the layout of the reference data: shared by the
//! build script (which computes the reference on the host) and the firmware (which checks
//! itself against it and counts), so that both run the same list in the same order.
//!
//! A variant is a [`Tracker`]: one of the core's entry points with its gains, or a baseline
//! (`baseline`). The list is the [`variants!`] table below: one line per variant. A variant
//! of an entry point that has a `Tracker` here (`Plain`, `Calibrated`, `Adc`, `Corrected`,
//! `PhaseLockedLoop`) is that one line; another `f32` entry point of the core first needs its
//! [`EntryPoint`] (its state, input type and call), and anything else (another arithmetic,
//! say) its `Tracker`: its state, input and output types, and its estimate as a [`Record`].
//! `run.sh` prints each variant under its name on the Cortex-M4F (`-m4` appended if it
//! contains `-fixed`) and with `-m0` appended on the Cortex-M0.

use angletrack_core::{
    AdcScaling, AngleCorrection, Calibrator, ConfigError, DemodulatedPair, Demodulator,
    DemodulatorSettings, Estimate, Exact, Fast, FaultThresholds, FixedEstimate, FixedGains,
    FixedState, Gains, MAX_CORRECTION_ORDER, ObserverState, Order, SinCos, SupportedOrder,
};

use crate::baseline::{Atan2, FastAtan2, LibmAtan2, PhaseLockedLoop, PllState};

/// What a variant runs per sample, and how its result compares with the host's.
pub trait Tracker {
    /// The per-channel state.
    type State;
    /// One input sample as the entry point takes it.
    type Input: Copy;
    /// What one update returns.
    type Output: Copy + Default;
    /// Whether [`Tracker::update_block`] is the core's block form (else it runs nothing).
    const BLOCK: bool = false;
    /// A fresh state.
    fn new_state(&self) -> Self::State;
    /// An input sample (amplitude about 1) as the entry point takes it; converted outside
    /// the counted update.
    fn input(y: f32) -> Self::Input;
    /// One sample.
    fn update(&self, state: &mut Self::State, y_c: Self::Input, y_s: Self::Input) -> Self::Output;
    /// The estimate after an update, as compared with the host's (read outside the counted
    /// update: an entry point that returns no estimate computes it here, on demand).
    fn record(&self, state: &Self::State, output: &Self::Output) -> Record;
    /// All samples in one call, if [`Tracker::BLOCK`]; returns the number of outputs.
    fn update_block(
        &self,
        _state: &mut Self::State,
        _y_c: &[f32],
        _y_s: &[f32],
        _out: &mut [Self::Output],
    ) -> usize {
        0
    }
}

/// One of the core's `Gains` entry points on an `f32` observer ([`Plain`], [`Calibrated`],
/// [`Adc`], [`Corrected`]): what differs between them. Each is a [`Tracker`] through the one
/// implementation below, which returns the core's estimate and records it.
pub trait EntryPoint {
    /// The per-channel state.
    type State: Default;
    /// One input sample as the entry point takes it.
    type Input: Sample;
    /// Whether [`EntryPoint::update_block`] is the core's block form (else it runs nothing).
    const BLOCK: bool = false;
    /// A fresh state.
    fn new_state(&self) -> Self::State {
        Self::State::default()
    }
    /// One sample.
    fn update(&self, state: &mut Self::State, y_c: Self::Input, y_s: Self::Input) -> Estimate<f32>;
    /// All samples in one call, if [`EntryPoint::BLOCK`]; returns the number of outputs.
    fn update_block(
        &self,
        _state: &mut Self::State,
        _y_c: &[f32],
        _y_s: &[f32],
        _out: &mut [Estimate<f32>],
    ) -> usize {
        0
    }
}

/// An input sample's form, from the simulated signal's sample (amplitude about 1).
pub trait Sample: Copy {
    /// The signal's sample `y` in this form.
    fn from_signal(y: f32) -> Self;
}

impl Sample for f32 {
    fn from_signal(y: f32) -> f32 {
        y
    }
}

/// The [`Adc`] entry point's input: [`adc_counts`].
impl Sample for i16 {
    fn from_signal(y: f32) -> i16 {
        adc_counts(y)
    }
}

impl<E: EntryPoint> Tracker for E {
    type State = E::State;
    type Input = E::Input;
    type Output = Estimate<f32>;
    const BLOCK: bool = E::BLOCK;
    fn new_state(&self) -> E::State {
        EntryPoint::new_state(self)
    }
    fn input(y: f32) -> E::Input {
        E::Input::from_signal(y)
    }
    #[inline(always)]
    fn update(&self, state: &mut E::State, y_c: E::Input, y_s: E::Input) -> Estimate<f32> {
        EntryPoint::update(self, state, y_c, y_s)
    }
    fn record(&self, _: &E::State, output: &Estimate<f32>) -> Record {
        Record::of(output)
    }
    #[inline(always)]
    fn update_block(
        &self,
        state: &mut E::State,
        y_c: &[f32],
        y_s: &[f32],
        out: &mut [Estimate<f32>],
    ) -> usize {
        EntryPoint::update_block(self, state, y_c, y_s, out)
    }
}

/// The core's `Gains::update`.
#[derive(Debug, Clone, Copy)]
pub struct Plain<const N: usize, S>(pub Gains<f32, N, S>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for Plain<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ObserverState<f32, N>;
    type Input = f32;
    const BLOCK: bool = true;
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) -> Estimate<f32> {
        self.0.update(state, y_c, y_s)
    }
    #[inline(always)]
    fn update_block(
        &self,
        state: &mut Self::State,
        y_c: &[f32],
        y_s: &[f32],
        out: &mut [Estimate<f32>],
    ) -> usize {
        self.0.update_block(state, y_c, y_s, out)
    }
}

/// The core's `Gains::update_calibrated`, the online calibration learning.
#[derive(Debug, Clone, Copy)]
pub struct Calibrated<const N: usize, S>(pub Gains<f32, N, S>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for Calibrated<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = (ObserverState<f32, N>, Calibrator<f32>);
    type Input = f32;
    fn new_state(&self) -> Self::State {
        let mut calibrator = Calibrator::new();
        calibrator.enable();
        (ObserverState::new(), calibrator)
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) -> Estimate<f32> {
        let (observer, calibrator) = state;
        self.0.update_calibrated(observer, calibrator, y_c, y_s)
    }
}

/// The core's `Gains::update_adc` on [`adc_counts`] of the inputs, 12-bit two's complement.
#[derive(Debug, Clone, Copy)]
pub struct Adc<const N: usize, S>(pub Gains<f32, N, S>, pub AdcScaling<f32>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for Adc<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ObserverState<f32, N>;
    type Input = i16;
    #[inline(always)]
    fn update(&self, state: &mut Self::State, raw_c: i16, raw_s: i16) -> Estimate<f32> {
        self.0.update_adc(state, &self.1, raw_c, raw_s)
    }
}

/// The core's `Gains::update_corrected`: the angle-harmonic correction [`correction`].
#[derive(Debug, Clone, Copy)]
pub struct Corrected<const N: usize, S>(pub Gains<f32, N, S>, pub AngleCorrection<f32>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for Corrected<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ObserverState<f32, N>;
    type Input = f32;
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) -> Estimate<f32> {
        self.0.update_corrected(state, &self.1, y_c, y_s)
    }
}

/// The core's `Gains::track`: the state only, the estimate read on demand
/// (`Gains::estimate`) where it is checked, outside the counted update.
#[derive(Debug, Clone, Copy)]
pub struct Track<const N: usize, S>(pub Gains<f32, N, S>);

impl<const N: usize, S: SinCos<f32>> Tracker for Track<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ObserverState<f32, N>;
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> Self::State {
        ObserverState::new()
    }
    fn input(y: f32) -> f32 {
        y
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) {
        self.0.track(state, y_c, y_s)
    }
    fn record(&self, state: &Self::State, _: &()) -> Record {
        Record::of(&self.0.estimate(state))
    }
}

/// The core's `Gains::track_calibrated` with the calibration off (the cost of having the
/// online calibration in the update, not of learning): the state only, the estimate read
/// on demand where it is checked.
#[derive(Debug, Clone, Copy)]
pub struct TrackCalibratedOff<const N: usize, S>(pub Gains<f32, N, S>);

impl<const N: usize, S: SinCos<f32>> Tracker for TrackCalibratedOff<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = (ObserverState<f32, N>, Calibrator<f32>);
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> Self::State {
        (ObserverState::new(), Calibrator::new())
    }
    fn input(y: f32) -> f32 {
        y
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) {
        let (observer, calibrator) = state;
        self.0.track_calibrated(observer, calibrator, y_c, y_s)
    }
    fn record(&self, state: &Self::State, _: &()) -> Record {
        Record::of(&self.0.estimate(&state.0))
    }
}

/// The core's `Gains::update_calibrated` with the calibration off.
#[derive(Debug, Clone, Copy)]
pub struct CalibratedOff<const N: usize, S>(pub Gains<f32, N, S>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for CalibratedOff<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = (ObserverState<f32, N>, Calibrator<f32>);
    type Input = f32;
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) -> Estimate<f32> {
        let (observer, calibrator) = state;
        self.0.update_calibrated(observer, calibrator, y_c, y_s)
    }
}

/// The baseline: an arctangent and a 2nd-order PLL; its state is its estimate.
impl<A: Atan2> Tracker for PhaseLockedLoop<A> {
    type State = PllState;
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> PllState {
        PllState::default()
    }
    fn input(y: f32) -> f32 {
        y
    }
    #[inline(always)]
    fn update(&self, state: &mut PllState, y_c: f32, y_s: f32) {
        PhaseLockedLoop::update(self, state, y_c, y_s)
    }
    fn record(&self, state: &PllState, _: &()) -> Record {
        Record {
            angle: state.angle,
            turns: state.turns,
            speed: state.speed,
            acceleration: 0.0,
        }
    }
}

/// An input sample (amplitude about 1) as a 12-bit two's complement ADC reading (full
/// scale +-2048 counts), truncated: the same on the host and on the target.
pub fn adc_counts(y: f32) -> i16 {
    (y * 2048.0) as i16
}

/// The angle-harmonic correction of the `angle-corrected` variant, order 4: a few mrad of
/// each harmonic, as a real resolver has (the benchmark's signal has none: the variant is
/// there for its cost; the host reference checks it all the same).
pub fn correction() -> Result<AngleCorrection<f32>, ConfigError> {
    let mut a = [0.0; MAX_CORRECTION_ORDER];
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    a[..4].copy_from_slice(&[2e-3, -1e-3, 5e-4, 1.5e-3]);
    b[..4].copy_from_slice(&[-1e-3, 3e-3, -5e-4, 1e-3]);
    AngleCorrection::new(a, b)
}

/// The natural frequency of the baselines' PLL (rad/s): that of the benchmarks' 2nd-order
/// ATO (50 Hz, damping 1).
pub const PLL_BANDWIDTH_RAD_S: f32 = core::f32::consts::TAU * 50.0;

/// The estimate compared with the host's: angle (rad), whole turns, speed (rad/s),
/// acceleration (rad/s^2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    /// Angle (rad).
    pub angle: f32,
    /// Whole turns.
    pub turns: i32,
    /// Speed (rad/s).
    pub speed: f32,
    /// Acceleration (rad/s^2).
    pub acceleration: f32,
}

/// Bytes of one encoded [`Record`]: angle (f32), turns (i32), speed (f32), acceleration
/// (f32), little endian.
pub const RECORD_BYTES: usize = 16;

impl Record {
    /// The record of an observer's estimate.
    pub fn of(estimate: &Estimate<f32>) -> Self {
        Self {
            angle: estimate.angle,
            turns: estimate.turns as i32,
            speed: estimate.speed,
            acceleration: estimate.acceleration,
        }
    }

    /// The record's bytes (written by the build script only).
    #[allow(dead_code)]
    pub fn encode(&self) -> [u8; RECORD_BYTES] {
        let mut r = [0; RECORD_BYTES];
        r[0..4].copy_from_slice(&self.angle.to_le_bytes());
        r[4..8].copy_from_slice(&self.turns.to_le_bytes());
        r[8..12].copy_from_slice(&self.speed.to_le_bytes());
        r[12..16].copy_from_slice(&self.acceleration.to_le_bytes());
        r
    }

    /// The record of [`Record::encode`]'s bytes.
    pub fn decode(r: &[u8]) -> Self {
        let word = |i: usize| [r[i], r[i + 1], r[i + 2], r[i + 3]];
        Self {
            angle: f32::from_le_bytes(word(0)),
            turns: i32::from_le_bytes(word(4)),
            speed: f32::from_le_bytes(word(8)),
            acceleration: f32::from_le_bytes(word(12)),
        }
    }
}

/// The discrete gains of the three observers and the sample period (s), in `f32`.
#[derive(Debug, Clone, Copy)]
pub struct Observers {
    /// `(l1, l2)` of the 2nd-order ATO.
    pub second_order: [f32; 2],
    /// `(l1, l2, l3)` of the 3rd-order ATO (pole placement).
    pub third_order: [f32; 3],
    /// `(l1, l2, l3)` of the Kalman ATO.
    pub kalman: [f32; 3],
    /// Sample period (s).
    pub sample_period_s: f32,
}

impl Observers {
    fn second_order(&self) -> Result<Gains<f32, 2, Exact>, ConfigError> {
        Gains::new(self.second_order, self.sample_period_s)
    }
    fn third_order(&self) -> Result<Gains<f32, 3, Exact>, ConfigError> {
        Gains::new(self.third_order, self.sample_period_s)
    }
    fn kalman(&self) -> Result<Gains<f32, 3, Exact>, ConfigError> {
        Gains::new(self.kalman, self.sample_period_s)
    }
    fn fixed(&self) -> Result<Fixed<3>, ConfigError> {
        let gains = FixedGains::new(self.kalman.map(f64::from), f64::from(self.sample_period_s))?;
        Ok(Fixed(gains, self.sample_period_s))
    }
    fn fixed_unmonitored(&self) -> Result<Fixed<3>, ConfigError> {
        let Fixed(gains, sample_period_s) = self.fixed()?;
        Ok(Fixed(gains.with_monitor(None)?, sample_period_s))
    }
    fn pll<A: Atan2>(&self) -> PhaseLockedLoop<A> {
        PhaseLockedLoop::new(PLL_BANDWIDTH_RAD_S, self.sample_period_s)
    }
}

/// The gains with the fast (polynomial) sin/cos.
fn fast<const N: usize>(gains: Gains<f32, N, Exact>) -> Gains<f32, N, Fast> {
    gains.with_sin_cos()
}

/// The gains with the diagnostics off (`FaultThresholds::disabled()`: the bare loop).
fn unmonitored<const N: usize>(
    gains: Gains<f32, N, Exact>,
) -> Result<Gains<f32, N, Exact>, ConfigError> {
    gains.with_fault_thresholds(FaultThresholds::disabled())
}

/// Something to do with one variant's tracker.
pub trait Job {
    /// Runs on variant `index` (into [`NAMES`]).
    fn run<T: Tracker>(&mut self, index: usize, tracker: T);
}

/// The variant table: `"name" => |observers| tracker,` one line per variant (the tracker a
/// `Result<impl Tracker, ConfigError>`), which makes [`NAMES`] and [`Observers::run`].
macro_rules! variants {
    ($($name:literal => |$o:ident| $tracker:expr,)*) => {
        /// The variants, as printed: `<observer>-<arithmetic>-<sincos>[-<entry>]`, or
        /// `baseline-<arctangent>-pll-<arithmetic>`.
        pub const NAMES: &[&str] = &[$($name),*];

        impl Observers {
            /// Runs `job` on variant `index`. Returns `Ok(false)` (and runs nothing) if
            /// `index` is not a variant, the error if its gains are refused.
            pub fn run(&self, index: usize, job: &mut impl Job) -> Result<bool, ConfigError> {
                let mut i = 0;
                $(
                    if index == i {
                        let $o = self;
                        job.run(index, $tracker?);
                        return Ok(true);
                    }
                    i += 1;
                )*
                let _ = i;
                Ok(false)
            }
        }
    };
}

variants! {
    "second-order-f32-exact" => |o| o.second_order().map(Plain),
    "second-order-f32-fast" => |o| o.second_order().map(fast).map(Plain),
    "third-order-f32-exact" => |o| o.third_order().map(Plain),
    "third-order-f32-fast" => |o| o.third_order().map(fast).map(Plain),
    "kalman-f32-exact" => |o| o.kalman().map(Plain),
    "kalman-f32-fast" => |o| o.kalman().map(fast).map(Plain),
    "kalman-f32-fast-unmonitored" => |o| o.kalman().and_then(unmonitored).map(fast).map(Plain),
    "kalman-f32-fast-calibrated" => |o| o.kalman().map(fast).map(Calibrated),
    "kalman-f32-fast-calibrated-off" => |o| o.kalman().map(fast).map(CalibratedOff),
    "kalman-f32-fast-track" => |o| o.kalman().map(fast).map(Track),
    "kalman-f32-fast-track-unmonitored" => |o| o.kalman().and_then(unmonitored).map(fast).map(Track),
    "kalman-f32-fast-track-calibrated-off" => |o| o.kalman().map(fast).map(TrackCalibratedOff),
    "kalman-f32-fast-adc" => |o| Ok(Adc(fast(o.kalman()?), AdcScaling::twos_complement(12)?)),
    "kalman-f32-fast-angle-corrected" => |o| Ok(Corrected(fast(o.kalman()?), correction()?)),
    "kalman-fixed" => |o| o.fixed(),
    "kalman-fixed-track" => |o| o.fixed().map(FixedTrack),
    "kalman-fixed-track-unmonitored" => |o| o.fixed_unmonitored().map(FixedTrack),
    "baseline-atan2-pll-f32" => |o| Ok(o.pll::<LibmAtan2>()),
    "baseline-fast-atan2-pll-f32" => |o| Ok(o.pll::<FastAtan2>()),
}

/// The variant whose types the loop alone (`count loop`) runs with.
pub const LOOP_VARIANT: &str = "kalman-f32-fast-unmonitored";

/// The resolver front end's variant, counted per ADC sample pair: the synchronous
/// demodulator (`Demodulator::push`) alone.
pub const DEMODULATOR: &str = "demodulator-f32";

/// ADC samples of each winding per carrier period of the demodulator variant.
pub const SAMPLES_PER_PERIOD: usize = 16;

/// The demodulator variant's carrier amplitude at the ADC (counts) and delay (rad).
pub const CARRIER_AMPLITUDE_COUNTS: f32 = 1800.0;
/// The carrier delay of the demodulator variant's raw samples (rad, 305 degrees).
pub const CARRIER_DELAY_RAD: f32 = 5.323_254;

/// Bytes of one input sample or demodulated pair: `y_c`, `y_s` (f32, little endian).
pub const PAIR_BYTES: usize = 8;

/// The demodulator of the variant: a 10 kHz carrier, 16 samples per period, 12-bit ADC,
/// the delay resolved near its true value.
pub fn demodulator() -> Result<Demodulator<f32, SAMPLES_PER_PERIOD>, ConfigError> {
    let mut settings = DemodulatorSettings::new(10e3, CARRIER_AMPLITUDE_COUNTS, 0.0, 4095.0);
    settings.expected_delay_rad = CARRIER_DELAY_RAD - 0.5;
    Demodulator::new(settings)
}

/// The reference record of one demodulated pair (written by the build script only).
#[allow(dead_code)]
pub fn encode_pair(pair: &DemodulatedPair<f32>) -> [u8; PAIR_BYTES] {
    let mut r = [0; PAIR_BYTES];
    r[0..4].copy_from_slice(&pair.y_c.to_le_bytes());
    r[4..8].copy_from_slice(&pair.y_s.to_le_bytes());
    r
}

/// An input sample (amplitude about 1) in the fixed-point variant's counts: amplitude 2^14,
/// rounded; the same on the host and on the target.
pub fn fixed_counts(y: f32) -> i16 {
    let scaled = y * 16384.0;
    (if scaled >= 0.0 {
        scaled + 0.5
    } else {
        scaled - 0.5
    }) as i16
}

/// The core's fixed-point observer (`FixedGains::update`, `docs/theory.md §14`) on 16-bit
/// counts ([`fixed_counts`]), with its default diagnostics, and the sample period (s) its
/// estimate is converted with (in `f32`, outside the counted update).
#[derive(Debug, Clone, Copy)]
pub struct Fixed<const N: usize>(pub FixedGains<N>, pub f32);

impl<const N: usize> Tracker for Fixed<N>
where
    Order<N>: SupportedOrder,
{
    type State = FixedState<N>;
    type Input = i16;
    type Output = FixedEstimate;
    fn new_state(&self) -> FixedState<N> {
        FixedState::new()
    }
    fn input(y: f32) -> i16 {
        fixed_counts(y)
    }
    #[inline(always)]
    fn update(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) -> FixedEstimate {
        self.0.update(state, y_c, y_s)
    }
    fn record(&self, _: &FixedState<N>, e: &FixedEstimate) -> Record {
        // 2^-32 turn in rad, and 2^-F more for the acceleration's fraction bits.
        const RAD_PER_UNIT: f32 = core::f32::consts::TAU / 4_294_967_296.0;
        let acceleration_unit = RAD_PER_UNIT / (1u32 << self.0.acceleration_fraction_bits()) as f32;
        let rate = 1.0 / self.1;
        Record {
            angle: e.angle as f32 * RAD_PER_UNIT,
            turns: e.turns as i32,
            speed: e.speed as f32 * RAD_PER_UNIT * rate,
            acceleration: e.acceleration as f32 * acceleration_unit * rate * rate,
        }
    }
}

/// The core's fixed-point observer through `FixedGains::track` (the state updated, no
/// estimate returned), the estimate read on demand outside the counted update.
#[derive(Debug, Clone, Copy)]
pub struct FixedTrack<const N: usize>(pub Fixed<N>);

impl<const N: usize> Tracker for FixedTrack<N>
where
    Order<N>: SupportedOrder,
{
    type State = FixedState<N>;
    type Input = i16;
    type Output = ();
    fn new_state(&self) -> FixedState<N> {
        FixedState::new()
    }
    fn input(y: f32) -> i16 {
        fixed_counts(y)
    }
    #[inline(always)]
    fn update(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) {
        self.0.0.track(state, y_c, y_s);
    }
    fn record(&self, state: &FixedState<N>, _: &()) -> Record {
        self.0.record(state, &FixedGains::estimate(state))
    }
}
