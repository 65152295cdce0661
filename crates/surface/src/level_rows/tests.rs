use ndarray::Array2;
use proptest::prelude::*;

use super::*;

/// A fixed pseudo-random sequence in [−1, 1) (a 64-bit LCG, Knuth's MMIX
/// constants), so the tests need no random crate and give the same maps.
struct Sequence(u64);

impl Sequence {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        2.0 * ((self.0 >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// `lines` (one scan line per row) as a map whose scan lines run along `axis`.
fn as_map(lines: &Array2<f64>, axis: Axis) -> Array2<f64> {
    match axis {
        Axis::X => lines.t().to_owned(),
        Axis::Y => lines.clone(),
    }
}

/// 37 lines of 53 points: ±10 nm of texture, about 8 % of the points NaN.
fn textured_lines(seed: u64) -> Array2<f64> {
    let mut random = Sequence(seed);
    Array2::from_shape_fn((37, 53), |_| {
        let z = 10e-9 * random.next();
        if random.next() > 0.84 { f64::NAN } else { z }
    })
}

/// The measured (index, height) pairs of a line.
fn measured(line: ndarray::ArrayView1<f64>) -> Vec<(f64, f64)> {
    line.iter()
        .enumerate()
        .filter(|(_, z)| !z.is_nan())
        .map(|(i, &z)| (i as f64, z))
        .collect()
}

/// The median by sorting (independent of the select-based one levelled with).
fn sorted_median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// Each line of `lines` made orthogonal, over its measured points, to 1,
/// i, …, i^degree by modified Gram–Schmidt on the monomials (twice, for
/// accuracy): a route independent of the Legendre basis and the SVD.
fn project_out_polynomials(lines: &mut Array2<f64>, degree: usize) {
    for mut line in lines.rows_mut() {
        let points = measured(line.view());
        let scale = line.len() as f64;
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for power in 0..=degree {
            let mut v: Vec<f64> = points
                .iter()
                .map(|(i, _)| (i / scale).powi(power as i32))
                .collect();
            for _ in 0..2 {
                for b in &basis {
                    let dot: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= dot * y);
                }
            }
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            basis.push(v.into_iter().map(|x| x / norm).collect());
        }
        let mut z: Vec<f64> = points.iter().map(|(_, z)| *z).collect();
        for _ in 0..2 {
            for b in &basis {
                let dot: f64 = z.iter().zip(b).map(|(x, y)| x * y).sum();
                z.iter_mut().zip(b).for_each(|(x, y)| *x -= dot * y);
            }
        }
        for ((i, _), z) in points.iter().zip(z) {
            line[*i as usize] = z;
        }
    }
}

/// Largest |a − b| over the points, NaN required at the same places.
fn worst_difference(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    assert_eq!(a.dim(), b.dim());
    a.iter().zip(b).fold(0.0, |worst, (x, y)| {
        assert_eq!(x.is_nan(), y.is_nan(), "NaN in one map only");
        if x.is_nan() {
            worst
        } else {
            worst.max((x - y).abs())
        }
    })
}

fn range(h: &Array2<f64>) -> f64 {
    let (lo, hi) = h
        .iter()
        .filter(|z| !z.is_nan())
        .fold((f64::MAX, f64::MIN), |(lo, hi), &z| (lo.min(z), hi.max(z)));
    hi - lo
}

/// A level base map plus per-line offsets c_k (up to ±50 nm) and, for
/// `tilted`, slopes (up to ±50 nm across the line) comes back to the base
/// map within 1e-12 of its range, along either axis: the model is exact
/// when each base line has nothing of it (median 0, mean 0, orthogonal to
/// the polynomials), which is built here by sorting, averaging and
/// Gram–Schmidt, not by the code under test.
#[test]
fn offsets_tilts_and_polynomials_added_to_a_level_map_come_back_exactly() {
    let cases: [(LineModel, usize, bool); 5] = [
        (LineModel::Median, 0, false),
        (LineModel::Mean, 0, false),
        (LineModel::Polynomial { degree: 1 }, 1, true),
        (LineModel::Polynomial { degree: 3 }, 3, true),
        (LineModel::Polynomial { degree: 0 }, 0, false),
    ];
    for (model, degree, tilted) in cases {
        let mut base = textured_lines(7);
        for mut line in base.rows_mut() {
            let z: Vec<f64> = measured(line.view()).iter().map(|p| p.1).collect();
            if model == LineModel::Median {
                let m = sorted_median(&z);
                line.mapv_inplace(|v| v - m);
            }
        }
        if model != LineModel::Median {
            project_out_polynomials(&mut base, degree);
        }
        let mut random = Sequence(99);
        let mut disturbed = base.clone();
        for mut line in disturbed.rows_mut() {
            let n = line.len() as f64;
            let (offset, slope) = (50e-9 * random.next(), 50e-9 * random.next() / n);
            let curve = 20e-9 * random.next() / (n * n * n);
            for (i, z) in line.iter_mut().enumerate() {
                let t = i as f64;
                *z += offset;
                if tilted {
                    *z += slope * t;
                }
                if degree == 3 {
                    *z += curve * (t - 20.0).powi(3);
                }
            }
        }
        for axis in [Axis::X, Axis::Y] {
            let out = level_rows(&as_map(&disturbed, axis), axis, model).unwrap();
            let expected = as_map(&base, axis);
            let worst = worst_difference(&out.height_m, &expected);
            assert!(
                worst <= 1e-12 * range(&expected),
                "{model:?} along {axis:?}: {worst:e} of a range {:e}",
                range(&expected)
            );
            assert_eq!((out.levelled, out.left_as_is, out.empty), (37, 0, 0));
            // what was removed is what was added: ≈ 29 nm rms of offsets
            assert!(
                out.removed_rms_m > 10e-9 && out.removed_rms_m < 60e-9,
                "{out:?}"
            );
        }
    }
}

/// Identical lines (with NaN holes at different places) shifted by c_k
/// come back to the identical lines plus median(c): the shifts chain from
/// the first line, then move by their median.
#[test]
fn median_differences_undo_line_shifts_exactly() {
    let mut random = Sequence(3);
    let profile: Vec<f64> = (0..53).map(|_| 10e-9 * random.next()).collect();
    let base = Array2::from_shape_fn((37, 53), |(k, i)| {
        if (k * 7 + i * 3) % 11 == 0 {
            f64::NAN
        } else {
            profile[i]
        }
    });
    let shifts: Vec<f64> = (0..37).map(|_| 50e-9 * random.next()).collect();
    let disturbed = Array2::from_shape_fn((37, 53), |(k, i)| base[[k, i]] + shifts[k]);
    let typical = sorted_median(&shifts);
    let expected = base.mapv(|z| z + typical);
    for axis in [Axis::X, Axis::Y] {
        let out = level_rows(
            &as_map(&disturbed, axis),
            axis,
            LineModel::MedianDifferences,
        )
        .unwrap();
        let worst = worst_difference(&out.height_m, &as_map(&expected, axis));
        assert!(worst <= 1e-12 * range(&expected), "{axis:?}: {worst:e}");
        // removed: the shifts about their mean
        let mean = shifts.iter().sum::<f64>() / 37.0;
        let rms = (shifts.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / 37.0).sqrt();
        assert!(
            (out.removed_rms_m / rms - 1.0).abs() < 0.1,
            "{out:?} vs {rms:e}"
        );
    }
}

/// A plateau 40 nm high over lines 10..20 and 30 % of each line: the
/// median of the differences to the line before is 0 at its edges, so the
/// plateau keeps its height exactly, while each line's own median is
/// pulled by it.
#[test]
fn median_differences_keep_a_plateau_that_line_medians_pull() {
    let map = Array2::from_shape_fn((40, 30), |(i, j)| {
        let ramp = 1e-9 * i as f64;
        if (10..20).contains(&j) && i < 12 {
            ramp + 40e-9
        } else {
            ramp
        }
    });
    let out = level_rows(&map, Axis::X, LineModel::MedianDifferences).unwrap();
    let step = out.height_m[[5, 15]] - out.height_m[[5, 5]];
    assert!((step - 40e-9).abs() < 1e-20, "{step:e}");
    assert_eq!(out.removed_rms_m, 0.0);
    let by_median = level_rows(&map, Axis::X, LineModel::Median).unwrap();
    let step = by_median.height_m[[5, 15]] - by_median.height_m[[5, 5]];
    assert!((step - 40e-9).abs() > 1e-9, "{step:e}");
}

/// Degree 0 is the mean; a line that is a polynomial of the degree is
/// removed to rounding (the analytic case); residuals are orthogonal to
/// the polynomials (the least-squares condition).
#[test]
fn polynomial_fits_are_least_squares() {
    let lines = textured_lines(11);
    let map = as_map(&lines, Axis::Y);
    let mean = level_rows(&map, Axis::Y, LineModel::Mean).unwrap();
    let degree_0 = level_rows(&map, Axis::Y, LineModel::Polynomial { degree: 0 }).unwrap();
    assert!(worst_difference(&mean.height_m, &degree_0.height_m) <= 1e-12 * range(&map));

    let parabola = Array2::from_shape_fn((5, 40), |(k, i)| {
        let t = i as f64;
        1e-6 * (k as f64 + 1.0) * (1.0 - 0.1 * t + 0.003 * t * t)
    });
    let out = level_rows(&parabola, Axis::Y, LineModel::Polynomial { degree: 2 }).unwrap();
    let worst = out.height_m.iter().fold(0.0_f64, |m, z| m.max(z.abs()));
    assert!(worst < 1e-12 * range(&parabola), "{worst:e}");

    for degree in 1..=MAX_DEGREE {
        let out = level_rows(&map, Axis::Y, LineModel::Polynomial { degree }).unwrap();
        for line in out.height_m.rows() {
            let points = measured(line);
            for power in 0..=degree {
                let dot: f64 = points
                    .iter()
                    .map(|(i, z)| z * (i / 52.0).powi(power as i32))
                    .sum();
                assert!(
                    dot.abs() < 1e-12 * 10e-9 * 53.0,
                    "degree {degree}, power {power}: {dot:e}"
                );
            }
        }
    }
}

/// Empty lines, lines with too few measured points, and (for median
/// differences) a line sharing no point with the line before are left as
/// is and counted; the next line is compared with the last one levelled.
#[test]
fn lines_with_too_few_points_are_left_as_is_and_counted() {
    let nan = f64::NAN;
    // lines along y: row k is line k
    let map = ndarray::array![
        [nan, nan, nan, nan, nan],
        [1.0, nan, nan, nan, nan],
        [1.0, 2.0, 3.0, nan, nan],
        [4.0, 5.0, 6.0, 7.0, 8.0],
        [nan, nan, nan, nan, 9.0],
        [2.0, 3.0, 4.0, 5.0, 6.0],
    ];
    let out = level_rows(&map, Axis::Y, LineModel::Median).unwrap();
    assert_eq!((out.levelled, out.left_as_is, out.empty), (3, 2, 1));
    assert_eq!(out.height_m[[1, 0]], 1.0);
    assert_eq!(out.height_m[[4, 4]], 9.0);
    assert_eq!(out.height_m.row(3).to_vec(), [-2.0, -1.0, 0.0, 1.0, 2.0]);
    assert!(out.height_m.row(0).iter().all(|z| z.is_nan()));

    let out = level_rows(&map, Axis::Y, LineModel::Polynomial { degree: 1 }).unwrap();
    assert_eq!((out.levelled, out.left_as_is, out.empty), (3, 2, 1));
    let out = level_rows(&map, Axis::Y, LineModel::Polynomial { degree: 2 }).unwrap();
    // line 2 has 3 points, as many as a parabola's unknowns
    assert_eq!((out.levelled, out.left_as_is, out.empty), (2, 3, 1));
    assert_eq!(out.height_m.row(2).to_vec()[..3], [1.0, 2.0, 3.0]);

    // Median differences: line 1 starts (shift 0), line 2 shares point 0
    // with it (0), line 3 points 0..3 with line 2 (+3), line 4 only point 4
    // with line 3 (+4), line 5 is compared with line 4 (+1).
    let out = level_rows(&map, Axis::Y, LineModel::MedianDifferences).unwrap();
    assert_eq!((out.levelled, out.left_as_is, out.empty), (5, 0, 1));
    let gaps = ndarray::array![
        [1.0, 2.0, nan, nan],
        [nan, nan, 5.0, 6.0],
        [3.0, 4.0, 7.0, 8.0],
    ];
    let out = level_rows(&gaps, Axis::Y, LineModel::MedianDifferences).unwrap();
    // line 1 shares no point with line 0: left as is; line 2 is compared with line 0
    assert_eq!((out.levelled, out.left_as_is, out.empty), (2, 1, 0));
    assert_eq!(out.height_m.row(1).to_vec()[2..], [5.0, 6.0]);
}

/// A constant map, a single line and a single column give zeros or are
/// refused naming the axis, never a panic.
#[test]
fn degenerate_maps_level_or_are_refused() {
    let constant = Array2::from_elem((4, 3), 2.5e-6);
    for model in [
        LineModel::Median,
        LineModel::Mean,
        LineModel::Polynomial { degree: 1 },
    ] {
        let out = level_rows(&constant, Axis::X, model).unwrap();
        assert!(
            out.height_m.iter().all(|&z| z.abs() < 1e-18),
            "{model:?}: {out:?}"
        );
    }
    let out = level_rows(&constant, Axis::X, LineModel::MedianDifferences).unwrap();
    assert_eq!(out.height_m, constant);

    // a line scan (7 × 1) levels as one line along x …
    let profile = Array2::from_shape_fn((7, 1), |(i, _)| i as f64 * 1e-9);
    let out = level_rows(&profile, Axis::X, LineModel::Median).unwrap();
    assert_eq!(out.height_m[[0, 0]], -profile[[3, 0]]);
    // … and is refused across y, where each line is one point
    let e = level_rows(&profile, Axis::Y, LineModel::Median).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the scan lines along y have 1 point(s) each, and a median per line needs at least 2 to \
         leave anything but zeros: is the fast axis x?"
    );
    let e = level_rows(&profile, Axis::X, LineModel::Polynomial { degree: 6 }).unwrap_err();
    assert!(e.to_string().contains("have 7 point(s) each"), "{e}");
    assert!(level_rows(&profile, Axis::X, LineModel::Polynomial { degree: 5 }).is_ok());

    let empty = Array2::<f64>::zeros((0, 4));
    let out = level_rows(&empty, Axis::X, LineModel::Median).unwrap();
    assert_eq!((out.levelled, out.removed_rms_m), (0, 0.0));
    let all_nan = Array2::from_elem((3, 3), f64::NAN);
    let out = level_rows(&all_nan, Axis::Y, LineModel::MedianDifferences).unwrap();
    assert_eq!(out.empty, 3);
}

#[test]
fn bad_degrees_infinite_heights_and_overflows_are_refused() {
    let map = Array2::from_elem((8, 8), 1.0);
    let e = level_rows(&map, Axis::X, LineModel::Polynomial { degree: 7 }).unwrap_err();
    assert_eq!(e, LevelRowsError::Degree { degree: 7 });
    assert!(e.to_string().contains("0 to 6"), "{e}");
    let mut inf = map.clone();
    inf[[2, 3]] = f64::NEG_INFINITY;
    let e = level_rows(&inf, Axis::X, LineModel::Median).unwrap_err();
    assert_eq!(
        e.to_string(),
        "height at point (2, 3) is -inf: heights must be finite or NaN (not measured)"
    );
    let huge = Array2::from_shape_fn((4, 4), |(i, j)| {
        if (i + j) % 2 == 0 {
            f64::MAX
        } else {
            -f64::MAX
        }
    });
    let e = level_rows(&huge, Axis::X, LineModel::MedianDifferences).unwrap_err();
    assert!(e.to_string().contains("overflow"), "{e}");
}

/// The same bits on 1 and 4 threads.
#[test]
fn the_same_bits_on_any_number_of_threads() {
    let map = as_map(&textured_lines(5), Axis::X);
    let run = |threads: usize, model: LineModel| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| level_rows(&map, Axis::X, model).unwrap())
    };
    for model in [
        LineModel::Median,
        LineModel::Polynomial { degree: 4 },
        LineModel::MedianDifferences,
    ] {
        let (one, four) = (run(1, model), run(4, model));
        let bits = |h: &Array2<f64>| h.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one.height_m), bits(&four.height_m), "{model:?}");
        assert_eq!(one.removed_rms_m.to_bits(), four.removed_rms_m.to_bits());
    }
}

fn any_height() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(0.0),
        Just(1e-300),
        Just(-1e300),
        Just(1e300),
        Just(f64::MAX),
        -1e-6..1e-6f64,
    ]
}

fn any_model() -> impl Strategy<Value = LineModel> {
    prop_oneof![
        Just(LineModel::Median),
        Just(LineModel::Mean),
        Just(LineModel::MedianDifferences),
        (0usize..=8).prop_map(|degree| LineModel::Polynomial { degree }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]
    /// Any small map (0 to 6 points a side, NaN, zeros, tiny, huge and
    /// ordinary heights), any model, either axis: a result or an error,
    /// never a panic; a result keeps the NaN points, has every measured
    /// point finite and counts every line once.
    #[test]
    fn small_maps_never_panic(
        nx in 0usize..7,
        ny in 0usize..7,
        heights in prop::collection::vec(any_height(), 49),
        model in any_model(),
        along_y in any::<bool>(),
    ) {
        let map = Array2::from_shape_fn((nx, ny), |(i, j)| heights[i * 7 + j]);
        let axis = if along_y { Axis::Y } else { Axis::X };
        if let Ok(out) = level_rows(&map, axis, model) {
            for (z, z0) in out.height_m.iter().zip(&map) {
                prop_assert_eq!(z.is_nan(), z0.is_nan());
                prop_assert!(z.is_nan() || z.is_finite());
            }
            let lines = if along_y { nx } else { ny };
            prop_assert_eq!(out.levelled + out.left_as_is + out.empty, lines);
        }
    }
}
