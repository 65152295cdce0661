//! Why a frame cannot be analysed.

/// Errors of the contact-image cores; each carries the values a user needs to
/// find the bad input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImageError {
    #[error("the image is empty ({width} × {height} pixels)")]
    Empty { width: usize, height: usize },
    #[error("{width} × {height} pixels exceed the {max} an image may hold")]
    TooManyPixels {
        width: usize,
        height: usize,
        max: usize,
    },
    #[error("a {width} × {height} image needs {expected} values, but {actual} were given")]
    WrongLength {
        width: usize,
        height: usize,
        expected: usize,
        actual: usize,
    },
    #[error("bit depth {bits} is outside 1..=16")]
    BitDepth { bits: u8 },
    #[error(
        "pixel (x = {x}, y = {y}) has value {value}, but a {bits}-bit frame holds values below {limit}"
    )]
    ValueOutOfRange {
        x: usize,
        y: usize,
        value: u16,
        bits: u8,
        limit: u32,
    },
    #[error("a histogram needs 1 to 65536 bins, not {len}")]
    HistogramLength { len: usize },
    #[error("the histogram counts no pixel")]
    EmptyHistogram,
    #[error("the histogram counts {total} pixels, more than the 2^48 its exact arithmetic allows")]
    HistogramTooLarge { total: u128 },
    #[error("every pixel has level {level}: no threshold separates a darker class")]
    SingleLevel { level: u16 },
    #[error("{occupied} occupied histogram bins cannot make {classes} non-empty classes")]
    TooFewLevels { occupied: usize, classes: usize },
    #[error("parameter `{name}` = {value}: {expected}")]
    Parameter {
        name: &'static str,
        value: String,
        expected: &'static str,
    },
    #[error(
        "the frame is {frame_width} × {frame_height} pixels but the reference is \
         {reference_width} × {reference_height}"
    )]
    ReferenceSize {
        frame_width: usize,
        frame_height: usize,
        reference_width: usize,
        reference_height: usize,
    },
    #[error("the frame is {frame_bits}-bit but the reference is {reference_bits}-bit")]
    ReferenceBits { frame_bits: u8, reference_bits: u8 },
    #[error(
        "no pixel of the reference frame is brighter than dark_level + min_reference = {floor}: \
         nothing can be flat-fielded"
    )]
    NoUsableReference { floor: f64 },
    #[error(
        "the contact level {contact} is not below the background level {background} \
         (reference-normalised intensity): no contrast to threshold"
    )]
    NoContrast { contact: f64, background: f64 },
    #[error(
        "column `camera_trigger` shows {exposures} complete exposures but the sequence has \
         {frames} frames: match the frames to their exposures (a frame dropped, a test shot, \
         the log started or stopped mid-sequence, or exposures shorter than the log's sample \
         spacing), or give `clock_offset_s`"
    )]
    TriggerCount { exposures: usize, frames: usize },
    #[error(
        "column `camera_trigger`: exposure {index} lies {deviation_s} s from the clock offset \
         the others agree on ({offset_s} s), more than two log samples ({tolerance_s} s): the \
         exposures do not match the frame times (a dropped frame?); give `clock_offset_s`"
    )]
    TriggerMismatch {
        index: usize,
        deviation_s: f64,
        offset_s: f64,
        tolerance_s: f64,
    },
}
