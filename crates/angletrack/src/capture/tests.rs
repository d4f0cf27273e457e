//! The capture reader on small files of every layout, and each malformed input's message.

use super::*;
use std::path::PathBuf;

fn file(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("angletrack_capture_tests_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn options(columns: &str) -> CaptureOptions {
    CaptureOptions {
        columns: columns.parse().unwrap(),
        ..Default::default()
    }
}

fn read(name: &str, bytes: &[u8], columns: &str) -> Result<Capture, CaptureError> {
    read_capture(file(name, bytes), options(columns))
}

fn error(name: &str, bytes: &[u8], columns: &str) -> String {
    read(name, bytes, columns).unwrap_err().to_string()
}

#[test]
fn every_delimiter_is_sniffed_and_columns_are_mapped_by_name() {
    for (name, text) in [
        ("semicolon.csv", "t;sin;cos\n0;0;1\n0.5;1;0\n1;0;-1\n"),
        ("comma.csv", "t,sin,cos\n0,0,1\n0.5,1,0\n1,0,-1\n"),
        ("crlf.csv", "t,sin,cos\r\n0,0,1\r\n0.5,1,0\r\n1,0,-1\r\n"),
        (
            "quoted.csv",
            "\"t\",\"sin\",\"cos\"\n\"0\",0,1\n0.5,\"1\",0\n1,0,-1",
        ),
        ("tab.tsv", "t\tsin\tcos\n0\t0\t1\n0.5\t1\t0\n1\t0\t-1\n"),
        (
            "blanks.txt",
            "  t   sin  cos\n 0  0  1\n 0.5  1 0\n\n 1 0   -1\n",
        ),
    ] {
        let c = read(name, text.as_bytes(), "time=t,y_s=sin,y_c=cos").unwrap();
        assert_eq!(c.samples.y_c, [1.0, 0.0, -1.0], "{name}");
        assert_eq!(c.samples.y_s, [0.0, 1.0, 0.0], "{name}");
        assert_eq!(
            c.samples.time_s.as_deref(),
            Some(&[0.0, 0.5, 1.0][..]),
            "{name}"
        );
        assert_eq!(c.sample_rate_hz, Some(2.0), "{name}");
    }
}

#[test]
fn usual_names_need_no_mapping_and_a_bom_is_skipped() {
    let c = read(
        "bom.csv",
        b"\xEF\xBB\xBFtime,y_c,y_s,reference\n0,1.0,0,0\n1,1,0,0\n",
        "",
    )
    .unwrap();
    assert_eq!(c.sample_dtype, "float64");
    assert_eq!(c.samples.reference_rad.as_deref(), Some(&[0.0, 0.0][..]));
    assert_eq!(c.mapping[0], (Role::Time, "time".to_string()));
}

#[test]
fn header_names_match_without_their_units() {
    let c = read(
        "units.csv",
        b"Time (s),Cos [V],Sin [V]\n0,1,0\n1,1,0\n",
        "y_c=cos,y_s=sin",
    )
    .unwrap();
    assert_eq!(c.mapping[0], (Role::Time, "Time (s)".to_string()));
    assert_eq!(c.sample_rate_hz, Some(1.0));
}

#[test]
fn a_signal_named_twice_in_the_header_is_ambiguous_unless_named_by_index() {
    let text = b"time,y_c,y_s,Y_S [V]\n0,1,0,0.5\n1,1,0,0.5\n";
    for columns in ["", "y_s=y_s"] {
        let e = error("twice.csv", text, columns);
        assert!(
            e.contains("y_s=y_s is ambiguous: columns 2 and 3") && e.contains("y_s=3"),
            "{e}"
        );
    }
    let c = read("twice.csv", text, "y_s=3").unwrap();
    assert_eq!(c.samples.y_s, [0.5, 0.5]);
}

#[test]
fn integer_counts_keep_their_dtype_and_indices_map_a_headerless_file() {
    let c = read("adc.csv", b"2048 3548\n2050 3547\n", "y_c=0,y_s=1").unwrap();
    assert_eq!(c.samples.y_c, [2048.0, 2050.0]);
    assert_eq!(c.sample_dtype, "int64");
    assert!(c.samples.time_s.is_none() && c.sample_rate_hz.is_none());
    let e = error("headerless.csv", b"1,0\n1,0\n", "");
    assert!(
        e.contains("no header line") && e.contains("y_c=0,y_s=1"),
        "{e}"
    );
}

#[test]
fn oscilloscope_pairs_use_one_time_column_and_check_the_other() {
    let text = "x-axis,1,x-axis,2\nsecond,Volt,second,Volt\n0,1,0,0\n0.001,0.9,0.001,0.1\n";
    let c = read("scope.csv", text.as_bytes(), "y_c=1,y_s=2").unwrap();
    assert_eq!(c.samples.y_s, [0.0, 0.1]);
    assert_eq!(c.samples.time_s.as_deref(), Some(&[0.0, 0.001][..]));
    let bad = "t1,ch1,t2,ch2\n0,1,0,0\n0.001,0.9,0.002,0.1\n";
    let e = error("scope_bad.csv", bad.as_bytes(), "y_c=ch1,y_s=ch2");
    assert!(
        e.ends_with("not sampled together; map the columns of one channel pair"),
        "{e}"
    );
    assert!(e.contains("scope_bad.csv:3:3: time column \"t2\""), "{e}");
}

#[test]
fn malformed_inputs_name_the_file_line_and_column() {
    let cases: [(&str, &[u8], &str, &str); 13] = [
        (
            "crlf_text.csv",
            b"time,y_c,y_s\r\n0,1,0\r\n\r\n1,abc,0\r\n",
            "",
            "crlf_text.csv:4:2: column \"y_c\": \"abc\"",
        ),
        ("empty.csv", b"", "", "empty.csv:1: empty file"),
        (
            "header_only.csv",
            b"time,y_c,y_s\n",
            "",
            "header_only.csv:1: header only: no data rows",
        ),
        (
            "one_row.csv",
            b"time,y_c,y_s\n0,1,0\n",
            "",
            "one_row.csv:2: only one data row",
        ),
        (
            "text.csv",
            b"time,y_c,y_s\n0,1,0\n1,abc,0\n",
            "",
            "text.csv:3:2: column \"y_c\": \"abc\" is not a number",
        ),
        (
            "missing.csv",
            b"time,y_c,y_s\n0,1,0\n1,,0\n",
            "",
            "missing.csv:3:2: column \"y_c\": missing value",
        ),
        (
            "short.csv",
            b"time,y_c,y_s\n0,1,0\n1,1\n",
            "",
            "short.csv:3:3: column \"y_s\": missing value (the row has 2 field(s)",
        ),
        (
            "unsorted.csv",
            b"time,y_c,y_s\n0,1,0\n2,1,0\n1,1,0\n",
            "",
            "unsorted.csv:4:1: column \"time\": unsorted time: 1 s after 2 s",
        ),
        (
            "duplicated.csv",
            b"time,y_c,y_s\n0,1,0\n1,1,0\n1,1,0\n",
            "",
            "duplicated.csv:4:1: column \"time\": duplicated time",
        ),
        (
            "nan_time.csv",
            b"time,y_c,y_s\n0,1,0\nnan,1,0\n",
            "",
            "nan_time.csv:3:1: column \"time\": the time is NaN",
        ),
        (
            "nan_ref.csv",
            b"time,y_c,y_s,reference\n0,1,0,0\n1,1,0,NaN\n",
            "",
            "nan_ref.csv:3:4: column \"reference\": the reference angle is NaN",
        ),
        (
            "binary.csv",
            b"time,y_c\n\x00\x01\xff",
            "",
            "binary.csv:2:1: not a text capture: binary data (byte 0x00)",
        ),
        (
            "jitter.csv",
            b"t,y_c,y_s\n0,1,0\n1,1,0\n2,1,0\n3.5,1,0\n",
            "",
            "jitter.csv:5:1: column \"t\": time step 1.5 s differs from the capture's 1 s by more than 1 %",
        ),
    ];
    for (name, bytes, columns, expected) in cases {
        let e = error(name, bytes, columns);
        assert!(e.contains(expected), "{name}: {e}");
    }
}

#[test]
fn evenly_spaced_epoch_nanoseconds_are_accepted_and_their_rate_kept() {
    // 160 kHz stamped in nanoseconds since 1970 (2025): 6250 ns apart, held in f64 seconds to
    // about 240 ns.
    let mut text = String::from("time,y_c,y_s\n");
    for k in 0..2000_i64 {
        text += &format!("{},1,0\n", 1_764_000_000_000_000_000 + 6250 * k);
    }
    let path = file("epoch_ns.csv", text.as_bytes());
    let c = read_capture(
        path,
        CaptureOptions {
            time_unit: TimeUnit::Nanoseconds,
            ..options("")
        },
    )
    .unwrap();
    // The rate from the first and last stamps, each to 240 ns over 12.5 ms: 2e-5.
    let rate = c.sample_rate_hz.unwrap();
    assert!((rate / 160e3 - 1.0).abs() < 1e-4, "{rate}");
    // A step 2 % off is still refused.
    text += "1764000000012506250,1,0\n";
    let path = file("epoch_ns_jump.csv", text.as_bytes());
    let e = read_capture(
        path,
        CaptureOptions {
            time_unit: TimeUnit::Nanoseconds,
            ..options("")
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("differs from the capture's"), "{e}");
}

#[test]
fn a_stated_rate_skips_the_spacing_check_and_units_convert_the_time() {
    let path = file(
        "jittered.csv",
        b"t,y_c,y_s\n0,1,0\n100,1,0\n230,1,0\n300,1,0\n",
    );
    let stated = CaptureOptions {
        sample_rate_hz: Some(1e4),
        time_unit: TimeUnit::Microseconds,
        ..Default::default()
    };
    let c = read_capture(&path, stated).unwrap();
    assert_eq!(c.sample_rate_hz, Some(1e4));
    assert_eq!(c.samples.time_s.unwrap()[1], 1e-4);
}

#[test]
fn a_stated_rate_that_contradicts_the_time_column_is_refused_naming_both() {
    // 20 kHz in the time column (rounded to 10 us, so each step alone is 40 to 60 us).
    let mut text = String::from("t,y_c,y_s\n");
    for k in 0..400 {
        text += &format!("{},1,0\n", (k as f64 * 50.0 / 10.0).round() * 10.0);
    }
    let path = file("rate.csv", text.as_bytes());
    let options = |rate: f64| CaptureOptions {
        sample_rate_hz: Some(rate),
        time_unit: TimeUnit::Microseconds,
        chunk_rows: 64,
        ..Default::default()
    };
    let e = read_capture(&path, options(1e4)).unwrap_err().to_string();
    assert!(
        e.contains(
            "--sample-rate 10000 Hz contradicts the time column, whose mean step 50 us is 20000 Hz"
        ),
        "{e}"
    );
    // The rate the stamps say, and one 0.5 % off (a crystal's error), are accepted.
    assert_eq!(
        read_capture(&path, options(2e4)).unwrap().sample_rate_hz,
        Some(2e4)
    );
    assert!(read_capture(&path, options(2.01e4)).is_ok());
    assert!(read_capture(&path, options(2.03e4)).is_err());
    // Stamps in seconds: their mean step to 12 significant digits, not the f64's tail.
    let mut text = String::from("t,y_c,y_s\n");
    for k in 0..400 {
        text += &format!("{},1,0\n", k as f64 / 2e4);
    }
    let path = file("rate_s.csv", text.as_bytes());
    let seconds = CaptureOptions {
        time_unit: TimeUnit::Seconds,
        ..options(1e4)
    };
    let e = read_capture(&path, seconds).unwrap_err().to_string();
    assert!(e.contains("whose mean step 0.00005 s is 20000 Hz"), "{e}");
}

#[test]
fn chunks_stream_the_rows_in_order() {
    let mut text = String::from("time;y_c;y_s\n");
    for k in 0..1001 {
        text += &format!(
            "{};{};{}\n",
            k as f64 * 1e-4,
            (k as f64).cos(),
            (k as f64).sin()
        );
    }
    let options = CaptureOptions {
        chunk_rows: 100,
        ..Default::default()
    };
    let mut reader = CaptureReader::open(file("chunks.csv", text.as_bytes()), options).unwrap();
    let mut lengths = Vec::new();
    while let Some(chunk) = reader.next_chunk().unwrap() {
        assert_eq!(chunk.y_c[0], (chunk.first_sample as f64).cos());
        lengths.push(chunk.len());
    }
    assert_eq!(lengths.len(), 11);
    assert_eq!(lengths[10], 1);
    assert_eq!(reader.rows(), 1001);
    assert!((reader.sample_rate_hz().unwrap() - 1e4).abs() < 1e-6);
}

fn npy_2d(descr: &str, rows: usize, data: &[u8]) -> Vec<u8> {
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, 3), }}");
    let mut h = b"\x93NUMPY\x01\x00".to_vec();
    let len = (dict.len() + 1).div_ceil(64) * 64 + 64 - 10;
    h.extend_from_slice(&(len as u16).to_le_bytes());
    h.extend_from_slice(dict.as_bytes());
    h.resize(len + 9, b' ');
    h.push(b'\n');
    h.extend_from_slice(data);
    h
}

#[test]
fn a_2d_npy_array_streams_its_rows_with_its_dtype() {
    let values: [i16; 6] = [0, 2048, 3548, 1, 2049, 3547];
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = file("counts.npy", &npy_2d("<i2", 2, &data));
    let c = read_capture(&path, options("time=0,y_c=1,y_s=2")).unwrap();
    assert_eq!(c.samples.y_s, [3548.0, 3547.0]);
    assert_eq!(c.sample_dtype, "int16");
    assert_eq!(c.format, "npy");
}

#[test]
fn estimates_round_trip_through_csv_and_npy() {
    let rows = EstimateRows {
        time_s: &[0.0, 1e-4],
        angle: &[0.1f32, -core::f32::consts::PI],
        position: &[0.1, 12.566370614359172],
        speed: &[2.5f32, 1e30],
        acceleration: &[0.0f32, f32::NAN],
        phase_error: &[1e-7f32, -0.0],
        faults: &[0, 200],
    };
    let csv = file("est.csv", b"");
    let mut w = EstimatesWriter::create::<f32>(&csv).unwrap();
    w.write(rows).unwrap();
    assert_eq!(w.finish().unwrap(), 2);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(
        text.lines().nth(2),
        Some("0.0001,-3.1415927,12.566370614359172,1e30,NaN,-0.0,200")
    );
    let npy = file("est.npy", b"");
    let mut w = EstimatesWriter::create::<f32>(&npy).unwrap();
    w.write(rows).unwrap();
    w.write(rows).unwrap();
    w.finish().unwrap();
    let bytes = std::fs::read(&npy).unwrap();
    let header = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(header.shape(), &[4]);
    assert_eq!(bytes.len(), 256 + 4 * (8 + 4 + 8 + 4 + 4 + 4 + 1));
}

#[test]
fn a_table_of_integer_and_float_columns_in_each_format() {
    let columns = [
        ("time_s", ColumnType::F64),
        ("angle_binary", ColumnType::I32),
        ("faults", ColumnType::U8),
        ("y_c", ColumnType::F32),
    ];
    let chunk = [
        Column::F64(&[0.0, 1e-4]),
        Column::I32(&[i32::MIN, 7]),
        Column::U8(&[0, 255]),
        Column::F32(&[0.5, -1e-7]),
    ];
    let csv = file("table.csv", b"");
    let mut w = TableWriter::create(&csv, &columns).unwrap();
    w.write(&chunk).unwrap();
    assert_eq!(w.finish().unwrap(), 2);
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        "time_s,angle_binary,faults,y_c\n0.0,-2147483648,0,0.5\n0.0001,7,255,-1e-7\n"
    );
    // A structured array: the fields' types in the header, the records packed after it.
    let npy = file("table.npy", b"");
    let mut w = TableWriter::create(&npy, &columns).unwrap();
    w.write(&chunk).unwrap();
    w.write(&chunk).unwrap();
    assert_eq!(w.finish().unwrap(), 4);
    let bytes = std::fs::read(&npy).unwrap();
    // The header's length: 10 bytes, then the dict's length (little-endian u16).
    let start = 10 + usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
    assert_eq!(start % 64, 0);
    let header = String::from_utf8_lossy(&bytes[10..start]);
    assert!(
        header.contains(
            "'descr': [('time_s', '<f8'), ('angle_binary', '<i4'), ('faults', '|u1'), \
             ('y_c', '<f4')], 'fortran_order': False, 'shape': (4,)"
        ),
        "{header}"
    );
    assert_eq!(bytes.len(), start + 4 * (8 + 4 + 1 + 4));
    assert_eq!(&bytes[start + 8..start + 12], &i32::MIN.to_le_bytes());
    assert_eq!(bytes[start + 12], 0);
    assert_eq!(&bytes[start + 17 + 8..start + 17 + 12], &7i32.to_le_bytes());
    // The header is written again at the end with the count: for every length of the
    // fields' list (so that some header's count crosses a 64-byte boundary), it has room.
    for length in 1..=64 {
        let name = "x".repeat(length);
        let npy = file("room.npy", b"");
        let mut w = TableWriter::create(&npy, &[(name.as_str(), ColumnType::F64)]).unwrap();
        w.write(&[Column::F64(&[0.5; 12_345])]).unwrap();
        w.finish().unwrap();
        let bytes = std::fs::read(&npy).unwrap();
        let start = 10 + usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        assert!(String::from_utf8_lossy(&bytes[10..start]).contains("'shape': (12345,)"));
        assert_eq!(bytes.len(), start + 12_345 * 8, "name of {length}");
        assert_eq!(&bytes[start..start + 8], &0.5f64.to_le_bytes());
    }
    // One array per column, named as the columns.
    let npz = file("table.npz", b"");
    let mut w = TableWriter::create(&npz, &columns).unwrap();
    w.write(&chunk).unwrap();
    w.finish().unwrap();
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&npz).unwrap()).unwrap();
    let names: Vec<String> = (0..zip.len())
        .map(|k| zip.by_index(k).unwrap().name().unwrap().into_owned())
        .collect();
    assert_eq!(
        names,
        ["time_s.npy", "angle_binary.npy", "faults.npy", "y_c.npy"]
    );
    let mut member = Vec::new();
    std::io::Read::read_to_end(&mut zip.by_name("angle_binary.npy").unwrap(), &mut member).unwrap();
    assert_eq!(&member[member.len() - 8..], &[0, 0, 0, 0x80, 7, 0, 0, 0]);
}

#[test]
fn a_table_refuses_bad_columns_and_leaves_the_target_as_it_was() {
    let target = file("kept.csv", b"before\n");
    for (columns, message) in [
        (&[][..], "columns: a table needs one at least"),
        (&[("angle rad", ColumnType::F64)][..], "is not a name"),
        (
            &[("a", ColumnType::F64), ("a", ColumnType::U8)][..],
            "a given twice",
        ),
    ] {
        let e = TableWriter::create(&target, columns)
            .unwrap_err()
            .to_string();
        assert!(e.contains(message), "{e}");
    }
    let mut w =
        TableWriter::create(&target, &[("a", ColumnType::F64), ("b", ColumnType::U8)]).unwrap();
    for (chunk, message) in [
        (
            &[Column::F64(&[1.0])][..],
            "columns: 1 given for a table of 2",
        ),
        (
            &[Column::F64(&[1.0]), Column::I32(&[1])][..],
            "b: values of numpy type <i4 for a column of |u1",
        ),
        (
            &[Column::F64(&[1.0]), Column::U8(&[1, 2])][..],
            "b: 2 values where the first column has 1",
        ),
    ] {
        let e = w.write(chunk).unwrap_err().to_string();
        assert!(e.contains(message), "{e}");
    }
    drop(w);
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "before\n");
}
