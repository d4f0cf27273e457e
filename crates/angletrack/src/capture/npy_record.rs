//! The fields of a structured `.npy` array (one record per sample, as `numpy.save` writes a
//! record array, and as `angletrack track` writes its estimates) as the columns of a
//! capture: each numeric field a column, by name, decoded from the record's bytes as they
//! stream (packed or aligned records, either byte order).

use std::io::Read;

use npyz::{DType, Endianness, TypeChar};

/// How one field of a record is read: its byte offset and width, its kind and byte order.
#[derive(Debug, Clone, Copy)]
struct FieldCodec {
    offset: usize,
    width: usize,
    kind: TypeChar,
    big_endian: bool,
}

impl FieldCodec {
    /// The field's value in `record` as `f64` (exactly for integers up to 2^53).
    fn decode(&self, record: &[u8]) -> f64 {
        let mut bytes = [0u8; 8];
        let field = record
            .get(self.offset..self.offset + self.width)
            .unwrap_or(&[]);
        bytes[..field.len()].copy_from_slice(field);
        if self.big_endian {
            bytes[..self.width].reverse();
        }
        let unsigned = u64::from_le_bytes(bytes);
        // Sign-extends a `width`-byte two's complement integer.
        let shift = 64 - 8 * self.width as u32;
        let signed = ((unsigned << shift) as i64) >> shift;
        match (self.kind, self.width) {
            (TypeChar::Float, 4) => f64::from(f32::from_bits(unsigned as u32)),
            (TypeChar::Float, _) => f64::from_bits(unsigned),
            (TypeChar::Int, _) => signed as f64,
            _ => unsigned as f64,
        }
    }
}

/// The numeric fields of a record dtype: their names, codecs and whether each is an integer
/// field, and the record's width in bytes; or a one-line reason naming the field that is not
/// a number. Fields of raw bytes (an aligned record's padding) are skipped.
pub(super) struct RecordLayout {
    pub(super) names: Vec<String>,
    pub(super) integer: Vec<bool>,
    pub(super) dtypes: Vec<String>,
    codecs: Vec<FieldCodec>,
    pub(super) width: usize,
}

impl RecordLayout {
    /// The layout of `dtype`, a record of scalar fields.
    pub(super) fn new(dtype: &DType) -> Result<Self, String> {
        let DType::Record(fields) = dtype else {
            return Err(format!("dtype {} is not a record", dtype.descr()));
        };
        let mut layout = RecordLayout {
            names: Vec::new(),
            integer: Vec::new(),
            dtypes: Vec::new(),
            codecs: Vec::new(),
            width: 0,
        };
        for field in fields {
            let DType::Plain(ts) = &field.dtype else {
                return Err(format!(
                    "field {:?} (dtype {}) is not a number: a record's fields must be numbers",
                    field.name,
                    field.dtype.descr()
                ));
            };
            let width = ts.size_field() as usize;
            let name = super::npy::numpy_name(ts.type_char(), ts.size_field());
            let numeric = match (name, ts.type_char()) {
                (Some(_), _) => true,
                (None, TypeChar::RawData) => false,
                (None, _) => {
                    return Err(format!(
                        "field {:?} has dtype {ts}: expected integers or float32/float64",
                        field.name
                    ));
                }
            };
            if numeric {
                layout.names.push(field.name.clone());
                layout.integer.push(ts.type_char() != TypeChar::Float);
                layout.dtypes.push(name.unwrap_or_default().to_string());
                layout.codecs.push(FieldCodec {
                    offset: layout.width,
                    width,
                    kind: ts.type_char(),
                    big_endian: ts.endianness() == Endianness::Big,
                });
            }
            layout.width += width;
        }
        if layout.names.is_empty() {
            return Err("a record without a numeric field".into());
        }
        Ok(layout)
    }

    /// The values of `reader`'s records (the numeric fields of each, in order) as they
    /// stream: ends at the end of the data, an error if it ends inside a record.
    pub(super) fn values<R: Read + Send + 'static>(
        &self,
        reader: R,
    ) -> Box<dyn Iterator<Item = std::io::Result<f64>> + Send> {
        Box::new(RecordValues {
            reader,
            codecs: self.codecs.clone(),
            record: vec![0; self.width],
            next: self.codecs.len(),
            done: false,
        })
    }
}

/// The numeric fields of the records of a stream, one value at a time.
struct RecordValues<R> {
    reader: R,
    codecs: Vec<FieldCodec>,
    record: Vec<u8>,
    /// The next field of `record` to give (all given: read the next record).
    next: usize,
    done: bool,
}

impl<R: Read> Iterator for RecordValues<R> {
    type Item = std::io::Result<f64>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        if self.next == self.codecs.len() {
            if let Err(e) = self.reader.read_exact(&mut self.record) {
                self.done = true;
                return (e.kind() != std::io::ErrorKind::UnexpectedEof).then_some(Err(e));
            }
            self.next = 0;
        }
        let value = self.codecs.get(self.next).map(|c| c.decode(&self.record));
        self.next += 1;
        value.map(Ok)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record `<f4, >i2, padding of 2, <u4, >f8` (NumPy's descr, as `numpy.save` writes it)
    /// decoded field by field, either byte order, integers sign-extended.
    #[test]
    fn a_record_is_decoded_field_by_field_in_either_byte_order() {
        let dtype =
            DType::parse("[('c', '<f4'), ('s', '>i2'), ('', '|V2'), ('n', '<u4'), ('t', '>f8')]")
                .unwrap();
        let layout = RecordLayout::new(&dtype).unwrap();
        assert_eq!(layout.names, ["c", "s", "n", "t"]);
        assert_eq!(layout.dtypes, ["float32", "int16", "uint32", "float64"]);
        assert_eq!(layout.integer, [false, true, true, false]);
        assert_eq!(layout.width, 4 + 2 + 2 + 4 + 8);
        let mut bytes = Vec::new();
        for (c, s, n, t) in [(1.5f32, -300i16, 70_000u32, -2.25f64), (-0.5, 7, 0, 1e-3)] {
            bytes.extend(c.to_le_bytes());
            bytes.extend(s.to_be_bytes());
            bytes.extend([0xff, 0xff]);
            bytes.extend(n.to_le_bytes());
            bytes.extend(t.to_be_bytes());
        }
        // A record cut short is not given.
        bytes.extend([1, 2, 3]);
        let values: Vec<f64> = layout
            .values(std::io::Cursor::new(bytes))
            .map(|v| v.unwrap())
            .collect();
        assert_eq!(values, [1.5, -300.0, 70_000.0, -2.25, -0.5, 7.0, 0.0, 1e-3]);
    }

    #[test]
    fn a_field_that_is_not_a_number_is_named() {
        let dtype = DType::parse("[('t', '<f8'), ('label', '<U4')]").unwrap();
        let Err(e) = RecordLayout::new(&dtype) else {
            panic!("a text field accepted");
        };
        assert!(e.starts_with("field \"label\" has dtype <U4"), "{e}");
    }
}
