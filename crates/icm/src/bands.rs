//! Bootstrap bands of any tangent-modulus contact model: each of
//! material-fit's replicate materials gets its own contact law E_t*(S), the
//! model's curve is recomputed under it, and [`BandTable`] takes the 5th, 50th
//! and 95th percentiles per response row.
//!
//! What a replicate costs depends on the model. The ICM integrates its own
//! profile equation; boundary elements, Persson and Greenwood–Williamson
//! solve the linear problem once (its contact set and unit-modulus load do
//! not depend on the modulus) and a replicate is one tangent integral over
//! it ([`crate::tangent`]), microseconds against the solve's seconds.
//!
//! Loads are normalised by the main material's E0* A0, so the bands sit on
//! the response's own axes; tangent moduli by each replicate's own E0*, so a
//! band of E_t*/E0* shows the shape of the law, not the spread of μ0.

use std::sync::Arc;

use rayon::prelude::*;

use hypercontact_core::contact::BandTable;
use hypercontact_core::{Context, Inputs, StageError, Table};
use hypercontact_material::MaterialError;
use hypercontact_material::bootstrap::{Replicate, from_replicates_table};

use crate::LawParams;
use crate::modulus::CompositeModulus;
use crate::tangent::TangentLoad;

/// One replicate's curve under its own law: the loads and E_t* at the
/// response's rows, or why the law gave out.
pub type ReplicateCurve<'a> = dyn Fn(&CompositeModulus) -> Result<TangentLoad, String> + Sync + 'a;

/// The replicates wired to input `replicates`, if it is; a table that does
/// not read as replicates names the input.
pub fn wired_replicates(inputs: &Inputs) -> Result<Option<Vec<Replicate>>, StageError> {
    if inputs.get("replicates").is_none() {
        return Ok(None);
    }
    let table: &Table = inputs.table("replicates")?;
    from_replicates_table(table)
        .map(Some)
        .map_err(|e: MaterialError| StageError::invalid(format!("input `replicates`: {e}")))
}

/// A replicate's own E0* (Pa) and its curve, or why its law gave out.
type Solved = Result<(f64, TangentLoad), String>;

/// Where the bands are drawn: the response's A/A0 per row and its axes,
/// the main material's E0* (Pa) and the nominal area A0 (m²).
#[derive(Clone, Copy, Debug)]
pub struct BandAxes<'a> {
    pub area_fraction: &'a [f64],
    pub e0_star_pa: f64,
    pub nominal_area_m2: f64,
}

/// Every replicate's curve (in parallel, collected in replicate order, so
/// the bands are the same on any thread count) as bands; a replicate whose
/// law gives out is left out, with a note naming one. No replicates: a
/// table without rows.
pub fn replicate_bands(
    replicates: Option<Vec<Replicate>>,
    law: &LawParams,
    axes: BandAxes<'_>,
    curve: &ReplicateCurve<'_>,
    ctx: &Context,
) -> BandTable {
    let Some(replicates) = replicates else {
        return BandTable::from_replicates(&[], &[], &[]);
    };
    let bar = ctx.progress(replicates.len() as u64, "bootstrap replicates");
    let solved: Vec<(i64, Solved)> = replicates
        .into_par_iter()
        .map(|(r, material)| {
            let out = law
                .modulus(Arc::from(material))
                .map_err(|e| e.to_string())
                .and_then(|modulus| Ok((modulus.e0_star_pa(), curve(&modulus)?)));
            bar.inc(1);
            (r, out)
        })
        .collect();
    let scale = axes.e0_star_pa * axes.nominal_area_m2;
    let (mut loads, mut tangents, mut failed) = (Vec::new(), Vec::new(), Vec::new());
    for (r, out) in solved {
        match out {
            Ok((own_e0_star_pa, curve)) => {
                loads.push(curve.load_n.iter().map(|f| f / scale).collect());
                tangents.push(
                    curve
                        .modulus_pa
                        .iter()
                        .map(|e| e / own_e0_star_pa)
                        .collect(),
                );
            }
            Err(e) => failed.push(format!("{r}: {e}")),
        }
    }
    if let Some(first) = failed.first() {
        ctx.note(&format!(
            "bands: {} of {} replicates left out, e.g. replicate {first}",
            failed.len(),
            failed.len() + loads.len(),
        ));
    }
    BandTable::from_replicates(axes.area_fraction, &loads, &tangents)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scheme;
    use crate::tangent::integrate;
    use hypercontact_core::Schema;
    use hypercontact_material::presets::paper_epdm;
    use hypercontact_material::{Hyperelastic, NeoHookean};

    fn replicate(r: i64, mu_pa: f64) -> Replicate {
        (
            r,
            Box::new(NeoHookean::new(mu_pa).unwrap()) as Box<dyn Hyperelastic>,
        )
    }

    /// Under a linear law each replicate's load is its own E0* f, so the
    /// band of F/(E0* A0) is the quantiles of the replicates' E0* over the
    /// main one's, times f/A0: by hand for three neo-Hookean materials.
    #[test]
    fn linear_law_bands_are_the_quantiles_of_the_replicates_moduli() {
        let law = LawParams {
            model: crate::Model::Linear,
            ..LawParams::default()
        };
        let f = [0.0, 1e-9, 3e-9];
        let area = [0.0, 1e-6, 2e-6];
        let curve = |m: &CompositeModulus| {
            integrate(&f, &area, Scheme::Heun, &mut |s| {
                m.at_stress_pa(s).map_err(|e| e.to_string())
            })
            .map_err(|e| e.to_string())
        };
        let main = CompositeModulus::new(
            Arc::new(NeoHookean::new(1e6).unwrap()),
            crate::Model::Linear,
            0.5,
        )
        .unwrap();
        let axes = BandAxes {
            area_fraction: &[0.0, 0.1, 0.2],
            e0_star_pa: main.e0_star_pa(),
            nominal_area_m2: 1e-5,
        };
        let reps = vec![
            replicate(1, 0.9e6),
            replicate(2, 1.0e6),
            replicate(3, 1.2e6),
        ];
        let ctx = Context::new("t");
        let bands = replicate_bands(Some(reps), &law, axes, &curve, &ctx);
        // Type 7 quantiles of {0.9, 1.0, 1.2}: 5 % → 0.9 + 0.1·0.1 = 0.91,
        // 95 % → 1.0 + 0.9·0.2 = 1.18.
        for (k, f) in f.iter().enumerate() {
            let unit = f / 1e-5;
            assert!((bands.load_norm_p05[k] - 0.91 * unit).abs() <= 1e-12 * unit.max(1e-30));
            assert!((bands.load_norm_p50[k] - unit).abs() <= 1e-12 * unit.max(1e-30));
            assert!((bands.load_norm_p95[k] - 1.18 * unit).abs() <= 1e-12 * unit.max(1e-30));
            assert_eq!(bands.tangent_ratio_p50[k], 1.0);
        }
        assert_eq!(bands.replicates, [3, 3, 3]);
        assert!(
            replicate_bands(None, &law, axes, &curve, &ctx)
                .into_table()
                .n_rows()
                == 0
        );
    }

    /// A replicate whose law cannot be built is left out, the rest banded.
    #[test]
    fn a_replicate_whose_law_fails_is_left_out() {
        let law = LawParams::default();
        let curve = |m: &CompositeModulus| {
            integrate(&[0.0, 1e-9], &[0.0, 1e-6], Scheme::Heun, &mut |s| {
                m.at_stress_pa(s).map_err(|e| e.to_string())
            })
            .map_err(|e| e.to_string())
        };
        let axes = BandAxes {
            area_fraction: &[0.0, 0.1],
            e0_star_pa: 7.16e6,
            nominal_area_m2: 1e-5,
        };
        let unstable: Replicate = (
            2,
            Box::new(hypercontact_material::Ogden::new(vec![-1e6], vec![2.0]).unwrap()),
        );
        let reps = vec![
            (1, Box::new(paper_epdm()) as Box<dyn Hyperelastic>),
            unstable,
        ];
        let bands = replicate_bands(Some(reps), &law, axes, &curve, &Context::new("t"));
        assert_eq!(bands.replicates, [1, 1]);
        // E_t*(0)/E0* = 2 for the paper's tangent at ν = ½.
        assert!((bands.tangent_ratio_p50[0] - 2.0).abs() < 1e-9);
    }
}
