//! Datx reader (not yet written).

use crate::{Format, FormatError, Topography};

/// Whether the first bytes are this format's magic.
pub(crate) fn matches(_bytes: &[u8]) -> bool {
    false
}

/// Reads the file's bytes.
pub(crate) fn read(_bytes: &[u8]) -> Result<Topography, FormatError> {
    Err(FormatError::Unsupported {
        format: Format::Datx.name(),
        message: "no reader yet".into(),
    })
}
