//! Length units as instrument files write them, in metres.
//!
//! The spellings are those of the vendors' headers and of SurfaceTopography's
//! unit table (`Support/UnitConversion.py`): the micro sign as U+00B5, as the
//! Greek mu U+03BC, as ASCII `u`, and as the two Latin-1 characters `Âµ`
//! that UTF-8 `µ` becomes when a header is read as Latin-1.

/// Metres per `unit`, `None` for anything that is not a length unit.
pub(crate) fn metres_per(unit: &str) -> Option<f64> {
    let factor = match unit.trim() {
        "m" | "meter" | "meters" | "metre" | "metres" => 1.0,
        "cm" => 1e-2,
        "mm" | "millimeter" | "millimeters" | "millimetre" | "millimetres" => 1e-3,
        "µm" | "μm" | "um" | "Âµm" | "micron" | "microns" | "micrometer" | "micrometers"
        | "micrometre" | "micrometres" => 1e-6,
        "nm" | "nanometer" | "nanometers" | "nanometre" | "nanometres" => 1e-9,
        "Å" | "Ã\u{85}" | "A" | "angstrom" | "angstroms" => 1e-10,
        "pm" => 1e-12,
        _ => return None,
    };
    Some(factor)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spelling_of_a_length_unit_is_read() {
        for (unit, factor) in [
            ("m", 1.0),
            ("mm", 1e-3),
            ("µm", 1e-6),
            ("\u{3bc}m", 1e-6),
            ("um", 1e-6),
            ("Âµm", 1e-6),
            (" nm ", 1e-9),
            ("Å", 1e-10),
            ("pm", 1e-12),
        ] {
            assert_eq!(metres_per(unit), Some(factor), "{unit}");
        }
        for unit in ["V", "deg", "º", "", "N"] {
            assert_eq!(metres_per(unit), None, "{unit}");
        }
    }
}
