//! What both theories read: the spectrum (from stage `surface`'s radial PSD
//! or from a height map) clipped to the requested q range, and the nominal
//! area A0 that turns p̄ into a load in newtons.

use hypercontact_core::field::SurfaceProblem;
use hypercontact_core::{Field, Inputs, StageError};
use hypercontact_surface::psd::{Window, psd_radial};
use hypercontact_surface::surface_stage::{PsdTable, StatsTable};
use ndarray::Array2;

use crate::error::ClassicalError;
use crate::spectrum::Spectrum;

/// The parameters that choose and cut the spectrum (shared by both stages).
#[derive(Clone, Copy, Debug)]
pub struct SourceOptions {
    pub q_min_per_m: Option<f64>,
    pub q_max_per_m: Option<f64>,
    pub nominal_area_m2: Option<f64>,
    pub bins_per_decade: usize,
    pub periodic: bool,
    /// The stage kind reading the spectrum, for errors.
    pub kind: &'static str,
}

/// The spectrum the theory integrates and where it came from.
#[derive(Clone, Debug)]
pub struct Source {
    /// Persson's normalisation, clipped to the q range.
    pub spectrum: Spectrum,
    pub nominal_area_m2: f64,
    /// `psd` or `surface`.
    pub input: &'static str,
}

pub fn read(inputs: &Inputs, options: &SourceOptions) -> Result<Source, StageError> {
    let has = |name: &str| inputs.get(name).is_some();
    let (full, derived_area, input) = match (has("psd"), has("surface")) {
        (true, true) | (false, false) => {
            return Err(ClassicalError::Input(
                "give exactly one of input `psd` (stage surface's PSD table) or `surface` (a \
                 height map)"
                    .into(),
            )
            .into());
        }
        (true, false) => {
            let psd: PsdTable = inputs.read("psd")?;
            let area = if has("stats") {
                let stats: StatsTable = inputs.read("stats")?;
                refuse_line_scan(&stats, options.kind)?;
                Some(stats_area_m2(&stats)?)
            } else {
                None
            };
            (radial(&psd)?, area, "psd")
        }
        (false, true) => {
            if has("stats") {
                return Err(ClassicalError::Input(
                    "input `stats` goes with `psd`; with `surface` A0 is the map's measured area"
                        .into(),
                )
                .into());
            }
            let (spectrum, area) = from_map(inputs.areal_field("surface", options.kind)?, options)?;
            (spectrum, Some(area), "surface")
        }
    };
    let nominal_area_m2 = match (derived_area, options.nominal_area_m2) {
        (Some(_), Some(given)) => {
            return Err(ClassicalError::Param(format!(
                "nominal_area_m2 = {given} m² is given, but input `{}` already sets A0: drop \
                 one of them",
                if input == "psd" { "stats" } else { "surface" }
            ))
            .into());
        }
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => {
            return Err(ClassicalError::Param(
                "A0 is unknown: wire input `stats` (stage surface's) beside `psd`, or set \
                 nominal_area_m2"
                    .into(),
            )
            .into());
        }
    };
    let spectrum = full
        .clip(options.q_min_per_m, options.q_max_per_m)
        .map_err(|e| ClassicalError::Spectrum(input, e))?;
    Ok(Source {
        spectrum,
        nominal_area_m2,
        input,
    })
}

/// The `radial` rows of a PSD table.
fn radial(psd: &PsdTable) -> Result<Spectrum, StageError> {
    let (q, c): (Vec<f64>, Vec<f64>) = psd
        .direction
        .iter()
        .zip(psd.q_per_m.iter().zip(&psd.c))
        .filter(|(d, _)| d.as_str() == "radial")
        .map(|(_, (&q, &c))| (q, c))
        .unzip();
    if q.is_empty() {
        return Err(ClassicalError::Input(
            "input `psd` has no row with direction `radial` (the theories need the isotropic \
             2-D spectrum of a height map; `surface` gives none for a line scan)"
                .into(),
        )
        .into());
    }
    Ok(
        Spectrum::from_surface_topography(&q, &c)
            .map_err(|e| ClassicalError::Spectrum("psd", e))?,
    )
}

/// An error when `stats` is of a line scan (one point across): its PSD
/// has no radial rows and its A0 no meaning.
fn refuse_line_scan(stats: &StatsTable, kind: &'static str) -> Result<(), StageError> {
    if let (Some(&nx), Some(&ny)) = (stats.nx.first(), stats.ny.first())
        && (nx == 1) != (ny == 1)
    {
        return Err(StageError::LineScan {
            kind,
            input: "psd".into(),
            nx: usize::try_from(nx).unwrap_or(0),
            ny: usize::try_from(ny).unwrap_or(0),
        });
    }
    Ok(())
}

/// A0 = nx ny dx² (1 − nan_fraction), as `bem` counts measured pixels.
fn stats_area_m2(stats: &StatsTable) -> Result<f64, ClassicalError> {
    let bad =
        || ClassicalError::Input("input `stats` must hold one row with nx, ny, dx_m > 0".into());
    if stats.nx.len() != 1 {
        return Err(bad());
    }
    let (nx, ny, dx) = (stats.nx[0], stats.ny[0], stats.dx_m[0]);
    let measured = 1.0 - stats.nan_fraction[0];
    let area = nx as f64 * ny as f64 * dx * dx * measured;
    if nx > 0 && ny > 0 && area > 0.0 && area.is_finite() {
        Ok(area)
    } else {
        Err(bad())
    }
}

/// The radial PSD of a height map, computed as stage `surface` does (mean
/// removed, NaN at the mean, Hann window unless periodic), and its measured area.
fn from_map(field: &Field, options: &SourceOptions) -> Result<(Spectrum, f64), StageError> {
    let bad =
        |why: String| StageError::from(ClassicalError::Input(format!("input `surface`: {why}")));
    match field.contact_surface_problem(4) {
        Some(p @ SurfaceProblem::Flat(_)) => return Err(bad(format!("{p}: it has no spectrum"))),
        Some(p) => return Err(bad(p.to_string())),
        None => {}
    }
    let (nx, ny) = (field.nx(), field.ny());
    let (measured, sum) = field
        .values
        .iter()
        .filter(|h| !h.is_nan())
        .fold((0usize, 0.0), |(n, s), h| (n + 1, s + h));
    let mean = sum / measured as f64;
    let heights = Array2::from_shape_fn((nx, ny), |(i, j)| {
        let h = field.values[[i, j]];
        if h.is_nan() { 0.0 } else { h - mean }
    });
    let window = if options.periodic {
        Window::None
    } else {
        Window::Hann
    };
    let psd = psd_radial(
        &heights,
        field.dx_m,
        field.dy_m,
        window,
        options.bins_per_decade,
    );
    let spectrum = Spectrum::from_surface_topography(&psd.q_per_m, &psd.c)
        .map_err(|e| ClassicalError::Spectrum("surface", e))?;
    Ok((spectrum, measured as f64 * field.dx_m * field.dy_m))
}
