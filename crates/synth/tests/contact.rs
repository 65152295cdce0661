//! Stage `synth-contact`: the lab files it writes and their truth.

use hypercontact_core::contact::ObservedMapIndex;
use hypercontact_core::{Context, Field, Files, Inputs, Params, Product, Schema, Stage};
use hypercontact_labfiles::FileSource;
use hypercontact_labfiles::sequence::Sequence;
use hypercontact_synth::contact::{
    ContactTruthTable, RigTruthTable, SynthContact, SynthContactParams,
};
use ndarray::Array2;

/// A paraboloid cap (R = 20 mm) on a 1.2 mm square map of 10 µm.
fn cap() -> Field {
    let (n, d, radius) = (121, 1e-5, 2e-2);
    let h = Array2::from_shape_fn((n, n), |(i, j)| {
        let x = (i as f64 - 60.0) * d;
        let y = (j as f64 - 60.0) * d;
        -(x * x + y * y) / (2.0 * radius)
    });
    Field::new(h, d, d).unwrap()
}

fn run(json: &str) -> Result<(Files, ContactTruthTable, RigTruthTable, Files), String> {
    let p = serde_json::from_str::<SynthContactParams>(json)
        .unwrap()
        .check()
        .map_err(|e| e.to_string())?;
    let material = hypercontact_material::presets::preset("paper-epdm").unwrap();
    let inputs = Inputs::new().with("surface", Product::Field(cap())).with(
        "material",
        Product::Table(hypercontact_material::table::to_table(material.as_ref())),
    );
    let out = SynthContact
        .run(&p, &inputs, &Context::new("synth-contact"))
        .map_err(|e| e.to_string())?;
    let files = |name: &str| out.get_files(name).expect(name).clone();
    let table = |name: &str| out.get_table(name).expect(name).clone();
    Ok((
        files("sequence"),
        ContactTruthTable::from_table(&table("truth")).unwrap(),
        RigTruthTable::from_table(&table("truth_rig")).unwrap(),
        files("truth_maps"),
    ))
}

const SMALL: &str = r#""width_px": 96, "height_px": 80, "resolution_m": 1e-5,
    "magnification": 0.65, "max_area_fraction": 0.3, "shift_x_m": 0, "shift_y_m": 0"#;

#[test]
fn writes_the_lab_files_and_a_consistent_truth() {
    let (sequence, truth, rig, maps) =
        run(&format!("{{{SMALL}, \"frames\": 8, \"bits\": 12}}")).unwrap();
    // The lab files as the analysis reads them (the workspace's one reader).
    let lab = Sequence::open(FileSource::Files {
        files: &sequence,
        input: "sequence".into(),
    })
    .unwrap();
    // frames.csv: exposure starts, every frame interval
    let frames = String::from_utf8(sequence.files["frames.csv"].clone()).unwrap();
    assert_eq!(frames.lines().next(), Some("frame,time_s,file"));
    assert_eq!(lab.frames.len(), 8);
    let interval = rig.frame_interval_s[0];
    for (k, entry) in lab.frames.iter().enumerate() {
        let t = entry.time_s;
        assert_eq!(entry.frame, k as i64);
        assert!((t - k as f64 * interval).abs() < 1e-9 * (1.0 + t));
        assert_eq!(entry.file, format!("frame_{k:03}.png"));
        // a 12-bit camera's counts, unscaled in a 16-bit PNG
        let png = image::load_from_memory(&sequence.files[&entry.file]).unwrap();
        assert_eq!((png.width(), png.height()), (96, 80));
        assert_eq!(png.color(), image::ColorType::L16);
        let counts = png.into_luma16().into_raw();
        assert!(counts.iter().all(|&c| c < 4096));
        // the background (no near-contact fringes) at about half of the full scale
        assert!(counts.iter().any(|&c| c > 1500), "under-exposed");
    }
    // Three frames before contact (the default), then growing contact and
    // force; the last frame at the requested A/A0 of the whole map.
    assert_eq!(truth.area_fraction[..3], [0.0; 3]);
    assert!(truth.penetration_m[..3].iter().all(|d| *d < 0.0));
    for w in truth.force_n[3..].windows(2) {
        assert!(w[1] > w[0], "{:?}", truth.force_n);
    }
    let last = *truth.area_fraction.last().unwrap();
    assert!((0.3..0.33).contains(&last), "{last}");
    // The ramp: 3 µm/s between frames, first contact 0.3 intervals before frame 3.
    let d = &truth.penetration_m;
    assert!((d[5] - d[4] - 3e-6 * interval).abs() < 1e-15);
    assert!((truth.mid_time_s[3] - rig.contact_time_s[0] - 0.3 * interval).abs() < 1e-9);
    assert_eq!(rig.angle_rad, [2.5f64.to_radians()]);
    assert!((rig.pixel_m[0] - 1e-5).abs() < 1e-18);

    // The force log on the sensor's clock: 50 Hz, multiples of 0.01 N,
    // the true force within resolution and noise (5 σ).
    let force = String::from_utf8(sequence.files["force.csv"].clone()).unwrap();
    assert!(!force.contains("-0.00\n"));
    let log = &lab.force;
    for k in 3..8 {
        let sensor_s = truth.mid_time_s[k] + 0.37;
        let j = log.partition_point(|(t, _)| *t < sensor_s);
        let (t, f) = log[j];
        assert!((t - sensor_s).abs() <= 0.02);
        // the force changes by little within one 20 ms sample here
        assert!(
            (f - truth.force_n[k]).abs() < 0.005 + 5.0 * 0.005 + 0.01 * truth.force_n[k],
            "frame {k}: {f} vs {}",
            truth.force_n[k]
        );
    }

    // True maps: 8-bit masks whose contact fraction is the view's A/A0.
    let index = ObservedMapIndex::from_table(maps.index.as_ref().unwrap()).unwrap();
    assert_eq!(index.frame.len(), index.file.len());
    for (k, file) in index.file.iter().enumerate() {
        let frame = index.frame[k] as usize;
        assert_eq!(index.area_fraction[k], truth.view_area_fraction[frame]);
        let mask = image::load_from_memory(&maps.files[file])
            .unwrap()
            .into_luma8();
        let contact = mask.pixels().filter(|p| p.0[0] == 255).count();
        let fraction = contact as f64 / (96.0 * 80.0);
        assert!((fraction - truth.view_area_fraction[frame]).abs() < 1e-12);
    }
}

/// The truth names the physics that rendered the frames (#49): the paper's
/// hyperelastic BEM with the equibiaxial tangent by default, the linear BEM
/// with `model: linear`; same contact, the linear force below the
/// tangent-modulus one (E_t*/E0* = 2 at first contact).
#[test]
fn the_truth_names_the_physics_of_each_law() {
    let truth = |law: &str| run(&format!("{{{SMALL}, \"frames\": 6{law}}}")).unwrap().1;
    let hyper = truth("");
    let linear = truth(r#", "model": "linear""#);
    let uniaxial = truth(r#", "tangent": "uniaxial", "boundary": "periodic""#);
    let one = |t: &ContactTruthTable| {
        assert_eq!(t.physics.len(), 6);
        assert!(
            t.physics.iter().all(|p| *p == t.physics[0]),
            "{:?}",
            t.physics
        );
        t.physics[0].clone()
    };
    assert_eq!(
        one(&hyper),
        "bem, hyperelastic, equibiaxial tangent, free boundary"
    );
    assert_eq!(
        one(&linear),
        "bem, linear elastic, small-strain modulus, free boundary"
    );
    assert_eq!(
        one(&uniaxial),
        "bem, hyperelastic, uniaxial tangent, periodic boundary"
    );
    assert_eq!(hyper.area_fraction, linear.area_fraction);
    for k in 3..6 {
        let ratio = hyper.force_n[k] / linear.force_n[k];
        assert!(ratio > 1.9, "frame {k}: {ratio}");
    }
}

#[test]
fn refuses_a_view_beyond_the_map_and_frames_faster_than_the_exposure() {
    let e = run(r#"{"width_px": 96, "height_px": 80, "resolution_m": 1e-5, "magnification": 0.5}"#)
        .unwrap_err();
    assert!(e.contains("reaches beyond the 1.20 × 1.20 mm map"), "{e}");
    let e = run(&format!("{{{SMALL}, \"frames\": 3000}}")).unwrap_err();
    assert!(e.contains("shorter than the 0.05 s exposure"), "{e}");
    let e = run(&format!(
        "{{{SMALL}, \"frames\": 8, \"frames_before_contact\": 7}}"
    ))
    .unwrap_err();
    assert!(e.contains("frames_before_contact"), "{e}");
}

#[test]
fn same_bytes_on_one_and_two_threads() {
    let once = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&format!("{{{SMALL}, \"frames\": 8}}")).unwrap())
    };
    let (a, ta, _, _) = once(1);
    let (b, tb, _, _) = once(2);
    assert_eq!(a, b);
    assert_eq!(ta, tb);
}
