//! The `fem` stage end to end on small patches: every declared output, the
//! window, coarsening and refinement, a linear material, the same bits on 1 and 2
//! threads, its refusals, and — the small-strain check of the whole chain —
//! the linear `bem` stage on the same (mirror-periodic) patch.

use hypercontact_bem::stage::{Bem, BemParams, BemResponseTable};
use hypercontact_core::{Checked, Context, Field, Inputs, Outputs, Params, Product, Schema, Stage};
use hypercontact_fem::sample::SampleSurface;
use hypercontact_fem::stage::{Fem, FemMapIndex, FemParams, FemResponseTable};
use hypercontact_material::material::{LinearElastic, Material};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::{material_to_table, to_table};
use hypercontact_surface::crop::refine;
use ndarray::Array2;

const PIXEL_M: f64 = 20e-6;

/// A 20 µm-pixel self-affine patch (rms slope about 0.2).
fn patch(n: usize, seed: u64) -> Field {
    let heights = SampleSurface {
        nx: n,
        ny: n,
        pixel_m: PIXEL_M,
        rms_m: 3e-6 * n as f64 / 32.0,
        hurst: 0.8,
        modes: 6,
        seed,
    }
    .heights_m();
    Field::new(
        Array2::from_shape_vec((n, n), heights).unwrap(),
        PIXEL_M,
        PIXEL_M,
    )
    .unwrap()
}

fn params(json: &str) -> Checked<FemParams> {
    serde_json::from_str::<FemParams>(json)
        .unwrap()
        .check()
        .unwrap()
}

fn run_with(p: &Checked<FemParams>, surface: Field, material: hypercontact_core::Table) -> Outputs {
    let inputs = Inputs::new()
        .with("surface", Product::Field(surface))
        .with("material", Product::Table(material));
    Fem.run(p, &inputs, &Context::new("fem")).unwrap()
}

fn run(p: &Checked<FemParams>, surface: Field) -> Outputs {
    run_with(p, surface, to_table(&paper_epdm()))
}

fn response(out: &Outputs) -> FemResponseTable {
    match out.get("response") {
        Some(Product::Table(t)) => FemResponseTable::from_table(t).unwrap(),
        _ => panic!("no response table"),
    }
}

fn maps(out: &Outputs) -> &hypercontact_core::Files {
    match out.get("contact_maps") {
        Some(Product::Files(f)) => f,
        _ => panic!("no contact maps"),
    }
}

fn npy(files: &hypercontact_core::Files, name: &str) -> Field {
    Field::read_npy(&files.files[name][..], 1.0, 1.0).unwrap()
}

#[test]
fn a_small_patch_writes_every_output() {
    let p = params(r#"{"steps": 6, "max_area_fraction": 0.2, "map_fractions": [0.1, 0.2]}"#);
    let out = run(&p, patch(16, 3));
    let table = response(&out);
    let r = &table.response;
    assert_eq!(r.area_fraction[0], 0.0);
    assert_eq!(r.load_n[0], 0.0);
    assert!(*r.area_fraction.last().unwrap() >= 0.2);
    // Load and area grow with the approach; z_m falls from the height range.
    for k in 1..r.load_n.len() {
        assert!(table.approach_m[k] > table.approach_m[k - 1]);
        assert!(r.load_n[k] > r.load_n[k - 1], "row {k}");
        assert!(r.area_fraction[k] >= r.area_fraction[k - 1], "row {k}");
        assert!((r.z_m[0] - r.z_m[k] - table.approach_m[k]).abs() < 1e-15);
        assert!(table.newton_iterations[k] >= 1);
        assert!(table.max_penetration_m[k] <= 1e-3 * table.approach_m[k]);
        assert!(r.tangent_ratio[k].is_nan());
        // Current area fraction near the node-counted one.
        assert!((table.area_fraction_current[k] - r.area_fraction[k]).abs() < 0.1);
    }
    // The mean gap closes by the approach, less what the block gives way.
    let closed = table.mean_gap_m[0] - table.mean_gap_m.last().unwrap();
    assert!(closed > 0.0 && closed <= *table.approach_m.last().unwrap() * 1.0001);
    // load_norm = F / (4 μ0 A0), A0 = (n − 1)² pixels.
    let a0_m2 = (15.0 * PIXEL_M).powi(2);
    let k = r.load_n.len() - 1;
    let mu0 = hypercontact_material::Hyperelastic::shear_modulus_pa(&paper_epdm());
    assert!((r.load_norm[k] - r.load_n[k] / (4.0 * mu0 * a0_m2)).abs() < 1e-12 * r.load_norm[k]);

    let files = maps(&out);
    let index = FemMapIndex::from_table(files.index.as_ref().unwrap()).unwrap();
    assert_eq!(index.maps.requested_area_fraction, vec![0.1, 0.2]);
    for (m, name) in index.maps.pressure_file.iter().enumerate() {
        let row = index.step[m] as usize;
        assert!(r.area_fraction[row] >= index.maps.requested_area_fraction[m]);
        assert!(row == 1 || r.area_fraction[row - 1] < index.maps.requested_area_fraction[m]);
        let pressure = npy(files, name);
        let contact = npy(files, &index.contact_file[m]);
        assert_eq!(pressure.values.dim(), (16, 16));
        // The mask counts the area fraction; pressure lives on it only.
        let in_contact = contact.values.iter().filter(|c| **c == 1.0).count();
        assert_eq!(in_contact as f64 / 256.0, r.area_fraction[row]);
        for (p, c) in pressure.values.iter().zip(&contact.values) {
            assert!(*c == 1.0 || *p == 0.0);
        }
        let vtk = String::from_utf8(files.files[&index.mesh_file[m]].clone()).unwrap();
        assert!(
            vtk.contains(&format!("POINTS {} double", 16 * 16 * 9)),
            "{}",
            &vtk[..200]
        );
    }
}

#[test]
fn the_window_and_coarsening_cut_what_they_say() {
    let p = params(
        r#"{"x0": 4, "y0": 2, "nx": 20, "ny": 21, "coarsen": 2, "steps": 2,
            "max_area_fraction": 0.1, "map_fractions": [0.1]}"#,
    );
    let (full, out, index, contact) = window_run(&p);
    // 20 × 21 points in blocks of 2: 10 × 10, at 40 µm.
    assert_eq!(contact.values.dim(), (10, 10));
    assert_eq!(index.maps.dx_m, vec![2.0 * PIXEL_M]);
    // The same as meshing the averaged window by hand.
    let hand = Array2::from_shape_fn((10, 10), |(i, j)| {
        let mut s = 0.0;
        for a in 0..2 {
            for b in 0..2 {
                s += full.values[[4 + 2 * i + a, 2 + 2 * j + b]];
            }
        }
        s / 4.0
    });
    same_as_whole(
        &out,
        Field::new(hand, 2.0 * PIXEL_M, 2.0 * PIXEL_M).unwrap(),
    );
}

/// `p` run on the 32² sample patch: the patch, the outputs, the map index
/// and the first contact map.
fn window_run(p: &Checked<FemParams>) -> (Field, Outputs, FemMapIndex, Field) {
    let full = patch(32, 5);
    let out = run(p, full.clone());
    let files = maps(&out);
    let index = FemMapIndex::from_table(files.index.as_ref().unwrap()).unwrap();
    let contact = npy(files, &index.contact_file[0]);
    (full, out, index, contact)
}

/// `out`'s response equals that of the whole of `map` meshed with the same
/// steps (NaN tangent ratios: the rows are compared as printed).
fn same_as_whole(out: &Outputs, map: Field) {
    let whole = params(r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1]}"#);
    let by_hand = run(&whole, map);
    assert_eq!(
        format!("{:?}", response(out)),
        format!("{:?}", response(&by_hand))
    );
}

/// `refine` reaches the mesh: the same as meshing the window refined by
/// hand, as the `crop` stage refines it.
#[test]
fn refine_meshes_the_window_refined_as_crop_refines_it() {
    let p = params(
        r#"{"x0": 3, "y0": 5, "nx": 9, "ny": 8, "refine": 2, "steps": 2,
            "max_area_fraction": 0.1, "map_fractions": [0.1]}"#,
    );
    let (full, out, index, contact) = window_run(&p);
    // 9 × 8 points refined twice: 17 × 15, at 10 µm.
    assert_eq!(contact.values.dim(), (17, 15));
    assert_eq!(index.maps.dx_m, vec![PIXEL_M / 2.0]);
    let cut = Array2::from_shape_fn((9, 8), |(i, j)| full.values[[3 + i, 5 + j]]);
    let window = Field::new(cut, PIXEL_M, PIXEL_M).unwrap();
    same_as_whole(&out, refine(&window, 2).unwrap());
}

/// `lateral_coarsening` reaches the mesh: the deformed mesh keeps the
/// lattice's points (unused ones unreferenced) with fewer cells, and
/// `max_nodes` counts the nodes elements use.
#[test]
fn lateral_coarsening_meshes_fewer_cells() {
    let p = params(
        r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1],
            "lateral_coarsening": true}"#,
    );
    let out = run(&p, patch(16, 3));
    let files = maps(&out);
    let index = FemMapIndex::from_table(files.index.as_ref().unwrap()).unwrap();
    let vtk = String::from_utf8(files.files[&index.mesh_file[0]].clone()).unwrap();
    assert!(vtk.contains(&format!("POINTS {} double", 16 * 16 * 9)));
    // 15 pixels deep: layers 4.2, 3.1, 2.3, 1.7 … pixels thick, elements
    // 4, 2, 2 and then 1 pixel wide: 4² + 2 × 8² + 5 × 15² cells.
    let cells = 16 + 2 * 64 + 5 * 225;
    assert!(
        vtk.contains(&format!("CELLS {cells} {}", 9 * cells)),
        "{}",
        &vtk[..300]
    );
    let table = response(&out);
    assert!(*table.response.area_fraction.last().unwrap() >= 0.1);
    let small = params(
        r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1], "max_nodes": 100,
            "lateral_coarsening": true}"#,
    );
    let message = Fem
        .run(
            &small,
            &Inputs::new()
                .with("surface", Product::Field(patch(12, 1)))
                .with("material", Product::Table(to_table(&paper_epdm()))),
            &Context::new("fem"),
        )
        .unwrap_err()
        .to_string();
    // 12² with 8 layers: levels 0 and 1 on every second point (7 × 7).
    let nodes = 2 * 49 + 7 * 144;
    assert!(
        message.contains(&format!("{nodes} nodes, above max_nodes = 100")),
        "{message}"
    );
}

#[test]
fn the_same_bits_on_one_and_two_threads() {
    let p = params(r#"{"steps": 6, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#);
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&p, patch(16, 3)))
    };
    let (one, two) = (on(1), on(2));
    assert_eq!(
        format!("{:?}", response(&one)),
        format!("{:?}", response(&two))
    );
    assert_eq!(maps(&one).files, maps(&two).files);
}

#[test]
fn refusals_name_what_is_wrong() {
    let p = params(r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1]}"#);
    let error = |surface: Field, p: &Checked<FemParams>| {
        let inputs = Inputs::new()
            .with("surface", Product::Field(surface))
            .with("material", Product::Table(to_table(&paper_epdm())));
        Fem.run(p, &inputs, &Context::new("fem"))
            .unwrap_err()
            .to_string()
    };
    let mut holed = patch(12, 1);
    holed.values[[3, 7]] = f64::NAN;
    let message = error(holed, &p);
    assert!(
        message.contains("1 of the window's 144 points"),
        "{message}"
    );
    assert!(message.contains("(3, 7)"), "{message}");
    let big = params(
        r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1], "max_nodes": 100}"#,
    );
    let message = error(patch(12, 1), &big);
    assert!(
        message.contains("1296 nodes, above max_nodes = 100"),
        "{message}"
    );
    // 12² × 9 levels: a factor of a few MB, above 1 MB.
    let tight = params(
        r#"{"steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1], "max_memory_gb": 0.001}"#,
    );
    let message = error(patch(12, 1), &tight);
    assert!(
        message.contains("(1296 nodes,") && message.contains("above max_memory_gb = 0.001"),
        "{message}"
    );
    let flat = Field::new(Array2::zeros((8, 8)), PIXEL_M, PIXEL_M).unwrap();
    assert!(error(flat, &p).contains("flat"));
    let outside =
        params(r#"{"x0": 12, "steps": 2, "max_area_fraction": 0.1, "map_fractions": [0.1]}"#);
    assert!(error(patch(12, 1), &outside).contains("x0 = 12"));
    // A map fraction above the curve's end is refused when checked.
    let bad =
        serde_json::from_str::<FemParams>(r#"{"max_area_fraction": 0.1, "map_fractions": [0.2]}"#)
            .unwrap()
            .check()
            .unwrap_err()
            .to_string();
    assert!(bad.contains("map_fractions.0"), "{bad}");
}

/// The small-strain limit of the whole chain: a linear material in `fem`
/// with periodic faces against the linear `bem` stage on the same periodic
/// map, mean pressure at equal approach (the block, incompressible and
/// confined, keeps its mean top displacement at zero, as bem's periodic
/// half-space does, so the approach means the same in both). The surface is
/// a sum of cosines resolved at 8 points per shortest wavelength.
///
/// Measured (this test's print): fem / bem = 0.983 at 18 % contact; 0.76 at
/// 2.5 %, where contact spots are one or two nodes (a node-counted contact
/// against bem's pixels of constant pressure) and bem is interpolated
/// between rows far apart. With finer steps on this map: 0.73 at 1.6 %,
/// 0.98 from 7 % to 11 %; on the same surface at 4 points per wavelength
/// (24², 20 µm): 0.77, 0.86, 0.91, 0.92 at 2, 5, 6 and 10 % — the gap
/// closes as the contact spots are resolved.
#[test]
fn a_linear_material_agrees_with_bem_on_a_periodic_map() {
    let (n, pixel_m) = (48, 10e-6);
    let heights = SampleSurface {
        nx: n,
        ny: n,
        pixel_m,
        rms_m: 2.25e-6,
        hurst: 0.8,
        modes: 6,
        seed: 13,
    }
    .heights_m();
    let map = Field::new(
        Array2::from_shape_vec((n, n), heights.clone()).unwrap(),
        pixel_m,
        pixel_m,
    )
    .unwrap();
    let extended = hypercontact_fem::mesh::periodic_extension(&heights, n, n);
    let block = Field::new(
        Array2::from_shape_vec((n + 1, n + 1), extended).unwrap(),
        pixel_m,
        pixel_m,
    )
    .unwrap();
    let linear = material_to_table(&Material::Linear(LinearElastic::new(3e6, 0.5).unwrap()));
    let p = params(
        r#"{"boundary": "periodic", "steps": 3, "max_area_fraction": 0.1,
            "map_fractions": [0.1], "layers": 12}"#,
    );
    let fem = response(&run_with(&p, block, linear.clone()));
    let bem = bem_linear(map, linear, 10, 0.25);
    let area_m2 = (n as f64 * pixel_m).powi(2);
    let mut judged = 0;
    for (fraction, ratio) in pressure_ratios((&fem, area_m2), (&bem, area_m2)) {
        if fraction >= 0.05 {
            assert!((ratio - 1.0).abs() < 0.05, "A/A0 {fraction}: {ratio}");
            judged += 1;
        }
    }
    assert!(judged >= 1);
}

/// The linear `bem` stage (periodic boundary) on `map`: its response.
fn bem_linear(
    map: Field,
    material: hypercontact_core::Table,
    steps: usize,
    max_area_fraction: f64,
) -> BemResponseTable {
    let bem_params: Checked<BemParams> = serde_json::from_value::<BemParams>(serde_json::json!({
        "boundary": "periodic", "model": "linear", "steps": steps,
        "max_area_fraction": max_area_fraction, "map_fractions": [max_area_fraction]
    }))
    .unwrap()
    .check()
    .unwrap();
    let inputs = Inputs::new()
        .with("surface", Product::Field(map))
        .with("material", Product::Table(material));
    match Bem
        .run(&bem_params, &inputs, &Context::new("bem"))
        .unwrap()
        .get("response")
    {
        Some(Product::Table(t)) => BemResponseTable::from_table(t).unwrap(),
        _ => panic!("no bem response"),
    }
}

/// fem's mean pressure over bem's at fem's approaches (bem's, since first
/// touch: z_m is the plane above the lowest point, so z[0] − z;
/// interpolated linearly), with fem's A/A0; each load over its own nominal
/// area (m²). Printed, for the tests' figures.
fn pressure_ratios(
    (fem, fem_area_m2): (&FemResponseTable, f64),
    (bem, bem_area_m2): (&BemResponseTable, f64),
) -> Vec<(f64, f64)> {
    let z = &bem.response.z_m;
    let bem_approach: Vec<f64> = z.iter().map(|z_m| z[0] - z_m).collect();
    let bem_p: Vec<f64> = (bem.response.load_n.iter())
        .map(|f| f / bem_area_m2)
        .collect();
    let mut ratios = Vec::new();
    for k in 1..fem.response.load_n.len() {
        let d = fem.approach_m[k];
        let j = bem_approach
            .iter()
            .position(|a| *a > d)
            .expect("bem reaches the approach");
        let t = (d - bem_approach[j - 1]) / (bem_approach[j] - bem_approach[j - 1]);
        let at_d = bem_p[j - 1] + t * (bem_p[j] - bem_p[j - 1]);
        let ratio = fem.response.load_n[k] / fem_area_m2 / at_d;
        let fraction = fem.response.area_fraction[k];
        let bem_a = bem.response.area_fraction[j - 1]
            + t * (bem.response.area_fraction[j] - bem.response.area_fraction[j - 1]);
        println!("approach {d:.4e} m, A/A0 {fraction:.3} (bem {bem_a:.3}): fem / bem = {ratio:.4}");
        ratios.push((fraction, ratio));
    }
    ratios
}

/// The paper pipeline's finite-strain comparison in its small-strain limit
/// (issue #49): a linear solid in `fem` with mirror faces (the window as
/// it is) against the linear `bem` on the window's mirror-image tiling
/// (periodic), mean pressure at equal approach, on a window refined 2× as
/// `crop` refines it, with the top layer about 1.7 dx thick. The block's
/// depth is what is left between them: bem's periodic half-space is
/// softer than a block on a rigid base, most for the tiling's longest
/// wavelength (twice the window). Measured on the paper's t1 patch
/// (48², 20 µm, refine 2, A/A0 0.05–0.2): fem / bem = 1.04–1.05 at depth
/// L (the default, the window's side) and 0.997–0.999 at depth 2L; at
/// refine 3 with depth L, 1.04–1.05 again (the gap is depth, not grid).
/// This test's smaller window (24² at 20 µm, refine 2, A/A0 0.1–0.2; its
/// print): 0.991–0.993 at depth 2L, 1.003–1.010 at depth L; held to 3 % at
/// 2L, and depth L stiffer than 2L by more than 1 %.
#[test]
fn a_deep_mirror_block_agrees_with_bem_on_the_mirror_tiling() {
    let (n, k) = (24, 2);
    let window = refine(&patch(n, 5), k).unwrap();
    let (m, dx) = (window.values.dim().0, window.dx_m);
    let side_m = (m - 1) as f64 * dx;
    let tiling = hypercontact_surface::crop::mirror_extension(&window).unwrap();
    let linear = material_to_table(&Material::Linear(LinearElastic::new(3e6, 0.5).unwrap()));
    let bem = bem_linear(tiling, linear.clone(), 30, 0.3);
    // Top layer ≈ 1.7 dx in both: 10 layers in geometric progression fill
    // the depth with bottom/top ratio 14.7 (2L) or 5.5 (L).
    let mean_ratio = |depth_m: f64, grading: f64| -> f64 {
        let p = params(&format!(
            r#"{{"boundary": "mirror", "strain": "small", "steps": 6, "max_area_fraction": 0.2,
                "map_fractions": [0.2], "layers": 10, "grading": {grading},
                "depth_m": {depth_m}, "lateral_coarsening": true}}"#
        ));
        let fem = response(&run_with(&p, window.clone(), linear.clone()));
        let judged: Vec<f64> =
            pressure_ratios((&fem, side_m * side_m), (&bem, 4.0 * side_m * side_m))
                .into_iter()
                .filter(|(fraction, _)| *fraction >= 0.05)
                .map(|(_, ratio)| ratio)
                .collect();
        assert!(judged.len() >= 2, "{judged:?}");
        judged.iter().sum::<f64>() / judged.len() as f64
    };
    let deep = mean_ratio(2.0 * side_m, 14.7);
    let shallow = mean_ratio(side_m, 5.5);
    println!("mean fem / bem: depth 2L {deep:.4}, depth L {shallow:.4}");
    assert!((deep - 1.0).abs() < 0.03, "depth 2L: {deep}");
    assert!(shallow > deep + 0.01, "depth L {shallow} against 2L {deep}");
}

/// `strain: small` is linear elasticity with the material's μ0 on the same
/// mesh: the same curve as a linear material with E = 3 μ0, ν = ½; and at
/// the small strains of a gentle patch the finite-strain load is within a
/// few per cent of it (issue #33's felupe look: 0.97–1.00).
#[test]
fn small_strain_is_the_linear_solid_of_the_initial_moduli() {
    let surface = patch(16, 3);
    let small = params(
        r#"{"strain": "small", "steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#,
    );
    let ours = response(&run(&small, surface.clone()));
    let mu0 = hypercontact_material::Hyperelastic::shear_modulus_pa(&paper_epdm());
    let linear = material_to_table(&Material::Linear(
        LinearElastic::new(3.0 * mu0, 0.5).unwrap(),
    ));
    let finite = params(r#"{"steps": 4, "max_area_fraction": 0.2, "map_fractions": [0.2]}"#);
    let theirs = response(&run_with(&finite, surface.clone(), linear));
    assert_eq!(ours.response.area_fraction, theirs.response.area_fraction);
    for (a, b) in ours.response.load_n.iter().zip(&theirs.response.load_n) {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
    }
    let hyper = response(&run(&finite, surface));
    let last = hyper.response.load_n.len() - 1;
    assert_eq!(hyper.approach_m[1], ours.approach_m[1]);
    let ratio = hyper.response.load_n[1] / ours.response.load_n[1];
    println!("finite / small at the first step: {ratio}");
    assert!((ratio - 1.0).abs() < 0.05, "{ratio}");
    assert!(hyper.response.load_n[last] > 0.0);
}
