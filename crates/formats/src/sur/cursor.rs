//! A little-endian byte cursor for the binary headers, whose errors name
//! the byte offset and the field. Kept private to the .sur reader for now;
//! the other binary readers of the crate may share it.

use super::invalid;
use crate::FormatError;

/// A little-endian reader over a byte slice.
pub(super) struct LeCursor<'a> {
    bytes: &'a [u8],
    pub(super) offset: usize,
}

impl<'a> LeCursor<'a> {
    pub(super) fn at(bytes: &'a [u8], offset: usize) -> Self {
        LeCursor { bytes, offset }
    }

    /// The next `len` bytes, or an error naming `what` and where the file ends.
    pub(super) fn take(&mut self, len: usize, what: &str) -> Result<&'a [u8], FormatError> {
        let end = self
            .offset
            .checked_add(len)
            .filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(invalid(format!(
                "byte {}: expected {len} bytes of {what}, but the file ends at byte {}",
                self.offset,
                self.bytes.len()
            )));
        };
        let taken = &self.bytes[self.offset..end];
        self.offset = end;
        Ok(taken)
    }

    pub(super) fn skip(&mut self, len: usize) {
        self.offset = self.offset.saturating_add(len);
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], FormatError> {
        let taken = self.take(N, what)?;
        let mut array = [0u8; N];
        array.copy_from_slice(taken);
        Ok(array)
    }

    pub(super) fn u16(&mut self, what: &str) -> Result<u16, FormatError> {
        self.array(what).map(u16::from_le_bytes)
    }

    pub(super) fn u32(&mut self, what: &str) -> Result<u32, FormatError> {
        self.array(what).map(u32::from_le_bytes)
    }

    pub(super) fn i32(&mut self, what: &str) -> Result<i32, FormatError> {
        self.array(what).map(i32::from_le_bytes)
    }

    pub(super) fn f32(&mut self, what: &str) -> Result<f32, FormatError> {
        self.array(what).map(f32::from_le_bytes)
    }
}
