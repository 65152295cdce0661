# The type stub of `hypercontact.stages`, generated from the stage declarations by
# crates/python/src/stubs.rs; do not edit. After changing a stage, rewrite it with
# HYPERCONTACT_WRITE_STUBS=1 cargo test --release -p hypercontact-python --test stubs

from os import PathLike
from typing import Any, Literal, Mapping, Optional, Sequence, TypedDict, Union

import polars as pl

from . import Field, Files, FilesLike, Table

_bemOutputs = TypedDict("_bemOutputs", {"response": pl.DataFrame, "contact_maps": Files, "bands": pl.DataFrame})

def bem(
    *,
    surface: Field,
    material: Table,
    replicates: Optional[Table] = None,
    boundary: Literal["free", "periodic"] = "free",
    model: Literal["hyperelastic", "linear"] = "hyperelastic",
    tangent: Literal["equibiaxial", "uniaxial"] = "equibiaxial",
    scheme: Literal["euler", "heun"] = "heun",
    poisson: Any = 0.5,
    steps: int = 40,
    max_area_fraction: float = 0.9,
    tolerance: float = 1e-8,
    max_iterations: int = 2000,
    map_fractions: Sequence[float] = ...,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _bemOutputs:
    """Boundary elements: load against contact area of a height map on an elastic half-space

    The rough surface as a linearly elastic half-space pressed onto a rigid plane, solved pixel by pixel (pixel-wise constant pressure) with FFTs, so asperities interact through the elastic field and the surface between them deforms (what profile theory leaves out). BOUNDARY: `free` (default) treats the map as a finite part of an infinite half-space loaded nowhere else: zero-padded to at least 2N x 2N with Love's closed-form displacement of a uniformly loaded rectangular pixel (Love 1929; Johnson, Contact Mechanics, 3.9), Hockney's method; `periodic` for periodic maps: u^(q) = 2 p^(q) / (E* |q|), mean of u zero. SOLVER: Polonsky & Keer's constrained conjugate gradient (Wear 231, 1999) under rigid-plane approach control, with an FFT preconditioner after Vollebregt (J. Comput. Phys. 257, 2014: the operator's inverse on a transform grid; for free maps the unpadded one, kernel wrapped) corrected on the contact set by a Schur-complement term for the points off it (two damped Jacobi terms; Saad, Iterative Methods for Sparse Linear Systems, 2003) and Polak-Ribiere conjugation, each solve warm-started from the previous two; a `bem` run after another on the same map with the same boundary, steps, max_area_fraction, tolerance and max_iterations in one process (the paper's linear and hyperelastic pair) replays that solve instead of repeating it, with the same bits (the contact set does not depend on the law); a solve is accepted when the rms of the complementarity violation (gap on {p > 0}, negative gap elsewhere) divided by the approach is at most `tolerance` (at 1e-8 the contact set is exact to the pixel and the load to ~1e-9); otherwise the stage fails naming the step, the plane height, the load and the residual. Sums are in a fixed order, so results are the same to the bit on any number of threads. STEPS: row 0 is first contact (F = 0, A = 0); rows 1..=steps aim at A/A0 = k max_area_fraction / steps and land within a quarter of the spacing (or as near as six solves get), the last at or above max_area_fraction (so every A/A0 up to it can be read off the curve); `iterations` counts every solve of a step. CONVENTIONS: `z_m` is the rigid plane's height above the lowest measured point (at first contact the map's height range; periodic: the plane relative to the mean surface, i.e. a mean gap); A = contact pixels (p > 0) x dx dy; A0 = measured pixels x dx dy (NaN heights never touch, as in `truncation`); E0* and E_t* exactly as in `icm` (E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu)); kappa = (A/A0) / (p/(E0* h'rms)) with p = F/A0 and h'rms the rms gradient by forward differences (as `surface` reports it); about 2 at small load on self-affine maps, falling with load; NaN at first contact. MODEL `linear`: F = E0* f(delta), f the load for E* = 1 (the contact set and f do not depend on the modulus). `hyperelastic`: the paper's tangent modulus (Eqs. 5-7) applied to the coupled contact instead of profile theory: dF = E_t*(-F/A) f'(delta) d delta, i.e. dF = E_t*(-F/A) df over the solved steps, F = 0 at first contact, with the ICM's E_t*(S) (same material law and sign convention: S = -F/A <= 0, E_t*/E0* = 2 at first contact for nu = 1/2 with the paper's `tangent: equibiaxial`, 1 with `uniaxial`; a linear material's E* throughout) and `scheme` (euler: the paper's explicit step; heun: trapezoid); tangent_ratio = E_t*/E0*. The contact set, A and the gap are the linear solution's; the pressure map is the linear one scaled to the load (F/f). BANDS: with `replicates` (material-fit's bootstrap) each replicate material's law is integrated over the same linear solve (its contact set and unit-modulus load do not depend on the modulus), so a replicate costs an integral, not a solve; `bands` gives per step the 5th, 50th and 95th percentiles of load_norm (over the main material's E0* A0) and of tangent_ratio (over the replicate's own E0*), as `icm` does; a replicate whose law gives out is left out with a note. CONTACT_MAPS: for each of map_fractions, the step whose A/A0 is nearest: pressure_a<fraction>.npy (Pa) and gap_a<fraction>.npy (m, NaN where not measured), axis 0 = x as in the input, indexed by the table contact_maps.parquet (one row per map: requested and kept A/A0, load, files, spacing, step, z_m).

    Parameters (keywords, as in a pipeline's `with:` block):
        boundary (default "free"): how the map continues beyond its edges
        model (default "hyperelastic"): contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
        tangent (default "equibiaxial"): the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
        scheme (default "heun"): integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
        poisson (default 0.5): Poisson's ratio ν of the composite moduli (a linear material uses its own)
        steps (default 40): load steps after first contact, about evenly spaced in A/A0
        max_area_fraction (default 0.9): A/A0 of the last step
        tolerance (default 1e-8): largest accepted residual: rms gap error on the contact set / approach
        max_iterations (default 2000): conjugate-gradient iterations per solve before the stage fails
        map_fractions (default [0.1,0.5,0.9]): A/A0 at which `contact_maps` holds the pressure and the gap

    Inputs (keywords; a table as a polars or pandas DataFrame):
        surface (field, one): height map, metres, NaN = not measured
        material (table, one): the material table (a preset or a fit)
        replicates (table, optional): material-fit's bootstrap replicates: each replicate's law is integrated over the same linear solve, for `bands`

    Returns a dict of the outputs:
        response (table): one row per load step, first contact first (icm's columns first)
        contact_maps (files): pressure and gap maps (.npy) at map_fractions, indexed
        bands (table): 5–95 % bands over the material's bootstrap replicates, one row per step (no rows without `replicates`)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_contact_compareOutputs = TypedDict("_contact_compareOutputs", {"transform": pl.DataFrame, "registrations": pl.DataFrame, "overlap": pl.DataFrame, "agreement": pl.DataFrame, "load_ratio": pl.DataFrame, "figures": Files})

def contact_compare(
    *,
    contact: Table,
    observed_maps: FilesLike,
    surface: Field,
    responses: Optional[Mapping[str, Table]] = None,
    model_maps: Optional[Mapping[str, FilesLike]] = None,
    truth: Optional[Table] = None,
    register_at: float = 0.5,
    register_with: Optional[str] = None,
    min_register_fraction: float = 0.02,
    angle_deg: float = 0.0,
    angle_range_deg: float = 10.0,
    refine_scale: bool = True,
    scale_range: float = 0.05,
    min_area_fraction: float = 0.01,
    max_area_fraction: float = 0.9,
    area_basis: Literal["view", "whole"] = "view",
    view_maps: Mapping[str, str] = ...,
    area_fractions: Sequence[float] = ...,
    figure_fractions: Sequence[float] = ...,
    figure_px: int = 1024,
    same_physics: Sequence[str] = ...,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _contact_compareOutputs:
    """Models against the contact experiment: registration of the observed contact maps, overlap per frame and agreement of the load-area curves (Figs. 6, 7)

    CHECKS (the index tables name no sample or run, so belonging is judged from grids and values): model maps on another grid than `surface`, a camera view larger than the scan, observed maps of different cameras, observed maps whose frame is not in `contact` or whose A/A0 is more than 0.01 + 25 % off the table's, a model_maps label `truncation` (reserved), and view_maps keys or values that are not wired are refused. Noted as warnings: the adopted turn or scale within 2 % of its search range from a bound, ZNCC below 0.5 (the paper pipeline's reach 0.78-0.81), and even the best model's rms log ratio above 1 (the paper pipeline's best: 0.08-0.10). REGISTRATION: the observed map (contact-images' contact_maps) nearest register_at is registered onto the prediction register_with, on the scan's grid: `truncation` (the height map `surface` cut at the observed A/A0: contact where the height is at or above the level that leaves that fraction above it, profile theory) or a model_maps label (any contact model's contact_maps: contact where the pressure is positive, at its map nearest the observed A/A0); by default the first model_maps label, else the truncation (a model's map is closer to the contact a camera sees than a cut through the heights). The turn (angle_deg ± angle_range_deg), shift and, with refine_scale, the camera-to-scan scale are found by a coarse search of turns with FFT correlation for the shift, then refined continuously (crate compare, module register); the transform follows the interference crate's convention: the camera pixel at p from the frame's centre sees the scan point R(angle) p + shift from the map's centre. Every other observed map is registered on its own too; the spread of those registrations (1.4826 MAD) is the transform's uncertainty (table `transform`, each in `registrations`). OVERLAP: with the adopted transform, each model's map (truncation always; each model_maps label) is sampled on the camera's pixels (bilinear, contact where >= 0.5; pixels off the scan are not counted) and compared with the observed map: Dice, IoU, precision, recall and the counts. AGREEMENT: each `responses` curve against the measured (area_fraction, force_n) of `contact`, over min_area_fraction <= A/A0 <= max_area_fraction: the model's load at each measured A/A0 (log-log interpolation, never extrapolated) over the measured force; rms and mean of the log ratio, rank 1 = smallest rms; `load_ratio` at area_fractions (both curves interpolated). BY CONSTRUCTION: a synthetic experiment has a physics (synth-contact's truth names it, e.g. the hyperelastic BEM with the equibiaxial tangent); a model of the same physics agrees with it by construction, whatever the physics is worth. The responses listed in same_physics are marked (by_construction = 1 in `agreement` and `load_ratio`), scored as the others but ranked 0 (not ranked) and left out of the best agreement noted; the others rank 1, 2, ... among themselves. With `truth` wired, its physics string is carried into both tables (column experiment_physics; empty without it). Without same_physics every row is 0 and the ranks are as before. The camera measures A/A0 of its view, the models give it for the whole scan, and on a free sample the two differ (its rim lifts off, so its centre carries more contact). With area_basis `view` (default) each model's A/A0 is converted to its view A/A0 before scoring: its own maps (model_maps of its label, or the label view_maps names, e.g. a linear model's response read on the maps of the model whose contact sets it shares) or else the truncation read inside the registered view, linear between the maps' (whole, view) pairs; column `area` says which. FIGURES: per observed map and model, observed.png/predicted.png (contact black) and an overlay (black: both, vermillion: predicted only, sky blue: observed only, white: neither, grey: off the scan), for the maps requested at figure_fractions, subsampled to figure_px, with the index `figures.parquet` (FigureIndex).

    Parameters (keywords, as in a pipeline's `with:` block):
        register_at (default 0.5): A/A0 of the observed map the adopted transform is found at (the map nearest it)
        register_with (optional): the prediction registered against: `truncation` (the height map cut at the observed A/A0) or a label of `model_maps` (default: the first model_maps label, else truncation)
        min_register_fraction (default 0.02): maps with less measured contact are not registered (a handful of spots pins no turn); they are still scored
        angle_deg (default 0.0) [deg]: the camera's expected turn against the scan
        angle_range_deg (default 10.0) [deg]: turns searched: angle_deg ± this (180: every turn)
        refine_scale (default true): refine the camera's pixel on the sample (the scale between camera and scan)
        scale_range (default 0.05): the scale is sought within 1 ± this
        min_area_fraction (default 0.01): agreement: the smallest measured A/A0 scored
        max_area_fraction (default 0.9): agreement: the largest measured A/A0 scored (the paper's range: 0.9)
        area_basis (default "view"): agreement: the models' A/A0 over the camera's view (`view`: from each model's own maps in the registered view) or over the whole scan (`whole`)
        view_maps (default {}): agreement on the view: whose maps give a response's view area (response label: model_maps label or `truncation`; other keys or values are refused); by default its own label's maps, else the truncation
        area_fractions (default [0.1,0.5,0.9]): A/A0 at which the load ratio F_model / F_experiment is reported
        figure_fractions (default [0.1,0.5,0.9]): the observed maps drawn as figures, by their requested A/A0 (contact-images' map_fractions); every map is scored
        figure_px (default 1024) [px]: the figures' longest side (the camera's maps are subsampled to it)
        same_physics (default []): responses (labels) whose physics is the experiment's, e.g. `bem-linear` against synth-contact's `model: linear`: they agree by construction, so their rows are marked `by_construction` and not ranked (a label that is not wired is refused)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        contact (table, one): contact-images' contact table
        observed_maps (files, one): contact-images' contact_maps (mask PNGs, indexed)
        surface (field, one): the sample's height map, metres (the stitched scan)
        responses (table, many): load-area curves of the contact models, labelled by model
        model_maps (files, many): contact models' contact_maps, labelled by model (pressure maps, indexed)
        truth (table, optional): the experiment's truth (synth-contact's truth): its physics is named in the tables

    Returns a dict of the outputs:
        transform (table): the adopted registration and its spread
        registrations (table): each observed map registered on its own
        overlap (table): per observed map and model
        agreement (table): per model response
        load_ratio (table): per model and area fraction
        figures (files): observed, predicted and overlay PNGs, indexed

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_contact_imagesOutputs = TypedDict("_contact_imagesOutputs", {"contact": pl.DataFrame, "sync": pl.DataFrame, "contact_maps": Files})

def contact_images(
    *,
    sequence: Optional[FilesLike] = None,
    method: Literal["calibrated", "otsu", "multi-otsu"] = "calibrated",
    dir: Optional[Union[str, PathLike[str]]] = None,
    bits: Optional[int] = None,
    pixel_m: float = 6.5e-6,
    exposure_s: float = 0.0,
    clock_offset_s: Optional[float] = None,
    force_resolution_n: float = 0.01,
    reference_frame: int = 0,
    dark_level: float = 0.0,
    contact_level: float = 0.0,
    background_level: float = 1.0,
    fraction: float = 0.2,
    seed_fraction: float = 0.1,
    min_patch_pixels: int = 4,
    map_fractions: Sequence[float] = ...,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _contact_imagesOutputs:
    """Contact area and patches per frame from contact-interference images and a force log

    Reads frames.csv (frame, time_s, file; time_s = exposure start on the camera's clock) or, without it, every PNG/TIFF file whose name carries its time (a field such as `t1.25s`, `1250ms` or `250000us` between `_`, `-` or spaces: img_0007_t1.25s.tif; the frames in time order, the frame number the name's digit field), the frames (PNG or TIFF, 8 or 16 bit; `bits` for a camera shallower than its files, e.g. 12-bit data in 16-bit files, which are then NOT rescaled, and values at or above 2^bits are refused) and force.csv (time_s, force_n), from the `sequence` input (the synthetic lab's files) or `dir`; a frame number or a file listed twice is refused. Contact regions are dark (the half-wave loss at the rubber). METHODS: `calibrated` (default): each frame divided by the reference frame (a frame without contact: the flat field, vignetting and illumination cancel), contact where the ratio is below contact_level + fraction (background_level - contact_level), grown from seeds below seed_fraction (hysteresis, 8-connected), patches under min_patch_pixels dropped; pixels whose reference is dark are never contact. With the defaults (0, 1, 0.2, seeds 0.1) contact means an intensity below a fifth of the background's: 'optical contact', a gap of at most a few tens of nm under white light (half the background is reached at 42 nm, crate `interference`), so A is overestimated where the gap opens slowly (a sphere of R = 5 mm: +23 % at A/A0 = 0.04, +2 % at 0.65; a rough self-affine sample from synth-contact: +10 % at A/A0 = 0.06, +3 % at 0.84). `otsu`: the paper's global Otsu threshold per frame on the full 2^bits histogram; it counts dark interference fringes (the second dark fringe near 265 nm is a third of the background) and dim corners as contact, so it overestimates A at low load (the rough sample: +16 to +20 % up to A/A0 = 0.25, +5 to +8 % above 0.6, and 2 to 56 times the patches, the fringe rings and noise specks) and splits a frame without contact into two classes (44 % 'contact' on a vignetted no-contact frame). `multi-otsu`: three classes, the darkest is contact. A0 = the frame's pixels (all pixels are the sample's); area = contact pixels x pixel_m². Patches: 8-connected components. SYNC: force-log time = camera time + clock_offset_s; force linearly interpolated at mid-exposure (time_s + exposure_s/2). Without clock_offset_s, when force.csv has a column camera_trigger (the camera's exposure signal logged with the force: 0/1 or volts), each run of high samples is one exposure, its centre the mean of the middles of its rising and falling gaps, and the offset is the median of (centre - frame mid-exposure time); the exposures must match the frames one to one (good to a fraction of a log sample: within 5 ms at 50 Hz). Otherwise the offset is estimated as the time the force leaves its baseline (detected at 6 robust sigma of the first 16 samples, at least twice force_resolution_n, and dated back to the last sample at the baseline) minus the time half-way between the last frame without contact and the first with, as the calibrated method sees it (whatever `method` is: a global threshold finds 'contact' in every frame), so it needs reference_frame: good to about one frame interval when the sequence starts before contact, and late by both the position of the touch between two frames and the time the force takes to rise out of the log's noise (measured on synth-contact's rough samples at frame intervals of 2.3-12.3 s: 1.1-3.7 s late, 0.30-0.46 of an interval, so the force was read 26-41 % high at A/A0 = 0.1 and 4-5 % at 0.5; log the camera's trigger when the load matters at low area). CONTACT_MAPS: for each of map_fractions, the frame whose A/A0 is nearest, as mask_a<fraction>.png (8-bit, 255 = contact), indexed by the table contact_maps.parquet (requested and kept A/A0, frame, file, pixel_m, time_s, force_n).

    Parameters (keywords, as in a pipeline's `with:` block):
        method (default "calibrated"): segmentation method
        dir (optional): folder with the frames (listed in frames.csv, or with their times in their names) and force.csv (instead of the `sequence` input)
        bits (optional): the camera's bit depth when the files' container is deeper (a 12-bit camera in 16-bit files: 12)
        pixel_m (default 6.5e-6) [m]: camera pixel size on the sample (sensor pixel / magnification)
        exposure_s (default 0.0) [s]: exposure time; force is read at mid-exposure (0: the frame times are mid-exposure)
        clock_offset_s (optional) [s]: force-log time minus camera time (default: estimated from first contact); must keep every frame inside force.csv's times
        force_resolution_n (default 0.01) [N]: force-log resolution, for the onset of the force in the offset estimate
        reference_frame (default 0): calibrated: index (in time order, from 0) of a frame without contact, the flat field (refused below half the brightest frame's mean signal: in contact; a warning below 90 %)
        dark_level (default 0.0): calibrated: camera dark offset in counts
        contact_level (default 0.0): calibrated: intensity of contact relative to the reference (≈ 0: contact is black)
        background_level (default 1.0): calibrated: intensity of the background relative to the reference (1: same illumination)
        fraction (default 0.2): calibrated: contact joins below this fraction of the way from contact to background
        seed_fraction (default 0.1): calibrated: contact seeds below this fraction (hysteresis; = fraction turns it off)
        min_patch_pixels (default 4) [px]: calibrated: smallest patch kept
        map_fractions (default [0.1,0.5,0.9]): A/A0 at which `contact_maps` holds the binary contact map (nearest frame)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        sequence (files, optional): the synthetic lab's files (or use `dir`)

    Returns a dict of the outputs:
        contact (table): one row per frame
        sync (table): the clock offset used, and how it was found
        contact_maps (files): binary contact maps (PNG) at map_fractions, indexed

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_cropOutputs = TypedDict("_cropOutputs", {"height": Field, "mirrored": Field})

def crop(
    *,
    surface: Field,
    x0: int = 0,
    y0: int = 0,
    nx: Optional[int] = None,
    ny: Optional[int] = None,
    coarsen: int = 1,
    refine: int = 1,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _cropOutputs:
    """A window of a height map, optionally coarsened or refined, and its mirror-image tiling

    Cuts the window of points [x0, x0 + nx) × [y0, y0 + ny) out of the map (axis 0 = x) and, with `coarsen` = k > 1, replaces each k × k block of it by the block's mean (an instrument with k times larger pixels; a block with a missing point is missing; points left over at the window's far edges, fewer than k, are dropped and the note says so), spacing k dx × k dy. With `refine` = r > 1 the patch (coarsened first, if asked) is then resampled r times finer by band-limited interpolation: the trigonometric (cosine, DCT-I) series of its mirror extension, evaluated at spacing dx/r × dy/r on (nx - 1) r + 1 x (ny - 1) r + 1 points (FFT of the extension, spectrum padded with zeros, the Nyquist bin split half and half between the positive and negative frequency, inverse FFT). The window's points are reproduced to round-off and nothing shorter than its Nyquist wavelength 2 dx appears: refinement interpolates and adds no content. A map filtered at a cut-off λc has λc/dx points per λc; refine multiplies that, so a model's mesh can resolve the same surface more finely. A window with a missing point is refused when refine > 1. `height` is that patch. `mirrored` is its even continuation across the patch's edges, h[2(nx - 1) - i] = h[i] (likewise in y): 2(nx - 1) x 2(ny - 1) points, periodic by construction. A solid whose lateral faces are symmetry planes (`fem` with `boundary: mirror`) is one cell of that tiling, so `bem` with `boundary: periodic` and `surface` with `periodic: true` on `mirrored` solve and describe the same contact problem as `fem` on `height`. A window that leaves the map or leaves fewer than 2 x 2 points is refused naming the parameter.

    Parameters (keywords, as in a pipeline's `with:` block):
        x0 (default 0): first point of the window along x (axis 0)
        y0 (default 0): first point of the window along y (axis 1)
        nx (optional): points of the window along x, before coarsening (default: to the map's end)
        ny (optional): points of the window along y, before coarsening (default: to the map's end)
        coarsen (default 1): each block of coarsen × coarsen points becomes one point (their mean), spacing × coarsen
        refine (default 1): the window (after coarsening) is resampled refine times finer by band-limited (cosine-series) interpolation, spacing / refine, (n − 1) refine + 1 points per axis; adds no content

    Inputs (keywords; a table as a polars or pandas DataFrame):
        surface (field, one): height map, metres, NaN = not measured

    Returns a dict of the outputs:
        height (field): the window (coarsened, refined), metres, NaN = not measured
        mirrored (field): the patch's even (mirror-image) continuation, periodic, 2(nx - 1) x 2(ny - 1) points for a patch of nx x ny

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_dicOutputs = TypedDict("_dicOutputs", {"tensile": pl.DataFrame, "field": pl.DataFrame, "strain": Field})

def dic(
    *,
    sequence: Optional[FilesLike] = None,
    method: Literal["subset", "markers"] = "subset",
    dir: Optional[Union[str, PathLike[str]]] = None,
    mode: Optional[Literal["UT", "PT", "BT"]] = None,
    roi_px: Optional[Sequence[int]] = None,
    roi_polygon_px: Optional[Sequence[Sequence[float]]] = None,
    mask: Optional[str] = None,
    loading_axis: Literal["x", "y", "principal"] = "x",
    bit_depth: Optional[int] = None,
    frame_rate_hz: Optional[float] = None,
    subset_px: int = 31,
    step_px: int = 10,
    strain_window: int = 5,
    max_iterations: int = 30,
    convergence_px: float = 0.001,
    min_zncc: float = 0.9,
    update_strain: float = 0.1,
    search_px: int = 64,
    marker_threshold: float = 0.07,
    marker_min_area_px: int = 20,
    marker_max_jump_px: float = 25.0,
    gauge_width_m: Optional[float] = None,
    thickness_m: Optional[float] = None,
    pixel_m: Optional[float] = None,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _dicOutputs:
    """Digital image correlation of a tensile test: stretch and strain per frame (force and nominal stress with a force log), and u, v, E, ZNCC per point per frame

    Reads the images (PNG/TIFF: 8/16-bit grey, colour converted by Y = 0.2126 R + 0.7152 G + 0.0722 B of the stored values rounded, palette, float TIFF as fractions 0 … 1), frames.csv, force.csv and specimen.json from the `sequence` input or the folder `dir`. Frames: frames.csv (frame, time_s, file); without it the PNG/TIFF files whose names carry their time (img_0007_t1.25s.tif, as contact-images), or with `frame_rate_hz` all PNG/TIFF files in natural order of their names at times k / rate. Counts are fractions of 2^bit_depth − 1 (`bit_depth` or specimen.json, else the file's 8/16 bits; never guessed: a note says when a 16-bit frame 0 stays below 4096). force.csv is optional: without it force_n and nominal_stress_pa are NaN (strain only; material-fit then refuses the table), and gauge width and thickness are not needed. Region: `roi_px`, `roi_polygon_px` and the `mask` image (non-zero = analyse), intersected; a POI is tracked only if its whole subset lies inside. method `subset`: POIs on a grid in the region; seeds spread over the region (up to 4 × 4 candidates, FFT ZNCC integer guess then IC-GN, all accepted ones queued best ZNCC first, more rounds for parts not reached), reliability-guided propagation, IC-GN with a first-order shape function and bicubic B-spline interpolation (Pan et al. 2013); POIs below `min_zncc` or not converged are invalid; incremental reference updating when the strain since the reference exceeds `update_strain`, positions and gradients composed so deformation accumulates from frame 0. method `markers`: weighted centroids of dark painted dots in the region's bounding box. Gauge value per frame: least-squares affine fit of all valid points → F → principal stretches, `stretch` the one nearest `loading_axis` (x, y, or principal: the final frame's largest principal stretch direction, reported in `loading_axis_deg` and a note). Table `field`: per POI per frame u, v, Green–Lagrange E_xx, E_yy, E_xy from strain-window fits, ZNCC and validity. Field `strain`: E_xx of the last frame (NaN where invalid). Force linearly interpolated at frame times; nominal stress = F / (gauge width × thickness).

    Parameters (keywords, as in a pipeline's `with:` block):
        method (default "subset"): how points are followed
        dir (optional): folder with the files (instead of the `sequence` input)
        mode (optional): the test (default: specimen.json)
        roi_px (optional) [px]: region of interest [x0, y0, x1, y1] in frame-0 pixels (default: specimen.json)
        roi_polygon_px (optional) [px]: region of interest as a polygon [[x, y], …] in frame-0 pixels (even-odd rule)
        mask (optional): image file beside the frames whose non-zero pixels are analysed (holes, notches, grips)
        loading_axis (default "x"): direction of `stretch`: x, y or principal (the final frame's largest principal stretch)
        bit_depth (optional): camera bits when fewer than the file's (12-bit data in 16-bit files; default: specimen.json)
        frame_rate_hz (optional) [Hz]: frame rate without frames.csv: frames in natural order of their names at times k / rate
        subset_px (default 31) [px]: subset side, odd
        step_px (default 10) [px]: POI spacing
        strain_window (default 5): strain window side in POIs
        max_iterations (default 30): IC-GN iteration limit
        convergence_px (default 0.001) [px]: IC-GN stops when the update moves the subset less
        min_zncc (default 0.9): POIs correlating worse are invalid
        update_strain (default 0.1): reference update threshold on |λ − 1|
        search_px (default 64) [px]: FFT seed search radius
        marker_threshold (default 0.07): marker pixels are darker than this fraction of full scale
        marker_min_area_px (default 20) [px]: smallest marker in frame 0
        marker_max_jump_px (default 25.0) [px]: largest distance from the predicted marker position
        gauge_width_m (optional) [m]: gauge width (default: specimen.json)
        thickness_m (optional) [m]: thickness (default: specimen.json)
        pixel_m (optional) [m]: object-space pixel size (default: specimen.json)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        sequence (files, optional): the synth-tensile files (or use `dir`)

    Returns a dict of the outputs:
        tensile (table): one row per frame
        field (table): one row per point per frame: u, v, Green–Lagrange E, ZNCC
        strain (field): Green–Lagrange E_xx of the last frame on the POI grid (markers: one gauge value)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_femOutputs = TypedDict("_femOutputs", {"response": pl.DataFrame, "contact_maps": Files})

def fem(
    *,
    surface: Field,
    material: Table,
    x0: int = 0,
    y0: int = 0,
    nx: Optional[int] = None,
    ny: Optional[int] = None,
    coarsen: int = 1,
    refine: int = 1,
    depth_m: Optional[float] = None,
    layers: int = 8,
    grading: float = 8.0,
    boundary: Literal["mirror", "periodic"] = "mirror",
    strain: Literal["finite", "small"] = "finite",
    bulk_ratio: float = 5000.0,
    steps: int = 20,
    max_area_fraction: float = 0.3,
    map_fractions: Sequence[float] = ...,
    tolerance: float = 1e-8,
    max_iterations: int = 30,
    max_nodes: int = 200000,
    max_memory_gb: float = 8.0,
    lateral_coarsening: bool = False,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _femOutputs:
    """Finite elements at finite strain: load against contact area of a rough, nearly incompressible hyperelastic block on a rigid flat

    The reference the tangent-modulus models are judged against: the rough patch as a block of the hyperelastic material (or a linear one), pressed by a rigid, flat, frictionless plane, solved at finite strain. PATCH: the window x0, y0, nx, ny of the input map (default all of it), each coarsen x coarsen block averaged, then with `refine` > 1 resampled refine times finer by band-limited interpolation (as the `crop` stage cuts and refines it; the mesh then has a top node per refined point). MESH (fixed conventions, so results compare with other codes): one top node per map point, node (i, j) at x = i dx, y = j dy, so the block is (nx - 1)dx x (ny - 1)dy; base at z = 0, top node at z = depth_m + h[i, j] - mean(h) (depth_m: default the larger lateral size; a block on a rigid base is stiffer than the half-space that bem, icm and persson assume, most for the longest wavelength: linear fem against linear bem on the paper's t1 window, at equal approach, 1.02-1.05 at depth = the window's side and 0.98-1.00 at twice it, so judge half-space models with depth_m at least twice the side, the extra layers graded to keep the top one); `layers` layers of trilinear hexahedra per column, thicknesses in geometric progression with bottom/top ratio `grading`, refused before meshing when an element would be more than 10 times wider than thick (its width over its layer's thickness in the lowest column; the shipped pipelines stay below 1.4); with lateral_coarsening, layer k's elements are s_k pixels wide in x and y, s_k the largest power of two not above the layer's thickness nor its top's depth below the surface, in pixels, 1 for the top layer, at most doubling from one layer to the next one down (the last element of a row shorter where s_k does not divide it), and the fine nodes on a coarser face below are hanging: position and displacement interpolated bilinearly from that face's corners (a conforming mesh). BOUNDARY: base clamped; lateral faces `mirror` (normal displacement zero: the patch is one cell of its mirror-image tiling, which `crop`'s `mirrored` output is, for the periodic models) or `periodic` (node (nx - 1, j) tied to (0, j), and likewise in y: the map's last row and column must repeat its first). MATERIAL: finite strain, W = W_iso(isochoric C) + K (J - 1)^2 / 2 with K = bulk_ratio mu0 (default 5000, nu = 0.4999); every hyperelastic family of the `material` table through its strain energy, with the consistent tangent; a `linear` material is small-strain linear elasticity with its E and nu (K from nu, or bulk_ratio mu at nu = 1/2); `strain: small` solves a hyperelastic material as small-strain linear elasticity with mu0 and K, on the same mesh and steps, so F_finite / F_small isolates the finite-strain effect from the discretisation. ELEMENT: the mixed Q1/P0 hexahedron (displacement, constant pressure and volume ratio per element, condensed), free of volumetric locking. CONTACT: exact active set on the top nodes (a node in contact has its z on the plane, released when its reaction pulls once the free residual is within sqrt(tolerance) of the reactions; a free node that penetrates enters at once), frictionless (x, y free), Newton with line search from the last converged state (a linear law's extrapolated from the last two), faer's sparse Cholesky with one symbolic factorisation (once Newton converges, chord steps keep the last factorisation while they cut the residual fourfold; with a constant tangent, as at small strain, a direction whose contact set differs from the factorised one in at most 6 nodes is solved by conjugate gradients preconditioned by the kept factor, to 1e-8 of the right-hand side in at most 12 iterations); MEMORY: the symbolic factor's exact size and the assembly's are added up before any numeric work, noted, and the stage refused above max_memory_gb (measured 16-20 kB per node at 8 layers); a step that fails is halved up to four times, an attempt whose line search damps the contact nodes' move to the plane to 1/4 or less being halved at once (first-touch cut; the last halving iterates to the end), then the stage fails naming the step, the approach and the residual. STEPS: row 0 is first touch (F = 0); step 1 goes to where the plane's overlap with the undeformed surface covers A/A0 = max_area_fraction / steps (the elastic area is smaller); step k aims at k max_area_fraction / steps (half a spacing past an overshoot), its approach from A taken as a power of the approach through the first and the last state, the increment within 1/4 and 2 times the last (step 2 at most doubles the approach); a step landing more than two spacings past its aim is solved again at a third of its increment (up to three times; frictionless elastic contact has no history); the last row is at or above max_area_fraction, more steps being taken if aims fall short (at most 4 steps + 10, then the stage fails). Nodes enter the contact set when they penetrate by more than 1e-6 of the approach and leave when they pull with more than 1e-9 of the reactions (a hysteresis against cycling). CONVENTIONS: A/A0 = top nodes in contact / top nodes (node-counted, as `bem` counts pixels); A0 = (nx - 1)dx (ny - 1)dy, A = A/A0 x A0; `area_fraction_current` is the contact area over the projected area, both deformed (each top face counts with the share of its nodes in contact); z_m = the plane's height above the patch's lowest point (the height range at first touch, as in `bem`); load_n is the plane's force; load_norm = F/(E0* A0) with E0* = 4 mu0 for a hyperelastic material (E0 = 3 mu0, nu = 1/2, as the other models take it) and E/(1 - nu^2) for a linear one; tangent_ratio is NaN: the finite-element solution has no single modulus (read F_model / F_fem at equal A/A0 instead). CONTACT_MAPS: at the first step reaching each of map_fractions: pressure_a<f>.npy (nodal reaction / tributary area, Pa), contact_a<f>.npy (1/0) on the patch's grid (axis 0 = x), and mesh_a<f>.vtk, the deformed mesh with displacement, pressure and contact as point data (ParaView), indexed by contact_maps.parquet. Sums are in a fixed order: the same bits on any number of threads.

    Parameters (keywords, as in a pipeline's `with:` block):
        x0 (default 0): first point of the window along x (axis 0)
        y0 (default 0): first point of the window along y (axis 1)
        nx (optional): points of the window along x, before coarsening (default: to the map's end)
        ny (optional): points of the window along y, before coarsening (default: to the map's end)
        coarsen (default 1): each block of coarsen × coarsen points becomes one point (their mean), spacing × coarsen
        refine (default 1): the window (after coarsening) is resampled refine times finer by band-limited (cosine-series) interpolation, spacing / refine, (n − 1) refine + 1 points per axis; adds no content
        depth_m (optional) [m]: block height at the mean surface (default: the larger lateral size; the block on its rigid base is then 2-5 % stiffer at equal approach than the half-space the other models assume, twice that depth within 1 %: see the stage doc)
        layers (default 8): element layers through the height (an element may be at most 10 times wider than thick, else the stage is refused: fewer layers, less grading or a deeper block)
        grading (default 8.0): bottom-layer / top-layer thickness (1: uniform; the top layer's elements at most 10 times wider than thick)
        boundary (default "mirror"): how the lateral faces are held
        strain (default "finite"): the kinematics: `finite` (the reference) or `small` (linear elasticity with the initial moduli, on the same mesh)
        bulk_ratio (default 5000.0): bulk modulus / μ0 of a hyperelastic material (a linear one uses its own ν unless ν = ½)
        steps (default 20): steps after first contact, aimed at evenly spaced A/A0
        max_area_fraction (default 0.3): A/A0 (top nodes in contact / top nodes) of the last step
        map_fractions (default [0.05,0.1,0.2,0.3]): A/A0 at which `contact_maps` keeps the pressure, the contact mask and the deformed mesh
        tolerance (default 1e-8): Newton's tolerance: residual 2-norm on the free unknowns / 2-norm of the contact reactions
        max_iterations (default 30): Newton iterations per attempt before the increment is halved (four times at most)
        max_nodes (default 200000): the most mesh nodes accepted, checked before meshing (measured: 16–20 kB per node at 8 layers on 24²–128² patches, about 30 kB at 16 layers; see max_memory_gb)
        max_memory_gb (default 8.0): the most memory the solve may hold, checked before it starts from the sparse factor's exact size (the estimate is in the notes)
        lateral_coarsening (default false): coarsen deep layers laterally: elements 2, 4, 8 … pixels wide where a layer is that many pixels thick and its top that deep below the surface (the top layer one pixel), the fine nodes on a coarse face tied to it; fewer nodes and a smaller factor for about the same load–area response (within 1 % on the paper's patches)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        surface (field, one): height map, metres (no missing points inside the window)
        material (table, one): the material table (a preset, a fit or the constants stage)

    Returns a dict of the outputs:
        response (table): one row per step, first touch first (the contact models' columns first)
        contact_maps (files): pressure and contact maps (.npy) and the deformed mesh (.vtk) at map_fractions, indexed

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_greenwood_williamsonOutputs = TypedDict("_greenwood_williamsonOutputs", {"response": pl.DataFrame, "summary": pl.DataFrame, "bands": pl.DataFrame})

def greenwood_williamson(
    *,
    psd: Optional[Table] = None,
    stats: Optional[Table] = None,
    surface: Optional[Field] = None,
    material: Table,
    replicates: Optional[Table] = None,
    model: Literal["hyperelastic", "linear"] = "hyperelastic",
    tangent: Literal["equibiaxial", "uniaxial"] = "equibiaxial",
    scheme: Literal["euler", "heun"] = "heun",
    poisson: Any = 0.5,
    min_area_fraction: float = 0.001,
    max_area_fraction: float = 0.95,
    steps: int = 200,
    q_min_per_m: Optional[float] = None,
    q_max_per_m: Optional[float] = None,
    nominal_area_m2: Optional[float] = None,
    bins_per_decade: int = 10,
    periodic: bool = False,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _greenwood_williamsonOutputs:
    """Greenwood-Williamson asperity model with its summits from the spectral moments: load against contact area

    Independent Hertzian summits of one radius with Gaussian heights, no elastic interaction between them (Greenwood & Williamson, Proc. R. Soc. A 295, 300, 1966). SPECTRUM: as in `persson` (input `psd` or `surface`, Persson's normalisation, q range default the whole spectrum with the 20 um filter's roll-off in it). PARAMETERS from the profile moments of the isotropic surface (Nayak, J. Lubr. Technol. 93, 398, 1971): m0 = 2 pi int q C dq, m2 = pi int q^3 C dq, m4 = (3 pi/4) int q^5 C dq; Nayak's alpha = m0 m4/m2^2; summit density eta = m4/(6 pi sqrt(3) m2); mean summit radius R = (3/8) sqrt(pi/m4), summit-height spread sigma_s = sqrt((1 - 0.8968/alpha) m0) and mean summit height 4 sqrt(m0/(pi alpha)) above the mean plane (McCool, Wear 107, 37, 1986). m4 and so eta and R are set by the shortest wavelengths kept (for a self-affine surface they grow without bound with q_max): the model's answer depends on the q range, reported in `summary`. INTEGRALS at separation d of the flat from the mean plane of the surface heights (u = (d - mean summit height)/sigma_s, F_k(u) = int_0^inf t^k phi(u + t) dt): contacts/A0 = eta F_0(u); A/A0 = pi eta R sigma_s F_1(u); p/E* = (4/3) eta sqrt(R) sigma_s^(3/2) F_(3/2)(u). `z_m` is d (it falls as the load rises); kappa = (A/A0)/(p/(E0* h'rms)), h'rms = sqrt(2 m2), grows without bound as the load vanishes (A/p ~ sqrt(u)) and falls with load. ROWS, LOAD, A0 and MODEL (linear, or the tangent modulus on the theory's curve, starting from the self-consistent small load) as in `persson`. GW counts each summit's Hertz area alone, so A/A0 may pass 1 at large load; the model is meant for small loads. BANDS: with `replicates` (material-fit's bootstrap) each replicate material's law is integrated over the same theory curve (the curve for E* = 1 does not depend on the material), a few microseconds each; `bands` gives per row the 5th, 50th and 95th percentiles of load_norm (over the main material's E0* A0) and of tangent_ratio (over the replicate's own E0*), as `icm` does; a replicate whose law gives out is left out with a note.

    Parameters (keywords, as in a pipeline's `with:` block):
        model (default "hyperelastic"): contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
        tangent (default "equibiaxial"): the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
        scheme (default "heun"): integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
        poisson (default 0.5): Poisson's ratio ν of the composite moduli (a linear material uses its own)
        min_area_fraction (default 0.001): A/A0 of the first row
        max_area_fraction (default 0.95): A/A0 of the last row (below 1: the theories reach full contact only as the load grows without bound)
        steps (default 200): rows, evenly spaced in ln(load)
        q_min_per_m (optional) [rad/m]: smallest wavevector integrated (default: the spectrum's first)
        q_max_per_m (optional) [rad/m]: largest wavevector integrated (default: the spectrum's last, the map's Nyquist)
        nominal_area_m2 (optional) [m²]: A0 when neither `stats` nor `surface` gives it
        bins_per_decade (default 10): log bins per decade of the PSD computed from input `surface`
        periodic (default false): input `surface` is periodic (no window for its PSD)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        psd (table, optional): stage surface's PSD table (its radial rows are used)
        stats (table, optional): stage surface's stats, beside `psd`: A0 = nx ny dx² (1 - nan_fraction)
        surface (field, optional): a height map instead of `psd` (its radial PSD is computed here)
        material (table, one): the material table (a preset or a fit)
        replicates (table, optional): material-fit's bootstrap replicates: each replicate's law is integrated over the same theory curve, for `bands`

    Returns a dict of the outputs:
        response (table): one row per load, icm's columns first
        summary (table): one row: q range, moments, Nayak's alpha, summit density, radius and heights, A0
        bands (table): 5–95 % bands over the material's bootstrap replicates, one row per load (no rows without `replicates`)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

def height_map(
    *,
    path: Union[str, PathLike[str]],
    channel: Optional[Any] = None,
    pixel_m: Optional[float] = None,
    pixel_y_m: Optional[float] = None,
    scale_to_m: float = 1.0,
    crop_points: Optional[Sequence[int]] = None,
    crop_m: Optional[Sequence[float]] = None,
    circle_m: Optional[Sequence[float]] = None,
    mask: Optional[Union[str, PathLike[str]]] = None,
    spikes: Literal["none", "local", "global"] = "none",
    spike_k: float = 5.0,
    spike_radius: int = 1,
    form: Literal["none", "polynomial", "sphere", "cylinder-x", "cylinder-y", "cylinder"] = "none",
    form_degree: int = 2,
    level_rows: Literal["none", "median", "mean", "tilt", "polynomial", "median-differences"] = "none",
    level_rows_degree: int = 2,
    fast_axis: Optional[Literal["x", "y"]] = None,
    tip_radius_m: Optional[float] = None,
    max_points: int = 67108864,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> Field:
    """Load a height map (.npy or an instrument file) with its grid spacing

    Reads a height map as the instrument wrote it. The format is told by the first bytes, the extension only where bytes cannot tell (text): optical profilers and interferometers (ISO 25178-72 X3P, Digital Surf .sur and MountainsMap .mnt, Sensofar .plu, Zygo MetroPro .dat and .datx, Wyko .opd, Alicona .al3d, FRT .frt, TrueMap/GelSight .tmd), AFMs (Bruker Nanoscope .di, Nanosurf .nid, Asylum/Igor .ibw, Molecular Imaging .mi), NetCDF .nc as SurfaceTopography writes it, text (an ASCII matrix with or without a header stating grid, pixel size and units; Gwyddion's ASCII export) and the Dektak stylus .csv (a line scan: an n x 1 map along x), each with its units and pixel size (non-square pixels kept; missing points NaN) and equal to what SurfaceTopography 1.x reads; or a 2-D .npy array (float64 or float32) whose axis 0 is x, as the SurfaceTopography package writes it, which holds no spacing: `pixel_m` is then required and values are multiplied by `scale_to_m`. CHANNELS: a multi-channel file gives its height channel (the one SurfaceTopography reads by default) unless `channel` names another by position or name; the note lists the channels found. For an instrument file `pixel_m` / `pixel_y_m` replace the file's spacing (a recalibration; the note says by how much) and `scale_to_m` must stay 1. The note names the format, the grid, the missing points and the instrument where the file says. A file no reader knows is refused naming what its bytes look like and the formats read. PREPARATION, in this order, each step in a note with what it removed: a mask (`mask`: a .npy file of the map's shape as read, axis 0 = x, bool true or uint8/float 1 = keep, false/0 = drop, any other value refused; its dropped points become NaN; a mask of another shape is refused naming both shapes; crop_m already gives a rectangle); a window (`crop_points`, or `crop_m` from the map's first point: first point round(x0/dx), end round((x0 + lx)/dx)); a disc kept (`circle_m`, the rest NaN); spikes set to NaN (`spikes: local`: a point farther than spike_k robust standard deviations (1.4826 MAD of all such deviations) from the median of what its neighbours within spike_radius predict along each direction, confirmed with the other candidates left out; `global`: farther than spike_k robust σ from the median height); a form subtracted (`form`: a least-squares polynomial of total degree form_degree in Legendre polynomials of centred, scaled coordinates; a sphere or a cylinder (axis along x, y or fitted in the plane), Levenberg-Marquardt from an algebraic (Kasa) start on the vertical residual); the scan lines levelled (`level_rows`, the methods of Gwyddion's Align Rows: each line along the fast axis has its `median` or `mean` height, its least-squares `tilt` or its least-squares `polynomial` of degree level_rows_degree (Legendre, in the position along the line) subtracted, or with `median-differences` is shifted so that the median of its height differences to the line before is zero, the shifts then moved by their median; NaN points take no part; a line with no more measured points than the model has unknowns (for median-differences, without one shared with the line before) is left as is and counted; the note gives the rms of what was removed). The fast axis is the file's where its format states it (the AFM formats read: x, each stored row a scan line), `fast_axis` where given (it overrides the file, the note saying so), x otherwise. Spikes go before the form, which they would pull; the lines are levelled on what the form leaves, as a line's own median or tilt would take its share of a curved form. All are off by default: the map is given as measured, and `surface` removes a plane. RELIABLE RANGE: with `tip_radius_m` = R (a probe's tip), the map as prepared gets the short-wavelength cut-off of SurfaceTopography's `short_reliability_cutoff` (Sanner et al., Appl. Surf. Sci. Adv. 7, 100190, 2022): the span λ_c of the central second difference [h(x + λ/2) − 2h(x) + h(x − λ/2)]/(λ/2)² along x (heights between points interpolated linearly; points whose stencil leaves the map, or touches a NaN, left out) at which its most negative value over the map is −1/(2R), the safety factor 1/2 of the paper, found by Brent's method between twice the mean spacing and half the mean side. Below λ_c the tip, not the surface, shapes the map. No cut-off when the map's curvature stays above −1/(2R) at twice the spacing (the tip resolves the grid); the mean side when it is below even at half of it (nothing reliable). The cut-off goes with the height field, as `short_cutoff_m` in its grid sidecar, and into a note.

    Parameters (keywords, as in a pipeline's `with:` block):
        path (required): the height map: .npy (2-D float64/float32, axis 0 = x, NaN = missing) or an instrument file of a format listed below
        channel (optional): the channel of a multi-channel file (AFM height, deflection, phase ...): its position from 0 in the list the note gives, or its name (default: the height channel SurfaceTopography reads first)
        pixel_m (optional) [m]: grid spacing along x (needed for .npy; for an instrument file it replaces the file's)
        pixel_y_m (optional) [m]: grid spacing along y (default: pixel_m, or the file's)
        scale_to_m (default 1.0) [m/unit]: factor from .npy units to metres (1e-6 for micrometres; instrument files state their units)
        crop_points (optional): a window in points, [x0, y0, nx, ny] (axis 0 = x), cut out first
        crop_m (optional) [m]: a window in metres from the map's first point, [x0_m, y0_m, lx_m, ly_m] (instead of crop_points)
        circle_m (optional) [m]: keep only the disc [xc_m, yc_m, radius_m] (metres from the map's first point); the rest becomes NaN
        mask (optional): points to keep: a .npy (2-D bool, uint8 or float 0/1, axis 0 = x) of the map's shape as read; its false/0 points become NaN first, before the window
        spikes (default "none"): spikes set to NaN (after the window, before the form)
        spike_k (default 5.0): spike threshold, in robust standard deviations (1.4826 MAD)
        spike_radius (default 1): half-width of the neighbourhood of the local spike rule: 1 = 3 x 3, 2 = 5 x 5, 3 = 7 x 7
        form (default "none"): the form subtracted (after spikes, before the scan lines are levelled)
        form_degree (default 2): total degree of the polynomial form
        level_rows (default "none"): scan-line levelling, last: each line along the fast axis has its median, mean, least-squares tilt or polynomial subtracted, or is shifted so the median of its differences to the line before is zero; NaN points take no part
        level_rows_degree (default 2): degree of each scan line's least-squares polynomial for level_rows: polynomial (0 = the mean, 1 = the tilt)
        fast_axis (optional): the axis along which each scan line ran, for level_rows (default: the file's where its format states it, x for the AFM formats read; otherwise x)
        tip_radius_m (optional) [m]: radius of the probe's tip (AFM, stylus): the map is then reliable only at length scales above the cut-off λ_c where its most negative scale-dependent curvature (the second difference spanning λ along x) reaches −1/(2 R), SurfaceTopography's short_reliability_cutoff (Sanner et al., Appl. Surf. Sci. Adv. 7, 100190, 2022); λ_c goes with the height field (its grid.json, short_cutoff_m) and into a note
        max_points (default 67108864): the most points a map may have (default 2^26 = 67 108 864, 512 MiB of heights); a file whose header claims more is refused before its data is read or inflated

    Returns the output:
        height (field): heights in metres, NaN where not measured

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_icmOutputs = TypedDict("_icmOutputs", {"response": pl.DataFrame, "bands": pl.DataFrame})

def icm(
    *,
    profile: Table,
    material: Table,
    replicates: Optional[Table] = None,
    model: Literal["hyperelastic", "linear"] = "hyperelastic",
    tangent: Literal["equibiaxial", "uniaxial"] = "equibiaxial",
    scheme: Literal["euler", "heun"] = "heun",
    poisson: Any = 0.5,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _icmOutputs:
    """Incremental contact model: load against contact area from a truncation profile

    Integrates dF/d(-z) = 2 E_t*(S) r(z) N(z) from F(z_max) = 0 downward over the profile's planes (the paper's Eqs. 5-7); `z_m` is the plane's height. Hyperelastic: E_t* = E_t(phi^-1(S)) / (1 - nu^2) with phi a nominal stress curve of the material (Eq. 2), E_t = dphi/deps (Eq. 6), evaluated at the compressive mean stress S = -F/A (so eps < 0). `tangent: equibiaxial` (default) is the paper's phi, the equibiaxial curve: E_t*/E0* = 2 at first contact for nu = 1/2, so the curve starts at twice the linear one; it assumes the patch's material is stretched equally in its plane. `tangent: uniaxial` takes phi from the uniaxial curve in compression (free lateral expansion, the small-strain limit of Hertz and Boussinesq): E_t*/E0* = 1 at first contact, where the curve meets the linear one. Linear (Wang's original ICM): E_t* = E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu). A linear-elastic material (stage `material`, family `linear`) gives E* = E/(1 - nu^2) with its own nu at every stress, whatever `model`, `tangent` and `poisson` say (a note says so). Schemes: `euler` is the paper's explicit step; `heun` the explicit trapezoidal rule (second order, using only tabulated planes; exact for a flat punch). Planes with A = 0 or N = 0 add no load. A0 is area_m2 / area_fraction of the profile. If S leaves the range where phi is invertible, the stage stops and names the plane and the stress. With `replicates` (material-fit's bootstrap) every replicate material is solved over the same planes (in parallel; the same on any thread count) and `bands` gives, per plane, the 5th, 50th and 95th percentiles of load_norm (each replicate's load over the main material's E0* A0, on the response's axes) and of tangent_ratio (each replicate's E_t* over its own E0*); a replicate whose law gives out is left out with a note.

    Parameters (keywords, as in a pipeline's `with:` block):
        model (default "hyperelastic"): contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
        tangent (default "equibiaxial"): the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
        scheme (default "heun"): integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
        poisson (default 0.5): Poisson's ratio ν of the composite moduli (a linear material uses its own)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        profile (table, one): the truncation profile, top down
        material (table, one): the material table (a preset or a fit)
        replicates (table, optional): material-fit's bootstrap replicates: each is solved too, for `bands`

    Returns a dict of the outputs:
        response (table): one row per profile plane
        bands (table): 5–95 % bands over the material's bootstrap replicates, one row per plane (no rows without `replicates`)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

def material(
    *,
    family: Optional[Literal["linear", "neo-hookean", "mooney-rivlin", "yeoh", "arruda-boyce", "ogden"]] = None,
    e_pa: Optional[float] = None,
    poisson: Optional[Any] = None,
    mu_pa: Optional[Any] = None,
    alpha: Optional[Any] = None,
    c10_pa: Optional[float] = None,
    c01_pa: Optional[float] = None,
    c20_pa: Optional[float] = None,
    c30_pa: Optional[float] = None,
    lambda_m: Optional[float] = None,
    file: Optional[Union[str, PathLike[str]]] = None,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> pl.DataFrame:
    """Any material by its constants (linear E, ν or a hyperelastic family) as the material table

    Writes the `material` table every contact stage reads (icm, bem, persson, greenwood-williamson, synth-contact), from `family` and exactly its parameters (any other is refused, naming it), moduli in Pa: `linear` e_pa, poisson (default 0.5); `neo-hookean` mu_pa (W = (mu/2)(I1 - 3), mu = mu0); `mooney-rivlin` c10_pa, c01_pa (mu0 = 2 (C10 + C01) > 0); `yeoh` c10_pa > 0, c20_pa, c30_pa; `arruda-boyce` mu_pa > 0, lambda_m > 1 (Abaqus' five-term series); `ogden` mu_pa and alpha, lists of one length (Abaqus' W = sum 2 mu_i/alpha_i^2 (...), mu0 = sum mu_i > 0, alpha_i != 0). Or `file` alone: a text file of lines `name, value[, value...]` with the same names (`family, ogden` / `mu_pa, 1.2e6, -2e5` / `alpha, 2, -2`), `#` comments and blank lines skipped, each name once; errors name the file and line. Refused, naming the parameter: a modulus term of size outside 1 Pa to 1e12 Pa (0 is allowed), and a hyperelastic law that is Drucker-unstable anywhere in 0.7 <= lambda <= 1.5 in uniaxial, planar or equibiaxial loading (Abaqus' check, as material-fit reports it; the message says in which test and beyond which stretch). A `linear` material is not hyperelastic: the contact stages use E* = E/(1 - nu^2) with its own nu at every stress, whatever their `model`, `tangent` and `poisson` say (they note it when these differ), so the hyperelastic and linear runs on it coincide. The paper's EPDM stays the preset `material-preset`.

    Parameters (keywords, as in a pipeline's `with:` block):
        family (optional): the family (or give `file`): linear | neo-hookean | mooney-rivlin | yeoh | arruda-boyce | ogden
        e_pa (optional) [Pa]: Young's modulus E (linear)
        poisson (optional): Poisson's ratio ν (linear; 0.5 when absent)
        mu_pa (optional) [Pa]: neo-hookean: the shear modulus μ0; arruda-boyce: μ; ogden: the list μ_i (Abaqus' convention, Σ μ_i = μ0)
        alpha (optional): ogden: the exponents α_i, one per μ_i, non-zero
        c10_pa (optional) [Pa]: mooney-rivlin, yeoh: C10
        c01_pa (optional) [Pa]: mooney-rivlin: C01
        c20_pa (optional) [Pa]: yeoh: C20
        c30_pa (optional) [Pa]: yeoh: C30
        lambda_m (optional): arruda-boyce: the locking stretch λm, > 1
        file (optional): a parameter file instead of the parameters above (lines `name, value[, value...]`, see the stage doc)

    Returns the output:
        material (table): the material: one row per parameter (model, param, value in SI); `linear` writes e and poisson

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_material_fitOutputs = TypedDict("_material_fitOutputs", {"material": pl.DataFrame, "params": pl.DataFrame, "quality": pl.DataFrame, "curves": pl.DataFrame, "stability": pl.DataFrame, "comparison": pl.DataFrame, "replicates": pl.DataFrame})

def material_fit(
    *,
    tensile: Union[Table, Mapping[str, Table]],
    model: Any = "ogden-6",
    residual: Literal["relative", "absolute"] = "relative",
    constraint: Literal["stable", "none", "in-range"] = "stable",
    compression_stretch: float = 0.6,
    windows: Any = ...,
    starts: int = 64,
    weights: Any = ...,
    compare: bool = True,
    seed: int = 1,
    poisson: Any = 0.5,
    bootstrap: Any = ...,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _material_fitOutputs:
    """Fit a hyperelastic model to UT, PT and BT data at once; quality, stability, comparison, bootstrap

    Fits one strain-energy family to all modes simultaneously by Levenberg–Marquardt (MINPACK-style, the `levenberg-marquardt` crate). Residuals are relative errors (T_fit − T)/T by default, as in Abaqus' material evaluation (the denominator is floored at 1 % of the mode's largest stress so points at λ ≈ 1 cannot dominate); `residual: absolute` uses stress differences. `weights` multiply each mode's squared residuals. Ogden (Abaqus convention, W = Σ 2μ_i/α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), μ0 = Σ μ_i) and Arruda–Boyce (Abaqus' five-term series) are non-convex: each of `starts` deterministic starts draws the shape parameters (α_i; λm) from a seeded generator, solves the moduli by linear least squares, then refines everything; the best converged start wins. A fit that converges from no start is an error naming the model; so is data with fewer points than parameters. Ogden terms are written in ascending α. `constraint: stable` (the default) holds every modulus ≥ 0 (Ogden μ_i in the Abaqus convention, Mooney–Rivlin C10 and C01, Yeoh C10…C30, neo-Hookean and Arruda–Boyce μ): each Ogden term is then convex in the log strains, so the model is Drucker-stable at every stretch by construction, and the moduli are non-negative least squares (Lawson–Hanson) inside the same search. It is the default because the unconstrained optimum of a many-term Ogden fit is ill-conditioned: its μ_i come out as huge numbers of both signs that cancel (±5e14 Pa on Treloar's data, ±5e9 Pa in the paper's own Table 1), move with any change of the data, cannot be read or reused, and can turn unstable just outside the data (the contact models evaluate the equibiaxial law in compression, beyond every tensile test). The price is a larger error where the data want cancelling terms: the `comparison` table fits every family under each constraint and the stage notes the chosen family's RMS error under each. α is not bounded: with μ_i ≥ 0 a large α is as stable as a small one, and the data decide. `constraint: none` is Abaqus' plain least squares (the paper's fit). `constraint: in-range` imposes Drucker stability inside the fit, over stated stretch windows rather than at every stretch: for each trial shape the moduli are least squares subject to the log-strain Hessian being positive definite (smallest eigenvalue at least 1e-6 of the largest measured stress) on a geometric grid of each window (Lawson–Hanson LSI, constraints added by cutting planes where the grid shows a violation; 64 stretches per window during the search, 2000 for each converged start), and the shape search's Jacobian is a forward difference. μ_i ≥ 0 is sufficient for stability, not necessary where the material is used: the paper's own Table 1 cancels at ±5e9 Pa and is Drucker-stable over the data, and in-range recovers it from its synthetic tests (μ0 within 0.1 % of 1.79 MPa, RMS at the 0.5 % noise) where `stable` keeps a single term (RMS 9.2 % on the shipped sample). It does not cure the ill-conditioning: where the data want cancelling moduli it keeps them (±5e12 Pa in the 6-term fit to Treloar's data), and assures only their stability on the windows. The default windows are each fitted mode's data range extended to λ = 1, and equibiaxial compression down to `compression_stretch` (0.6): the paper pipeline's deepest mean contact stress is −4.9 MPa with its in-range fit and −7.9 MPa with the softer `stable` one (Greenwood–Williamson on T1 at 95 % contact), and with the paper's Table 1 material φ(0.64) ≈ −7.0 MPa and φ(0.6) ≈ −9.9 MPa, so 0.6 covers it; the paper's material itself is Drucker-unstable below λ ≈ 0.56 in BT. `windows: { UT: [lo, hi], PT: .., BT: .. }` replaces a mode's window (0.1 ≤ lo ≤ 1 ≤ hi ≤ 10). Bootstrap refits and the comparison's in-range rows use the windows of the full data set. The `quality` table gives the fit's condition number (its Jacobian in the free parameters, columns scaled to unit length) and the largest parameter correlation. `bootstrap: {count, seed, starts}` refits `count` resampled data sets (each mode's points drawn with replacement, as many as it has: the pairs bootstrap, which unlike resampling residuals does not assume the family is the true law), each from the full-data optimum plus `starts` seeded starts, in parallel and the same on any thread count; `replicates` holds every refit's material for the contact models, which then write 5–95 % bands, and `params` gains each parameter's 5–95 % interval (none for an Ogden term held at μ_i = 0, neither μ_i nor its α_i). Stability, as Abaqus checks it: Drucker's condition dσ:dε > 0 for every volume-keeping increment of log strain (true stress against log strain), i.e. the Hessian of W in the log strains (ε1, ε2) is positive definite, checked along UT, PT and BT for 0.1 ≤ λ ≤ 10; `stability` gives the interval around λ = 1 where it holds (λ < 1 is compression), flags a limit that is the search range's edge (0.1 or 10: stable that far, not an instability found), gives the windows imposed under `in-range` (NaN otherwise), and beside it the interval where the nominal stress rises (dT/dλ > 0), which is where a load-controlled test is stable and, in BT, where the paper's φ can be inverted. For the paper's Table 1 material the BT nominal stress φ peaks at λ ≈ 1.46 (ε ≈ 0.46) and falls until λ ≈ 2; the Drucker condition itself holds in BT tension up to λ ≈ 4.4 but fails in equibiaxial compression below λ ≈ 0.56 (ε ≈ −0.44; the same state as UT tension beyond λ ≈ 3.2). Contact uses the compressive branch: the contact stress is compressive, so the incremental contact model evaluates ε = φ⁻¹(S) at S = −F/A < 0 (ε < 0), where φ rises monotonically. `comparison` fits every family (ogden-1…6, neo-hookean, mooney-rivlin, yeoh, arruda-boyce) to the same data under each constraint (stable, none, in-range) and ranks them by total RMS relative error (each mode's beside it), with their stable ranges, so the choice of model and what each constraint costs can be read as the paper did; a note gives the chosen family's RMS error under each constraint.

    Parameters (keywords, as in a pipeline's `with:` block):
        model (default "ogden-6"): the strain-energy family to fit
        residual (default "relative"): how a residual is measured (relative, as Abaqus)
        constraint (default "stable"): stable (all moduli ≥ 0, Drucker-stable at every stretch), in-range (Drucker-stable on the windows, imposed in the fit) or none
        compression_stretch (default 0.6): lower end of the default equibiaxial window of `in-range` (BT compression)
        windows (default {"UT":null,"PT":null,"BT":null}): explicit windows of `in-range`, e.g. { BT: [0.5, 2.0] }
        starts (default 64): number of starts for Ogden and Arruda–Boyce (deterministic)
        weights (default {"UT":1.0,"PT":1.0,"BT":1.0}): mode weights in the objective
        compare (default true): also fit and rank every family
        seed (default 1): seed of the random starts
        poisson (default 0.5): Poisson's ratio ν of the derived moduli e0 and e0_star
        bootstrap (default {"count":0,"seed":1,"starts":4}): refits on resampled data, carried downstream as `replicates`

    Inputs (keywords; a table as a polars or pandas DataFrame):
        tensile (table, oneormore): UT/PT/BT stress–stretch data (tensile-table or the DIC stage): one table (`tensile: csv`) or several fitted together (`tensile: { UT: dic-ut, PT: dic-pt }`)

    Returns a dict of the outputs:
        material (table): the fitted model, for downstream stages (the ICM reads it)
        params (table): fitted parameters and the derived initial moduli
        quality (table): fit quality per mode and over all points
        curves (table): measured and fitted stress at every measured stretch
        stability (table): Drucker-stable stretch range per mode, whether a limit is the search range's edge, and the windows imposed
        comparison (table): every family fitted to the same data under each constraint (stable, none, in-range), ranked (only the chosen family if compare: false)
        replicates (table): the material of every bootstrap refit (no rows without `bootstrap`), for the contact models' bands

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

def material_preset(
    *,
    name: Literal["paper-epdm"] = "paper-epdm",
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> pl.DataFrame:
    """A built-in material (default: the paper's 6-term Ogden EPDM, Table 1)

    `paper-epdm` is the paper's Table 1: a 6-term Ogden model in the Abaqus convention W = Σ 2μ_i/α_i² (λ1^α_i + λ2^α_i + λ3^α_i − 3), μ0 = Σ μ_i = 1.79 MPa, E0 = 3 μ0 = 5.37 MPa, E0* = E0/(1 − ν²) = 7.16 MPa. Sign convention for contact: the contact stress is compressive, so the incremental contact model evaluates ε = φ⁻¹(S) at S = −F/A < 0 (ε < 0), where the equibiaxial tangent E_t rises from E_t(0) = 6 μ0 = 2 E0. Stability: with these parameters φ (the equibiaxial nominal stress) peaks at ε ≈ 0.46 in tension and is not invertible beyond; it rises monotonically in compression. Abaqus' Drucker check holds in equibiaxial tension up to λ ≈ 4.4 and fails in equibiaxial compression below λ ≈ 0.56 (ε ≈ −0.44, stresses below about −15 MPa); see `material-fit`'s `stability` table.

    Parameters (keywords, as in a pipeline's `with:` block):
        name (default "paper-epdm"): the preset

    Returns the output:
        material (table): the model: one row per parameter (model, param, value in SI)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_perssonOutputs = TypedDict("_perssonOutputs", {"response": pl.DataFrame, "summary": pl.DataFrame, "bands": pl.DataFrame})

def persson(
    *,
    psd: Optional[Table] = None,
    stats: Optional[Table] = None,
    surface: Optional[Field] = None,
    material: Table,
    replicates: Optional[Table] = None,
    variant: Literal["original", "yang-persson"] = "original",
    gamma: float = 0.45,
    model: Literal["hyperelastic", "linear"] = "hyperelastic",
    tangent: Literal["equibiaxial", "uniaxial"] = "equibiaxial",
    scheme: Literal["euler", "heun"] = "heun",
    poisson: Any = 0.5,
    min_area_fraction: float = 0.001,
    max_area_fraction: float = 0.95,
    steps: int = 200,
    q_min_per_m: Optional[float] = None,
    q_max_per_m: Optional[float] = None,
    nominal_area_m2: Optional[float] = None,
    bins_per_decade: int = 10,
    periodic: bool = False,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _perssonOutputs:
    """Persson's theory (2001; Yang & Persson 2008): load against contact area and mean separation from the height spectrum

    The rough surface as a rigid, randomly rough (Gaussian, isotropic) surface on an elastic half-space, described by its spectrum alone. SPECTRUM: input `psd` (stage surface's radial rows, SurfaceTopography's normalisation) or `surface` (a height map; its radial PSD computed as surface does: mean removed, NaN at the mean, Hann window unless `periodic`, bins_per_decade); converted to Persson's C = C_ST/(2 pi)^2 (<h^2> = 2 pi int q C dq); C is a power law between tabulated points. Q RANGE: by default the whole spectrum, from its first bin to the map's Nyquist wavevector pi/dx. The 20 um filter of stage surface is not undone: its roll-off (a Gaussian passing 25 % of the power at the Nyquist wavelength) is in the spectrum, so the theory sees the same surface as icm and bem on the filtered map; h'rms, which sets the small-load area, is dominated by the shortest wavelengths kept, so q_max_per_m changes the answer and is reported in `summary` (h'rms here is the spectral one, sqrt(2 pi int q^3 C dq), not surface's forward differences). THEORY: A/A0 = erf(p/sqrt(2 V)), V = (pi/2) E*^2 int q^3 C dq = E*^2 h'rms^2/4 (Persson, J. Chem. Phys. 115, 3840, 2001); small load: A/A0 = sqrt(8/pi) p/(E* h'rms), kappa = 1.596. `yang-persson`: Yang & Persson (J. Phys.: Condens. Matter 20, 215214, 2008) march in q with the partial-contact factor S = gamma + (1 - gamma) P(q)^2 slowing the stress diffusion, dV_p = S dV, P = erf(p/sqrt(2 V_p)); kappa -> 1.596/sqrt(gamma) at small load (2.38 for gamma = 0.45). MEAN SEPARATION (`mean_separation_m`, and `z_m`): p = -dU_el/du with U_el/A0 = (pi/2) E* int q^2 C P S dq (S = 1 for original; Persson, PRL 99, 125502, 2007), u = 0 at full contact: the mean gap between the flat and the deformed surface, so `z_m` here is a separation, not icm's plane height from the lowest point. ROWS: `steps` loads evenly spaced in ln(p) from A/A0 = min_area_fraction to max_area_fraction of the linear theory. LOAD: p = F/A0, A0 from input `stats` (nx ny dx^2 (1 - nan_fraction), the map's measured area as bem counts it), from input `surface`, or nominal_area_m2. MODEL `linear`: F = E0* f, f = A0 p/E* (E0* = E0/(1 - nu^2), E0 = 2 mu0 (1 + nu), as in icm). `hyperelastic`: the paper's tangent modulus (Eqs. 5-7) on the theory's curve, dF = E_t*(-F/A) df, as bem does (E_t*/E0* = 2 at first contact for nu = 1/2 with the paper's `tangent: equibiaxial`, 1 with `uniaxial`; a linear material's E* throughout); the theory puts the mean contact stress at about E_t* h'rms/kappa at small load, so the first row starts from the self-consistent F = f E_t*(-F/A) instead of F = 0 (a material that stiffens faster than that has no such load and is refused). tangent_ratio = E_t*/E0*; kappa = (A/A0)/(p/(E0* h'rms)) with the spectral h'rms. BANDS: with `replicates` (material-fit's bootstrap) each replicate material's law is integrated over the same theory curve (the curve for E* = 1 does not depend on the material), a few microseconds each; `bands` gives per row the 5th, 50th and 95th percentiles of load_norm (over the main material's E0* A0) and of tangent_ratio (over the replicate's own E0*), as `icm` does; a replicate whose law gives out is left out with a note.

    Parameters (keywords, as in a pipeline's `with:` block):
        variant (default "original"): the theory's form
        gamma (default 0.45): Yang & Persson's γ (0.42–0.45 in the literature); only for yang-persson
        model (default "hyperelastic"): contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
        tangent (default "equibiaxial"): the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
        scheme (default "heun"): integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
        poisson (default 0.5): Poisson's ratio ν of the composite moduli (a linear material uses its own)
        min_area_fraction (default 0.001): A/A0 of the first row
        max_area_fraction (default 0.95): A/A0 of the last row (below 1: the theories reach full contact only as the load grows without bound)
        steps (default 200): rows, evenly spaced in ln(load)
        q_min_per_m (optional) [rad/m]: smallest wavevector integrated (default: the spectrum's first)
        q_max_per_m (optional) [rad/m]: largest wavevector integrated (default: the spectrum's last, the map's Nyquist)
        nominal_area_m2 (optional) [m²]: A0 when neither `stats` nor `surface` gives it
        bins_per_decade (default 10): log bins per decade of the PSD computed from input `surface`
        periodic (default false): input `surface` is periodic (no window for its PSD)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        psd (table, optional): stage surface's PSD table (its radial rows are used)
        stats (table, optional): stage surface's stats, beside `psd`: A0 = nx ny dx² (1 - nan_fraction)
        surface (field, optional): a height map instead of `psd` (its radial PSD is computed here)
        material (table, one): the material table (a preset or a fit)
        replicates (table, optional): material-fit's bootstrap replicates: each replicate's law is integrated over the same theory curve, for `bands`

    Returns a dict of the outputs:
        response (table): one row per load, icm's columns first
        summary (table): one row: variant, q range, h_rms, h'rms, small-load kappa, A0
        bands (table): 5–95 % bands over the material's bootstrap replicates, one row per load (no rows without `replicates`)

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

def report(
    *,
    curves: Optional[Table] = None,
    quality: Optional[Table] = None,
    params: Optional[Table] = None,
    stability: Optional[Table] = None,
    comparison: Optional[Table] = None,
    material: Optional[Table] = None,
    heights: Optional[Mapping[str, Field]] = None,
    psd: Optional[Mapping[str, Table]] = None,
    stats: Optional[Mapping[str, Table]] = None,
    profiles: Optional[Mapping[str, Table]] = None,
    areal: Optional[Mapping[str, Table]] = None,
    material_ratio: Optional[Mapping[str, Table]] = None,
    acf: Optional[Mapping[str, Table]] = None,
    scale_dependent: Optional[Mapping[str, Table]] = None,
    distributions: Optional[Mapping[str, Table]] = None,
    responses: Optional[Mapping[str, Mapping[str, Table]]] = None,
    bands: Optional[Mapping[str, Mapping[str, Table]]] = None,
    model_summaries: Optional[Mapping[str, Mapping[str, Table]]] = None,
    experiments: Optional[Mapping[str, Table]] = None,
    agreement: Optional[Mapping[str, Table]] = None,
    load_ratio: Optional[Mapping[str, Table]] = None,
    transforms: Optional[Mapping[str, Table]] = None,
    finite_strain: Optional[Mapping[str, Mapping[str, Table]]] = None,
    refinement: Optional[Mapping[str, Mapping[str, Table]]] = None,
    compare_figures: Optional[Mapping[str, FilesLike]] = None,
    title: str = "hypercontact — rough-surface contact of a hyperelastic rubber",
    area_fractions: Sequence[float] = ...,
    poisson: Any = 0.5,
    models: Sequence[str] = ...,
    fig7_models: Sequence[str] = ...,
    fig9_models: Sequence[str] = ...,
    summary_models: Sequence[str] = ...,
    reference_model: Optional[str] = None,
    finite_strain_reference: str = "fem",
    finite_strain_area_fractions: Sequence[float] = ...,
    refinement_area_fractions: Sequence[float] = ...,
    refinement_points_per_wavelength: float = 2.0,
    published_material: Optional[Literal["paper-epdm"]] = None,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> Files:
    """HTML report with the paper's Figs. 2, 4, 6, 7, 8, a model comparison (Fig. 9; PNG + SVG), Table 1 and a summary

    Every input is optional: a figure whose inputs are not wired is skipped and the page says why (e.g. a pipeline without the tensile branch still gets Figs. 4, 7 and 8). Per-sample inputs are labelled by sample (`stats: {T1: s1, ...}`); one sample gets one colour in every single-panel figure. The contact models are a role: `responses` takes any number of them per sample, labelled by sample and then by model (`responses: {T1: {icm: a, bem: b}}`), and `bands` and `model_summaries` likewise; a model's label is its legend name, its colour comes from a fixed palette by the order of the labels (parameter `models`, then label order; labels `x` and `x-...` share a family's colour), and its stroke from its law as the data say (a response whose tangent_ratio is 1 everywhere is linear: dashed). Fig. 2 needs `curves` (R² from `quality`, limits from `stability`); Fig. 4 any of `heights`, `psd`, `profiles` (the H of the drawn power law comes from `stats` when wired, otherwise from a log-log least-squares fit); the surface stage's statistics per sample (`areal`, `material_ratio`, `acf`, `scale_dependent`, `distributions`, each optional) give a table of the ISO 25178-2 areal parameters (one column per sample, lengths in µm), Fig. 4b (the Abbott–Firestone curve with the ISO 13565-2 core band, equivalence line, Smr1 and Smr2), Fig. 4c (the ACF radially averaged and along x and y, with the 1/e and s = 0.2 levels, up to six correlation lengths), Fig. 4d (rms slope and curvature against scale, log–log) and Fig. 4e (height and slope densities); a sample without one of them is named in a note, and a figure none of whose inputs is wired is skipped with the reason; Fig. 7 the `fig7_models` (default every wired model) with the measured points of `experiments` (contact-images' contact, the force over the models' E0* A0) and the agreement table of `agreement` and `load_ratio` (contact-compare) under it (a model contact-compare marked by_construction, its physics the experiment's, shows "by construction" in place of a rank, after the ranked ones; the captions of Figs. 7 and 9 and the experiment's section name the experiment's physics from the tables' experiment_physics column, and the models that share it), then each model's load over `reference_model`'s at `area_fractions` where that is set; Fig. 6 the first sample's `compare_figures` (observed, predicted and overlay maps at one scale with a bar, read through contact-compare's figure index) with the registrations of `transforms`; Fig. 8 every model whose tangent_ratio is not 1 throughout; Fig. 9 the `fig9_models` side by side with the experiment, with a table of kappa = (A/A0)/(F/(A0 E0* h'rms)) per model at A/A0 = 0.02 and 0.1 (h'rms from `stats`, one yardstick for every model; read off each curve by linear interpolation in A/A0, n/a outside it) and each model's `model_summaries` table (one row: what it was given) as it is. A label in a model parameter that no response is wired under stops the stage, naming the parameter, the label and the wired ones. `bands` (a model's bootstrap bands; a table without rows is no band) shades the 5–95 % band of F/(E0* A0) under the curves of Figs. 7 and 9 and of E_t*/E0* under Fig. 8's (opacity 0.2; sample colour in single panels, the model's in per-sample panels; points at or below zero left off the log axis), with a legend entry. Table 1 decodes `material` and gives its initial moduli μ0, E0 and E0* at Poisson's ratio `poisson`; with `params` wired, each parameter and modulus with its 5–95 % bootstrap interval where finite (none for an Ogden term held at μ_i = 0, which moves nothing); with `comparison` wired, a table of what each constraint costs: the same family under every setting of material-fit's `constraint` (the adopted one first) with its RMS relative error over all points and per mode, the largest, μ0 and the condition number; with `published_material`, that material (not refitted) on the same measured curves as a last row, and its parameters as a table of their own. Fig. 2 draws the measured curves as lines and the fitted model as symbols, as the paper's caption says. One E0* on the page: each wired response must have been normalised by Table 1's (its E0* is mean_stress_pa · area_fraction / load_norm, from the response alone), and a wired `params` must be the fit of `material` at the same ν; otherwise the stage stops and names the input, so set `poisson` to the contact model's (and the fit's). The summary reads F/(E0* A0) of every model at `area_fractions` by linear interpolation in A/A0 (null outside the computed range), and each band's 5th and 95th percentiles the same way; its table on the page shows `summary_models`. FINITE STRAIN: with `finite_strain` wired (one patch per sample: `fem` and the other models on the same window), Fig. 10 draws every curve per sample over the reference's range of A/A0 (reference black and thick; colour = family, the label's text before `-`; stroke = the label's suffix: none solid, `-uniaxial` dashed, `-linear` dotted, other long dashes) and a table gives F_model / F_reference at `finite_strain_area_fractions` per sample with the mean over samples, both as F/(E0* A0) read by linear interpolation in A/A0, and says in words which model comes nearest and whether each family's tangent modulus moves its load toward the finite-strain one or away (against its `-linear` variant). FINDINGS: the page opens with "What this rerun finds", sentences written from the numbers above, each linking its figure or table and left out when its inputs are not wired: the models compared with the equibiaxial tangent (labels without a law suffix whose tangent_ratio is not 1), the finite-strain verdict (F_reference/F of its small-strain twin, the reference's family, and the range of F_model/F_reference of the equibiaxial and the `-linear` models, from the finite-strain table), and the experiment (its physics, the models marked by_construction, the best-ranked of the others and the equibiaxial models' load ratio at the load_ratio A/A0 nearest 0.5), and with `refinement` wired the judge's resolution (the coarsest refine factor k from which on every level's F_fem/F_bem at equal approach lies within 5 % of 1 at each of `refinement_area_fractions` inside 0.05–0.3 that every level reads, or, when none does, the level whose largest deviation is smallest, with the finest level's ratios beside it); summary.json holds them under `findings`. REFINEMENT: with `refinement` wired (levels labelled by the refine factor k, each with `fem` and `bem`; a level without both, another label, or a bem whose tangent_ratio is not 1 stops the stage naming the input), the section "Is the finite-strain judge converged?" gives F_fem, F_bem (as F/(E0* A0)) and their ratio per k at equal approach (the same z_m, read where the finest bem reaches each of `refinement_area_fractions`; linear in z_m) and at equal counted area (those A/A0; linear in A/A0), n/a outside a curve, with the observed order p of each from the three finest levels (F_k = F* + C h_k^p with h_k = 1/k solved for p by bisection, as the refinement ratios differ; n/a if the differences change sign or vanish), and Fig. 11: the ratio against the points per shortest wavelength (k times `refinement_points_per_wavelength`), solid at equal approach and dashed at equal area; its caption names fem's block depth from the depth_m of the fem stages in the run's record. summary.json then holds `refinement` (absent without the input): `points_per_wavelength_at_refine_1`, the compared `area_fractions`, `z_m_equal_approach` (m, per A/A0; null where the finest bem does not reach it), `levels` (per k: `refine`, `points_per_wavelength`, F_fem/F_bem per A/A0 as `ratio_equal_approach` and `ratio_equal_area`, null where a load is not read, each with its `_min` and `_max` over the A/A0 read) and `observed_order` (per compared point: `compared_at` equal_approach or equal_area, `area_fraction`, and the order p of F_fem, F_bem and their ratio as `order_fem`, `order_bem`, `order_ratio`). Figures use the bundled DejaVu Sans font; no system font or network is needed.

    Parameters (keywords, as in a pipeline's `with:` block):
        title (default "hypercontact — rough-surface contact of a hyperelastic rubber"): the page title
        area_fractions (default [0.1,0.5,0.9]): A/A0 values at which the summary reads F/(E0* A0) (1 to 10 of them)
        poisson (default 0.5): Poisson's ratio ν of Table 1's E0 and E0*: that of the contact model whose responses are wired
        models (default []): the contact models' order in legends and colours, by their labels in `responses` (labels not listed follow in label order); a model's colour is its family's (the label's text before its first `-`)
        fig7_models (default []): the models Fig. 7 draws, by label (none listed: every wired model)
        fig9_models (default []): the models Fig. 9 compares side by side, by label (none listed: every wired model)
        summary_models (default []): the models whose loads the per-sample summary table shows, by label (none listed: the first model)
        reference_model (optional): the model every other model's load is divided by at equal A/A0 in the load-ratio table (unset: no table)
        finite_strain_reference (default "fem"): the label of the finite-element reference in `finite_strain`, that every other curve there is divided by
        finite_strain_area_fractions (default [0.05,0.1,0.2,0.3]): A/A0 at which the finite-strain table reads F_model / F_reference (1 to 10 of them)
        refinement_area_fractions (default [0.05,0.1,0.2]): A/A0 at which the refinement study compares fem and bem at equal area, and (where the finest bem reaches them) at equal approach (1 to 10 of them)
        refinement_points_per_wavelength (default 2.0): points per shortest wavelength at refine factor 1 in the refinement study (the surface's filter wavelength over its spacing; refine k gives k times it)
        published_material (optional): a published material set beside the fit in Table 1 with its error on the same tensile data, not refitted (`paper-epdm`: the paper's Table 1; unset: none)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        curves (table, optional): material fit: measured and fitted stress per mode
        quality (table, optional): material fit: quality per mode (shown as is)
        params (table, optional): material fit: parameter table (shown as is)
        stability (table, optional): material fit: Drucker-stable stretch ranges
        comparison (table, optional): material fit: model ranking (shown as is)
        material (table, optional): the fitted material
        heights (field, many): height map per sample
        psd (table, many): PSD per sample
        stats (table, many): surface statistics per sample
        profiles (table, many): truncation profile per sample
        areal (table, many): surface stage's ISO 25178-2 areal parameters per sample: the areal table
        material_ratio (table, many): surface stage's Abbott-Firestone curve per sample: Fig. 4b
        acf (table, many): surface stage's autocorrelation per sample: Fig. 4c
        scale_dependent (table, many): surface stage's scale-dependent rms slope and curvature per sample: Fig. 4d
        distributions (table, many): surface stage's height, slope and curvature histograms per sample: Fig. 4e
        responses (table, nested): every contact model's load-area curve, by sample and model label: Figs. 7, 8, 9, the κ, load-ratio and summary tables
        bands (table, nested): contact models' 5–95 % bootstrap bands, by sample and model label: shaded in Figs. 7 and 8, read in the summary
        model_summaries (table, nested): what each model was given (any one-row table), by sample and model label: shown as is under Fig. 9
        experiments (table, many): contact experiment per sample (contact-images' contact): Fig. 7's symbols
        agreement (table, many): contact-compare's agreement per sample: the table under Fig. 7
        load_ratio (table, many): contact-compare's load ratios per sample
        transforms (table, many): contact-compare's registration per sample
        finite_strain (table, nested): the finite-strain comparison on one patch per sample, by sample and model label: the finite-element reference (`finite_strain_reference`) and the models on the same window (Fig. 10 and its load-ratio table)
        refinement (table, nested): the refinement study, by refine factor and then `fem` and `bem` (`{"1": {fem: a.response, bem: b.response}, ...}`): linear fem at small strain and linear periodic bem on the mirror tiling of one window (the table and Fig. 11)
        compare_figures (files, many): contact-compare's figures per sample, indexed: Fig. 6 (the first sample wired)

    Returns the output:
        report (files): index.html, figN.png, figN.svg, summary.json

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_surfaceOutputs = TypedDict("_surfaceOutputs", {"height": Field, "psd": pl.DataFrame, "stats": pl.DataFrame, "stitch": pl.DataFrame, "areal": pl.DataFrame, "material_ratio": pl.DataFrame, "distributions": pl.DataFrame, "acf": pl.DataFrame, "scale_dependent": pl.DataFrame})

def surface(
    *,
    tiles: Optional[FilesLike] = None,
    height: Optional[Field] = None,
    dir: Optional[Union[str, PathLike[str]]] = None,
    tile_files: Sequence[Union[str, PathLike[str]]] = ...,
    positions: Optional[Union[str, PathLike[str]]] = None,
    resolution_m: float = 0.0,
    reference: Literal["lowest", "percentile"] = "lowest",
    reference_percent: float = 1.0,
    detrend: Literal["plane", "mean"] = "plane",
    periodic: bool = False,
    fill: Literal["harmonic", "zero"] = "harmonic",
    max_missing_fraction: float = 0.1,
    bins_per_decade: int = 10,
    hurst_lambda_min_m: Optional[float] = None,
    hurst_lambda_max_m: Optional[float] = None,
    histogram_bins: int = 64,
    min_overlap_px: int = 16,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _surfaceOutputs:
    """Stitch interferometer tiles, filter to a lateral resolution, PSD, σ and Hurst exponent, ISO 25178 parameters, ACF, distributions

    Source: exactly one of input `tiles` (a Files product: tile_NNN.npy + positions.csv, as synth-surface writes), param `dir` (a folder of the same layout, real data) or input `height` (an already stitched map, e.g. from height-map). positions.csv has columns tile, file, x_m, y_m and pixel_m (nominal position of each tile's pixel [0, 0]; pixel_m may be left out where the tile files state their spacing). Tiles are read by their first bytes: .npy (float64/float32, metres, axis 0 = x, NaN = missing) or any instrument format height-map reads (X3P, .sur, .plu, MetroPro .dat, .datx, .opd; square pixels, one spacing for all); without positions.csv the tiles are the folder's tile files in natural order of their names, placed by the stage positions the files record (X3P's CX/CY offsets). STITCHING: overlapping pairs registered by phase correlation: the eight highest peaks (of the half-whitened cross-power spectrum), each also taken modulo the overlap size, are checked by the Pearson correlation of the overlap they imply and the best wins, then the sub-pixel rest by Gauss–Newton on the heights of the re-cut overlap (cubic-convolution interpolation, a plane absorbing tilt and piston); all pair offsets solved together by least squares (mean correction zero), pairs more than 0.5 px from the joint solution dropped as outliers while the tiles stay connected; a plane (tilt + piston) per tile from the overlaps by least squares; feathered blending (weights fall linearly to tile edges), tiles placed at whole pixels; NaN where no tile measured; the map is cropped to the region fully inside tile footprints. FILTER: ISO 16610-61 Gaussian low-pass with cut-off 2·resolution_m (50 % amplitude there), sampled every resolution_m; NaN-aware (normalised convolution; NaN where under half the kernel weight was measured); resolution_m: 0, the default, keeps the grid: no lab map is filtered unless the pipeline says so (the paper's pipelines set its 20 µm). A note gives the grid before and after (also in stats: nx_measured, ny_measured, dx_measured_m, dy_measured_m against nx, ny, dx_m, dy_m), and a note starting with "warning:" when the filter keeps under 10 % of the measured points, and another when it discards more than half of the PSD's range in log q: the filtered map's last q, π/resolution_m, below √(q_min·q_max) of the measured map (q from 2π/longest side to π/coarser spacing). DETRENDING: least-squares plane (or mean) over measured points, before statistics and PSDs. HEIGHT REFERENCE: `lowest` (the paper's choice: the lowest point is z = 0) or `percentile` (z = 0 at reference_percent of the heights); a single pit pixel shifts every z under `lowest`, a percentile is robust to it. PSD (SurfaceTopography conventions, numbers comparable one to one): axis 0 = x; L = N·dx; q = 2πk/L in rad/m; 1-D: C1D = |dx·FFT_x(w·h)|²/L, k = 0…N/2−1 (Nyquist dropped), averaged over all profiles; y: the same on the transposed map; radial: C2D = |dx·dy·FFT2(w·h)|²/(Lx·Ly) averaged over |q| bins up to π/dx; all binned in log-spaced bins (bins_per_decade, edges as SurfaceTopography's make_grid), each bin reporting the mean q and mean C of its members; window: none if `periodic`, otherwise Hann scaled to mean(w²) = 1 (1-D along the profile; rotationally symmetric for radial). MISSING POINTS: points still NaN after filtering (their share is nan_fraction) are filled before the FFT only (the `height` output keeps its NaN, σ and slope use measured points only): `fill: harmonic` (default) solves the 5-point Laplace equation on them with the measured heights as Dirichlet data and a zero normal derivative at the map edge (periodic maps wrap), as SurfaceTopography's interpolate_undefined_data (legs weighted 1/dx², 1/dy²), by preconditioned conjugate gradients to a relative residual of 1e-12; `fill: zero` puts them at the detrended mean (the behaviour of stage version 3). A map with more than max_missing_fraction missing is refused: an in-fill carries no roughness shorter than its holes, so the PSD at high q falls by about the missing share (10 % scattered missing: C up to 9 % low at the short wavelengths, the Nyquist bin 28 % high, the median bin within 1 %); what was filled is in stats (fill, filled_points, filled_fraction) and a note. STATS: sigma_m = areal rms height Sq (not profile Rq); rms_slope = √⟨|∇h|²⟩ by forward differences. AREAL (ISO 25178-2, of the detrended map about its mean plane, measured points only): Sa, Sq, Ssk, Sku, Sp, Sv, Sz; Sdq (as rms_slope); Sdr (cells with four measured corners, the two triangulations averaged); Sal and Str from the areal autocorrelation (FFT, normalised by the overlap count, mean removed) at s = 0.2, searched along 360 directions out to half the map (Str is an upper bound where some direction never decays there); Sk, Spk, Svk, Smr1, Smr2 of ISO 13565-2 (the equivalence line is the 40 % secant of least slope); the correlation length where the radially averaged ACF falls to 1/e. They match SurfaceTopography 1.27 to 1e-9 where it defines the same quantity (Sq, Sa, Ssk, Sku, Sp, Sv, the ACF); its Sdq differs on maps with holes (it drops points next to holes). `material_ratio` is the Abbott-Firestone curve at every whole per cent. Parameters are of the map analysed: after the filter, if any. `acf`: the normalised ACF (as for Sal) radially averaged over the lags within the search ellipse (rings one finer spacing wide, each at the mean |τ| of its lags: direction radial), and along the x and y axes out to ⌊(n − 1)/2⌋ pixels (directions x, y); NaN where no pair of measured points lies that far apart. `distributions`: histograms (histogram_bins equal-width bins from the smallest to the largest value) of the height about the mean plane (m), the slope |∇h| (1) and the curvature ∇²h/2 (1/m), both by central differences at the points whose four neighbours are measured (the map's edge left out); each row gives its unit, the count and the density count/(points · bin width). `scale_dependent` (variable bandwidth, SurfaceTopography's scale_dependent_statistical_property): at scales k·Δ, k = 1, 2, 4, … ≤ ⌊(min(nx, ny) − 1)/2⌋, Δ = (dx + dy)/2, the rms slope ⟨gx² + gy²⟩^½ with gx = (h[i+k, j] − h[i, j])/(k·dx), gy likewise, averaged where both exist (k = 1: SurfaceTopography's rms_gradient; Sdq averages gx² and gy² apart), and the rms curvature ∇²h/2 by central second differences of step k/2 (a stencil k pixels long; none at k = 1), over the points whose stencil is measured; NaN for fewer than 4 values. Of a self-affine map the slope goes as scale^(H−1), the curvature as scale^(H−2). HURST: least squares of ln C on ln q, C ∝ q^(−1−2H) (1-D) and q^(−2−2H) (radial), over wavelengths hurst_lambda_min_m … hurst_lambda_max_m (default 4·dx … L/4; on a map this stage filtered, from the wavelength where the Gaussian still passes 90 % of the power, 3.6 cut-offs = 7.3·resolution_m, so the filter's roll-off does not steepen the slope). Each fit reports its R² (ln C on ln q) and the q range of the bins it used (hurst_*_r2, hurst_*_q_min_per_m, hurst_*_q_max_per_m) and a flag (hurst_*_flag): "poor power law (R² < 0.9)" first, else "outside 0…1", else "ok"; a flagged fit also gets a note starting with "warning:". LINE SCANS: a map one point across (n x 1: a profile along x; 1 x n: along y), e.g. a stylus profile, is analysed as the profile it is (a note says so): the filter is the same Gaussian along the line (ISO 16610-21's profile filter, cut-off 2·resolution_m; resolution_m is judged against the spacing along the line); `detrend: plane` removes the least-squares line, `mean` the mean; missing points are filled by linear interpolation between measured neighbours (the harmonic in-fill in 1-D; ends held at the nearest measured height, a periodic profile interpolated across the wrap), max_missing_fraction applies; the PSD along the line is the x PSD's (same normalisation, window and bins; equal to the x PSD of a map of identical copies of the line) and its Hurst exponent goes in hurst_x (or hurst_y); the other direction and radial have no PSD rows, NaN exponents and the flag "not defined (line scan)"; sigma_m is the profile's Rq and rms_slope its forward-difference rms slope; the `areal` table holds the profile parameters of the same definitions: Ra, Rq, Rsk, Rku, Rp, Rv, Rz (ISO 4287) in Sa … Sz, Rdq in Sdq, Rk, Rpk, Rvk, Mr1, Mr2 (ISO 13565-2) in Sk … Smr2, the lag where the profile's autocorrelation falls to 0.2 in Sal and to 1/e in the correlation length; Sdr and Str need an area and are NaN; `distributions` holds the height histogram only, `acf` the autocorrelation along the line (direction x or y), `scale_dependent` is empty (slope and curvature statistics are areal). Tiles that are line scans are not stitched (one line scan alone is analysed). The stages that need a 2-D map (truncation, bem, fem, crop, persson, greenwood-williamson, synth-contact, contact-compare) refuse a line scan, naming themselves.

    Parameters (keywords, as in a pipeline's `with:` block):
        dir (optional): folder of tiles + positions.csv (instead of input `tiles`)
        tile_files (default []): tile files in any format read here (instead of `dir` or input `tiles`)
        positions (optional): positions.csv for `tile_files` (its `file` column names them by file name; default: the positions the files record)
        resolution_m (default 0.0) [m]: lateral resolution and new grid spacing; 0 (the default) keeps the measured grid (the paper's pipelines set 20e-6)
        reference (default "lowest"): height reference
        reference_percent (default 1.0) [%]: percentile for `reference: percentile`
        detrend (default "plane"): removed before stats and PSDs (periodic maps: mean only)
        periodic (default false): the map is periodic: no window, and only the mean is removed
        fill (default "harmonic"): how missing points are filled before the PSDs
        max_missing_fraction (default 0.1): refuse PSDs of maps with more missing points than this (after filtering)
        bins_per_decade (default 10): log bins per decade of q
        hurst_lambda_min_m (optional) [m]: shortest wavelength of the Hurst fit (default 4·dx, 7.3·resolution_m when filtered)
        hurst_lambda_max_m (optional) [m]: longest wavelength of the Hurst fit (default L/4)
        histogram_bins (default 64): bins of each histogram of output `distributions` (height, slope, curvature)
        min_overlap_px (default 16) [px]: least overlap (both directions) for a tile pair

    Inputs (keywords; a table as a polars or pandas DataFrame):
        tiles (files, optional): tile_NNN.npy + positions.csv
        height (field, optional): an already stitched map (skips stitching)

    Returns a dict of the outputs:
        height (field): stitched, filtered, detrended map from the reference height, metres (NaN = unmeasured)
        psd (table): binned PSDs
        stats (table): one row
        stitch (table): per tile
        areal (table): one row: ISO 25178-2 areal parameters
        material_ratio (table): the Abbott-Firestone curve at every whole per cent
        distributions (table): histograms of height, slope and curvature (long format)
        acf (table): the autocorrelation radially averaged and along x and y, against lag
        scale_dependent (table): rms slope and rms curvature against scale

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_synth_contactOutputs = TypedDict("_synth_contactOutputs", {"sequence": Files, "truth": pl.DataFrame, "truth_rig": pl.DataFrame, "truth_maps": Files})

def synth_contact(
    *,
    surface: Field,
    material: Table,
    model: Literal["hyperelastic", "linear"] = "hyperelastic",
    tangent: Literal["equibiaxial", "uniaxial"] = "equibiaxial",
    scheme: Literal["euler", "heun"] = "heun",
    poisson: Any = 0.5,
    boundary: Literal["free", "periodic"] = "free",
    resolution_m: float = 0.00002,
    frames: int = 30,
    frames_before_contact: int = 3,
    contact_phase: float = 0.3,
    max_area_fraction: float = 0.9,
    speed_m_per_s: float = 3e-6,
    exposure_s: float = 0.05,
    width_px: int = 2048,
    height_px: int = 2048,
    sensor_pixel_m: float = 6.5e-6,
    magnification: float = 2.0,
    bits: int = 16,
    exposure_fraction: float = 0.8,
    full_well_e: float = 30000.0,
    read_noise_e: float = 1.6,
    vignetting: float = 0.15,
    noise: bool = True,
    angle_deg: float = 2.5,
    shift_x_m: float = 0.00015,
    shift_y_m: float = -0.0001,
    force_rate_hz: float = 50.0,
    force_resolution_n: float = 0.01,
    force_noise_n: float = 0.005,
    clock_offset_s: float = 0.37,
    trigger: bool = True,
    tolerance: float = 1e-8,
    max_iterations: int = 2000,
    map_fractions: Sequence[float] = ...,
    seed: int = 1,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _synth_contactOutputs:
    """Synthetic contact experiment: interference frames, frame times and force log of a rough sample pressed onto glass, with the ground truth

    The paper's in-situ rig (Section 3, Fig. 3). SAMPLE: the height map (use the synthetic sample's ground truth, `synth-surface`'s `truth`, so experiment and model see the surface through different instruments) is low-pass filtered to `resolution_m` exactly as `surface` filters a stitched scan (Gaussian, cut-off twice the spacing); the contact with the rigid glass is solved on that grid by the `bem` solver (same boundary, tolerance and law: `hyperelastic` by default, the force by the tangent-modulus integral over the solved frames, E_t*/E0* = 2 at first contact with the paper's `tangent: equibiaxial` and 1 with `uniaxial`), each frame warm-started from the previous one. PHYSICS: the experiment is the linear-elastic boundary-element half-space of `bem` (with `boundary`), its force either E0* times the linear load (`model: linear`, or a linear material) or the tangent-modulus integral (`model: hyperelastic`, with `tangent`); the truth table's column `physics` names which (e.g. `bem, hyperelastic, equibiaxial tangent, free boundary` or `bem, linear elastic, small-strain modulus, free boundary`). A model run with the same physics (`bem` with the same law and boundary) agrees with this experiment by construction: its score measures only what the imaging, the image analysis and the scan add, not the physics; contact-compare marks such responses with `same_physics`. RAMP: the servo advances at `speed_m_per_s` (the paper: 3 µm/s, quasi-static); the last frame's penetration is where the solve first reaches `max_area_fraction` (found by the `bem` curve search); frames are evenly spaced in time, `frames_before_contact` of them with an open gap, first contact `contact_phase` of an interval before the next frame's mid-exposure, so the frame interval follows (an error if shorter than the exposure); each frame shows the state at mid-exposure (no motion blur: 0.15 µm of travel in 50 ms). IMAGES: the gap of the solve is drawn onto the camera's pixels: a pixel whose nearest solve point is in contact has gap 0 (the solve's pixel-wise contact), elsewhere the gap is bilinear, contact nodes at a patch edge carrying minus their open neighbours' mean gap so that it rises from zero at the edge of the contact cell; seen through a known rotation `angle_deg` and shift of the camera against the scan (pixel on the sample = sensor_pixel_m / magnification); each gap's reflectance is the glass-air-rubber thin film (Airy; quartz 1.458, rubber 1.50, the half-wave loss at the rubber) averaged over a white LED's spectrum; then vignetting, shot and read noise, quantisation to `bits` (files are 16-bit PNG with the counts unscaled when bits > 8). Outside the solved map the camera sees the background. Contact is near black; gaps of 60 nm are half-way to the background; the second dark fringe (~270 nm) of a phosphor white LED falls to ~0.3 of the background, which a global Otsu threshold counts as contact at low load. FORCE: the true force at the ramp's penetration (linear between the solved frames, 0 before contact), Gaussian noise `force_noise_n`, quantised to `force_resolution_n`, sampled at `force_rate_hz` on the sensor's clock (sensor time = camera time + clock_offset_s) from 1 s (or two frame intervals) before the first frame to as long after the last; with `trigger` (default) the log has a column camera_trigger, 1 at the samples taken while the shutter was open (a DAQ wired to the camera's trigger output), from which contact-images finds the clock offset. TRUTH (never read by the analysis): `truth` per frame (penetration, A/A0 of the whole map and of the camera's view, force, physics), `truth_rig` (transform, pixel size, clock offset, timing, solve grid), `truth_maps` (the true contact on the camera's pixels as 8-bit PNG masks, 255 = contact, at the frames nearest map_fractions of view A/A0, indexed by the table truth_maps.parquet as contact-images indexes its maps, area_fraction being the view's).

    Parameters (keywords, as in a pipeline's `with:` block):
        model (default "hyperelastic"): contact law: `hyperelastic` (the paper's tangent modulus E_t* at the mean contact stress) or `linear` (E0* throughout)
        tangent (default "equibiaxial"): the curve E_t = dφ/dε comes from: `equibiaxial` (the paper's; E_t*(0) = 2 E0* at ν = ½) or `uniaxial` (compression with free lateral expansion; E_t*(0) = E0*)
        scheme (default "heun"): integration of the hyperelastic load over the rows: `euler` (the paper's explicit step) or `heun` (trapezoid)
        poisson (default 0.5): Poisson's ratio ν of the composite moduli (a linear material uses its own)
        boundary (default "free"): how the sample continues beyond the map (as `bem`)
        resolution_m (default 0.00002) [m]: spacing of the contact solve: the surface is low-pass filtered to it (as `surface`)
        frames (default 30): camera frames
        frames_before_contact (default 3): frames before first contact (the flat-field reference and the clock)
        contact_phase (default 0.3): where first contact falls before the first frame in contact, in frame intervals
        max_area_fraction (default 0.9): A/A0 of the solve at the last frame
        speed_m_per_s (default 3e-6) [m/s]: servo speed (the paper's: 3 µm/s)
        exposure_s (default 0.05) [s]: exposure time (the paper's: 50 ms)
        width_px (default 2048) [px]: sensor width (pco.panda 4.2: 2048)
        height_px (default 2048) [px]: sensor height
        sensor_pixel_m (default 6.5e-6) [m]: sensor pixel pitch (pco.panda 4.2: 6.5 µm)
        magnification (default 2.0): optical magnification (pixel on the sample = sensor pixel / magnification)
        bits (default 16): camera bit depth (counts written unscaled in 16-bit files above 8)
        exposure_fraction (default 0.8): signal of the brightest gap at the image centre, fraction of the full well
        full_well_e (default 30000.0) [e]: full-well capacity
        read_noise_e (default 1.6) [e]: read noise, rms
        vignetting (default 0.15): flat-field fall-off at the image corners
        noise (default true): shot and read noise (false: only the optics, for tests)
        angle_deg (default 2.5) [deg]: turn of the camera against the scan's axes
        shift_x_m (default 0.00015) [m]: scan point under the image centre, from the map's centre, x
        shift_y_m (default -0.0001) [m]: scan point under the image centre, from the map's centre, y
        force_rate_hz (default 50.0) [Hz]: force sampling rate (the paper's: 50 Hz)
        force_resolution_n (default 0.01) [N]: force resolution (the paper's: 0.01 N)
        force_noise_n (default 0.005) [N]: force noise, rms, before quantisation
        clock_offset_s (default 0.37) [s]: force-sensor clock minus camera clock
        trigger (default true): log the camera's exposure signal beside the force (column camera_trigger, 0/1), as a DAQ wired to the camera's trigger output does
        tolerance (default 1e-8): relative tolerance of each contact solve (as `bem`)
        max_iterations (default 2000): conjugate-gradient iterations per solve
        map_fractions (default [0.1,0.5,0.9]): A/A0 (true, in the camera's view) of the frames whose true contact map is written
        seed (default 1): random seed (camera and force noise)

    Inputs (keywords; a table as a polars or pandas DataFrame):
        surface (field, one): the sample's true height map, metres (synth-surface's truth)
        material (table, one): the rubber's material (the true one: synth-tensile's material)

    Returns a dict of the outputs:
        sequence (files): frame_NNN.png (16-bit), frames.csv, force.csv: what contact-images reads
        truth (table): the true contact per frame
        truth_rig (table): the true transform, clock and timing
        truth_maps (files): mask_aX.png (true contact on the camera's pixels), indexed

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_synth_surfaceOutputs = TypedDict("_synth_surfaceOutputs", {"tiles": Files, "truth": Field, "truth_offsets": pl.DataFrame})

def synth_surface(
    *,
    hurst: float = 0.8,
    rms_m: float = 5e-6,
    lambda_min_m: float = 5e-6,
    lambda_max_m: float = 0.0002,
    tile_px: int = 256,
    pixel_m: float = 1.02333984375e-6,
    tiles_x: int = 3,
    tiles_y: int = 3,
    overlap: float = 0.15,
    position_error_px: float = 3.0,
    noise_m: float = 2e-9,
    dropout_fraction: float = 0.02,
    tilt_rad: float = 0.001,
    piston_m: float = 1e-6,
    seed: int = 1,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _synth_surfaceOutputs:
    """Synthetic interferometer tiles of a self-affine surface, with the ground truth

    A self-affine random surface by Fourier filtering (isotropic 2-D PSD C ∝ q^(−2−2H) between q_r = 2π/lambda_max_m and q_s = 2π/lambda_min_m, flat below q_r, zero above q_s; normalised as in SurfaceTopography so Σ C/(Lx·Ly) = rms_m²), generated periodic on a grid larger than the sample and cropped, so the sample is not periodic. It is scanned as a white-light interferometer would: square tiles of tile_px × tile_px on a grid with the given overlap (scan order x fastest), each displaced from its nominal position by a Gaussian error (position_error_px, rounded to whole pixels), with its own tilt (about the tile centre) and piston, Gaussian noise (noise_m) and dropout pixels (NaN). Output `tiles`: tile_NNN.npy (float64, metres, axis 0 = x) and positions.csv (tile, file, x_m, y_m, pixel_m: the nominal position of pixel [0, 0]). Ground truth: `truth` (the surface over the scanned area, no noise, no tilt) and `truth_offsets`. Defaults are small; the paper's scale is tile_px: 1024, tiles_x: 10, tiles_y: 10.

    Parameters (keywords, as in a pipeline's `with:` block):
        hurst (default 0.8): Hurst exponent H
        rms_m (default 5e-6) [m]: expected rms height of the generated surface
        lambda_min_m (default 5e-6) [m]: short-wavelength cut-off (no power below)
        lambda_max_m (default 0.0002) [m]: long-wavelength roll-off (flat PSD above)
        tile_px (default 256) [px]: tile side in pixels
        pixel_m (default 1.02333984375e-6) [m]: pixel size (the paper's field of view, 1047.9 µm, on 1024 pixels)
        tiles_x (default 3): tiles along x
        tiles_y (default 3): tiles along y
        overlap (default 0.15): overlap of neighbouring tiles, fraction of the side
        position_error_px (default 3.0) [px]: std of the stage-position error
        noise_m (default 2e-9) [m]: std of the measurement noise
        dropout_fraction (default 0.02): share of dropout (NaN) pixels
        tilt_rad (default 0.001) [rad]: std of each tile's tilt
        piston_m (default 1e-6) [m]: std of each tile's piston offset
        seed (default 1): random seed

    Returns a dict of the outputs:
        tiles (files): tile_NNN.npy (metres, axis 0 = x, NaN dropouts) and positions.csv
        truth (field): the true surface over the scanned area (pixel [0, 0] at the smallest true tile position)
        truth_offsets (table): the truth about each tile

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_synth_tensileOutputs = TypedDict("_synth_tensileOutputs", {"sequence": Files, "truth": pl.DataFrame, "material": pl.DataFrame})

def synth_tensile(
    *,
    mode: Literal["UT", "PT", "BT"] = "UT",
    preset: Literal["paper-epdm"] = "paper-epdm",
    max_stretch: Optional[float] = None,
    frames: int = 20,
    frame_interval_s: float = 0.5,
    width_px: int = 512,
    height_px: int = 512,
    bit_depth: int = 16,
    noise: float = 0.005,
    speckle_radius_px: float = 2.5,
    speckle_coverage: float = 0.5,
    supersample: int = 4,
    markers: bool = True,
    marker_radius_px: float = 6.0,
    pixel_m: float = 0.00002,
    gauge_width_m: Optional[float] = None,
    gauge_length_m: Optional[float] = None,
    thickness_m: float = 0.0015,
    force_resolution_n: Optional[float] = None,
    force_rate_hz: float = 50.0,
    seed: int = 1,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _synth_tensileOutputs:
    """Synthetic UT/PT/BT tensile test: speckle images, frame times, force log, specimen

    Renders a sprayed speckle pattern (Gaussian blobs, saturating optical density, four painted marker dots) at each homogeneously deformed state, evaluating the pattern at the inverse-mapped reference coordinate of sub-samples of every pixel (no image interpolation), then adds camera noise and quantises to 8 or 16 bits. Loading is along x about the image centre: UT (λ, λ^-1/2), PT (λ, 1), BT (λ, λ), λ linear in time. The force log (sampled at force_rate_hz) is the preset's nominal stress × the undeformed cross-section (gauge width × thickness) plus sensor noise, quantised to force_resolution_n. The ground truth goes to separate outputs the dic stage never reads.

    Parameters (keywords, as in a pipeline's `with:` block):
        mode (default "UT"): the test
        preset (default "paper-epdm"): ground-truth material preset
        max_stretch (optional): final loading stretch, in (1, 10] (default UT 2.5, PT 2, BT 1.5)
        frames (default 20): number of frames
        frame_interval_s (default 0.5) [s]: time between frames
        width_px (default 512) [px]: image width (the paper's camera: 2048)
        height_px (default 512) [px]: image height
        bit_depth (default 16): 8 or 16
        noise (default 0.005): camera noise std, fraction of full scale
        speckle_radius_px (default 2.5) [px]: mean speckle radius
        speckle_coverage (default 0.5): sprayed fraction of the surface (before overlaps)
        supersample (default 4): sub-samples per pixel side
        markers (default true): paint four marker dots for the `markers` method
        marker_radius_px (default 6.0) [px]: marker dot radius
        pixel_m (default 0.00002) [m]: object-space pixel size
        gauge_width_m (optional) [m]: gauge width (default: the paper's per mode)
        gauge_length_m (optional) [m]: gauge length (default: the paper's per mode)
        thickness_m (default 0.0015) [m]: thickness (the paper's)
        force_resolution_n (optional) [N]: force sensor resolution (default: the paper's, UT 0.01, PT 0.1, BT 0.01)
        force_rate_hz (default 50.0) [Hz]: force sampling rate
        seed (default 1): random seed

    Returns a dict of the outputs:
        sequence (files): frame_NNN.png, frames.csv, force.csv, specimen.json
        truth (table): the true stretches and stress per frame
        material (table): the generating material

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

def tensile_table(
    *,
    path: Union[str, PathLike[str]],
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> pl.DataFrame:
    """Load UT/PT/BT tensile data (CSV or Parquet) and validate it

    Reads a table with columns `mode` (UT, PT or BT; PS is read as PT, ET/EB as BT), `stretch` and `nominal_stress_pa` (force over undeformed area, Pa). Every row is checked: a known mode, no NaN or infinite value, stretch ≥ 1 and strictly increasing within each mode (rows of different modes may interleave), and no compressive stress at stretch > 1 (every mode is a tension test, so a negative stress is a sign or unit mistake; dips below zero within 1 % of the mode's largest stress pass as load-cell noise). Errors name the file, the line (of a CSV file, as an editor numbers it: header, `#` comment and blank lines counted; a Parquet file's 1-based row) and the column. Extra columns pass through unchanged. Whether there are enough points for a model is checked by `material-fit`, which knows the model.

    Parameters (keywords, as in a pipeline's `with:` block):
        path (required): the CSV or Parquet file (columns mode, stretch, nominal_stress_pa)

    Returns the output:
        tensile (table): the validated data, mode labels made canonical, file order kept

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

_truncationOutputs = TypedDict("_truncationOutputs", {"profile": pl.DataFrame, "patch_sizes": pl.DataFrame})

def truncation(
    *,
    surface: Field,
    levels: Any = 1000,
    connectivity: Any = 8,
    patch_fractions: Sequence[float] = ...,
    out_dir: Union[str, PathLike[str], None] = None,
    progress: Optional[bool] = None,
) -> _truncationOutputs:
    """Profile theory: contact area, patch count and radius of a truncated height map

    A plane at height z above the lowest measured point touches every pixel with h >= z (NaN pixels never touch). A(z) is the touched area, N(z) the number of connected touched patches (8- or 4-connectivity, `connectivity`; MATLAB's bwlabel, which the paper used, joins 8 neighbours; map edges are not wrapped) and r = sqrt(A/(pi N)) (the paper's Eq. 3). sigma is the rms height about the mean of the measured points; A0 = (measured points) * dx * dy, so NaN holes count in neither A nor A0. Planes: z_k = z_max (levels - k) / levels for k = 0..levels, top down, or every distinct height with `levels: all`. All planes come from one sweep over the pixels in the order the planes reach them (grouped by plane with a counting sort for `levels: N`, sorted by height for `all`), with a union-find (path compression, union by size); the map is never relabelled per plane. `patch_sizes` lists every patch's area at the first plane whose A/A0 reaches each of `patch_fractions`.

    Parameters (keywords, as in a pipeline's `with:` block):
        levels (default 1000): number of equal steps from z_max down to 0, or `all` distinct heights
        connectivity (default 8): 8 (MATLAB's bwlabel, the paper's) or 4
        patch_fractions (default [0.01,0.1,0.3,0.5]): area fractions at which every patch's area is listed

    Inputs (keywords; a table as a polars or pandas DataFrame):
        surface (field, one): height map, metres, NaN = not measured

    Returns a dict of the outputs:
        profile (table): one row per plane, top down
        patch_sizes (table): every patch's area at a few area fractions

    Also: out_dir, the folder for file outputs (default a new temporary folder); progress, bars on stderr (default: when stderr is a terminal)."""
    ...

__all__ = ["bem", "contact_compare", "contact_images", "crop", "dic", "fem", "greenwood_williamson", "height_map", "icm", "material", "material_fit", "material_preset", "persson", "report", "surface", "synth_contact", "synth_surface", "synth_tensile", "tensile_table", "truncation"]
