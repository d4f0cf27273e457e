//! [`EstimatesWriter`]: an observer's estimates written chunk by chunk, a [`TableWriter`]
//! of the estimates' columns: CSV text whose numbers have the digits their float type needs
//! (the shortest decimal that reads back to the same float, by `ryu`), a NumPy `.npy`
//! structured array or an `.npz` of one array per column; written beside the target and
//! renamed over it when complete.

use std::path::Path;

use super::error::CaptureError;
#[cfg(doc)]
use super::table::EstimatesFormat;
use super::table::{Column, ColumnType, TableWriter};

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
    /// The table's column type of the float.
    const COLUMN_TYPE: ColumnType;
    /// The values as a table's column.
    fn column(values: &[Self]) -> Column<'_>;
}

impl OutputFloat for f32 {
    const COLUMN_TYPE: ColumnType = ColumnType::F32;
    fn column(values: &[f32]) -> Column<'_> {
        Column::F32(values)
    }
}

impl OutputFloat for f64 {
    const COLUMN_TYPE: ColumnType = ColumnType::F64;
    fn column(values: &[f64]) -> Column<'_> {
        Column::F64(values)
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
    table: TableWriter,
    float: ColumnType,
}

impl EstimatesWriter {
    /// Starts `path` (format from its extension, [`EstimatesFormat::of_path`]; another
    /// extension is refused) for estimates in the float type `T`. The rows go to a
    /// temporary file beside `path`, renamed to it by [`finish`](Self::finish): a writer
    /// dropped before leaves `path` as it was.
    pub fn create<T: OutputFloat>(path: impl AsRef<Path>) -> Result<Self, CaptureError> {
        let columns = estimate_columns(T::COLUMN_TYPE);
        Ok(Self {
            table: TableWriter::create(path, &columns)?,
            float: T::COLUMN_TYPE,
        })
    }

    /// Appends a chunk (every slice of one length).
    pub fn write<T: OutputFloat>(&mut self, rows: EstimateRows<'_, T>) -> Result<(), CaptureError> {
        if T::COLUMN_TYPE != self.float {
            return Err(CaptureError::new(
                self.table.path(),
                "estimates: float type other than the writer's",
            ));
        }
        self.table.write(&[
            Column::F64(rows.time_s),
            T::column(rows.angle),
            Column::F64(rows.position),
            T::column(rows.speed),
            T::column(rows.acceleration),
            T::column(rows.phase_error),
            Column::U8(rows.faults),
        ])
    }

    /// Completes the file (a `.npy` gets its final record count, an `.npz` its arrays),
    /// renames it to the target and returns the rows written.
    pub fn finish(self) -> Result<u64, CaptureError> {
        self.table.finish()
    }
}

/// The estimates' columns and their types for estimates in the float type `float`
/// ([`ESTIMATE_COLUMNS`]): the table an [`EstimatesWriter`] writes.
pub fn estimate_columns(float: ColumnType) -> [(&'static str, ColumnType); 7] {
    ESTIMATE_COLUMNS.map(|name| (name, field_type(name, float)))
}

/// The type of the estimates' column `name` when the observer's floats are `float`: the
/// time and the multi-turn position are always `f64`, the faults `u8`.
fn field_type(name: &str, float: ColumnType) -> ColumnType {
    match name {
        "time_s" | "position_rad" => ColumnType::F64,
        "faults" => ColumnType::U8,
        _ => float,
    }
}
