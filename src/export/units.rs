//! Units of exported quantities.
//!
//! Table columns follow the workspace's naming rule (STYLE.md: "names say
//! the quantity and unit": `pixel_m`, `load_n`, `mean_stress_pa`): the
//! suffix after the last `_` names the unit. A field (`.npy`) carries no
//! unit in its grid file, so the quantity and unit of each field a stage
//! declares are listed here, by the output's or the index column's name.

/// Suffixes and the units they name, longest first so `_per_m2` wins over
/// `_m2` and `_m`.
const SUFFIXES: [(&str, &str); 14] = [
    ("_per_m2", "1/m²"),
    ("_per_m", "1/m"),
    ("_percent", "%"),
    ("_m2", "m²"),
    ("_mpa", "MPa"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_pa", "Pa"),
    ("_px", "px"),
    ("_hz", "Hz"),
    ("_um", "µm"),
    ("_mb", "MB"),
    ("_m", "m"),
    ("_s", "s"),
];

/// The unit a column's name gives by its suffix (`load_n` → N), or "" when
/// the name ends in none of them. `_n` is read as newtons only as the whole
/// last word (`load_n`, `force_n`), as every other suffix.
pub fn unit_from_name(column: &str) -> &'static str {
    if column.ends_with("_n") {
        return "N";
    }
    SUFFIXES
        .iter()
        .find(|(suffix, _)| column.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

/// The fields the stages write, by output name (`height`) or by the index
/// column that lists them without its `_file` (`pressure`): quantity and
/// unit. `mirrored` (crop) and `truth` (synth-surface) are height maps;
/// `strain` is dic's Green–Lagrange E_xx; `contact` fem's contact mask.
const FIELDS: [(&str, &str, &str); 7] = [
    ("height", "height", "m"),
    ("mirrored", "height", "m"),
    ("truth", "height", "m"),
    ("strain", "E_xx", "1"),
    ("pressure", "pressure", "Pa"),
    ("gap", "gap", "m"),
    ("contact", "contact", "1"),
];

/// The quantity and unit of a field named `name`: a known one from the
/// list above, else the name itself with no unit ("").
pub fn field_quantity(name: &str) -> (&str, &'static str) {
    match FIELDS.iter().find(|(n, _, _)| *n == name) {
        Some((_, quantity, unit)) => (quantity, unit),
        None => (name, ""),
    }
}

/// The VTK array name: `quantity [unit]`, or the quantity alone.
pub fn array_name(quantity: &str, unit: &str) -> String {
    match unit {
        "" => quantity.to_owned(),
        unit => format!("{quantity} [{unit}]"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suffixes_name_units() {
        for (column, unit) in [
            ("load_n", "N"),
            ("mean_stress_pa", "Pa"),
            ("z_m", "m"),
            ("contact_area_m2", "m²"),
            ("summit_density_per_m2", "1/m²"),
            ("q_per_m", "1/m"),
            ("time_s", "s"),
            ("u_px", "px"),
            ("sdr_percent", "%"),
            ("tilt_x_rad", "rad"),
            ("angle_deg", "deg"),
            ("area_fraction", ""),
            ("step", ""),
            ("hurst", ""),
            ("mode", ""),
            ("pressure_file", ""),
        ] {
            assert_eq!(unit_from_name(column), unit, "{column}");
        }
        assert_eq!(field_quantity("mirrored"), ("height", "m"));
        assert_eq!(field_quantity("pressure"), ("pressure", "Pa"));
        assert_eq!(field_quantity("other"), ("other", ""));
        assert_eq!(array_name("gap", "m"), "gap [m]");
        assert_eq!(array_name("other", ""), "other");
    }
}
