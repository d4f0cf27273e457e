//! The NumPy side of the estimates writer: `.npy` headers, and an `.npz` (a zip of one
//! `.npy` per column, as `numpy.savez` writes) assembled when the number of rows is known
//! from columns kept in temporary files meanwhile, so that memory stays constant.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

use super::error::CaptureError;
use super::output::{TemporaryFile, temporary_beside};

/// A `.npy` (version 1.0) header for an array of numpy type `descr` (`'<f8'`, or a
/// structured type's list) and `shape` (`"(12,)"`), padded with blanks to a multiple of 64
/// bytes and at least `min_bytes` (room for a count written later).
pub fn npy_header(descr: &str, shape: &str, min_bytes: usize) -> Vec<u8> {
    let dict = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': {shape}, }}");
    let unpadded = 10 + dict.len() + 1;
    let total = unpadded.div_ceil(64).max(min_bytes.div_ceil(64)) * 64;
    let mut header = b"\x93NUMPY\x01\x00".to_vec();
    header.extend_from_slice(&((total - 10) as u16).to_le_bytes());
    header.extend_from_slice(dict.as_bytes());
    header.resize(total - 1, b' ');
    header.push(b'\n');
    header
}

/// One column of an `.npz` being written: its values, little-endian, in a temporary file.
#[derive(Debug)]
pub struct NpzColumn {
    /// The array's name in the archive (without `.npy`).
    pub name: String,
    /// Its numpy type string (`<f8`, `<f4`, `|u1`).
    pub descr: &'static str,
    /// The values written so far.
    pub out: BufWriter<File>,
    temp: TemporaryFile,
}

impl NpzColumn {
    /// A column named `name` of type `descr`, kept beside `target` until the archive is
    /// assembled.
    pub fn create(target: &Path, name: &str, descr: &'static str) -> Result<Self, CaptureError> {
        let (path, file) = temporary_beside(target)?;
        Ok(Self {
            name: name.to_owned(),
            descr,
            out: BufWriter::with_capacity(1 << 18, file),
            temp: TemporaryFile::new(path),
        })
    }
}

/// Writes the `.npz` archive of `columns` (each `rows` values long) to `out`, each array
/// stored uncompressed as `numpy.savez` stores it; the columns' temporary files are removed.
pub fn write_npz(
    out: &mut (impl Write + Seek),
    columns: Vec<NpzColumn>,
    rows: u64,
    target: &Path,
) -> Result<(), CaptureError> {
    let io = |e: std::io::Error| CaptureError::io(target, &e);
    let zip_error = |e: zip::result::ZipError| CaptureError::new(target, e.to_string());
    let mut zip = zip::ZipWriter::new(out);
    for column in columns {
        let NpzColumn {
            name,
            descr,
            out,
            temp,
        } = column;
        let mut file = out.into_inner().map_err(|e| io(e.into_error()))?;
        let bytes = file.seek(SeekFrom::End(0)).map_err(io)?;
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        let header = npy_header(&format!("'{descr}'"), &format!("({rows},)"), 0);
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored)
            .large_file(bytes + header.len() as u64 >= u64::from(u32::MAX));
        zip.start_file(format!("{name}.npy"), options)
            .map_err(zip_error)?;
        zip.write_all(&header).map_err(io)?;
        std::io::copy(&mut file, &mut zip).map_err(io)?;
        drop(temp);
    }
    zip.finish().map_err(zip_error)?;
    Ok(())
}
