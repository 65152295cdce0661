//! The contact experiment against the models (contact-compare's products):
//! Fig. 6, the observed and predicted contact maps of one sample side by
//! side and overlaid, each with a scale bar; the registration of every
//! sample; and the agreement table under Fig. 7.

use hypercontact_compare::stage::{AgreementTable, FigureIndex, LoadRatioTable, TRUNCATION};
use hypercontact_core::Files;
use image::{Rgb, RgbImage};

use crate::ReportError;
use crate::gather::ReportData;
use crate::html::{anchored_table, escape, fmt_sig, simple_table};

/// Scale-bar lengths tried, metres (the longest not above a quarter of the
/// image is drawn).
const BAR_LENGTHS_M: [f64; 12] = [
    5e-6, 1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2,
];

/// A file name and its PNG bytes.
pub type NamedPng = (String, Vec<u8>);

/// One row of contact-compare's figure index.
struct FigureRow {
    model: String,
    requested: f64,
    area_fraction: f64,
    model_area_fraction: f64,
    frame: i64,
    observed: String,
    predicted: String,
    overlay: String,
    /// the figure's pixel on the sample and its width in pixels
    pixel_m: f64,
    width_px: f64,
}

fn rows_of(index: &FigureIndex) -> Vec<FigureRow> {
    (0..index.model.len())
        .map(|k| FigureRow {
            model: index.model[k].clone(),
            requested: index.requested_area_fraction[k],
            area_fraction: index.area_fraction[k],
            model_area_fraction: index.model_area_fraction[k],
            frame: index.frame[k],
            observed: index.observed_file[k].clone(),
            predicted: index.predicted_file[k].clone(),
            overlay: index.overlay_file[k].clone(),
            pixel_m: index.pixel_m[k],
            width_px: index.width_px[k] as f64,
        })
        .collect()
}

/// An RGB PNG of the figures with a scale bar of `bar_px` drawn at its
/// lower left (black on a white margin).
fn with_bar(input: &str, name: &str, bytes: &[u8], bar_px: u32) -> Result<Vec<u8>, ReportError> {
    let mut image: RgbImage = image::load_from_memory(bytes)
        .map_err(|e| ReportError::input(input, format!("{name}: {e}")))?
        .into_rgb8();
    let (w, h) = image.dimensions();
    let thick = (h / 60).max(2);
    let margin = (w / 40).max(2);
    let (x0, y1) = (margin, h.saturating_sub(margin));
    let y0 = y1.saturating_sub(thick);
    let pad = (thick / 2).max(1);
    for y in y0.saturating_sub(pad)..(y1 + pad).min(h) {
        for x in x0.saturating_sub(pad)..(x0 + bar_px + pad).min(w) {
            let inside = y >= y0 && y < y1 && x >= x0 && x < x0 + bar_px;
            image.put_pixel(
                x,
                y,
                if inside {
                    Rgb([0, 0, 0])
                } else {
                    Rgb([255, 255, 255])
                },
            );
        }
    }
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| ReportError::input(input, format!("{name}: {e}")))?;
    Ok(png)
}

fn data_uri(png: &[u8]) -> String {
    use base64::Engine;
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    )
}

/// A length for the bar, as the caption writes it.
fn length_text(m: f64) -> String {
    if m >= 1e-3 {
        format!("{} mm", fmt_sig(m * 1e3, 3))
    } else {
        format!("{} µm", fmt_sig(m * 1e6, 3))
    }
}

/// The labels in first-seen order.
fn distinct<T: PartialEq + Copy>(values: impl Iterator<Item = T>) -> Vec<T> {
    let mut seen = Vec::new();
    for v in values {
        if !seen.contains(&v) {
            seen.push(v);
        }
    }
    seen
}

/// The longest bar not above a quarter of the figures' width, in metres
/// and in figure pixels.
fn bar(first: &FigureRow) -> (f64, u32) {
    let width_m = first.width_px * first.pixel_m;
    let bar_m = BAR_LENGTHS_M
        .iter()
        .copied()
        .rfind(|l| *l <= 0.25 * width_m)
        .unwrap_or(BAR_LENGTHS_M[0]);
    (bar_m, (bar_m / first.pixel_m).round() as u32)
}

/// The figures of one sample, each embedded with the scale bar and kept
/// for writing beside the page.
struct Cells<'a> {
    sample: &'a str,
    input: String,
    files: &'a Files,
    bar_px: u32,
    images: Vec<NamedPng>,
}

impl Cells<'_> {
    fn cell(&mut self, name: &str) -> Result<String, ReportError> {
        let bytes = self
            .files
            .files
            .get(name)
            .ok_or_else(|| ReportError::input(&self.input, format!("{name} is missing")))?;
        let png = with_bar(&self.input, name, bytes, self.bar_px)?;
        let out = format!("fig6_{}_{name}", self.sample);
        let html = format!(
            "<td><img src=\"{}\" alt=\"{}\" style=\"width:100%\"></td>",
            data_uri(&png),
            escape(&out)
        );
        self.images.push((out, png));
        Ok(html)
    }
}

/// The table of Fig. 6: a row per mapped area fraction, the observed map
/// and each model's predicted map and overlay.
fn fig6_grid(rows: &[FigureRow], cells: &mut Cells<'_>) -> Result<String, ReportError> {
    let models = distinct(rows.iter().map(|r| r.model.as_str()));
    let requested = distinct(rows.iter().map(|r| r.requested));
    let mut html = String::from(
        "<figure id=\"fig6\"><table class=\"fig6\"><thead><tr><th></th><th>observed</th>",
    );
    for m in &models {
        html.push_str(&format!(
            "<th>{} predicted</th><th>{} overlay</th>",
            escape(m),
            escape(m)
        ));
    }
    html.push_str("</tr></thead><tbody>\n");
    for &want in &requested {
        let of_fraction: Vec<&FigureRow> = rows.iter().filter(|r| r.requested == want).collect();
        let head = of_fraction[0];
        html.push_str(&format!(
            "<tr><th>frame {}<br>A/A<sub>0</sub> = {}</th>{}",
            head.frame,
            fmt_sig(head.area_fraction, 3),
            cells.cell(&head.observed)?
        ));
        for m in &models {
            match of_fraction.iter().find(|r| r.model == *m) {
                Some(r) => {
                    html.push_str(&cells.cell(&r.predicted)?);
                    html.push_str(&cells.cell(&r.overlay)?);
                }
                None => html.push_str("<td></td><td></td>"),
            }
        }
        html.push_str("</tr>\n");
    }
    Ok(html)
}

/// Fig. 6 for the first sample with contact-compare's figures: per mapped
/// area fraction, the observed map, and each model's predicted map and its
/// overlay on the observed one; every image at one scale with one bar.
/// Returns the HTML and the images it embeds (also written beside it).
pub fn fig6(data: &ReportData<'_>) -> Result<(String, Vec<NamedPng>), ReportError> {
    let Some((sample, (files, index))) = data
        .samples
        .iter()
        .find_map(|s| Some((s, s.compare_figures.as_ref()?)))
    else {
        return Ok((
            "<p class=\"skipped\" id=\"fig6\"><b>Fig. 6</b> skipped: no `compare_figures` \
             (contact-compare's figures) is wired.</p>\n"
                .into(),
            Vec::new(),
        ));
    };
    let input = format!("compare_figures.{}", sample.label);
    let rows = rows_of(index);
    let Some(first) = rows.first() else {
        return Ok((
            format!(
                "<p class=\"skipped\" id=\"fig6\"><b>Fig. 6</b> skipped: {} lists no map.</p>\n",
                escape(&input)
            ),
            Vec::new(),
        ));
    };
    let (bar_m, bar_px) = bar(first);
    let mut cells = Cells {
        sample: &sample.label,
        input,
        files,
        bar_px,
        images: Vec::new(),
    };
    let mut html = fig6_grid(&rows, &mut cells)?;
    html.push_str(&format!(
        "</tbody></table><figcaption><b>Fig. 6.</b> Sample {}: contact observed by the camera \
         (black) and predicted by each model on the registered scan, at the mapped frames; \
         overlay: black = contact in both, vermillion = predicted only, sky blue = observed \
         only, white = neither, grey = off the scan. Truncation = the height map cut at the \
         observed A/A<sub>0</sub> (profile theory); a model's map is its own at the nearest \
         A/A<sub>0</sub> ({}). All panels at one scale: bar = {}.</figcaption></figure>\n",
        escape(&sample.label),
        rows.iter()
            .filter(|r| r.model != TRUNCATION)
            .map(|r| format!("{} {}", escape(&r.model), fmt_sig(r.model_area_fraction, 3)))
            .collect::<Vec<_>>()
            .join(", "),
        length_text(bar_m),
    ));
    Ok((html, cells.images))
}

/// The registration of each sample's camera view onto its scan.
pub fn transform_table(data: &ReportData<'_>) -> String {
    let rows: Vec<Vec<String>> = data
        .samples
        .iter()
        .filter_map(|s| Some((s, s.transform.as_ref()?)))
        .map(|(s, t)| {
            let pm = |v: f64, sd: f64, scale: f64, digits: usize| {
                if sd.is_finite() {
                    format!(
                        "{} ± {}",
                        fmt_sig(v * scale, digits),
                        fmt_sig(sd * scale, 2)
                    )
                } else {
                    fmt_sig(v * scale, digits)
                }
            };
            vec![
                escape(&s.label),
                escape(&t.against[0]),
                format!("{} ({})", t.frame[0], fmt_sig(t.area_fraction[0], 3)),
                pm(t.angle_deg[0], t.angle_sd_deg[0], 1.0, 4),
                pm(t.shift_x_m[0], t.shift_x_sd_m[0], 1e6, 4),
                pm(t.shift_y_m[0], t.shift_y_sd_m[0], 1e6, 4),
                pm(t.scale[0], t.scale_sd[0], 1.0, 5),
                fmt_sig(t.zncc[0], 3),
            ]
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let header: Vec<String> = [
        "sample",
        "registered against",
        "frame (A/A<sub>0</sub>)",
        "turn (°)",
        "shift x (µm)",
        "shift y (µm)",
        "scale",
        "ZNCC",
    ]
    .map(String::from)
    .to_vec();
    let mut html = simple_table(
        "Registration of the camera's view onto the scan (contact-compare)",
        &header,
        &rows,
    );
    html.push_str(
        "<p class=\"note\">The camera pixel at p from the frame's centre sees the scan point \
         R(turn) p + shift from the scan's centre; scale = the camera's pixel on the sample \
         over the nominal one. ± = standard deviation of the registrations made at each mapped \
         frame on its own.</p>\n",
    );
    html
}

/// One sample's contact-compare tables, as the agreement table reads them.
pub struct Scored<'a> {
    pub label: &'a str,
    pub agreement: &'a AgreementTable,
    pub load_ratio: Option<&'a LoadRatioTable>,
}

/// The samples with an agreement table.
pub(crate) fn scored<'a>(data: &'a ReportData<'_>) -> Vec<Scored<'a>> {
    data.samples
        .iter()
        .filter_map(|s| {
            Some(Scored {
                label: &s.label,
                agreement: s.agreement.as_ref()?,
                load_ratio: s.load_ratio.as_ref(),
            })
        })
        .collect()
}

/// The experiment's physics as contact-compare names it (its truth's
/// physics string); None when no truth was wired.
pub(crate) fn physics_of(a: &AgreementTable) -> Option<&str> {
    a.experiment_physics
        .iter()
        .find(|p| !p.is_empty())
        .map(String::as_str)
}

/// The models marked by construction (their physics is the experiment's).
pub(crate) fn marked(a: &AgreementTable) -> Vec<&str> {
    (0..a.model.len())
        .filter(|&k| a.by_construction.get(k).is_some_and(|&b| b != 0))
        .map(|k| a.model[k].as_str())
        .collect()
}

/// What the captions of Figs. 7 and 9 and the experiment's section say of
/// the experiment's physics: per group of samples with the same physics and
/// the same marked models, the physics and which models share it. Empty
/// when no sample names a physics or marks a model.
pub fn physics_sentence(samples: &[Scored<'_>]) -> String {
    let mut groups: Vec<(Option<&str>, Vec<&str>, Vec<&str>)> = Vec::new();
    for s in samples {
        let (physics, models) = (physics_of(s.agreement), marked(s.agreement));
        if physics.is_none() && models.is_empty() {
            continue;
        }
        match groups.iter_mut().find(|g| g.0 == physics && g.1 == models) {
            Some(g) => g.2.push(s.label),
            None => groups.push((physics, models, vec![s.label])),
        }
    }
    let mut text = String::new();
    for (physics, models, labels) in groups {
        let shared = if models.is_empty() {
            "no compared model shares it".to_owned()
        } else {
            format!(
                "{} {} it, so {} with the experiment by construction (marked, not ranked)",
                escape(&models.join(", ")),
                if models.len() == 1 { "shares" } else { "share" },
                if models.len() == 1 { "agrees" } else { "agree" },
            )
        };
        text.push_str(&format!(
            " The experiment of {}: {}; {shared}.",
            escape(&labels.join(", ")),
            match physics {
                Some(p) => format!("rendered by <i>{}</i>", escape(p)),
                None => "its physics not stated (no truth wired)".to_owned(),
            }
        ));
    }
    text
}

/// The same for the report's data.
pub fn experiment_physics(data: &ReportData<'_>) -> String {
    physics_sentence(&scored(data))
}

/// The anchor of the agreement table.
pub const AGREEMENT_ID: &str = "agreement-table";

/// The agreement of each model's load–area curve with the experiment, per
/// sample, best first, with the load ratios.
pub fn agreement_table(data: &ReportData<'_>) -> String {
    agreement_html(&scored(data))
}

/// [`agreement_table`] of the samples' tables: a model marked by
/// construction shows "by construction" in place of a rank, after the
/// ranked ones.
pub fn agreement_html(samples: &[Scored<'_>]) -> String {
    if samples.is_empty() {
        return String::new();
    }
    let mut fractions: Vec<f64> = Vec::new();
    for s in samples {
        for &a in s.load_ratio.iter().flat_map(|r| &r.area_fraction) {
            if !fractions.contains(&a) {
                fractions.push(a);
            }
        }
    }
    let mut rows = Vec::new();
    for s in samples {
        let a = s.agreement;
        let by_construction = |k: usize| a.by_construction.get(k).is_some_and(|&b| b != 0);
        let mut order: Vec<usize> = (0..a.model.len()).collect();
        order.sort_by_key(|&k| (by_construction(k), a.rank[k]));
        for k in order {
            let mut row = vec![
                escape(s.label),
                if by_construction(k) {
                    "by construction".to_owned()
                } else {
                    a.rank[k].to_string()
                },
                escape(&a.model[k]),
                escape(&a.area[k]),
                fmt_sig(a.rms_log_ratio[k], 3),
                fmt_sig(a.mean_log_ratio[k], 3),
                a.points[k].to_string(),
            ];
            for &want in &fractions {
                let ratio = s.load_ratio.and_then(|r| {
                    (0..r.model.len())
                        .find(|&i| r.model[i] == a.model[k] && r.area_fraction[i] == want)
                        .map(|i| r.load_ratio[i])
                });
                row.push(match ratio {
                    Some(v) if v.is_finite() => fmt_sig(v, 3),
                    _ => "n/a".into(),
                });
            }
            rows.push(row);
        }
    }
    let mut header: Vec<String> = [
        "sample",
        "rank",
        "model",
        "model A/A<sub>0</sub> read on",
        "rms ln(F<sub>model</sub>/F<sub>exp</sub>)",
        "mean ln(F<sub>model</sub>/F<sub>exp</sub>)",
        "frames",
    ]
    .map(String::from)
    .to_vec();
    header.extend(
        fractions
            .iter()
            .map(|a| format!("F<sub>model</sub>/F<sub>exp</sub> at A/A<sub>0</sub> = {a}")),
    );
    let mut html = anchored_table(
        AGREEMENT_ID,
        "Agreement of the models with the contact experiment (load at equal contact area)",
        &header,
        &rows,
    );
    html.push_str(&agreement_note(&physics_sentence(samples)));
    html
}

/// The note under the agreement table, with what the experiment's physics
/// is (`physics`, from [`physics_sentence`]).
fn agreement_note(physics: &str) -> String {
    format!(
        "<p class=\"note\">At every measured frame in the scored range the model's load at the \
         measured A/A<sub>0</sub> (interpolated log-log on its curve, never extrapolated) over \
         the measured force; rank 1 = the smallest rms among the models judged. A mean below \
         0: the model reaches the area at a smaller load than measured. The measured \
         A/A<sub>0</sub> is that of the camera's view; a model's is read on the view (its own \
         contact maps, or profile theory's truncation, inside the registered view) or on the \
         whole scan, as the fourth column says (the rim of a free sample lifts off, so the two \
         differ by up to a third at A/A<sub>0</sub> = 0.5). <b>What the score measures depends \
         on where the images come from.</b> When the experiment is the synthetic lab's \
         (<code>synth-contact</code>), its physics is one model's: a model of that physics \
         agrees with it by construction (its score measures only what the imaging, the image \
         analysis and the scan add, not whether the physics is right), so it is shown \
         <i>by construction</i> instead of ranked.{physics} On a lab's real images every \
         model is judged alike, against the rubber itself.</p>\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const LINEAR: &str = "bem, linear elastic, small-strain modulus, free boundary";

    fn agreement(marked: [i64; 3], physics: &str) -> AgreementTable {
        AgreementTable {
            model: vec!["icm".into(), "bem-linear".into(), "bem".into()],
            rms_log_ratio: vec![0.5, 0.01, 0.7],
            mean_log_ratio: vec![0.5, 0.0, 0.7],
            points: vec![9; 3],
            outside_model: vec![0; 3],
            area: vec!["whole".into(); 3],
            rank: marked
                .iter()
                .scan(0, |r, &m| {
                    *r += 1 - m;
                    Some(if m == 1 { 0 } else { *r })
                })
                .collect(),
            by_construction: marked.to_vec(),
            experiment_physics: vec![physics.into(); 3],
        }
    }

    /// #49: a model marked by construction shows so in place of a rank,
    /// after the ranked ones, and the note names the experiment's physics.
    #[test]
    fn a_model_of_the_experiments_physics_shows_by_construction_not_a_rank() {
        let marked = agreement([0, 1, 0], LINEAR);
        let ratios = LoadRatioTable {
            model: vec!["icm".into(), "bem-linear".into(), "bem".into()],
            area_fraction: vec![0.5; 3],
            load_ratio: vec![1.6, 1.0, 2.0],
            by_construction: vec![0, 1, 0],
            experiment_physics: vec![LINEAR.into(); 3],
        };
        let samples = [Scored {
            label: "T1",
            agreement: &marked,
            load_ratio: Some(&ratios),
        }];
        let html = agreement_html(&samples);
        let icm = html.find("<td>T1</td><td>1</td><td>icm</td>").unwrap();
        let bem = html.find("<td>T1</td><td>2</td><td>bem</td>").unwrap();
        let own = html
            .find(
                "<td>T1</td><td>by construction</td><td>bem-linear</td><td>whole</td><td>0.01</td>",
            )
            .unwrap();
        assert!(icm < bem && bem < own, "{html}");
        assert!(!html.contains("<td>0</td><td>bem-linear"), "{html}");
        assert!(
            html.contains(
                "The experiment of T1: rendered by <i>bem, linear elastic, small-strain \
                 modulus, free boundary</i>; bem-linear shares it, so agrees with the \
                 experiment by construction (marked, not ranked)."
            ),
            "{html}"
        );
    }

    /// Samples of one physics are named together; a sample whose physics
    /// no model shares says so; tables without truth or marks say nothing.
    #[test]
    fn the_physics_sentence_groups_samples_and_says_when_no_model_shares_it() {
        let hyper = "bem, hyperelastic, equibiaxial tangent, free boundary";
        let (t1, t2) = (agreement([0, 1, 0], LINEAR), agreement([0, 1, 0], LINEAR));
        let t3 = agreement([0, 0, 0], hyper);
        let plain = agreement([0, 0, 0], "");
        let scored = |label, agreement| Scored {
            label,
            agreement,
            load_ratio: None,
        };
        let text = physics_sentence(&[
            scored("T1", &t1),
            scored("T2", &t2),
            scored("T3", &t3),
            scored("T4", &plain),
        ]);
        assert!(text.starts_with(" The experiment of T1, T2: rendered by <i>bem, linear"));
        assert!(text.ends_with(
            " The experiment of T3: rendered by <i>bem, hyperelastic, equibiaxial tangent, \
             free boundary</i>; no compared model shares it."
        ));
        assert!(!text.contains("T4"), "{text}");
        // The table of before #49's columns' defaults: ranks as they are.
        let html = agreement_html(&[scored("T4", &plain)]);
        assert!(html.contains("<td>T4</td><td>1</td><td>icm</td>"), "{html}");
        assert!(!html.contains("<td>by construction</td>"), "{html}");
    }
}
