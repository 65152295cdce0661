//! Bad input gets an error that names the file or the parameter.

use crate::common;

use hypercontact_core::{Context, Files, Inputs, Params, Stage};
use hypercontact_dic::{Dic, DicParams};
use hypercontact_synth::encode_png;

fn error(files: &Files, params: &DicParams) -> String {
    common::dic(files, params).unwrap_err().to_string()
}

#[test]
fn a_small_sequence_runs() {
    let table = common::dic(&common::small_sequence(), &DicParams::default()).unwrap();
    assert_eq!(table.n_rows(), 3);
    assert_eq!(table.str("mode").unwrap()[0], "UT");
}

#[test]
fn mismatched_and_unreadable_images_name_the_file() {
    let mut files = common::small_sequence();
    let png = encode_png(100, 90, 16, vec![7; 9000]).unwrap();
    files.files.insert("frame_002.png".into(), png);
    let e = error(&files, &DicParams::default());
    assert!(e.contains("frame_002.png") && e.contains("100 × 90"), "{e}");

    let mut files = common::small_sequence();
    files
        .files
        .insert("frame_001.png".into(), b"not an image".to_vec());
    let e = error(&files, &DicParams::default());
    assert!(
        e.contains("frame_001.png") && e.contains("not a readable"),
        "{e}"
    );

    let mut files = common::small_sequence();
    files.files.remove("frame_001.png");
    let e = error(&files, &DicParams::default());
    assert!(e.contains("frame_001.png") && e.contains("missing"), "{e}");
}

#[test]
fn empty_roi_and_oversized_subset_name_the_parameter() {
    let files = common::small_sequence();
    let e = error(
        &files,
        &DicParams {
            roi_px: Some([60, 60, 60, 100]),
            ..Default::default()
        },
    );
    assert!(e.contains("roi_px") && e.contains("empty"), "{e}");
    let e = error(
        &files,
        &DicParams {
            roi_px: Some([60, 60, 80, 100]),
            ..Default::default()
        },
    );
    assert!(e.contains("subset_px") && e.contains("does not fit"), "{e}");
}

#[test]
fn a_force_log_that_ends_early_names_the_frame() {
    let mut files = common::small_sequence();
    let force = String::from_utf8(files.files["force.csv"].clone()).unwrap();
    let short: String = force.lines().take(10).map(|l| format!("{l}\n")).collect();
    files.files.insert("force.csv".into(), short.into_bytes());
    let e = error(&files, &DicParams::default());
    assert!(
        e.contains("force.csv") && e.contains("frame_001.png"),
        "{e}"
    );
}

#[test]
fn exactly_one_source_of_images() {
    let e = Dic
        .run(
            &DicParams::default().check().unwrap(),
            &Inputs::new(),
            &Context::new("dic"),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("`dir`") && e.contains("sequence"), "{e}");
}

#[test]
fn reads_a_folder_of_real_files() {
    let files = common::small_sequence();
    let dir = std::env::temp_dir().join(format!("hc-dic-dir-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in &files.files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let from_files = common::dic(&files, &DicParams::default()).unwrap();
    let params = DicParams {
        dir: Some(dir.clone().into()),
        ..Default::default()
    }
    .check()
    .unwrap();
    let out = Dic
        .run(&params, &Inputs::new(), &Context::new("dic"))
        .unwrap();
    let Some(hypercontact_core::Product::Table(from_dir)) = out.get("tensile") else {
        panic!("no table")
    };
    assert_eq!(
        from_dir.f64("stretch").unwrap(),
        from_files.f64("stretch").unwrap()
    );
    std::fs::remove_dir_all(dir).unwrap();
}
