//! What every reader of the crate shares: bounds-checked reads of numbers,
//! text and value arrays in the file's byte order (at absolute offsets, or
//! one after another with a [`Cursor`]), whose errors name the format, the
//! field and the bytes it needed; the cap on a map's points, checked before
//! anything is allocated; and the turn of a grid stored as rows of constant
//! y into hypercontact's axis 0 = x.

use ndarray::Array2;

use crate::FormatError;

/// Largest height map a reader accepts whatever `max_points` says (2^32
/// points, 32 GiB of f64): the ceiling of the caller's limit, and the bound
/// of buffers sized before the grid is known.
pub(crate) const MAX_POINTS: usize = 1 << 32;

/// The byte order of a file's numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ByteOrder {
    Little,
    Big,
}

/// A number stored in a fixed number of bytes.
pub(crate) trait Stored: Copy {
    /// bytes of one value
    const SIZE: usize;
    /// The value of exactly [`Stored::SIZE`] bytes.
    fn decode(bytes: &[u8], order: ByteOrder) -> Self;
}

macro_rules! stored {
    ($($number:ty),*) => {$(
        impl Stored for $number {
            const SIZE: usize = std::mem::size_of::<$number>();
            fn decode(bytes: &[u8], order: ByteOrder) -> Self {
                let mut array = [0u8; std::mem::size_of::<$number>()];
                array.copy_from_slice(bytes);
                match order {
                    ByteOrder::Little => <$number>::from_le_bytes(array),
                    ByteOrder::Big => <$number>::from_be_bytes(array),
                }
            }
        }
    )*};
}

stored!(u8, i8, u16, i16, u32, i32, u64, i64, f32, f64);

/// An `Invalid` error of the format named `format`.
fn invalid(format: &'static str, message: String) -> FormatError {
    FormatError::Invalid { format, message }
}

/// A file's bytes, read at absolute offsets in one byte order on behalf of
/// one format (named in the errors).
#[derive(Clone, Copy)]
pub(crate) struct Bytes<'a> {
    data: &'a [u8],
    format: &'static str,
    order: ByteOrder,
}

impl<'a> Bytes<'a> {
    pub(crate) fn new(data: &'a [u8], format: &'static str, order: ByteOrder) -> Self {
        Bytes {
            data,
            format,
            order,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.data.len()
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
                invalid(
                    self.format,
                    format!(
                        "{what} needs bytes {offset}..{} but the file has {} bytes",
                        offset.saturating_add(len),
                        self.data.len()
                    ),
                )
            })
    }

    /// The number at `offset`.
    pub(crate) fn read<T: Stored>(&self, offset: usize, what: &str) -> Result<T, FormatError> {
        self.slice(offset, T::SIZE, what)
            .map(|bytes| T::decode(bytes, self.order))
    }

    /// `count` numbers one after another from `offset`.
    pub(crate) fn values<T: Stored>(
        &self,
        offset: usize,
        count: usize,
        what: &str,
    ) -> Result<Vec<T>, FormatError> {
        let len = count.checked_mul(T::SIZE).ok_or_else(|| {
            invalid(
                self.format,
                format!("{what}: {count} values of {} bytes overflow", T::SIZE),
            )
        })?;
        let bytes = self.slice(offset, len, what)?;
        Ok(bytes
            .chunks_exact(T::SIZE)
            .map(|value| T::decode(value, self.order))
            .collect())
    }

    /// `count` integers of `bits` (8, 16; any other width reads as 32)
    /// bits, signed or not, from `offset`, as f64 (exact: every such
    /// integer is a double).
    pub(crate) fn integers(
        &self,
        offset: usize,
        count: usize,
        (bits, signed): (u32, bool),
        what: &str,
    ) -> Result<Vec<f64>, FormatError> {
        fn widen<T: Into<f64>>(values: Vec<T>) -> Vec<f64> {
            values.into_iter().map(Into::into).collect()
        }
        Ok(match (bits, signed) {
            (8, true) => widen(self.values::<i8>(offset, count, what)?),
            (8, false) => widen(self.values::<u8>(offset, count, what)?),
            (16, true) => widen(self.values::<i16>(offset, count, what)?),
            (16, false) => widen(self.values::<u16>(offset, count, what)?),
            (_, true) => widen(self.values::<i32>(offset, count, what)?),
            (_, false) => widen(self.values::<u32>(offset, count, what)?),
        })
    }

    /// A fixed-width text field as [`latin1`] reads it.
    pub(crate) fn text(
        &self,
        offset: usize,
        len: usize,
        what: &str,
    ) -> Result<String, FormatError> {
        self.slice(offset, len, what).map(latin1)
    }

    /// A cursor that reads on from `offset`.
    pub(crate) fn cursor(self, offset: usize) -> Cursor<'a> {
        Cursor {
            bytes: self,
            offset,
        }
    }
}

/// Reads of [`Bytes`] one after another, for headers laid out field by
/// field.
pub(crate) struct Cursor<'a> {
    bytes: Bytes<'a>,
    offset: usize,
}

impl<'a> Cursor<'a> {
    /// Where the next read starts.
    pub(crate) fn offset(&self) -> usize {
        self.offset
    }

    /// The next `len` bytes.
    pub(crate) fn take(&mut self, len: usize, what: &str) -> Result<&'a [u8], FormatError> {
        let taken = self.bytes.slice(self.offset, len, what)?;
        self.offset += len;
        Ok(taken)
    }

    /// Passes over `len` bytes (a later read says if the file ends before).
    pub(crate) fn skip(&mut self, len: usize) {
        self.offset = self.offset.saturating_add(len);
    }

    /// The next number.
    pub(crate) fn read<T: Stored>(&mut self, what: &str) -> Result<T, FormatError> {
        let value = self.bytes.read(self.offset, what)?;
        self.offset += T::SIZE;
        Ok(value)
    }
}

/// A fixed-width text field: up to the first NUL, surrounding blanks
/// trimmed, bytes outside ASCII read as Latin-1 (the vendors' Windows
/// software writes code-page text; Latin-1 never fails).
pub(crate) fn latin1(bytes: &[u8]) -> String {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    let text: String = bytes[..end].iter().map(|&b| char::from(b)).collect();
    text.trim().to_string()
}

/// The number of points of an `nx` × `ny` grid, refused when empty or above
/// `max_points` (the caller's limit, itself at most [`MAX_POINTS`]), before
/// anything is allocated; `what` says where the sizes were read.
pub(crate) fn grid_points(
    format: &'static str,
    nx: usize,
    ny: usize,
    what: &str,
    max_points: usize,
) -> Result<usize, FormatError> {
    if nx == 0 || ny == 0 {
        return Err(invalid(
            format,
            format!("{what}: an empty {nx} × {ny} grid"),
        ));
    }
    let limit = max_points.min(MAX_POINTS);
    match nx.checked_mul(ny) {
        Some(n) if n <= limit => Ok(n),
        claimed => Err(invalid(
            format,
            format!(
                "{what}: the header claims {nx} × {ny} = {} points, above the limit of {} (max_points); \
                 raise `max_points` if the map is real",
                claimed.map_or_else(|| "more than a usize counts".into(), grouped),
                grouped(limit)
            ),
        )),
    }
}

/// A count with its digits in groups of three (`268 435 456`), as messages
/// quote sizes a reader must compare at a glance.
pub(crate) fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() * 4 / 3);
    for (i, digit) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(digit);
    }
    out
}

/// A grid stored as `ny` rows of `nx` values (rows of constant y, the layout
/// of most formats read here) turned to axis 0 = x, by `height` of each
/// stored value; `rows` holds `nx × ny` values.
pub(crate) fn x_major<T: Copy>(
    nx: usize,
    ny: usize,
    rows: &[T],
    height: impl Fn(T) -> f64,
) -> Array2<f64> {
    Array2::from_shape_fn((nx, ny), |(i, j)| height(rows[j * nx + i]))
}

/// A Unix time stamp (seconds since 1970 UTC) as ISO 8601 text in UTC,
/// e.g. `2011-07-23T16:49:36Z`; `None` outside chrono's range.
pub(crate) fn utc_text(seconds: i64) -> Option<String> {
    chrono::DateTime::from_timestamp(seconds, 0)
        .map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_both_byte_orders_and_names_the_missing_bytes() {
        let data = [0x88, 0x1b, 0x03, 0x6f, 0x3f, 0x80, 0x00, 0x00];
        let big = Bytes::new(&data, "test", ByteOrder::Big);
        let little = Bytes::new(&data, "test", ByteOrder::Little);
        assert_eq!(big.read::<u32>(0, "magic").unwrap(), 0x881b_036f);
        assert_eq!(little.read::<u32>(0, "magic").unwrap(), 0x6f03_1b88);
        assert_eq!(big.read::<u16>(2, "x").unwrap(), 0x036f);
        assert_eq!(big.read::<i16>(0, "x").unwrap(), 0x881b_u16 as i16);
        assert_eq!(big.read::<f32>(4, "one").unwrap(), 1.0);
        let err = big
            .read::<u32>(6, "the phase count")
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "test: the phase count needs bytes 6..10 but the file has 8 bytes"
        );
        assert!(big.slice(usize::MAX, 2, "x").is_err());
    }

    #[test]
    fn a_cursor_reads_on_and_says_where_it_stopped() {
        let data = [1, 0, 2, 0, 0, 0, 0xff];
        let mut cursor = Bytes::new(&data, "test", ByteOrder::Little).cursor(0);
        assert_eq!(cursor.read::<u16>("a").unwrap(), 1);
        assert_eq!(cursor.read::<u32>("b").unwrap(), 2);
        assert_eq!(cursor.offset(), 6);
        let err = cursor.read::<u16>("c").unwrap_err().to_string();
        assert_eq!(err, "test: c needs bytes 6..8 but the file has 7 bytes");
        cursor.skip(usize::MAX);
        assert!(cursor.take(1, "d").is_err());
    }

    #[test]
    fn text_stops_at_nul_and_reads_latin1() {
        let bytes = Bytes::new(b" 20X  Mirau\0junk\xb5m", "test", ByteOrder::Little);
        assert_eq!(bytes.text(0, 12, "objective").unwrap(), "20X  Mirau");
        assert_eq!(bytes.text(16, 2, "unit").unwrap(), "µm");
        assert_eq!(latin1(b"mm\0\0\0\0"), "mm");
        assert_eq!(latin1(b"X               "), "X");
        assert_eq!(latin1(&[0xb5, b'm', 0]), "µm");
    }

    #[test]
    fn rows_of_constant_y_become_axis_0_x() {
        // 3 × 2 grid stored row by row: (x, y) holds 10 y + x
        let rows = [0, 1, 2, 10, 11, 12];
        let grid = x_major(3, 2, &rows, f64::from);
        assert_eq!(grid.dim(), (3, 2));
        assert_eq!(grid[[2, 0]], 2.0);
        assert_eq!(grid[[1, 1]], 11.0);
        let bytes = Bytes::new(&[1, 0, 2, 0, 3], "t", ByteOrder::Little);
        assert_eq!(bytes.values::<u16>(0, 2, "v").unwrap(), [1, 2]);
        assert!(bytes.values::<u16>(0, 3, "v").is_err());
        assert!(bytes.values::<u16>(0, usize::MAX, "v").is_err());
    }

    #[test]
    fn integers_of_each_width_and_sign_widen_exactly() {
        let raw = [0xff, 0xff, 0xff, 0xff, 0x01, 0x00, 0x00, 0x80];
        let bytes = Bytes::new(&raw, "t", ByteOrder::Little);
        assert_eq!(bytes.integers(0, 2, (8, true), "v").unwrap(), [-1.0, -1.0]);
        assert_eq!(
            bytes.integers(0, 2, (8, false), "v").unwrap(),
            [255.0, 255.0]
        );
        assert_eq!(bytes.integers(2, 2, (16, true), "v").unwrap(), [-1.0, 1.0]);
        assert_eq!(
            bytes.integers(2, 2, (16, false), "v").unwrap(),
            [65535.0, 1.0]
        );
        assert_eq!(
            bytes.integers(0, 2, (32, true), "v").unwrap(),
            [-1.0, -2_147_483_647.0]
        );
        assert_eq!(
            bytes.integers(0, 2, (32, false), "v").unwrap(),
            [4_294_967_295.0, 2_147_483_649.0]
        );
        assert!(bytes.integers(0, 3, (32, false), "v").is_err());
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
        let default = crate::DEFAULT_MAX_POINTS;
        assert_eq!(grid_points("t", 640, 480, "h", default).unwrap(), 307_200);
        assert!(grid_points("t", 0, 480, "h", default).is_err());
        assert!(grid_points("t", usize::MAX, 2, "h", usize::MAX).is_err());
        // the bomb: 16384² is refused by default, read when raised
        let e = grid_points("t", 1 << 14, 1 << 14, "bytes 4–7", default).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t: bytes 4–7: the header claims 16384 × 16384 = 268 435 456 points, above the limit of \
             67 108 864 (max_points); raise `max_points` if the map is real"
        );
        assert!(grid_points("t", 1 << 14, 1 << 14, "h", 1 << 28).is_ok());
        // never beyond the ceiling, whatever the caller asks
        assert!(grid_points("t", 1 << 17, 1 << 16, "h", usize::MAX).is_err());
    }
}
