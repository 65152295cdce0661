//! The `markers` method: centroids of a few painted dots, the paper's
//! "continuous tracking of markers" (section 2).
//!
//! A marker is found as a connected set (8-connectivity) of pixels darker
//! than a threshold. Its position is then the centroid of darkness,
//! weighted by (background − intensity) over a window around the blob with
//! the background taken as the median of the window's rim. That weight is
//! linear in the paint's cover, so pixel integration keeps it exact under an
//! affine map (a thresholded weight would not be: its outline flickers with
//! noise and pixel phase). It assumes the marker sits on a clean patch, as
//! painted dots on an unsprayed spot do. Markers found in frame 0 inside the
//! ROI are matched in later frames to the blob nearest their extrapolated
//! position.

use crate::DicError;
use crate::gray::GrayImage;

/// A dark blob.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blob {
    pub centroid: [f64; 2],
    pub area_px: usize,
}

/// Controls of the marker method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerSettings {
    /// Pixels below this fraction of full scale belong to markers.
    pub threshold: f64,
    pub min_area_px: usize,
    /// A marker farther than this from its predicted position is lost.
    pub max_jump_px: f64,
}

/// Every dark blob of at least `min_area_px` pixels.
pub fn detect(image: &GrayImage, threshold: f64, min_area_px: usize) -> Vec<Blob> {
    let (w, h) = (image.width, image.height);
    let mut label = vec![false; w * h];
    let mut blobs = Vec::new();
    let mut stack = Vec::new();
    for start in 0..w * h {
        if label[start] || image.pixels[start] >= threshold {
            continue;
        }
        label[start] = true;
        stack.push(start);
        let (mut weight, mut sx, mut sy, mut area) = (0.0, 0.0, 0.0, 0usize);
        let (mut x_min, mut x_max, mut y_min, mut y_max) = (w, 0, h, 0);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            let wgt = threshold - image.pixels[i];
            weight += wgt;
            sx += wgt * x as f64;
            sy += wgt * y as f64;
            area += 1;
            (x_min, x_max) = (x_min.min(x), x_max.max(x));
            (y_min, y_max) = (y_min.min(y), y_max.max(y));
            for ny in y.saturating_sub(1)..(y + 2).min(h) {
                for nx in x.saturating_sub(1)..(x + 2).min(w) {
                    let j = ny * w + nx;
                    if !label[j] && image.pixels[j] < threshold {
                        label[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        if area >= min_area_px && weight > 0.0 {
            let rough = [sx / weight, sy / weight];
            let reach = [
                (rough[0] - x_min as f64).max(x_max as f64 - rough[0]) + RIM_PX,
                (rough[1] - y_min as f64).max(y_max as f64 - rough[1]) + RIM_PX,
            ];
            blobs.push(Blob {
                centroid: darkness_centroid(image, rough, reach).unwrap_or(rough),
                area_px: area,
            });
        }
    }
    blobs
}

/// How far beyond a blob's outline its window reaches, pixels.
const RIM_PX: f64 = 4.0;

/// The centroid of (background − intensity) over the window of half-sizes
/// `reach` around `centre`; None if the window leaves the image.
fn darkness_centroid(image: &GrayImage, centre: [f64; 2], reach: [f64; 2]) -> Option<[f64; 2]> {
    let x0 = (centre[0] - reach[0]).round();
    let x1 = (centre[0] + reach[0]).round();
    let y0 = (centre[1] - reach[1]).round();
    let y1 = (centre[1] + reach[1]).round();
    if x0 < 0.0 || y0 < 0.0 || x1 >= image.width as f64 || y1 >= image.height as f64 {
        return None;
    }
    let (x0, x1, y0, y1) = (x0 as usize, x1 as usize, y0 as usize, y1 as usize);
    let mut rim: Vec<f64> = Vec::new();
    for x in x0..=x1 {
        rim.push(image.get(x, y0));
        rim.push(image.get(x, y1));
    }
    for y in y0 + 1..y1 {
        rim.push(image.get(x0, y));
        rim.push(image.get(x1, y));
    }
    rim.sort_by(f64::total_cmp);
    let background = rim[rim.len() / 2];
    // Unclipped weights: noise on the background averages out instead of
    // rectifying into a bias.
    let (mut weight, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let wgt = background - image.get(x, y);
            weight += wgt;
            sx += wgt * x as f64;
            sy += wgt * y as f64;
        }
    }
    (weight > 0.0).then(|| [sx / weight, sy / weight])
}

/// Follows the markers of frame 0 through a sequence.
pub struct MarkerTracker {
    settings: MarkerSettings,
    /// Frame-0 positions.
    pub reference: Vec<[f64; 2]>,
    last: Vec<Option<[f64; 2]>>,
    before_last: Vec<Option<[f64; 2]>>,
    size: (usize, usize),
}

impl MarkerTracker {
    /// Finds the markers of `frame0` whose centroid lies in `roi_px`.
    pub fn new(
        settings: MarkerSettings,
        frame0: &GrayImage,
        roi_px: [usize; 4],
        file: &str,
    ) -> Result<Self, DicError> {
        let [x0, y0, x1, y1] = roi_px;
        let reference: Vec<[f64; 2]> = detect(frame0, settings.threshold, settings.min_area_px)
            .into_iter()
            .map(|b| b.centroid)
            .filter(|c| {
                c[0] >= x0 as f64 && c[0] <= x1 as f64 && c[1] >= y0 as f64 && c[1] <= y1 as f64
            })
            .collect();
        if reference.len() < 3 {
            return Err(DicError::file(
                file,
                format!(
                    "found {} marker(s) darker than `marker_threshold` = {} with at least \
                     `marker_min_area_px` = {} pixels inside the region of interest {roi_px:?}; \
                     the markers method needs at least 3",
                    reference.len(),
                    settings.threshold,
                    settings.min_area_px
                ),
            ));
        }
        Ok(Self {
            settings,
            last: reference.iter().copied().map(Some).collect(),
            before_last: vec![None; reference.len()],
            reference,
            size: (frame0.width, frame0.height),
        })
    }

    /// Marker positions in `image`, None where lost.
    pub fn track(
        &mut self,
        image: &GrayImage,
        frame: usize,
        file: &str,
    ) -> Result<Vec<Option<[f64; 2]>>, DicError> {
        if (image.width, image.height) != self.size {
            return Err(DicError::SizeMismatch {
                frame,
                file: file.to_owned(),
                width: image.width,
                height: image.height,
                width0: self.size.0,
                height0: self.size.1,
            });
        }
        // Markers stretch with the specimen: accept half their frame-0 area.
        let blobs = detect(
            image,
            self.settings.threshold,
            (self.settings.min_area_px / 2).max(1),
        );
        let mut found = Vec::with_capacity(self.reference.len());
        for k in 0..self.reference.len() {
            let predicted = match (self.last[k], self.before_last[k]) {
                (Some(a), Some(b)) => Some([2.0 * a[0] - b[0], 2.0 * a[1] - b[1]]),
                (Some(a), None) => Some(a),
                _ => None,
            };
            let hit = predicted.and_then(|p| {
                blobs
                    .iter()
                    .map(|b| (b, (b.centroid[0] - p[0]).hypot(b.centroid[1] - p[1])))
                    .filter(|(_, d)| *d <= self.settings.max_jump_px)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(b, _)| b.centroid)
            });
            self.before_last[k] = self.last[k];
            self.last[k] = hit;
            found.push(hit);
        }
        if found.iter().filter(|f| f.is_some()).count() < 3 {
            return Err(DicError::Lost {
                frame,
                file: file.to_owned(),
                reason: format!(
                    "fewer than 3 markers within `marker_max_jump_px` = {} px of their predicted \
                     positions",
                    self.settings.max_jump_px
                ),
            });
        }
        Ok(found)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_centroid_of_a_dark_disc() {
        let (w, h) = (40, 30);
        let (cx, cy, r) = (17.3, 12.6, 5.0);
        let mut pixels = vec![0.9; w * h];
        for y in 0..h {
            for x in 0..w {
                let d = ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt();
                // A smooth edge so the centroid is sub-pixel accurate.
                pixels[y * w + x] = 0.02 + 0.88 / (1.0 + (-(d - r) / 0.7).exp());
            }
        }
        let image = GrayImage::new(w, h, pixels).unwrap();
        let blobs = detect(&image, 0.3, 10);
        assert_eq!(blobs.len(), 1);
        let c = blobs[0].centroid;
        assert!(
            (c[0] - cx).abs() < 0.02 && (c[1] - cy).abs() < 0.02,
            "{c:?}"
        );
    }
}
