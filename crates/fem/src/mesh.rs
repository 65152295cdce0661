//! The mapped hexahedral mesh of a height-map patch, in the conventions of
//! issue #33 (fixed so that results compare with other codes):
//!
//! - one surface node per map point: node (i, j) at x = i·dx, y = j·dy, so
//!   the block is (nx − 1)dx × (ny − 1)dy;
//! - base at z = 0, top node at z = depth + h[i, j] − mean(h);
//! - `layers` element layers over the height of each column, graded toward
//!   the top: layer thicknesses form a geometric series whose bottom/top
//!   ratio is `grading` (1: uniform), scaled to each column's height;
//! - boundary sets: base (k = 0), the four lateral faces, top (k = layers).
//!
//! Heights are indexed `heights_m[i * ny + j]` (x-major, the (nx, ny) layout
//! of the `bem` crate). Node (i, j, k) is number (k nx + i) ny + j.

use crate::FemError;

/// A height map on a regular grid, m.
#[derive(Clone, Copy, Debug)]
pub struct HeightMap<'a> {
    /// h[i, j] at `i * ny + j`, m.
    pub heights_m: &'a [f64],
    pub nx: usize,
    pub ny: usize,
    pub dx_m: f64,
    pub dy_m: f64,
}

/// How the four lateral faces are held.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lateral {
    /// Normal displacement zero (symmetry planes): the patch is one cell of
    /// its mirror-image tiling. The default.
    #[default]
    Mirror,
    /// Node (nx − 1, j) tied to (0, j) and (i, ny − 1) to (i, 0): periods
    /// (nx − 1)dx and (ny − 1)dy. The map's last row and column should then
    /// repeat its first ([`periodic_extension`]).
    Periodic,
}

/// Mesh parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    /// Block height at the mean surface, m; `None`: the larger lateral size.
    pub depth_m: Option<f64>,
    /// Element layers through the height.
    pub layers: usize,
    /// Bottom-layer / top-layer thickness.
    pub grading: f64,
}

impl Default for MeshOptions {
    /// 8 layers graded 8 : 1: for a block as deep as it is wide, on a 32²
    /// patch, the top layer is then about one pixel thick.
    fn default() -> Self {
        Self {
            depth_m: None,
            layers: 8,
            grading: 8.0,
        }
    }
}

/// The mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub nx: usize,
    pub ny: usize,
    pub layers: usize,
    pub dx_m: f64,
    pub dy_m: f64,
    pub depth_m: f64,
    /// mean(h) that was subtracted, m.
    pub mean_height_m: f64,
    /// Node coordinates, m.
    pub nodes_m: Vec<[f64; 3]>,
    /// Hexahedra, VTK node order.
    pub elements: Vec<[usize; 8]>,
}

impl Mesh {
    /// Meshes `map` with `options`.
    pub fn new(map: &HeightMap<'_>, options: &MeshOptions) -> Result<Self, FemError> {
        check_map(map)?;
        check_options(options)?;
        let (nx, ny, layers) = (map.nx, map.ny, options.layers);
        let mean = map.heights_m.iter().sum::<f64>() / map.heights_m.len() as f64;
        let depth = options
            .depth_m
            .unwrap_or(((nx - 1) as f64 * map.dx_m).max((ny - 1) as f64 * map.dy_m));
        let lowest = map.heights_m.iter().copied().fold(f64::INFINITY, f64::min);
        if !(depth > 0.0 && depth + lowest - mean > 0.0) {
            return Err(FemError::MeshOption {
                option: "depth_m",
                value: format!("{depth:e}"),
                message: format!(
                    "the block must stand above its base everywhere: the lowest surface point \
                     lies {:e} m below the mean",
                    mean - lowest
                ),
            });
        }
        let levels = level_fractions(layers, options.grading);
        let mut nodes_m = Vec::with_capacity((layers + 1) * nx * ny);
        for fraction in &levels {
            for i in 0..nx {
                for j in 0..ny {
                    let top = depth + map.heights_m[i * ny + j] - mean;
                    nodes_m.push([i as f64 * map.dx_m, j as f64 * map.dy_m, fraction * top]);
                }
            }
        }
        let node = |i: usize, j: usize, k: usize| (k * nx + i) * ny + j;
        let mut elements = Vec::with_capacity(layers * (nx - 1) * (ny - 1));
        for k in 0..layers {
            for i in 0..nx - 1 {
                for j in 0..ny - 1 {
                    let face = |k| {
                        [
                            node(i, j, k),
                            node(i + 1, j, k),
                            node(i + 1, j + 1, k),
                            node(i, j + 1, k),
                        ]
                    };
                    let (b, t) = (face(k), face(k + 1));
                    elements.push([b[0], b[1], b[2], b[3], t[0], t[1], t[2], t[3]]);
                }
            }
        }
        Ok(Self {
            nx,
            ny,
            layers,
            dx_m: map.dx_m,
            dy_m: map.dy_m,
            depth_m: depth,
            mean_height_m: mean,
            nodes_m,
            elements,
        })
    }

    /// The number of node (i, j, k).
    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.nx + i) * self.ny + j
    }

    /// Top nodes, in map order (i * ny + j).
    pub fn top_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        let k = self.layers;
        (0..self.nx).flat_map(move |i| (0..self.ny).map(move |j| self.node(i, j, k)))
    }

    /// Base nodes (z = 0).
    pub fn base_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.nx).flat_map(move |i| (0..self.ny).map(move |j| self.node(i, j, 0)))
    }

    /// Nodes on the face x = 0 (`high` false) or x = (nx − 1)dx.
    pub fn x_face_nodes(&self, high: bool) -> impl Iterator<Item = usize> + '_ {
        let i = if high { self.nx - 1 } else { 0 };
        (0..=self.layers).flat_map(move |k| (0..self.ny).map(move |j| self.node(i, j, k)))
    }

    /// Nodes on the face y = 0 (`high` false) or y = (ny − 1)dy.
    pub fn y_face_nodes(&self, high: bool) -> impl Iterator<Item = usize> + '_ {
        let j = if high { self.ny - 1 } else { 0 };
        (0..=self.layers).flat_map(move |k| (0..self.nx).map(move |i| self.node(i, j, k)))
    }

    /// The (i, j, k) of a node.
    pub fn grid_of(&self, node: usize) -> (usize, usize, usize) {
        (
            node / self.ny % self.nx,
            node % self.ny,
            node / (self.nx * self.ny),
        )
    }

    /// The reference area that top node (i, j) stands for: dx·dy, halved on
    /// each lateral face it lies on, m².
    pub fn tributary_area_m2(&self, i: usize, j: usize) -> f64 {
        let edge = |index: usize, n: usize| {
            if index == 0 || index == n - 1 {
                0.5
            } else {
                1.0
            }
        };
        self.dx_m * self.dy_m * edge(i, self.nx) * edge(j, self.ny)
    }
}

/// The height fractions z_k / z_top of the node levels k = 0…layers.
pub fn level_fractions(layers: usize, grading: f64) -> Vec<f64> {
    let ratio = if layers > 1 {
        grading.powf(-1.0 / (layers - 1) as f64)
    } else {
        1.0
    };
    let thickness: Vec<f64> = (0..layers).map(|k| ratio.powi(k as i32)).collect();
    let total: f64 = thickness.iter().sum();
    let mut levels = Vec::with_capacity(layers + 1);
    let mut sum = 0.0;
    levels.push(0.0);
    for t in &thickness {
        sum += t;
        levels.push(sum / total);
    }
    // Exactly the top, whatever the rounding of the sum.
    levels[layers] = 1.0;
    levels
}

/// `map` with its first row and column repeated at the end: the map of
/// nx + 1 by ny + 1 points whose periodic block has periods nx·dx, ny·dy,
/// the periods an FFT solver gives the original map.
pub fn periodic_extension(heights_m: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity((nx + 1) * (ny + 1));
    for i in 0..=nx {
        for j in 0..=ny {
            out.push(heights_m[(i % nx) * ny + j % ny]);
        }
    }
    out
}

fn check_map(map: &HeightMap<'_>) -> Result<(), FemError> {
    if map.nx < 2 || map.ny < 2 {
        return Err(FemError::HeightMap(format!(
            "needs at least 2 × 2 points, got {} × {}",
            map.nx, map.ny
        )));
    }
    if map.heights_m.len() != map.nx * map.ny {
        return Err(FemError::HeightMap(format!(
            "{} heights for a {} × {} grid",
            map.heights_m.len(),
            map.nx,
            map.ny
        )));
    }
    if !(map.dx_m > 0.0 && map.dy_m > 0.0 && map.dx_m.is_finite() && map.dy_m.is_finite()) {
        return Err(FemError::HeightMap(format!(
            "spacing must be positive and finite, got dx = {:e} m, dy = {:e} m",
            map.dx_m, map.dy_m
        )));
    }
    if let Some(index) = map.heights_m.iter().position(|h| !h.is_finite()) {
        return Err(FemError::HeightMap(format!(
            "height at i = {}, j = {} is {} (the mesh needs every point; fill or crop missing \
             points first)",
            index / map.ny,
            index % map.ny,
            map.heights_m[index]
        )));
    }
    Ok(())
}

fn check_options(options: &MeshOptions) -> Result<(), FemError> {
    if options.layers == 0 {
        return Err(FemError::MeshOption {
            option: "layers",
            value: "0".into(),
            message: "at least one layer".into(),
        });
    }
    if !(options.grading > 0.0 && options.grading.is_finite()) {
        return Err(FemError::MeshOption {
            option: "grading",
            value: options.grading.to_string(),
            message: "must be positive and finite (1: uniform layers)".into(),
        });
    }
    if let Some(depth) = options.depth_m
        && !(depth > 0.0 && depth.is_finite())
    {
        return Err(FemError::MeshOption {
            option: "depth_m",
            value: depth.to_string(),
            message: "must be positive and finite".into(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_follow_the_conventions() {
        let heights = [0.0, 1e-6, 2e-6, 3e-6, 4e-6, 5e-6];
        let map = HeightMap {
            heights_m: &heights,
            nx: 3,
            ny: 2,
            dx_m: 1e-5,
            dy_m: 2e-5,
        };
        let mesh = Mesh::new(&map, &MeshOptions::default()).unwrap();
        // depth = max(2 dx, 1 dy) = 2e-5; mean = 2.5e-6.
        assert_eq!(mesh.depth_m, 2e-5);
        let top = mesh.node(2, 1, 8);
        assert_eq!(mesh.nodes_m[top], [2e-5, 2e-5, 2e-5 + 5e-6 - 2.5e-6]);
        assert_eq!(mesh.grid_of(top), (2, 1, 8));
        assert_eq!(mesh.nodes_m[mesh.node(1, 0, 0)], [1e-5, 0.0, 0.0]);
        assert_eq!(mesh.elements.len(), 8 * 2);
        assert_eq!(mesh.top_nodes().count(), 6);
        assert_eq!(mesh.x_face_nodes(true).count(), 9 * 2);
        let area: f64 = (0..3)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| mesh.tributary_area_m2(i, j))
            .sum();
        assert!((area - 2e-5 * 2e-5).abs() < 1e-20);
    }

    #[test]
    fn layers_are_graded_bottom_to_top() {
        let levels = level_fractions(8, 8.0);
        let bottom = levels[1] - levels[0];
        let top = levels[8] - levels[7];
        assert!((bottom / top - 8.0).abs() < 1e-12);
        assert_eq!(level_fractions(1, 3.0), vec![0.0, 1.0]);
        let uniform = level_fractions(4, 1.0);
        assert!((uniform[1] - 0.25).abs() < 1e-15);
    }

    #[test]
    fn bad_maps_and_options_are_named() {
        let heights = [0.0, f64::NAN, 0.0, 0.0];
        let map = HeightMap {
            heights_m: &heights,
            nx: 2,
            ny: 2,
            dx_m: 1.0,
            dy_m: 1.0,
        };
        let e = Mesh::new(&map, &MeshOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("i = 0, j = 1") && e.contains("NaN"), "{e}");
        let ok = [0.0; 4];
        let map = HeightMap {
            heights_m: &ok,
            ..map
        };
        let options = MeshOptions {
            grading: -1.0,
            ..Default::default()
        };
        let e = Mesh::new(&map, &options).unwrap_err().to_string();
        assert!(e.contains("`grading`"), "{e}");
        let deep = [0.0, 0.0, 0.0, -10.0];
        let map = HeightMap {
            heights_m: &deep,
            ..map
        };
        let e = Mesh::new(&map, &MeshOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("`depth_m`"), "{e}");
    }

    #[test]
    fn periodic_extension_repeats_the_first_row_and_column() {
        let h = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(
            periodic_extension(&h, 2, 2),
            vec![1.0, 2.0, 1.0, 3.0, 4.0, 3.0, 1.0, 2.0, 1.0]
        );
    }
}
