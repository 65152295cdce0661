//! The sample against the glass at a sequence of penetrations: one
//! boundary-element solve per frame (crate `hypercontact-bem`), each
//! warm-started from the last two frames' pressures, and the force with the
//! paper's tangent modulus on the coupled contact (as the `bem` stage
//! computes it), so the synthetic experiment and the `bem` model share one
//! physics.

use hypercontact_bem::curve::warm_start;
use hypercontact_bem::{Control, CurveOptions, Problem, SolverOptions, solve_curve};
use hypercontact_icm::tangent::integrate;
use hypercontact_icm::{CompositeModulus, Scheme};

/// The contact at one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameContact {
    /// Rigid-plane penetration from first contact (≤ 0: not touching), m.
    pub penetration_m: f64,
    /// Gap per point of the solve grid, m (NaN where not measured);
    /// row-major with axis 0 = x, as the height map.
    pub gap_m: Vec<f64>,
    /// Points in contact (p > 0).
    pub contact_points: usize,
    /// p > 0 per point of the solve grid, row-major as `gap_m`.
    pub in_contact: Vec<bool>,
    /// Contact points / measured points.
    pub area_fraction: f64,
    /// Total load, N.
    pub force_n: f64,
}

/// Why the sequence could not be solved.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    #[error("the height map cannot be a contact problem: {0}")]
    Problem(String),
    #[error("penetrations must increase: {previous_m:e} m then {next_m:e} m (frame {frame})")]
    NotIncreasing {
        frame: usize,
        previous_m: f64,
        next_m: f64,
    },
    #[error("frame {frame} (penetration {penetration_m:e} m): {cause}")]
    Solve {
        frame: usize,
        penetration_m: f64,
        cause: String,
    },
    #[error("the force: {0}")]
    Force(String),
}

/// The rigid-plane penetration at which the contact first covers
/// `area_fraction` of the measured points (within a few per cent above it:
/// the `bem` stage's curve search, two steps), m.
pub fn penetration_at_m(
    problem: &Problem,
    solver: SolverOptions,
    area_fraction: f64,
) -> Result<f64, ContactError> {
    let options = CurveOptions {
        steps: 2,
        max_area_fraction: area_fraction,
        solver,
    };
    let rows =
        solve_curve(problem, options, &mut |_, _, _| {}).map_err(|e| ContactError::Solve {
            frame: 0,
            penetration_m: e.approach_m,
            cause: format!("finding the penetration for A/A0 = {area_fraction}: {e}"),
        })?;
    Ok(rows.last().map_or(0.0, |r| r.approach_m))
}

/// Solves every frame's contact on `problem` (a grid of cells of
/// `pixel_m2`). `penetrations_m` increase; frames at or below 0 have no
/// contact (their gap is the plane's height above the surface).
/// `on_frame(k)` is called as frame k is done.
pub fn contact_sequence(
    problem: &Problem,
    pixel_m2: f64,
    modulus: &CompositeModulus,
    scheme: Scheme,
    solver: SolverOptions,
    penetrations_m: &[f64],
    on_frame: &mut dyn FnMut(usize),
) -> Result<Vec<FrameContact>, ContactError> {
    for (k, w) in penetrations_m.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(ContactError::NotIncreasing {
                frame: k + 1,
                previous_m: w[0],
                next_m: w[1],
            });
        }
    }
    let h = problem.heights_m();
    let measured = problem.measured() as f64;
    let top_m = problem.top_m();

    let mut frames = Vec::with_capacity(penetrations_m.len());
    // f = F/E* and A per frame, with a first-contact row in front for the
    // tangent-modulus integral (F = 0 there).
    let mut unit_load_m2 = vec![0.0];
    let mut area_m2 = vec![0.0];
    // The last two solves (penetration, pressure), most recent last: the
    // next one starts from their extrapolation, as the `bem` stage's steps.
    let mut recent: Vec<(f64, Vec<f64>)> = Vec::with_capacity(2);
    for (k, &delta) in penetrations_m.iter().enumerate() {
        if delta <= 0.0 {
            let plane = top_m - delta;
            frames.push(FrameContact {
                penetration_m: delta,
                // unmeasured points (−∞ in the problem) have no gap: NaN
                gap_m: h
                    .iter()
                    .map(|&z| if z.is_finite() { plane - z } else { f64::NAN })
                    .collect(),
                contact_points: 0,
                in_contact: vec![false; h.len()],
                area_fraction: 0.0,
                force_n: 0.0,
            });
            on_frame(k);
            continue;
        }
        let s = problem
            .solve(
                Control::Approach(delta),
                solver,
                warm_start(&recent, delta).as_deref(),
            )
            .map_err(|e| ContactError::Solve {
                frame: k,
                penetration_m: delta,
                cause: e.to_string(),
            })?;
        unit_load_m2.push(s.mean_pressure * measured * pixel_m2);
        area_m2.push(s.contact_pixels as f64 * pixel_m2);
        frames.push(FrameContact {
            penetration_m: delta,
            gap_m: s.gap_m,
            in_contact: s.pressure.iter().map(|p| *p > 0.0).collect(),
            contact_points: s.contact_pixels,
            area_fraction: s.contact_pixels as f64 / measured,
            force_n: 0.0,
        });
        if recent.len() == 2 {
            recent.remove(0);
        }
        recent.push((delta, s.pressure));
        on_frame(k);
    }
    let load = integrate(&unit_load_m2, &area_m2, scheme, &mut |stress| {
        modulus.at_stress_pa(stress).map_err(|e| e.to_string())
    })
    .map_err(|e| ContactError::Force(e.to_string()))?;
    // The touching frames are the last ones, in order, after the first row.
    let touching = frames.iter().filter(|f| f.penetration_m > 0.0).count();
    let first = frames.len() - touching;
    for (frame, force) in frames[first..].iter_mut().zip(&load.load_n[1..]) {
        frame.force_n = *force;
    }
    Ok(frames)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_bem::{Boundary, Influence};
    use hypercontact_core::Field;
    use hypercontact_icm::Model;
    use hypercontact_material::{Ogden, Poisson};
    use ndarray::Array2;
    use std::sync::Arc;

    /// A paraboloid cap (R = 2 mm) on a 64² grid of 5 µm.
    fn sphere() -> Field {
        let (n, d, radius) = (64, 5e-6, 2e-3);
        let h = Array2::from_shape_fn((n, n), |(i, j)| {
            let x = (i as f64 - 31.5) * d;
            let y = (j as f64 - 31.5) * d;
            -(x * x + y * y) / (2.0 * radius)
        });
        Field::new(h, d, d).unwrap()
    }

    fn modulus(model: Model) -> CompositeModulus {
        let neo = Ogden::new(vec![0.5e6], vec![2.0]).unwrap();
        CompositeModulus::new(Arc::new(neo), model, Poisson::INCOMPRESSIBLE.0).unwrap()
    }

    /// The sphere's frames at `deltas` under `model`.
    fn sequence(model: Model, deltas: &[f64]) -> Result<Vec<FrameContact>, ContactError> {
        let field = sphere();
        let heights: Vec<f64> = field.values.iter().copied().collect();
        let influence = Influence::new(64, 64, field.dx_m, field.dy_m, Boundary::Free);
        let problem = Problem::new(&influence, &heights).unwrap();
        contact_sequence(
            &problem,
            field.dx_m * field.dy_m,
            &modulus(model),
            Scheme::Heun,
            SolverOptions::default(),
            deltas,
            &mut |_| {},
        )
    }

    #[test]
    fn frames_before_contact_are_open_and_loads_grow_with_penetration() {
        let deltas = [-1e-6, 0.0, 0.5e-6, 1e-6, 2e-6];
        let frames = sequence(Model::Linear, &deltas).unwrap();
        assert_eq!(frames[0].contact_points, 0);
        assert!(frames[0].gap_m.iter().all(|g| *g >= 1e-6 - 1e-15));
        for w in frames[2..].windows(2) {
            assert!(w[1].force_n > w[0].force_n && w[1].contact_points > w[0].contact_points);
        }
        // Hertz: F = (4/3) E* √R δ^1.5; neo-Hookean μ0 = 0.5 MPa, E0 = 2 μ0 (1 + ν)
        // = 1.5 MPa, E0* = E0 / (1 − ν²) = 2 MPa at ν = ½; within the grid's
        // discretisation (a ≈ 89 µm ≈ 18 pixels at δ = 2 µm).
        let hertz = 4.0 / 3.0 * 2e6 * 2e-3f64.sqrt() * 2e-6f64.powf(1.5);
        assert!(
            (frames[4].force_n / hertz - 1.0).abs() < 0.05,
            "{} vs {hertz}",
            frames[4].force_n
        );
        // Contact gaps are zero (to the solver tolerance: far below 0.1 nm).
        let last = &frames[4];
        assert!(last.gap_m.iter().filter(|g| g.abs() < 1e-10).count() >= last.contact_points);
    }

    #[test]
    fn hyperelastic_needs_more_force_and_penetrations_must_increase() {
        let deltas = [0.5e-6, 1e-6, 2e-6];
        let run = |model| sequence(model, &deltas).unwrap();
        let (linear, hyper) = (run(Model::Linear), run(Model::Hyperelastic));
        for (l, h) in linear.iter().zip(&hyper) {
            // Same contact set (linear half-space), E_t*/E0* ≥ 2 from first contact.
            assert_eq!(l.contact_points, h.contact_points);
            assert!(
                h.force_n > 1.9 * l.force_n,
                "{} vs {}",
                h.force_n,
                l.force_n
            );
        }
        let e = sequence(Model::Linear, &[1e-6, 1e-6]).unwrap_err();
        assert!(e.to_string().contains("must increase"), "{e}");
    }
}
