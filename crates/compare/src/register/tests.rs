//! The registration's conventions, checks and determinism on small maps;
//! accuracy on synthetic experiments is in `tests/register.rs`.

use super::*;
use hypercontact_synth::surface::SelfAffine;
use ndarray::Array2;
use proptest::prelude::*;

const DX: f64 = 20e-6;

/// A 0/1 contact map (a self-affine surface above its median) of nx × ny
/// points at 20 µm.
fn binary_map(nx: usize, ny: usize, seed: u64) -> Array2<f64> {
    let h = SelfAffine {
        hurst: 0.8,
        rms_m: 1e-5,
        lambda_min_m: 3.0 * DX,
        lambda_max_m: 40.0 * DX,
    }
    .non_periodic(nx, ny, DX, seed);
    let mut sorted: Vec<f64> = h.iter().copied().collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    h.mapv(|v| if v >= median { 1.0 } else { 0.0 })
}

fn map_of(f: &Array2<f64>) -> PredictedMap<'_> {
    PredictedMap {
        fraction: f.view(),
        dx_m: DX,
        dy_m: DX,
    }
}

/// The mask the map itself gives through `registration` (samples ≥ ½).
fn rendered_mask(
    map: &PredictedMap,
    registration: &Registration,
    camera: &CameraGrid,
) -> Vec<bool> {
    sample_predicted(map, registration, camera)
        .unwrap()
        .iter()
        .map(|&v| {
            assert!(!v.is_nan(), "the test view must lie on the map");
            v >= 0.5
        })
        .collect()
}

fn exact(placement: Placement) -> Registration {
    Registration {
        placement,
        scale: 1.0,
        score: 1.0,
        coarse_angles: 1,
    }
}

fn dice(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let total = a.iter().filter(|x| **x).count() + b.iter().filter(|x| **x).count();
    2.0 * both as f64 / total as f64
}

#[test]
fn identity_placement_gives_dice_one_and_zncc_one() {
    // the camera on the scan's own grid, over the central 64 × 48 points of
    // a 96 × 80 map: sampling at the identity reads the map's values
    let f = binary_map(96, 80, 1);
    let map = map_of(&f);
    let camera = CameraGrid {
        width_px: 64,
        height_px: 48,
        pixel_m: DX,
    };
    let identity = exact(Placement::default());
    let on_camera = sample_predicted(&map, &identity, &camera).unwrap();
    for y in 0..48 {
        for x in 0..64 {
            assert_eq!(on_camera[y * 64 + x], f[[x + 16, y + 16]], "({x}, {y})");
        }
    }
    let mask = rendered_mask(&map, &identity, &camera);
    assert_eq!(zncc(&on_camera, &mask).unwrap(), 1.0);

    let observed = ObservedMask {
        contact: &mask,
        width_px: 64,
        height_px: 48,
        pixel_m: DX,
    };
    let found = register(&map, &observed, &RegisterSettings::default()).unwrap();
    let p = found.placement;
    assert!(p.angle_rad.abs() < 1e-4, "{found:?}");
    assert!(p.shift_x_m.hypot(p.shift_y_m) < 0.01 * DX, "{found:?}");
    assert!((found.scale - 1.0).abs() < 1e-4, "{found:?}");
    assert!(found.score > 1.0 - 1e-6, "{found:?}");
    let again = rendered_mask(&map, &found, &camera);
    assert_eq!(dice(&again, &mask), 1.0);
}

#[test]
fn axes_follow_the_geometry_convention_on_non_square_grids() {
    // a turned, shifted half-pitch camera on a 120 × 80 map (blocks of 2
    // pixels leave a column and a row over): a swapped axis
    // or a sign would put the recovered shift elsewhere
    let f = binary_map(120, 80, 2);
    let map = map_of(&f);
    let camera = CameraGrid {
        width_px: 91,
        height_px: 61,
        pixel_m: DX / 2.0,
    };
    let truth = Placement {
        angle_rad: 0.06,
        shift_x_m: 13.5 * DX,
        shift_y_m: -6.25 * DX,
    };
    let mask = rendered_mask(&map, &exact(truth), &camera);
    let observed = ObservedMask {
        contact: &mask,
        width_px: 91,
        height_px: 61,
        pixel_m: DX / 2.0,
    };
    let found = register(&map, &observed, &RegisterSettings::default()).unwrap();
    let p = found.placement;
    assert!(
        (p.angle_rad - truth.angle_rad).abs() < 0.2f64.to_radians(),
        "{found:?}"
    );
    let miss = (p.shift_x_m - truth.shift_x_m).hypot(p.shift_y_m - truth.shift_y_m);
    assert!(miss < camera.pixel_m, "{found:?}: {miss}");
}

#[test]
fn the_coarse_search_alone_lands_within_a_cell_and_half_a_step() {
    // a view 2.4 mm across turned 97° and shifted 0.6 mm on a 5.2 mm map:
    // the FFT search's own answer, before any refinement
    let f = binary_map(260, 260, 7);
    let map = map_of(&f);
    let camera = CameraGrid {
        width_px: 121,
        height_px: 119,
        pixel_m: DX,
    };
    let truth = Placement {
        angle_rad: 97f64.to_radians(),
        shift_x_m: 0.5e-3,
        shift_y_m: -0.35e-3,
    };
    let mask = rendered_mask(&map, &exact(truth), &camera);
    let observed = ObservedMask {
        contact: &mask,
        width_px: 121,
        height_px: 119,
        pixel_m: DX,
    };
    let coarse = Pitch::new(&map, &observed, 2, 0.9);
    let step = 2.0f64.to_radians();
    let angles = angle_list(0.0, PI, step);
    let pose = coarse.coarse_search(&angles, 0.9).unwrap().unwrap();
    assert!(
        (pose.angle_rad - truth.angle_rad).abs() <= step / 2.0 + 1e-12,
        "{pose:?}"
    );
    let miss = (pose.shift_m[0] - truth.shift_x_m).hypot(pose.shift_m[1] - truth.shift_y_m);
    assert!(miss < coarse.pitch_m(), "{pose:?}: {miss}");
    assert_eq!(pose.scale, 1.0);
}

#[test]
fn angle_lists_cover_the_range_once() {
    let a = angle_list(0.1, 0.0, 0.01);
    assert_eq!(a, vec![0.1]);
    let a = angle_list(0.0, 0.1, 0.03);
    // ceil(0.1 / 0.03) = 4 steps each way of 0.025
    assert_eq!(a.len(), 9);
    assert!((a[0] + 0.1).abs() < 1e-15 && (a[8] - 0.1).abs() < 1e-15);
    assert!(a.windows(2).all(|w| (w[1] - w[0] - 0.025).abs() < 1e-15));
    let full = angle_list(0.0, PI, PI / 4.0);
    // −180° … 135°: +180° is −180° again
    assert_eq!(full.len(), 8);
    assert!((full[0] + PI).abs() < 1e-15 && (full[7] - 0.75 * PI).abs() < 1e-15);
}

#[test]
fn zncc_of_known_pairs_and_unmeasured_pixels() {
    let observed = [true, false, true, false, true];
    // perfectly anti-correlated on the measured pixels; the NaN pixel
    // would be a perfect match if it were read as 0
    let predicted = [0.0, 1.0, 0.0, f64::NAN, 0.0];
    assert_eq!(zncc(&predicted, &observed).unwrap(), -1.0);
    let linear = [0.9, 0.1, 0.9, 0.1, 0.9];
    assert!((zncc(&linear, &observed).unwrap() - 1.0).abs() < 1e-12);
    // a hand value: x = (1, 0, 1, 0), y = (0.5, 0, 0, 0): cov / σσ = 1/√3
    let z = zncc(&[0.5, 0.0, 0.0, 0.0], &[true, false, true, false]).unwrap();
    assert!((z - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{z}");
    assert!(matches!(
        zncc(&[0.0; 4], &observed),
        Err(CompareError::Length { .. })
    ));
    assert!(matches!(
        zncc(&[f64::NAN; 5], &observed),
        Err(CompareError::Empty { .. })
    ));
    assert!(matches!(
        zncc(&[0.3; 5], &observed),
        Err(CompareError::Uniform { .. })
    ));
    assert!(matches!(
        zncc(&[0.0, f64::INFINITY, 0.0, 0.0, 1.0], &observed),
        Err(CompareError::Value { index: 1, .. })
    ));
}

/// A 24 × 24 mask at the map's pitch taken from the centre of `f`.
fn central_mask(f: &Array2<f64>) -> Vec<bool> {
    let camera = CameraGrid {
        width_px: 24,
        height_px: 24,
        pixel_m: DX,
    };
    rendered_mask(&map_of(f), &exact(Placement::default()), &camera)
}

#[test]
fn uniform_masks_and_maps_are_refused_by_name() {
    let f = binary_map(48, 48, 3);
    let map = map_of(&f);
    let settings = RegisterSettings::default();
    let observed = |contact: &'static [bool]| ObservedMask {
        contact,
        width_px: 24,
        height_px: 24,
        pixel_m: DX,
    };
    let err = register(&map, &observed(&[false; 576]), &settings).unwrap_err();
    assert_eq!(
        err,
        CompareError::Uniform {
            what: "the observed mask",
            state: "no contact"
        }
    );
    assert!(err.to_string().contains("no contact"), "{err}");
    let err = register(&map, &observed(&[true; 576]), &settings).unwrap_err();
    assert!(err.to_string().contains("contact everywhere"), "{err}");

    let mask = central_mask(&f);
    let mask = ObservedMask {
        contact: &mask,
        ..observed(&[])
    };
    for (value, state) in [
        (0.0, "no contact"),
        (1.0, "contact everywhere"),
        (0.4, "one contact fraction everywhere"),
    ] {
        let flat = f.mapv(|_| value);
        let err = register(&map_of(&flat), &mask, &settings).unwrap_err();
        assert_eq!(
            err,
            CompareError::Uniform {
                what: "the predicted map",
                state
            }
        );
    }
    let unmeasured = f.mapv(|_| f64::NAN);
    assert!(matches!(
        register(&map_of(&unmeasured), &mask, &settings),
        Err(CompareError::Empty { .. })
    ));
}

#[test]
fn a_view_larger_than_the_map_is_refused() {
    let f = binary_map(40, 40, 4);
    let map = map_of(&f);
    // 1.5 × the map each way at the map's pitch, any turn
    let mask: Vec<bool> = (0..60 * 60).map(|k| (k * 7 + k / 60) % 5 < 2).collect();
    let observed = ObservedMask {
        contact: &mask,
        width_px: 60,
        height_px: 60,
        pixel_m: DX,
    };
    for range in [10.0, 180.0] {
        let settings = RegisterSettings {
            angle_range_deg: range,
            ..RegisterSettings::default()
        };
        let err = register(&map, &observed, &settings).unwrap_err();
        assert!(
            matches!(err, CompareError::ViewOutsideMap { .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains("1.200 × 1.200 mm"), "{err}");
    }
}

#[test]
fn bad_inputs_get_errors_naming_them() {
    let f = binary_map(48, 48, 5);
    let mask = central_mask(&f);
    let good_map = map_of(&f);
    let good_mask = ObservedMask {
        contact: &mask,
        width_px: 24,
        height_px: 24,
        pixel_m: DX,
    };
    let settings = RegisterSettings::default();
    assert!(register(&good_map, &good_mask, &settings).is_ok());

    let mut bad_value = f.clone();
    bad_value[[3, 2]] = 1.5;
    let mut infinite = f.clone();
    infinite[[0, 1]] = f64::INFINITY;
    let empty = Array2::<f64>::zeros((0, 5));
    for (map, want) in [
        (
            map_of(&bad_value),
            "predicted map (logical order, ix * ny + iy)[146] = 1.5",
        ),
        (map_of(&infinite), "[1] = inf"),
        (map_of(&empty), "predicted map is empty"),
        (
            PredictedMap {
                dx_m: 0.0,
                ..good_map
            },
            "`predicted map dx_m` = 0",
        ),
        (
            PredictedMap {
                dy_m: f64::NAN,
                ..good_map
            },
            "`predicted map dy_m` = NaN",
        ),
    ] {
        let err = register(&map, &good_mask, &settings).unwrap_err();
        assert!(err.to_string().contains(want), "{err} lacks {want}");
    }
    for (observed, want) in [
        (
            ObservedMask {
                contact: &mask[1..],
                ..good_mask
            },
            "holds 575 values, 576 expected",
        ),
        (
            ObservedMask {
                width_px: 0,
                ..good_mask
            },
            "observed mask is empty",
        ),
        (
            ObservedMask {
                pixel_m: -1.0,
                ..good_mask
            },
            "pixel_m",
        ),
        (
            ObservedMask {
                pixel_m: f64::NAN,
                ..good_mask
            },
            "pixel_m",
        ),
        // 24 pixels of 4 µm span 4.8 scan pixels of 20 µm
        (
            ObservedMask {
                pixel_m: 4e-6,
                ..good_mask
            },
            "is too small",
        ),
    ] {
        let err = register(&good_map, &observed, &settings).unwrap_err();
        assert!(err.to_string().contains(want), "{err} lacks {want}");
    }
    let d = RegisterSettings::default();
    for (bad, param) in [
        (
            RegisterSettings {
                angle_centre_deg: f64::NAN,
                ..d
            },
            "angle_centre_deg",
        ),
        (
            RegisterSettings {
                angle_range_deg: 181.0,
                ..d
            },
            "angle_range_deg",
        ),
        (
            RegisterSettings {
                angle_range_deg: -1.0,
                ..d
            },
            "angle_range_deg",
        ),
        (
            RegisterSettings {
                coarse_step_deg: Some(0.0),
                ..d
            },
            "coarse_step_deg",
        ),
        (
            RegisterSettings {
                angle_range_deg: 180.0,
                coarse_step_deg: Some(1e-3),
                ..d
            },
            "coarse_step_deg",
        ),
        (
            RegisterSettings {
                coarse_factor: 0,
                ..d
            },
            "coarse_factor",
        ),
        (
            RegisterSettings {
                scale_range: 0.6,
                ..d
            },
            "scale_range",
        ),
        (
            RegisterSettings {
                min_overlap: 0.0,
                ..d
            },
            "min_overlap",
        ),
        (
            RegisterSettings {
                min_overlap: 1.5,
                ..d
            },
            "min_overlap",
        ),
    ] {
        let err = register(&good_map, &good_mask, &bad).unwrap_err();
        assert!(
            matches!(&err, CompareError::Param { param: p, .. } if *p == param),
            "{err:?}"
        );
    }
    let bad_scale = Registration {
        scale: 0.0,
        ..exact(Placement::default())
    };
    assert!(sample_predicted(&good_map, &bad_scale, &good_mask.grid()).is_err());
}

#[test]
fn the_same_answer_on_any_number_of_threads() {
    let f = binary_map(72, 72, 6);
    let map = map_of(&f);
    let camera = CameraGrid {
        width_px: 100,
        height_px: 80,
        pixel_m: DX / 3.0,
    };
    let truth = Placement {
        angle_rad: -0.05,
        shift_x_m: 4.3 * DX,
        shift_y_m: 2.1 * DX,
    };
    let mask = rendered_mask(&map, &exact(truth), &camera);
    let observed = ObservedMask {
        contact: &mask,
        width_px: 100,
        height_px: 80,
        pixel_m: DX / 3.0,
    };
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| register(&map, &observed, &RegisterSettings::default()).unwrap())
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert_eq!(one, on(5));
}

proptest! {
    #![proptest_config(hypercontact_fuzz::config(48))]

    /// Any input gets an answer or an error, never a panic.
    #[test]
    fn never_panics(
        nx in 0usize..24,
        ny in 0usize..24,
        values in proptest::collection::vec(
            prop_oneof![Just(0.0), Just(1.0), 0.0f64..1.0, Just(f64::NAN), Just(-0.5), Just(f64::INFINITY)],
            576,
        ),
        width in 0usize..40,
        height in 0usize..40,
        mut contact in proptest::collection::vec(any::<bool>(), 0..1700),
        fit_length in any::<bool>(),
        pixel_m in prop_oneof![Just(DX), 1e-6f64..1e-4, Just(0.0), Just(f64::NAN)],
        range in prop_oneof![Just(10.0), 0.0f64..200.0],
        overlap in prop_oneof![Just(0.9), 0.0f64..1.2],
        factor in 0usize..4,
    ) {
        if fit_length {
            // mostly the mask's stated size, to reach past the length check
            let n = width * height;
            contact = (0..n).map(|k| contact.get(k).copied().unwrap_or(k % 3 == 0)).collect();
        }
        let f = Array2::from_shape_fn((nx, ny), |(i, j)| values[i * 24 + j]);
        let map = map_of(&f);
        let observed = ObservedMask { contact: &contact, width_px: width, height_px: height, pixel_m };
        let settings = RegisterSettings {
            angle_range_deg: range,
            min_overlap: overlap,
            coarse_factor: factor,
            ..RegisterSettings::default()
        };
        if let Ok(found) = register(&map, &observed, &settings) {
            prop_assert!(found.score.is_finite() && found.scale > 0.0);
        }
    }
}
