//! The X3P writer: what it writes, the crate's reader reads back bit for bit
//! (a synthetic map with missing points, -0.0, non-square pixels and a
//! position; every reference file; arbitrary maps), the reader checks the
//! MD5 sums it writes, and what X3P cannot hold is refused.
//!
//! Read by an independent reader once, outside these tests (which do not
//! need Python), on 2026-11-24: SurfaceTopography 1.27.1 (`pip install
//! SurfaceTopography` in a venv, `read_topography`) read the files this
//! writer made of [`synthetic`] and of every reference file read here (the
//! five vendor files and datx-1, datx-2). For all eight it gave the grid,
//! the spacing (physical size / points, equal as f64) and the heights of
//! this crate's reader bit for bit, NaN (masked) at the same points (4 in
//! the synthetic map, -0.0 kept; 117 in sur-2, 116 in opd-1, 5 in each
//! datx); for the seven files, the same heights as SurfaceTopography reads
//! from the vendor files themselves (`*_m.npy`, difference 0). It named
//! the synthetic map's instrument "hypercontact (version 0.1.0)" and its
//! acquisition time 2024-05-01 10:00:00.

use crate::common;

use std::path::Path;

use common::{assert_identical, bytes, data, meta, stored_zip, zip_members};
use hypercontact_formats::{Format, FormatError, Topography, read_bytes, write_x3p};
use hypercontact_fuzz::config;
use ndarray::Array2;
use proptest::prelude::*;

/// A 7 × 5 map with non-square pixels (0.25 × 0.7 µm), a stage position,
/// four points not measured and heights that test the bits: -0.0, the
/// smallest subnormal, the largest finite number.
fn synthetic() -> Topography {
    let mut heights_m = Array2::from_shape_fn((7, 5), |(i, j)| {
        1e-6 * (0.37 * i as f64 - 0.11 * (j * j) as f64).sin()
    });
    for at in [[0, 0], [3, 2], [6, 4], [2, 1]] {
        heights_m[at] = f64::NAN;
    }
    heights_m[[1, 0]] = -0.0;
    heights_m[[4, 3]] = f64::from_bits(1);
    heights_m[[5, 1]] = f64::MAX;
    Topography {
        heights_m,
        dx_m: 0.25e-6,
        dy_m: 0.7e-6,
        format: Format::Sur,
        position_m: Some((1.5e-3, -2.25e-4)),
        metadata: vec![
            ("date".into(), "2024-05-01T10:00:00".into()),
            ("operator_name".into(), "A <&> B".into()),
            ("instrument".into(), "PLu neox".into()),
            ("comment".into(), "tile 3\u{1}".into()),
        ],
    }
}

/// The map read back from what the writer makes of it.
fn round_trip(map: &Topography) -> Topography {
    let file = write_x3p(map).unwrap();
    read_bytes(&file, Some(Path::new("written.x3p"))).unwrap()
}

/// Heights bit for bit, spacing and position to the bit.
fn assert_same(read: &Topography, written: &Topography) {
    assert_eq!(read.format, Format::X3p);
    assert_identical(&read.heights_m, &written.heights_m);
    assert_eq!(read.dx_m.to_bits(), written.dx_m.to_bits(), "dx");
    assert_eq!(read.dy_m.to_bits(), written.dy_m.to_bits(), "dy");
    let bits = |p: Option<(f64, f64)>| p.map(|(x, y)| (x.to_bits(), y.to_bits()));
    assert_eq!(bits(read.position_m), bits(written.position_m), "position");
}

#[test]
fn a_synthetic_map_reads_back_bit_for_bit() {
    let map = synthetic();
    let read = round_trip(&map);
    assert_same(&read, &map);
    assert_eq!(read.heights_m.iter().filter(|h| h.is_nan()).count(), 4);
    assert!(read.heights_m[[1, 0]].is_sign_negative());
    assert_eq!(meta(&read, "md5_point_data"), Some("verified"));
    assert_eq!(meta(&read, "md5_main_xml"), Some("verified"));
    assert_eq!(meta(&read, "z_data_type"), Some("D (float64)"));
    assert_eq!(meta(&read, "date"), Some("2024-05-01T10:00:00"));
    assert_eq!(meta(&read, "creator"), Some("A <&> B"));
    assert_eq!(
        meta(&read, "instrument"),
        Some(concat!("hypercontact version ", env!("CARGO_PKG_VERSION")))
    );
    assert_eq!(
        meta(&read, "comment"),
        Some(
            "written by hypercontact from a map read as Digital Surf .sur; \
             instrument: PLu neox; comment: tile 3\u{fffd}"
        )
    );
    let names: Vec<String> = zip_members(&write_x3p(&map).unwrap())
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    assert_eq!(
        names,
        [
            "main.xml",
            "md5checksum.hex",
            "bindata/data.bin",
            "bindata/valid.bin"
        ]
    );
}

#[test]
fn a_map_without_gaps_or_position_has_neither_mask_nor_offsets() {
    let mut map = synthetic();
    map.heights_m
        .mapv_inplace(|h| if h.is_nan() { 1e-7 } else { h });
    map.position_m = None;
    map.metadata.clear();
    let file = write_x3p(&map).unwrap();
    let members = zip_members(&file);
    assert_eq!(members.len(), 3);
    let main_xml = String::from_utf8(members[0].1.clone()).unwrap();
    assert!(!main_xml.contains("Offset"), "{main_xml}");
    assert!(!main_xml.contains("ValidPointsLink"), "{main_xml}");
    // the epoch stands for the unknown date
    assert!(main_xml.contains("<Date>1970-01-01T00:00:00Z</Date>"));
    let read = read_bytes(&file, None).unwrap();
    assert_same(&read, &map);
    assert_eq!(read.position_m, None);
}

#[test]
fn every_reference_file_reads_back_the_same() {
    let files = [
        ("x3p-2.x3p", bytes("x3p-2.x3p")),
        ("sur-2.sur", bytes("sur-2.sur")),
        ("plu-1.plu", bytes("plu-1.plu")),
        ("metropro-1.dat", bytes("metropro-1.dat")),
        ("opd-1.opd", bytes("opd-1.opd")),
        ("datx-1.datx", data("datx-1.datx")),
        ("datx-2.datx", data("datx-2.datx")),
    ];
    for (name, file) in files {
        let original = read_bytes(&file, Some(Path::new(name))).unwrap();
        let read = round_trip(&original);
        assert_same(&read, &original);
        assert_eq!(meta(&read, "md5_point_data"), Some("verified"), "{name}");
        // ISO dates carry over (X3P's own, .sur's when set, the UTC stamps)
        let date = meta(&original, "date_utc").or(meta(&original, "date"));
        if name == "x3p-2.x3p" || name == "metropro-1.dat" || name == "plu-1.plu" {
            assert_eq!(meta(&read, "date"), date, "{name}");
        }
    }
}

#[test]
fn the_reader_checks_the_md5_sums_written() {
    let file = write_x3p(&synthetic()).unwrap();
    let corrupt = |member: &str, at: usize| {
        let mut members = zip_members(&file);
        let content = &mut members.iter_mut().find(|(n, _)| n == member).unwrap().1;
        content[at] ^= 0x01;
        read_bytes(&stored_zip(&members), None)
            .unwrap_err()
            .to_string()
    };
    // re-zipped, so only the MD5 sums can notice
    let message = corrupt("bindata/data.bin", 100);
    assert!(
        message.contains("MD5 of bindata/data.bin") && message.contains("corrupt"),
        "{message}"
    );
    let message = corrupt("bindata/valid.bin", 0);
    assert!(message.contains("MD5 of bindata/valid.bin"), "{message}");
    // a digit of CX's increment: the XML stays well-formed
    let members = zip_members(&file);
    let at = String::from_utf8_lossy(&members[0].1)
        .find("<Increment>2.5e-7")
        .unwrap()
        + 11;
    let message = corrupt("main.xml", at);
    assert!(message.contains("MD5 of main.xml"), "{message}");
}

#[test]
fn the_same_map_gives_the_same_bytes() {
    assert_eq!(
        write_x3p(&synthetic()).unwrap(),
        write_x3p(&synthetic()).unwrap()
    );
}

#[test]
fn what_x3p_cannot_hold_is_refused() {
    let refused = |edit: &dyn Fn(&mut Topography)| {
        let mut map = synthetic();
        edit(&mut map);
        match write_x3p(&map) {
            Err(e @ FormatError::Unsupported { .. }) => e.to_string(),
            other => panic!("expected a refusal, got {other:?}"),
        }
    };
    let message = refused(&|m| m.heights_m = Array2::zeros((0, 3)));
    assert!(message.contains("a 0 × 3 map"), "{message}");
    let message = refused(&|m| m.dx_m = 0.0);
    assert!(message.contains("dx_m = 0"), "{message}");
    let message = refused(&|m| m.dy_m = f64::NAN);
    assert!(message.contains("dy_m = NaN"), "{message}");
    let message = refused(&|m| m.heights_m[[2, 3]] = f64::NEG_INFINITY);
    assert!(
        message.contains("-inf at x index 2, y index 3"),
        "{message}"
    );
    let message = refused(&|m| m.position_m = Some((f64::INFINITY, 0.0)));
    assert!(message.contains("position (inf, 0)"), "{message}");
}

/// Any finite f64 or NaN, from its bits (infinities become NaN).
fn height() -> impl Strategy<Value = f64> {
    any::<u64>().prop_map(|bits| {
        let h = f64::from_bits(bits);
        if h.is_infinite() { f64::NAN } else { h }
    })
}

/// A positive finite spacing over the whole range of f64.
fn spacing() -> impl Strategy<Value = f64> {
    (1u64..0x7ff0_0000_0000_0000).prop_map(f64::from_bits)
}

proptest! {
    #![proptest_config(config(128))]

    #[test]
    fn arbitrary_maps_read_back_bit_for_bit(
        (nx, ny, heights) in (1usize..9, 1usize..9).prop_flat_map(|(nx, ny)| {
            (Just(nx), Just(ny), prop::collection::vec(height(), nx * ny))
        }),
        dx_m in spacing(),
        dy_m in spacing(),
        position_m in prop::option::of((height(), height())
            .prop_map(|(x, y)| (if x.is_nan() { 0.0 } else { x }, if y.is_nan() { 0.0 } else { y }))),
    ) {
        let map = Topography {
            heights_m: Array2::from_shape_vec((nx, ny), heights).unwrap(),
            dx_m,
            dy_m,
            format: Format::Npy,
            position_m,
            metadata: Vec::new(),
        };
        let read = round_trip(&map);
        assert_same(&read, &map);
    }
}
