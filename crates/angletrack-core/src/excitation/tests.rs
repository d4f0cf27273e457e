use super::*;

#[test]
// 160,000 ticks: minutes under Miri's interpreter, which checks memory safety, not this
// arithmetic; every other run (the test command's `cargo test`) runs it.
#[cfg_attr(miri, ignore)]
fn the_phase_returns_exactly_after_one_second_of_ticks() {
    // 7 kHz at 160 kHz: 2^32 * 7000 / 160000 is not an integer.
    let excitation = Excitation::new(7_000, 160_000, Waveform::Sine).unwrap();
    let mut state = ExcitationState::default();
    for _ in 0..160_000 {
        let _: f32 = excitation.tick(&mut state);
    }
    assert_eq!(state, ExcitationState::default());
    assert_eq!(excitation.samples_per_period(), None);
}

#[test]
fn sine_and_square_follow_the_phase() {
    let sine = Excitation::new(10_000, 160_000, Waveform::Sine).unwrap();
    let square = Excitation::new(10_000, 160_000, Waveform::Square).unwrap();
    let (mut a, mut b) = (ExcitationState::default(), ExcitationState::default());
    for k in 0..64 {
        let expected = (core::f64::consts::TAU * k as f64 / 16.0).sin();
        let value: f64 = sine.tick(&mut a);
        assert!(
            (value - expected).abs() < 1e-12,
            "tick {k}: {value} vs {expected}"
        );
        let sq: f32 = square.tick(&mut b);
        assert_eq!(sq, if k % 16 < 8 { 1.0 } else { -1.0 });
    }
}

#[test]
fn refuses_zero_and_aliasing_rates() {
    let p = |c, r| {
        Excitation::new(c, r, Waveform::Sine)
            .unwrap_err()
            .parameter()
    };
    assert_eq!(p(0, 1000), Parameter::CarrierFrequency);
    assert_eq!(p(10, 0), Parameter::TickRate);
    assert_eq!(p(500, 1000), Parameter::CarrierFrequency);
}

#[test]
fn peak_time_covers_every_delay() {
    let excitation = Excitation::new(10_000, 160_000, Waveform::Sine).unwrap();
    for degrees in [0.0f64, 90.0, 180.0, 305.0, -30.0] {
        let delay = degrees.to_radians();
        let t: f64 = excitation.peak_sample_time_s(delay);
        assert!((0.0..1e-4).contains(&t));
        let carrier = (core::f64::consts::TAU * 1e4 * t - delay).sin();
        assert!((carrier - 1.0).abs() < 1e-9, "{degrees}: {carrier}");
    }
}
