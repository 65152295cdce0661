//! Stage `truncation`: a height map in, the profile-theory table out.

use hypercontact_core::product::ProductKind;
use hypercontact_core::{
    Arity, ColumnSpec, Context, InputSpec, Inputs, OutputSpec, Outputs, ParamDoc, ParamError,
    Params, Stage, StageError, StageInfo, Table,
};
use serde::{Deserialize, Serialize};

use crate::levels::{Connectivity, Levels};
use crate::profile::{Profile, TruncationOptions, truncate};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TruncationParams {
    /// Number of equal steps from z_max to 0, or `all` distinct heights.
    pub levels: Levels,
    /// 8 (MATLAB's default, the paper's) or 4.
    pub connectivity: Connectivity,
    /// Area fractions at which `patch_sizes` lists every patch.
    pub patch_fractions: Vec<f64>,
}

impl Default for TruncationParams {
    fn default() -> Self {
        let options = TruncationOptions::default();
        Self {
            levels: options.levels,
            connectivity: options.connectivity,
            patch_fractions: options.patch_fractions,
        }
    }
}

impl Params for TruncationParams {
    fn check(&self) -> Result<(), ParamError> {
        match self.levels {
            Levels::Count(0) => return Err(ParamError::new("levels", "must be at least 1")),
            // Each plane is a row of five columns; beyond this use `all`.
            Levels::Count(n) if n > MAX_LEVELS => {
                return Err(ParamError::new(
                    "levels",
                    format!("at most {MAX_LEVELS} (or `all` distinct heights), got {n}"),
                ));
            }
            _ => {}
        }
        if let Some(bad) = self
            .patch_fractions
            .iter()
            .find(|f| !(**f > 0.0 && **f <= 1.0))
        {
            return Err(ParamError::new(
                "patch_fractions",
                format!("every fraction must lie in (0, 1], got {bad}"),
            ));
        }
        Ok(())
    }
}

/// The `truncation` stage.
pub struct Truncation;

/// The most planes `levels: N` may ask for.
pub const MAX_LEVELS: u32 = 100_000_000;

/// The `profile` table, in column order.
pub const PROFILE_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::f64("z_m", "m", "plane height above the lowest measured point"),
    ColumnSpec::f64(
        "z_over_sigma",
        "",
        "z / σ (σ: rms height of the measured points)",
    ),
    ColumnSpec::f64(
        "area_fraction",
        "",
        "A / A0 (A0: measured points · dx · dy)",
    ),
    ColumnSpec::i64("patches", "", "connected touched patches N"),
    ColumnSpec::f64("radius_m", "m", "Eq. (3): sqrt(A / (π N)); 0 where N = 0"),
    ColumnSpec::f64("area_m2", "m²", "touched area A"),
];

/// The `patch_sizes` table: one row per patch at each chosen fraction.
pub const PATCH_SIZE_COLUMNS: &[ColumnSpec] = &[
    ColumnSpec::f64(
        "target_area_fraction",
        "",
        "the fraction asked for in patch_fractions",
    ),
    ColumnSpec::f64("z_m", "m", "the first plane (from the top) reaching it"),
    ColumnSpec::f64("z_over_sigma", "", "z / σ of that plane"),
    ColumnSpec::f64("area_fraction", "", "A / A0 at that plane"),
    ColumnSpec::f64("patch_area_m2", "m²", "area of one patch (largest first)"),
];

static INFO: StageInfo = StageInfo {
    kind: "truncation",
    version: 1,
    summary: "Profile theory: contact area, patch count and radius of a truncated height map",
    doc: "A plane at height z above the lowest measured point touches every pixel with \
          h >= z (NaN pixels never touch). A(z) is the touched area, N(z) the number of \
          connected touched patches (8-connectivity by default, like MATLAB's bwlabel, which \
          the paper used; 4 as an option; map edges are not wrapped) and r = sqrt(A/(pi N)) \
          (the paper's Eq. 3). sigma is the rms height about the mean of the measured points; \
          A0 = (measured points) * dx * dy, so NaN holes count in neither A nor A0. Planes: \
          z_k = z_max (levels - k) / levels for k = 0..levels, top down, or every distinct \
          height with `levels: all`. All planes come from one sweep over the heights sorted \
          once, with a union-find (path compression, union by size); the map is never \
          relabelled per plane. `patch_sizes` lists every patch's area at the first plane \
          whose A/A0 reaches each of `patch_fractions`.",
    params: &[
        ParamDoc {
            name: "levels",
            unit: "",
            doc: "number of equal steps from z_max down to 0 (1000), or `all` distinct heights",
        },
        ParamDoc {
            name: "connectivity",
            unit: "",
            doc: "8 (default, MATLAB's bwlabel) or 4",
        },
        ParamDoc {
            name: "patch_fractions",
            unit: "",
            doc: "area fractions at which every patch's area is listed (0.01, 0.1, 0.3, 0.5)",
        },
    ],
    inputs: &[InputSpec {
        name: "surface",
        kind: ProductKind::Field,
        arity: Arity::One,
        columns: &[],
        doc: "height map, metres, NaN = not measured",
    }],
    outputs: &[
        OutputSpec {
            name: "profile",
            kind: ProductKind::Table,
            columns: PROFILE_COLUMNS,
            doc: "one row per plane, top down",
        },
        OutputSpec {
            name: "patch_sizes",
            kind: ProductKind::Table,
            columns: PATCH_SIZE_COLUMNS,
            doc: "every patch's area at a few area fractions",
        },
    ],
};

impl Stage for Truncation {
    type Params = TruncationParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &TruncationParams,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.field("surface")?;
        let measured = surface.values.iter().filter(|h| !h.is_nan()).count();
        let bar = ctx.progress(measured as u64, "pixels swept");
        let options = TruncationOptions {
            levels: p.levels,
            connectivity: p.connectivity,
            patch_fractions: p.patch_fractions.clone(),
        };
        let profile = truncate(
            surface.values.view(),
            surface.dx_m,
            surface.dy_m,
            &options,
            &mut |n| bar.inc(n),
        )
        .map_err(StageError::other)?;
        ctx.note(&format!(
            "{} planes, sigma = {:.4e} m, z_max = {:.4e} m",
            profile.z_m.len(),
            profile.sigma_m,
            profile.z_m[0]
        ));
        Ok(Outputs::new()
            .table("profile", profile_table(&profile))
            .table("patch_sizes", patch_size_table(&profile)))
    }
}

/// The `profile` table of a profile.
pub fn profile_table(p: &Profile) -> Table {
    Table::new()
        .with("z_m", p.z_m.clone())
        .with(
            "z_over_sigma",
            p.z_m.iter().map(|z| z / p.sigma_m).collect::<Vec<_>>(),
        )
        .with("area_fraction", p.area_fraction.clone())
        .with(
            "patches",
            p.patches.iter().map(|&n| n as i64).collect::<Vec<_>>(),
        )
        .with("radius_m", p.radius_m.clone())
        .with("area_m2", p.area_m2.clone())
}

/// The `patch_sizes` table of a profile.
pub fn patch_size_table(p: &Profile) -> Table {
    let (mut target, mut z, mut zs, mut frac, mut area) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for s in &p.snapshots {
        for &a in &s.patch_areas_m2 {
            target.push(s.target_area_fraction);
            z.push(p.z_m[s.level]);
            zs.push(p.z_m[s.level] / p.sigma_m);
            frac.push(p.area_fraction[s.level]);
            area.push(a);
        }
    }
    Table::new()
        .with("target_area_fraction", target)
        .with("z_m", z)
        .with("z_over_sigma", zs)
        .with("area_fraction", frac)
        .with("patch_area_m2", area)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{Field, Product};
    use ndarray::array;

    #[test]
    fn stage_writes_both_tables_in_the_documented_order() {
        let field = Field::new(array![[0.0, 1e-6], [3e-6, f64::NAN]], 2e-5, 2e-5).unwrap();
        let inputs = Inputs::new().with("surface", Product::Field(field));
        let params: TruncationParams =
            serde_json::from_str(r#"{"levels": 3, "connectivity": 4}"#).unwrap();
        params.check().unwrap();
        let out = Truncation
            .run(&params, &inputs, &Context::new("t"))
            .unwrap();
        let Some(Product::Table(profile)) = out.get("profile") else {
            panic!("no profile")
        };
        profile.validate().unwrap();
        profile.conform(PROFILE_COLUMNS).unwrap();
        let names: Vec<&str> = PROFILE_COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(profile.column_names(), names);
        let z = profile.f64("z_m").unwrap();
        for (z, expected) in z.iter().zip([3e-6, 2e-6, 1e-6, 0.0]) {
            assert!((z - expected).abs() < 1e-20, "{z} vs {expected}");
        }
        // (1,0) and (0,1) are diagonal: apart under 4-connectivity until (0,0) joins them.
        assert_eq!(profile.i64("patches").unwrap(), &[1, 1, 2, 1]);
        // Heights 0, 1, 3 µm: mean 4/3, σ² = (16 + 1 + 25)/9 / 3 µm².
        let sigma = (42.0_f64 / 27.0).sqrt() * 1e-6;
        let zs = profile.f64("z_over_sigma").unwrap();
        assert!((zs[0] - 3e-6 / sigma).abs() < 1e-12);
        let Some(Product::Table(patches)) = out.get("patch_sizes") else {
            panic!("no patch_sizes")
        };
        patches.validate().unwrap();
        patches.conform(PATCH_SIZE_COLUMNS).unwrap();
        // One patch at 0.01, 0.1 and 0.3 (the top plane has A/A0 = 1/3), two
        // single pixels at 0.5 (the plane z = 1 µm, A/A0 = 2/3).
        assert_eq!(
            patches.f64("target_area_fraction").unwrap(),
            &[0.01, 0.1, 0.3, 0.5, 0.5]
        );
        let pixel_m2 = 2e-5 * 2e-5;
        assert_eq!(patches.f64("patch_area_m2").unwrap(), &[pixel_m2; 5]);
        assert_eq!(patches.f64("area_fraction").unwrap()[4], 2.0 / 3.0);
    }

    #[test]
    fn bad_params_are_named() {
        let p = TruncationParams {
            patch_fractions: vec![0.5, 1.5],
            ..Default::default()
        };
        assert_eq!(p.check().unwrap_err().param, "patch_fractions");
        let p = TruncationParams {
            levels: Levels::Count(u32::MAX),
            ..Default::default()
        };
        assert_eq!(p.check().unwrap_err().param, "levels");
        let e = serde_json::from_str::<TruncationParams>(r#"{"levls": 3}"#).unwrap_err();
        assert!(e.to_string().contains("levls"));
    }
}
