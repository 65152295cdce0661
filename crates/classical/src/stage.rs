//! Stages `persson` and `greenwood-williamson`: a spectrum and a material
//! in, the `icm` response columns (and the theory's own) out. Checks and
//! tables here; the theories in [`crate::persson`] and [`crate::gw`], the
//! load grid and the tangent modulus in [`crate::curve`].

use hypercontact_core::contact::{BandTable, Curve, ResponseTable};
use hypercontact_core::{
    Arity, Checked, Choice, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamError, Schema,
    Stage, StageError, StageInfo, params,
};
use hypercontact_icm::bands::{BandAxes, replicate_bands, wired_replicates};
use hypercontact_icm::tangent::TangentError;
use hypercontact_icm::{CompositeModulus, LawParams};
use hypercontact_material::bootstrap::ReplicatesTable;
use hypercontact_material::table::MaterialTable;
use hypercontact_surface::surface_stage::{PsdTable, StatsTable};

use crate::curve::{Theory, log_grid, tangent_loads, unit_pressure_at};
use crate::error::ClassicalError;
use crate::gw::Asperities;
use crate::persson::{Persson, Variant};
use crate::source::{Source, SourceOptions, read};

/// Which form of Persson's theory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum PerssonVariant {
    /// Persson 2001: A/A0 = erf(p̄/√(2V))
    #[default]
    Original,
    /// Yang & Persson 2008: the diffusion slowed by S = γ + (1 − γ) P² (marched in q)
    YangPersson,
}

/// Parameters of `persson`: the theory's form, then what both theories take.
#[params]
pub struct PerssonParams {
    /// the theory's form
    #[param(default = PerssonVariant::Original)]
    pub variant: PerssonVariant,
    /// Yang & Persson's γ (0.42–0.45 in the literature); only for yang-persson
    #[param(default = 0.45, positive, range = ..=1.0)]
    pub gamma: f64,
    #[param(flatten)]
    pub spectrum: SpectrumParams,
}

/// Parameters of `greenwood-williamson`: what both theories take.
#[params]
pub struct GwParams {
    #[param(flatten)]
    pub spectrum: SpectrumParams,
}

/// The contact law, the rows and the spectrum's route, as both theories
/// take them.
#[params(check = ordered)]
pub struct SpectrumParams {
    #[param(flatten)]
    pub law: LawParams,
    /// A/A0 of the first row
    #[param(default = 0.001, positive, range = ..1.0)]
    pub min_area_fraction: f64,
    /// A/A0 of the last row (below 1: the theories reach full contact only as the load grows without bound)
    #[param(default = 0.95, positive, range = ..1.0)]
    pub max_area_fraction: f64,
    /// rows, evenly spaced in ln(load)
    #[param(default = 200, range = 2..=100_000)]
    pub steps: usize,
    /// smallest wavevector integrated (default: the spectrum's first)
    #[param(unit = "rad/m", positive)]
    pub q_min_per_m: Option<f64>,
    /// largest wavevector integrated (default: the spectrum's last, the map's Nyquist)
    #[param(unit = "rad/m", positive)]
    pub q_max_per_m: Option<f64>,
    /// A0 when neither `stats` nor `surface` gives it
    #[param(unit = "m²", positive)]
    pub nominal_area_m2: Option<f64>,
    /// log bins per decade of the PSD computed from input `surface`
    #[param(default = 10, range = 1..=100)]
    pub bins_per_decade: usize,
    /// input `surface` is periodic (no window for its PSD)
    #[param(default = false)]
    pub periodic: bool,
}

fn ordered(p: &SpectrumParams) -> Result<(), ParamError> {
    let (min, max) = (p.min_area_fraction, p.max_area_fraction);
    if min >= max {
        return Err(ParamError::new(
            "min_area_fraction",
            format!("{min} is not below max_area_fraction ({max})"),
        ));
    }
    if let (Some(lo), Some(hi)) = (p.q_min_per_m, p.q_max_per_m)
        && lo >= hi
    {
        return Err(ParamError::new(
            "q_min_per_m",
            format!("{lo} rad/m is not below q_max_per_m ({hi} rad/m)"),
        ));
    }
    Ok(())
}

/// `persson`'s `response`: every contact model's columns, then the theory's.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct PerssonResponseTable {
    #[column(flatten)]
    pub response: ResponseTable,
    /// mean interfacial separation ū, from the elastic energy (Persson 2007); `z_m` too
    #[column(unit = "m")]
    pub mean_separation_m: Vec<f64>,
    /// (A/A0) / (p̄ / (E0* h'rms)), h'rms of the spectrum integrated
    pub kappa: Vec<f64>,
}

/// `greenwood-williamson`'s `response`: every contact model's columns, then
/// the theory's.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct GwResponseTable {
    #[column(flatten)]
    pub response: ResponseTable,
    /// (A/A0) / (p̄ / (E0* h'rms)), h'rms = √(2 m2)
    pub kappa: Vec<f64>,
    /// summits in contact per area
    #[column(unit = "1/m²")]
    pub contacts_per_m2: Vec<f64>,
    /// mean Hertz contact radius √(R δ) of the touching summits
    #[column(unit = "m")]
    pub mean_contact_radius_m: Vec<f64>,
}

/// `persson`'s `summary`: one row, what the theory was given.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct PerssonSummaryTable {
    /// original or yang-persson
    pub variant: Vec<String>,
    /// γ (NaN for original)
    pub gamma: Vec<f64>,
    /// where the spectrum came from: psd or surface
    pub input: Vec<String>,
    /// smallest wavevector integrated
    #[column(unit = "rad/m")]
    pub q_min_per_m: Vec<f64>,
    /// largest wavevector integrated
    #[column(unit = "rad/m")]
    pub q_max_per_m: Vec<f64>,
    /// √m0 over the range
    #[column(unit = "m")]
    pub rms_height_m: Vec<f64>,
    /// h'rms = √(2 m2) over the range
    pub rms_slope: Vec<f64>,
    /// κ of the linear theory at vanishing load (√(8/π) = 1.596 for original)
    pub kappa_small_load: Vec<f64>,
    /// nominal area A0
    #[column(unit = "m²")]
    pub nominal_area_m2: Vec<f64>,
    /// E0* of the material
    #[column(unit = "Pa")]
    pub e0_star_pa: Vec<f64>,
}

/// `greenwood-williamson`'s `summary`: one row, the asperity parameters.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct GwSummaryTable {
    /// where the spectrum came from: psd or surface
    pub input: Vec<String>,
    /// smallest wavevector in the moments
    #[column(unit = "rad/m")]
    pub q_min_per_m: Vec<f64>,
    /// largest wavevector in the moments
    #[column(unit = "rad/m")]
    pub q_max_per_m: Vec<f64>,
    /// m0 = ⟨h²⟩
    #[column(unit = "m²")]
    pub m0_m2: Vec<f64>,
    /// m2 = ⟨(∂h/∂x)²⟩
    pub m2: Vec<f64>,
    /// m4 = ⟨(∂²h/∂x²)²⟩
    #[column(unit = "1/m²")]
    pub m4_per_m2: Vec<f64>,
    /// Nayak's α = m0 m4 / m2²
    pub nayak_alpha: Vec<f64>,
    /// η = m4 / (6π√3 m2)
    #[column(unit = "1/m²")]
    pub summit_density_per_m2: Vec<f64>,
    /// R = (3/8) √(π/m4)
    #[column(unit = "m")]
    pub summit_radius_m: Vec<f64>,
    /// σ_s = √((1 − 0.8968/α) m0)
    #[column(unit = "m")]
    pub summit_sigma_m: Vec<f64>,
    /// mean summit height above the mean plane, 4 √(m0/(π α))
    #[column(unit = "m")]
    pub summit_mean_m: Vec<f64>,
    /// nominal area A0
    #[column(unit = "m²")]
    pub nominal_area_m2: Vec<f64>,
    /// E0* of the material
    #[column(unit = "Pa")]
    pub e0_star_pa: Vec<f64>,
}

/// The inputs both stages take.
static INPUTS: &[InputSpec] = &[
    InputSpec::table::<PsdTable>(
        "psd",
        Arity::Optional,
        "stage surface's PSD table (its radial rows are used)",
    ),
    InputSpec::table::<StatsTable>(
        "stats",
        Arity::Optional,
        "stage surface's stats, beside `psd`: A0 = nx ny dx² (1 - nan_fraction)",
    ),
    InputSpec::field(
        "surface",
        Arity::Optional,
        "a height map instead of `psd` (its radial PSD is computed here)",
    ),
    InputSpec::table::<MaterialTable>(
        "material",
        Arity::One,
        "the material table (a preset or a fit)",
    ),
    InputSpec::table::<ReplicatesTable>(
        "replicates",
        Arity::Optional,
        "material-fit's bootstrap replicates: each replicate's law is integrated over the same \
         theory curve, for `bands`",
    ),
];

/// The `bands` output of both stages.
const BANDS: OutputSpec = OutputSpec::table::<BandTable>(
    "bands",
    "5–95 % bands over the material's bootstrap replicates, one row per load (no rows without \
     `replicates`)",
);

/// What both stages' docs say about `replicates`.
macro_rules! bands_doc {
    () => {
        " BANDS: with `replicates` (material-fit's bootstrap) each replicate material's law is \
         integrated over the same theory curve (the curve for E* = 1 does not depend on the \
         material), a few microseconds each; `bands` gives per row the 5th, 50th and 95th \
         percentiles of load_norm (over the main material's E0* A0) and of tangent_ratio (over \
         the replicate's own E0*), as `icm` does; a replicate whose law gives out is left out \
         with a note."
    };
}

/// The `persson` stage.
pub struct PerssonStage;

static PERSSON: StageInfo = StageInfo {
    kind: "persson",
    version: 2,
    summary: "Persson's theory (2001; Yang & Persson 2008): load against contact area and mean \
              separation from the height spectrum",
    doc: concat!(
        "The rough surface as a rigid, randomly rough (Gaussian, isotropic) surface on an \
          elastic half-space, described by its spectrum alone. SPECTRUM: input `psd` (stage \
          surface's radial rows, SurfaceTopography's normalisation) or `surface` (a height map; \
          its radial PSD computed as surface does: mean removed, NaN at the mean, Hann window \
          unless `periodic`, bins_per_decade); converted to Persson's C = C_ST/(2 pi)^2 \
          (<h^2> = 2 pi int q C dq); C is a power law between tabulated points. Q RANGE: by \
          default the whole spectrum, from its first bin to the map's Nyquist wavevector pi/dx. \
          The 20 um filter of stage surface is not undone: its roll-off (a Gaussian passing 25 % \
          of the power at the Nyquist wavelength) is in the spectrum, so the theory sees the same \
          surface as icm and bem on the filtered map; h'rms, which sets the small-load area, is \
          dominated by the shortest wavelengths kept, so q_max_per_m changes the answer and is \
          reported in `summary` (h'rms here is the spectral one, sqrt(2 pi int q^3 C dq), not \
          surface's forward differences). THEORY: A/A0 = erf(p/sqrt(2 V)), V = (pi/2) E*^2 int \
          q^3 C dq = E*^2 h'rms^2/4 (Persson, J. Chem. Phys. 115, 3840, 2001); small load: A/A0 = \
          sqrt(8/pi) p/(E* h'rms), kappa = 1.596. `yang-persson`: Yang & Persson (J. Phys.: \
          Condens. Matter 20, 215214, 2008) march in q with the partial-contact factor S = gamma \
          + (1 - gamma) P(q)^2 slowing the stress diffusion, dV_p = S dV, P = erf(p/sqrt(2 V_p)); \
          kappa -> 1.596/sqrt(gamma) at small load (2.38 for gamma = 0.45). MEAN SEPARATION \
          (`mean_separation_m`, and `z_m`): p = -dU_el/du with U_el/A0 = (pi/2) E* int q^2 C P S \
          dq (S = 1 for original; Persson, PRL 99, 125502, 2007), u = 0 at full contact: the \
          mean gap between the flat and the deformed surface, so `z_m` here is a separation, not \
          icm's plane height from the lowest point. ROWS: `steps` loads evenly spaced in ln(p) \
          from A/A0 = min_area_fraction to max_area_fraction of the linear theory. LOAD: p = \
          F/A0, A0 from input `stats` (nx ny dx^2 (1 - nan_fraction), the map's measured area as \
          bem counts it), from input `surface`, or nominal_area_m2. MODEL `linear`: F = E0* f, f \
          = A0 p/E* (E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu), as in icm). `hyperelastic`: the \
          paper's tangent modulus (Eqs. 5-7) on the theory's curve, dF = E_t*(-F/A) df, as bem \
          does (E_t*/E0* = 2 at first contact for nu = 1/2 with the paper's `tangent: \
          equibiaxial`, 1 with `uniaxial`; a linear material's E* throughout); the theory puts \
          the mean contact stress at about E_t* h'rms/kappa at small load, so the first row \
          starts from the self-consistent F = f E_t*(-F/A) instead of F = 0 \
          (a material that stiffens faster than that has no such load and is refused). \
          tangent_ratio = E_t*/E0*; kappa = (A/A0)/(p/(E0* h'rms)) with the spectral h'rms.",
        bands_doc!()
    ),
    inputs: INPUTS,
    outputs: &[
        OutputSpec::table::<PerssonResponseTable>(
            "response",
            "one row per load, icm's columns first",
        ),
        OutputSpec::table::<PerssonSummaryTable>(
            "summary",
            "one row: variant, q range, h_rms, h'rms, small-load kappa, A0",
        ),
        BANDS,
    ],
};

impl Stage for PerssonStage {
    type Params = PerssonParams;

    fn info(&self) -> &'static StageInfo {
        &PERSSON
    }

    fn run(
        &self,
        p: &Checked<PerssonParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let (source, modulus) = setup(inputs, &p.spectrum, PERSSON.kind, ctx)?;
        let variant = match p.variant {
            PerssonVariant::Original => Variant::Original,
            PerssonVariant::YangPersson => Variant::YangPersson { gamma: p.gamma },
        };
        let theory = Persson::new(&source.spectrum, variant);
        let moments = source.spectrum.moments();
        let slope = moments.rms_slope();
        let unit_pressure = load_rows(&theory, slope, &p.spectrum)?;
        let progress = ctx.progress(1, "mean separation");
        let points = theory.curve(&unit_pressure);
        drop(progress);
        let area_fraction: Vec<f64> = points.iter().map(|q| q.area_fraction).collect();
        let separation: Vec<f64> = points.iter().map(|q| q.mean_separation_m).collect();
        let (response, bands) = respond(
            &unit_pressure,
            (area_fraction, separation.clone()),
            (&source, &modulus),
            &p.spectrum.law,
            (inputs, ctx),
        )?;
        let response = PerssonResponseTable {
            kappa: response.kappa(slope),
            mean_separation_m: separation,
            response,
        };
        let tiny = 1e-6 * slope;
        let summary = PerssonSummaryTable {
            variant: vec![hypercontact_core::param::Choice::name(&p.variant).to_owned()],
            gamma: vec![match variant {
                Variant::Original => f64::NAN,
                Variant::YangPersson { gamma } => gamma,
            }],
            input: vec![source.input.to_owned()],
            q_min_per_m: vec![source.spectrum.q_min()],
            q_max_per_m: vec![source.spectrum.q_max()],
            rms_height_m: vec![moments.rms_height_m()],
            rms_slope: vec![slope],
            kappa_small_load: vec![theory.area_fraction(tiny) / (tiny / slope)],
            nominal_area_m2: vec![source.nominal_area_m2],
            e0_star_pa: vec![modulus.e0_star_pa()],
        };
        let area = &response.response.area_fraction;
        ctx.note(&format!(
            "{} rows, A/A0 {:.4} … {:.4}, h'rms {:.4} over q = {:.3e} … {:.3e} rad/m",
            p.spectrum.steps,
            area[0],
            area[area.len() - 1],
            slope,
            source.spectrum.q_min(),
            source.spectrum.q_max()
        ));
        Ok(Outputs::new()
            .table("response", response.into_table())
            .table("summary", summary.into_table())
            .table("bands", bands.into_table()))
    }
}

/// The `greenwood-williamson` stage.
pub struct GreenwoodWilliamson;

static GW: StageInfo = StageInfo {
    kind: "greenwood-williamson",
    version: 2,
    summary: "Greenwood-Williamson asperity model with its summits from the spectral moments: \
              load against contact area",
    doc: concat!(
        "Independent Hertzian summits of one radius with Gaussian heights, no elastic \
          interaction between them (Greenwood & Williamson, Proc. R. Soc. A 295, 300, 1966). \
          SPECTRUM: as in `persson` (input `psd` or `surface`, Persson's normalisation, q range \
          default the whole spectrum with the 20 um filter's roll-off in it). PARAMETERS from the \
          profile moments of the isotropic surface (Nayak, J. Lubr. Technol. 93, 398, 1971): m0 = \
          2 pi int q C dq, m2 = pi int q^3 C dq, m4 = (3 pi/4) int q^5 C dq; Nayak's alpha = m0 \
          m4/m2^2; summit density eta = m4/(6 pi sqrt(3) m2); mean summit radius R = (3/8) \
          sqrt(pi/m4), summit-height spread sigma_s = sqrt((1 - 0.8968/alpha) m0) and mean summit \
          height 4 sqrt(m0/(pi alpha)) above the mean plane (McCool, Wear 107, 37, 1986). m4 and \
          so eta and R are set by the shortest wavelengths kept (for a self-affine surface they \
          grow without bound with q_max): the model's answer depends on the q range, reported in \
          `summary`. INTEGRALS at separation d of the flat from the mean plane of the surface \
          heights (u = (d - mean summit height)/sigma_s, F_k(u) = int_0^inf t^k phi(u + t) dt): \
          contacts/A0 = eta F_0(u); A/A0 = pi eta R sigma_s F_1(u); p/E* = (4/3) eta sqrt(R) \
          sigma_s^(3/2) F_(3/2)(u). `z_m` is d (it falls as the load rises); kappa = (A/A0)/(p/(E0* \
          h'rms)), h'rms = sqrt(2 m2), grows without bound as the load vanishes (A/p ~ \
          sqrt(u)) and falls with load. ROWS, LOAD, A0 and MODEL (linear, or the tangent modulus \
          on the theory's curve, starting from the self-consistent small load) as in `persson`. \
          GW counts each summit's Hertz area alone, so A/A0 may pass 1 at large load; the model \
          is meant for small loads.",
        bands_doc!()
    ),
    inputs: INPUTS,
    outputs: &[
        OutputSpec::table::<GwResponseTable>("response", "one row per load, icm's columns first"),
        OutputSpec::table::<GwSummaryTable>(
            "summary",
            "one row: q range, moments, Nayak's alpha, summit density, radius and heights, A0",
        ),
        BANDS,
    ],
};

impl Stage for GreenwoodWilliamson {
    type Params = GwParams;

    fn info(&self) -> &'static StageInfo {
        &GW
    }

    fn run(
        &self,
        p: &Checked<GwParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let (source, modulus) = setup(inputs, &p.spectrum, GW.kind, ctx)?;
        let m = source.spectrum.moments();
        let asperities = Asperities::from_moments(m)
            .map_err(|e| ClassicalError::Input(format!("input `{}`: {e}", source.input)))?;
        let slope = m.rms_slope();
        let unit_pressure = load_rows(&asperities, slope, &p.spectrum)?;
        let points: Vec<_> = unit_pressure
            .iter()
            .map(|&pu| {
                let d = asperities.separation_at_unit_pressure(pu);
                (d, asperities.at_separation(d))
            })
            .collect();
        let area_fraction: Vec<f64> = points.iter().map(|(_, q)| q.area_fraction).collect();
        let (response, bands) = respond(
            &unit_pressure,
            (area_fraction, points.iter().map(|(d, _)| *d).collect()),
            (&source, &modulus),
            &p.spectrum.law,
            (inputs, ctx),
        )?;
        let response = GwResponseTable {
            kappa: response.kappa(slope),
            response,
            contacts_per_m2: points.iter().map(|(_, q)| q.contacts_per_m2).collect(),
            mean_contact_radius_m: points
                .iter()
                .map(|(_, q)| q.mean_contact_radius_m)
                .collect(),
        };
        let a = &asperities;
        let summary = GwSummaryTable {
            input: vec![source.input.to_owned()],
            q_min_per_m: vec![source.spectrum.q_min()],
            q_max_per_m: vec![source.spectrum.q_max()],
            m0_m2: vec![m.m0],
            m2: vec![m.m2],
            m4_per_m2: vec![m.m4],
            nayak_alpha: vec![a.nayak_alpha],
            summit_density_per_m2: vec![a.summit_density_per_m2],
            summit_radius_m: vec![a.summit_radius_m],
            summit_sigma_m: vec![a.summit_sigma_m],
            summit_mean_m: vec![a.summit_mean_m],
            nominal_area_m2: vec![source.nominal_area_m2],
            e0_star_pa: vec![modulus.e0_star_pa()],
        };
        ctx.note(&format!(
            "Nayak alpha {:.1}, {:.3e} summits/mm², R {:.3e} m, sigma_s {:.3e} m",
            a.nayak_alpha,
            a.summit_density_per_m2 * 1e-6,
            a.summit_radius_m,
            a.summit_sigma_m
        ));
        Ok(Outputs::new()
            .table("response", response.into_table())
            .table("summary", summary.into_table())
            .table("bands", bands.into_table()))
    }
}

/// The spectrum (input `psd` or `surface`) and the contact law of `material`.
fn setup(
    inputs: &Inputs,
    p: &SpectrumParams,
    kind: &'static str,
    ctx: &Context,
) -> Result<(Source, CompositeModulus), StageError> {
    let source = read(
        inputs,
        &SourceOptions {
            q_min_per_m: p.q_min_per_m,
            q_max_per_m: p.q_max_per_m,
            nominal_area_m2: p.nominal_area_m2,
            bins_per_decade: p.bins_per_decade,
            periodic: p.periodic,
            kind,
        },
    )?;
    let modulus = (p.law)
        .modulus_from_table(inputs.table("material")?, ctx)
        .map_err(ClassicalError::Material)?;
    Ok((source, modulus))
}

/// The bootstrap bands of a theory's rows (`unit_pressure` = p̄/E*, A/A0)
/// when `replicates` is wired.
fn bands(
    inputs: &Inputs,
    law: &LawParams,
    (unit_pressure, area_fraction): (&[f64], &[f64]),
    source: &Source,
    modulus: &CompositeModulus,
    ctx: &Context,
) -> Result<BandTable, StageError> {
    let a0 = source.nominal_area_m2;
    Ok(replicate_bands(
        wired_replicates(inputs)?,
        law,
        BandAxes {
            area_fraction,
            e0_star_pa: modulus.e0_star_pa(),
            nominal_area_m2: a0,
        },
        &|m| {
            tangent_loads(unit_pressure, area_fraction, a0, m, law.scheme)
                .map_err(|e| e.to_string())
        },
        ctx,
    ))
}

/// p̄/E* of the rows: from the load at min to the load at max A/A0.
fn load_rows(theory: &dyn Theory, slope: f64, p: &SpectrumParams) -> Result<Vec<f64>, StageError> {
    let lo = unit_pressure_at(theory, p.min_area_fraction, slope).map_err(ClassicalError::Range)?;
    let hi = unit_pressure_at(theory, p.max_area_fraction, slope).map_err(ClassicalError::Range)?;
    Ok(log_grid(lo, hi, p.steps))
}

/// The response on the theory's rows (A/A0 and z at each p̄/E* of
/// `unit_pressure`) under the contact law: E0* times the theory's load, or
/// the tangent-modulus integral over it; and the bootstrap bands of the same
/// rows when `replicates` is wired.
fn respond(
    unit_pressure: &[f64],
    (area_fraction, z_m): (Vec<f64>, Vec<f64>),
    (source, modulus): (&Source, &CompositeModulus),
    law: &LawParams,
    (inputs, ctx): (&Inputs, &Context),
) -> Result<(ResponseTable, BandTable), StageError> {
    let bands = bands(
        inputs,
        law,
        (unit_pressure, &area_fraction),
        source,
        modulus,
        ctx,
    )?;
    let a0 = source.nominal_area_m2;
    let loads = tangent_loads(unit_pressure, &area_fraction, a0, modulus, law.scheme)
        .map_err(|e| tangent_error(e, &area_fraction))?;
    let curve = Curve {
        area_m2: area_fraction.iter().map(|a| a * a0).collect(),
        z_m,
        area_fraction,
        load_n: loads.load_n,
        modulus_pa: loads.modulus_pa,
    };
    let response = ResponseTable::from_curve(curve, modulus.e0_star_pa(), a0);
    Ok((response, bands))
}

fn tangent_error(e: TangentError, area_fraction: &[f64]) -> ClassicalError {
    let at = area_fraction.get(e.step).copied().unwrap_or(f64::NAN);
    let hint = if e.step == 0 {
        "at small load these theories hold the mean contact stress near E_t* h'rms/kappa, and \
         this material stiffens faster than that stress: use `model: linear`, a smaller \
         q_max_per_m (smaller h'rms) or another material"
    } else {
        "lower max_area_fraction, or use `model: linear`"
    };
    ClassicalError::Tangent(format!("row {} (A/A0 = {at:.4}): {e}; {hint}", e.step))
}
