//! Stage `fem`: a height-map patch and a material in, the finite-strain
//! load–area response of the nearly incompressible block pressed by a rigid
//! flat plane out — the reference the tangent-modulus contact models are
//! judged against (issue #33). Checks, stepping and tables here; the
//! mechanics in [`crate::contact`] and the element.

use std::sync::Arc;

use hypercontact_core::contact::{
    Curve as ResponseCurve, ModelMapIndex, ResponseTable, area_fraction_label,
    check_maps_within_curve, map_npy,
};
use hypercontact_core::{
    Arity, Checked, Choice, Context, Field, Files, InputSpec, Inputs, OutputSpec, Outputs,
    ParamError, Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_material::material::{LinearElastic, Material};
use hypercontact_material::table::{MaterialTable, material_from_table};
use hypercontact_surface::crop::{CropParams, Window, refine};

use crate::cause::{Failure, unstable_stretches, with_likely_cause};
use crate::contact::{ContactProblem, NewtonOptions, Step};
use crate::curve::{AreaSteps, Curve, bearing_approach_m, solve_area_steps};
use crate::law::Law;
use crate::mesh::{Flatness, HeightMap, Lateral, MAX_FLATNESS, Mesh, MeshOptions};

/// How the lateral faces of the block are held.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum FemBoundary {
    /// normal displacement zero: the patch is one cell of its mirror-image tiling
    #[default]
    Mirror,
    /// opposite faces tied: the map's last row and column must repeat its first
    Periodic,
}

/// Which kinematics the block is solved with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Strain {
    /// finite strain with the material's strain energy
    #[default]
    Finite,
    /// small-strain linear elasticity with the material's initial moduli (μ0 and the bulk modulus): the same mesh's linear answer, to isolate the finite-strain effect
    Small,
}

/// Parameters of `fem`.
#[params(check = maps_within_curve)]
pub struct FemParams {
    #[param(flatten)]
    pub window: CropParams,
    /// block height at the mean surface (default: the larger lateral size; the block on its rigid base is then 2-5 % stiffer at equal approach than the half-space the other models assume, twice that depth within 1 %: see the stage doc)
    #[param(unit = "m", positive)]
    pub depth_m: Option<f64>,
    /// element layers through the height (an element may be at most 10 times wider than thick, else the stage is refused: fewer layers, less grading or a deeper block)
    #[param(default = 8, range = 1..=256)]
    pub layers: usize,
    /// bottom-layer / top-layer thickness (1: uniform; the top layer's elements at most 10 times wider than thick)
    #[param(default = 8.0, range = 1.0..=1000.0)]
    pub grading: f64,
    /// how the lateral faces are held
    #[param(default = FemBoundary::Mirror)]
    pub boundary: FemBoundary,
    /// the kinematics: `finite` (the reference) or `small` (linear elasticity with the initial moduli, on the same mesh)
    #[param(default = Strain::Finite)]
    pub strain: Strain,
    /// bulk modulus / μ0 of a hyperelastic material (a linear one uses its own ν unless ν = ½)
    #[param(default = 5000.0, range = 10.0..=1.0e9)]
    pub bulk_ratio: f64,
    /// steps after first contact, aimed at evenly spaced A/A0
    #[param(default = 20, range = 1..=10_000)]
    pub steps: usize,
    /// A/A0 (top nodes in contact / top nodes) of the last step
    #[param(default = 0.3, positive, range = ..=1.0)]
    pub max_area_fraction: f64,
    /// A/A0 at which `contact_maps` keeps the pressure, the contact mask and the deformed mesh
    #[param(default = vec![0.05, 0.1, 0.2, 0.3], positive, range = ..=1.0)]
    pub map_fractions: Vec<f64>,
    /// Newton's tolerance: residual 2-norm on the free unknowns / 2-norm of the contact reactions
    #[param(default = 1e-8, positive, range = ..=1e-2)]
    pub tolerance: f64,
    /// Newton iterations per attempt before the increment is halved (four times at most)
    #[param(default = 30, range = 2..=1000)]
    pub max_iterations: usize,
    /// the most mesh nodes accepted, checked before meshing (measured: 16–20 kB per node at 8 layers on 24²–128² patches, about 30 kB at 16 layers; see max_memory_gb)
    #[param(default = 200_000, range = 8..=10_000_000)]
    pub max_nodes: usize,
    /// the most memory the solve may hold, checked before it starts from the sparse factor's exact size (the estimate is in the notes)
    #[param(default = 8.0, positive, range = ..=1.0e4)]
    pub max_memory_gb: f64,
    /// coarsen deep layers laterally: elements 2, 4, 8 … pixels wide where a layer is that many pixels thick and its top that deep below the surface (the top layer one pixel), the fine nodes on a coarse face tied to it; fewer nodes and a smaller factor for about the same load–area response (within 1 % on the paper's patches)
    #[param(default = false)]
    pub lateral_coarsening: bool,
}

fn maps_within_curve(p: &FemParams) -> Result<(), ParamError> {
    check_maps_within_curve(&p.map_fractions, p.max_area_fraction)
}

/// The `response` table: every contact model's columns, then the solver's.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct FemResponseTable {
    #[column(flatten)]
    pub response: ResponseTable,
    /// travel of the rigid plane since it first touched the highest point
    #[column(unit = "m")]
    pub approach_m: Vec<f64>,
    /// contact area / projected area, both in the deformed configuration
    pub area_fraction_current: Vec<f64>,
    /// mean gap between the plane and the deformed top (tributary-area weights)
    #[column(unit = "m")]
    pub mean_gap_m: Vec<f64>,
    /// Newton iterations of the step (chord steps on a kept factorisation and halved attempts included)
    pub newton_iterations: Vec<i64>,
    /// largest height of a free top node above the plane (0: none penetrates)
    #[column(unit = "m")]
    pub max_penetration_m: Vec<f64>,
}

/// The index of `contact_maps`: every model's map columns, then the mask
/// and the mesh.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct FemMapIndex {
    #[column(flatten)]
    pub maps: ModelMapIndex,
    /// the step kept (a row of `response`)
    pub step: Vec<i64>,
    /// its approach (`response`'s approach_m)
    #[column(unit = "m")]
    pub approach_m: Vec<f64>,
    /// the contact mask (.npy, 1 in contact, 0 not)
    pub contact_file: Vec<String>,
    /// the deformed mesh (legacy VTK, for ParaView)
    pub mesh_file: Vec<String>,
}

/// The `fem` stage.
pub struct Fem;

static INFO: StageInfo = StageInfo {
    kind: "fem",
    version: 4,
    summary: "Finite elements at finite strain: load against contact area of a rough, nearly \
              incompressible hyperelastic block on a rigid flat",
    doc: "The reference the tangent-modulus models are judged against: the rough patch as a \
          block of the hyperelastic material (or a linear one), pressed by a rigid, flat, \
          frictionless plane, solved at finite strain. PATCH: the window x0, y0, nx, ny of the \
          input map (default all of it), each coarsen x coarsen block averaged, then with \
          `refine` > 1 resampled refine times finer by band-limited interpolation (as the `crop` \
          stage cuts and refines it; the mesh then has a top node per refined point). MESH (fixed conventions, so results compare with other codes): one \
          top node per map point, node (i, j) at x = i dx, y = j dy, so the block is \
          (nx - 1)dx x (ny - 1)dy; base at z = 0, top node at z = depth_m + h[i, j] - mean(h) \
          (depth_m: default the larger lateral size; a block on a rigid base is stiffer than \
          the half-space that bem, icm and persson assume, most for the longest wavelength: \
          linear fem against linear bem on the paper's t1 window, at equal approach, 1.02-1.05 \
          at depth = the window's side and 0.98-1.00 at twice it, so judge half-space models \
          with depth_m at least twice the side, the extra layers graded to keep the top one); \
          `layers` layers of trilinear hexahedra per \
          column, thicknesses in geometric progression with bottom/top ratio `grading`, refused \
          before meshing when an element would be more than 10 times wider than thick (its \
          width over its layer's thickness in the lowest column; the shipped pipelines stay \
          below 1.4); with \
          lateral_coarsening, layer k's elements are s_k pixels wide in x and y, s_k the \
          largest power of two not above the layer's thickness nor its top's depth below the \
          surface, in pixels, 1 for the top layer, \
          at most doubling from one layer to the next one down (the last element of a row \
          shorter where s_k does not divide it), and the fine nodes on a coarser face below \
          are hanging: position and displacement interpolated bilinearly from that face's \
          corners (a conforming mesh). \
          BOUNDARY: base clamped; lateral faces `mirror` (normal displacement zero: the patch is \
          one cell of its mirror-image tiling, which `crop`'s `mirrored` output is, for the \
          periodic models) or `periodic` (node (nx - 1, j) tied to (0, j), and likewise in y: \
          the map's last row and column must repeat its first). MATERIAL: finite strain, \
          W = W_iso(isochoric C) + K (J - 1)^2 / 2 with K = bulk_ratio mu0 (default 5000, nu = \
          0.4999); every hyperelastic family of the `material` table through its strain \
          energy, with the consistent tangent; a `linear` material is small-strain linear \
          elasticity with its E and nu (K from nu, or bulk_ratio mu at nu = 1/2); `strain: \
          small` solves a hyperelastic material as small-strain linear elasticity with mu0 and \
          K, on the same mesh and steps, so F_finite / F_small isolates the finite-strain \
          effect from the discretisation. ELEMENT: \
          the mixed Q1/P0 hexahedron (displacement, constant pressure and volume ratio per \
          element, condensed), free of volumetric locking. CONTACT: exact active set on the \
          top nodes (a node in contact has its z on the plane, released when its reaction \
          pulls once the free residual is within sqrt(tolerance) of the reactions; a free node \
          that penetrates enters at once), frictionless (x, y free), Newton with line search \
          from the last converged state (a linear law's extrapolated from the last two), \
          faer's sparse Cholesky with one symbolic factorisation (once Newton converges, chord \
          steps keep the last factorisation while they cut the residual fourfold; with a \
          constant tangent, as at small strain, a direction whose contact set differs from the \
          factorised one in at most 6 nodes is solved by conjugate gradients preconditioned by \
          the kept factor, to 1e-8 of the right-hand side in at most 12 iterations); MEMORY: the \
          symbolic factor's exact size and the assembly's are added up before any numeric work, \
          noted, and the stage refused above max_memory_gb (measured 16-20 kB per node at 8 \
          layers); a step that fails is halved up to four times, an \
          attempt whose line search damps the contact nodes' move to the plane to 1/4 or less \
          being halved at once (first-touch cut; the last halving iterates to the end), then \
          the stage fails naming the step, the approach and the residual. STEPS: row 0 is \
          first touch (F = 0); step 1 goes to where the plane's overlap with the undeformed \
          surface covers A/A0 = max_area_fraction / steps (the elastic area is smaller); step \
          k aims at k max_area_fraction / steps (half a spacing past an overshoot), its \
          approach from A taken as a power of the approach through the first and the last \
          state, the increment within 1/4 and 2 times the last (step 2 at most doubles the \
          approach); a step landing more than two spacings past its aim is solved again at a \
          third of its increment (up to three times; frictionless elastic contact has no \
          history); the last row is at or above max_area_fraction, more steps being taken if \
          aims fall short (at most 4 steps + 10, then the stage fails). Nodes enter the \
          contact set when they penetrate by more than 1e-6 of the approach and leave when \
          they pull with more than 1e-9 of the reactions (a hysteresis against cycling). \
          CONVENTIONS: A/A0 = top nodes in contact / top nodes (node-counted, as `bem` counts \
          pixels); A0 = (nx - 1)dx (ny - 1)dy, A = A/A0 x A0; `area_fraction_current` is the \
          contact area over the projected area, both deformed (each top face counts with the \
          share of its nodes in contact); z_m = the plane's height above the patch's lowest \
          point (the height range at first touch, as in `bem`); load_n is the plane's force; \
          load_norm = F/(E0* A0) with E0* = 4 mu0 for a hyperelastic material (E0 = 3 mu0, \
          nu = 1/2, as the other models take it) and E/(1 - nu^2) for a linear one; \
          tangent_ratio is NaN: the finite-element solution has no single modulus (read \
          F_model / F_fem at equal A/A0 instead). CONTACT_MAPS: at the first step reaching each \
          of map_fractions: pressure_a<f>.npy (nodal reaction / tributary area, Pa), \
          contact_a<f>.npy (1/0) on the patch's grid (axis 0 = x), and mesh_a<f>.vtk, the \
          deformed mesh with displacement, pressure and contact as point data (ParaView), \
          indexed by contact_maps.parquet. Sums are in a fixed order: the same bits on any \
          number of threads.",
    inputs: &[
        InputSpec::field(
            "surface",
            Arity::One,
            "height map, metres (no missing points inside the window)",
        ),
        InputSpec::table::<MaterialTable>(
            "material",
            Arity::One,
            "the material table (a preset, a fit or the constants stage)",
        ),
    ],
    outputs: &[
        OutputSpec::table::<FemResponseTable>(
            "response",
            "one row per step, first touch first (the contact models' columns first)",
        ),
        OutputSpec::files_indexed::<FemMapIndex>(
            "contact_maps",
            "pressure and contact maps (.npy) and the deformed mesh (.vtk) at map_fractions, \
             indexed",
        ),
    ],
};

impl Stage for Fem {
    type Params = FemParams;
    /// Parallel (rayon) assembly and factorisation.
    const RESOURCES: hypercontact_core::Resources = hypercontact_core::Resources::PARALLEL;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<FemParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.areal_field("surface", "fem")?;
        let window = Window::of(&p.window, surface.values.dim())?;
        let (patch, heights_m) = checked_patch(window.cut(surface)?, &window, p)?;
        let (law, e0_star_pa, unstable) =
            law_of(inputs.table("material")?, p.bulk_ratio, p.strain)?;
        let (nx, ny) = patch.values.dim();
        let map = HeightMap {
            heights_m: &heights_m,
            nx,
            ny,
            dx_m: patch.dx_m,
            dy_m: patch.dy_m,
        };
        let mesh = Mesh::new(&map, &mesh_options(p)).map_err(StageError::other)?;
        let lateral = match p.boundary {
            FemBoundary::Mirror => Lateral::Mirror,
            FemBoundary::Periodic => Lateral::Periodic,
        };
        let newton = NewtonOptions {
            tolerance: p.tolerance,
            max_iterations: p.max_iterations,
            ..NewtonOptions::default()
        };
        let mut problem =
            ContactProblem::new(mesh, law, lateral, newton).map_err(StageError::other)?;
        check_memory(&problem, p, ctx)?;
        // At first touch, before any step: the undeformed top's mean gap.
        let first_gap_m = problem.mean_gap_m(0.0);
        let curve = solve(&mut problem, &heights_m, p, unstable.as_deref(), ctx)?;
        let a0_m2 = (nx - 1) as f64 * patch.dx_m * (ny - 1) as f64 * patch.dy_m;
        let range_m = height_range_m(&heights_m);
        let table = response_table(&curve.steps, e0_star_pa, a0_m2, range_m, first_gap_m);
        let files = map_files(&curve, &problem, &table, &patch)?;
        Ok(Outputs::new()
            .table("response", table.into_table())
            .files("contact_maps", files))
    }
}

/// Refuses a solve whose memory estimate (from the symbolic factorisation,
/// before any numeric work) exceeds `max_memory_gb`; notes it otherwise.
fn check_memory(problem: &ContactProblem, p: &FemParams, ctx: &Context) -> Result<(), StageError> {
    let estimate_gb = problem.memory_estimate_bytes() as f64 / 1e9;
    let factor_gb = problem.factor_bytes() as f64 / 1e9;
    let nodes = problem.mesh.node_count();
    let per_node_kb = estimate_gb * 1e6 / nodes as f64;
    let (nx, ny) = (problem.mesh.nx, problem.mesh.ny);
    if estimate_gb > p.max_memory_gb {
        return Err(StageError::invalid(format!(
            "a {nx} × {ny} patch with {} layers ({nodes} nodes, {} unknowns) needs about \
             {estimate_gb:.2} GB ({per_node_kb:.1} kB per node; the sparse factor \
             {factor_gb:.2} GB of it), above max_memory_gb = {}: take fewer layers, a smaller \
             window, lateral_coarsening or a coarser map, or raise max_memory_gb",
            p.layers, problem.dofs.count, p.max_memory_gb
        )));
    }
    ctx.note(&format!(
        "memory: about {estimate_gb:.2} GB for {nodes} nodes ({per_node_kb:.1} kB per node; the \
         sparse factor {factor_gb:.2} GB of it)"
    ));
    Ok(())
}

/// The mesh parameters of `p`.
fn mesh_options(p: &FemParams) -> MeshOptions {
    MeshOptions {
        depth_m: p.depth_m,
        layers: p.layers,
        grading: p.grading,
        lateral_coarsening: p.lateral_coarsening,
    }
}

/// The window's patch, refined `refine` times as `crop` refines it, and its
/// heights (`i * ny + j`); refused if a point of the window is missing or
/// the mesh would exceed `max_nodes`.
fn checked_patch(
    patch: Field,
    window: &Window,
    p: &FemParams,
) -> Result<(Field, Vec<f64>), StageError> {
    let (nx, ny) = patch.values.dim();
    let missing = patch.values.iter().filter(|h| !h.is_finite()).count();
    if missing > 0 {
        let first = patch
            .values
            .indexed_iter()
            .find(|(_, h)| !h.is_finite())
            .map_or((0, 0), |(ij, _)| ij);
        return Err(StageError::invalid(format!(
            "{missing} of the window's {} points are missing (NaN), the first at patch point \
             ({}, {}) = input point ({}, {}): the block needs a height at every node (choose a \
             window without them, or fill them with `surface`)",
            nx * ny,
            first.0,
            first.1,
            window.x0 + first.0 * window.coarsen,
            window.y0 + first.1 * window.coarsen,
        )));
    }
    let patch = refine(&patch, p.window.refine)?;
    let (nx, ny) = patch.values.dim();
    let heights_m: Vec<f64> = patch.values.iter().copied().collect();
    let map = HeightMap {
        heights_m: &heights_m,
        nx,
        ny,
        dx_m: patch.dx_m,
        dy_m: patch.dy_m,
    };
    let nodes = Mesh::node_count_of(&map, &mesh_options(p));
    if nodes > p.max_nodes {
        return Err(StageError::invalid(format!(
            "a {nx} × {ny} patch with {} layers has {nodes} nodes, above max_nodes = {} (the \
             solve holds 16–20 kB per node at 8 layers, more with more layers): take a smaller \
             window, coarsen it, or raise max_nodes",
            p.layers, p.max_nodes
        )));
    }
    check_flatness(&map, p)?;
    if height_range_m(&heights_m) <= 0.0 {
        return Err(StageError::invalid(
            "the patch is flat: all of it touches at once".to_owned(),
        ));
    }
    Ok((patch, heights_m))
}

/// Refuses a mesh whose elements are more than [`MAX_FLATNESS`] times
/// wider than thick: Newton fails or crawls on such slivers.
fn check_flatness(map: &HeightMap<'_>, p: &FemParams) -> Result<(), StageError> {
    let Some(flat) = Flatness::of(map, &mesh_options(p)) else {
        return Ok(());
    };
    if flat.ratio <= MAX_FLATNESS {
        return Ok(());
    }
    Err(StageError::invalid(format!(
        "degenerate elements: layer {} of {} is {:.3e} m thick under {:.3e} m wide \
         elements, aspect ratio {:.1} above the bound {MAX_FLATNESS} (width / thickness): \
         take fewer `layers`, a smaller `grading`, a larger `depth_m`, or a window with more \
         points (`nx`, `ny`, `refine`)",
        flat.layer + 1,
        p.layers,
        flat.thickness_m,
        flat.width_m,
        flat.ratio,
    )))
}

fn height_range_m(heights_m: &[f64]) -> f64 {
    let (lo, hi) = heights_m
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    hi - lo
}

/// The element law of the material table, its E0*: 4 μ0 for a
/// hyperelastic material (ν = ½, as every contact model takes it), E/(1 −
/// ν²) for a linear one, and where a finite-strain law is unstable (for a
/// failure's likely cause).
fn law_of(
    table: &hypercontact_core::Table,
    bulk_ratio: f64,
    strain: Strain,
) -> Result<(Law, f64, Option<String>), StageError> {
    let material = material_from_table(table).map_err(StageError::other)?;
    match material {
        Material::Hyperelastic(model) => {
            let law =
                Law::hyperelastic(Arc::as_ref(&model), bulk_ratio).map_err(StageError::other)?;
            let shear_pa = law.shear_modulus_pa();
            let (law, unstable) = match strain {
                Strain::Finite => (law, unstable_stretches(Arc::as_ref(&model))),
                Strain::Small => (
                    Law::linear_elastic(shear_pa, bulk_ratio).map_err(StageError::other)?,
                    None,
                ),
            };
            Ok((law, 4.0 * shear_pa, unstable))
        }
        Material::Linear(LinearElastic { e_pa, poisson }) => {
            let shear_pa = e_pa / (2.0 * (1.0 + poisson));
            // K/μ = 2(1 + ν) / (3(1 − 2ν)); at ν = ½ the stage's bulk_ratio.
            let ratio = if poisson < 0.5 {
                2.0 * (1.0 + poisson) / (3.0 * (1.0 - 2.0 * poisson))
            } else {
                bulk_ratio
            };
            let law = Law::linear_elastic(shear_pa, ratio).map_err(StageError::other)?;
            Ok((law, e_pa / (1.0 - poisson * poisson), None))
        }
    }
}

/// The curve from first touch to max_area_fraction, with a progress bar;
/// a failure names its likely cause ([`crate::cause`]).
fn solve(
    problem: &mut ContactProblem,
    heights_m: &[f64],
    p: &FemParams,
    unstable_material: Option<&str>,
    ctx: &Context,
) -> Result<Curve, StageError> {
    let first_target = p.max_area_fraction / p.steps as f64;
    // The bearing approach overestimates the elastic area, so the first step
    // lands below its target; never less than 1e-3 of the height range.
    let first_approach_m =
        bearing_approach_m(heights_m, first_target).max(1e-3 * height_range_m(heights_m));
    let options = AreaSteps {
        steps: p.steps,
        max_area_fraction: p.max_area_fraction,
        first_approach_m,
        snapshot_area_fractions: p.map_fractions.clone(),
        max_steps: 4 * p.steps + 10,
    };
    let progress = ctx.progress(p.steps as u64, "load steps (aimed)");
    let mut iterations = 0;
    let mut reached = Vec::new();
    let solved = solve_area_steps(problem, &options, &mut |step: &Step| {
        iterations += step.iterations;
        reached.push((step.approach_m, step.area_fraction));
        progress.inc(1);
    });
    let failure = Failure {
        reached: &reached,
        unstable_material,
        steps: p.steps,
        max_area_fraction: p.max_area_fraction,
    };
    let curve = solved.map_err(|e| StageError::other(with_likely_cause(e, &failure)))?;
    drop(progress);
    let last = curve.steps.last().map_or(0.0, |s| s.area_fraction);
    ctx.note(&format!(
        "{} steps, {iterations} Newton iterations, {} nodes, A/A0 up to {last:.4}",
        curve.steps.len(),
        problem.mesh.node_count(),
    ));
    Ok(curve)
}

/// The response rows: first touch, then every step.
fn response_table(
    steps: &[Step],
    e0_star_pa: f64,
    a0_m2: f64,
    range_m: f64,
    first_gap_m: f64,
) -> FemResponseTable {
    let first_touch = Step {
        approach_m: 0.0,
        area_fraction: 0.0,
        area_fraction_current: 0.0,
        load_n: 0.0,
        iterations: 0,
        largest_penetration_m: 0.0,
        mean_gap_m: f64::NAN,
    };
    let rows: Vec<&Step> = std::iter::once(&first_touch).chain(steps).collect();
    let column = |f: &dyn Fn(&Step) -> f64| rows.iter().map(|s| f(s)).collect::<Vec<f64>>();
    let curve = ResponseCurve {
        z_m: column(&|s| range_m - s.approach_m),
        area_fraction: column(&|s| s.area_fraction),
        area_m2: column(&|s| s.area_fraction * a0_m2),
        load_n: column(&|s| s.load_n),
        modulus_pa: column(&|_| f64::NAN),
    };
    let mut mean_gap_m = column(&|s| s.mean_gap_m);
    mean_gap_m[0] = first_gap_m;
    FemResponseTable {
        response: ResponseTable::from_curve(curve, e0_star_pa, a0_m2),
        approach_m: column(&|s| s.approach_m),
        area_fraction_current: column(&|s| s.area_fraction_current),
        mean_gap_m,
        newton_iterations: rows.iter().map(|s| s.iterations as i64).collect(),
        max_penetration_m: column(&|s| s.largest_penetration_m),
    }
}

/// The `contact_maps` product at the kept steps.
fn map_files(
    curve: &Curve,
    problem: &ContactProblem,
    table: &FemResponseTable,
    patch: &Field,
) -> Result<Files, StageError> {
    let (nx, ny) = patch.values.dim();
    let npy = |values: Vec<f64>| map_npy(values, (nx, ny), patch.dx_m, patch.dy_m);
    let mut files = Files::new();
    let mut index = FemMapIndex::default();
    for snapshot in &curve.snapshots {
        // Row 0 of the table is first touch: step k is row k + 1.
        let row = snapshot.step + 1;
        let label = area_fraction_label(snapshot.requested_area_fraction);
        let (pressure_file, contact_file, mesh_file) = (
            format!("pressure_{label}.npy"),
            format!("contact_{label}.npy"),
            format!("mesh_{label}.vtk"),
        );
        files
            .files
            .insert(pressure_file.clone(), npy(snapshot.pressure_pa.clone())?);
        let mask = snapshot
            .contact
            .iter()
            .map(|&c| f64::from(u8::from(c)))
            .collect();
        files.files.insert(contact_file.clone(), npy(mask)?);
        let mut vtk = Vec::new();
        crate::vtk::write_deformed(
            &mut vtk,
            &problem.mesh,
            &snapshot.displacement_m,
            &snapshot.pressure_pa,
            &snapshot.contact,
            &format!(
                "hypercontact fem, A/A0 = {:.4}",
                table.response.area_fraction[row]
            ),
        )
        .map_err(StageError::other)?;
        files.files.insert(mesh_file.clone(), vtk);
        let m = &mut index.maps;
        m.requested_area_fraction
            .push(snapshot.requested_area_fraction);
        m.area_fraction.push(table.response.area_fraction[row]);
        m.load_n.push(table.response.load_n[row]);
        m.pressure_file.push(pressure_file);
        m.dx_m.push(patch.dx_m);
        m.dy_m.push(patch.dy_m);
        index.step.push(row as i64);
        index.approach_m.push(table.approach_m[row]);
        index.contact_file.push(contact_file);
        index.mesh_file.push(mesh_file);
    }
    Ok(files.with_index(index))
}
