//! The incremental contact model, Eqs. (4)–(7) of the paper: integrate
//!
//!   dF/d(−z) = 2 E_t*(S) r(z) N(z),   S = −F/A,   F(z_max) = 0,
//!
//! from the top of the surface downward over the planes of a truncation
//! profile. A pure function of slices and a modulus closure, so it is tested
//! without tables or materials.
//!
//! Schemes (step h_k = z_k − z_{k+1} > 0, g_k(F) = 2 E_t*(−F/A_k) r_k N_k):
//! - `euler`, the paper's explicit iteration: F_{k+1} = F_k + h_k g_k(F_k);
//! - `heun`, the explicit trapezoidal rule (second order):
//!   F̃ = F_k + h_k g_k(F_k), F_{k+1} = F_k + h_k/2 [g_k(F_k) + g_{k+1}(F̃)].
//!   Heun rather than a classic RK4 because A, N and r are known only at the
//!   tabulated planes: RK4's half-step stages would need them between planes,
//!   i.e. an interpolation of a step-like function that adds its own error.
//!   Heun uses exactly the tabulated values, is exact when the stiffness is
//!   constant over a step (the flat punch), and re-evaluates E_t* at the end
//!   of the step, which is where Euler lags as the stress rises.

/// The integration scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, hypercontact_core::Choice)]
pub enum Scheme {
    /// the paper's explicit step (first order)
    Euler,
    /// explicit trapezoidal predictor–corrector (second order)
    #[default]
    Heun,
}

/// The truncation profile the solver integrates over, top down.
#[derive(Clone, Copy, Debug)]
pub struct ProfileSlices<'a> {
    /// Plane heights, strictly decreasing, m.
    pub z_m: &'a [f64],
    /// Touched area A, m².
    pub area_m2: &'a [f64],
    /// Patch count N.
    pub patches: &'a [f64],
    /// Equivalent patch radius r, m.
    pub radius_m: &'a [f64],
}

/// The load at every plane and the composite tangent modulus there.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    pub load_n: Vec<f64>,
    /// F / A, Pa (0 where A = 0): the magnitude of the compressive stress.
    pub mean_stress_pa: Vec<f64>,
    /// E_t*(−F/A), Pa.
    pub modulus_pa: Vec<f64>,
}

/// Why the integration stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error(
        "the profile columns differ in length (z_m {z}, area_m2 {area}, patches {patches}, \
         radius_m {radius})"
    )]
    Ragged {
        z: usize,
        area: usize,
        patches: usize,
        radius: usize,
    },
    #[error("the profile has no rows")]
    Empty,
    #[error("row {index}: {column} = {value} (must be finite and not negative)")]
    BadValue {
        index: usize,
        column: &'static str,
        value: f64,
    },
    #[error("rows {index} and {next}: z_m must decrease strictly, got {z_m} then {next_z_m}")]
    NotDecreasing {
        index: usize,
        next: usize,
        z_m: f64,
        next_z_m: f64,
    },
    #[error(
        "at level {index} (z = {z_m:.6e} m) the mean contact stress S = −F/A = \
         {stress_pa:.6e} Pa leaves the material's invertible range: {reason}"
    )]
    Modulus {
        index: usize,
        z_m: f64,
        stress_pa: f64,
        reason: String,
    },
    #[error("at level {index} (z = {z_m:.6e} m) the load is {load_n:.6e} N on zero contact area")]
    LoadWithoutArea { index: usize, z_m: f64, load_n: f64 },
}

/// Integrates the ICM. `modulus(S)` is E_t* at the (compressive, ≤ 0)
/// stress S, Pa; its error text is reported with the level.
pub fn solve(
    profile: ProfileSlices,
    scheme: Scheme,
    modulus: &mut dyn FnMut(f64) -> Result<f64, String>,
) -> Result<Solution, SolveError> {
    check(&profile)?;
    let ProfileSlices {
        z_m,
        area_m2,
        patches,
        radius_m,
    } = profile;
    let n = z_m.len();

    // E_t*(−F/A_k) with the level named on failure; (stress, modulus).
    let mut state = |k: usize, load_n: f64| -> Result<(f64, f64), SolveError> {
        let mean_stress_pa = if area_m2[k] > 0.0 {
            load_n / area_m2[k]
        } else if load_n == 0.0 {
            0.0
        } else {
            return Err(SolveError::LoadWithoutArea {
                index: k,
                z_m: z_m[k],
                load_n,
            });
        };
        let stress_pa = -mean_stress_pa;
        let e = modulus(stress_pa).map_err(|reason| SolveError::Modulus {
            index: k,
            z_m: z_m[k],
            stress_pa,
            reason,
        })?;
        Ok((mean_stress_pa, e))
    };
    // Interface stiffness 2 r N (times E_t*): zero where nothing touches.
    let shape = |k: usize| {
        if area_m2[k] > 0.0 && patches[k] > 0.0 {
            2.0 * radius_m[k] * patches[k]
        } else {
            0.0
        }
    };

    let mut out = Solution {
        load_n: Vec::with_capacity(n),
        mean_stress_pa: Vec::with_capacity(n),
        modulus_pa: Vec::with_capacity(n),
    };
    let mut load_n = 0.0;
    let (mut stress, mut e) = state(0, load_n)?;
    for k in 0..n {
        out.load_n.push(load_n);
        out.mean_stress_pa.push(stress);
        out.modulus_pa.push(e);
        if k + 1 == n {
            break;
        }
        let h = z_m[k] - z_m[k + 1];
        let slope = e * shape(k);
        let next = match scheme {
            Scheme::Euler => load_n + h * slope,
            Scheme::Heun => {
                let predicted = load_n + h * slope;
                let (_, e_end) = state(k + 1, predicted)?;
                load_n + 0.5 * h * (slope + e_end * shape(k + 1))
            }
        };
        load_n = next;
        (stress, e) = state(k + 1, load_n)?;
    }
    Ok(out)
}

fn check(p: &ProfileSlices) -> Result<(), SolveError> {
    let n = p.z_m.len();
    if [p.area_m2.len(), p.patches.len(), p.radius_m.len()]
        .iter()
        .any(|&l| l != n)
    {
        return Err(SolveError::Ragged {
            z: n,
            area: p.area_m2.len(),
            patches: p.patches.len(),
            radius: p.radius_m.len(),
        });
    }
    if n == 0 {
        return Err(SolveError::Empty);
    }
    for (column, values) in [
        ("area_m2", p.area_m2),
        ("patches", p.patches),
        ("radius_m", p.radius_m),
    ] {
        if let Some(index) = values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(SolveError::BadValue {
                index,
                column,
                value: values[index],
            });
        }
    }
    if let Some(index) = p.z_m.iter().position(|z| !z.is_finite()) {
        return Err(SolveError::BadValue {
            index,
            column: "z_m",
            value: p.z_m[index],
        });
    }
    if let Some(index) = p.z_m.windows(2).position(|w| w[1] >= w[0]) {
        return Err(SolveError::NotDecreasing {
            index,
            next: index + 1,
            z_m: p.z_m[index],
            next_z_m: p.z_m[index + 1],
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant(e: f64) -> impl FnMut(f64) -> Result<f64, String> {
        move |_| Ok(e)
    }

    #[test]
    fn flat_punch_gives_sneddons_load_exactly() {
        // A flat-topped cylinder of radius a: A = π a², N = 1 at every plane
        // above its base, so F = 2 E* a Δz (Sneddon) with either scheme.
        let a_m = 3e-4;
        let e_star = 7.16e6;
        let z_m: Vec<f64> = (0..=50).map(|k| 1e-5 * (50 - k) as f64 / 50.0).collect();
        let area = vec![std::f64::consts::PI * a_m * a_m; z_m.len()];
        let patches = vec![1.0; z_m.len()];
        let radius = vec![a_m; z_m.len()];
        let profile = ProfileSlices {
            z_m: &z_m,
            area_m2: &area,
            patches: &patches,
            radius_m: &radius,
        };
        for scheme in [Scheme::Euler, Scheme::Heun] {
            let s = solve(profile, scheme, &mut constant(e_star)).unwrap();
            for (k, f) in s.load_n.iter().enumerate() {
                let exact = 2.0 * e_star * a_m * (z_m[0] - z_m[k]);
                assert!(
                    (f - exact).abs() <= 1e-12 * exact.max(1e-30),
                    "{scheme:?} {k}"
                );
            }
        }
    }

    #[test]
    fn euler_and_heun_follow_their_formulas_on_a_growing_contact() {
        // Stiffness 2 r N = 2 k (k = level), modulus 1 + |S|: one step by hand.
        let z_m = [2.0, 1.0, 0.0];
        let area = [1.0, 2.0, 4.0];
        let patches = [1.0, 1.0, 1.0];
        let radius = [0.0, 1.0, 2.0];
        let p = ProfileSlices {
            z_m: &z_m,
            area_m2: &area,
            patches: &patches,
            radius_m: &radius,
        };
        let mut law = |s: f64| Ok(1.0 + s.abs());
        let euler = solve(p, Scheme::Euler, &mut law).unwrap();
        // F1 = 0 + 1·(1·0) = 0; F2 = 0 + 1·(1 + 0)·2 = 2.
        assert_eq!(euler.load_n, [0.0, 0.0, 2.0]);
        let heun = solve(p, Scheme::Heun, &mut law).unwrap();
        // Step 1: slope 0, predicted 0, end slope (1+0)·2 = 2 → F1 = 1.
        // Step 2: S1 = 1/2, slope 1.5·2 = 3, F̃ = 4, end slope (1+1)·4 = 8
        //         → F2 = 1 + (3 + 8)/2 = 6.5.
        assert_eq!(heun.load_n, [0.0, 1.0, 6.5]);
        assert_eq!(heun.mean_stress_pa, [0.0, 0.5, 1.625]);
        assert_eq!(heun.modulus_pa, [1.0, 1.5, 2.625]);
    }

    #[test]
    fn empty_planes_contribute_nothing() {
        let z_m = [3.0, 2.0, 1.0, 0.0];
        let area = [0.0, 0.0, 1.0, 1.0];
        let patches = [0.0, 0.0, 1.0, 1.0];
        let radius = [0.0, 0.0, 0.5, 0.5];
        let p = ProfileSlices {
            z_m: &z_m,
            area_m2: &area,
            patches: &patches,
            radius_m: &radius,
        };
        let s = solve(p, Scheme::Euler, &mut constant(2.0)).unwrap();
        assert_eq!(s.load_n, [0.0, 0.0, 0.0, 2.0]);
        assert_eq!(s.mean_stress_pa[0], 0.0);
    }

    #[test]
    fn failures_name_the_level_and_the_stress() {
        let z_m = [2.0, 1.0, 0.0];
        let area = [1.0, 1.0, 1.0];
        let ones = [1.0, 1.0, 1.0];
        let p = ProfileSlices {
            z_m: &z_m,
            area_m2: &area,
            patches: &ones,
            radius_m: &ones,
        };
        let mut law = |s: f64| {
            if s < -1.0 {
                Err("beyond −1 Pa".to_owned())
            } else {
                Ok(1.0)
            }
        };
        let e = solve(p, Scheme::Euler, &mut law).unwrap_err();
        assert!(
            matches!(e, SolveError::Modulus { index: 1, stress_pa, .. } if stress_pa == -2.0),
            "{e:?}"
        );
        let text = e.to_string();
        assert!(
            text.contains("level 1") && text.contains("z = 1") && text.contains("-2"),
            "{text}"
        );

        let bad_z = [1.0, 1.0, 0.0];
        let e = solve(
            ProfileSlices { z_m: &bad_z, ..p },
            Scheme::Euler,
            &mut constant(1.0),
        )
        .unwrap_err();
        assert!(matches!(e, SolveError::NotDecreasing { index: 0, .. }));
        let nan = [1.0, f64::NAN, 1.0];
        let e = solve(
            ProfileSlices {
                radius_m: &nan,
                ..p
            },
            Scheme::Euler,
            &mut constant(1.0),
        )
        .unwrap_err();
        assert!(e.to_string().contains("radius_m"), "{e}");
    }
}
