//! Stage `contact-images`: a contact-interference image sequence and its
//! force log in, the measured contact area and patch count per frame out
//! (the paper's Section 3 experiment), with binary contact maps for Fig. 6.
//! The physics of the methods is in [`mod@crate::otsu`], [`mod@crate::multi_otsu`]
//! and [`crate::calibrated`]; reading in [`hypercontact_labfiles::sequence`];
//! the analysis of the frames and the clock in `analysis.rs`.

use hypercontact_core::contact::{ObservedMapIndex, area_fraction_label, check_map_fraction};
use hypercontact_core::{
    Arity, Checked, Choice, Context, Files, InputPath, InputSpec, Inputs, OutputSpec, Outputs,
    ParamError, Schema, Stage, StageError, StageInfo, params,
};
use hypercontact_labfiles::FileSource;
use hypercontact_labfiles::sequence::Sequence;

use crate::Mask;
use crate::analysis::analyse;

/// How contact is told from the rest of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Choice)]
pub enum Method {
    /// flat-field with the reference frame, threshold between contact and background, hysteresis, minimum patch
    #[default]
    Calibrated,
    /// the paper's: global Otsu per frame on the full histogram
    Otsu,
    /// three-class Otsu, the darkest class is contact
    MultiOtsu,
}

impl Method {
    pub(crate) fn label(self) -> &'static str {
        match self {
            Method::Calibrated => "calibrated",
            Method::Otsu => "otsu",
            Method::MultiOtsu => "multi-otsu",
        }
    }
}

/// Parameters of `contact-images`.
#[params(check = consistent)]
pub struct ContactImagesParams {
    /// segmentation method
    #[param(default = Method::Calibrated)]
    pub method: Method,
    /// folder with the frames (listed in frames.csv, or with their times in their names) and force.csv (instead of the `sequence` input)
    pub dir: Option<InputPath>,
    /// the camera's bit depth when the files' container is deeper (a 12-bit camera in 16-bit files: 12)
    #[param(range = 1..=16)]
    pub bits: Option<u8>,
    /// camera pixel size on the sample (sensor pixel / magnification)
    #[param(default = 6.5e-6, unit = "m", positive)]
    pub pixel_m: f64,
    /// exposure time; force is read at mid-exposure (0: the frame times are mid-exposure)
    #[param(default = 0.0, unit = "s", range = 0.0..)]
    pub exposure_s: f64,
    /// force-log time minus camera time (default: estimated from first contact); must keep every frame inside force.csv's times
    #[param(unit = "s")]
    pub clock_offset_s: Option<f64>,
    /// force-log resolution, for the onset of the force in the offset estimate
    #[param(default = 0.01, unit = "N", range = 0.0..)]
    pub force_resolution_n: f64,
    /// calibrated: index (in time order, from 0) of a frame without contact, the flat field (refused below half the brightest frame's mean signal: in contact; a warning below 90 %)
    #[param(default = 0)]
    pub reference_frame: usize,
    /// calibrated: camera dark offset in counts
    #[param(default = 0.0, range = 0.0..)]
    pub dark_level: f64,
    /// calibrated: intensity of contact relative to the reference (≈ 0: contact is black)
    #[param(default = 0.0, range = 0.0..)]
    pub contact_level: f64,
    /// calibrated: intensity of the background relative to the reference (1: same illumination)
    #[param(default = 1.0, positive)]
    pub background_level: f64,
    /// calibrated: contact joins below this fraction of the way from contact to background
    #[param(default = 0.2, positive, range = ..1.0)]
    pub fraction: f64,
    /// calibrated: contact seeds below this fraction (hysteresis; = fraction turns it off)
    #[param(default = 0.1, positive, range = ..1.0)]
    pub seed_fraction: f64,
    /// calibrated: smallest patch kept
    #[param(default = 4, unit = "px", range = 1..)]
    pub min_patch_pixels: u64,
    /// A/A0 at which `contact_maps` holds the binary contact map (nearest frame)
    #[param(default = vec![0.1, 0.5, 0.9], positive, range = ..=1.0)]
    pub map_fractions: Vec<f64>,
}

fn consistent(p: &ContactImagesParams) -> Result<(), ParamError> {
    if p.seed_fraction > p.fraction {
        return Err(ParamError::new(
            "seed_fraction",
            format!(
                "{} lies above fraction ({}): seeds must be darker than what joins them",
                p.seed_fraction, p.fraction
            ),
        ));
    }
    if p.contact_level >= p.background_level {
        return Err(ParamError::new(
            "contact_level",
            format!(
                "{} is not below background_level ({})",
                p.contact_level, p.background_level
            ),
        ));
    }
    (0..p.map_fractions.len()).try_for_each(|i| check_map_fraction(&p.map_fractions, i))
}

/// The `contact` table: one row per frame.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct ContactTable {
    /// frame number as frames.csv gives it
    pub frame: Vec<i64>,
    /// camera time at mid-exposure
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// force interpolated at time_s + clock offset
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
    /// contact pixels / analysed pixels
    pub area_fraction: Vec<f64>,
    /// contact pixels × pixel area
    #[column(unit = "m²")]
    pub contact_area_m2: Vec<f64>,
    /// 8-connected contact patches
    pub patches: Vec<i64>,
    /// the threshold used (counts for otsu/multi-otsu; intensity relative to the reference for calibrated)
    pub threshold: Vec<f64>,
    /// segmentation method
    pub method: Vec<String>,
}

/// The `sync` table: one row.
#[derive(Clone, Debug, PartialEq, Schema)]
pub struct SyncTable {
    /// force-log time minus camera time
    #[column(unit = "s")]
    pub clock_offset_s: Vec<f64>,
    /// 1 when estimated (from the trigger or first contact), 0 when given
    pub estimated: Vec<i64>,
    /// how: given, trigger (the camera's exposure signal in force.csv) or first-contact
    pub source: Vec<String>,
    /// force-log time at which the force leaves its baseline (NaN if given or not found)
    #[column(unit = "s")]
    pub force_onset_s: Vec<f64>,
    /// camera time half-way between the last frame without contact and the first with (NaN if given or not found)
    #[column(unit = "s")]
    pub contact_onset_s: Vec<f64>,
}

/// The `contact-images` stage.
pub struct ContactImages;

/// The index of `contact_maps`: the observed maps' columns, then when the
/// frame was taken and the force then.
#[derive(Clone, Debug, Default, PartialEq, Schema)]
pub struct ContactMapIndex {
    #[column(flatten)]
    pub maps: ObservedMapIndex,
    /// the frame's time
    #[column(unit = "s")]
    pub time_s: Vec<f64>,
    /// the force at that time
    #[column(unit = "N")]
    pub force_n: Vec<f64>,
}

static INFO: StageInfo = StageInfo {
    kind: "contact-images",
    version: 4,
    summary: "Contact area and patches per frame from contact-interference images and a force log",
    doc: "Reads frames.csv (frame, time_s, file; time_s = exposure start on the camera's clock) \
          or, without it, every PNG/TIFF file whose name carries its time (a field such as \
          `t1.25s`, `1250ms` or `250000us` between `_`, `-` or spaces: img_0007_t1.25s.tif; the \
          frames in time order, the frame number the name's digit field), the frames (PNG or \
          TIFF, 8 or 16 bit; \
          `bits` for a camera shallower than its files, e.g. 12-bit data in 16-bit files, which \
          are then NOT rescaled, and values at or above 2^bits are refused) and force.csv \
          (time_s, force_n), from the `sequence` input (the synthetic lab's files) or `dir`; \
          a frame number or a file listed twice is refused. \
          Contact regions are dark (the half-wave loss at the rubber). METHODS: `calibrated` \
          (default): each frame divided by the reference frame (a frame without contact: the \
          flat field, vignetting and illumination cancel), contact where the ratio is below \
          contact_level + fraction (background_level - contact_level), grown from seeds below \
          seed_fraction (hysteresis, 8-connected), patches under min_patch_pixels dropped; \
          pixels whose reference is dark are never contact. With the defaults (0, 1, 0.2, \
          seeds 0.1) contact means an intensity below a fifth of the background's: 'optical \
          contact', a gap of at most a few tens of nm under white light (half the background \
          is reached at 42 nm, crate `interference`), so A is overestimated where the gap \
          opens slowly (a sphere of R = 5 mm: +23 % at A/A0 = 0.04, +2 % at 0.65; a rough \
          self-affine sample from synth-contact: +10 % at A/A0 = 0.06, +3 % at 0.84). `otsu`: the paper's global Otsu \
          threshold per frame on the full 2^bits histogram; it counts dark interference \
          fringes (the second dark fringe near 265 nm is a third of the background) and dim \
          corners as contact, so it overestimates A at low load (the rough sample: +16 to +20 % \
          up to A/A0 = 0.25, +5 to +8 % above 0.6, and 2 to 56 times the patches, the fringe \
          rings and noise specks) and splits a frame without contact into two classes (44 % \
          'contact' on a vignetted no-contact frame). `multi-otsu`: three classes, \
          the darkest is contact. A0 = the frame's pixels (all pixels are the sample's); area = \
          contact pixels x pixel_m². Patches: 8-connected components. SYNC: force-log time = \
          camera time + clock_offset_s; force linearly interpolated at mid-exposure (time_s + \
          exposure_s/2). Without clock_offset_s, when force.csv has a column camera_trigger (the \
          camera's exposure signal logged with the force: 0/1 or volts), each run of high \
          samples is one exposure, its centre the mean of the middles of its rising and falling \
          gaps, and the offset is the median of (centre - frame mid-exposure time); the \
          exposures must match the frames one to one (good to a fraction of a log sample: \
          within 5 ms at 50 Hz). Otherwise the offset is estimated as the time the force \
          leaves its baseline (detected at 6 robust sigma of the first 16 samples, at least \
          twice force_resolution_n, and dated back to the last sample at the baseline) minus \
          the time half-way between the last frame without contact and the first with, as the \
          calibrated method sees it (whatever `method` is: a global threshold finds \
          'contact' in every frame), so it needs reference_frame: good to about one frame \
          interval when the sequence starts before contact, and late by both the position of \
          the touch between two frames and the time the force takes to rise out of the log's \
          noise (measured on synth-contact's rough samples at frame intervals of 2.3-12.3 s: \
          1.1-3.7 s late, 0.30-0.46 of an interval, so the force was read 26-41 % high at \
          A/A0 = 0.1 and 4-5 % at 0.5; log the camera's trigger when the load matters at low \
          area). CONTACT_MAPS: for each \
          of map_fractions, the frame whose A/A0 is nearest, as mask_a<fraction>.png (8-bit, \
          255 = contact), indexed by the table contact_maps.parquet (requested and kept A/A0, \
          frame, file, pixel_m, time_s, force_n).",
    inputs: &[InputSpec::files(
        "sequence",
        Arity::Optional,
        "the synthetic lab's files (or use `dir`)",
    )],
    outputs: &[
        OutputSpec::table::<ContactTable>("contact", "one row per frame"),
        OutputSpec::table::<SyncTable>("sync", "the clock offset used, and how it was found"),
        OutputSpec::files_indexed::<ContactMapIndex>(
            "contact_maps",
            "binary contact maps (PNG) at map_fractions, indexed",
        ),
    ],
};

impl Stage for ContactImages {
    type Params = ContactImagesParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<ContactImagesParams>,
        inputs: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let source = FileSource::input_or_dir(inputs, "sequence", "dir", p.dir.as_ref())?;
        let sequence = Sequence::open(source)?;
        let analysis = analyse(&sequence, p, ctx)?;
        let files = map_files(analysis.maps, &analysis.contact, p)?;
        Ok(Outputs::new()
            .table("contact", analysis.contact.into_table())
            .table("sync", analysis.sync.into_table())
            .files("contact_maps", files))
    }
}

fn map_files(
    maps: Vec<Option<(usize, Mask)>>,
    table: &ContactTable,
    p: &ContactImagesParams,
) -> Result<Files, StageError> {
    let mut files = Files::new();
    let mut index = ContactMapIndex::default();
    for (slot, &want) in maps.into_iter().zip(&p.map_fractions) {
        let Some((k, mask)) = slot else { continue };
        let name = format!("mask_{}.png", area_fraction_label(want));
        let pixels: Vec<u8> = mask
            .pixels()
            .iter()
            .map(|&c| if c { 255 } else { 0 })
            .collect();
        let png = hypercontact_labfiles::png::encode_png(
            mask.width() as u32,
            mask.height() as u32,
            hypercontact_labfiles::png::Pixels::Gray8(pixels),
        )
        .map_err(StageError::invalid)?;
        let m = &mut index.maps;
        m.requested_area_fraction.push(want);
        m.area_fraction.push(table.area_fraction[k]);
        m.frame.push(table.frame[k]);
        m.file.push(name.clone());
        m.pixel_m.push(p.pixel_m);
        index.time_s.push(table.time_s[k]);
        index.force_n.push(table.force_n[k]);
        files.files.insert(name, png);
    }
    Ok(files.with_index(index))
}
