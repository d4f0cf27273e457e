//! [`EstimatesWriter`]: an observer's estimates written chunk by chunk, as CSV text whose
//! numbers have the digits their float type needs (the shortest decimal that reads back to
//! the same float, by `ryu`), or as a NumPy `.npy` structured array.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::error::CaptureError;

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
    /// Comma-separated text with a header line (any extension but `.npy`).
    Csv,
    /// A NumPy structured array, one record per sample, fields [`ESTIMATE_COLUMNS`].
    Npy,
}

impl EstimatesFormat {
    /// The format of `path`: `.npy` for NumPy, anything else CSV.
    pub fn of_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("npy") => EstimatesFormat::Npy,
            _ => EstimatesFormat::Csv,
        }
    }
}

/// Room kept in the `.npy` header for the number of records, written when it is known.
const NPY_HEADER_BYTES: usize = 256;

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
    out: BufWriter<File>,
    format: EstimatesFormat,
    npy_type: &'static str,
    rows: u64,
}

impl EstimatesWriter {
    /// Creates `path` (format from its extension, [`EstimatesFormat::of_path`]) for
    /// estimates in the float type `T`.
    pub fn create<T: OutputFloat>(path: impl AsRef<Path>) -> Result<Self, CaptureError> {
        let path = path.as_ref();
        let file = File::create(path).map_err(|e| CaptureError::io(path, &e))?;
        let mut writer = Self {
            path: path.to_path_buf(),
            out: BufWriter::with_capacity(1 << 20, file),
            format: EstimatesFormat::of_path(path),
            npy_type: T::NPY_TYPE,
            rows: 0,
        };
        let header = match writer.format {
            EstimatesFormat::Csv => format!("{}\n", ESTIMATE_COLUMNS.join(",")).into_bytes(),
            EstimatesFormat::Npy => writer.npy_header(),
        };
        writer.out.write_all(&header).map_err(|e| writer.io(&e))?;
        Ok(writer)
    }

    fn io(&self, e: &std::io::Error) -> CaptureError {
        CaptureError::io(&self.path, e)
    }

    /// The `.npy` (version 1.0) header for the records written so far, padded to
    /// [`NPY_HEADER_BYTES`].
    fn npy_header(&self) -> Vec<u8> {
        let t = self.npy_type;
        let fields: Vec<String> = ESTIMATE_COLUMNS
            .iter()
            .map(|&name| {
                let ty = match name {
                    "time_s" | "position_rad" => "<f8",
                    "faults" => "|u1",
                    _ => t,
                };
                format!("('{name}', '{ty}')")
            })
            .collect();
        let dict = format!(
            "{{'descr': [{}], 'fortran_order': False, 'shape': ({},), }}",
            fields.join(", "),
            self.rows
        );
        let mut header = b"\x93NUMPY\x01\x00".to_vec();
        let len = NPY_HEADER_BYTES - 10;
        header.extend_from_slice(&(len as u16).to_le_bytes());
        header.extend_from_slice(dict.as_bytes());
        header.resize(NPY_HEADER_BYTES - 1, b' ');
        header.push(b'\n');
        header
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
        let result = match self.format {
            EstimatesFormat::Csv => write_csv(&mut self.out, &rows),
            EstimatesFormat::Npy => write_npy(&mut self.out, &rows),
        };
        result.map_err(|e| self.io(&e))?;
        self.rows += n as u64;
        Ok(())
    }

    /// Flushes the file (a `.npy` gets its final record count) and returns the rows written.
    pub fn finish(mut self) -> Result<u64, CaptureError> {
        if self.format == EstimatesFormat::Npy {
            let header = self.npy_header();
            let out = &mut self.out;
            let result = out
                .flush()
                .and_then(|()| out.seek(SeekFrom::Start(0)))
                .and_then(|_| out.write_all(&header));
            result.map_err(|e| self.io(&e))?;
        }
        self.out.flush().map_err(|e| self.io(&e))?;
        Ok(self.rows)
    }
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
