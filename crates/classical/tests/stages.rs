//! The `persson` and `greenwood-williamson` stages on a synthetic map: the
//! icm columns, the theories' limits through the stage, the two input
//! routes agreeing, and every misuse named.

use hypercontact_classical::stage::{
    GreenwoodWilliamson, GwParams, GwResponseTable, PerssonParams, PerssonResponseTable,
    PerssonStage,
};
use hypercontact_core::contact::ResponseTable;
use hypercontact_core::{Context, Field, Inputs, Params, Product, Schema, Stage, Table};
use hypercontact_material::presets::paper_epdm;
use hypercontact_material::table::to_table;
use hypercontact_surface::psd::{Window, psd_radial};
use hypercontact_surface::surface_stage::{PsdTable, StatsTable};
use hypercontact_synth::surface::self_affine::SelfAffine;

const N: usize = 128;
const PIXEL_M: f64 = 20e-6;

fn map() -> Field {
    let surface = SelfAffine {
        hurst: 0.8,
        rms_m: 10e-6,
        lambda_min_m: 4.0 * PIXEL_M,
        lambda_max_m: 0.5 * N as f64 * PIXEL_M,
    };
    Field::new(surface.periodic(N, N, PIXEL_M, 3), PIXEL_M, PIXEL_M).unwrap()
}

fn material() -> Product {
    Product::Table(to_table(&paper_epdm()))
}

/// Stage surface's tables of the map: the radial PSD as it computes it
/// (periodic: no window) and the one-row stats.
fn psd_and_stats() -> (Table, Table) {
    let f = map();
    let spectrum = psd_radial(&f.values, PIXEL_M, PIXEL_M, Window::None, 10);
    let mut psd = PsdTable::default();
    psd.push("radial", &spectrum);
    let stats = StatsTable {
        sigma_m: vec![10e-6],
        rms_slope: vec![0.1],
        hurst_x: vec![0.8],
        hurst_y: vec![0.8],
        hurst_radial: vec![0.8],
        nx: vec![N as i64],
        ny: vec![N as i64],
        dx_m: vec![PIXEL_M],
        nan_fraction: vec![0.0],
        ..Default::default()
    };
    (psd.into_table(), stats.into_table())
}

fn persson(json: &str, inputs: &Inputs) -> Result<(PerssonResponseTable, Table), String> {
    let p: PerssonParams = serde_json::from_str(json).map_err(|e| e.to_string())?;
    let p = p.check().map_err(|e| e.to_string())?;
    let out = PerssonStage
        .run(&p, inputs, &Context::new("t"))
        .map_err(|e| e.to_string())?;
    let table = |name| match out.get(name) {
        Some(Product::Table(t)) => t.clone(),
        _ => panic!("no {name}"),
    };
    Ok((
        PerssonResponseTable::from_table(&table("response")).unwrap(),
        table("summary"),
    ))
}

fn from_map() -> Inputs {
    Inputs::new()
        .with("surface", Product::Field(map()))
        .with("material", material())
}

fn from_psd() -> Inputs {
    let (psd, stats) = psd_and_stats();
    Inputs::new()
        .with("psd", Product::Table(psd))
        .with("stats", Product::Table(stats))
        .with("material", material())
}

#[test]
fn persson_emits_the_icm_columns_and_its_small_load_slope() {
    let (r, summary) = persson(
        r#"{"model": "linear", "periodic": true, "steps": 50}"#,
        &from_map(),
    )
    .unwrap();
    let t = r.clone().into_table();
    t.conform(ResponseTable::COLUMNS).unwrap();
    let names: Vec<&str> = ResponseTable::COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(&t.column_names()[..6], &names[..]);
    assert_eq!(r.response.area_fraction.len(), 50);
    assert!((r.response.area_fraction[0] / 0.001 - 1.0).abs() < 1e-9);
    assert!((r.response.area_fraction[49] / 0.95 - 1.0).abs() < 1e-9);
    // Linear, original: κ on the spectrum's own h'rms is √(8/π) at small load.
    assert!(
        (r.kappa[0] / (8.0 / std::f64::consts::PI).sqrt() - 1.0).abs() < 1e-3,
        "{}",
        r.kappa[0]
    );
    assert!(r.response.tangent_ratio.iter().all(|&x| x == 1.0));
    // A0 = the map's area; z_m is the mean separation, falling with load.
    let a0 = (N * N) as f64 * PIXEL_M * PIXEL_M;
    let e0 = summary.f64("e0_star_pa").unwrap()[0];
    assert!((r.response.load_n[10] / (r.response.load_norm[10] * e0 * a0) - 1.0).abs() < 1e-12);
    assert_eq!(r.response.z_m, r.mean_separation_m);
    assert!(r.response.z_m.windows(2).all(|w| w[1] < w[0]));
    assert_eq!(summary.str("variant").unwrap()[0], "original");
    assert_eq!(summary.str("input").unwrap()[0], "surface");
}

#[test]
fn the_psd_route_and_the_map_route_agree() {
    let json = r#"{"variant": "yang-persson", "periodic": true, "steps": 30}"#;
    let (a, _) = persson(json, &from_map()).unwrap();
    let (b, summary) = persson(json, &from_psd()).unwrap();
    assert_eq!(summary.str("input").unwrap()[0], "psd");
    // The same spectrum up to rounding (the map route removes the mean
    // first); the corrected march's Runge–Kutta steps (≤ 5 % of x, error
    // ~1e-7) may fall differently on such a change.
    for (x, y) in a.response.load_n.iter().zip(&b.response.load_n) {
        assert!((x / y - 1.0).abs() < 1e-6, "{x} vs {y}");
    }
    for (x, y) in a
        .response
        .area_fraction
        .iter()
        .zip(&b.response.area_fraction)
    {
        assert!((x / y - 1.0).abs() < 1e-9, "{x} vs {y}");
    }
}

#[test]
fn hyperelastic_persson_stiffens_and_the_corrected_variant_needs_less_load() {
    let (hyper, _) = persson(r#"{"periodic": true}"#, &from_map()).unwrap();
    let (linear, _) = persson(r#"{"periodic": true, "model": "linear"}"#, &from_map()).unwrap();
    // E_t*/E0* above 2 from the first row (the contact stress is not zero
    // there) and rising; more load than the linear law at every area.
    assert!(hyper.response.tangent_ratio[0] > 2.0);
    assert!(
        hyper
            .response
            .tangent_ratio
            .windows(2)
            .all(|w| w[1] >= w[0])
    );
    assert!(
        hyper
            .response
            .load_n
            .iter()
            .zip(&linear.response.load_n)
            .all(|(h, l)| h > &(2.0 * l))
    );
    let (corrected, _) = persson(
        r#"{"periodic": true, "variant": "yang-persson"}"#,
        &from_map(),
    )
    .unwrap();
    // Rows 0 and last sit at min and max A/A0 in both.
    for k in [0, 199] {
        assert!(
            (corrected.response.area_fraction[k] / hyper.response.area_fraction[k] - 1.0).abs()
                < 1e-9
        );
        assert!(
            corrected.response.load_n[k] < hyper.response.load_n[k],
            "row {k}"
        );
    }
}

#[test]
fn greenwood_williamson_falls_in_kappa_and_reports_its_summits() {
    let p: GwParams = serde_json::from_str(r#"{"model": "linear", "periodic": true}"#).unwrap();
    let out = GreenwoodWilliamson
        .run(&p.check().unwrap(), &from_map(), &Context::new("t"))
        .unwrap();
    let Some(Product::Table(t)) = out.get("response") else {
        panic!()
    };
    t.conform(ResponseTable::COLUMNS).unwrap();
    let r = GwResponseTable::from_table(t).unwrap();
    assert!(r.kappa.windows(2).all(|w| w[1] < w[0]), "{:?}", r.kappa);
    assert!(r.response.z_m.windows(2).all(|w| w[1] < w[0]));
    assert!(r.contacts_per_m2.windows(2).all(|w| w[1] > w[0]));
    let Some(Product::Table(s)) = out.get("summary") else {
        panic!()
    };
    let alpha = s.f64("nayak_alpha").unwrap()[0];
    let (m0, m2, m4) = (
        s.f64("m0_m2").unwrap()[0],
        s.f64("m2").unwrap()[0],
        s.f64("m4_per_m2").unwrap()[0],
    );
    assert!((alpha / (m0 * m4 / (m2 * m2)) - 1.0).abs() < 1e-12);
    let eta = s.f64("summit_density_per_m2").unwrap()[0];
    assert!((eta / (m4 / (6.0 * std::f64::consts::PI * 3f64.sqrt() * m2)) - 1.0).abs() < 1e-12);
}

#[test]
fn misuse_is_named() {
    let fail = |json: &str, inputs: &Inputs| persson(json, inputs).unwrap_err();
    let (psd, stats) = psd_and_stats();
    let both = from_map().with("psd", Product::Table(psd.clone()));
    assert!(fail("{}", &both).contains("exactly one of input `psd`"));
    let no_area = Inputs::new()
        .with("psd", Product::Table(psd.clone()))
        .with("material", material());
    assert!(fail("{}", &no_area).contains("A0 is unknown"));
    let e = fail(r#"{"nominal_area_m2": 1e-6}"#, &from_psd());
    assert!(
        e.contains("nominal_area_m2") && e.contains("`stats`"),
        "{e}"
    );
    let (_, _) = persson(r#"{"nominal_area_m2": 1e-6}"#, &no_area).unwrap();
    let mut x_only = PsdTable::from_table(&psd).unwrap();
    x_only.direction.iter_mut().for_each(|d| *d = "x".into());
    let x_only = Inputs::new()
        .with("psd", Product::Table(x_only.into_table()))
        .with("stats", Product::Table(stats))
        .with("material", material());
    assert!(fail("{}", &x_only).contains("no row with direction `radial`"));
    let e = fail(r#"{"q_min_per_m": 1e9}"#, &from_map());
    assert!(e.contains("leaves no part"), "{e}");
    assert!(
        fail(r#"{"q_min_per_m": 2e5, "q_max_per_m": 1e5}"#, &from_map()).contains("q_min_per_m")
    );
    assert!(
        fail(
            r#"{"min_area_fraction": 0.5, "max_area_fraction": 0.4}"#,
            &from_map()
        )
        .contains("min_area_fraction")
    );
    assert!(fail(r#"{"max_area_fraction": 1.0}"#, &from_map()).contains("max_area_fraction"));
    assert!(fail(r#"{"variant": "persson-2007"}"#, &from_map()).contains("persson-2007"));
    let mut flat = map();
    flat.values.fill(1e-6);
    let e = fail(
        "{}",
        &Inputs::new()
            .with("surface", Product::Field(flat))
            .with("material", material()),
    );
    assert!(e.contains("the map is flat"), "{e}");
}

/// Both theories' bands over two replicate materials equal the quantiles
/// of two runs on those materials alone (two values, type 7: p05 = a +
/// 0.05 (b − a)), on the main material's E0* A0.
#[test]
fn replicate_bands_equal_separate_runs_on_each_material() {
    use hypercontact_core::Outputs;
    use hypercontact_core::contact::BandTable;
    use hypercontact_material::bootstrap::ReplicatesTable;
    use hypercontact_material::{Hyperelastic, NeoHookean};
    let (soft, stiff) = (
        NeoHookean::new(0.8e6).unwrap(),
        NeoHookean::new(1.1e6).unwrap(),
    );
    let models: [&dyn Hyperelastic; 2] = [&soft, &stiff];
    let replicates = ReplicatesTable::new((1..).zip(models)).into_table();
    let with = |m: &dyn Hyperelastic| from_psd().with("material", Product::Table(to_table(m)));
    let json = r#"{"periodic": true, "steps": 12, "max_area_fraction": 0.3}"#;
    fn table(out: &Outputs, name: &str) -> Table {
        match out.get(name) {
            Some(Product::Table(t)) => t.clone(),
            _ => panic!("no {name}"),
        }
    }
    let check = |outputs: &dyn Fn(&Inputs) -> Outputs| {
        let banded = outputs(&from_psd().with("replicates", Product::Table(replicates.clone())));
        let bands = BandTable::from_table(&table(&banded, "bands")).unwrap();
        let main = ResponseTable::from_table(&table(&banded, "response")).unwrap();
        let scale = main.load_n[3] / main.load_norm[3];
        let alone = |m| ResponseTable::from_table(&table(&outputs(&with(m)), "response")).unwrap();
        let (a, b) = (alone(&soft), alone(&stiff));
        assert_eq!(bands.replicates, vec![2; main.load_n.len()]);
        for k in 0..main.load_n.len() {
            let (lo, hi) = (a.load_n[k] / scale, b.load_n[k] / scale);
            let p05 = lo + 0.05 * (hi - lo);
            let p95 = lo + 0.95 * (hi - lo);
            assert!(
                (bands.load_norm_p05[k] - p05).abs() <= 1e-12 * p05,
                "row {k}"
            );
            assert!(
                (bands.load_norm_p95[k] - p95).abs() <= 1e-12 * p95,
                "row {k}"
            );
        }
        let bare = outputs(&from_psd());
        assert_eq!(table(&bare, "bands").n_rows(), 0);
    };
    check(&|inputs| {
        let p: PerssonParams = serde_json::from_str(json).unwrap();
        let p = p.check().unwrap();
        PerssonStage.run(&p, inputs, &Context::new("t")).unwrap()
    });
    check(&|inputs| {
        let p: GwParams = serde_json::from_str(json).unwrap();
        let p = p.check().unwrap();
        GreenwoodWilliamson
            .run(&p, inputs, &Context::new("t"))
            .unwrap()
    });
}
