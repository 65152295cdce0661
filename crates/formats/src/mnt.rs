//! stub
use crate::{Format, FormatError, Topography};
pub(crate) fn matches(_bytes: &[u8]) -> bool {
    false
}
pub(crate) fn read(_data: &[u8]) -> Result<Topography, FormatError> {
    Err(Format::Mnt.unsupported("not yet"))
}
