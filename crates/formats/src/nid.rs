//! stub
use crate::{Channel, Format, FormatError, Topography};
pub(crate) fn matches(_bytes: &[u8]) -> bool {
    false
}
pub(crate) fn read(_data: &[u8], _c: &Channel) -> Result<Topography, FormatError> {
    Err(Format::Nid.unsupported("not yet"))
}
