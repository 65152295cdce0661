//! `contact-compare`'s readers on edited inputs: the mask PNGs and a
//! model's pressure `.npy` of a small valid comparison with bytes
//! overwritten, inserted or cut, and their indexes with absurd values in any
//! cell. The stage returns a result or an error, never panics; the
//! untouched inputs compare.

use hypercontact_compare::stage::{ContactCompare, ContactCompareParams};
use hypercontact_contact_images::stage::ContactTable;
use hypercontact_core::contact::{ModelMapIndex, ObservedMapIndex};
use hypercontact_core::{
    ColumnData, Context, Field, Files, Inputs, Params, Product, Schema, Stage, Table,
};
use hypercontact_fuzz::{byte_edits, config, splice};
use hypercontact_interference::{CameraGrid, GapMap, Placement, resample};
use hypercontact_labfiles::png::{Pixels, encode_png};
use proptest::prelude::*;

const N: usize = 120;
const DX_M: f64 = 2e-5;
const CAMERA_PX: usize = 96;
const CAMERA_M: f64 = 1e-5;

fn surface() -> Field {
    let values = hypercontact_synth::surface::SelfAffine {
        hurst: 0.8,
        rms_m: 5e-6,
        lambda_min_m: 6e-5,
        lambda_max_m: 1e-3,
    }
    .non_periodic(N, N, DX_M, 5);
    Field::new(values, DX_M, DX_M).unwrap()
}

/// The heights above the level of `fraction` of the points, on the camera
/// (turned 3°, shifted 0.1 mm), as an 8-bit mask PNG.
fn mask_png(surface: &Field, fraction: f64) -> Vec<u8> {
    let mut sorted: Vec<f64> = surface.values.iter().copied().collect();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let level = sorted[(fraction * sorted.len() as f64) as usize];
    let gap = surface.values.mapv(|h| level - h);
    let seen = resample(
        &GapMap {
            gap_m: gap.view(),
            dx_m: DX_M,
            dy_m: DX_M,
        },
        &Placement {
            angle_rad: 3f64.to_radians(),
            shift_x_m: 1e-4,
            shift_y_m: -5e-5,
        },
        &CameraGrid {
            width_px: CAMERA_PX,
            height_px: CAMERA_PX,
            pixel_m: CAMERA_M,
        },
    )
    .unwrap();
    let pixels = seen
        .iter()
        .map(|g| if *g <= 0.0 { 255 } else { 0 })
        .collect();
    encode_png(CAMERA_PX as u32, CAMERA_PX as u32, Pixels::Gray8(pixels)).unwrap()
}

fn npy(values: ndarray::Array2<f64>) -> Vec<u8> {
    let mut bytes = Vec::new();
    Field::new(values, DX_M, DX_M)
        .unwrap()
        .write_npy(&mut bytes)
        .unwrap();
    bytes
}

/// A valid comparison: the observed maps, a "model" whose pressure is the
/// heights above the median, and a measured curve.
fn inputs(observed: Files, model: Files) -> Inputs {
    let contact = ContactTable {
        frame: vec![0, 1, 2],
        time_s: vec![0.0, 1.0, 2.0],
        force_n: vec![0.0, 1.0, 3.0],
        area_fraction: vec![0.0, 0.3, 0.5],
        contact_area_m2: vec![0.0; 3],
        patches: vec![0; 3],
        threshold: vec![0.0; 3],
        method: vec!["calibrated".into(); 3],
    };
    Inputs::new()
        .with("contact", Product::Table(contact.into_table()))
        .with("observed_maps", Product::Files(observed))
        .with("surface", Product::Field(surface()))
        .with("model_maps.m", Product::Files(model))
}

fn observed() -> Files {
    let s = surface();
    Files::new()
        .with("mask_a0.300.png", mask_png(&s, 0.3))
        .with("mask_a0.500.png", mask_png(&s, 0.5))
        .with_index(ObservedMapIndex {
            requested_area_fraction: vec![0.3, 0.5],
            area_fraction: vec![0.3, 0.5],
            frame: vec![1, 2],
            file: vec!["mask_a0.300.png".into(), "mask_a0.500.png".into()],
            pixel_m: vec![1e-5, 1e-5],
        })
}

fn model() -> Files {
    let s = surface();
    let mut sorted: Vec<f64> = s.values.iter().copied().collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    Files::new()
        .with(
            "pressure_a0.500.npy",
            npy(s.values.mapv(|h| (h - median).max(0.0) * 1e9)),
        )
        .with_index(ModelMapIndex {
            requested_area_fraction: vec![0.5],
            area_fraction: vec![0.5],
            load_n: vec![2.0],
            pressure_file: vec!["pressure_a0.500.npy".into()],
            dx_m: vec![DX_M],
            dy_m: vec![DX_M],
        })
}

/// Values no index should hold, for the cells the fuzz test edits.
const ABSURD: [f64; 8] = [
    f64::NAN,
    f64::INFINITY,
    -1.0,
    0.0,
    1e300,
    -1e-300,
    7.5,
    1e-12,
];

/// `files`' index with cell `(column, row)` (wrapped) made absurd: a number
/// from [`ABSURD`], or a file name that is not there, empty, or reaching out.
fn edit_index(files: &mut Files, column: usize, row: usize, pick: usize) {
    let index = files.index.as_ref().unwrap();
    let name = index.column_names()[column % index.column_names().len()].to_owned();
    let mut table = Table::new();
    for c in index.columns() {
        let mut data = c.data.clone();
        if c.name == name {
            let n = data.len();
            match &mut data {
                ColumnData::F64(v) => v[row % n] = ABSURD[pick % ABSURD.len()],
                ColumnData::I64(v) => v[row % n] = [i64::MIN, -1, 0, i64::MAX][pick % 4],
                ColumnData::Str(v) => {
                    v[row % n] = ["", "absent.png", "../escape.npy", "a\0b"][pick % 4].into()
                }
            }
        }
        table.push(&c.name, data);
    }
    files.index = Some(table);
}

fn compare(inputs: &Inputs) -> Result<(), String> {
    let p = ContactCompareParams::default().check().unwrap();
    ContactCompare
        .run(&p, inputs, &Context::new("contact-compare"))
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[test]
fn the_untouched_inputs_compare_and_missing_files_are_named() {
    compare(&inputs(observed(), model())).unwrap();
    let mut gone = observed();
    gone.files.remove("mask_a0.500.png");
    let e = compare(&inputs(gone, model())).unwrap_err();
    assert!(
        e.contains("observed_maps") && e.contains("mask_a0.500.png"),
        "{e}"
    );
    let mut gone = model();
    gone.index = None;
    let e = compare(&inputs(observed(), gone)).unwrap_err();
    assert!(
        e.contains("model_maps.m") && e.contains("without an index"),
        "{e}"
    );
    let e = {
        let p = serde_json::from_str::<ContactCompareParams>(r#"{"register_with": "bem"}"#)
            .unwrap()
            .check()
            .unwrap();
        ContactCompare
            .run(
                &p,
                &inputs(observed(), model()),
                &Context::new("contact-compare"),
            )
            .unwrap_err()
            .to_string()
    };
    assert!(e.contains("register_with") && e.contains("m"), "{e}");
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn edited_inputs_never_panic(which in 0usize..2, edits in byte_edits()) {
        let (mut obs, mut m) = (observed(), model());
        let (files, name) = match which {
            0 => (&mut obs, "mask_a0.500.png"),
            _ => (&mut m, "pressure_a0.500.npy"),
        };
        let bytes = files.files[name].clone();
        files.files.insert(name.into(), splice(bytes, &edits));
        let _ = compare(&inputs(obs, m));
    }

    #[test]
    fn absurd_index_cells_never_panic(
        model_side in any::<bool>(), column in 0usize..8, row in 0usize..2, pick in 0usize..8,
    ) {
        let (mut obs, mut m) = (observed(), model());
        edit_index(if model_side { &mut m } else { &mut obs }, column, row, pick);
        let _ = compare(&inputs(obs, m));
    }
}
