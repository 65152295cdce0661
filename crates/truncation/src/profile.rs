//! Profile theory (Abbott and Firestone; the paper's section 4, Eq. 3): a
//! plane at height z above the lowest point touches every pixel with
//! h ≥ z. A(z) is the touched area, N(z) the number of connected touched
//! patches and r(z) = sqrt(A / (π N)) their equivalent radius.
//!
//! All levels come from ONE sweep: the measured pixels are grouped by the
//! first plane that touches them ([`crate::plane_order`]), added from the
//! top down, and joined to their touched neighbours in a union–find
//! ([`crate::sweep`]); A and N are read off whenever the next plane is
//! passed. N changes by +1 per added pixel and −1 per successful union.
//! The map is not periodic: pixels on opposite edges are not neighbours (as
//! in MATLAB's `bwlabel`).
//!
//! Conventions: σ is the rms height about the mean of the measured (non-NaN)
//! points; A0 = (number of measured points) · dx · dy, so NaN holes count
//! neither in A nor in A0 and A/A0 reaches 1 at z = 0.

use ndarray::ArrayView2;

use crate::TruncationError;
use crate::levels::{Connectivity, Levels};
use crate::plane_order::{PlaneOrder, plane_order};
use crate::sweep::Sweep;
use crate::union_find::MAX_PIXELS;

/// How to truncate a map.
#[derive(Clone, Debug, PartialEq)]
pub struct TruncationOptions {
    pub levels: Levels,
    pub connectivity: Connectivity,
    /// Area fractions at which every patch's area is recorded: at the first
    /// plane (from the top) whose A/A0 reaches each of them.
    pub patch_fractions: Vec<f64>,
}

impl Default for TruncationOptions {
    fn default() -> Self {
        Self {
            levels: Levels::default(),
            connectivity: Connectivity::default(),
            patch_fractions: vec![0.01, 0.1, 0.3, 0.5],
        }
    }
}

/// Every patch's area at one plane.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchSnapshot {
    /// The area fraction asked for.
    pub target_area_fraction: f64,
    /// The row of the profile where it was taken.
    pub level: usize,
    /// Patch areas, largest first, m².
    pub patch_areas_m2: Vec<f64>,
}

/// The truncation profile, one entry per plane, top down.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Plane height above the lowest measured point, m.
    pub z_m: Vec<f64>,
    /// Touched area A, m².
    pub area_m2: Vec<f64>,
    /// A / A0.
    pub area_fraction: Vec<f64>,
    /// Connected touched patches N.
    pub patches: Vec<u64>,
    /// Eq. (3): r = sqrt(A / (π N)), m; 0 where N = 0.
    pub radius_m: Vec<f64>,
    /// RMS height about the mean of the measured points, m.
    pub sigma_m: f64,
    /// Nominal area A0 = measured points · dx · dy, m².
    pub nominal_area_m2: f64,
    pub measured_points: usize,
    pub snapshots: Vec<PatchSnapshot>,
}

/// Truncates `heights` (axis 0 = x, metres, NaN = not measured) at every
/// plane of `options.levels`. `progress` receives the number of pixels added
/// since its last call.
pub fn truncate(
    heights: ArrayView2<f64>,
    dx_m: f64,
    dy_m: f64,
    options: &TruncationOptions,
    progress: &mut dyn FnMut(u64),
) -> Result<Profile, TruncationError> {
    let (nx, ny) = heights.dim();
    // The sets live on the map framed by one never-touched pixel on every
    // side, so neighbours need no bounds checks: index (ix+1)·(ny+2) + iy+1.
    let stride = ny + 2;
    if (nx + 2) * stride > MAX_PIXELS {
        return Err(TruncationError::TooLarge { nx, ny });
    }
    let heights = heights.as_standard_layout();
    let flat = heights
        .as_slice()
        .expect("a standard-layout array is contiguous");
    let PlaneOrder {
        planes_m,
        pixels,
        ends,
    } = plane_order(flat, ny, stride, options.levels)?;
    let measured = pixels.len();
    let pixel_area_m2 = dx_m * dy_m;
    let mut targets: Vec<f64> = options.patch_fractions.clone();
    targets.sort_by(f64::total_cmp);
    let mut targets = targets.into_iter().peekable();

    let mut sweep = Sweep::new(options.connectivity, (nx + 2) * stride, stride);
    let mut profile = Profile {
        z_m: Vec::with_capacity(planes_m.len()),
        area_m2: Vec::with_capacity(planes_m.len()),
        area_fraction: Vec::with_capacity(planes_m.len()),
        patches: Vec::with_capacity(planes_m.len()),
        radius_m: Vec::with_capacity(planes_m.len()),
        sigma_m: rms_about_mean(flat),
        nominal_area_m2: measured as f64 * pixel_area_m2,
        measured_points: measured,
        snapshots: Vec::new(),
    };
    for (level, (&z_m, &end)) in planes_m.iter().zip(&ends).enumerate() {
        let new = &pixels[sweep.added..end as usize];
        sweep.add(new);
        progress(new.len() as u64);
        let area_m2 = sweep.added as f64 * pixel_area_m2;
        let area_fraction = sweep.added as f64 / measured as f64;
        profile.z_m.push(z_m);
        profile.area_m2.push(area_m2);
        profile.area_fraction.push(area_fraction);
        profile.patches.push(sweep.patches);
        profile.radius_m.push(if sweep.patches == 0 {
            0.0
        } else {
            (area_m2 / (std::f64::consts::PI * sweep.patches as f64)).sqrt()
        });
        while let Some(&target) = targets.peek() {
            if area_fraction < target {
                break;
            }
            profile.snapshots.push(PatchSnapshot {
                target_area_fraction: target,
                level,
                patch_areas_m2: sweep.patch_areas_m2(pixel_area_m2),
            });
            targets.next();
        }
    }
    Ok(profile)
}

/// RMS about the mean of the non-NaN values.
fn rms_about_mean(values: &[f64]) -> f64 {
    let (mut n, mut sum) = (0_usize, 0.0);
    for &h in values.iter().filter(|h| !h.is_nan()) {
        n += 1;
        sum += h;
    }
    let mean = sum / n as f64;
    let sq: f64 = values
        .iter()
        .filter(|h| !h.is_nan())
        .map(|h| (h - mean) * (h - mean))
        .sum();
    (sq / n as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flood_fill::label_at;
    use ndarray::{Array2, array};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn run(h: &Array2<f64>, levels: Levels, connectivity: Connectivity) -> Profile {
        let options = TruncationOptions {
            levels,
            connectivity,
            ..Default::default()
        };
        truncate(h.view(), 1.0, 1.0, &options, &mut |_| {}).unwrap()
    }

    /// Compares every level with an independent flood-fill labelling.
    fn check_against_flood_fill(h: &Array2<f64>, levels: Levels) {
        let h_min = h
            .iter()
            .copied()
            .filter(|v| !v.is_nan())
            .fold(f64::INFINITY, f64::min);
        // Heights above the lowest point, as the profile defines them.
        let above = h.mapv(|v| v - h_min);
        for connectivity in [Connectivity::Four, Connectivity::Eight] {
            let p = run(h, levels, connectivity);
            for (k, &z) in p.z_m.iter().enumerate() {
                let (touched, patches) = label_at(above.view(), z, connectivity);
                assert_eq!(
                    p.area_m2[k], touched as f64,
                    "A at level {k} ({connectivity:?})"
                );
                assert_eq!(
                    p.patches[k], patches as u64,
                    "N at level {k}, z = {z} ({connectivity:?})\n{h:?}"
                );
            }
        }
    }

    fn random_map(rng: &mut ChaCha8Rng, nx: usize, ny: usize) -> Array2<f64> {
        Array2::from_shape_fn((nx, ny), |_| rng.random::<f64>() * 1e-5)
    }

    #[test]
    fn random_maps_match_flood_fill_at_every_level() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for (nx, ny) in [(1, 1), (1, 9), (7, 1), (13, 17), (24, 19)] {
            let mut h = random_map(&mut rng, nx, ny);
            h[[0, 0]] += 1e-5; // a single-pixel map must not be flat
            if nx * ny > 1 {
                check_against_flood_fill(&h, Levels::Count(37));
                check_against_flood_fill(&h, Levels::All);
            }
        }
    }

    #[test]
    fn plateaus_match_flood_fill() {
        // Four height values only: every plane cuts through ties.
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        for _ in 0..5 {
            let h = Array2::from_shape_fn((21, 16), |_| f64::from(rng.random_range(0..4_u8)));
            check_against_flood_fill(&h, Levels::All);
            check_against_flood_fill(&h, Levels::Count(3));
            check_against_flood_fill(&h, Levels::Count(12));
        }
    }

    #[test]
    fn nan_holes_match_flood_fill_and_never_touch() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..5 {
            let mut h = random_map(&mut rng, 19, 23);
            for v in h.iter_mut() {
                if rng.random::<f64>() < 0.25 {
                    *v = f64::NAN;
                }
            }
            check_against_flood_fill(&h, Levels::Count(50));
            check_against_flood_fill(&h, Levels::All);
            let p = run(&h, Levels::Count(10), Connectivity::Eight);
            let measured = h.iter().filter(|v| !v.is_nan()).count();
            assert_eq!(p.measured_points, measured);
            assert_eq!(*p.area_fraction.last().unwrap(), 1.0);
            assert_eq!(*p.area_m2.last().unwrap(), measured as f64);
        }
    }

    #[test]
    fn diagonal_pixels_join_only_with_eight_connectivity() {
        let h = array![[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]];
        let four = run(&h, Levels::Count(2), Connectivity::Four);
        let eight = run(&h, Levels::Count(2), Connectivity::Eight);
        assert_eq!(four.patches, [3, 3, 1]);
        assert_eq!(eight.patches, [1, 1, 1]);
        assert_eq!(four.area_m2, [3.0, 3.0, 9.0]);
        let r = (3.0 / (std::f64::consts::PI * 3.0)).sqrt();
        assert!((four.radius_m[0] - r).abs() < 1e-15);
    }

    #[test]
    fn statistics_and_snapshot_follow_the_documented_conventions() {
        let h = array![[1.0, 3.0], [f64::NAN, 5.0]];
        let options = TruncationOptions {
            levels: Levels::Count(4),
            connectivity: Connectivity::Four,
            patch_fractions: vec![0.5, 0.01],
        };
        let p = truncate(h.view(), 2.0, 3.0, &options, &mut |_| {}).unwrap();
        // Heights above the lowest: 0, 2, 4; mean 3, σ² = (4 + 0 + 4) / 3.
        assert_eq!(p.z_m, [4.0, 3.0, 2.0, 1.0, 0.0]);
        assert!((p.sigma_m - (8.0_f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(p.nominal_area_m2, 18.0);
        assert_eq!(p.area_m2, [6.0, 6.0, 12.0, 12.0, 18.0]);
        assert_eq!(p.snapshots.len(), 2);
        assert_eq!(p.snapshots[0].target_area_fraction, 0.01);
        assert_eq!(p.snapshots[0].level, 0);
        assert_eq!(p.snapshots[1].level, 2);
        assert_eq!(p.snapshots[1].patch_areas_m2, [12.0]);
    }

    /// FNV-1a (Fowler–Noll–Vo) over every number of a profile, in a fixed
    /// order: a fingerprint of its exact bits that does not depend on std's
    /// unspecified hasher.
    fn fingerprint(p: &Profile) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325_u64;
        let mut eat = |word: u64| {
            for byte in word.to_le_bytes() {
                hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for column in [&p.z_m, &p.area_m2, &p.area_fraction, &p.radius_m] {
            column.iter().for_each(|v| eat(v.to_bits()));
        }
        p.patches.iter().for_each(|&n| eat(n));
        eat(p.sigma_m.to_bits());
        eat(p.nominal_area_m2.to_bits());
        eat(p.measured_points as u64);
        for s in &p.snapshots {
            eat(s.target_area_fraction.to_bits());
            eat(s.level as u64);
            s.patch_areas_m2.iter().for_each(|v| eat(v.to_bits()));
        }
        hash
    }

    /// The profiles of a few maps, bit for bit as the sort-based sweep of
    /// commit 026d9d5 produced them (its fingerprints, recorded then): a
    /// faster sweep must not change a single bit of the products.
    #[test]
    fn profiles_keep_the_bits_of_the_sort_based_sweep() {
        use hypercontact_synth::surface::SelfAffine;
        let mut rng = ChaCha8Rng::seed_from_u64(35);
        let rough = SelfAffine::whole_band(256, 2e-5).non_periodic(256, 192, 2e-5, 35);
        let mut holed = rough.clone();
        for v in holed.iter_mut() {
            if rng.random::<f64>() < 0.05 {
                *v = f64::NAN;
            }
        }
        let plateaus = Array2::from_shape_fn((97, 64), |_| f64::from(rng.random_range(0..9_u8)));
        let mut found = Vec::new();
        for h in [&rough, &holed, &plateaus] {
            for levels in [Levels::Count(1000), Levels::Count(7), Levels::All] {
                for connectivity in [Connectivity::Eight, Connectivity::Four] {
                    let options = TruncationOptions {
                        levels,
                        connectivity,
                        patch_fractions: vec![0.001, 0.01, 0.1, 0.3, 0.5, 0.9, 1.0],
                    };
                    let p = truncate(h.view(), 2e-5, 3e-5, &options, &mut |_| {}).unwrap();
                    found.push(fingerprint(&p));
                }
            }
        }
        let recorded: [u64; 18] = [
            0xe9d2_9b9c_189b_1db1,
            0x4eb9_bc2e_11d4_1da0,
            0x8df0_4f70_8f47_45f4,
            0x0103_e12b_5b71_abeb,
            0x1c0a_3b7c_21bc_97cf,
            0xde2a_dac4_7946_7790,
            0x31fa_08a7_3847_3726,
            0xd1a8_7f40_b701_279b,
            0x5133_8d8c_99b4_6d22,
            0x19dd_8bda_b6d0_4572,
            0xe471_452f_8933_e5a1,
            0x13c3_9fcf_e4bc_05f4,
            0xfb57_0f50_628e_731b,
            0xb08e_69c0_7116_d16b,
            0x5850_4d9d_17c8_f9b5,
            0x8638_80e7_3502_a340,
            0x76cf_8973_6e81_be1b,
            0x0405_0d0f_4613_206f,
        ];
        assert_eq!(found, recorded, "{found:#x?}");
    }

    #[test]
    fn bad_maps_are_named_errors() {
        let none = truncate(
            array![[f64::NAN]].view(),
            1.0,
            1.0,
            &TruncationOptions::default(),
            &mut |_| {},
        );
        assert!(matches!(none, Err(TruncationError::NothingMeasured)));
        let flat = truncate(
            array![[2.0, 2.0]].view(),
            1.0,
            1.0,
            &TruncationOptions::default(),
            &mut |_| {},
        );
        assert!(matches!(flat, Err(TruncationError::Flat)));
        let inf = truncate(
            array![[2.0, 1.0], [f64::INFINITY, 0.0]].view(),
            1.0,
            1.0,
            &TruncationOptions::default(),
            &mut |_| {},
        )
        .unwrap_err()
        .to_string();
        assert!(inf.contains("[1, 0]"), "{inf}");
    }
}
