//! Spikes and outliers: isolated points of a height map far from their
//! neighbours (dust, a bad pixel, a lost fringe), set to NaN so that later
//! stages treat them as not measured.
//!
//! Local rule ([`remove_spikes`]): each point's height is estimated from
//! its neighbours along every direction v of the (2r + 1)² square (4
//! directions for 3 × 3, 12 for 5 × 5): by the mean of the two points ±v
//! about it, or where one of them is missing (an edge, a hole) by the
//! straight-line extrapolation 2 z(p + v) − z(p + 2v) from the other side
//! (for the 8 nearest directions only: longer ones extrapolate too far).
//! The deviation d = z − median(estimates) is kept where at least
//! `min_estimates` directions give one. A point is a spike if |d −
//! median(d)| > k·σ, σ = 1.4826·median|d − median(d)| over the whole map
//! (the MAD, scaled to the standard deviation for normal deviations;
//! Hampel's identifier, with the spread taken over the map). The rule is
//! Each point so flagged is a candidate, confirmed only if it still
//! deviates when its estimates are taken without the other candidates (a
//! point beside a spike deviates only through the estimates that spike
//! spoils). The neighbours of the confirmed spikes are then judged again
//! with those spikes set to NaN, and so on (same σ, up to [`PASSES`]
//! passes), so that spikes hidden by other spikes are found too.
//!
//! Why estimates along directions and not the median of the neighbours
//! themselves: on a sloped surface the neighbours' median is off by about
//! the slope times the spacing wherever the neighbourhood is not symmetric
//! (the map's edges, the neighbours of a hole or of a spike), while the
//! deviations inside are of second order (curvature times spacing²); on a
//! rough map with steep pixel-to-pixel slopes the plain median flagged
//! whole edges (146 false points on the 80 × 70 test map). The means of
//! opposite points and the extrapolations are exact for a plane, so d is of
//! second order everywhere.
//!
//! Why the spread over the map and not per window: with 8 neighbours the
//! window's own MAD is itself noisy (it is 0 whenever 5 of 9 heights
//! agree, as on quantised data, which would flag every other point), while
//! the deviations d of a smooth rough surface are, away from spikes, of one
//! scale across the map. Gwyddion's "mask of outliers" marks, as we
//! remember its user guide (not checked again here), the points beyond 3
//! standard deviations from the mean of the whole image, a σ that a few
//! large spikes inflate (they raise the threshold they are judged by); that
//! is the global rule [`remove_outliers`], made robust with the median and
//! MAD. SurfaceTopography has, as far as we know, no spike filter, and
//! MountainsMap's rule is not published; neither was checked here.

use ndarray::Array2;
use rayon::prelude::*;

/// 1.4826 = 1/Φ⁻¹(3/4): the MAD of normal data times this is its standard
/// deviation.
pub const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// Errors of the spike rules; each names the parameter or the map's problem.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SpikeError {
    #[error("{parameter} = {value}: {problem}")]
    Parameter {
        parameter: &'static str,
        value: String,
        problem: &'static str,
    },
    #[error(
        "the map's {what} have no spread (their median absolute deviation is 0: more than half \
         are equal, a synthetic or heavily quantised map), so no threshold k·σ can be set"
    )]
    NoSpread { what: &'static str },
    #[error("the map has no point with {needed} measured neighbours to judge")]
    NothingToJudge { needed: usize },
}

/// Passes of the local rule at most (each after setting the spikes found
/// so far to NaN).
pub const PASSES: usize = 4;

/// The local rule's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalRule {
    /// Threshold in robust standard deviations (default 5).
    pub k: f64,
    /// Half-width of the neighbourhood: 1 for 3 × 3, 2 for 5 × 5 (1..=3).
    pub radius: usize,
    /// Points with estimates from fewer directions are not judged (default 2).
    pub min_estimates: usize,
}

impl Default for LocalRule {
    fn default() -> Self {
        Self {
            k: 5.0,
            radius: 1,
            min_estimates: 2,
        }
    }
}

/// The map with its spikes (or outliers) set to NaN, and what was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Spikes {
    pub height_m: Array2<f64>,
    /// The points set to NaN, (i, j) in row-major order.
    pub points: Vec<(usize, usize)>,
    /// The robust standard deviation σ of the module doc, metres.
    pub sigma_m: f64,
    /// Points not judged (too few measured neighbours); 0 for the global rule.
    pub not_judged: usize,
    /// One line for the stage's note.
    pub description: String,
}

/// The median of `values` (the mean of the two middle ones for an even
/// count), reordering them; NaN if empty.
pub fn median(values: &mut [f64]) -> f64 {
    let n = values.len();
    if n == 0 {
        return f64::NAN;
    }
    let (lower, middle, _) = values.select_nth_unstable_by(n / 2, f64::total_cmp);
    let upper = *middle;
    if n % 2 == 1 {
        upper
    } else {
        let below = lower.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        below + (upper - below) / 2.0
    }
}

/// (median, σ = 1.4826 MAD) of `values`, reordering them.
fn robust_spread(values: &mut [f64]) -> (f64, f64) {
    let centre = median(values);
    values.iter_mut().for_each(|v| *v = (*v - centre).abs());
    (centre, MAD_TO_SIGMA * median(values))
}

fn check_k(k: f64) -> Result<(), SpikeError> {
    if k.is_finite() && k > 0.0 {
        Ok(())
    } else {
        Err(SpikeError::Parameter {
            parameter: "k",
            value: k.to_string(),
            problem: "the threshold must be finite and positive",
        })
    }
}

/// One of each pair ±v of the directions in the (2r + 1)² square.
fn directions(radius: usize) -> Vec<(isize, isize)> {
    let r = radius as isize;
    (0..=r)
        .flat_map(|a| (-r..=r).map(move |b| (a, b)))
        .filter(|&(a, b)| a > 0 || b > 0)
        .collect()
}

/// The estimate of z at (i, j) along ±v of the module doc, if it has one.
fn estimate(h: &Array2<f64>, (i, j): (usize, usize), (a, b): (isize, isize)) -> Option<f64> {
    let (nx, ny) = h.dim();
    let at = |k: isize| {
        let x = i.checked_add_signed(k * a).filter(|&x| x < nx)?;
        let y = j.checked_add_signed(k * b).filter(|&y| y < ny)?;
        Some(h[[x, y]]).filter(|z| !z.is_nan())
    };
    match (at(1), at(-1)) {
        (Some(up), Some(down)) => Some(up + (down - up) / 2.0),
        // Extrapolations only along the 8 nearest directions: along v = (2,
        // 2) it would reach 4√2 spacings and miss by 8 z'' spacings².
        _ if a.abs().max(b.abs()) > 1 => None,
        (Some(near), None) => at(2).map(|far| 2.0 * near - far),
        (None, Some(near)) => at(-2).map(|far| 2.0 * near - far),
        (None, None) => None,
    }
}

/// z − median of the estimates of (i, j) on `h` (where its own height
/// is not used), if at least `min_estimates` directions give one.
fn deviation_at(
    h: &Array2<f64>,
    z: f64,
    point: (usize, usize),
    dirs: &[(isize, isize)],
    min_estimates: usize,
    estimates: &mut Vec<f64>,
) -> Option<f64> {
    estimates.clear();
    estimates.extend(dirs.iter().filter_map(|&v| estimate(h, point, v)));
    (estimates.len() >= min_estimates).then(|| z - median(estimates))
}

/// [`deviation_at`] at every point (row-major); NaN where the point is not
/// measured or not judged.
fn deviations(h: &Array2<f64>, dirs: &[(isize, isize)], min_estimates: usize) -> Vec<f64> {
    let (nx, ny) = h.dim();
    let mut out = vec![f64::NAN; nx * ny];
    out.par_chunks_mut(ny.max(1))
        .enumerate()
        .for_each(|(i, row)| {
            let mut estimates = Vec::with_capacity(dirs.len());
            for (j, d) in row.iter_mut().enumerate() {
                let z = h[[i, j]];
                if !z.is_nan() {
                    let found = deviation_at(h, z, (i, j), dirs, min_estimates, &mut estimates);
                    *d = found.unwrap_or(f64::NAN);
                }
            }
        });
    out
}

/// The measured points of `h` for which `score` holds, in row-major order,
/// and `h` with them set to NaN.
fn flag(
    h: &Array2<f64>,
    score: impl Fn(usize, usize) -> bool,
) -> (Array2<f64>, Vec<(usize, usize)>) {
    let mut out = h.clone();
    let mut points = Vec::new();
    for ((i, j), v) in out.indexed_iter_mut() {
        if !v.is_nan() && score(i, j) {
            *v = f64::NAN;
            points.push((i, j));
        }
    }
    (out, points)
}

/// Lists up to 5 points, then how many more.
fn listed(points: &[(usize, usize)]) -> String {
    let mut s: Vec<String> = points
        .iter()
        .take(5)
        .map(|(i, j)| format!("({i}, {j})"))
        .collect();
    if points.len() > 5 {
        s.push(format!("… {} more", points.len() - 5));
    }
    s.join(", ")
}

/// The local rule of the module doc on `height_m` (axis 0 = x, NaN = not
/// measured).
pub fn remove_spikes(height_m: &Array2<f64>, rule: &LocalRule) -> Result<Spikes, SpikeError> {
    check_local(rule)?;
    let dirs = directions(rule.radius);
    let d = deviations(height_m, &dirs, rule.min_estimates);
    let mut judged: Vec<f64> = d.iter().copied().filter(|v| !v.is_nan()).collect();
    if judged.is_empty() {
        return Err(SpikeError::NothingToJudge {
            needed: rule.min_estimates,
        });
    }
    let judged_count = judged.len();
    let (centre, sigma_m) = robust_spread(&mut judged);
    if sigma_m.is_nan() || sigma_m <= 0.0 {
        return Err(SpikeError::NoSpread {
            what: "deviations from their neighbours' estimates",
        });
    }
    let ny = height_m.ncols();
    let is_spike = |d: f64| (d - centre).abs() > rule.k * sigma_m;
    let mut candidates: Vec<(usize, usize)> = height_m
        .indexed_iter()
        .filter(|&((i, j), _)| is_spike(d[i * ny + j]))
        .map(|(p, _)| p)
        .collect();
    let (mut out, mut points) = (height_m.clone(), Vec::new());
    let mut estimates = Vec::new();
    for _ in 0..PASSES {
        // A candidate is confirmed if it still deviates when judged without
        // the other candidates: a point beside a spike deviates only
        // through that spike's spoiled estimates.
        let mut others = out.clone();
        candidates.iter().for_each(|&p| others[p] = f64::NAN);
        let confirmed: Vec<(usize, usize)> = candidates
            .iter()
            .copied()
            .filter(|&p| {
                deviation_at(
                    &others,
                    height_m[p],
                    p,
                    &dirs,
                    rule.min_estimates,
                    &mut estimates,
                )
                .is_some_and(is_spike)
            })
            .collect();
        if confirmed.is_empty() {
            break;
        }
        confirmed.iter().for_each(|&p| out[p] = f64::NAN);
        points.extend(confirmed.iter().copied());
        // Next, the neighbours of the spikes found, judged without them.
        candidates = neighbours(out.dim(), &confirmed, rule.radius)
            .into_iter()
            .filter(|&p| {
                !out[p].is_nan()
                    && deviation_at(&out, out[p], p, &dirs, rule.min_estimates, &mut estimates)
                        .is_some_and(is_spike)
            })
            .collect();
    }
    points.sort_unstable();
    let measured = height_m.iter().filter(|v| !v.is_nan()).count();
    let not_judged = measured - judged_count;
    let description = local_description(rule, measured, &points, sigma_m, not_judged);
    Ok(Spikes {
        height_m: out,
        points,
        sigma_m,
        not_judged,
        description,
    })
}

/// The points within `radius` (in i and j) of `points`, each once, in
/// row-major order.
fn neighbours(
    (nx, ny): (usize, usize),
    points: &[(usize, usize)],
    radius: usize,
) -> Vec<(usize, usize)> {
    let mut near: Vec<(usize, usize)> = points
        .iter()
        .flat_map(|&(i, j)| {
            let rows = i.saturating_sub(radius)..(i + radius + 1).min(nx);
            rows.flat_map(move |a| {
                (j.saturating_sub(radius)..(j + radius + 1).min(ny)).map(move |b| (a, b))
            })
        })
        .collect();
    near.sort_unstable();
    near.dedup();
    near
}

fn check_local(rule: &LocalRule) -> Result<(), SpikeError> {
    check_k(rule.k)?;
    if !(1..=3).contains(&rule.radius) {
        return Err(SpikeError::Parameter {
            parameter: "radius",
            value: rule.radius.to_string(),
            problem: "the neighbourhood's half-width must be 1 (3 x 3), 2 (5 x 5) or 3 (7 x 7)",
        });
    }
    let most = directions(rule.radius).len();
    if !(1..=most).contains(&rule.min_estimates) {
        return Err(SpikeError::Parameter {
            parameter: "min_estimates",
            value: rule.min_estimates.to_string(),
            problem: "must be at least 1 and at most the neighbourhood's number of directions \
                      (4 for 3 x 3, 12 for 5 x 5, 24 for 7 x 7)",
        });
    }
    Ok(())
}

fn local_description(
    rule: &LocalRule,
    measured: usize,
    points: &[(usize, usize)],
    sigma_m: f64,
    not_judged: usize,
) -> String {
    let side = 2 * rule.radius + 1;
    let found = if points.is_empty() {
        String::new()
    } else {
        format!(": {}", listed(points))
    };
    let unjudged = if not_judged > 0 {
        format!(
            "; {not_judged} points with estimates from fewer than {} directions not judged",
            rule.min_estimates
        )
    } else {
        String::new()
    };
    format!(
        "spikes: {} of {measured} points set to NaN, deviating from their {side} × {side} \
         neighbours' estimate by more than {} × {sigma_m:.3e} m (1.4826 MAD){found}{unjudged}",
        points.len(),
        rule.k,
    )
}

/// The global rule: points with |z − median(z)| > k·1.4826·MAD(z) over the
/// whole map. Meant for a map whose form has been removed (on a tilted or
/// curved map it cuts the high and low ends of the form instead).
pub fn remove_outliers(height_m: &Array2<f64>, k: f64) -> Result<Spikes, SpikeError> {
    check_k(k)?;
    let mut measured: Vec<f64> = height_m.iter().copied().filter(|v| !v.is_nan()).collect();
    if measured.is_empty() {
        return Err(SpikeError::NothingToJudge { needed: 0 });
    }
    let count = measured.len();
    let (centre, sigma_m) = robust_spread(&mut measured);
    if sigma_m.is_nan() || sigma_m <= 0.0 {
        return Err(SpikeError::NoSpread { what: "heights" });
    }
    let limit = k * sigma_m;
    let (out, points) = flag(height_m, |i, j| (height_m[[i, j]] - centre).abs() > limit);
    let description = format!(
        "outliers: {} of {count} points set to NaN, farther than {k} × {sigma_m:.3e} m \
         (1.4826 MAD) from the median height{}",
        points.len(),
        if points.is_empty() {
            String::new()
        } else {
            format!(": {}", listed(&points))
        },
    );
    Ok(Spikes {
        height_m: out,
        points,
        sigma_m,
        not_judged: 0,
        description,
    })
}

#[cfg(test)]
mod tests;
