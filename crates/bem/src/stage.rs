//! Stage `bem`: a height map and a material in, the load–area response (the
//! `icm` columns and more) and pressure/gap maps out. Checks and table
//! building here; the physics in [`crate::polonsky_keer`],
//! [`crate::curve`] and [`hypercontact_icm::tangent`].

use hypercontact_core::contact::{
    BandTable, Curve, ModelMapIndex, ResponseTable, area_fraction_label, check_maps_within_curve,
    map_npy,
};
use hypercontact_core::field::SurfaceProblem;
use hypercontact_core::{
    Arity, Checked, Context, Field, Files, InputSpec, Inputs, OutputSpec, Outputs, ParamError,
    Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_icm::bands::{BandAxes, replicate_bands, wired_replicates};
use hypercontact_icm::tangent::{TangentError, TangentLoad, integrate};
use hypercontact_icm::{CompositeModulus, LawParams, Scheme};
use hypercontact_material::bootstrap::ReplicatesTable;
use hypercontact_material::table::MaterialTable;

use crate::curve::CurveOptions;
use crate::influence::{Boundary, Influence};
use crate::polonsky_keer::{Problem, SolveError, SolverOptions};
use crate::shared::{CurveKey, solve_curve_shared};
use crate::{BemError, CurveError};

/// Parameters of `bem`.
#[params(check = maps_within_curve)]
pub struct BemParams {
    /// how the map continues beyond its edges
    #[param(default = Boundary::Free)]
    pub boundary: Boundary,
    #[param(flatten)]
    pub law: LawParams,
    /// load steps after first contact, about evenly spaced in A/A0
    #[param(default = 40, range = 1..=100_000)]
    pub steps: usize,
    /// A/A0 of the last step
    #[param(default = 0.9, positive, range = ..=1.0)]
    pub max_area_fraction: f64,
    /// largest accepted residual: rms gap error on the contact set / approach
    #[param(default = 1e-8, positive, range = ..=0.1)]
    pub tolerance: f64,
    /// conjugate-gradient iterations per solve before the stage fails
    #[param(default = 2000, range = 1..=10_000_000)]
    pub max_iterations: usize,
    /// A/A0 at which `contact_maps` holds the pressure and the gap
    #[param(default = vec![0.1, 0.5, 0.9], positive, range = ..=1.0)]
    pub map_fractions: Vec<f64>,
}

fn maps_within_curve(p: &BemParams) -> Result<(), ParamError> {
    check_maps_within_curve(&p.map_fractions, p.max_area_fraction)
}

/// The `response` table: every contact model's columns, then the solver's.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct BemResponseTable {
    #[column(flatten)]
    pub response: ResponseTable,
    /// (A/A0) / (p̄ / (E0* h'rms)), p̄ = F/A0; NaN at first contact
    pub kappa: Vec<f64>,
    /// conjugate-gradient iterations spent on the step
    pub iterations: Vec<i64>,
    /// residual of the accepted solve (rms gap error / approach)
    pub residual: Vec<f64>,
}

/// The index of `contact_maps`: every model's map columns, then the gap.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct BemMapIndex {
    #[column(flatten)]
    pub maps: ModelMapIndex,
    /// the step kept (a row of `response`)
    pub step: Vec<i64>,
    /// its rigid-plane height (`response`'s z_m)
    #[column(unit = "m")]
    pub z_m: Vec<f64>,
    /// the gap map (.npy, m; NaN where not measured)
    pub gap_file: Vec<String>,
}

/// The `bem` stage.
pub struct Bem;

static INFO: StageInfo = StageInfo {
    kind: "bem",
    version: 4,
    summary: "Boundary elements: load against contact area of a height map on an elastic \
              half-space",
    doc: "The rough surface as a linearly elastic half-space pressed onto a rigid plane, solved \
          pixel by pixel (pixel-wise constant pressure) with FFTs, so asperities interact \
          through the elastic field and the surface between them deforms (what profile theory \
          leaves out). BOUNDARY: `free` (default) treats the map as a finite part of an infinite \
          half-space loaded nowhere else: zero-padded to at least 2N x 2N with Love's \
          closed-form displacement of a uniformly loaded rectangular pixel (Love 1929; Johnson, \
          Contact Mechanics, 3.9), Hockney's method; `periodic` for periodic maps: u^(q) = 2 \
          p^(q) / (E* |q|), mean of u zero. SOLVER: Polonsky & Keer's constrained conjugate \
          gradient (Wear 231, 1999) under rigid-plane approach control, with an FFT \
          preconditioner after Vollebregt (J. Comput. Phys. 257, 2014: the operator's inverse on \
          a transform grid; for free maps the unpadded one, kernel wrapped) corrected on the \
          contact set by a Schur-complement term for the points off it (two damped Jacobi \
          terms; Saad, Iterative Methods for Sparse Linear Systems, 2003) and Polak-Ribiere \
          conjugation, each solve warm-started from the previous two; a `bem` run after another on \
          the same map with the same boundary, steps, max_area_fraction, tolerance and \
          max_iterations in one process (the paper's linear and hyperelastic pair) replays that \
          solve instead of repeating it, with the same bits (the contact set does not depend \
          on the law); a solve is accepted when the rms of the complementarity violation (gap on {p > 0}, negative gap \
          elsewhere) divided by the approach is at most `tolerance` (at 1e-8 the contact set is \
          exact to the pixel and the load to ~1e-9); otherwise the stage fails naming the step, \
          the plane height, the load and the residual. Sums are in a fixed order, so results are \
          the same to the bit on any number of threads. STEPS: row 0 is first contact (F = 0, A \
          = 0); rows 1..=steps aim at A/A0 = k max_area_fraction / steps and land within a \
          quarter of the spacing (or as near as six solves get), the last at or above \
          max_area_fraction (so every A/A0 up to it can be read off the curve); `iterations` \
          counts every solve of a step. CONVENTIONS: `z_m` is the rigid plane's height above the lowest measured \
          point (at first contact the map's height range; periodic: the plane relative to the \
          mean surface, i.e. a mean gap); A = contact pixels (p > 0) x dx dy; A0 = measured \
          pixels x dx dy (NaN heights never touch, as in `truncation`); E0* and E_t* exactly as \
          in `icm` (E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu)); kappa = (A/A0) / (p/(E0* h'rms)) \
          with p = F/A0 and h'rms the rms gradient by forward differences (as `surface` reports \
          it); about 2 at small load on self-affine maps, falling with load; NaN at first \
          contact. MODEL `linear`: F = E0* f(delta), f the load for E* = 1 (the contact set and \
          f do not depend on the modulus). `hyperelastic`: the paper's tangent modulus (Eqs. \
          5-7) applied to the coupled contact instead of profile theory: dF = E_t*(-F/A) \
          f'(delta) d delta, i.e. dF = E_t*(-F/A) df over the solved steps, F = 0 at first \
          contact, with the ICM's E_t*(S) (same material law and sign convention: S = -F/A <= 0, \
          E_t*/E0* = 2 at first contact for nu = 1/2 with the paper's `tangent: equibiaxial`, 1 \
          with `uniaxial`; a linear material's E* throughout) and `scheme` (euler: the paper's \
          explicit step; heun: trapezoid); tangent_ratio = E_t*/E0*. The contact set, A and \
          the gap are the linear solution's; the pressure map is the linear one scaled to the \
          load (F/f). BANDS: with `replicates` (material-fit's bootstrap) each replicate \
          material's law is integrated over the same linear solve (its contact set and \
          unit-modulus load do not depend on the modulus), so a replicate costs an integral, \
          not a solve; `bands` gives per step the 5th, 50th and 95th percentiles of load_norm \
          (over the main material's E0* A0) and of tangent_ratio (over the replicate's own \
          E0*), as `icm` does; a replicate whose law gives out is left out with a note. \
          CONTACT_MAPS: for each of map_fractions, the step whose A/A0 is nearest: \
          pressure_a<fraction>.npy (Pa) and gap_a<fraction>.npy (m, NaN where not measured), \
          axis 0 = x as in the input, indexed by the table contact_maps.parquet (one row per \
          map: requested and kept A/A0, load, files, spacing, step, z_m).",
    inputs: &[
        InputSpec::field(
            "surface",
            Arity::One,
            "height map, metres, NaN = not measured",
        ),
        InputSpec::table::<MaterialTable>(
            "material",
            Arity::One,
            "the material table (a preset or a fit)",
        ),
        InputSpec::table::<ReplicatesTable>(
            "replicates",
            Arity::Optional,
            "material-fit's bootstrap replicates: each replicate's law is integrated over the \
             same linear solve, for `bands`",
        ),
    ],
    outputs: &[
        OutputSpec::table::<BemResponseTable>(
            "response",
            "one row per load step, first contact first (icm's columns first)",
        ),
        OutputSpec::files_indexed::<BemMapIndex>(
            "contact_maps",
            "pressure and gap maps (.npy) at map_fractions, indexed",
        ),
        OutputSpec::table::<BandTable>(
            "bands",
            "5–95 % bands over the material's bootstrap replicates, one row per step (no rows \
             without `replicates`)",
        ),
    ],
};

/// The maps kept for one requested fraction: the nearest step so far.
struct MapChoice {
    requested: f64,
    step: usize,
    area_fraction: f64,
    pressure: Vec<f64>,
    gap_m: Vec<f64>,
}

impl Stage for Bem {
    type Params = BemParams;
    /// Parallel (rayon) over its work: a few cores pay off on a cluster.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn let_go(&self) {
        crate::shared::forget();
    }

    fn run(
        &self,
        p: &Checked<BemParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.areal_field("surface", "bem")?;
        let heights_m = checked_heights(surface).map_err(StageError::other)?;
        let modulus = (p.law)
            .modulus_from_table(inputs.table("material")?, ctx)
            .map_err(|e| StageError::other(BemError::Material(e)))?;
        let grid = (surface.nx(), surface.ny(), surface.dx_m, surface.dy_m);
        let influence = Influence::new(grid.0, grid.1, grid.2, grid.3, p.boundary);
        let problem = Problem::new(&influence, &heights_m)
            .map_err(|e| StageError::other(BemError::Surface(e.to_string())))?;
        // dx·dy first, then the count: the order the areas have always had.
        let pixel_m2 = grid.2 * grid.3;
        let a0_m2 = problem.measured() as f64 * pixel_m2;
        let lowest_m = heights_m
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .fold(f64::INFINITY, f64::min);
        let z_of = |approach_m: f64| problem.top_m() - approach_m - lowest_m;

        let (rows, maps) = solve_steps(&problem, (grid, &heights_m), p, ctx).map_err(|e| {
            StageError::other(not_converged(e, &z_of, modulus.e0_star_pa() * a0_m2))
        })?;
        ctx.note(&format!(
            "{} steps, {} iterations, A/A0 up to {:.4}",
            p.steps,
            rows.iter().map(|r| r.iterations).sum::<usize>(),
            rows.last().map_or(0.0, |r| r.area_fraction),
        ));
        let curve = Curve {
            z_m: rows.iter().map(|r| z_of(r.approach_m)).collect(),
            area_fraction: rows.iter().map(|r| r.area_fraction).collect(),
            area_m2: rows
                .iter()
                .map(|r| r.contact_pixels as f64 * pixel_m2)
                .collect(),
            ..Curve::default()
        };
        let unit_load_m2: Vec<f64> = rows.iter().map(|r| r.mean_pressure * a0_m2).collect();
        let bands = replicate_bands(
            wired_replicates(inputs)?,
            &p.law,
            BandAxes {
                area_fraction: &curve.area_fraction,
                e0_star_pa: modulus.e0_star_pa(),
                nominal_area_m2: a0_m2,
            },
            &|m| {
                tangent_load(&unit_load_m2, &curve.area_m2, m, p.law.scheme)
                    .map_err(|e| e.to_string())
            },
            ctx,
        );
        let response = respond(curve, &unit_load_m2, &modulus, p.law.scheme, a0_m2)?;
        let slope = hypercontact_surface::stats::rms_slope(&surface.values, grid.2, grid.3);
        let table = BemResponseTable {
            kappa: response.kappa(slope),
            iterations: rows.iter().map(|r| r.iterations as i64).collect(),
            residual: rows.iter().map(|r| r.residual).collect(),
            response,
        };
        let files = map_files(maps, &table.response, &unit_load_m2, grid)?;
        Ok(Outputs::new()
            .table("response", table.into_table())
            .files("contact_maps", files)
            .table("bands", bands.into_table()))
    }
}

/// The curve from first contact to max_area_fraction, for E* = 1, with the
/// maps nearest each of map_fractions; the thread's last curve when it is
/// the same one ([`crate::shared`]).
fn solve_steps(
    problem: &Problem<'_>,
    (grid, heights_m): ((usize, usize, f64, f64), &[f64]),
    p: &BemParams,
    ctx: &Context,
) -> Result<(Vec<crate::Step>, Vec<MapChoice>), CurveError> {
    let options = CurveOptions {
        steps: p.steps,
        max_area_fraction: p.max_area_fraction,
        solver: SolverOptions {
            tolerance: p.tolerance,
            max_iterations: p.max_iterations,
            ..SolverOptions::default()
        },
    };
    let mut maps: Vec<Option<MapChoice>> = p.map_fractions.iter().map(|_| None).collect();
    let progress = ctx.progress(p.steps as u64, "load steps");
    let mut keep = |k: usize, row: &crate::Step, pressure: &[f64], gap_m: &[f64]| {
        progress.inc(1);
        for (slot, &requested) in maps.iter_mut().zip(&p.map_fractions) {
            let nearer = slot.as_ref().is_none_or(|m| {
                (row.area_fraction - requested).abs() < (m.area_fraction - requested).abs()
            });
            if nearer {
                *slot = Some(MapChoice {
                    requested,
                    step: k,
                    area_fraction: row.area_fraction,
                    pressure: pressure.to_vec(),
                    gap_m: gap_m.to_vec(),
                });
            }
        }
    };
    let (rows, _) = solve_curve_shared(
        CurveKey::new(grid, p.boundary, heights_m, options),
        problem,
        &mut keep,
    )?;
    drop(progress);
    Ok((rows, maps.into_iter().flatten().collect()))
}

/// The response under the contact law: E0* f for a linear law, or the
/// tangent-modulus integral over the unit-modulus loads f
/// (`unit_load_m2`, F/E* in m²) on the curve's contact areas.
fn respond(
    mut curve: Curve,
    unit_load_m2: &[f64],
    modulus: &CompositeModulus,
    scheme: Scheme,
    a0_m2: f64,
) -> Result<ResponseTable, StageError> {
    let tangent = tangent_load(unit_load_m2, &curve.area_m2, modulus, scheme)
        .map_err(|e| StageError::other(BemError::Tangent(e)))?;
    curve.load_n = tangent.load_n;
    curve.modulus_pa = tangent.modulus_pa;
    Ok(ResponseTable::from_curve(
        curve,
        modulus.e0_star_pa(),
        a0_m2,
    ))
}

/// The tangent-modulus load over the unit-modulus loads `unit_load_m2` on
/// the contact areas `area_m2` under one law.
fn tangent_load(
    unit_load_m2: &[f64],
    area_m2: &[f64],
    modulus: &CompositeModulus,
    scheme: Scheme,
) -> Result<TangentLoad, TangentError> {
    integrate(unit_load_m2, area_m2, scheme, &mut |s| {
        modulus.at_stress_pa(s).map_err(|e| e.to_string())
    })
}

/// The heights as a row-major vector (axis 0 = x), refused if they cannot be
/// a contact problem.
fn checked_heights(surface: &Field) -> Result<Vec<f64>, BemError> {
    match surface.contact_surface_problem(2) {
        Some(p @ SurfaceProblem::Flat(_)) => {
            Err(BemError::Surface(format!("{p}: all of it touches at once")))
        }
        Some(p) => Err(BemError::Surface(p.to_string())),
        None => Ok(surface.values.iter().copied().collect()),
    }
}

/// A failed step as the user should read it: the plane's height and the
/// load (at E0*) instead of solver units.
fn not_converged(e: CurveError, z_of: &dyn Fn(f64) -> f64, load_per_pressure_n: f64) -> BemError {
    match e.source {
        SolveError::NotConverged {
            iterations,
            residual,
            tolerance,
            mean_pressure,
        } => BemError::NotConverged {
            step: e.step,
            steps: e.steps,
            z_m: z_of(e.approach_m),
            load_n: mean_pressure * load_per_pressure_n,
            iterations,
            residual,
            tolerance,
        },
        _ => BemError::Curve(e),
    }
}

/// The `contact_maps` product: pressure (Pa) and gap (m) at the chosen
/// steps, with their index.
fn map_files(
    maps: Vec<MapChoice>,
    response: &ResponseTable,
    unit_load_m2: &[f64],
    (nx, ny, dx, dy): (usize, usize, f64, f64),
) -> Result<Files, StageError> {
    let npy = |values: Vec<f64>| map_npy(values, (nx, ny), dx, dy);
    let mut files = Files::new();
    let mut index = BemMapIndex::default();
    for map in maps {
        let k = map.step;
        // p in Pa: the unit-modulus pressure times the secant modulus F/f.
        let secant_pa = response.load_n[k] / unit_load_m2[k];
        let pressure_file = format!("pressure_{}.npy", area_fraction_label(map.requested));
        let gap_file = format!("gap_{}.npy", area_fraction_label(map.requested));
        files.files.insert(
            pressure_file.clone(),
            npy(map.pressure.iter().map(|p| p * secant_pa).collect())?,
        );
        files.files.insert(gap_file.clone(), npy(map.gap_m)?);
        let m = &mut index.maps;
        m.requested_area_fraction.push(map.requested);
        m.area_fraction.push(map.area_fraction);
        m.load_n.push(response.load_n[k]);
        m.pressure_file.push(pressure_file);
        m.dx_m.push(dx);
        m.dy_m.push(dy);
        index.step.push(k as i64);
        index.z_m.push(response.z_m[k]);
        index.gap_file.push(gap_file);
    }
    Ok(files.with_index(index))
}
