//! From a linear theory's area against load to the stage's response rows:
//! the load grid and the paper's tangent modulus on it.
//!
//! A theory gives A/A0 as a function of p̄/E* (the contact area of a linear
//! half-space depends on load and modulus only through their ratio). The
//! rows are `steps` loads evenly spaced in ln(p̄/E*), from the load at which
//! A/A0 = min_area_fraction to the one at which it is max_area_fraction.
//! The load of each row is then E* times the unit-modulus load f = A0 p̄/E*
//! (`linear`), or the tangent-modulus integral dF = E_t*(−F/A) df
//! (`hyperelastic`, [`hypercontact_icm::tangent`]), started at the first row
//! from the self-consistent small load F = f E_t*(−F/A).

use hypercontact_icm::tangent::{TangentError, TangentLoad, integrate_from, small_load};
use hypercontact_icm::{CompositeModulus, Scheme};

/// A/A0 against p̄/E*, non-decreasing, 0 at no load.
pub trait Theory {
    fn area_fraction(&self, unit_pressure: f64) -> f64;
}

/// The load range could not be found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RangeError {
    #[error("A/A0 = {target} is not reached below p̄/E* = {limit:.3e} (A/A0 there: {reached:.6})")]
    Unreached {
        target: f64,
        limit: f64,
        reached: f64,
    },
    #[error("A/A0 is still {reached:.3e} at p̄/E* = {limit:.3e}, above the requested {target}")]
    TooStiff {
        target: f64,
        limit: f64,
        reached: f64,
    },
}

/// p̄/E* at which the theory's A/A0 equals `target` (0 < target), by
/// bisection in ln(p̄/E*) from a bracket grown by factors of 4 about
/// `scale` (a load of the right order, e.g. h'rms).
pub fn unit_pressure_at(theory: &dyn Theory, target: f64, scale: f64) -> Result<f64, RangeError> {
    let (mut lo, mut hi) = (scale, scale);
    for _ in 0..200 {
        let a = theory.area_fraction(lo);
        if a <= target {
            break;
        }
        lo /= 4.0;
        if lo < 1e-300 {
            return Err(RangeError::TooStiff {
                target,
                limit: lo,
                reached: a,
            });
        }
    }
    for _ in 0..200 {
        let a = theory.area_fraction(hi);
        if a >= target {
            break;
        }
        hi *= 4.0;
        if hi > 1e30 {
            return Err(RangeError::Unreached {
                target,
                limit: hi,
                reached: a,
            });
        }
    }
    while hi / lo > 1.0 + 1e-13 {
        let mid = (lo * hi).sqrt();
        if mid <= lo || mid >= hi {
            break;
        }
        if theory.area_fraction(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok((lo * hi).sqrt())
}

/// `steps` values evenly spaced in ln from `lo` to `hi` (both included).
pub fn log_grid(lo: f64, hi: f64, steps: usize) -> Vec<f64> {
    match steps {
        0 => Vec::new(),
        1 => vec![lo],
        _ => (0..steps)
            .map(|k| {
                if k + 1 == steps {
                    hi
                } else {
                    lo * (hi / lo).powf(k as f64 / (steps - 1) as f64)
                }
            })
            .collect(),
    }
}

/// The loads of the rows: f = A0 p̄/E* and A = A0 A/A0 in, F and E_t* out.
pub fn tangent_loads(
    unit_pressure: &[f64],
    area_fraction: &[f64],
    nominal_area_m2: f64,
    modulus: &CompositeModulus,
    scheme: Scheme,
) -> Result<TangentLoad, TangentError> {
    let unit_load_m2: Vec<f64> = unit_pressure.iter().map(|p| p * nominal_area_m2).collect();
    let area_m2: Vec<f64> = area_fraction.iter().map(|a| a * nominal_area_m2).collect();
    let mut law = |s: f64| modulus.at_stress_pa(s).map_err(|e| e.to_string());
    let start = match (unit_load_m2.first(), area_m2.first()) {
        (Some(&f), Some(&a)) => small_load(f, a, &mut law)?,
        _ => 0.0,
    };
    integrate_from(start, &unit_load_m2, &area_m2, scheme, &mut law)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_icm::Model;
    use hypercontact_material::presets::paper_epdm;
    use hypercontact_material::testing::ConstantTangent;
    use std::sync::Arc;

    struct Erf(f64);
    impl Theory for Erf {
        fn area_fraction(&self, p: f64) -> f64 {
            libm::erf(p / self.0)
        }
    }

    #[test]
    fn the_range_inverts_the_theory() {
        let theory = Erf(0.2);
        for target in [1e-4, 0.1, 0.9, 0.999] {
            let p = unit_pressure_at(&theory, target, 0.3).unwrap();
            assert!(
                (theory.area_fraction(p) / target - 1.0).abs() < 1e-12,
                "{target}"
            );
        }
        let e = unit_pressure_at(&theory, 1.5, 0.3).unwrap_err();
        assert!(e.to_string().contains("not reached"), "{e}");
        let grid = log_grid(1e-3, 1.0, 4);
        assert_eq!(grid.len(), 4);
        assert!((grid[1] - 1e-2).abs() < 1e-15 && grid[3] == 1.0);
    }

    #[test]
    fn a_constant_tangent_material_gives_the_linear_loads() {
        let p = log_grid(1e-4, 0.3, 50);
        let a: Vec<f64> = p.iter().map(|p| Erf(0.2).area_fraction(*p)).collect();
        let material = Arc::new(ConstantTangent { mu_pa: 1e6 });
        let hyper = CompositeModulus::new(material.clone(), Model::Hyperelastic, 0.5).unwrap();
        let e_t = hyper.at_stress_pa(0.0).unwrap();
        for scheme in [Scheme::Euler, Scheme::Heun] {
            let out = tangent_loads(&p, &a, 2e-6, &hyper, scheme).unwrap();
            for (f, p) in out.load_n.iter().zip(&p) {
                assert!((f / (e_t * p * 2e-6) - 1.0).abs() < 1e-12, "{scheme:?}");
            }
        }
        let linear = CompositeModulus::new(material, Model::Linear, 0.5).unwrap();
        let out = tangent_loads(&p, &a, 2e-6, &linear, Scheme::Heun).unwrap();
        let e0 = linear.e0_star_pa();
        assert!(
            out.load_n
                .iter()
                .zip(&p)
                .all(|(f, p)| (f / (e0 * p * 2e-6) - 1.0).abs() < 1e-12)
        );
    }

    #[test]
    fn a_stiffening_material_carries_more_load_than_its_initial_modulus() {
        // A/A0 ≈ 1.13 p/(0.05 E*) at small load: a mean contact stress of
        // about E_t* h'rms/κ with h'rms ≈ 0.07, as on the paper's T1.
        let p = log_grid(1e-5, 0.08, 80);
        let a: Vec<f64> = p.iter().map(|p| Erf(0.05).area_fraction(*p)).collect();
        let hyper =
            CompositeModulus::new(Arc::new(paper_epdm()), Model::Hyperelastic, 0.5).unwrap();
        let out = tangent_loads(&p, &a, 1e-6, &hyper, Scheme::Heun).unwrap();
        let e0 = hyper.e0_star_pa();
        // E_t*/E0* ≥ 2 (= 2 at zero stress) and rising with the mean stress.
        let ratio: Vec<f64> = out.modulus_pa.iter().map(|e| e / e0).collect();
        assert!(
            ratio[0] > 2.0 && ratio.windows(2).all(|w| w[1] >= w[0]),
            "{ratio:?}"
        );
        // The first row is self-consistent: F0 = f0 E_t*(−F0/A0).
        let f0 = p[0] * 1e-6;
        assert!((out.load_n[0] / (f0 * out.modulus_pa[0]) - 1.0).abs() < 1e-12);
    }
}
