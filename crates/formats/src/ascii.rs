//! stub
use crate::{Format, FormatError, Topography};
pub(crate) fn matches(_bytes: &[u8]) -> bool {
    false
}
pub(crate) fn read(_data: &[u8], _c: &crate::Channel) -> Result<Topography, FormatError> {
    Err(Format::AsciiMatrix.unsupported("not yet"))
}
pub(crate) fn plausible(_bytes: &[u8]) -> bool {
    false
}
