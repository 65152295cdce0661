//! The contact models compared (Fig. 9's tables): κ of every wired model at
//! small load, and what the theories from the spectrum were given.
//!
//! κ = (A/A0) / (F/(A0 E0* h'rms)) = (A/A0) h'rms / load_norm, the
//! dimensionless contact stiffness of the area: 1.596 for Persson's original
//! theory at vanishing load, about 2 for boundary elements on self-affine
//! surfaces (SPEC). One h'rms per sample for every model (the `stats` one:
//! forward differences on the map), so the numbers compare areas at equal
//! load, not the models' own yardsticks.

use serde::Serialize;

use crate::gather::{Response, Sample};
use crate::html::{escape, fmt_sig, simple_table};
use crate::interp::interpolate;

/// A/A0 at which κ is read: small load, and the top of the early regime.
pub const KAPPA_AREAS: [f64; 2] = [0.02, 0.1];

/// κ of each wired model of one sample at one A/A0 (None: not wired, no
/// h'rms, or A/A0 outside the curve).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct KappaAt {
    pub area_fraction: f64,
    pub icm: Option<f64>,
    pub icm_linear: Option<f64>,
    pub bem: Option<f64>,
    pub bem_linear: Option<f64>,
    pub persson: Option<f64>,
    pub gw: Option<f64>,
    pub experiment: Option<f64>,
}

/// The columns of the κ table: heading and value.
type KappaColumn = (&'static str, fn(&KappaAt) -> Option<f64>);

const COLUMNS: [KappaColumn; 7] = [
    ("hyperelastic ICM", |k| k.icm),
    ("linear ICM", |k| k.icm_linear),
    ("hyperelastic BEM", |k| k.bem),
    ("linear BEM", |k| k.bem_linear),
    ("Persson", |k| k.persson),
    ("Greenwood–Williamson", |k| k.gw),
    ("experiment", |k| k.experiment),
];

/// κ of a response at A/A0 = `a` (load_norm linearly interpolated in A/A0).
pub fn kappa_at(r: &Response, a: f64, rms_slope: f64) -> Option<f64> {
    let load = interpolate(&r.area_fraction, &r.load_norm, a)?;
    (load > 0.0 && rms_slope > 0.0).then(|| a * rms_slope / load)
}

impl KappaAt {
    /// Every wired model of `s` at `a`; `experiment` is the measured curve
    /// on the models' axes (sorted by A/A0 here).
    pub fn read(s: &Sample<'_>, experiment: Option<&Response>, a: f64) -> Self {
        let slope = s.stats.as_ref().map_or(f64::NAN, |st| st.rms_slope);
        let at = |r: &Option<Response>| r.as_ref().and_then(|r| kappa_at(r, a, slope));
        let measured = experiment.and_then(|e| {
            let mut points: Vec<(f64, f64)> = e
                .area_fraction
                .iter()
                .copied()
                .zip(e.load_norm.iter().copied())
                .collect();
            points.sort_by(|x, y| x.0.total_cmp(&y.0));
            let (area_fraction, load_norm) = points.into_iter().unzip();
            kappa_at(
                &Response {
                    area_fraction,
                    load_norm,
                    ..Default::default()
                },
                a,
                slope,
            )
        });
        KappaAt {
            area_fraction: a,
            icm: at(&s.response),
            icm_linear: at(&s.response_linear),
            bem: at(&s.bem),
            bem_linear: at(&s.bem_linear),
            persson: at(&s.persson),
            gw: at(&s.gw),
            experiment: measured,
        }
    }
}

/// The κ table under Fig. 9: a row per sample and A/A0, a column per model
/// wired anywhere. Empty when no theory from the spectrum is wired.
pub fn kappa_table(samples: &[(&str, Vec<KappaAt>)]) -> String {
    let wired: Vec<&KappaColumn> = COLUMNS
        .iter()
        .filter(|(_, get)| {
            samples
                .iter()
                .any(|(_, ks)| ks.iter().any(|k| get(k).is_some()))
        })
        .collect();
    if wired.is_empty() {
        return String::new();
    }
    let mut header = vec!["sample".to_owned(), "A/A<sub>0</sub>".to_owned()];
    header.extend(wired.iter().map(|(name, _)| (*name).to_owned()));
    let wired = &wired;
    let rows: Vec<Vec<String>> = samples
        .iter()
        .flat_map(|(label, ks)| {
            ks.iter().map(move |k| {
                let mut row = vec![escape(label), fmt_sig(k.area_fraction, 3)];
                row.extend(
                    wired
                        .iter()
                        .map(|(_, get)| get(k).map_or("n/a".into(), |v| fmt_sig(v, 3))),
                );
                row
            })
        })
        .collect();
    let mut html = simple_table(
        "κ = (A/A0) / (F/(A0 E0* h'rms)) at small load, per model",
        &header,
        &rows,
    );
    html.push_str(
        "<p class=\"note\">h'rms is the sample's rms slope from the surface statistics \
         (forward differences on the filtered map), the same for every model, so a larger κ \
         is more contact area at the same load. Loads read off each curve by linear \
         interpolation in A/A<sub>0</sub>; n/a = not wired or outside the curve. Known \
         values: Persson's original theory 1.596 at vanishing load on its own (spectral) \
         h'rms; boundary elements about 2 on self-affine surfaces, falling with load; \
         Greenwood–Williamson's κ grows without bound as the load vanishes. A hyperelastic \
         model's κ is about half its linear one (E<sub>t</sub>* ≈ 2 E<sub>0</sub>* at small \
         stress).</p>\n",
    );
    html
}

/// What Persson's theory and Greenwood–Williamson were given, per sample.
pub fn theory_table(samples: &[Sample<'_>]) -> String {
    let rows: Vec<Vec<String>> = samples
        .iter()
        .filter(|s| s.persson_summary.is_some() || s.gw_summary.is_some())
        .map(|s| {
            let n = |v: Option<f64>, digits| {
                v.filter(|v| v.is_finite())
                    .map_or("n/a".into(), |v| fmt_sig(v, digits))
            };
            let p = s.persson_summary.as_ref();
            let g = s.gw_summary.as_ref();
            let first = |v: Option<&Vec<f64>>| v.and_then(|v| v.first().copied());
            let variant = p.map_or("n/a".into(), |p| {
                match (p.variant.first(), p.gamma.first()) {
                    (Some(v), Some(g)) if g.is_finite() => {
                        format!("{} (γ = {})", escape(v), fmt_sig(*g, 3))
                    }
                    (Some(v), _) => escape(v),
                    _ => "n/a".into(),
                }
            });
            let q_range = p
                .map(|p| (first(Some(&p.q_min_per_m)), first(Some(&p.q_max_per_m))))
                .or_else(|| g.map(|g| (first(Some(&g.q_min_per_m)), first(Some(&g.q_max_per_m)))));
            let q = match q_range {
                Some((Some(lo), Some(hi))) => format!("{} … {}", fmt_sig(lo, 3), fmt_sig(hi, 3)),
                _ => "n/a".into(),
            };
            vec![
                escape(&s.label),
                variant,
                q,
                n(p.and_then(|p| first(Some(&p.rms_slope))), 3),
                n(s.stats.as_ref().map(|st| st.rms_slope), 3),
                n(p.and_then(|p| first(Some(&p.kappa_small_load))), 4),
                n(g.and_then(|g| first(Some(&g.nayak_alpha))), 3),
                n(
                    g.and_then(|g| first(Some(&g.summit_density_per_m2)))
                        .map(|v| v * 1e-6),
                    4,
                ),
                n(
                    g.and_then(|g| first(Some(&g.summit_radius_m)))
                        .map(|v| v * 1e6),
                    4,
                ),
                n(
                    g.and_then(|g| first(Some(&g.summit_sigma_m)))
                        .map(|v| v * 1e6),
                    4,
                ),
            ]
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let header = [
        "sample",
        "Persson",
        "q range (rad/m)",
        "h'rms (spectrum)",
        "h'rms (map)",
        "κ at vanishing load (linear, own h'rms)",
        "Nayak α",
        "summits per mm²",
        "summit radius (µm)",
        "summit σ<sub>s</sub> (µm)",
    ]
    .map(String::from);
    let mut html = simple_table(
        "The theories from the spectrum: what they were given",
        &header,
        &rows,
    );
    html.push_str(
        "<p class=\"note\">Both theories integrate the sample's radial PSD over the q range \
         shown (by default up to the map's Nyquist wavevector, the 20 µm filter's roll-off \
         included). The spectral h'rms = √(2π∫q³C dq) differs from the map's forward \
         differences; the shortest wavelengths kept set h'rms, and Greenwood–Williamson's \
         summit density and radius (from m<sub>4</sub>) even more so.</p>\n",
    );
    html
}
