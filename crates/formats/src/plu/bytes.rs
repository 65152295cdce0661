//! Bounds-checked reads of fixed-layout binary headers (little- and
//! big-endian), shared by the binary readers of this branch (Sensofar .plu,
//! Zygo MetroPro .dat, Wyko .opd) until the lead unifies them with the other
//! readers' cursor. Every read names the field and its byte offset, so a
//! truncated or corrupt file says where it went wrong.

use crate::FormatError;

/// Largest height map a reader accepts (2^28 points, 2 GiB of f64): a header
/// claiming more is refused before anything is allocated.
pub(crate) const MAX_POINTS: usize = 1 << 28;

/// A file's bytes, read at absolute offsets on behalf of one format.
#[derive(Clone, Copy)]
pub(crate) struct Bytes<'a> {
    data: &'a [u8],
    format: &'static str,
}

impl<'a> Bytes<'a> {
    pub(crate) fn new(data: &'a [u8], format: &'static str) -> Self {
        Bytes { data, format }
    }

    pub(crate) fn len(&self) -> usize {
        self.data.len()
    }

    /// An `Invalid` error of this format.
    pub(crate) fn invalid(&self, message: impl Into<String>) -> FormatError {
        FormatError::Invalid {
            format: self.format,
            message: message.into(),
        }
    }

    /// An `Unsupported` error of this format.
    pub(crate) fn unsupported(&self, message: impl Into<String>) -> FormatError {
        FormatError::Unsupported {
            format: self.format,
            message: message.into(),
        }
    }

    /// `len` bytes from `offset`, or an error naming `what` and the bytes it needs.
    pub(crate) fn slice(
        &self,
        offset: usize,
        len: usize,
        what: &str,
    ) -> Result<&'a [u8], FormatError> {
        offset
            .checked_add(len)
            .and_then(|end| self.data.get(offset..end))
            .ok_or_else(|| {
                self.invalid(format!(
                    "{what} needs bytes {offset}..{} but the file has {} bytes",
                    offset.saturating_add(len),
                    self.data.len()
                ))
            })
    }

    fn array<const N: usize>(&self, offset: usize, what: &str) -> Result<[u8; N], FormatError> {
        let bytes = self.slice(offset, N, what)?;
        let mut out = [0u8; N];
        out.copy_from_slice(bytes);
        Ok(out)
    }

    pub(crate) fn u8(&self, offset: usize, what: &str) -> Result<u8, FormatError> {
        Ok(self.array::<1>(offset, what)?[0])
    }

    pub(crate) fn u16_le(&self, offset: usize, what: &str) -> Result<u16, FormatError> {
        self.array(offset, what).map(u16::from_le_bytes)
    }

    pub(crate) fn u16_be(&self, offset: usize, what: &str) -> Result<u16, FormatError> {
        self.array(offset, what).map(u16::from_be_bytes)
    }

    pub(crate) fn i16_le(&self, offset: usize, what: &str) -> Result<i16, FormatError> {
        self.array(offset, what).map(i16::from_le_bytes)
    }

    pub(crate) fn i16_be(&self, offset: usize, what: &str) -> Result<i16, FormatError> {
        self.array(offset, what).map(i16::from_be_bytes)
    }

    pub(crate) fn u32_le(&self, offset: usize, what: &str) -> Result<u32, FormatError> {
        self.array(offset, what).map(u32::from_le_bytes)
    }

    pub(crate) fn u32_be(&self, offset: usize, what: &str) -> Result<u32, FormatError> {
        self.array(offset, what).map(u32::from_be_bytes)
    }

    pub(crate) fn i32_le(&self, offset: usize, what: &str) -> Result<i32, FormatError> {
        self.array(offset, what).map(i32::from_le_bytes)
    }

    pub(crate) fn i32_be(&self, offset: usize, what: &str) -> Result<i32, FormatError> {
        self.array(offset, what).map(i32::from_be_bytes)
    }

    pub(crate) fn f32_le(&self, offset: usize, what: &str) -> Result<f32, FormatError> {
        self.array(offset, what).map(f32::from_le_bytes)
    }

    pub(crate) fn f32_be(&self, offset: usize, what: &str) -> Result<f32, FormatError> {
        self.array(offset, what).map(f32::from_be_bytes)
    }

    pub(crate) fn f64_le(&self, offset: usize, what: &str) -> Result<f64, FormatError> {
        self.array(offset, what).map(f64::from_le_bytes)
    }

    /// `count` values of `N` bytes each from `offset`, decoded by `decode`
    /// (e.g. `f32::from_le_bytes`).
    pub(crate) fn values<const N: usize, T>(
        &self,
        offset: usize,
        count: usize,
        what: &str,
        decode: fn([u8; N]) -> T,
    ) -> Result<Vec<T>, FormatError> {
        let len = count
            .checked_mul(N)
            .ok_or_else(|| self.invalid(format!("{what}: {count} values of {N} bytes overflow")))?;
        let bytes = self.slice(offset, len, what)?;
        Ok(bytes
            .chunks_exact(N)
            .map(|chunk| {
                let mut value = [0u8; N];
                value.copy_from_slice(chunk);
                decode(value)
            })
            .collect())
    }

    /// A fixed-width text field: up to the first NUL, surrounding blanks
    /// trimmed, bytes outside ASCII read as Latin-1 (the vendors' Windows
    /// software writes code-page text; Latin-1 never fails).
    pub(crate) fn text(
        &self,
        offset: usize,
        len: usize,
        what: &str,
    ) -> Result<String, FormatError> {
        let bytes = self.slice(offset, len, what)?;
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        let text: String = bytes[..end].iter().map(|&b| char::from(b)).collect();
        Ok(text.trim().to_string())
    }
}

/// The number of points of an `nx` × `ny` grid, refused when empty or above
/// [`MAX_POINTS`]; `what` says where the sizes were read.
pub(crate) fn grid_points(
    format: &'static str,
    nx: usize,
    ny: usize,
    what: &str,
) -> Result<usize, FormatError> {
    let invalid = |message: String| FormatError::Invalid { format, message };
    if nx == 0 || ny == 0 {
        return Err(invalid(format!("{what}: an empty {nx} × {ny} grid")));
    }
    match nx.checked_mul(ny) {
        Some(n) if n <= MAX_POINTS => Ok(n),
        _ => Err(invalid(format!(
            "{what}: a {nx} × {ny} grid is more than the {MAX_POINTS} points a height map may have"
        ))),
    }
}

/// A Unix time stamp (seconds since 1970 UTC) as ISO 8601 text in UTC,
/// e.g. `2011-07-23T16:49:36Z`; `None` outside chrono's range.
pub(crate) fn utc_text(seconds: i64) -> Option<String> {
    chrono::DateTime::from_timestamp(seconds, 0)
        .map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true))
}

/// A grid stored as `ny` rows of `nx` values (rows of constant y, the layout
/// of every format read here) turned to axis 0 = x, by `height` of each
/// stored value.
pub(crate) fn x_major<T: Copy>(
    nx: usize,
    ny: usize,
    rows: &[T],
    height: impl Fn(T) -> f64,
) -> ndarray::Array2<f64> {
    ndarray::Array2::from_shape_fn((nx, ny), |(i, j)| height(rows[j * nx + i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_both_byte_orders_and_names_the_missing_bytes() {
        let bytes = Bytes::new(&[0x88, 0x1b, 0x03, 0x6f, 0x3f, 0x80, 0x00, 0x00], "test");
        assert_eq!(bytes.u32_be(0, "magic").unwrap(), 0x881b_036f);
        assert_eq!(bytes.u32_le(0, "magic").unwrap(), 0x6f03_1b88);
        assert_eq!(bytes.u16_be(2, "x").unwrap(), 0x036f);
        assert_eq!(bytes.i16_be(0, "x").unwrap(), 0x881b_u16 as i16);
        assert_eq!(bytes.f32_be(4, "one").unwrap(), 1.0);
        let err = bytes.u32_be(6, "the phase count").unwrap_err().to_string();
        assert_eq!(
            err,
            "test: the phase count needs bytes 6..10 but the file has 8 bytes"
        );
        assert!(bytes.slice(usize::MAX, 2, "x").is_err());
    }

    #[test]
    fn text_stops_at_nul_and_reads_latin1() {
        let bytes = Bytes::new(b" 20X  Mirau\0junk\xb5m", "test");
        assert_eq!(bytes.text(0, 12, "objective").unwrap(), "20X  Mirau");
        assert_eq!(bytes.text(16, 2, "unit").unwrap(), "µm");
    }

    #[test]
    fn rows_of_constant_y_become_axis_0_x() {
        // 3 × 2 grid stored row by row: (x, y) holds 10 y + x
        let rows = [0, 1, 2, 10, 11, 12];
        let grid = x_major(3, 2, &rows, f64::from);
        assert_eq!(grid.dim(), (3, 2));
        assert_eq!(grid[[2, 0]], 2.0);
        assert_eq!(grid[[1, 1]], 11.0);
        let bytes = Bytes::new(&[1, 0, 2, 0, 3], "t");
        assert_eq!(bytes.values(0, 2, "v", u16::from_le_bytes).unwrap(), [1, 2]);
        assert!(bytes.values(0, 3, "v", u16::from_le_bytes).is_err());
        assert!(
            bytes
                .values(0, usize::MAX, "v", u16::from_le_bytes)
                .is_err()
        );
    }

    #[test]
    fn unix_stamps_are_utc_dates() {
        // python3 -c "import datetime; print(datetime.datetime.fromtimestamp(1311439776, datetime.UTC))"
        assert_eq!(utc_text(1_311_439_776).unwrap(), "2011-07-23T16:49:36Z");
        assert_eq!(utc_text(0).unwrap(), "1970-01-01T00:00:00Z");
        assert_eq!(utc_text(i64::MAX), None);
    }

    #[test]
    fn grids_are_bounded_before_allocation() {
        assert_eq!(grid_points("t", 640, 480, "h").unwrap(), 307_200);
        assert!(grid_points("t", 0, 480, "h").is_err());
        assert!(grid_points("t", 1 << 15, 1 << 14, "h").is_err());
        assert!(grid_points("t", usize::MAX, 2, "h").is_err());
        assert!(grid_points("t", 1 << 14, 1 << 14, "h").is_ok());
    }
}
