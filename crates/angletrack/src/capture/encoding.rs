//! The text encodings of captures: UTF-8 (with or without its byte-order mark), UTF-16
//! with its byte-order mark (as some Windows tools export), and Latin-1 (a `µs` or `°` in a
//! header written by an older instrument), each told from the file's first bytes and read
//! as UTF-8 (UTF-16 transcoded as it streams; Latin-1's numbers are ASCII already).

use std::borrow::Cow;
use std::io::Read;

/// How a text capture is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// UTF-8 (ASCII included).
    Utf8,
    /// ISO 8859-1: every byte one character.
    Latin1,
    /// UTF-16, little-endian.
    Utf16Le,
    /// UTF-16, big-endian.
    Utf16Be,
}

impl Encoding {
    /// Its name in messages and metadata.
    pub const fn name(self) -> &'static str {
        match self {
            Encoding::Utf8 => "UTF-8",
            Encoding::Latin1 => "Latin-1",
            Encoding::Utf16Le => "UTF-16LE",
            Encoding::Utf16Be => "UTF-16BE",
        }
    }
}

const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";
const UTF16LE_BOM: &[u8] = b"\xFF\xFE";
const UTF16BE_BOM: &[u8] = b"\xFE\xFF";

/// The encoding a byte-order mark at the start of `head` declares, and the mark's length.
pub fn by_bom(head: &[u8]) -> Option<(Encoding, u64)> {
    if head.starts_with(UTF8_BOM) {
        Some((Encoding::Utf8, 3))
    } else if head.starts_with(UTF16LE_BOM) {
        Some((Encoding::Utf16Le, 2))
    } else if head.starts_with(UTF16BE_BOM) {
        Some((Encoding::Utf16Be, 2))
    } else {
        None
    }
}

/// Whether `bytes` (not UTF-8) read as Latin-1 are text: no control byte but tab, line
/// feed, form feed and carriage return (a binary file has them, and NUL bytes).
pub fn is_latin1_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .all(|&b| b >= 0x20 || matches!(b, b'\t' | b'\n' | b'\r' | 0x0C))
}

/// `bytes` in `encoding` as text (a character cut by the end of `bytes` dropped).
pub fn decode(bytes: &[u8], encoding: Encoding) -> Cow<'_, str> {
    match encoding {
        Encoding::Utf8 => match std::str::from_utf8(bytes) {
            Ok(t) => Cow::Borrowed(t),
            Err(e) => String::from_utf8_lossy(&bytes[..e.valid_up_to()]),
        },
        Encoding::Latin1 => Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
        Encoding::Utf16Le | Encoding::Utf16Be => {
            let units = bytes.chunks_exact(2).map(|p| unit(encoding, [p[0], p[1]]));
            Cow::Owned(
                char::decode_utf16(units)
                    .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
                    .collect(),
            )
        }
    }
}

fn unit(encoding: Encoding, pair: [u8; 2]) -> u16 {
    match encoding {
        Encoding::Utf16Be => u16::from_be_bytes(pair),
        _ => u16::from_le_bytes(pair),
    }
}

/// A reader of UTF-16 text (after its byte-order mark) that yields the text as UTF-8.
#[derive(Debug)]
pub struct Utf16Reader<R> {
    inner: R,
    encoding: Encoding,
    input: Vec<u8>,
    output: Vec<u8>,
    at: usize,
    /// A high surrogate whose low half is in the next block.
    pending: Option<u16>,
    /// Bytes read from `inner`.
    pub bytes_in: u64,
}

impl<R: Read> Utf16Reader<R> {
    /// Reads `inner` (UTF-16 in `encoding`, the byte-order mark skipped).
    pub fn new(inner: R, encoding: Encoding) -> Self {
        Self {
            inner,
            encoding,
            input: Vec::new(),
            output: Vec::new(),
            at: 0,
            pending: None,
            bytes_in: 0,
        }
    }

    /// Transcodes the next block; `false` at the end of the input.
    fn fill(&mut self) -> std::io::Result<bool> {
        let kept = self.input.len();
        self.input.resize(kept + (1 << 16), 0);
        let n = self.inner.read(&mut self.input[kept..])?;
        self.input.truncate(kept + n);
        self.bytes_in += n as u64;
        if n == 0 && self.input.len() < 2 {
            return Ok(false);
        }
        let whole = self.input.len() & !1;
        let mut units: Vec<u16> = self.pending.take().into_iter().collect();
        units.extend(
            self.input[..whole]
                .chunks_exact(2)
                .map(|p| unit(self.encoding, [p[0], p[1]])),
        );
        self.input.drain(..whole);
        if n > 0 && units.last().is_some_and(|u| (0xD800..0xDC00).contains(u)) {
            self.pending = units.pop();
        }
        self.output.clear();
        self.at = 0;
        let mut buffer = [0u8; 4];
        for c in char::decode_utf16(units) {
            let c = c.unwrap_or(char::REPLACEMENT_CHARACTER);
            self.output
                .extend_from_slice(c.encode_utf8(&mut buffer).as_bytes());
        }
        Ok(true)
    }
}

impl<R: Read> Read for Utf16Reader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        while self.at == self.output.len() {
            if !self.fill()? {
                return Ok(0);
            }
        }
        let n = buf.len().min(self.output.len() - self.at);
        buf[..n].copy_from_slice(&self.output[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_streams_as_utf8_across_blocks() {
        let text = "Zeit (µs);cos;sin\n0;1;0\n1;0,5;0,866\n".repeat(5000) + "😀";
        for encoding in [Encoding::Utf16Le, Encoding::Utf16Be] {
            let bytes: Vec<u8> = text
                .encode_utf16()
                .flat_map(|u| match encoding {
                    Encoding::Utf16Le => u.to_le_bytes(),
                    _ => u.to_be_bytes(),
                })
                .collect();
            let mut out = String::new();
            Utf16Reader::new(&bytes[..], encoding)
                .read_to_string(&mut out)
                .unwrap();
            assert_eq!(out, text);
            assert_eq!(
                decode(&bytes[..64], encoding),
                text.chars().take(32).collect::<String>()
            );
        }
    }
}
