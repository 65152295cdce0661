//! The `bem` stage end to end on small maps: κ on a self-affine surface,
//! the modulus-independence of the linear contact, the tangent model, the
//! maps, bit-identity across thread counts, and its refusals.

use std::sync::Arc;

use hypercontact_bem::stage::{Bem, BemMapIndex, BemParams, BemResponseTable};
use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{
    Checked, Context, Field, Inputs, Outputs, Params, Product, Schema, Stage, Table,
};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_material::{Hyperelastic, NeoHookean};
use ndarray::Array2;

fn sample_256() -> Field {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/samples/self-affine-256.npy"
    );
    Field::read_npy(std::fs::File::open(path).unwrap(), 2e-5, 2e-5).unwrap()
}

/// A small non-periodic self-affine map with a few unmeasured points.
fn small_map(nx: usize, ny: usize) -> Field {
    let mut values = hypercontact_synth::surface::SelfAffine {
        hurst: 0.8,
        rms_m: 1e-5,
        lambda_min_m: 4e-5,
        lambda_max_m: 2e-3,
    }
    .non_periodic(nx, ny, 2e-5, 7);
    values[[3, 5]] = f64::NAN;
    values[[nx - 1, ny / 2]] = f64::NAN;
    Field::new(values, 2e-5, 2e-5).unwrap()
}

fn params(json: &str) -> Checked<BemParams> {
    serde_json::from_str::<BemParams>(json)
        .unwrap()
        .check()
        .unwrap()
}

fn run(p: &Checked<BemParams>, surface: Field, material: &dyn Hyperelastic) -> Outputs {
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface))
        .with("material", Product::Table(to_table(material)));
    Bem.run(p, &inputs, &Context::new("bem")).unwrap()
}

fn response(out: &Outputs) -> BemResponseTable {
    match out.get("response") {
        Some(Product::Table(t)) => BemResponseTable::from_table(t).unwrap(),
        _ => panic!("no response table"),
    }
}

fn table(out: &Outputs) -> &Table {
    match out.get("response") {
        Some(Product::Table(t)) => t,
        _ => panic!("no response table"),
    }
}

fn maps(out: &Outputs) -> &hypercontact_core::Files {
    match out.get("contact_maps") {
        Some(Product::Files(f)) => f,
        _ => panic!("no contact maps"),
    }
}

#[test]
fn kappa_on_a_self_affine_map_is_about_two_at_small_load() {
    let p = params(
        r#"{"boundary": "periodic", "model": "linear", "steps": 5, "max_area_fraction": 0.05,
            "map_fractions": [0.05]}"#,
    );
    let started = std::time::Instant::now();
    let r = response(&run(&p, sample_256(), &paper_epdm()));
    eprintln!(
        "κ {:?} at A/A0 {:?} in {:?}",
        r.kappa,
        r.response.area_fraction,
        started.elapsed()
    );
    assert!(r.kappa[0].is_nan());
    for k in 1..r.kappa.len() {
        assert!(r.response.area_fraction[k] < 0.06);
        assert!(
            (2.0..=2.5).contains(&r.kappa[k]),
            "step {k}: κ = {} at A/A0 = {}",
            r.kappa[k],
            r.response.area_fraction[k]
        );
    }
    // κ falls with load (BEM literature, tamaas).
    assert!(r.kappa[1] > r.kappa[r.kappa.len() - 1]);
}

#[test]
fn response_has_icm_columns_first_and_even_area_steps() {
    let p = params(r#"{"steps": 8, "max_area_fraction": 0.4, "map_fractions": [0.1, 0.4]}"#);
    let out = run(&p, small_map(48, 40), &paper_epdm());
    let t = table(&out);
    t.validate().unwrap();
    // Readers of the shared contact-model table read it as they read icm's.
    t.conform(ResponseTable::COLUMNS).unwrap();
    let icm: Vec<&str> = ResponseTable::COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(&t.column_names()[..icm.len()], icm.as_slice());
    ResponseTable::from_table(t).unwrap();

    let r = response(&out);
    assert_eq!(r.response.z_m.len(), 9);
    assert_eq!(
        (r.response.area_fraction[0], r.response.load_n[0]),
        (0.0, 0.0)
    );
    // Hyperelastic (the default): E_t*/E0* = 2 at first contact, rising.
    assert!((r.response.tangent_ratio[0] - 2.0).abs() < 1e-9);
    for k in 1..r.response.z_m.len() {
        let target = 0.05 * k as f64;
        assert!(
            (r.response.area_fraction[k] - target).abs() <= 0.25 * 0.05 + 1e-12,
            "{k}: {}",
            r.response.area_fraction[k]
        );
        if k == 8 {
            // The top is reached, so the curve can be read at 0.4.
            assert!(
                r.response.area_fraction[k] >= 0.4,
                "{}",
                r.response.area_fraction[k]
            );
        }
        assert!(
            r.response.z_m[k] < r.response.z_m[k - 1]
                && r.response.load_n[k] > r.response.load_n[k - 1]
        );
        assert!(r.response.tangent_ratio[k] >= r.response.tangent_ratio[k - 1]);
        assert!(r.residual[k] <= 1e-8 && r.iterations[k] > 0);
    }
    let files = &maps(&out).files;
    let names: Vec<&str> = files.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "gap_a0.100.npy",
            "gap_a0.400.npy",
            "pressure_a0.100.npy",
            "pressure_a0.400.npy"
        ]
    );
    let index = BemMapIndex::from_table(maps(&out).index.as_ref().unwrap()).unwrap();
    assert_eq!(index.maps.requested_area_fraction, [0.1, 0.4]);
    assert_eq!(index.maps.pressure_file[1], "pressure_a0.400.npy");
    assert_eq!(index.gap_file[1], "gap_a0.400.npy");
    // The pressure map integrates to the step's load; the gap is closed
    // where it presses, open elsewhere, NaN where nothing was measured.
    let step = index.step[1] as usize;
    assert_eq!(step, 8);
    assert_eq!(index.maps.load_n[1], r.response.load_n[step]);
    assert_eq!(index.z_m[1], r.response.z_m[step]);
    let pressure = Field::read_npy(files["pressure_a0.400.npy"].as_slice(), 2e-5, 2e-5).unwrap();
    let gap = Field::read_npy(files["gap_a0.400.npy"].as_slice(), 2e-5, 2e-5).unwrap();
    let load: f64 = pressure.values.iter().sum::<f64>() * 4e-10;
    assert!((load / r.response.load_n[step] - 1.0).abs() < 1e-12);
    assert!(gap.values[[3, 5]].is_nan() && pressure.values[[3, 5]] == 0.0);
    let contact = pressure.values.iter().filter(|&&p| p > 0.0).count();
    let measured = gap.values.iter().filter(|g| !g.is_nan()).count();
    assert!((contact as f64 / measured as f64 - r.response.area_fraction[step]).abs() < 1e-15);
    for (p, g) in pressure.values.iter().zip(&gap.values) {
        if *p > 0.0 {
            assert!(g.abs() < 1e-6 * r.response.z_m[0]);
        } else if !g.is_nan() {
            assert!(*g >= -1e-6 * r.response.z_m[0]);
        }
    }
}

#[test]
fn linear_contact_does_not_depend_on_the_modulus_and_the_tangent_model_scales_it() {
    let soft = NeoHookean::new(0.2e6).unwrap();
    let stiff = NeoHookean::new(3e6).unwrap();
    let p = params(
        r#"{"model": "linear", "steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#,
    );
    let a = run(&p, small_map(40, 40), &soft);
    let b = run(&p, small_map(40, 40), &stiff);
    let (ra, rb) = (response(&a), response(&b));
    assert_eq!(ra.response.area_fraction, rb.response.area_fraction);
    assert_eq!(ra.response.z_m, rb.response.z_m);
    for (a, b) in ra.response.load_norm.iter().zip(&rb.response.load_norm) {
        assert!((a - b).abs() <= 1e-14 * a, "{a} {b}");
    }
    assert_eq!(
        maps(&a).files["gap_a0.200.npy"],
        maps(&b).files["gap_a0.200.npy"]
    );
    for (fa, fb) in ra.response.load_n.iter().zip(&rb.response.load_n) {
        assert!((fb - 15.0 * fa).abs() <= 1e-12 * fb, "{fa} {fb}");
    }
    assert!(ra.response.tangent_ratio.iter().all(|&t| t == 1.0));
    // The tangent model on the same contact: same areas and planes, more
    // load (the rubber stiffens in compression), never less than 2× linear.
    let h = run(
        &params(r#"{"steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#),
        small_map(40, 40),
        &soft,
    );
    let rh = response(&h);
    assert_eq!(rh.response.area_fraction, ra.response.area_fraction);
    for k in 1..rh.response.load_n.len() {
        assert!(
            rh.response.load_n[k] >= 2.0 * ra.response.load_n[k] * (1.0 - 1e-12),
            "{k}"
        );
    }
}

#[test]
fn bytes_are_the_same_on_one_two_and_three_threads() {
    let p = params(r#"{"steps": 3, "max_area_fraction": 0.3, "map_fractions": [0.15, 0.3]}"#);
    let periodic = params(
        r#"{"boundary": "periodic", "steps": 3, "max_area_fraction": 0.3, "map_fractions": [0.3]}"#,
    );
    // The map is made once, outside the pools (the generator's own
    // determinism is another crate's business).
    let map = small_map(128, 100);
    let on = |threads: usize, p: &Checked<BemParams>| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let out = run(p, map.clone(), &paper_epdm());
                let r = response(&out);
                let bits: Vec<Vec<u64>> = [
                    r.response.z_m,
                    r.response.load_n,
                    r.response.area_fraction,
                    r.kappa,
                    r.residual,
                ]
                .iter()
                .map(|c| c.iter().map(|v| v.to_bits()).collect())
                .collect();
                (bits, r.iterations, maps(&out).clone())
            })
    };
    for p in [&p, &periodic] {
        let (bits, iterations, files) = on(1, p);
        for threads in [2, 3] {
            let (other_bits, other_iterations, other_files) = on(threads, p);
            assert_eq!(bits, other_bits, "{threads} threads");
            assert_eq!(iterations, other_iterations, "{threads} threads");
            for (name, bytes) in &files.files {
                assert!(
                    other_files.files[name] == *bytes,
                    "{name} differs on {threads} threads"
                );
            }
            assert_eq!(files.index, other_files.index, "index on {threads} threads");
        }
    }
}

#[test]
fn refusals_name_what_is_wrong() {
    let e = serde_json::from_str::<BemParams>(r#"{"max_area_fraction": 0.3}"#)
        .unwrap()
        .check()
        .unwrap_err();
    assert_eq!(e.param, "map_fractions.1");
    assert!(e.message.contains("max_area_fraction"), "{e}");
    let e = serde_json::from_str::<BemParams>(r#"{"map_fractions": [0.1, 0.1001]}"#)
        .unwrap()
        .check()
        .unwrap_err();
    assert_eq!(e.param, "map_fractions.1");
    assert!(serde_json::from_str::<BemParams>(r#"{"boundary": "open"}"#).is_err());
    for bad in [
        r#"{"tolerance": 0}"#,
        r#"{"steps": 0}"#,
        r#"{"max_area_fraction": 1.5}"#,
    ] {
        let p: BemParams = serde_json::from_str(bad).unwrap();
        assert!(p.check().is_err(), "{bad}");
    }

    let fail = |surface: Field, p: &Checked<BemParams>| {
        let inputs = Inputs::new()
            .with("surface", Product::Field(surface))
            .with("material", Product::Table(to_table(&paper_epdm())));
        Bem.run(p, &inputs, &Context::new("bem"))
            .unwrap_err()
            .to_string()
    };
    let defaults = BemParams::default().check().unwrap();
    let flat = Field::new(Array2::from_elem((8, 8), 1e-6), 1e-5, 1e-5).unwrap();
    let e = fail(flat, &defaults);
    assert!(e.contains("surface") && e.contains("flat"), "{e}");
    let line = Field::new(Array2::from_elem((1, 8), 1e-6), 1e-5, 1e-5).unwrap();
    assert!(fail(line, &defaults).contains("1 × 8"));
    let mut inf = small_map(8, 8);
    inf.values[[2, 3]] = f64::INFINITY;
    assert!(fail(inf, &defaults).contains("[2, 3]"));

    // No convergence: the step, the plane, the load and the residual.
    let starved = params(
        r#"{"max_iterations": 2, "steps": 2, "max_area_fraction": 0.2, "map_fractions": []}"#,
    );
    let e = fail(small_map(32, 32), &starved);
    assert!(
        e.contains("step 1 of 2")
            && e.contains("z = ")
            && e.contains(" N")
            && e.contains("residual"),
        "{e}"
    );
}

#[test]
fn tangent_model_with_a_constant_modulus_is_the_linear_model() {
    use hypercontact_bem::{Boundary, CurveOptions, Influence, Problem, SolverOptions};
    use hypercontact_icm::{CompositeModulus, Model, Scheme};

    let map = small_map(40, 32);
    let heights: Vec<f64> = map.values.iter().copied().collect();
    let influence = Influence::new(40, 32, 2e-5, 2e-5, Boundary::Free);
    let problem = Problem::new(&influence, &heights).unwrap();
    let options = CurveOptions {
        steps: 4,
        max_area_fraction: 0.3,
        solver: SolverOptions::default(),
    };
    let rows = hypercontact_bem::solve_curve(&problem, options, &mut |_, _, _| {}).unwrap();
    let a0 = problem.measured() as f64 * 4e-10;
    let f: Vec<f64> = rows.iter().map(|r| r.mean_pressure * a0).collect();
    let area: Vec<f64> = rows
        .iter()
        .map(|r| r.contact_pixels as f64 * 4e-10)
        .collect();
    let material = Arc::new(hypercontact_material::testing::ConstantTangent { mu_pa: 1e6 });
    let modulus = CompositeModulus::new(material, Model::Hyperelastic, 0.5).unwrap();
    let e_t = modulus.at_stress_pa(0.0).unwrap();
    assert!((e_t / modulus.e0_star_pa() - 2.0).abs() < 1e-12);
    for scheme in [Scheme::Euler, Scheme::Heun] {
        let out = hypercontact_icm::tangent::integrate(&f, &area, scheme, &mut |s| {
            modulus.at_stress_pa(s).map_err(|e| e.to_string())
        })
        .unwrap();
        for (load, f) in out.load_n.iter().zip(&f) {
            assert!((load - e_t * f).abs() <= 1e-12 * e_t * f, "{scheme:?}");
        }
    }
}

/// The bands of two replicate materials, each integrated over the main
/// material's one linear solve, equal the quantiles of two full solves on
/// those materials (type 7 of two values: p05 = a + 0.05 (b − a)), on the
/// main material's axes.
#[test]
fn replicate_bands_equal_separate_solves_on_each_material() {
    use hypercontact_core::contact::BandTable;
    use hypercontact_material::bootstrap::ReplicatesTable;
    let p = params(r#"{"steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#);
    let main = paper_epdm();
    let (soft, stiff) = (
        NeoHookean::new(0.8e6).unwrap(),
        NeoHookean::new(1.1e6).unwrap(),
    );
    let replicates: [&dyn Hyperelastic; 2] = [&stiff, &soft];
    let inputs = Inputs::new()
        .with("surface", Product::Field(small_map(40, 40)))
        .with("material", Product::Table(to_table(&main)))
        .with(
            "replicates",
            Product::Table(ReplicatesTable::new((1..).zip(replicates)).into_table()),
        );
    let out = Bem.run(&p, &inputs, &Context::new("bem")).unwrap();
    let bands = match out.get("bands") {
        Some(Product::Table(t)) => BandTable::from_table(t).unwrap(),
        _ => panic!("no bands"),
    };
    let main_response = response(&out).response;
    let scale = main_response.load_n[1] / main_response.load_norm[1];
    let alone = |m: &dyn Hyperelastic| response(&run(&p, small_map(40, 40), m)).response;
    let (a, b) = (alone(&soft), alone(&stiff));
    assert_eq!(bands.area_fraction, main_response.area_fraction);
    assert_eq!(bands.replicates, vec![2; main_response.load_n.len()]);
    for k in 1..a.load_n.len() {
        let (lo, hi) = (a.load_n[k] / scale, b.load_n[k] / scale);
        for (band, q) in [(&bands.load_norm_p05, 0.05), (&bands.load_norm_p95, 0.95)] {
            let expected = lo + q * (hi - lo);
            assert!((band[k] - expected).abs() <= 1e-12 * expected, "step {k}");
        }
        let expected = a.tangent_ratio[k] + 0.5 * (b.tangent_ratio[k] - a.tangent_ratio[k]);
        assert!((bands.tangent_ratio_p50[k] - expected).abs() <= 1e-12 * expected);
    }
    // Without replicates the table has its columns and no rows.
    let bare = run(&p, small_map(40, 40), &main);
    match bare.get("bands") {
        Some(Product::Table(t)) => assert_eq!(t.n_rows(), 0),
        _ => panic!("no bands"),
    }
}
