//! The reader on real exports (decimal commas, instruments' metadata lines, Latin-1 and
//! UTF-16 text, an ignored time column, rounded stamps, deflated `.npz`), and outputs that
//! never replace an input nor stay half written.

use super::*;
use std::io::Write;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("angletrack_capture_real_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn file(name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn read(name: &str, bytes: &[u8], options: CaptureOptions) -> Result<Capture, CaptureError> {
    read_capture(file(name, bytes), options)
}

fn columns(map: &str) -> CaptureOptions {
    CaptureOptions {
        columns: map.parse().unwrap(),
        ..Default::default()
    }
}

#[test]
fn decimal_commas_are_sniffed_beside_semicolons_and_stated_beside_blanks() {
    let text = b"Zeit;cos;sin\n0;1;0\n0,5;0,5;-0,866\n1;0;1E-3\n";
    let c = read("comma.csv", text, columns("time=Zeit")).unwrap();
    assert_eq!(c.samples.y_c, [1.0, 0.5, 0.0]);
    assert_eq!(c.samples.y_s, [0.0, -0.866, 1e-3]);
    assert_eq!(c.format, "text, delimiter ;, decimal comma");
    let stated = CaptureOptions {
        decimal: Some(DecimalMark::Comma),
        ..columns("y_c=0,y_s=1")
    };
    let c = read("blanks.txt", b"0,25 1\n0,5 2\n", stated).unwrap();
    assert_eq!(c.samples.y_c, [0.25, 0.5]);
}

#[test]
fn an_oscilloscope_export_skips_its_metadata_lines() {
    let text = "Model,MSO44\nFirmware Version,1.24\nRecord Length,3\nSample Interval,1e-4\n\
                Label,,\nTIME,CH1,CH2\n0,1,0\n1e-4,0.5,0.866\n2e-4,0,1\n";
    let c = read("scope.csv", text.as_bytes(), columns("y_c=CH1,y_s=CH2")).unwrap();
    assert_eq!(c.samples.y_s, [0.0, 0.866, 1.0]);
    assert_eq!(c.mapping[0], (Role::Time, "TIME".to_string()));
    assert_eq!(c.format, "text, delimiter ,, 5 metadata lines skipped");
    // Metadata of the data's width is not told from a header: it is stated.
    let text = b"Rate,1e4,Hz\nProbe,10,x\nt,cos,sin\n0,1,0\n1e-4,1,0\n";
    assert!(read("same_width.csv", text, columns("")).is_err());
    let stated = CaptureOptions {
        skip_rows: 2,
        ..Default::default()
    };
    let c = read("same_width.csv", text, stated).unwrap();
    assert_eq!(c.samples.y_c, [1.0, 1.0]);
    // A header wider than its rows is the header, after metadata or not.
    for text in [
        "t,y_c,y_s,\n0,1,0\n1e-4,1,0\n",
        "Model,X\nt,y_c,y_s,\n0,1,0\n1e-4,1,0\n",
    ] {
        let c = read("wide.csv", text.as_bytes(), columns("")).unwrap();
        assert_eq!(c.mapping[0], (Role::Time, "t".to_string()), "{text}");
    }
    // A malformed first row is an error, not metadata.
    let e = read(
        "bad_row.csv",
        b"1,2\n0,1,0\n1,1,0\n",
        columns("y_c=1,y_s=2"),
    );
    let e = e.unwrap_err().to_string();
    assert!(e.contains("columns: y_s=2 names no column"), "{e}");
}

#[test]
fn latin1_and_utf16_text_is_decoded() {
    let latin1 = b"Zeit (\xb5s);cos;sin\n0;1;0\n100;0,5;0,5\n";
    let options = CaptureOptions {
        time_unit: TimeUnit::Microseconds,
        ..columns("time=Zeit (\u{b5}s)")
    };
    let c = read("latin1.csv", latin1, options.clone()).unwrap();
    assert_eq!(c.samples.time_s.as_deref(), Some(&[0.0, 1e-4][..]));
    assert_eq!(c.format, "text, delimiter ;, decimal comma, Latin-1");
    for (name, bom, le) in [
        ("le.csv", [0xFF, 0xFE], true),
        ("be.csv", [0xFE, 0xFF], false),
    ] {
        let text = "Zeit (µs);cos;sin\r\n0;1;0\r\n100;0,5;0,5\r\n";
        let mut bytes = bom.to_vec();
        for u in text.encode_utf16() {
            bytes.extend(if le { u.to_le_bytes() } else { u.to_be_bytes() });
        }
        let c = read(name, &bytes, options.clone()).unwrap();
        assert_eq!(c.samples.y_s, [0.0, 0.5], "{name}");
    }
    let e = read("binary.csv", b"t,y_c\n\x01\x02\xff\n", columns("")).unwrap_err();
    assert!(e.to_string().contains("binary data (byte 0x01)"), "{e}");
}

#[test]
fn a_time_column_can_be_ignored_and_rounded_stamps_pass_with_a_stated_rate() {
    let rounded = b"time,y_c,y_s\n0,1,0\n0,1,0\n0.001,1,0\n0.001,1,0\n";
    let c = read("ignored.csv", rounded, columns("time=-")).unwrap();
    assert!(c.samples.time_s.is_none() && c.sample_rate_hz.is_none());
    assert!(read("rounded.csv", rounded, columns("")).is_err());
    let stated = CaptureOptions {
        sample_rate_hz: Some(2000.0),
        ..Default::default()
    };
    let c = read("rounded.csv", rounded, stated.clone()).unwrap();
    assert_eq!(c.samples.time_s.unwrap(), [0.0, 0.0, 0.001, 0.001]);
    let e = read("back.csv", b"time,y_c,y_s\n1,1,0\n0,1,0\n", stated).unwrap_err();
    assert!(
        e.to_string()
            .contains("back.csv:3:1: column \"time\": unsorted"),
        "{e}"
    );
    let e = "y_c=-".parse::<ColumnMap>().unwrap_err();
    assert!(e.contains("y_c=-"), "{e}");
}

#[test]
fn one_column_for_two_roles_is_refused() {
    let e = read(
        "twice.csv",
        b"t,a,b\n0,1,0\n1,1,0\n",
        columns("y_c=1,y_s=1"),
    );
    let e = e.unwrap_err().to_string();
    assert!(
        e.contains("columns: y_c and y_s are both column 1 (\"a\")"),
        "{e}"
    );
    let e = read("time_too.csv", b"t,a\n0,1\n1,1\n", columns("y_c=a,y_s=t"));
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("time and y_s are both column 0")
    );
}

fn estimates(n: usize) -> (Vec<f64>, Vec<f32>, Vec<u8>) {
    let time: Vec<f64> = (0..n).map(|k| k as f64 * 1e-4).collect();
    let angle: Vec<f32> = (0..n).map(|k| (k as f32 * 0.01).sin()).collect();
    (time, angle, (0..n).map(|k| (k % 3) as u8).collect())
}

fn write_estimates(path: &Path, n: usize) -> Result<u64, CaptureError> {
    let (time, angle, faults) = estimates(n);
    let mut w = EstimatesWriter::create::<f32>(path)?;
    for range in [0..n / 2, n / 2..n] {
        w.write(EstimateRows {
            time_s: &time[range.clone()],
            angle: &angle[range.clone()],
            position: &time[range.clone()],
            speed: &angle[range.clone()],
            acceleration: &angle[range.clone()],
            phase_error: &angle[range.clone()],
            faults: &faults[range],
        })?;
    }
    w.finish()
}

#[test]
fn estimates_in_npz_stream_back_in_chunks_and_other_extensions_are_refused() {
    let path = dir().join("est.npz");
    assert_eq!(write_estimates(&path, 1001).unwrap(), 1001);
    let options = CaptureOptions {
        chunk_rows: 100,
        ..columns("time=time_s,y_c=angle_rad,y_s=speed_rad_s,reference=position_rad")
    };
    let mut reader = CaptureReader::open(&path, options).unwrap();
    let (time, angle, _) = estimates(1001);
    let mut k = 0;
    while let Some(chunk) = reader.next_chunk().unwrap() {
        for (i, &v) in chunk.y_c.iter().enumerate() {
            assert_eq!(v, f64::from(angle[k + i]));
        }
        k += chunk.len();
    }
    assert_eq!(k, 1001);
    assert_eq!(reader.sample_dtype(), "float32");
    assert!((reader.sample_rate_hz().unwrap() - 1e4).abs() < 1e-6);
    assert_eq!(time.len(), 1001);
    let e = write_estimates(&dir().join("est.dat"), 4).unwrap_err();
    assert!(e.to_string().contains(".csv (text), .npy"), "{e}");
    assert!(!dir().join("est.dat").exists());
}

#[test]
fn a_deflated_npz_streams_like_a_stored_one() {
    let path = dir().join("deflated.npz");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, values) in [("cos", [1.0f64, 0.5, 0.0]), ("sin", [0.0, 0.866, 1.0])] {
        zip.start_file(format!("{name}.npy"), options).unwrap();
        zip.write_all(&npy_out::npy_header("'<f8'", "(3,)", 0))
            .unwrap();
        values
            .iter()
            .for_each(|v| zip.write_all(&v.to_le_bytes()).unwrap());
    }
    zip.finish().unwrap();
    let c = read_capture(&path, columns("y_c=cos,y_s=sin")).unwrap();
    assert_eq!(c.samples.y_s, [0.0, 0.866, 1.0]);
}

#[test]
fn an_output_that_is_an_input_is_refused_in_every_spelling() {
    let d = dir().join("outputs");
    std::fs::create_dir_all(d.join("out")).unwrap();
    let capture = d.join("capture.csv");
    std::fs::write(&capture, "y_c,y_s\n1,0\n").unwrap();
    let link = d.join("link.csv");
    let hard = d.join("hard.csv");
    let _ = std::fs::remove_file(&link);
    let _ = std::fs::remove_file(&hard);
    #[cfg(unix)]
    std::os::unix::fs::symlink(&capture, &link).unwrap();
    std::fs::hard_link(&capture, &hard).unwrap();
    let inputs = [("capture", capture.as_path())];
    for output in [
        capture.clone(),
        d.join("out").join("..").join("capture.csv"),
        link.clone(),
        hard.clone(),
    ] {
        if !output.exists() {
            continue;
        }
        let e = check_outputs(&[("--output", &output)], &inputs).unwrap_err();
        assert!(e.to_string().contains("--output: is the capture"), "{e}");
    }
    // Through directories that do not exist yet (the run would create them), and an output
    // whose own directory does not.
    for output in [
        d.join("new").join("..").join("capture.csv"),
        d.join("new")
            .join("deeper")
            .join("..")
            .join("..")
            .join("capture.csv"),
        d.join("out")
            .join("new")
            .join(".")
            .join("..")
            .join("..")
            .join("link.csv"),
    ] {
        let e = check_outputs(&[("--output", &output)], &inputs).unwrap_err();
        assert!(e.to_string().contains("--output: is the capture"), "{e}");
    }
    let e = check_outputs(
        &[
            ("--output", &d.join("new").join("a.csv")),
            (
                "--plot",
                &d.join("other").join("..").join("new").join("a.csv"),
            ),
        ],
        &inputs,
    );
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("--plot: is the --output")
    );
    assert!(check_outputs(&[("--output", &d.join("new").join("capture.csv"))], &inputs).is_ok());
    let a = d.join("a.csv");
    let e = check_outputs(&[("--output", &a), ("--calibration-out", &a)], &inputs);
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("--calibration-out: is the --output")
    );
    assert!(check_outputs(&[("--output", &a)], &inputs).is_ok());
    // A run that fails part way leaves the old file and no temporary file.
    std::fs::write(&a, "old").unwrap();
    let (time, angle, faults) = estimates(3);
    let mut w = EstimatesWriter::create::<f32>(&a).unwrap();
    let rows = EstimateRows {
        time_s: &time,
        angle: &angle,
        position: &time,
        speed: &angle,
        acceleration: &angle,
        phase_error: &angle,
        faults: &faults,
    };
    w.write(rows).unwrap();
    drop(w);
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 5, "{names:?}"); // capture, link, hard, out, a.csv
}
