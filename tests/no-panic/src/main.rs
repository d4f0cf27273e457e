//! Every f32 per-sample entry point of the core (a chain's `track`, `update`,
//! `update_block`, `track_bank` and `update_bank`: with no front end, with every front-end
//! stage, with a sin/cos unit; the resolver front end) and the fixed-point chain's, fed with values the optimiser cannot see (`black_box`). The panic handler below is only kept by the linker if some path
//! of these calls can panic; `scripts/test.d/40-robustness.sh` builds the image for a
//! Cortex-M4F (thumbv7em-none-eabihf) and a Cortex-M0 (thumbv6m-none-eabi, soft float) and
//! fails when the handler's symbol is in either.
#![no_std]
#![no_main]

use core::hint::black_box;

use angletrack_core::{
    AdcCounts, AdcScaling, AngleCorrection, AngleCorrectionTable, CalibrationSettings, Calibrator,
    Chain, ChainState, ChannelBank, Demodulator, DemodulatorSettings, DemodulatorState,
    DriveOutputs, DriveOutputsState, Estimate, Exact, Excitation, ExcitationState, Fast,
    FixedAngleCorrectionTable, FixedCalibration, FixedGains, FixedState, Gains,
    MAX_CORRECTION_ORDER, ObserverState, OnlineCalibration, Order, SensorCalibration, SinCos,
    SupportedOrder, Waveform,
};
use cortex_m_rt::entry;

fn exercise<const N: usize, S: SinCos<f32>>(l: [f32; N]) -> f32
where
    Order<N>: SupportedOrder,
{
    let Ok(gains) = Gains::<f32, N, S>::new(black_box(l), black_box(1e-4)) else {
        return 0.0;
    };
    // The observer alone: a chain with no front end.
    let bare = Chain::new((), gains);
    let mut chained = ChainState::new();
    let mut sum = 0.0;
    for _ in 0..black_box(8) {
        let e = bare.update(&mut chained, (black_box(0.5), black_box(0.5)));
        sum += e.angle + e.speed + e.acceleration + e.phase_error + e.faults.bits() as f32;
        bare.track(&mut chained, (black_box(0.5), black_box(-0.5)));
    }
    let samples = black_box([(0.25f32, 0.25f32); 16]);
    let mut out = [Estimate::default(); 16];
    let n = bare.update_block(&mut chained, samples, &mut out);
    let mut state = chained.observer;
    sum += corrected(&gains);
    // Its phase detector's sin/cos by a unit with state.
    let unit = Chain::new((), gains.with_unit::<S>());
    let mut united = ChainState {
        front_end: (),
        observer: (ObserverState::new(), S::default()),
    };
    sum += unit
        .update(&mut united, (black_box(1.0), black_box(0.0)))
        .angle;
    // A bank of channels: its update (side by side and lane by lane), block update and
    // accessors.
    let mut banked = ChainState::<[(); 4], ChannelBank<f32, N, 4>>::new_bank();
    for _ in 0..black_box(4) {
        bare.track_bank(&mut banked, &black_box([(0.5, -0.5); 4]));
    }
    let bank = banked.observer;
    sum += bank.angles()[1] + bank.turns()[2] as f32 + bank.phase_errors()[0];
    if let Some(e) = gains.bank_estimate(&bank, black_box(2)) {
        sum += e.angle + e.speed;
    }
    // A chain's bank form: an online calibration (learning: lane by lane with the
    // feedback; off: side by side).
    if let Ok(online) = OnlineCalibration::new(CalibrationSettings::default(), black_box(1e-4)) {
        let chain = Chain::new(online, gains);
        let mut banked = ChainState::<[Calibrator<f32>; 4], ChannelBank<f32, N, 4>>::new_bank();
        if black_box(true) {
            banked.front_end[1].enable();
        }
        let inputs = black_box([(0.5f32, -0.5f32); 4]);
        for _ in 0..black_box(4) {
            chain.track_bank(&mut banked, &inputs);
        }
        let e = chain.update_bank(&mut banked, &inputs);
        sum += e[black_box(1) % 4].angle + banked.observer.latched_faults()[3].bits() as f32;
    }
    sum += raw_and_calibrated(&gains);
    sum + out[black_box(3) % 16].angle + n as f32 + state.clear_faults().bits() as f32
}

/// The ADC entry point (every sample type) and the online calibration (learning, frozen,
/// written and read), with their constructors.
fn raw_and_calibrated<const N: usize, S: SinCos<f32>>(gains: &Gains<f32, N, S>) -> f32
where
    Order<N>: SupportedOrder,
{
    let mut sum = 0.0;
    let mut state = ObserverState::new();
    if let Ok(adc) = AdcScaling::<f32>::new(black_box(2048), black_box(2048.0)) {
        let chain = Chain::new(adc, *gains);
        let mut chained = ChainState {
            front_end: (),
            observer: state,
        };
        sum += chain
            .update(&mut chained, (black_box(4095u16), black_box(0u16)))
            .angle;
        sum += chain
            .update(&mut chained, (black_box(-7i16), black_box(9i16)))
            .angle;
        sum += chain
            .update(&mut chained, (black_box(i32::MIN), black_box(i32::MAX)))
            .angle;
        state = chained.observer;
    }
    if let Ok(adc) = AdcScaling::<f32>::offset_binary(black_box(12)) {
        sum += adc.scale(black_box(17u16));
    }
    let mut settings = CalibrationSettings::default();
    settings.min_speed_rad_s = Some(black_box(20.0));
    let Ok(gains) = gains.with_calibration_settings(settings) else {
        return sum;
    };
    let learning = Chain::new(gains.online_calibration(), gains);
    let mut learnt = ChainState {
        front_end: Calibrator::new(),
        observer: state,
    };
    learnt.front_end.enable();
    let mut angle = 0.0f32;
    for _ in 0..black_box(400) {
        angle = if angle > 3.0 {
            angle - 6.2
        } else {
            angle + 0.05
        };
        let (y_c, y_s) = (black_box(angle * 0.3), black_box(0.9 - angle * angle * 0.1));
        sum += learning.update(&mut learnt, (y_c, y_s)).angle;
    }
    learnt.front_end.freeze();
    sum += learning.update(&mut learnt, (0.5, 0.5)).speed;
    let ChainState {
        front_end: mut calibrator,
        observer: state,
    } = learnt;
    let stored = calibrator.calibration();
    let (o_c, o_s, a_c, a_s, phi) = stored.parameters();
    if let Ok(loaded) = SensorCalibration::new(o_c, o_s, a_c, black_box(a_s), phi) {
        calibrator.set_calibration(loaded);
    }
    sum + o_c + state.amplitude() + calibrator.turns_learned() as f32
}

/// The angle-harmonic correction (order 4), alone and after the calibration.
fn corrected<const N: usize, S: SinCos<f32>>(gains: &Gains<f32, N, S>) -> f32
where
    Order<N>: SupportedOrder,
{
    let (mut a, mut b) = (
        [0.0f32; MAX_CORRECTION_ORDER],
        [0.0f32; MAX_CORRECTION_ORDER],
    );
    a[..4].copy_from_slice(&black_box([2e-3, -1e-3, 5e-4, 1.5e-3]));
    b[..4].copy_from_slice(&black_box([-1e-3, 3e-3, -5e-4, 1e-3]));
    let Ok(correction) = AngleCorrection::new(a, b) else {
        return 0.0;
    };
    let learning = Chain::new(gains.online_calibration(), *gains);
    let mut learnt = ChainState::<Calibrator<f32>, ObserverState<f32, N>>::new();
    let mut sum = 0.0;
    // The chain of every float stage: counts, a stored calibration, the online one (its
    // mode changed on the way), the harmonics and their table.
    let Ok(adc) = AdcScaling::<f32>::offset_binary(black_box(12)) else {
        return 0.0;
    };
    let Ok(stored) = SensorCalibration::new(black_box(0.01), 0.0, 1.0, 1.02, 0.01) else {
        return 0.0;
    };
    let Ok(online) = OnlineCalibration::new(CalibrationSettings::default(), gains.sample_period())
    else {
        return 0.0;
    };
    let table = AngleCorrectionTable::<f32, 256>::from_harmonics(&correction);
    let chain = Chain::new((adc, (stored, (online, (correction, table)))), *gains);
    let mut chain_state =
        ChainState::<((), ((), (Calibrator<f32>, ((), ())))), ObserverState<f32, N>>::new();
    chain_state.front_end.1.1.0.enable();
    for k in 0..black_box(8u16) {
        let (y_c, y_s) = (black_box(0.6), black_box(-0.8));
        sum += learning.update(&mut learnt, (y_c, y_s)).speed;
        let raw = (black_box(2048 + 100 * k), black_box(4000 - 100 * k));
        sum += chain.update(&mut chain_state, raw).angle;
        chain.track(&mut chain_state, raw);
        if k == black_box(4) {
            chain_state.front_end.1.1.0.freeze();
        }
    }
    sum += chain.estimate(&chain_state).speed + table.error_at(black_box(0.3));
    sum + correction.error_at(black_box(0.3))
}

/// The resolver front end's per-sample entry points: the excitation's tick, the
/// demodulator's push and push_block (then the observer's chain), the drive outputs.
fn front_end() -> f32 {
    let Ok(excitation) = Excitation::new(black_box(10_000), black_box(160_000), Waveform::Sine)
    else {
        return 0.0;
    };
    let settings = DemodulatorSettings::new(black_box(1e4), 1.6e5, 1800.0, 0.0, 4095.0);
    let Ok(demodulator) = Demodulator::<f32>::new(settings) else {
        return 0.0;
    };
    let Ok(gains) = Gains::<f32, 3>::new(black_box([0.5, 0.18, 0.03]), black_box(1e-4)) else {
        return 0.0;
    };
    let Ok(outputs) = DriveOutputs::<f32>::new(black_box(4), black_box(1), 6e-5, 1e-4) else {
        return 0.0;
    };
    let mut carrier = ExcitationState::default();
    let chain = Chain::new((), gains);
    let (mut front_end, mut observer) = (DemodulatorState::new(), ChainState::new());
    let mut drive = DriveOutputsState::default();
    let mut sum = 0.0;
    for _ in 0..black_box(640) {
        let dac: f32 = excitation.tick(&mut carrier);
        let (c, s) = (black_box(2048.0 + dac), black_box(2048.0 - dac));
        if let Some(pair) = demodulator.push(&mut front_end, c, s) {
            sum += pair.y_c + pair.faults.bits() as f32;
        }
        if let Some(pair) = demodulator.push(&mut front_end, c, s) {
            let e = chain.update(&mut observer, (pair.y_c, pair.y_s));
            let angle = outputs.outputs(&mut drive, &e);
            sum += angle.electrical_angle + angle.mechanical_turns as f32;
        }
    }
    let block = black_box([2048.0f32; 37]);
    demodulator.push_block(&mut front_end, &block, &block[1..], |pair| sum += pair.y_s);
    sum + front_end.clear_faults().bits() as f32
}

/// The fixed-point observer (`docs/theory.md §14`): construction, its update on the extreme
/// `i16` samples and others the optimiser cannot see, and its estimate.
fn fixed_point<const N: usize>(l: [f64; N]) -> f32
where
    Order<N>: SupportedOrder,
{
    let Ok(gains) = FixedGains::<N>::new(black_box(l), black_box(1e-4)) else {
        return 0.0;
    };
    let Ok(gains) = gains.with_monitor(black_box(Some(20_000.0))) else {
        return 0.0;
    };
    let bare = Chain::new((), gains);
    let mut state = ChainState::<(), FixedState<N>>::new();
    let mut sum = 0i64;
    for k in 0..black_box(8i16) {
        let (y_c, y_s) = (black_box(i16::MIN + k), black_box(i16::MAX - k));
        let e = bare.update(&mut state, (y_c, y_s));
        sum += e.turns + i64::from(e.angle) + i64::from(e.speed) + i64::from(e.phase_error);
        bare.track(&mut state, (black_box(y_s), black_box(y_c)));
    }
    let e = bare.estimate(&state);
    sum += i64::from(e.acceleration) + i64::from(state.observer.latched_faults().bits());
    // The fixed-point chain of every integer stage, on each counts type.
    let Ok(stored) =
        SensorCalibration::<f64>::new(black_box(300.0), -200.0, 16000.0, 17000.0, 0.02)
    else {
        return 0.0;
    };
    let Ok(calibration) = FixedCalibration::new(&stored) else {
        return 0.0;
    };
    let (mut a, b) = (
        [0.0f64; MAX_CORRECTION_ORDER],
        [0.0f64; MAX_CORRECTION_ORDER],
    );
    a[2] = black_box(4e-3);
    let Ok(harmonics) = AngleCorrection::new(a, b) else {
        return 0.0;
    };
    let table = FixedAngleCorrectionTable::<256>::from_harmonics(&harmonics);
    let (Ok(unsigned), Ok(signed)) = (
        AdcCounts::offset_binary(black_box(12)),
        AdcCounts::twos_complement(black_box(16)),
    ) else {
        return 0.0;
    };
    let chain = Chain::new((unsigned, (calibration, table)), gains);
    let signed_chain = Chain::new((signed, (calibration, table)), gains);
    let mut chain_state = ChainState::new();
    for k in 0..black_box(8u16) {
        let e = chain.update(&mut chain_state, (black_box(4095 - k), black_box(k)));
        sum += i64::from(e.angle) + e.turns;
        signed_chain.track(&mut chain_state, (black_box(i16::MIN), black_box(i16::MAX)));
        signed_chain.track(&mut chain_state, (black_box(i32::MIN), black_box(i32::MAX)));
    }
    (sum + i64::from(chain.estimate(&chain_state).speed)) as f32
}

#[entry]
fn main() -> ! {
    // One line per entry point (or family of them, generic over the order and sin/cos).
    let mut sum = exercise::<2, Fast>([0.06, 0.001]);
    sum += front_end();
    sum += exercise::<3, Fast>([0.06, 0.0019, 3e-5]);
    if cfg!(feature = "exact") {
        sum += exercise::<2, Exact>([0.06, 0.001]);
        sum += exercise::<3, Exact>([0.06, 0.0019, 3e-5]);
    }
    if cfg!(feature = "fixed-point") {
        sum += fixed_point::<2>([0.06, 0.001]);
        sum += fixed_point::<3>([0.06, 0.0019, 3e-5]);
    }
    if cfg!(feature = "panic-control") {
        let table = black_box([1.0f32; 4]);
        sum += table[black_box(7usize)];
    }
    black_box(sum);
    loop {
        black_box(());
    }
}

/// Kept in the image only if a panic path remains.
#[panic_handler]
fn angletrack_panic_path_exists(_: &core::panic::PanicInfo) -> ! {
    loop {
        black_box(());
    }
}
