//! What the ICM's integration tests share: one material's solve over a
//! truncation profile.

use std::sync::Arc;

use hypercontact_icm::{CompositeModulus, Model, ProfileSlices, Scheme, Solution, solve};
use hypercontact_material::Hyperelastic;
use hypercontact_truncation::Profile;

/// `material`'s ICM over `p` (ν = ½), and its E0*.
pub fn solve_profile(
    p: &Profile,
    material: Arc<dyn Hyperelastic>,
    model: Model,
    scheme: Scheme,
) -> (Solution, f64) {
    let modulus = CompositeModulus::new(material, model, 0.5).unwrap();
    let patches: Vec<f64> = p.patches.iter().map(|&n| n as f64).collect();
    let s = solve(
        ProfileSlices {
            z_m: &p.z_m,
            area_m2: &p.area_m2,
            patches: &patches,
            radius_m: &p.radius_m,
        },
        scheme,
        &mut |s| modulus.at_stress_pa(s).map_err(|e| e.to_string()),
    )
    .unwrap();
    (s, modulus.e0_star_pa())
}
