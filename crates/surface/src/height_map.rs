//! Stage `height-map`: loads one height map, from a `.npy` array or from an
//! instrument's own file (the formats of `hypercontact-formats`: optical
//! profilometers, AFMs, stylus profiles, text exports), the format told by
//! the file's first bytes; one channel of a multi-channel file.

use hypercontact_core::{
    Checked, Context, Field, InputPath, Inputs, OutputSpec, Outputs, ParamError, Stage, StageError,
    StageInfo, params,
};
use std::io::{Read, Seek, SeekFrom};

use hypercontact_formats::{Format, Topography};

use crate::channel_param::ChannelParam;
use crate::level_rows::Axis;
use crate::prepare::{FastAxis, FormKind, LevelRows, SpikeRule, StatedFastAxis, prepare};
use crate::tip_cutoff::tip_reliability_cutoff_m;

/// Parameters of `height-map`.
#[params(check = one_window)]
pub struct HeightMapParams {
    /// the height map: .npy (2-D float64/float32, axis 0 = x, NaN = missing) or an instrument file of a format listed below
    pub path: InputPath,
    /// the channel of a multi-channel file (AFM height, deflection, phase ...): its position from 0 in the list the note gives, or its name (default: the height channel SurfaceTopography reads first)
    pub channel: Option<ChannelParam>,
    /// grid spacing along x (needed for .npy; for an instrument file it replaces the file's)
    #[param(unit = "m", positive)]
    pub pixel_m: Option<f64>,
    /// grid spacing along y (default: pixel_m, or the file's)
    #[param(unit = "m", positive)]
    pub pixel_y_m: Option<f64>,
    /// factor from .npy units to metres (1e-6 for micrometres; instrument files state their units)
    #[param(default = 1.0, unit = "m/unit", positive)]
    pub scale_to_m: f64,
    /// a window in points, [x0, y0, nx, ny] (axis 0 = x), cut out first
    pub crop_points: Option<[usize; 4]>,
    /// a window in metres from the map's first point, [x0_m, y0_m, lx_m, ly_m] (instead of crop_points)
    #[param(unit = "m")]
    pub crop_m: Option<[f64; 4]>,
    /// keep only the disc [xc_m, yc_m, radius_m] (metres from the map's first point); the rest becomes NaN
    #[param(unit = "m")]
    pub circle_m: Option<[f64; 3]>,
    /// points to keep: a .npy (2-D bool, uint8 or float 0/1, axis 0 = x) of the map's shape as read; its false/0 points become NaN first, before the window
    pub mask: Option<InputPath>,
    /// spikes set to NaN (after the window, before the form)
    #[param(default = SpikeRule::None)]
    pub spikes: SpikeRule,
    /// spike threshold, in robust standard deviations (1.4826 MAD)
    #[param(default = 5.0, positive)]
    pub spike_k: f64,
    /// half-width of the neighbourhood of the local spike rule: 1 = 3 x 3, 2 = 5 x 5, 3 = 7 x 7
    #[param(default = 1, range = 1..=3)]
    pub spike_radius: usize,
    /// the form subtracted (after spikes, before the scan lines are levelled)
    #[param(default = FormKind::None)]
    pub form: FormKind,
    /// total degree of the polynomial form
    #[param(default = 2, range = 0..=6)]
    pub form_degree: usize,
    /// scan-line levelling, last: each line along the fast axis has its median, mean, least-squares tilt or polynomial subtracted, or is shifted so the median of its differences to the line before is zero; NaN points take no part
    #[param(default = LevelRows::None)]
    pub level_rows: LevelRows,
    /// degree of each scan line's least-squares polynomial for level_rows: polynomial (0 = the mean, 1 = the tilt)
    #[param(default = 2, range = 0..=6)]
    pub level_rows_degree: usize,
    /// the axis along which each scan line ran, for level_rows (default: the file's where its format states it, x for the AFM formats read; otherwise x)
    pub fast_axis: Option<FastAxis>,
    /// radius of the probe's tip (AFM, stylus): the map is then reliable only at length scales above the cut-off λ_c where its most negative scale-dependent curvature (the second difference spanning λ along x) reaches −1/(2 R), SurfaceTopography's short_reliability_cutoff (Sanner et al., Appl. Surf. Sci. Adv. 7, 100190, 2022); λ_c goes with the height field (its grid.json, short_cutoff_m) and into a note
    #[param(unit = "m", positive)]
    pub tip_radius_m: Option<f64>,
    /// the most points a map may have (default 2^26 = 67 108 864, 512 MiB of heights); a file whose header claims more is refused before its data is read or inflated
    #[param(default = 67_108_864, range = 1..=2_147_483_647)]
    pub max_points: usize,
}

fn one_window(p: &HeightMapParams) -> Result<(), ParamError> {
    if p.crop_points.is_some() && p.crop_m.is_some() {
        return Err(ParamError::new(
            "crop_m",
            "give the window once: crop_points or crop_m, not both",
        ));
    }
    Ok(())
}

/// The `height-map` stage.
pub struct HeightMap;

static INFO: StageInfo = StageInfo {
    kind: "height-map",
    version: 3,
    summary: "Load a height map (.npy or an instrument file) with its grid spacing",
    doc: "Reads a height map as the instrument wrote it. The format is told by the first \
          bytes, the extension only where bytes cannot tell (text): optical profilers and \
          interferometers (ISO 25178-72 X3P, Digital Surf .sur and MountainsMap .mnt, Sensofar \
          .plu, Zygo MetroPro .dat and .datx, Wyko .opd, Alicona .al3d, FRT .frt, TrueMap/GelSight \
          .tmd), AFMs (Bruker Nanoscope .di, Nanosurf .nid, Asylum/Igor .ibw, Molecular Imaging \
          .mi), NetCDF .nc as SurfaceTopography writes it, text (an ASCII matrix with or without \
          a header stating grid, pixel size and units; Gwyddion's ASCII export) and the Dektak \
          stylus .csv (a line scan: an n x 1 map along x), each with its units and pixel size \
          (non-square pixels kept; missing points NaN) and equal to what SurfaceTopography 1.x \
          reads; or a 2-D .npy array (float64 or float32) whose axis 0 is x, as the \
          SurfaceTopography package writes it, which holds no spacing: `pixel_m` is then \
          required and values are multiplied by `scale_to_m`. CHANNELS: a multi-channel file \
          gives its height channel (the one SurfaceTopography reads by default) unless \
          `channel` names another by position or name; the note lists the channels found. For \
          an instrument file `pixel_m` / `pixel_y_m` replace the file's spacing (a \
          recalibration; the note says by how much) and `scale_to_m` must stay 1. The note \
          names the format, the grid, the missing points and the instrument where the file \
          says. A file no reader knows is refused naming what its bytes look like and the \
          formats read. PREPARATION, in this order, each step in a note with what it removed: \
          a mask (`mask`: a .npy file of the map's shape as read, axis 0 = x, bool true or \
          uint8/float 1 = keep, false/0 = drop, any other value refused; its dropped points \
          become NaN; a mask of another shape is refused naming both shapes; crop_m already \
          gives a rectangle); a window (`crop_points`, or `crop_m` from the map's first point: first point \
          round(x0/dx), end round((x0 + lx)/dx)); a disc kept (`circle_m`, the rest NaN); \
          spikes set to NaN (`spikes: local`: a point farther than spike_k robust standard \
          deviations (1.4826 MAD of all such deviations) from the median of what its \
          neighbours within spike_radius predict along each direction, confirmed with the \
          other candidates left out; `global`: farther than spike_k robust σ from the median \
          height); a form subtracted (`form`: a least-squares polynomial of total degree \
          form_degree in Legendre polynomials of centred, scaled coordinates; a sphere or a \
          cylinder (axis along x, y or fitted in the plane), Levenberg-Marquardt from an \
          algebraic (Kasa) start on the vertical residual); the scan lines levelled \
          (`level_rows`, the methods of Gwyddion's Align Rows: each line along the fast axis \
          has its `median` or `mean` height, its least-squares `tilt` or its least-squares \
          `polynomial` of degree level_rows_degree (Legendre, in the position along the line) \
          subtracted, or with `median-differences` is shifted so that the median of its height \
          differences to the line before is zero, the shifts then moved by their median; NaN \
          points take no part; a line with no more measured points than the model has unknowns \
          (for median-differences, without one shared with the line before) is left as is and \
          counted; the note gives the rms of what was removed). The fast axis is the file's \
          where its format states it (the AFM formats read: x, each stored row a scan line), \
          `fast_axis` where given (it overrides the file, the note saying so), x otherwise. \
          Spikes go before the form, which they would pull; the lines are levelled on what the \
          form leaves, as a line's own median or tilt would take its share of a curved form. \
          All are off by default: the map is given as measured, and `surface` removes a plane. \
          RELIABLE RANGE: with `tip_radius_m` = R (a probe's tip), the map as prepared gets the \
          short-wavelength cut-off of SurfaceTopography's `short_reliability_cutoff` (Sanner et \
          al., Appl. Surf. Sci. Adv. 7, 100190, 2022): the span λ_c of the central second \
          difference [h(x + λ/2) − 2h(x) + h(x − λ/2)]/(λ/2)² along x (heights between points \
          interpolated linearly; points whose stencil leaves the map, or touches a NaN, left \
          out) at which its most negative value over the map is −1/(2R), the safety factor 1/2 \
          of the paper, found by Brent's method between twice the mean spacing and half the mean \
          side. Below λ_c the tip, not the surface, shapes the map. No cut-off when the map's \
          curvature stays above −1/(2R) at twice the spacing (the tip resolves the grid); the \
          mean side when it is below even at half of it (nothing reliable). The cut-off goes \
          with the height field, as `short_cutoff_m` in its grid sidecar, and into a note.",
    inputs: &[],
    outputs: &[OutputSpec::field(
        "height",
        "heights in metres, NaN where not measured",
    )],
};

impl Stage for HeightMap {
    type Params = HeightMapParams;

    fn info(&self) -> &'static StageInfo {
        &INFO
    }

    fn run(
        &self,
        p: &Checked<HeightMapParams>,
        _: &Inputs,
        ctx: &Context,
    ) -> Result<Outputs, StageError> {
        let (map, stated) = read_map(p, ctx)?;
        let field = prepare(map, stated, p, ctx)?;
        if field.values.iter().all(|h| h.is_nan()) {
            return Err(StageError::file(&p.path, "every point is NaN"));
        }
        if let Some(bad) = field.values.iter().find(|h| h.is_infinite()) {
            return Err(StageError::file(
                &p.path,
                format!("holds an infinite height ({bad})"),
            ));
        }
        let field = with_tip_cutoff(field, p, ctx)?;
        Ok(Outputs::new().field("height", field))
    }
}

/// The map with the reliability cut-off of a tip of `tip_radius_m`, when
/// one is given, and a note saying what it is.
fn with_tip_cutoff(field: Field, p: &HeightMapParams, ctx: &Context) -> Result<Field, StageError> {
    let Some(radius_m) = p.tip_radius_m else {
        return Ok(field);
    };
    let cutoff_m = tip_reliability_cutoff_m(&field, radius_m)
        .map_err(|e| StageError::file(&p.path, format!("tip_radius_m: {e}")))?;
    let (dx_m, dy_m) = (field.dx_m, field.dy_m);
    let length = |m: f64| {
        if m < 1e-6 {
            format!("{:.4} nm", m * 1e9)
        } else {
            format!("{:.4} µm", m * 1e6)
        }
    };
    let tip = format!("tip: R = {}", length(radius_m));
    ctx.note(&match cutoff_m {
        None => format!(
            "{tip} resolves every scale of the grid (the map curves down by less than 1/(2R) \
             already over twice the spacing, {}): no short cut-off",
            length(match (field.nx(), field.ny()) {
                (1, _) => 2.0 * dy_m,
                (_, 1) => 2.0 * dx_m,
                _ => dx_m + dy_m,
            })
        ),
        Some(m) => format!(
            "{tip}: reliable above λ_c = {} (short_cutoff_m = {m:e}; below it the map curves down \
             by more than 1/(2R) and the tip, not the surface, shapes it; SurfaceTopography's \
             short_reliability_cutoff)",
            length(m)
        ),
    });
    field
        .with_short_cutoff_m(cutoff_m)
        .map_err(|e| StageError::file(&p.path, format!("tip_radius_m: {e}")))
}

/// The map, its format told by the file's first bytes: a `.npy` array is
/// judged by its header before its data is read; an instrument file by its
/// reader, with the points limit; anything else is named for what it is.
/// With it, the fast axis where the file states one.
fn read_map(
    p: &HeightMapParams,
    ctx: &Context,
) -> Result<(Field, Option<StatedFastAxis>), StageError> {
    let path: &std::path::Path = &p.path;
    hypercontact_core::regular_file::check_regular_file(path)?;
    let io_error = |e: std::io::Error| StageError::file(path, e.to_string());
    let mut file = std::fs::File::open(path).map_err(io_error)?;
    let file_bytes = file.metadata().map_err(io_error)?.len();
    let mut magic = Vec::new();
    (&mut file)
        .take(6)
        .read_to_end(&mut magic)
        .map_err(io_error)?;
    if magic == b"\x93NUMPY" {
        if p.channel.is_some() {
            return Err(StageError::file(
                path,
                "is a .npy array, which holds one map: leave out `channel`",
            ));
        }
        file.seek(SeekFrom::Start(0)).map_err(io_error)?;
        return Ok((read_npy(p, file, file_bytes)?, None));
    }
    let bytes = read_bounded(p, file, file_bytes)?;
    match hypercontact_formats::detect(&bytes, Some(path)) {
        None | Some(Format::Npy) => Err(StageError::file(path, unrecognised(path, &bytes))),
        Some(_) => read_instrument_file(p, &bytes, ctx),
    }
}

/// An instrument's file, whole, once its size is judged against the largest
/// its format (by extension; the loosest format's when unknown) could be
/// with at most `max_points` points: a real header before gigabytes of
/// zeros is refused unread (#31, 6), and no more than the bound is read
/// even from a file that grows meanwhile.
fn read_bounded(
    p: &HeightMapParams,
    mut file: std::fs::File,
    file_bytes: u64,
) -> Result<Vec<u8>, StageError> {
    let path: &std::path::Path = &p.path;
    let format = hypercontact_formats::format_of_extension(path);
    let bound = hypercontact_formats::max_file_bytes(format, p.max_points);
    if file_bytes > bound {
        let per_point = hypercontact_formats::bytes_per_point(format);
        return Err(StageError::file(
            path,
            format!(
                "is {file_bytes} bytes, more than {what} of at most {} points (max_points) can \
                 be: {bound} bytes ({per_point} bytes a point with every channel it may hold, \
                 plus {} MiB of header); raise `max_points` if the map is real",
                p.max_points,
                hypercontact_formats::HEADER_ALLOWANCE_BYTES >> 20,
                what = format.map_or_else(
                    || "a height map of any format read".to_string(),
                    |f| format!("a {} file", f.name())
                ),
            ),
        ));
    }
    let io_error = |e: std::io::Error| StageError::file(path, e.to_string());
    file.seek(SeekFrom::Start(0)).map_err(io_error)?;
    let mut bytes = Vec::new();
    file.take(bound.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io_error)?;
    if bytes.len() as u64 > bound {
        return Err(StageError::file(
            path,
            format!("grew past {bound} bytes while it was read"),
        ));
    }
    Ok(bytes)
}

/// Why a file no reader recognises is not read: what its bytes are, what
/// its extension promised, and the formats read.
fn unrecognised(path: &std::path::Path, bytes: &[u8]) -> String {
    let is = hypercontact_formats::describe(bytes);
    let expected = hypercontact_formats::format_of_extension(path).map_or_else(
        || "a height map".to_string(),
        |f| {
            let article = if f.name().starts_with(['A', 'E', 'I', 'O', 'U']) {
                "an"
            } else {
                "a"
            };
            format!("{article} {} file", f.name())
        },
    );
    let formats = Format::all_names();
    if is.starts_with("first bytes") {
        format!("is not {expected} ({is}); the formats read are {formats}")
    } else {
        format!("is {is}, not {expected}; the formats read are {formats}")
    }
}

/// A `.npy` map: spacing and units from the parameters.
fn read_npy(
    p: &HeightMapParams,
    file: std::fs::File,
    file_bytes: u64,
) -> Result<Field, StageError> {
    let Some(dx_m) = p.pixel_m else {
        return Err(StageError::file(
            &p.path,
            "a .npy array holds no grid spacing: give `pixel_m` (and `pixel_y_m` if the pixels \
             are not square)",
        ));
    };
    let dy_m = p.pixel_y_m.unwrap_or(dx_m);
    let reader = std::io::BufReader::new(file);
    let mut field = Field::read_npy_file(reader, file_bytes, dx_m, dy_m, p.max_points)
        .map_err(|e| StageError::file(&p.path, e.to_string()))?;
    if p.scale_to_m != 1.0 {
        field.values.mapv_inplace(|h| h * p.scale_to_m);
    }
    Ok(field)
}

/// An instrument's file: heights in metres and the spacing it states,
/// which `pixel_m` / `pixel_y_m` may replace; the fast axis it states.
fn read_instrument_file(
    p: &HeightMapParams,
    bytes: &[u8],
    ctx: &Context,
) -> Result<(Field, Option<StatedFastAxis>), StageError> {
    let channel = p.channel.as_ref().map_or(
        hypercontact_formats::Channel::Default,
        ChannelParam::to_channel,
    );
    let map: Topography =
        hypercontact_formats::read_bytes_limited(bytes, Some(&p.path), &channel, p.max_points)
            .map_err(|e| StageError::file(&p.path, e.to_string()))?;
    if p.scale_to_m != 1.0 {
        return Err(StageError::file(
            &p.path,
            format!(
                "is a {} file, which states its own height units: leave `scale_to_m` at 1 \
                 (it is {})",
                map.format.name(),
                p.scale_to_m
            ),
        ));
    }
    let dx_m = p.pixel_m.unwrap_or(map.dx_m);
    let dy_m = p.pixel_y_m.or(p.pixel_m).unwrap_or(map.dy_m);
    let (nx, ny) = map.heights_m.dim();
    let missing = map.heights_m.iter().filter(|h| h.is_nan()).count();
    let mut note = if map.is_line_scan() {
        format!(
            "{}: a line scan of {nx} points at {}, {missing} missing",
            map.format.name(),
            spacing(map.dx_m, None),
        )
    } else {
        format!(
            "{}: {nx} × {ny} points at {}, {missing} missing",
            map.format.name(),
            spacing(map.dx_m, Some(map.dy_m)),
        )
    };
    note.push_str(&channel_note(&map));
    if (dx_m, dy_m) != (map.dx_m, map.dy_m) {
        note.push_str(&format!(
            "; spacing replaced by the parameters: {} ({:+.3} % along x)",
            spacing(dx_m, Some(dy_m)),
            100.0 * (dx_m / map.dx_m - 1.0)
        ));
    }
    if let Some(instrument) = map
        .metadata
        .iter()
        .find(|(key, _)| key.to_ascii_lowercase().contains("instrument"))
    {
        note.push_str(&format!("; {}: {}", instrument.0, instrument.1));
    }
    ctx.note(&note);
    let stated = map.fast_axis().map(|axis| StatedFastAxis {
        axis: if axis == "y" { Axis::Y } else { Axis::X },
        format: map.format.name(),
    });
    let field = Field::new(map.heights_m, dx_m, dy_m)
        .map_err(|e| StageError::file(&p.path, e.to_string()))?;
    Ok((field, stated))
}

/// Which channel was read, and the others, when the file holds more than
/// one (the formats crate's `channel` and `channels` metadata).
fn channel_note(map: &Topography) -> String {
    match (map.meta("channel"), map.meta("channels")) {
        (Some(read), Some(all)) if all.contains(';') => {
            format!("; channel `{read}` read (the file's channels: {all})")
        }
        _ => String::new(),
    }
}

/// Spacings for a note, `1.5000 × 2.5000 µm`, in nanometres below 0.1 µm
/// (an AFM's 0.9766 nm pixels would read 0.0010 µm).
fn spacing(dx_m: f64, dy_m: Option<f64>) -> String {
    let (unit, per_m) = if dx_m.max(dy_m.unwrap_or(dx_m)) < 1e-7 {
        ("nm", 1e9)
    } else {
        ("µm", 1e6)
    };
    match dy_m {
        Some(dy_m) => format!("{:.4} × {:.4} {unit}", dx_m * per_m, dy_m * per_m),
        None => format!("{:.4} {unit}", dx_m * per_m),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_core::{DynStage, Params};
    use ndarray::array;
    use serde_json::json;

    /// Every parameter at its default (no path: each test gives its own).
    fn with_defaults() -> HeightMapParams {
        HeightMapParams {
            path: std::path::PathBuf::new().into(),
            channel: None,
            pixel_m: None,
            pixel_y_m: None,
            scale_to_m: 1.0,
            crop_points: None,
            crop_m: None,
            circle_m: None,
            mask: None,
            spikes: SpikeRule::None,
            spike_k: 5.0,
            spike_radius: 1,
            form: FormKind::None,
            form_degree: 2,
            level_rows: LevelRows::None,
            level_rows_degree: 2,
            fast_axis: None,
            tip_radius_m: None,
            max_points: 1 << 26,
        }
    }

    #[test]
    fn loads_and_scales_a_map() {
        let dir = std::env::temp_dir().join(format!("hc-hm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.npy");
        let f = Field::new(array![[1.0, 2.0], [f64::NAN, 4.0]], 1.0, 1.0).unwrap();
        f.write_npy(std::fs::File::create(&path).unwrap()).unwrap();
        let params = HeightMapParams {
            path: path.clone().into(),
            pixel_m: Some(2e-5),
            channel: None,
            pixel_y_m: None,
            scale_to_m: 1e-6,
            max_points: 1 << 26,
            ..with_defaults()
        }
        .check()
        .unwrap();
        let out = HeightMap
            .run(&params, &Inputs::new(), &Context::new("t"))
            .unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        assert_eq!(h.values[[1, 1]], 4e-6);
        assert!(h.values[[1, 0]].is_nan());
        assert_eq!((h.dx_m, h.dy_m), (2e-5, 2e-5));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn missing_path_and_spacing_are_named() {
        let parse = |value| HeightMap.params_from_json(value, std::path::Path::new("."));
        let e = parse(json!({"pixel_m": 2e-5})).unwrap_err();
        assert!(e.message.contains("missing field `path`"), "{e}");
        let e = parse(json!({"path": "x.npy", "pixel_m": 0.0})).unwrap_err();
        assert_eq!(e.param, "pixel_m");
    }

    /// An instrument file under a misleading name is read by its bytes,
    /// with the file's spacing and position-free heights; `pixel_m`
    /// replaces the spacing with a note; `scale_to_m` is refused; a `.npy`
    /// without `pixel_m` says what to give.
    #[test]
    fn instrument_files_are_told_by_their_bytes() {
        let dir = std::env::temp_dir().join(format!("hc-hm-x3p-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let heights = array![[1e-6, 2e-6, f64::NAN], [3e-6, 4e-6, 5e-6]];
        let map = Topography {
            heights_m: heights.clone(),
            dx_m: 1.5e-6,
            dy_m: 2.5e-6,
            format: Format::X3p,
            position_m: None,
            metadata: Vec::new(),
        };
        let path = dir.join("scan.dat");
        std::fs::write(&path, hypercontact_formats::write_x3p(&map).unwrap()).unwrap();
        let run = |pixel_m: Option<f64>, scale_to_m: f64| {
            let params = HeightMapParams {
                path: path.clone().into(),
                pixel_m,
                pixel_y_m: None,
                channel: None,
                scale_to_m,
                max_points: 1 << 26,
                ..with_defaults()
            }
            .check()
            .unwrap();
            let ctx = Context::new("scan");
            let out = HeightMap.run(&params, &Inputs::new(), &ctx);
            (out, ctx.notes())
        };
        let (out, notes) = run(None, 1.0);
        let out = out.unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        assert_eq!((h.dx_m, h.dy_m), (1.5e-6, 2.5e-6));
        assert_eq!(h.values[[1, 2]], 5e-6);
        assert!(h.values[[0, 2]].is_nan());
        assert_eq!(
            notes,
            [format!(
                "ISO 25178-72 X3P: 2 × 3 points at 1.5000 × 2.5000 µm, 1 missing; \
                 instrument: hypercontact version {}",
                env!("CARGO_PKG_VERSION")
            )]
        );

        let (out, notes) = run(Some(1.515e-6), 1.0);
        let out = out.unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        assert_eq!((h.dx_m, h.dy_m), (1.515e-6, 1.515e-6));
        assert!(notes[0].contains("replaced by the parameters") && notes[0].contains("+1.000 %"));

        let e = run(None, 1e-6).0.unwrap_err().to_string();
        assert!(e.contains("states its own height units"), "{e}");

        let npy = dir.join("m.npy");
        let f = Field::new(heights, 1.0, 1.0).unwrap();
        f.write_npy(std::fs::File::create(&npy).unwrap()).unwrap();
        let params = HeightMapParams {
            path: npy.into(),
            pixel_m: None,
            pixel_y_m: None,
            channel: None,
            scale_to_m: 1.0,
            max_points: 1 << 26,
            ..with_defaults()
        }
        .check()
        .unwrap();
        let e = HeightMap
            .run(&params, &Inputs::new(), &Context::new("t"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("holds no grid spacing: give `pixel_m`"), "{e}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Item 13 of #31: files no reader recognises were all told "a .npy
    /// array holds no grid spacing"; now each is named for what it is, and
    /// only a real .npy without `pixel_m` hears about the spacing.
    #[test]
    fn unrecognised_files_are_named_for_what_they_are() {
        let dir = std::env::temp_dir().join(format!("hc-hm-what-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let run = |name: &str, bytes: &[u8], max_points: usize| {
            let path = dir.join(name);
            std::fs::write(&path, bytes).unwrap();
            let params = HeightMapParams {
                path: path.into(),
                pixel_m: None,
                pixel_y_m: None,
                channel: None,
                scale_to_m: 1.0,
                max_points,
                ..with_defaults()
            }
            .check()
            .unwrap();
            let e = HeightMap
                .run(&params, &Inputs::new(), &Context::new("t"))
                .unwrap_err()
                .to_string();
            assert!(!e.contains("grid spacing"), "{name}: {e}");
            e
        };
        let e = run("f.x3p", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 1 << 26);
        assert!(
            e.contains(
                "is a PNG image (first bytes 89 50 4e 47 0d 0a 1a 0a), not an ISO 25178-72 X3P file"
            ) && e.contains("the formats read are NumPy .npy, ISO 25178-72 X3P"),
            "{e}"
        );
        let e = run("f.sur", b"", 1 << 26);
        assert!(
            e.contains("is an empty file, not a Digital Surf .sur file"),
            "{e}"
        );
        let e = run("f.plu", b"a text file, not a plu\n", 1 << 26);
        assert!(
            e.contains("is text (first bytes 61 20 74 65 78 74 20 66), not a Sensofar .plu file"),
            "{e}"
        );
        let e = run("f.sur", b"DIGITAL SURF\0\0", 1 << 26);
        assert!(
            e.contains("Digital Surf .sur: the file ends at byte 14"),
            "{e}"
        );
        // an X3P whose header claims more points than the limit
        let map = Topography {
            heights_m: ndarray::Array2::zeros((4, 3)),
            dx_m: 1e-6,
            dy_m: 1e-6,
            format: Format::X3p,
            position_m: None,
            metadata: Vec::new(),
        };
        let x3p = hypercontact_formats::write_x3p(&map).unwrap();
        let e = run("f.x3p", &x3p, 11);
        assert!(
            e.contains("the header claims 4 × 3 = 12 points, above the limit of 11 (max_points)"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A real .plu header before 4 GiB of holes (#31, 6) is refused from
    /// its size, unread (before, the stage read all 4 GiB); the real file
    /// beside it still reads; a file one byte past the bound is refused.
    #[test]
    fn a_vendor_file_beyond_its_formats_bound_is_refused_unread() {
        let reference = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/reference/topography/plu-1.plu");
        let real = std::fs::read(&reference).unwrap();
        let dir = std::env::temp_dir().join(format!("hc-hm-bound-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let run = |path: &std::path::Path, max_points: usize| {
            let params = HeightMapParams {
                path: path.to_owned().into(),
                pixel_m: None,
                pixel_y_m: None,
                channel: None,
                scale_to_m: 1.0,
                max_points,
                ..with_defaults()
            }
            .check()
            .unwrap();
            HeightMap.run(&params, &Inputs::new(), &Context::new("t"))
        };
        let huge = dir.join("huge.plu");
        std::fs::write(&huge, &real[..65536]).unwrap();
        std::fs::OpenOptions::new()
            .write(true)
            .open(&huge)
            .unwrap()
            .set_len(4 << 30)
            .unwrap();
        let started = std::time::Instant::now();
        let e = run(&huge, 1 << 26).unwrap_err().to_string();
        assert!(
            started.elapsed().as_secs_f64() < 1.0,
            "{:?}",
            started.elapsed()
        );
        assert!(
            e.contains(
                "is 4294967296 bytes, more than a Sensofar .plu file of at most 67108864 points"
            ) && e.contains("raise `max_points`"),
            "{e}"
        );
        assert!(run(&reference, 1 << 26).is_ok());
        // At the bound (1 point: 16 bytes + the header allowance) the size
        // passes and the points limit speaks; one byte more, the size.
        let bound = hypercontact_formats::max_file_bytes(Some(Format::Plu), 1);
        for (len, by_size) in [(bound, false), (bound + 1, true)] {
            std::fs::OpenOptions::new()
                .write(true)
                .open(&huge)
                .unwrap()
                .set_len(len)
                .unwrap();
            let e = run(&huge, 1).unwrap_err().to_string();
            assert_eq!(e.contains("bytes, more than"), by_size, "{len}: {e}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A file of the shared reference folder (beside the repository).
    fn more_reference(name: &str) -> std::path::PathBuf {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/reference/topography/more")
            .join(name);
        assert!(
            path.exists(),
            "{} is missing: clone the repository beside shared/",
            path.display()
        );
        path
    }

    /// The map `channel` of `path`, and the stage's notes.
    fn read_channel(
        path: &std::path::Path,
        channel: Option<ChannelParam>,
    ) -> Result<(Field, Vec<String>), String> {
        let params = HeightMapParams {
            path: path.to_path_buf().into(),
            pixel_m: None,
            pixel_y_m: None,
            channel,
            scale_to_m: 1.0,
            max_points: 1 << 26,
            ..with_defaults()
        }
        .check()
        .unwrap();
        let ctx = Context::new("afm");
        let out = HeightMap
            .run(&params, &Inputs::new(), &ctx)
            .map_err(|e| e.to_string())?;
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        Ok((h.clone(), ctx.notes()))
    }

    // The reference is what SurfaceTopography 1.x reads by default from
    // di-1.di (shared/reference/topography/more/index.json: channel 0,
    // "Height", of 4).
    #[test]
    fn a_channel_is_chosen_by_position_or_name_and_the_note_lists_them() {
        let di = more_reference("di-1.di");
        let npy = more_reference("di-1_m.npy");
        let bytes = std::fs::metadata(&npy).unwrap().len();
        let file = std::io::BufReader::new(std::fs::File::open(&npy).unwrap());
        let reference = Field::read_npy_file(file, bytes, 1.0, 1.0, 1 << 26).unwrap();

        // Equal to the reference within 1e-12 of its range (the bar).
        let range_m = reference.values.iter().fold(0.0_f64, |m, v| m.max(v.abs())) * 2.0;
        let same = |a: &Field| {
            a.values.dim() == reference.values.dim()
                && a.values
                    .iter()
                    .zip(&reference.values)
                    .all(|(x, y)| (x - y).abs() <= 1e-12 * range_m)
        };
        let (default, notes) = read_channel(&di, None).unwrap();
        assert!(same(&default));
        assert!((default.dx_m / 9.765625e-10 - 1.0).abs() < 1e-9);
        assert!(
            notes[0].contains("512 × 512 points") && notes[0].contains("channel `Height` read"),
            "{notes:?}"
        );
        assert!(notes[0].contains("0: Height; 1: "), "{notes:?}");
        assert!(notes[0].contains("at 0.9766 × 0.9766 nm"), "{notes:?}");

        let by_name = read_channel(&di, Some(ChannelParam::Name("height".into()))).unwrap();
        assert!(same(&by_name.0));
        let by_index = read_channel(&di, Some(ChannelParam::Index(0))).unwrap();
        assert_eq!(by_index.0.values, default.values);
        let (other, notes) = read_channel(&di, Some(ChannelParam::Index(1))).unwrap();
        assert!(!same(&other), "{notes:?}");

        let e = read_channel(&di, Some(ChannelParam::Name("Topography".into()))).unwrap_err();
        assert!(e.contains("Height"), "the channels are listed: {e}");
        let e = read_channel(&di, Some(ChannelParam::Index(9))).unwrap_err();
        assert!(e.contains("Height"), "the channels are listed: {e}");
        let e = read_channel(&npy, Some(ChannelParam::Index(0))).unwrap_err();
        assert!(e.contains("leave out `channel`"), "{e}");
    }

    // The Dektak stylus export is a profile: an n × 1 map along x.
    #[test]
    fn a_stylus_profile_is_a_line_scan_along_x() {
        let (line, notes) = read_channel(&more_reference("dektak-1.csv"), None).unwrap();
        assert_eq!((line.nx(), line.ny()), (9600, 1));
        // The header's length, 1500 µm, over 9600 points (the formats
        // crate's test says why this differs from the reference's 1499.8).
        assert!(
            (line.dx_m / (1500e-6 / 9600.0) - 1.0).abs() < 3e-8,
            "{}",
            line.dx_m
        );
        assert!(notes[0].contains("a line scan of 9600 points"), "{notes:?}");
    }

    // A tilted bowl of known radius with two spikes, as a .npy: the window,
    // the spikes and the sphere each leave their note, the spikes are NaN
    // and what is left is the bowl's residual (zero to rounding).
    #[test]
    fn window_spikes_and_form_are_removed_in_order_with_notes() {
        let dir = tempfile_dir("prepare");
        let (n, dx_m, r_m) = (64usize, 1e-6, 2e-3);
        let bowl = |i: usize, j: usize| {
            let (x, y) = (i as f64 * dx_m - 30e-6, j as f64 * dx_m - 20e-6);
            r_m - (r_m * r_m - x * x - y * y).sqrt() + 1e-4 * x
        };
        // ±1 nm of texture (a fixed pseudo-random sequence), so the robust
        // σ of the spike rule is the texture's.
        let texture = |i: usize, j: usize| {
            let k = (i * 7919 + j * 104_729) as u64;
            let u = (k.wrapping_mul(6_364_136_223_846_793_005) >> 11) as f64 / (1u64 << 53) as f64;
            2e-9 * (u - 0.5)
        };
        let mut h = ndarray::Array2::from_shape_fn((n, n), |(i, j)| bowl(i, j) + texture(i, j));
        h[[20, 30]] += 5e-7;
        h[[40, 12]] -= 5e-7;
        let path = dir.join("bowl.npy");
        let map = Field::new(h, 1.0, 1.0).unwrap();
        map.write_npy(std::fs::File::create(&path).unwrap())
            .unwrap();
        let mut params = HeightMapParams {
            path: path.into(),
            pixel_m: Some(dx_m),
            pixel_y_m: None,
            channel: None,
            crop_points: Some([2, 2, 60, 60]),
            crop_m: None,
            circle_m: None,
            mask: None,
            spikes: SpikeRule::Local,
            spike_k: 5.0,
            spike_radius: 1,
            form: FormKind::Sphere,
            form_degree: 2,
            scale_to_m: 1.0,
            max_points: 1 << 26,
            ..with_defaults()
        };
        let run = |params: &HeightMapParams| {
            let ctx = Context::new("bowl");
            let out = HeightMap.run(&params.clone().check().unwrap(), &Inputs::new(), &ctx);
            (out.map_err(|e| e.to_string()), ctx.notes())
        };
        let (out, notes) = run(&params);
        let out = out.unwrap();
        let Some(hypercontact_core::Product::Field(f)) = out.get("height") else {
            panic!("no height output")
        };
        assert_eq!(f.values.dim(), (60, 60));
        let nan: Vec<(usize, usize)> = f
            .values
            .indexed_iter()
            .filter(|(_, v)| v.is_nan())
            .map(|(ij, _)| ij)
            .collect();
        assert_eq!(nan, [(18, 28), (38, 10)], "{notes:?}");
        // What is left is the texture: within its ±1 nm, plus the fit's error.
        let worst = f
            .values
            .iter()
            .filter(|v| !v.is_nan())
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(worst < 1.5e-9, "residual {worst} m: {notes:?}");
        assert_eq!(notes.len(), 3, "{notes:?}");
        assert!(notes[0].starts_with("crop: x 2..62, y 2..62"), "{notes:?}");
        assert!(
            notes[1].starts_with("spikes: 2 of 3600 points"),
            "{notes:?}"
        );
        assert!(
            notes[2].starts_with("form: sphere R = 2.00 mm removed"),
            "{notes:?}"
        );

        // Without texture the robust σ is rounding noise: refused, not 28 %
        // of the map set to NaN.
        let smooth = dir.join("smooth.npy");
        let map = Field::new(
            ndarray::Array2::from_shape_fn((n, n), |(i, j)| bowl(i, j)),
            1.0,
            1.0,
        );
        map.unwrap()
            .write_npy(std::fs::File::create(&smooth).unwrap())
            .unwrap();
        let mut on_smooth = params.clone();
        on_smooth.path = smooth.into();
        let e = run(&on_smooth).0.unwrap_err();
        assert!(e.contains("more than spikes can be"), "{e}");

        params.crop_m = Some([0.0, 0.0, 10e-6, 10e-6]);
        let e = params.clone().check().unwrap_err();
        assert_eq!(e.param, "crop_m");
        params.crop_points = None;
        params.crop_m = Some([0.0, 0.0, 1e-3, 10e-6]);
        let e = run(&params).0.unwrap_err();
        assert!(e.contains("lx_m") || e.contains("crop"), "{e}");
    }

    // A hand mask of the map as read removes exactly its false points
    // (before the window, which then cuts the masked map); a mask of
    // another shape is refused naming the file and both shapes.
    #[test]
    fn a_mask_file_removes_exactly_its_points() {
        use ndarray_npy::WriteNpyExt;
        let dir = tempfile_dir("mask");
        let map = Field::new(
            ndarray::Array2::from_shape_fn((4, 3), |(i, j)| (10 * i + j) as f64),
            1.0,
            1.0,
        )
        .unwrap();
        let path = dir.join("map.npy");
        map.write_npy(std::fs::File::create(&path).unwrap())
            .unwrap();
        let keep = ndarray::Array2::from_shape_fn((4, 3), |(i, j)| !(i == j || (i, j) == (3, 0)));
        let mask = dir.join("keep.npy");
        keep.write_npy(std::fs::File::create(&mask).unwrap())
            .unwrap();
        let run = |mask: &std::path::Path, crop_points: Option<[usize; 4]>| {
            let params = HeightMapParams {
                path: path.clone().into(),
                pixel_m: Some(1e-6),
                mask: Some(mask.to_owned().into()),
                crop_points,
                ..with_defaults()
            }
            .check()
            .unwrap();
            let ctx = Context::new("mask");
            let out = HeightMap.run(&params, &Inputs::new(), &ctx);
            (out.map_err(|e| e.to_string()), ctx.notes())
        };
        let (out, notes) = run(&mask, None);
        let out = out.unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        for ((i, j), v) in h.values.indexed_iter() {
            if keep[[i, j]] {
                assert_eq!(*v, (10 * i + j) as f64, "[{i}, {j}]");
            } else {
                assert!(v.is_nan(), "[{i}, {j}]");
            }
        }
        assert!(
            notes[0].starts_with("mask: 4 of 12 points (33.3 %) outside the given mask")
                && notes[0].contains("keep.npy"),
            "{notes:?}"
        );
        // The window cuts the masked map: [1, 1] stays NaN at [0, 0].
        let (out, _) = run(&mask, Some([1, 1, 3, 2]));
        let out = out.unwrap();
        let Some(hypercontact_core::Product::Field(h)) = out.get("height") else {
            panic!("no height output")
        };
        assert!(h.values[[0, 0]].is_nan() && h.values[[0, 1]] == 12.0);

        let wrong = dir.join("wrong.npy");
        ndarray::Array2::from_elem((3, 4), 1u8)
            .write_npy(std::fs::File::create(&wrong).unwrap())
            .unwrap();
        let e = run(&wrong, None).0.unwrap_err();
        assert!(
            e.contains("wrong.npy")
                && e.contains("the mask has shape (3, 4) but the map has (4, 3)"),
            "{e}"
        );
        let not_npy = dir.join("mask.txt");
        std::fs::write(&not_npy, "1 0 1").unwrap();
        let e = run(&not_npy, None).0.unwrap_err();
        assert!(
            e.contains("mask.txt") && e.contains("not a .npy file"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    fn tempfile_dir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("hc-hm-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }
}
