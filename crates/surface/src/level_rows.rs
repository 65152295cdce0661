//! Scan-line levelling: a scanning instrument (an AFM, a stylus or
//! confocal line scanner) measures a map line by line along its fast
//! axis, and each line may come out shifted or tilted against its
//! neighbours (drift, a tip change, the feedback settling), which shows as
//! streaks along the fast axis. Each line is levelled on its own here; the
//! methods are those the Gwyddion user guide lists under "Align Rows"
//! (Data Process → Correct Data): Median, Polynomial (degree 0 being the
//! mean, 1 the tilt) and Median difference (its Modus, Matching and Trimmed
//! mean are not offered).
//!
//! - [`LineModel::Median`], [`LineModel::Mean`]: the line's median or mean
//!   height over its measured points is subtracted;
//! - [`LineModel::Polynomial`]: the least-squares polynomial of the given
//!   degree in the position along the line, in Legendre polynomials
//!   P_0 … P_d of t = (i − c)/c, c = (n − 1)/2, i = 0 … n − 1 the point's
//!   index along the line (so t runs over [−1, 1] whatever is measured),
//!   fitted to the measured points by nalgebra's SVD of the design matrix
//!   (not the normal equations, so a line measured over a short stretch
//!   keeps its accuracy) and subtracted;
//! - [`LineModel::MedianDifferences`]: lines are shifted so that the median
//!   of the height differences between a line and the one before it
//!   (over the points measured in both) is zero; the shifts accumulate
//!   from the first measured line, and are then all moved by their median
//!   so that the typical line keeps its height. It leaves a feature that
//!   spans many lines (a step, a particle) in place where a line's own
//!   median would be pulled by it.
//!
//! NaN points (not measured, masked, spikes) take no part in any line's
//! fit and stay NaN. A line with no more measured points than its model
//! has unknowns (one for a median or a mean, d + 1 for a polynomial of
//! degree d), which the fit would set to zero whatever they were, is left
//! as is and counted; so is, for median differences, a line without a
//! point measured both in it and in the line it is compared to. Lines of a
//! single point, or of no more points than a polynomial's terms, are
//! refused outright: every line would come out zero.
//!
//! Lines are independent (the median differences excepted, which are
//! accumulated in line order), each computed in a fixed order, and the
//! statistics are summed line by line in order: the result is the same
//! bits on any number of threads.

use nalgebra::{DMatrix, DVector};
use ndarray::{Array2, ArrayView1, Axis as NdAxis};
use rayon::prelude::*;

use crate::form::polynomial::legendre;
use crate::spikes::median;

/// Highest polynomial degree of a line fit.
pub const MAX_DEGREE: usize = 6;

/// The map's axis along which each scan line runs (the fast axis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Lines along x (array axis 0): line j is `h[.., j]`.
    X,
    /// Lines along y (array axis 1): line i is `h[i, ..]`.
    Y,
}

impl Axis {
    /// `x` or `y`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
        }
    }
}

/// What is subtracted from each line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineModel {
    Median,
    Mean,
    Polynomial { degree: usize },
    MedianDifferences,
}

impl LineModel {
    /// The measured points a line needs to be levelled: more than the
    /// model's unknowns, or one shared with the line before for median
    /// differences (whose shift the other line sets).
    pub fn min_points(self) -> usize {
        match self {
            LineModel::Polynomial { degree } => degree + 2,
            LineModel::Median | LineModel::Mean => 2,
            LineModel::MedianDifferences => 1,
        }
    }

    /// The shortest scan line (points along the fast axis) that levelling
    /// leaves more than zeros on.
    pub fn min_line_points(self) -> usize {
        self.min_points().max(2)
    }

    /// For a note: `median`, `polynomial of degree 2`, …
    pub fn name(self) -> String {
        match self {
            LineModel::Median => "median".into(),
            LineModel::Mean => "mean".into(),
            LineModel::Polynomial { degree: 1 } => "least-squares tilt".into(),
            LineModel::Polynomial { degree } => {
                format!("least-squares polynomial of degree {degree}")
            }
            LineModel::MedianDifferences => "median of differences to the line before".into(),
        }
    }
}

/// Errors of scan-line levelling; each says what is wrong with the input.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LevelRowsError {
    #[error("degree = {degree}: a scan line's polynomial degree must be 0 to {MAX_DEGREE}")]
    Degree { degree: usize },
    #[error(
        "the scan lines along {axis} have {points} point(s) each, and a {model} per line \
         needs at least {needed} to leave anything but zeros: is the fast axis {other}?"
    )]
    LinesTooShort {
        axis: &'static str,
        other: &'static str,
        points: usize,
        model: String,
        needed: usize,
    },
    #[error("height at point ({i}, {j}) is {value}: heights must be finite or NaN (not measured)")]
    NotFinite { i: usize, j: usize, value: f64 },
    #[error(
        "the levelled height at point ({i}, {j}) is {value}: the heights (of order {height:e}) \
         overflow a line's fit"
    )]
    Overflow {
        i: usize,
        j: usize,
        value: f64,
        height: f64,
    },
}

/// A map with its scan lines levelled, and what was removed.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelledRows {
    /// The levelled heights, metres; NaN where the input is NaN.
    pub height_m: Array2<f64>,
    /// Lines levelled.
    pub levelled: usize,
    /// Lines with a measured point but fewer than the model needs, left as is.
    pub left_as_is: usize,
    /// Lines with no measured point.
    pub empty: usize,
    /// Rms about its mean of what was subtracted, over the measured points
    /// (its mean, one height for the whole map, is not a line artefact).
    pub removed_rms_m: f64,
    /// Largest |subtracted − its mean| over the measured points.
    pub removed_max_m: f64,
    /// Rms of the levelled map about its mean over the measured points.
    pub residual_rms_m: f64,
}

/// What is subtracted from one line: a height, or one value per point.
#[derive(Clone, Debug, PartialEq)]
enum Removed {
    Offset(f64),
    Values(Vec<f64>),
}

impl Removed {
    fn at(&self, k: usize) -> f64 {
        match self {
            Removed::Offset(c) => *c,
            Removed::Values(v) => v[k],
        }
    }
}

/// How one line came out.
#[derive(Clone, Debug, PartialEq)]
enum LineFit {
    Empty,
    TooFew,
    Levelled(Removed),
}

/// `height_m` (axis 0 = x, NaN = not measured) with each scan line along
/// `axis` levelled by `model`.
pub fn level_rows(
    height_m: &Array2<f64>,
    axis: Axis,
    model: LineModel,
) -> Result<LevelledRows, LevelRowsError> {
    check(height_m, axis, model)?;
    // One line per row of `lines`.
    let mut lines = match axis {
        Axis::X => height_m.t().to_owned(),
        Axis::Y => height_m.to_owned(),
    };
    let fits = match model {
        LineModel::Median | LineModel::Mean | LineModel::Polynomial { .. } => (0..lines.nrows())
            .into_par_iter()
            .map(|k| fit_line(lines.row(k), model))
            .collect(),
        LineModel::MedianDifferences => median_differences(&lines),
    };
    for (mut line, fit) in lines.axis_iter_mut(NdAxis(0)).zip(&fits) {
        if let LineFit::Levelled(removed) = fit {
            line.indexed_iter_mut()
                .for_each(|(k, z)| *z -= removed.at(k));
        }
    }
    let (removed_rms_m, removed_max_m) = removed_spread(&lines, &fits);
    let levelled_m = match axis {
        Axis::X => lines.t().to_owned(),
        Axis::Y => lines,
    };
    let overflow = levelled_m
        .indexed_iter()
        .find(|&(ij, z)| !z.is_finite() && !height_m[ij].is_nan());
    if let Some(((i, j), &value)) = overflow {
        let height = height_m[[i, j]];
        return Err(LevelRowsError::Overflow {
            i,
            j,
            value,
            height,
        });
    }
    let count = |kind: fn(&LineFit) -> bool| fits.iter().filter(|f| kind(f)).count();
    Ok(LevelledRows {
        residual_rms_m: rms_about_mean(&levelled_m),
        height_m: levelled_m,
        levelled: count(|f| matches!(f, LineFit::Levelled(_))),
        left_as_is: count(|f| matches!(f, LineFit::TooFew)),
        empty: count(|f| matches!(f, LineFit::Empty)),
        removed_rms_m,
        removed_max_m,
    })
}

fn check(height_m: &Array2<f64>, axis: Axis, model: LineModel) -> Result<(), LevelRowsError> {
    if let LineModel::Polynomial { degree } = model
        && degree > MAX_DEGREE
    {
        return Err(LevelRowsError::Degree { degree });
    }
    if let Some(((i, j), &value)) = height_m.indexed_iter().find(|(_, v)| v.is_infinite()) {
        return Err(LevelRowsError::NotFinite { i, j, value });
    }
    let (points, other) = match axis {
        Axis::X => (height_m.nrows(), Axis::Y),
        Axis::Y => (height_m.ncols(), Axis::X),
    };
    // A model with as many unknowns as a line has points fits it exactly
    // and leaves zeros (one-point lines of a line scan across y).
    let needed = model.min_line_points();
    if points < needed && !height_m.is_empty() {
        return Err(LevelRowsError::LinesTooShort {
            axis: axis.name(),
            other: other.name(),
            points,
            model: model.name(),
            needed,
        });
    }
    Ok(())
}

/// The median, mean or polynomial of one line.
fn fit_line(line: ArrayView1<f64>, model: LineModel) -> LineFit {
    let mut measured: Vec<f64> = line.iter().copied().filter(|z| !z.is_nan()).collect();
    if measured.is_empty() {
        return LineFit::Empty;
    }
    if measured.len() < model.min_points() {
        return LineFit::TooFew;
    }
    let removed = match model {
        LineModel::Median | LineModel::MedianDifferences => Removed::Offset(median(&mut measured)),
        // Σ (z/n) rather than (Σ z)/n: heights near f64::MAX do not overflow
        LineModel::Mean => {
            let n = measured.len() as f64;
            Removed::Offset(measured.iter().map(|z| z / n).sum())
        }
        LineModel::Polynomial { degree } => Removed::Values(polynomial(line, degree)),
    };
    LineFit::Levelled(removed)
}

/// The least-squares polynomial of the module doc through the measured
/// points of `line` (at least degree + 2 of them), at every point.
fn polynomial(line: ArrayView1<f64>, degree: usize) -> Vec<f64> {
    let n = line.len();
    let terms = degree + 1;
    // n ≥ degree + 2 ≥ 2 (checked), so the scale is not 0
    let centre = (n as f64 - 1.0) / 2.0;
    let basis = |i: usize, out: &mut [f64]| legendre((i as f64 - centre) / centre, out);
    let measured: Vec<(usize, f64)> = line
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, z)| !z.is_nan())
        .collect();
    let mut row = vec![0.0; terms];
    let mut design = DMatrix::zeros(measured.len(), terms);
    for (r, &(i, _)) in measured.iter().enumerate() {
        basis(i, &mut row);
        for (c, &p) in row.iter().enumerate() {
            design[(r, c)] = p;
        }
    }
    let heights = DVector::from_iterator(measured.len(), measured.iter().map(|&(_, z)| z));
    let svd = design.svd(true, true);
    let largest = svd.singular_values.max();
    let tolerance = largest * measured.len() as f64 * f64::EPSILON;
    let coefficients = svd
        .solve(&heights, tolerance)
        .unwrap_or_else(|_| DVector::zeros(terms));
    (0..n)
        .map(|i| {
            basis(i, &mut row);
            row.iter()
                .zip(coefficients.iter())
                .map(|(p, c)| p * c)
                .sum()
        })
        .collect()
}

/// The shifts of the median-differences model, line by line in order:
/// each line is compared to the last line levelled before it.
fn median_differences(lines: &Array2<f64>) -> Vec<LineFit> {
    let mut fits = Vec::with_capacity(lines.nrows());
    let mut reference: Option<(usize, f64)> = None;
    let mut differences = Vec::with_capacity(lines.ncols());
    for (k, line) in lines.axis_iter(NdAxis(0)).enumerate() {
        if line.iter().all(|z| z.is_nan()) {
            fits.push(LineFit::Empty);
            continue;
        }
        let Some((r, shift_r)) = reference else {
            reference = Some((k, 0.0));
            fits.push(LineFit::Levelled(Removed::Offset(0.0)));
            continue;
        };
        differences.clear();
        differences.extend(
            line.iter()
                .zip(lines.row(r))
                .map(|(z, z_r)| z - z_r)
                .filter(|d| !d.is_nan()),
        );
        if differences.is_empty() {
            fits.push(LineFit::TooFew);
            continue;
        }
        let shift = shift_r + median(&mut differences);
        reference = Some((k, shift));
        fits.push(LineFit::Levelled(Removed::Offset(shift)));
    }
    // The typical line keeps its height.
    let mut shifts: Vec<f64> = fits
        .iter()
        .filter_map(|f| match f {
            LineFit::Levelled(Removed::Offset(c)) => Some(*c),
            _ => None,
        })
        .collect();
    let centre = median(&mut shifts);
    for fit in &mut fits {
        if let LineFit::Levelled(Removed::Offset(c)) = fit {
            *c -= centre;
        }
    }
    fits
}

/// (rms about the mean, largest deviation from the mean) of what `fits`
/// subtracted from the measured points of `lines` (0 on lines left as
/// is), summed line by line in order in two passes.
fn removed_spread(lines: &Array2<f64>, fits: &[LineFit]) -> (f64, f64) {
    let removed = || {
        lines
            .axis_iter(NdAxis(0))
            .zip(fits)
            .flat_map(|(line, fit)| {
                let measured: Vec<usize> = (0..line.len()).filter(|&k| !line[k].is_nan()).collect();
                measured.into_iter().map(move |k| match fit {
                    LineFit::Levelled(removed) => removed.at(k),
                    _ => 0.0,
                })
            })
    };
    let n = removed().count();
    if n == 0 {
        return (0.0, 0.0);
    }
    let mean = removed().sum::<f64>() / n as f64;
    let squares: f64 = removed().map(|r| (r - mean) * (r - mean)).sum();
    let largest = removed().fold(0.0_f64, |m, r| m.max((r - mean).abs()));
    ((squares / n as f64).sqrt(), largest)
}

/// Rms about the mean of the measured points of `h`, in row-major order
/// (two passes); 0 if none is measured.
fn rms_about_mean(h: &Array2<f64>) -> f64 {
    let measured = || h.iter().copied().filter(|z| !z.is_nan());
    let n = measured().count();
    if n == 0 {
        return 0.0;
    }
    let mean = measured().sum::<f64>() / n as f64;
    (measured().map(|z| (z - mean) * (z - mean)).sum::<f64>() / n as f64).sqrt()
}

#[cfg(test)]
mod tests;
