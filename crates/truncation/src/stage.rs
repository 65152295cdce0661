//! Stage `truncation`: a height map in, the profile-theory table out.

use hypercontact_core::{
    Arity, Checked, Context, InputSpec, Inputs, OutputSpec, Outputs, Schema, Stage, StageError,
    StageInfo, params,
};

use crate::levels::{Connectivity, Levels};
use crate::profile::{Profile, TruncationOptions, truncate};

/// Parameters of `truncation`.
#[params]
pub struct TruncationParams {
    /// number of equal steps from z_max down to 0, or `all` distinct heights
    #[param(default = TruncationOptions::default().levels, check = at_most_max_levels)]
    pub levels: Levels,
    /// 8 (MATLAB's bwlabel, the paper's) or 4
    #[param(default = TruncationOptions::default().connectivity)]
    pub connectivity: Connectivity,
    /// area fractions at which every patch's area is listed
    #[param(default = TruncationOptions::default().patch_fractions, positive, range = ..=1.0)]
    pub patch_fractions: Vec<f64>,
}

/// The most planes `levels: N` may ask for: each plane is a row of the
/// profile; beyond this use `all`.
pub const MAX_LEVELS: u32 = 100_000_000;

fn at_most_max_levels(levels: &Levels) -> Result<(), String> {
    match *levels {
        Levels::Count(0) => Err("must be at least 1".into()),
        Levels::Count(n) if n > MAX_LEVELS => Err(format!(
            "at most {MAX_LEVELS} (or `all` distinct heights), got {n}"
        )),
        _ => Ok(()),
    }
}

/// The `truncation` stage.
pub struct Truncation;

/// The `profile` table: one row per plane, top down.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ProfileTable {
    /// plane height above the lowest measured point
    #[column(unit = "m")]
    pub z_m: Vec<f64>,
    /// z / σ (σ: rms height of the measured points)
    pub z_over_sigma: Vec<f64>,
    /// A / A0 (A0: measured points · dx · dy)
    pub area_fraction: Vec<f64>,
    /// connected touched patches N
    pub patches: Vec<i64>,
    /// Eq. (3): sqrt(A / (π N)); 0 where N = 0
    #[column(unit = "m")]
    pub radius_m: Vec<f64>,
    /// touched area A
    #[column(unit = "m²")]
    pub area_m2: Vec<f64>,
}

/// The `patch_sizes` table: one row per patch at each chosen fraction.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct PatchSizeTable {
    /// the fraction asked for in patch_fractions
    pub target_area_fraction: Vec<f64>,
    /// the first plane (from the top) reaching it
    #[column(unit = "m")]
    pub z_m: Vec<f64>,
    /// z / σ of that plane
    pub z_over_sigma: Vec<f64>,
    /// A / A0 at that plane
    pub area_fraction: Vec<f64>,
    /// area of one patch (largest first)
    #[column(unit = "m²")]
    pub patch_area_m2: Vec<f64>,
}

static INFO: StageInfo = StageInfo {
    kind: "truncation",
    version: 1,
    summary: "Profile theory: contact area, patch count and radius of a truncated height map",
    doc: "A plane at height z above the lowest measured point touches every pixel with h >= z \
          (NaN pixels never touch). A(z) is the touched area, N(z) the number of connected \
          touched patches (8- or 4-connectivity, `connectivity`; MATLAB's bwlabel, which the \
          paper used, joins 8 neighbours; map edges are not wrapped) and r = sqrt(A/(pi N)) \
          (the paper's Eq. 3). sigma is the rms height about the mean of the measured points; \
          A0 = (measured points) * dx * dy, so NaN holes count in neither A nor A0. Planes: \
          z_k = z_max (levels - k) / levels for k = 0..levels, top down, or every distinct \
          height with `levels: all`. All planes come from one sweep over the pixels in the \
          order the planes reach them (grouped by plane with a counting sort for `levels: N`, \
          sorted by height for `all`), with a union-find (path compression, union by size); \
          the map is never relabelled per plane. `patch_sizes` lists every patch's area at the first plane \
          whose A/A0 reaches each of `patch_fractions`.",
    inputs: &[InputSpec::field(
        "surface",
        Arity::One,
        "height map, metres, NaN = not measured",
    )],
    outputs: &[
        OutputSpec::table::<ProfileTable>("profile", "one row per plane, top down"),
        OutputSpec::table::<PatchSizeTable>(
            "patch_sizes",
            "every patch's area at a few area fractions",
        ),
    ],
};

impl Stage for Truncation {
    type Params = TruncationParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<TruncationParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let surface = inputs.areal_field("surface", "truncation")?;
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
            .table("profile", profile_table(&profile).into_table())
            .table("patch_sizes", patch_size_table(&profile).into_table()))
    }
}

/// The `profile` table of a profile.
pub fn profile_table(p: &Profile) -> ProfileTable {
    ProfileTable {
        z_m: p.z_m.clone(),
        z_over_sigma: p.z_m.iter().map(|z| z / p.sigma_m).collect(),
        area_fraction: p.area_fraction.clone(),
        patches: p.patches.iter().map(|&n| n as i64).collect(),
        radius_m: p.radius_m.clone(),
        area_m2: p.area_m2.clone(),
    }
}

/// The `patch_sizes` table of a profile.
pub fn patch_size_table(p: &Profile) -> PatchSizeTable {
    let mut t = PatchSizeTable::default();
    for s in &p.snapshots {
        for &a in &s.patch_areas_m2 {
            t.target_area_fraction.push(s.target_area_fraction);
            t.z_m.push(p.z_m[s.level]);
            t.z_over_sigma.push(p.z_m[s.level] / p.sigma_m);
            t.area_fraction.push(p.area_fraction[s.level]);
            t.patch_area_m2.push(a);
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{Field, Params, Product};
    use ndarray::array;

    #[test]
    fn stage_writes_both_tables_in_the_documented_order() {
        let field = Field::new(array![[0.0, 1e-6], [3e-6, f64::NAN]], 2e-5, 2e-5).unwrap();
        let inputs = Inputs::new().with("surface", Product::Field(field));
        let params: TruncationParams =
            serde_json::from_str(r#"{"levels": 3, "connectivity": 4}"#).unwrap();
        let params = params.check().unwrap();
        let out = Truncation
            .run(&params, &inputs, &Context::new("t"))
            .unwrap();
        let Some(Product::Table(profile)) = out.get("profile") else {
            panic!("no profile")
        };
        profile.validate().unwrap();
        profile.conform(ProfileTable::COLUMNS).unwrap();
        let names: Vec<&str> = ProfileTable::COLUMNS.iter().map(|c| c.name).collect();
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
        patches.conform(PatchSizeTable::COLUMNS).unwrap();
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
        assert_eq!(p.check().unwrap_err().param, "patch_fractions.1");
        let p = TruncationParams {
            levels: Levels::Count(u32::MAX),
            ..Default::default()
        };
        assert_eq!(p.check().unwrap_err().param, "levels");
        let e = serde_json::from_str::<TruncationParams>(r#"{"levls": 3}"#).unwrap_err();
        assert!(e.to_string().contains("levls"));
    }
}
