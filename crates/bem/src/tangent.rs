//! The paper's tangent-modulus idea (Eqs. 5–7) applied to the elastically
//! coupled contact instead of profile theory.
//!
//! For a linear half-space the contact set and the load at a rigid-plane
//! approach δ scale with the modulus: F = E* f(δ), with f the load for
//! E* = 1 and the contact area A(δ) independent of E*. The hyperelastic
//! model lets the modulus follow the mean contact stress, as the ICM does:
//!
//!   dF = E_t*(−F/A) · f'(δ) dδ = E_t*(−F/A) df,   F = 0 at first contact,
//!
//! with E_t* from [`hypercontact_icm::CompositeModulus`] (the ICM's own,
//! same sign convention: the law is evaluated at the compressive S = −F/A).
//! Integrated over the solved steps in f, with the ICM's schemes:
//! `euler` F_{k+1} = F_k + Δf E(F_k), `heun` the trapezoid with an Euler
//! predictor. With a constant modulus both give E* f (to rounding), i.e. `linear`.

use hypercontact_icm::Scheme;

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
    let mut load_n = 0.0;
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
}
