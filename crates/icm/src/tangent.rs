//! The paper's tangent-modulus idea (Eqs. 5–7) applied to any linear-elastic
//! contact model: the elastically coupled one (`bem`) and the theories from
//! the spectrum (`persson`, `greenwood-williamson`), besides profile theory.
//!
//! For a linear half-space the contact set and the load at a given approach
//! scale with the modulus: F = E* f, with f the load for E* = 1 and the
//! contact area A independent of E*. The hyperelastic model lets the modulus
//! follow the mean contact stress, as the ICM does:
//!
//!   dF = E_t*(−F/A) df,   F = 0 at first contact,
//!
//! with E_t* from [`crate::CompositeModulus`] (the ICM's own, same sign
//! convention: the law is evaluated at the compressive S = −F/A).
//! Integrated over the steps in f with the ICM's schemes: `euler`
//! F_{k+1} = F_k + Δf E(F_k), `heun` the trapezoid with an Euler predictor.
//! With a constant modulus both give E* f (to rounding), i.e. `linear`.
//!
//! A curve that starts at a positive load instead of first contact (a theory
//! evaluated on a log-spaced load grid) starts from [`small_load`]: where the
//! area grows in proportion to the load, the mean stress is constant, and so
//! is the modulus, F = f E_t*(−F/A).

use crate::Scheme;

/// F and E_t* at every step.
#[derive(Clone, Debug, PartialEq)]
pub struct TangentLoad {
    pub load_n: Vec<f64>,
    /// E_t*(−F/A), Pa.
    pub modulus_pa: Vec<f64>,
}

/// The modulus law failed at a step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "at step {step} the mean contact stress S = −F/A = {stress_pa:.6e} Pa leaves the material's \
     invertible range: {reason}"
)]
pub struct TangentError {
    pub step: usize,
    pub stress_pa: f64,
    pub reason: String,
}

/// Integrates dF = E_t*(−F/A) df over steps of unit-modulus load
/// `unit_load_m2` (f = F/E*, non-decreasing, f₀ = 0) and area `area_m2`.
/// `modulus(S)` is E_t* at the compressive stress S ≤ 0, Pa.
pub fn integrate(
    unit_load_m2: &[f64],
    area_m2: &[f64],
    scheme: Scheme,
    modulus: &mut dyn FnMut(f64) -> Result<f64, String>,
) -> Result<TangentLoad, TangentError> {
    integrate_from(0.0, unit_load_m2, area_m2, scheme, modulus)
}

/// [`integrate`] from the load `initial_load_n` at the first step instead of
/// zero (e.g. [`small_load`]'s).
pub fn integrate_from(
    initial_load_n: f64,
    unit_load_m2: &[f64],
    area_m2: &[f64],
    scheme: Scheme,
    modulus: &mut dyn FnMut(f64) -> Result<f64, String>,
) -> Result<TangentLoad, TangentError> {
    assert_eq!(unit_load_m2.len(), area_m2.len());
    let mut at = |k: usize, load_n: f64| -> Result<f64, TangentError> {
        let stress_pa = if area_m2[k] > 0.0 {
            -load_n / area_m2[k]
        } else {
            0.0
        };
        modulus(stress_pa).map_err(|reason| TangentError {
            step: k,
            stress_pa,
            reason,
        })
    };
    let n = unit_load_m2.len();
    let mut out = TangentLoad {
        load_n: Vec::with_capacity(n),
        modulus_pa: Vec::with_capacity(n),
    };
    if n == 0 {
        return Ok(out);
    }
    let mut load_n = initial_load_n;
    let mut e = at(0, load_n)?;
    for k in 0..n {
        out.load_n.push(load_n);
        out.modulus_pa.push(e);
        if k + 1 == n {
            break;
        }
        let df = unit_load_m2[k + 1] - unit_load_m2[k];
        load_n = match scheme {
            Scheme::Euler => load_n + df * e,
            Scheme::Heun => {
                let predicted = load_n + df * e;
                load_n + 0.5 * df * (e + at(k + 1, predicted)?)
            }
        };
        e = at(k + 1, load_n)?;
    }
    Ok(out)
}

/// The load F that solves F = f E_t*(−F/A) at one step of unit-modulus load
/// `unit_load_m2` = f and area `area_m2` = A: the tangent-modulus load where
/// A ∝ f, so that F/A and the modulus are constant below the step. Found by
/// bisection on the mean stress S = F/A in [0, S_hi], S_hi doubled from
/// (f/A) E_t*(0) until S > (f/A) E_t*(−S); the root is unique when the
/// modulus rises more slowly than S A/f, which the doubling also checks
/// (a law that outgrows it is refused, naming the stress reached).
pub fn small_load(
    unit_load_m2: f64,
    area_m2: f64,
    modulus: &mut dyn FnMut(f64) -> Result<f64, String>,
) -> Result<f64, TangentError> {
    if !(unit_load_m2 > 0.0 && area_m2 > 0.0) {
        return Ok(0.0);
    }
    let ratio = unit_load_m2 / area_m2;
    // S − (f/A) E_t*(−S): negative at S = 0, positive beyond the root.
    let mut excess = |stress_pa: f64| -> Result<f64, TangentError> {
        let e = modulus(-stress_pa).map_err(|reason| TangentError {
            step: 0,
            stress_pa: -stress_pa,
            reason,
        })?;
        Ok(stress_pa - ratio * e)
    };
    let mut lo = 0.0;
    let mut hi = -excess(0.0)?;
    let mut doublings = 0;
    while excess(hi)? <= 0.0 {
        lo = hi;
        hi *= 2.0;
        doublings += 1;
        if doublings > 60 {
            return Err(TangentError {
                step: 0,
                stress_pa: -hi,
                reason: "the modulus grows as fast as the stress: no self-consistent load".into(),
            });
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if excess(mid)? <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi) * area_m2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_modulus_gives_the_linear_load() {
        let f = [0.0, 1e-9, 3e-9, 3.5e-9, 8e-9];
        let area = [0.0, 1e-6, 2e-6, 2.2e-6, 4e-6];
        let e_star = 7.16e6;
        for scheme in [Scheme::Euler, Scheme::Heun] {
            let out = integrate(&f, &area, scheme, &mut |_| Ok(e_star)).unwrap();
            for (load, f) in out.load_n.iter().zip(f) {
                assert!(
                    (load - e_star * f).abs() <= 1e-14 * e_star * f,
                    "{scheme:?}"
                );
            }
            assert!(out.modulus_pa.iter().all(|&e| e == e_star));
        }
    }

    #[test]
    fn heun_follows_its_formula_and_failures_name_the_step() {
        // E(S) = 1 + |S|: step 1 by hand with Δf = 1, A1 = 1.
        let f = [0.0, 1.0];
        let area = [0.0, 1.0];
        let mut law = |s: f64| Ok(1.0 + s.abs());
        let out = integrate(&f, &area, Scheme::Heun, &mut law).unwrap();
        // predicted F̃ = 1, E(−1) = 2 → F1 = 0 + ½ (1 + 2) = 1.5; E(−1.5) = 2.5.
        assert_eq!(out.load_n, [0.0, 1.5]);
        assert_eq!(out.modulus_pa, [1.0, 2.5]);
        let e = integrate(&f, &area, Scheme::Euler, &mut |s| {
            if s < -0.5 {
                Err("beyond".into())
            } else {
                Ok(1.0)
            }
        })
        .unwrap_err();
        assert_eq!(e.step, 1);
        assert!(e.to_string().contains("step 1") && e.to_string().contains("beyond"));
    }

    #[test]
    fn the_small_load_start_is_self_consistent_and_follows_proportional_growth() {
        // E(S) = 1 + |S|/4, f/A = 0.5: S = 0.5 (1 + S/4) → S = 4/7.
        let mut law = |s: f64| Ok(1.0 + s.abs() / 4.0);
        let load = small_load(2.0, 4.0, &mut law).unwrap();
        assert!((load / 4.0 - 4.0 / 7.0).abs() < 1e-14, "{load}");
        // With A ∝ f the curve started there stays at that stress.
        let f = [2.0, 3.0, 5.0, 9.0];
        let area: Vec<f64> = f.iter().map(|f| 2.0 * f).collect();
        let out = integrate_from(load, &f, &area, Scheme::Heun, &mut law).unwrap();
        for (k, (load, a)) in out.load_n.iter().zip(&area).enumerate() {
            assert!((load / a - 4.0 / 7.0).abs() < 1e-13, "step {k}");
        }
        // A law stiffening faster than the stress has no such load.
        let e = small_load(1.0, 1.0, &mut |s: f64| Ok(1.0 + 2.0 * s.abs())).unwrap_err();
        assert!(e.to_string().contains("no self-consistent load"), "{e}");
        assert_eq!(small_load(0.0, 0.0, &mut law).unwrap(), 0.0);
    }
}
