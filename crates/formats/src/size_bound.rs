//! How large a file of each format may be before it is read (#31, 6): the
//! points limit (`max_points`) bounds the heights, and each format a number
//! of bytes a point may take with everything it stores per point, so a file
//! far beyond what any real map of that format could be — a real header
//! followed by gigabytes of zeros — is refused from its size alone, and no
//! reader is ever handed more than the bound.
//!
//! The budgets are generous on purpose: they bound a read, they do not
//! judge a file. Each holds every reference file of its format (see the
//! test below and `../shared/reference/topography`).

use crate::Format;

/// Room for what is not points: headers, metadata, thumbnails, XML.
pub const HEADER_ALLOWANCE_BYTES: u64 = 64 << 20;

impl Format {
    /// The most bytes a point of this format may take, counting every
    /// channel or layer and per-point mask the format can hold beside the
    /// heights.
    pub const fn max_bytes_per_point(self) -> u64 {
        match self {
            // One array of at most 8-byte values (.plu adds a 1-byte mask).
            Format::Npy | Format::Sur | Format::Plu | Format::MetroPro => 16,
            // Heights plus intensity or validity arrays.
            Format::X3p | Format::Opd | Format::Datx => 32,
            // Numbers as text: up to ~25 characters each, with separators.
            Format::AsciiMatrix | Format::DektakCsv => 64,
            // Several channels (AFM traces and retraces, texture layers).
            Format::Al3d
            | Format::Nanoscope
            | Format::Frt
            | Format::Mnt
            | Format::Nid
            | Format::Ibw
            | Format::Mi
            | Format::Tmd
            | Format::NetCdf => 128,
        }
    }
}

/// The bytes a point of `format` may take; the loosest format's budget
/// when it is not known.
pub fn bytes_per_point(format: Option<Format>) -> u64 {
    format.map_or(128, Format::max_bytes_per_point)
}

/// The largest file of `format` (the loosest format's budget when it is not
/// known) holding at most `max_points` points per channel.
pub fn max_file_bytes(format: Option<Format>, max_points: usize) -> u64 {
    let per_point = bytes_per_point(format);
    (max_points as u64)
        .saturating_mul(per_point)
        .saturating_add(HEADER_ALLOWANCE_BYTES)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Every real instrument file the project holds fits the budget of its
    /// format for its own number of points (from SurfaceTopography's
    /// heights beside it) with only 64 KiB for its header, not the 64 MiB
    /// allowance: the budgets hold real files on their own (measured
    /// ratios, bytes per point: .ibw 34.3, .nid 32.5, Dektak 17.8, .mi 16.1,
    /// .opd 13.1, the rest ≤ 9.3).
    #[test]
    fn every_reference_file_fits_its_formats_budget() {
        let root =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/reference/topography");
        let mut checked = 0;
        for dir in [root.clone(), root.join("more")] {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                let name = path.to_string_lossy().into_owned();
                if name.ends_with("_m.npy") || name.ends_with(".json") || path.is_dir() {
                    continue;
                }
                let bytes = std::fs::read(&path).unwrap();
                let format = crate::detect(&bytes, Some(&path)).unwrap_or_else(|| panic!("{name}"));
                let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
                let heights = std::fs::read(dir.join(format!("{stem}_m.npy"))).unwrap();
                // The .npy data after its header: 8 bytes a point.
                let points = (heights.len() as u64 - 128) / 8;
                let budget = points * format.max_bytes_per_point();
                assert!(
                    bytes.len() as u64 <= budget + (64 << 10),
                    "{name}: {} bytes for {points} points",
                    bytes.len()
                );
                checked += 1;
            }
        }
        assert!(checked >= 15, "only {checked} reference files");
    }

    #[test]
    fn the_bound_grows_with_the_limit_and_saturates() {
        assert_eq!(
            max_file_bytes(Some(Format::Plu), 1 << 26),
            (1 << 26) * 16 + HEADER_ALLOWANCE_BYTES
        );
        assert_eq!(max_file_bytes(None, 10), 10 * 128 + HEADER_ALLOWANCE_BYTES);
        assert_eq!(max_file_bytes(None, usize::MAX), u64::MAX);
    }
}
