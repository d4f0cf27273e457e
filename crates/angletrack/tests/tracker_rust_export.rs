//! A tracker file as a Rust `static` (`angletrack export --format rust`): the text against
//! its reference files (`tests/fixtures/tracker/`, which this test rewrites with
//! `ANGLETRACK_WRITE_FIXTURES=1`), and those files compiled here (the compiler evaluates
//! their `const` constructors) and run on the sensor the file describes: 12-bit counts with
//! offsets, imbalance, quadrature and a 3rd-harmonic angle error, in `f32` and fixed point.

use angletrack::export::GainsFile;
use angletrack::tracker_file::{
    AdcRange, Calibration, CaptureHead, Correction, Input, Language, NumberType, TrackerFile,
    TrackerRun,
};
use angletrack_core::{AngleCorrection, FaultThresholds, SensorCalibration, TrackerState};

mod exported_f32 {
    include!("fixtures/tracker/motor_f32.rs.txt");
}
mod exported_fixed {
    include!("fixtures/tracker/motor_fixed.rs.txt");
}

/// The sensor: offsets and amplitudes in counts, quadrature (rad).
const SENSOR: (f64, f64, f64, f64, f64) = (36.0, -36.0, 1800.0, 1854.0, 0.01);
/// The 3rd harmonic of the angle error (rad): cosine and sine coefficients.
const HARMONIC_3: (f64, f64) = (1.2e-3, 3.8e-3);
const SAMPLE_PERIOD_S: f64 = 50e-6;

fn harmonics() -> AngleCorrection<f64> {
    let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
    (a[2], b[2]) = HARMONIC_3;
    AngleCorrection::new(a, b).unwrap()
}

fn tracker_file(number_type: NumberType) -> TrackerFile {
    let gains = GainsFile {
        gains: vec![
            0.048770575499286,
            0.0012192008871052071,
            1.5239217375442759e-5,
        ],
        sample_period_s: SAMPLE_PERIOD_S,
        design: None,
    };
    let (o_c, o_s, a_c, a_s, phi) = SENSOR;
    TrackerFile {
        number_type,
        input: Input::Bits {
            bits: 12,
            signed: false,
        },
        adc_range: AdcRange::FullScale,
        fault_thresholds: Some(FaultThresholds::for_amplitude(1800.0)),
        calibration: Calibration::Stored(SensorCalibration::new(o_c, o_s, a_c, a_s, phi).unwrap()),
        correction: Correction::Harmonics(harmonics()),
        ..TrackerFile::new(gains)
    }
}

#[test]
fn the_rust_export_of_a_tracker_file_is_its_reference() {
    for (number_type, name) in [
        (NumberType::F32, "motor_f32.rs.txt"),
        (NumberType::Fixed, "motor_fixed.rs.txt"),
    ] {
        let text = tracker_file(number_type)
            .firmware_constants("motor.json", Language::Rust, "motor")
            .unwrap();
        let path = format!(
            "{}/tests/fixtures/tracker/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        if std::env::var_os("ANGLETRACK_WRITE_FIXTURES").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        assert_eq!(text, std::fs::read_to_string(&path).unwrap(), "{name}");
    }
}

/// The code of the sensor's channel at its reading `angle` (the truth plus its error).
fn counts(angle: f64) -> (i32, i32) {
    let (o_c, o_s, a_c, a_s, phi) = SENSOR;
    let code = |v: f64| 2048 + v.round() as i32;
    (
        code(o_c + a_c * angle.cos()),
        code(o_s + a_s * (angle + phi).sin()),
    )
}

fn wrap(angle: f64) -> f64 {
    (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[test]
fn the_exported_statics_track_the_sensor_the_file_describes() {
    let speed_rad_s = std::f64::consts::TAU * 30.0;
    let mut state_f32 = TrackerState::new();
    let mut state_fixed = TrackerState::new();
    let (mut worst_f32, mut worst_fixed): (f64, f64) = (0.0, 0.0);
    for k in 0..8000 {
        let truth = wrap(speed_rad_s * k as f64 * SAMPLE_PERIOD_S);
        let sample = counts(truth + harmonics().error_at(truth));
        let f = exported_f32::MOTOR_TRACKER.update(&mut state_f32, sample);
        let x = exported_fixed::MOTOR_TRACKER.update(&mut state_fixed, sample);
        if k >= 4000 {
            assert!(
                f.faults.is_empty() && x.faults.is_empty(),
                "{k}: {:?} {:?}",
                f.faults,
                x.faults
            );
            worst_f32 = worst_f32.max(wrap(f64::from(f.angle) - truth).abs());
            let fixed_angle = f64::from(x.angle) * std::f64::consts::TAU / 4294967296.0;
            worst_fixed = worst_fixed.max(wrap(fixed_angle - truth).abs());
        }
    }
    // 12-bit counts of an 1800-count signal: about 0.3 mrad of quantisation.
    assert!(
        worst_f32 < 1.5e-3 && worst_fixed < 1.5e-3,
        "{worst_f32} {worst_fixed}"
    );
}

/// The sensor's counts over `samples` samples: at rest for a while (a standstill is no
/// clipping), then accelerating to 30 turns/s, with a clipped stretch (the amplitude raised
/// beyond the 12-bit codes) and a dead sine channel near the end, so that the flags have
/// something to say.
fn capture(samples: usize) -> (Vec<f64>, Vec<f64>) {
    let mut angle = 0.4;
    let (mut y_c, mut y_s) = (Vec::new(), Vec::new());
    for k in 0..samples {
        let speed = if k < 1500 {
            0.0
        } else {
            std::f64::consts::TAU * 30.0 * ((k - 1500) as f64 / 3000.0).min(1.0)
        };
        angle = wrap(angle + speed * SAMPLE_PERIOD_S);
        let (mut c, mut s) = counts(angle + harmonics().error_at(angle));
        if (6000..6300).contains(&k) {
            (c, s) = (
                (2048 + (c - 2048) * 5 / 4).clamp(0, 4095),
                (2048 + (s - 2048) * 5 / 4).clamp(0, 4095),
            );
        }
        if k >= 7500 {
            s = 2048;
        }
        y_c.push(f64::from(c));
        y_s.push(f64::from(s));
    }
    (y_c, y_s)
}

/// The same tracker file through the exported `static` (a firmware's Rust) and through
/// [`TrackerRun`] (what `angletrack track --tracker` and Python's `Tracker` hold), the
/// latter fed in uneven chunks: the same angles and flags, bit for bit, in `f32` and in
/// fixed point (issue 35, item 5).
#[test]
fn the_exported_static_and_the_host_run_of_a_file_agree_bit_for_bit() {
    let (y_c, y_s) = capture(9000);
    let head = CaptureHead {
        y_c: &y_c,
        y_s: &y_s,
        counts: None,
    };
    for number_type in [NumberType::F32, NumberType::Fixed] {
        let mut run = TrackerRun::new(&tracker_file(number_type), "motor.json", &head).unwrap();
        let mut rows = angletrack::tracker_file::TrackedRows::default();
        let mut start = 0;
        for (k, size) in [1, 999, 4096, 17, 5000].into_iter().cycle().enumerate() {
            if start >= y_c.len() || k > 20 {
                break;
            }
            let end = (start + size).min(y_c.len());
            let part = run.track(&y_c[start..end], &y_s[start..end]);
            rows.angle_rad.extend(part.angle_rad);
            rows.faults.extend(part.faults);
            rows.front_end_faults.extend(part.front_end_faults);
            start = end;
        }
        assert_eq!(rows.angle_rad.len(), y_c.len());
        let (mut state_f32, mut state_fixed) = (TrackerState::new(), TrackerState::new());
        let mut flagged = 0;
        for (k, (&c, &s)) in y_c.iter().zip(&y_s).enumerate() {
            let sample = (c as i32, s as i32);
            let (angle, faults, front_end) = match number_type {
                NumberType::F32 => {
                    let e = exported_f32::MOTOR_TRACKER.update(&mut state_f32, sample);
                    (f64::from(e.angle), e.faults, state_f32.front_end.faults())
                }
                _ => {
                    let e = exported_fixed::MOTOR_TRACKER.update(&mut state_fixed, sample);
                    (
                        f64::from(e.angle) * std::f64::consts::PI / 2147483648.0,
                        e.faults,
                        state_fixed.front_end.faults(),
                    )
                }
            };
            assert_eq!(
                rows.angle_rad[k].to_bits(),
                angle.to_bits(),
                "{number_type:?} {k}"
            );
            assert_eq!(
                (rows.faults[k], rows.front_end_faults[k]),
                (faults.bits(), front_end.bits()),
                "{number_type:?} {k}"
            );
            flagged += usize::from(faults.bits() != 0 || front_end.bits() != 0);
        }
        // Not trivially equal: the clipping and the dead channel were flagged, the
        // standstill was not.
        assert!(
            (300..9000 - 1500).contains(&flagged),
            "{number_type:?}: {flagged}"
        );
        assert!(
            rows.faults[..1500].iter().skip(100).all(|&f| f == 0),
            "{number_type:?}"
        );
    }
}

/// FNV-1a over each sample's angle bits (`f32` bits for the float chain, the binary angle
/// for fixed point; little-endian) and its fault byte: what the C door's identity test
/// (`crates/angletrack-c/tests/c/test_host_identity.c`) computes on its own run.
fn fnv1a(rows: &angletrack::tracker_file::TrackedRows, fixed: bool) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for (k, &faults) in rows.faults.iter().enumerate() {
        let bits = if fixed {
            rows.angle_binary[k] as u32
        } else {
            (rows.angle_rad[k] as f32).to_bits()
        };
        for byte in bits.to_le_bytes().into_iter().chain([faults]) {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    hash
}

/// The C door's identity test's inputs and expectations (`crates/angletrack-c/tests/c/identity/`,
/// rewritten with `ANGLETRACK_WRITE_FIXTURES=1`): the capture as 12-bit codes, the C
/// headers `angletrack export --format c` writes for the two tracker files (the f32 one's
/// thresholds left out: its C header does not carry them yet, so the C program states the
/// amplitude; the fixed-point chain's constants carry them; the fixed-point one also as
/// `tests/c/guide/motor.h`, the C guide's example's), and the hash of [`TrackerRun`]'s angles and flags on the capture. Held here
/// to what `TrackerRun` gives now, so that they cannot go stale.
#[test]
fn the_c_identity_fixtures_are_the_host_run_of_the_files() {
    let (y_c, y_s) = capture(9000);
    let head = CaptureHead {
        y_c: &y_c,
        y_s: &y_s,
        counts: None,
    };
    let dir = format!(
        "{}/../angletrack-c/tests/c/identity",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut capture_bytes = Vec::new();
    for (&c, &s) in y_c.iter().zip(&y_s) {
        capture_bytes.extend((c as u16).to_le_bytes());
        capture_bytes.extend((s as u16).to_le_bytes());
    }
    let mut files = vec![("capture.bin".to_string(), capture_bytes)];
    let mut expected = String::from(
        "/* The C door's identity test: what the Rust crate's TrackerRun gives on capture.bin with\n \
         * the tracker files of motor_f32.h and motor_fixed.h (FNV-1a over each sample's angle bits\n \
         * and faults). Generated by crates/angletrack/tests/tracker_rust_export.rs. */\n\
         #define IDENTITY_SAMPLES 9000\n#define IDENTITY_AMPLITUDE_COUNTS 1800.0\n",
    );
    for (number_type, name) in [(NumberType::F32, "f32"), (NumberType::Fixed, "fixed")] {
        let file = tracker_file(number_type);
        let rows = TrackerRun::new(&file, "motor.json", &head)
            .unwrap()
            .track(&y_c, &y_s);
        let upper = name.to_uppercase();
        expected += &format!(
            "#define IDENTITY_{upper}_HASH 0x{:016x}ULL\n#define IDENTITY_{upper}_FLAGGED {}\n",
            fnv1a(&rows, number_type == NumberType::Fixed),
            rows.faults.iter().filter(|&&f| f != 0).count()
        );
        // The fixed-point chain's constants carry the monitor's thresholds; the f32 header
        // does not yet (the C program states the amplitude).
        let file_for_c = match number_type {
            NumberType::Fixed => file,
            _ => TrackerFile {
                fault_thresholds: None,
                ..file
            },
        };
        let header = file_for_c
            .firmware_constants("motor.json", Language::C, &format!("motor_{name}"))
            .unwrap();
        files.push((format!("motor_{name}.h"), header.into_bytes()));
        if number_type == NumberType::Fixed {
            // The C guide's example of the fixed-point chain from its integers.
            let guide = file_for_c.firmware_constants("motor.json", Language::C, "motor");
            files.push(("../guide/motor.h".to_string(), guide.unwrap().into_bytes()));
        }
    }
    files.push(("expected.h".to_string(), expected.into_bytes()));
    for (name, bytes) in files {
        let path = format!("{dir}/{name}");
        if std::env::var_os("ANGLETRACK_WRITE_FIXTURES").is_some() {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &bytes).unwrap();
        }
        let stored = std::fs::read(&path).unwrap();
        // Text shown as text: a changed hash is then readable.
        assert_eq!(
            String::from_utf8_lossy(&stored),
            String::from_utf8_lossy(&bytes),
            "{name}: rewrite with ANGLETRACK_WRITE_FIXTURES=1"
        );
        assert_eq!(stored, bytes, "{name}");
    }
}
