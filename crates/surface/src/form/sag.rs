//! A sphere, or a cylinder whose axis lies in the map's plane, fitted to
//! the measured points by least squares on the vertical residual
//! z − f(x, y).
//!
//! Both are written as the sag of a circle of signed curvature c = ±1/R
//! below its apex height h₀ (the optical-surface form, as in ISO 10110-12's
//! sag of a sphere):
//!
//!   f = h₀ − c·q / (1 + √(1 − c²q)),
//!
//! with q = (x − x₀)² + (y − y₀)² for a sphere of centre (x₀, y₀) and q = d²,
//! d the distance from the axis, for a cylinder. c > 0 is a cap (dome),
//! c < 0 a bowl. Unlike z₀ ± √(R² − q), this stays well conditioned as R
//! grows past the map's size (h₀ and c are nearly independent, where z₀ and
//! R move together) and becomes a plane smoothly as c → 0.
//!
//! The fit works in coordinates centred on the map and divided by L, half
//! the map's larger side (heights too, centred on their mean), so that the
//! parameters are of order one. It starts from an algebraic fit (Kåsa 1976:
//! the circle or sphere x² + y² + z² = A x + B y + C z + D, linear in A..D,
//! exact for points on a circle or sphere; the cylinder's axis direction,
//! when fitted, from the Hessian of a quadric's fit), then Levenberg–
//! Marquardt refines it on the vertical residual. The normal equations of
//! 3 or 4 parameters are summed in one pass over the map per iteration, so
//! the Jacobian (4 × 4 M values on 2048²) is never stored, as a
//! MINPACK-style solver would; the damping is Marquardt's (λ·diag(JᵀJ)).

use hypercontact_numeric::reduce;
use nalgebra::{DMatrix, DVector};
use ndarray::Array2;

use super::{Form, FormError, FormRemoval, check_map, length, subtract};

/// Which way a sphere or cylinder curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cap {
    /// Convex upwards (a dome, c > 0): the apex is the highest point.
    Up,
    /// Concave (a bowl, c < 0): the apex is the lowest point.
    Down,
}

/// A fitted sphere, metres; x, y from the map's first point.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    pub radius_m: f64,
    pub cap: Cap,
    pub centre_x_m: f64,
    pub centre_y_m: f64,
    /// Height of the sphere's centre: apex_z_m − R (cap up) or + R (down).
    pub centre_z_m: f64,
    /// Height of the point of the sphere above (or below) its centre.
    pub apex_z_m: f64,
}

impl Form for Sphere {
    fn name(&self) -> String {
        format!("sphere R = {}", length(self.radius_m))
    }
}

/// The cylinder's axis direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CylinderAxis {
    /// Along x (axis 0): the cylinder curves along y.
    X,
    /// Along y.
    Y,
    /// At the in-plane angle that fits best.
    Fitted,
}

/// A fitted cylinder with its axis in the plane of the map, metres.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    pub radius_m: f64,
    pub cap: Cap,
    /// Angle of the axis from the x axis towards y, in (−π/2, π/2].
    pub axis_angle_rad: f64,
    /// The point of the axis nearest the map's centre, projected on the map
    /// (x, y from its first point).
    pub axis_x_m: f64,
    pub axis_y_m: f64,
    /// Height of the cylinder's crest (cap up) or trough (down) line.
    pub apex_z_m: f64,
}

impl Form for Cylinder {
    fn name(&self) -> String {
        format!(
            "cylinder R = {} (axis at {:.2}° to x)",
            length(self.radius_m),
            self.axis_angle_rad.to_degrees()
        )
    }
}

/// Sag s = c q / (1 + g), g = √(1 − c²q), with ∂s/∂c = q/(g(1 + g)) and
/// ∂s/∂q = c/(2g); None where c²q ≥ 1 (beyond the circle's edge).
fn sag(c: f64, q: f64) -> Option<(f64, f64, f64)> {
    let g2 = 1.0 - c * c * q;
    if g2.is_nan() || g2 <= 0.0 {
        return None;
    }
    let g = g2.sqrt();
    Some((c * q / (1.0 + g), q / (g * (1.0 + g)), c / (2.0 * g)))
}

/// The map in the fit's coordinates X = (i dx − x_c)/L, Y = (j dy − y_c)/L,
/// Z = (z − z_c)/L.
struct Frame<'a> {
    h: &'a Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    x_centre_m: f64,
    y_centre_m: f64,
    z_centre_m: f64,
    scale_m: f64,
}

impl<'a> Frame<'a> {
    fn new(h: &'a Array2<f64>, dx_m: f64, dy_m: f64) -> Self {
        let (nx, ny) = h.dim();
        let (x_centre_m, y_centre_m) = ((nx - 1) as f64 * dx_m / 2.0, (ny - 1) as f64 * dy_m / 2.0);
        let [n, sum] = reduce::sums(nx * ny, |k| {
            let z = h[[k / ny, k % ny]];
            if z.is_nan() { [0.0, 0.0] } else { [1.0, z] }
        });
        Frame {
            h,
            dx_m,
            dy_m,
            x_centre_m,
            y_centre_m,
            z_centre_m: sum / n.max(1.0),
            scale_m: x_centre_m.max(y_centre_m),
        }
    }

    fn x(&self, i: usize) -> f64 {
        (i as f64 * self.dx_m - self.x_centre_m) / self.scale_m
    }

    fn y(&self, j: usize) -> f64 {
        (j as f64 * self.dy_m - self.y_centre_m) / self.scale_m
    }

    /// `n` sums of `add(X, Y, Z, sums)` over the measured points, rows
    /// summed left to right and merged in the fixed tree of `reduce`.
    fn sums(&self, n: usize, add: impl Fn(f64, f64, f64, &mut [f64]) + Sync) -> Vec<f64> {
        reduce::reduce(
            self.h.nrows(),
            || vec![0.0; n],
            |i| {
                let mut out = vec![0.0; n];
                let x = self.x(i);
                for (j, &z) in self.h.row(i).iter().enumerate() {
                    if !z.is_nan() {
                        add(x, self.y(j), (z - self.z_centre_m) / self.scale_m, &mut out);
                    }
                }
                out
            },
            reduce::add_into,
        )
    }

    /// Least squares of target ≈ Σ_k a_k basis_k over the measured points,
    /// `point` giving (basis, target); columns are equilibrated (scaled to
    /// a unit diagonal) before the SVD so a small column (heights of a
    /// shallow cap) is not taken for rank deficiency. None if the points
    /// do not determine the K coefficients.
    fn linear_fit<const K: usize>(
        &self,
        point: impl Fn(f64, f64, f64) -> ([f64; K], f64) + Sync,
    ) -> Option<[f64; K]> {
        let sums = self.sums(K * K + K, |x, y, z, out| {
            let (basis, target) = point(x, y, z);
            for k in 0..K {
                out[K * K + k] += basis[k] * target;
                for l in 0..K {
                    out[k * K + l] += basis[k] * basis[l];
                }
            }
        });
        let scale: [f64; K] = std::array::from_fn(|k| sums[k * K + k].sqrt());
        if scale.iter().any(|s| s.is_nan() || *s <= 0.0) {
            return None;
        }
        let gram = DMatrix::from_fn(K, K, |k, l| sums[k * K + l] / (scale[k] * scale[l]));
        let rhs = DVector::from_fn(K, |k, _| sums[K * K + k] / scale[k]);
        let svd = gram.svd(true, true);
        let (smallest, largest) = (svd.singular_values.min(), svd.singular_values.max());
        if smallest.is_nan() || smallest <= 1e-13 * largest {
            return None;
        }
        let a = svd.solve(&rhs, 0.0).ok()?;
        let a: [f64; K] = std::array::from_fn(|k| a[k] / scale[k]);
        a.iter().all(|v| v.is_finite()).then_some(a)
    }
}

/// Longest Levenberg–Marquardt run (each iteration is one pass over the map).
const MAX_ITERATIONS: usize = 200;

/// Minimises Σ (Z − model(p, X, Y))² from `start`. `model` gives the value
/// and its gradient in p, or None outside its domain (a trial step that
/// puts any point there is refused like one that raises the cost). Ends
/// when a step changes no parameter by more than 1e-14 (the coordinates
/// are of order one), or when no step lowers the cost any more (λ beyond
/// 1e12: at the minimum to rounding).
fn levenberg_marquardt<const P: usize>(
    frame: &Frame,
    start: [f64; P],
    model: impl Fn(&[f64; P], f64, f64) -> Option<(f64, [f64; P])> + Sync,
) -> Result<[f64; P], usize> {
    let normal_equations = |p: &[f64; P]| {
        let sums = frame.sums(P * P + P + 2, |x, y, z, out| match model(p, x, y) {
            Some((f, grad)) => {
                let r = z - f;
                for k in 0..P {
                    out[P * P + k] += grad[k] * r;
                    for l in k..P {
                        out[k * P + l] += grad[k] * grad[l];
                    }
                }
                out[P * P + P] += r * r;
            }
            None => out[P * P + P + 1] += 1.0,
        });
        (sums[P * P + P + 1] == 0.0).then(|| {
            let jtj = DMatrix::from_fn(P, P, |k, l| sums[k.min(l) * P + k.max(l)]);
            let jtr = DVector::from_fn(P, |k, _| sums[P * P + k]);
            (jtj, jtr, sums[P * P + P])
        })
    };
    let mut p = start;
    let Some(mut current) = normal_equations(&p) else {
        return Err(0);
    };
    let mut lambda = 1e-3;
    for _ in 0..MAX_ITERATIONS {
        let (jtj, jtr, cost) = &current;
        let mut damped = jtj.clone();
        for k in 0..P {
            damped[(k, k)] += lambda * jtj[(k, k)];
        }
        let step = damped.cholesky().map(|c| c.solve(jtr));
        let trial = step.map(|s| std::array::from_fn::<f64, P, _>(|k| p[k] + s[k]));
        let accepted = trial.and_then(|t| {
            let next = normal_equations(&t)?;
            (next.2 <= *cost).then_some((t, next))
        });
        match accepted {
            Some((t, next)) => {
                let largest_step = (0..P).map(|k| (t[k] - p[k]).abs()).fold(0.0, f64::max);
                p = t;
                current = next;
                lambda = (lambda / 10.0).max(1e-12);
                if largest_step <= 1e-14 {
                    return Ok(p);
                }
            }
            None => {
                lambda *= 10.0;
                if lambda > 1e12 {
                    return Ok(p);
                }
            }
        }
    }
    Err(MAX_ITERATIONS)
}

fn too_few(form: &str, needed: usize, found: usize) -> Result<(), FormError> {
    if found < needed {
        return Err(FormError::TooFewPoints {
            form: form.into(),
            needed,
            found,
        });
    }
    Ok(())
}

fn no_convergence(form: &str) -> impl Fn(usize) -> FormError + '_ {
    move |iterations| {
        if iterations == 0 {
            FormError::Degenerate {
                form: form.into(),
                why: "the algebraic start puts measured points beyond the circle's edge; the map \
                      is not this shape"
                    .into(),
            }
        } else {
            FormError::NoConvergence {
                form: form.into(),
                iterations,
            }
        }
    }
}

/// Fits a sphere to the measured points of `height_m` (axis 0 = x,
/// spacings `dx_m`, `dy_m`) and subtracts it.
pub fn remove_sphere(
    height_m: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
) -> Result<FormRemoval<Sphere>, FormError> {
    let measured = check_map(height_m, dx_m, dy_m)?;
    too_few("sphere", 5, measured)?;
    let frame = Frame::new(height_m, dx_m, dy_m);
    let flat = || FormError::Degenerate {
        form: "sphere".into(),
        why: "the measured points fit no sphere (a plane, or points on one line?)".into(),
    };
    // Kåsa: X² + Y² + Z² = A X + B Y + C Z + D, centre (A, B, C)/2.
    let [a, b, c, d] = frame
        .linear_fit(|x, y, z| ([x, y, z, 1.0], x * x + y * y + z * z))
        .ok_or_else(flat)?;
    let (x0, y0, z0) = (a / 2.0, b / 2.0, c / 2.0);
    let radius = (d + x0 * x0 + y0 * y0 + z0 * z0).sqrt();
    if !(radius.is_finite() && radius > 0.0) {
        return Err(flat());
    }
    // The data's mean height is 0 in the frame: a centre below it is a cap.
    let curvature = if z0 < 0.0 {
        1.0 / radius
    } else {
        -1.0 / radius
    };
    let start = [z0 + curvature.signum() * radius, x0, y0, curvature];
    let model = |p: &[f64; 4], x: f64, y: f64| {
        let (u, v) = (x - p[1], y - p[2]);
        let (s, ds_dc, ds_dq) = sag(p[3], u * u + v * v)?;
        Some((p[0] - s, [1.0, 2.0 * u * ds_dq, 2.0 * v * ds_dq, -ds_dc]))
    };
    let p = levenberg_marquardt(&frame, start, model).map_err(no_convergence("sphere"))?;
    let (l, curvature) = (frame.scale_m, p[3]);
    let apex_z_m = frame.z_centre_m + l * p[0];
    let radius_m = l / curvature.abs();
    let sphere = Sphere {
        radius_m,
        cap: if curvature > 0.0 { Cap::Up } else { Cap::Down },
        centre_x_m: frame.x_centre_m + l * p[1],
        centre_y_m: frame.y_centre_m + l * p[2],
        centre_z_m: apex_z_m - curvature.signum() * radius_m,
        apex_z_m,
    };
    let value = |i: usize, j: usize| {
        let f = model(&p, frame.x(i), frame.y(j)).map_or(f64::NAN, |(f, _)| f);
        frame.z_centre_m + l * f
    };
    let (residual_m, points, removed_rms_m, residual_rms_m) =
        subtract(height_m, frame.z_centre_m, value);
    Ok(FormRemoval {
        residual_m,
        form: sphere,
        points,
        removed_rms_m,
        residual_rms_m,
    })
}

/// Fits a cylinder with its axis in the plane of the map (along x, along y
/// or at the angle that fits best) to the measured points of `height_m` and
/// subtracts it.
pub fn remove_cylinder(
    height_m: &Array2<f64>,
    dx_m: f64,
    dy_m: f64,
    axis: CylinderAxis,
) -> Result<FormRemoval<Cylinder>, FormError> {
    let measured = check_map(height_m, dx_m, dy_m)?;
    too_few("cylinder", 6, measured)?;
    let frame = Frame::new(height_m, dx_m, dy_m);
    let flat = || FormError::Degenerate {
        form: "cylinder".into(),
        why: "the measured points fit no cylinder (a plane, or no curvature across the axis?)"
            .into(),
    };
    let angle = match axis {
        CylinderAxis::X => 0.0,
        CylinderAxis::Y => std::f64::consts::FRAC_PI_2,
        CylinderAxis::Fitted => axis_angle(&frame).ok_or_else(flat)?,
    };
    // Kåsa in the plane across the axis: D² + Z² = A D + B Z + C, with D the
    // signed distance from the line through the map's centre along the axis.
    let (sin0, cos0) = angle.sin_cos();
    let [a, b, c] = frame
        .linear_fit(|x, y, z| {
            let d = -x * sin0 + y * cos0;
            ([d, z, 1.0], d * d + z * z)
        })
        .ok_or_else(flat)?;
    let (d0, z0) = (a / 2.0, b / 2.0);
    let radius = (c + d0 * d0 + z0 * z0).sqrt();
    if !(radius.is_finite() && radius > 0.0) {
        return Err(flat());
    }
    let curvature = if z0 < 0.0 {
        1.0 / radius
    } else {
        -1.0 / radius
    };
    let h0 = z0 + curvature.signum() * radius;
    // p = [h₀, d₀, c] with the angle fixed, [h₀, d₀, c, θ] when fitted.
    let fixed = |p: &[f64; 3], x: f64, y: f64| {
        let d = -x * sin0 + y * cos0 - p[1];
        let (s, ds_dc, ds_dq) = sag(p[2], d * d)?;
        Some((p[0] - s, [1.0, 2.0 * d * ds_dq, -ds_dc]))
    };
    let free = |p: &[f64; 4], x: f64, y: f64| {
        let (sin, cos) = p[3].sin_cos();
        let d = -x * sin + y * cos - p[1];
        let (s, ds_dc, ds_dq) = sag(p[2], d * d)?;
        let g = 2.0 * d * ds_dq;
        Some((p[0] - s, [1.0, g, -ds_dc, g * (x * cos + y * sin)]))
    };
    let p = match axis {
        CylinderAxis::Fitted => levenberg_marquardt(&frame, [h0, d0, curvature, angle], free),
        _ => levenberg_marquardt(&frame, [h0, d0, curvature], fixed)
            .map(|p| [p[0], p[1], p[2], angle]),
    }
    .map_err(no_convergence("cylinder"))?;
    let value = |i: usize, j: usize| {
        let f = free(&p, frame.x(i), frame.y(j)).map_or(f64::NAN, |(f, _)| f);
        frame.z_centre_m + frame.scale_m * f
    };
    let (residual_m, points, removed_rms_m, residual_rms_m) =
        subtract(height_m, frame.z_centre_m, value);
    Ok(FormRemoval {
        residual_m,
        form: cylinder_of(&frame, p),
        points,
        removed_rms_m,
        residual_rms_m,
    })
}

/// The cylinder in metres from the fit's [h₀, d₀, c, θ].
fn cylinder_of(frame: &Frame, [h0, d0, curvature, angle]: [f64; 4]) -> Cylinder {
    let l = frame.scale_m;
    // The axis is the line −X sin θ + Y cos θ = d₀; θ and θ + π are one axis
    // with d₀ of opposite sign.
    let pi = std::f64::consts::PI;
    let turns = (angle / pi).round();
    let (mut angle, mut d0) = (angle - turns * pi, d0);
    if turns % 2.0 != 0.0 {
        d0 = -d0;
    }
    if angle <= -pi / 2.0 {
        angle += pi;
        d0 = -d0;
    }
    let (sin, cos) = angle.sin_cos();
    Cylinder {
        radius_m: l / curvature.abs(),
        cap: if curvature > 0.0 { Cap::Up } else { Cap::Down },
        axis_angle_rad: angle,
        axis_x_m: frame.x_centre_m - l * d0 * sin,
        axis_y_m: frame.y_centre_m + l * d0 * cos,
        apex_z_m: frame.z_centre_m + l * h0,
    }
}

/// The axis direction of a cylinder-like map: the quadric Z ≈ a + bX + cY +
/// eX² + fXY + gY² is fitted, and the axis is the eigenvector of its
/// Hessian [[2e, f], [f, 2g]] with the smaller curvature in magnitude (a
/// cylinder does not curve along its axis). None without curvature.
fn axis_angle(frame: &Frame) -> Option<f64> {
    let [_, _, _, e, f, g] = frame.linear_fit(|x, y, z| ([1.0, x, y, x * x, x * y, y * y], z))?;
    // Eigenvalues of the symmetric [[2e, f], [f, 2g]].
    let (mean, half_gap) = (e + g, ((e - g).powi(2) + f * f).sqrt());
    if !(half_gap > 0.0 || mean != 0.0) {
        return None;
    }
    let small = if mean >= 0.0 {
        mean - half_gap
    } else {
        mean + half_gap
    };
    // (2e − λ) v_x + f v_y = 0 → v ∝ (f, λ − 2e), or from the other row.
    let (vx, vy) = if (small - 2.0 * e).abs() + f.abs() > (small - 2.0 * g).abs() + f.abs() {
        (f, small - 2.0 * e)
    } else {
        (small - 2.0 * g, f)
    };
    Some(vy.atan2(vx))
}
