//! [`EstimatesWriter`]: an observer's estimates written chunk by chunk, as CSV text whose
//! numbers have the digits their float type needs (the shortest decimal that reads back to
//! the same float, by `ryu`), as a NumPy `.npy` structured array or as an `.npz` of one
//! array per column; written beside the target and renamed over it when complete.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::error::CaptureError;
use super::npy_out::{NpzColumn, npy_header, write_npz};
use super::output::OutputFile;

/// The columns of the estimates, in file order: `time_s` (f64), `angle_rad`, `position_rad`
/// (f64), `speed_rad_s`, `acceleration_rad_s2`, `phase_error` (the observer's float type),
/// `faults` (bits, u8).
pub const ESTIMATE_COLUMNS: [&str; 7] = [
    "time_s",
    "angle_rad",
    "position_rad",
    "speed_rad_s",
    "acceleration_rad_s2",
    "phase_error",
    "faults",
];

/// A float type the estimates are written in: `f32` or `f64`.
pub trait OutputFloat: Copy + ryu::Float {
    /// The little-endian numpy type string (`<f4`, `<f8`).
    const NPY_TYPE: &'static str;
    /// The little-endian bytes of the value.
    fn write_le(self, out: &mut impl Write) -> std::io::Result<()>;
}

impl OutputFloat for f32 {
    const NPY_TYPE: &'static str = "<f4";
    fn write_le(self, out: &mut impl Write) -> std::io::Result<()> {
        out.write_all(&self.to_le_bytes())
    }
}

impl OutputFloat for f64 {
    const NPY_TYPE: &'static str = "<f8";
    fn write_le(self, out: &mut impl Write) -> std::io::Result<()> {
        out.write_all(&self.to_le_bytes())
    }
}

/// One chunk of estimates: slices of one length.
#[derive(Debug, Clone, Copy)]
pub struct EstimateRows<'a, T> {
    /// Time (s).
    pub time_s: &'a [f64],
    /// Angle (rad), wrapped.
    pub angle: &'a [T],
    /// Multi-turn position (rad).
    pub position: &'a [f64],
    /// Speed (rad/s).
    pub speed: &'a [T],
    /// Acceleration (rad/s^2).
    pub acceleration: &'a [T],
    /// Phase-detector output.
    pub phase_error: &'a [T],
    /// Fault bits.
    pub faults: &'a [u8],
}

/// How estimates are stored, from the output file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EstimatesFormat {
    /// Comma-separated text with a header line (`.csv`).
    Csv,
    /// A NumPy structured array, one record per sample, fields [`ESTIMATE_COLUMNS`] (`.npy`).
    Npy,
    /// A NumPy `.npz` archive of one 1-D array per column, named as [`ESTIMATE_COLUMNS`].
    Npz,
}

impl EstimatesFormat {
    /// The format of `path` from its extension (any case): `.csv`, `.npy` or `.npz`;
    /// `None` for any other, which would hide what the file holds.
    ///
    /// ```
    /// use angletrack::capture::EstimatesFormat;
    /// use std::path::Path;
    /// assert_eq!(EstimatesFormat::of_path(Path::new("est.NPZ")), Some(EstimatesFormat::Npz));
    /// assert_eq!(EstimatesFormat::of_path(Path::new("est.dat")), None);
    /// ```
    pub fn of_path(path: &Path) -> Option<Self> {
        let extension = path.extension().and_then(|e| e.to_str())?;
        [
            ("csv", EstimatesFormat::Csv),
            ("npy", EstimatesFormat::Npy),
            ("npz", EstimatesFormat::Npz),
        ]
        .into_iter()
        .find(|(e, _)| extension.eq_ignore_ascii_case(e))
        .map(|(_, f)| f)
    }
}

/// Room kept in the `.npy` header for the number of records, written when it is known.
const NPY_HEADER_BYTES: usize = 256;

/// Where the rows go while they are written.
#[derive(Debug)]
enum Sink {
    /// CSV text or `.npy` records, into the output's temporary file.
    Records(BufWriter<File>),
    /// One temporary file per column, assembled into the `.npz` at the end.
    Columns(Vec<NpzColumn>),
}

/// Writes estimates chunk by chunk in constant memory.
///
/// ```
/// use angletrack::capture::{EstimateRows, EstimatesWriter};
/// let path = std::env::temp_dir().join("angletrack_doc_estimates.csv");
/// let mut w = EstimatesWriter::create::<f32>(&path).map_err(|e| e.to_string())?;
/// w.write(EstimateRows { time_s: &[0.0], angle: &[0.1f32], position: &[0.1], speed: &[2.5f32],
///     acceleration: &[0.0f32], phase_error: &[1e-7f32], faults: &[0] }).map_err(|e| e.to_string())?;
/// assert_eq!(w.finish().map_err(|e| e.to_string())?, 1);
/// let text = std::fs::read_to_string(&path).unwrap();
/// assert_eq!(text.lines().nth(1), Some("0.0,0.1,0.1,2.5,0.0,1e-7,0"));
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), String>(())
/// ```
#[derive(Debug)]
pub struct EstimatesWriter {
    path: PathBuf,
    output: OutputFile,
    sink: Sink,
    format: EstimatesFormat,
    npy_type: &'static str,
    rows: u64,
}

impl EstimatesWriter {
    /// Starts `path` (format from its extension, [`EstimatesFormat::of_path`]; another
    /// extension is refused) for estimates in the float type `T`. The rows go to a
    /// temporary file beside `path`, renamed to it by [`finish`](Self::finish): a writer
    /// dropped before leaves `path` as it was.
    pub fn create<T: OutputFloat>(path: impl AsRef<Path>) -> Result<Self, CaptureError> {
        let path = path.as_ref();
        let format = EstimatesFormat::of_path(path).ok_or_else(|| {
            CaptureError::new(
                path,
                "output: the estimates' format follows the file's extension: .csv (text), .npy \
                 (a structured array) or .npz (one array per column)",
            )
        })?;
        let mut output = OutputFile::create(path)?;
        let io = |e: std::io::Error| CaptureError::io(path, &e);
        let sink = match format {
            EstimatesFormat::Npz => Sink::Columns(
                ESTIMATE_COLUMNS
                    .iter()
                    .map(|&name| NpzColumn::create(path, name, field_type(name, T::NPY_TYPE)))
                    .collect::<Result<_, _>>()?,
            ),
            _ => Sink::Records(BufWriter::with_capacity(
                1 << 20,
                output.file().try_clone().map_err(io)?,
            )),
        };
        let mut writer = Self {
            path: path.to_path_buf(),
            output,
            sink,
            format,
            npy_type: T::NPY_TYPE,
            rows: 0,
        };
        let header = match writer.format {
            EstimatesFormat::Csv => format!("{}\n", ESTIMATE_COLUMNS.join(",")).into_bytes(),
            EstimatesFormat::Npy => writer.npy_header(),
            EstimatesFormat::Npz => Vec::new(),
        };
        if let Sink::Records(out) = &mut writer.sink {
            out.write_all(&header).map_err(io)?;
        }
        Ok(writer)
    }

    fn io(&self, e: &std::io::Error) -> CaptureError {
        CaptureError::io(&self.path, e)
    }

    /// The `.npy` (version 1.0) header for the records written so far, padded to
    /// [`NPY_HEADER_BYTES`].
    fn npy_header(&self) -> Vec<u8> {
        let fields: Vec<String> = ESTIMATE_COLUMNS
            .iter()
            .map(|&name| format!("('{name}', '{}')", field_type(name, self.npy_type)))
            .collect();
        let descr = format!("[{}]", fields.join(", "));
        npy_header(&descr, &format!("({},)", self.rows), NPY_HEADER_BYTES)
    }

    /// Appends a chunk (every slice of one length).
    pub fn write<T: OutputFloat>(&mut self, rows: EstimateRows<'_, T>) -> Result<(), CaptureError> {
        let n = rows.time_s.len();
        let lengths = [
            rows.angle.len(),
            rows.position.len(),
            rows.speed.len(),
            rows.acceleration.len(),
            rows.phase_error.len(),
            rows.faults.len(),
        ];
        if lengths.iter().any(|&l| l != n) || T::NPY_TYPE != self.npy_type {
            return Err(CaptureError::new(
                &self.path,
                "estimates: columns of different lengths or float types",
            ));
        }
        let result = match (&mut self.sink, self.format) {
            (Sink::Records(out), EstimatesFormat::Csv) => write_csv(out, &rows),
            (Sink::Records(out), _) => write_npy(out, &rows),
            (Sink::Columns(columns), _) => write_columns(columns, &rows),
        };
        result.map_err(|e| self.io(&e))?;
        self.rows += n as u64;
        Ok(())
    }

    /// Completes the file (a `.npy` gets its final record count, an `.npz` its arrays),
    /// renames it to the target and returns the rows written.
    pub fn finish(mut self) -> Result<u64, CaptureError> {
        let path = self.path.clone();
        let io = |e: std::io::Error| CaptureError::io(&path, &e);
        match std::mem::replace(&mut self.sink, Sink::Columns(Vec::new())) {
            Sink::Records(mut out) => {
                if self.format == EstimatesFormat::Npy {
                    let header = self.npy_header();
                    out.flush()
                        .and_then(|()| out.seek(SeekFrom::Start(0)))
                        .and_then(|_| out.write_all(&header))
                        .map_err(io)?;
                }
                out.flush().map_err(io)?;
            }
            Sink::Columns(columns) => {
                let file = self.output.file().try_clone().map_err(io)?;
                let mut out = BufWriter::with_capacity(1 << 20, file);
                write_npz(&mut out, columns, self.rows, &path)?;
                out.flush().map_err(io)?;
            }
        }
        self.output.commit()?;
        Ok(self.rows)
    }
}

/// The numpy type of the estimates' column `name` when the observer's floats are `float`:
/// the time and the multi-turn position are always `<f8`, the faults `|u1`.
fn field_type(name: &str, float: &'static str) -> &'static str {
    match name {
        "time_s" | "position_rad" => "<f8",
        "faults" => "|u1",
        _ => float,
    }
}

/// Appends the rows to the `.npz` columns, in [`ESTIMATE_COLUMNS`] order.
fn write_columns<T: OutputFloat>(
    columns: &mut [NpzColumn],
    r: &EstimateRows<'_, T>,
) -> std::io::Result<()> {
    let [
        time,
        angle,
        position,
        speed,
        acceleration,
        phase_error,
        faults,
    ] = columns
    else {
        return Err(std::io::Error::other("the .npz has 7 columns"));
    };
    r.time_s
        .iter()
        .try_for_each(|v| v.write_le(&mut time.out))?;
    r.angle
        .iter()
        .try_for_each(|v| v.write_le(&mut angle.out))?;
    r.position
        .iter()
        .try_for_each(|v| v.write_le(&mut position.out))?;
    r.speed
        .iter()
        .try_for_each(|v| v.write_le(&mut speed.out))?;
    r.acceleration
        .iter()
        .try_for_each(|v| v.write_le(&mut acceleration.out))?;
    r.phase_error
        .iter()
        .try_for_each(|v| v.write_le(&mut phase_error.out))?;
    faults.out.write_all(r.faults)
}

fn write_csv<T: OutputFloat>(out: &mut impl Write, r: &EstimateRows<'_, T>) -> std::io::Result<()> {
    let mut buffer = ryu::Buffer::new();
    let mut line = Vec::with_capacity(256);
    for k in 0..r.time_s.len() {
        line.clear();
        push(&mut line, &mut buffer, r.time_s[k]);
        push(&mut line, &mut buffer, r.angle[k]);
        push(&mut line, &mut buffer, r.position[k]);
        push(&mut line, &mut buffer, r.speed[k]);
        push(&mut line, &mut buffer, r.acceleration[k]);
        push(&mut line, &mut buffer, r.phase_error[k]);
        push_u8(&mut line, r.faults[k]);
        line.push(b'\n');
        out.write_all(&line)?;
    }
    Ok(())
}

/// Appends the shortest round-trip decimal of `x` and a comma.
fn push<F: ryu::Float>(line: &mut Vec<u8>, buffer: &mut ryu::Buffer, x: F) {
    line.extend_from_slice(buffer.format(x).as_bytes());
    line.push(b',');
}

/// Appends the decimal digits of `bits`.
fn push_u8(line: &mut Vec<u8>, bits: u8) {
    if bits >= 100 {
        line.push(b'0' + bits / 100);
    }
    if bits >= 10 {
        line.push(b'0' + bits / 10 % 10);
    }
    line.push(b'0' + bits % 10);
}

fn write_npy<T: OutputFloat>(out: &mut impl Write, r: &EstimateRows<'_, T>) -> std::io::Result<()> {
    for k in 0..r.time_s.len() {
        r.time_s[k].write_le(out)?;
        r.angle[k].write_le(out)?;
        r.position[k].write_le(out)?;
        r.speed[k].write_le(out)?;
        r.acceleration[k].write_le(out)?;
        r.phase_error[k].write_le(out)?;
        out.write_all(&[r.faults[k]])?;
    }
    Ok(())
}
