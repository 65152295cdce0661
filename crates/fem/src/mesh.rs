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
//!
//! Lateral coarsening (option `lateral_coarsening`, issue #48): layer k
//! (between levels k and k + 1) has elements s_k map points wide in x and
//! y, s_k a power of two: the largest not above the layer's thickness nor
//! the depth of its top below the surface, both in pixels (the larger of
//! dx, dy; at the mean column height `depth`), then, from the top down,
//! s = 1 for the top layer and s_k between s_{k+1} and 2 s_{k+1} (no finer
//! below a coarser layer, at most a doubling per level; a layer thinner
//! than two pixels, or less than two below the surface, keeps s = 1). The
//! depth bound keeps the fields under the contact spots, which vary on the
//! scale of the depth, resolved: with the thickness alone the second layer
//! of the paper's 48² patches (2.2 pixels thick, 1.7 below the surface)
//! was two pixels wide and the load 0.9–4.3 % above the uniform mesh's at
//! small strain; with it, 0.4–0.9 % (the first steps; less later). A row of layer k
//! has corners at i = 0, s_k, 2 s_k, … and nx − 1 (its last element shorter
//! when s_k does not divide nx − 1), likewise in j. The node lattice and its
//! numbering stay; lattice nodes that no element uses are unused (no
//! unknowns, not counted). Where the layer below a level is coarser than
//! the one above, the fine corners that are not corners of the coarse face
//! under them are hanging: their position, and in [`crate::dofs`] their
//! displacement, is the bilinear interpolation of that face's four corners
//! (weights from the map indices: ½ on an edge, ¼ at a face centre,
//! fractions beside a shorter last element), which keeps the mesh
//! conforming (the usual constraint of hanging nodes on trilinear
//! elements, e.g. Rheinboldt & Mesztenyi, ACM TOMS 6, 1980). Off, every
//! layer has s = 1: the mesh is the one above, bit for bit.

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
    /// Coarsen deep layers laterally (module docs); false: one node per
    /// map point in every layer.
    pub lateral_coarsening: bool,
}

impl Default for MeshOptions {
    /// 8 layers graded 8 : 1: for a block as deep as it is wide, on a 32²
    /// patch, the top layer is then about one pixel thick.
    fn default() -> Self {
        Self {
            depth_m: None,
            layers: 8,
            grading: 8.0,
            lateral_coarsening: false,
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
    /// Node coordinates of the whole lattice (unused nodes included), m.
    pub nodes_m: Vec<[f64; 3]>,
    /// Hexahedra, VTK node order.
    pub elements: Vec<[usize; 8]>,
    /// The lateral element size s_k of each layer, in map points (all 1
    /// without lateral coarsening).
    pub layer_steps: Vec<usize>,
    /// Per lattice node: whether an element uses it.
    pub used: Vec<bool>,
    /// The hanging nodes, by increasing number.
    pub hanging: Vec<HangingNode>,
}

/// A node tied to the coarse face under it: its position and displacement
/// are Σ weight · those of the masters (the face's corners, at the same
/// level).
#[derive(Clone, Debug, PartialEq)]
pub struct HangingNode {
    pub node: usize,
    /// (master node, weight), weights summing to 1, none zero.
    pub masters: Vec<(usize, f64)>,
}

/// Depth, level fractions and layer steps of a mesh.
struct Plan {
    depth_m: f64,
    mean_m: f64,
    levels: Vec<f64>,
    steps: Vec<usize>,
}

impl Plan {
    fn new(map: &HeightMap<'_>, options: &MeshOptions) -> Result<Self, FemError> {
        check_map(map)?;
        check_options(options)?;
        let (nx, ny) = (map.nx, map.ny);
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
        let levels = level_fractions(options.layers, options.grading);
        let steps = layer_steps(
            &levels,
            depth / map.dx_m.max(map.dy_m),
            options.lateral_coarsening,
        );
        Ok(Self {
            depth_m: depth,
            mean_m: mean,
            levels,
            steps,
        })
    }

    /// The step of level k: that of the finer layer it bounds.
    fn level_step(&self, k: usize) -> usize {
        self.steps[k.min(self.steps.len() - 1)]
    }

    /// Whether node (i, j) of level k is an element corner.
    fn is_used(&self, (nx, ny): (usize, usize), i: usize, j: usize, k: usize) -> bool {
        let step = self.level_step(k);
        is_corner(i, nx, step) && is_corner(j, ny, step)
    }
}

impl Mesh {
    /// Meshes `map` with `options`.
    pub fn new(map: &HeightMap<'_>, options: &MeshOptions) -> Result<Self, FemError> {
        let plan = Plan::new(map, options)?;
        let (nx, ny, layers) = (map.nx, map.ny, options.layers);
        let mut nodes_m = Vec::with_capacity((layers + 1) * nx * ny);
        let mut used = Vec::with_capacity((layers + 1) * nx * ny);
        for (k, fraction) in plan.levels.iter().enumerate() {
            for i in 0..nx {
                for j in 0..ny {
                    let top = plan.depth_m + map.heights_m[i * ny + j] - plan.mean_m;
                    nodes_m.push([i as f64 * map.dx_m, j as f64 * map.dy_m, fraction * top]);
                    used.push(plan.is_used((nx, ny), i, j, k));
                }
            }
        }
        let mut mesh = Self {
            nx,
            ny,
            layers,
            dx_m: map.dx_m,
            dy_m: map.dy_m,
            depth_m: plan.depth_m,
            mean_height_m: plan.mean_m,
            nodes_m,
            elements: Vec::new(),
            layer_steps: plan.steps,
            used,
            hanging: Vec::new(),
        };
        mesh.elements = mesh.build_elements();
        mesh.hanging = mesh.hanging_nodes();
        // Conformity: a hanging node lies on the bilinear face of its masters.
        for hanging in &mesh.hanging {
            let mut x = [0.0; 3];
            for (c, value) in x.iter_mut().enumerate() {
                *value = weighted(&hanging.masters, |m| mesh.nodes_m[m][c]);
            }
            mesh.nodes_m[hanging.node] = x;
        }
        Ok(mesh)
    }

    /// The number of nodes that elements use (the lattice's without
    /// coarsening) for `map` and `options`, without building the mesh; the
    /// whole lattice's if the options are refused (then by [`Mesh::new`]).
    pub fn node_count_of(map: &HeightMap<'_>, options: &MeshOptions) -> usize {
        let (nx, ny) = (map.nx, map.ny);
        let Ok(plan) = Plan::new(map, options) else {
            return (options.layers + 1) * nx * ny;
        };
        (0..=options.layers)
            .map(|k| {
                let step = plan.level_step(k);
                corner_indices(nx, step).len() * corner_indices(ny, step).len()
            })
            .sum()
    }

    /// Elements layer by layer, then by i, then by j.
    fn build_elements(&self) -> Vec<[usize; 8]> {
        let mut elements = Vec::new();
        for (k, &step) in self.layer_steps.iter().enumerate() {
            let (columns_i, columns_j) =
                (corner_indices(self.nx, step), corner_indices(self.ny, step));
            for pair_i in columns_i.windows(2) {
                for pair_j in columns_j.windows(2) {
                    let face = |k| {
                        [
                            self.node(pair_i[0], pair_j[0], k),
                            self.node(pair_i[1], pair_j[0], k),
                            self.node(pair_i[1], pair_j[1], k),
                            self.node(pair_i[0], pair_j[1], k),
                        ]
                    };
                    let (b, t) = (face(k), face(k + 1));
                    elements.push([b[0], b[1], b[2], b[3], t[0], t[1], t[2], t[3]]);
                }
            }
        }
        elements
    }

    /// The corners of the layer above each level that are not corners of
    /// the coarser layer below, with their masters.
    fn hanging_nodes(&self) -> Vec<HangingNode> {
        let mut hanging = Vec::new();
        for k in 1..self.layers {
            let (fine, coarse) = (self.layer_steps[k], self.layer_steps[k - 1]);
            if fine == coarse {
                continue;
            }
            for i in corner_indices(self.nx, fine) {
                for j in corner_indices(self.ny, fine) {
                    let (along_i, along_j) = (
                        interpolation(i, self.nx, coarse),
                        interpolation(j, self.ny, coarse),
                    );
                    if along_i.len() == 1 && along_j.len() == 1 {
                        continue;
                    }
                    let masters = along_i
                        .iter()
                        .flat_map(|&(a, wa)| along_j.iter().map(move |&(b, wb)| (a, b, wa * wb)))
                        .map(|(a, b, w)| (self.node(a, b, k), w))
                        .collect();
                    hanging.push(HangingNode {
                        node: self.node(i, j, k),
                        masters,
                    });
                }
            }
        }
        hanging.sort_by_key(|h| h.node);
        hanging
    }

    /// The number of node (i, j, k).
    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.nx + i) * self.ny + j
    }

    /// The nodes that elements use.
    pub fn node_count(&self) -> usize {
        self.used.iter().filter(|u| **u).count()
    }

    /// Whether `node` is hanging.
    pub fn is_hanging(&self, node: usize) -> bool {
        self.hanging.binary_search_by_key(&node, |h| h.node).is_ok()
    }

    /// The largest lateral element size, in map points.
    pub fn largest_step(&self) -> usize {
        self.layer_steps.iter().copied().max().unwrap_or(1)
    }

    /// Top nodes, in map order (i * ny + j).
    pub fn top_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        let k = self.layers;
        (0..self.nx).flat_map(move |i| (0..self.ny).map(move |j| self.node(i, j, k)))
    }

    /// Base nodes (z = 0) that elements use.
    pub fn base_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.nx)
            .flat_map(move |i| (0..self.ny).map(move |j| self.node(i, j, 0)))
            .filter(|n| self.used[*n])
    }

    /// Used nodes on the face x = 0 (`high` false) or x = (nx − 1)dx.
    pub fn x_face_nodes(&self, high: bool) -> impl Iterator<Item = usize> + '_ {
        let i = if high { self.nx - 1 } else { 0 };
        (0..=self.layers)
            .flat_map(move |k| (0..self.ny).map(move |j| self.node(i, j, k)))
            .filter(|n| self.used[*n])
    }

    /// Used nodes on the face y = 0 (`high` false) or y = (ny − 1)dy.
    pub fn y_face_nodes(&self, high: bool) -> impl Iterator<Item = usize> + '_ {
        let j = if high { self.ny - 1 } else { 0 };
        (0..=self.layers)
            .flat_map(move |k| (0..self.nx).map(move |i| self.node(i, j, k)))
            .filter(|n| self.used[*n])
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

/// Σ weight · value(master), summed in the masters' order.
pub(crate) fn weighted(masters: &[(usize, f64)], value: impl Fn(usize) -> f64) -> f64 {
    masters.iter().map(|&(m, w)| w * value(m)).sum()
}

/// The flattest elements of a mesh: their layer and how many times wider
/// than thick they are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flatness {
    /// Element width / thickness: the wider of s_k dx and s_k dy over the
    /// layer's thickness in the lowest column.
    pub ratio: f64,
    /// The layer, 0 at the base.
    pub layer: usize,
    pub width_m: f64,
    pub thickness_m: f64,
}

/// The most an element may be wider than thick (the `fem` stage refuses a
/// flatter mesh before meshing). The shipped pipelines stay below 1.4 and
/// the stage's tests below 3.2; a 4 × 4 window with 32 layers (36) failed
/// Newton after 10–45 s and one with 256 (288) ran for minutes. Tall
/// elements (thickness over width: 27 at the default 8 layers on a 96²
/// patch, which the bench solves) are not bounded.
pub const MAX_FLATNESS: f64 = 10.0;

impl Flatness {
    /// The flattest layer of the mesh `map` and `options` would give,
    /// without building it; None if the options are refused (then by
    /// [`Mesh::new`]).
    pub fn of(map: &HeightMap<'_>, options: &MeshOptions) -> Option<Flatness> {
        let plan = Plan::new(map, options).ok()?;
        let lowest = map.heights_m.iter().copied().fold(f64::INFINITY, f64::min);
        let lowest_column_m = plan.depth_m + lowest - plan.mean_m;
        (0..options.layers)
            .map(|k| {
                let width_m = plan.steps[k] as f64 * map.dx_m.max(map.dy_m);
                let thickness_m = (plan.levels[k + 1] - plan.levels[k]) * lowest_column_m;
                Flatness {
                    ratio: width_m / thickness_m,
                    layer: k,
                    width_m,
                    thickness_m,
                }
            })
            .max_by(|a, b| a.ratio.total_cmp(&b.ratio))
    }
}

/// The lateral element size of each layer, in map points (module docs),
/// from the level fractions and the mean column height in pixels.
pub fn layer_steps(levels: &[f64], depth_px: f64, coarsen: bool) -> Vec<usize> {
    let layers = levels.len() - 1;
    let mut steps = vec![1; layers];
    if !coarsen {
        return steps;
    }
    for k in (0..layers.saturating_sub(1)).rev() {
        let thickness_px = (levels[k + 1] - levels[k]) * depth_px;
        let below_surface_px = (1.0 - levels[k + 1]) * depth_px;
        let bound_px = thickness_px.min(below_surface_px);
        let widest = if bound_px >= 2.0 {
            1usize << (bound_px.log2().floor().min(30.0) as u32)
        } else {
            1
        };
        steps[k] = widest.clamp(steps[k + 1], 2 * steps[k + 1]);
    }
    steps
}

/// Whether index i of a row of n points is a corner for element size
/// `step`.
fn is_corner(i: usize, n: usize, step: usize) -> bool {
    i.is_multiple_of(step) || i == n - 1
}

/// The corners 0, step, 2 step, … below n − 1, and n − 1.
pub fn corner_indices(n: usize, step: usize) -> Vec<usize> {
    (0..n - 1)
        .step_by(step)
        .chain(std::iter::once(n - 1))
        .collect()
}

/// Index i of a row of n points as the linear interpolation of the corners
/// of element size `step`: itself with weight 1 if it is one, else the two
/// corners around it with weights from the distances.
fn interpolation(i: usize, n: usize, step: usize) -> Vec<(usize, f64)> {
    if is_corner(i, n, step) {
        return vec![(i, 1.0)];
    }
    let low = i / step * step;
    let high = (low + step).min(n - 1);
    let span = (high - low) as f64;
    vec![
        (low, (high - i) as f64 / span),
        (high, (i - low) as f64 / span),
    ]
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
pub(crate) mod tests {
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

    /// Issue #50, item 2: the flattest layer is the top one of a small
    /// window with many layers, measured in its lowest column.
    #[test]
    fn flatness_is_the_top_layer_width_over_its_thickness() {
        let heights = [0.0, 0.0, 0.0, -1e-6];
        let map = HeightMap {
            heights_m: &heights,
            nx: 2,
            ny: 2,
            dx_m: 1e-5,
            dy_m: 1e-5,
        };
        let options = MeshOptions {
            layers: 4,
            grading: 1.0,
            ..Default::default()
        };
        let flat = Flatness::of(&map, &options).unwrap();
        // depth 1e-5, mean −2.5e-7: the lowest column 9.25e-6, layers a quarter.
        assert!((flat.thickness_m - 9.25e-6 / 4.0).abs() < 1e-18, "{flat:?}");
        assert_eq!(flat.width_m, 1e-5);
        let graded = MeshOptions {
            layers: 256,
            grading: 8.0,
            ..Default::default()
        };
        let flat = Flatness::of(&map, &graded).unwrap();
        assert_eq!(flat.layer, 255);
        assert!(flat.ratio > 10.0 * MAX_FLATNESS, "{flat:?}");
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

    /// A rough 15 × 13 map (remainders in both directions) under a block
    /// deep enough for three coarsenings (4 layers of 8 pixels).
    pub(crate) fn coarsened(lateral_coarsening: bool) -> Mesh {
        let (nx, ny) = (15, 13);
        let heights: Vec<f64> = (0..nx * ny)
            .map(|p| 0.3 * ((p * 7 % 11) as f64 / 10.0 - 0.5))
            .collect();
        let map = HeightMap {
            heights_m: &heights,
            nx,
            ny,
            dx_m: 1.0,
            dy_m: 1.0,
        };
        let options = MeshOptions {
            depth_m: Some(32.0),
            layers: 4,
            grading: 1.0,
            lateral_coarsening,
        };
        Mesh::new(&map, &options).unwrap()
    }

    #[test]
    fn layer_steps_follow_the_thickness_and_the_depth() {
        // Thicknesses 8.5, 4.3, 2.1, 1.1 pixels, tops 7.5, 3.2, 1.1, 0
        // pixels below the surface: the third layer stays fine.
        assert_eq!(
            layer_steps(&level_fractions(4, 8.0), 16.0, true),
            [4, 2, 1, 1]
        );
        assert_eq!(layer_steps(&level_fractions(4, 8.0), 16.0, false), [1; 4]);
        // Uniform 24-pixel layers: the top one stays fine, then doubling.
        assert_eq!(
            layer_steps(&level_fractions(4, 1.0), 96.0, true),
            [8, 4, 2, 1]
        );
        // Thinner than two pixels: no coarsening.
        assert_eq!(layer_steps(&level_fractions(3, 1.0), 5.0, true), [1, 1, 1]);
        // A thick top over thin layers: never finer below.
        assert_eq!(layer_steps(&level_fractions(3, 0.1), 30.0, true), [2, 2, 1]);
    }

    #[test]
    fn coarsened_mesh_is_conforming() {
        let mesh = coarsened(true);
        assert_eq!(mesh.layer_steps, [8, 4, 2, 1]);
        assert_eq!(corner_indices(15, 8), [0, 8, 14]);
        assert_eq!(corner_indices(13, 4), [0, 4, 8, 12]);
        // Elements per layer: (2 × 2), (4 × 3), (7 × 6), (14 × 12).
        assert_eq!(mesh.elements.len(), 4 + 12 + 42 + 168);
        let lattice = coarsened(false);
        let counted = |m: &Mesh| m.used.iter().filter(|u| **u).count();
        assert_eq!(counted(&lattice), 5 * 15 * 13);
        assert_eq!(mesh.node_count(), counted(&mesh));
        let corners = |step| corner_indices(15, step).len() * corner_indices(13, step).len();
        let used = corners(8) + corners(4) + corners(2) + 2 * corners(1);
        assert_eq!(mesh.node_count(), used);
        let options = MeshOptions {
            depth_m: Some(32.0),
            layers: 4,
            grading: 1.0,
            lateral_coarsening: true,
        };
        let heights: Vec<f64> = (0..15 * 13)
            .map(|p| 0.3 * ((p * 7 % 11) as f64 / 10.0 - 0.5))
            .collect();
        let map = HeightMap {
            heights_m: &heights,
            nx: 15,
            ny: 13,
            dx_m: 1.0,
            dy_m: 1.0,
        };
        assert_eq!(Mesh::node_count_of(&map, &options), used);
        // Every used node of levels 1–3 that is not a corner of the layer
        // below hangs: level 1 (4 over 8), 2 (2 over 4), 3 (1 over 2).
        let hanging =
            (corners(4) - corners(8)) + (corners(2) - corners(4)) + (corners(1) - corners(2));
        assert_eq!(mesh.hanging.len(), hanging);
        // Each element's nodes are used, and the bottom face of a fine
        // element over a coarse one lies on that coarse element's top face:
        // a hanging node sits where the coarse top face's bilinear map puts
        // its (i, j).
        for element in &mesh.elements {
            assert!(element.iter().all(|n| mesh.used[*n]));
        }
        for h in &mesh.hanging {
            let (i, j, k) = mesh.grid_of(h.node);
            let coarse = mesh.layer_steps[k - 1];
            let (i0, j0) = (i / coarse * coarse, j / coarse * coarse);
            let (i1, j1) = ((i0 + coarse).min(14), (j0 + coarse).min(12));
            let fraction = |a: usize, a0: usize, a1: usize| {
                if a1 > a0 {
                    (a - a0) as f64 / (a1 - a0) as f64
                } else {
                    0.0
                }
            };
            let (s, t) = (fraction(i, i0, i1), fraction(j, j0, j1));
            let z = |a, b| lattice.nodes_m[lattice.node(a, b, k)][2];
            let expected = (1.0 - s) * (1.0 - t) * z(i0, j0)
                + s * (1.0 - t) * z(i1, j0)
                + s * t * z(i1, j1)
                + (1.0 - s) * t * z(i0, j1);
            let x = mesh.nodes_m[h.node];
            assert!((x[2] - expected).abs() < 1e-12, "{:?}", (i, j, k));
            assert!((x[0] - i as f64).abs() < 1e-12 && (x[1] - j as f64).abs() < 1e-12);
            let total: f64 = h.masters.iter().map(|m| m.1).sum();
            assert!((total - 1.0).abs() < 1e-15 && h.masters.iter().all(|m| m.1 > 0.0));
        }
        // The remainder: node 12 of a row of 15 between coarse corners 8
        // and 14 (level 1, 4 over 8) has weights 1/3 and 2/3.
        let h = &mesh.hanging[mesh
            .hanging
            .binary_search_by_key(&mesh.node(12, 0, 1), |h| h.node)
            .unwrap()];
        assert_eq!(
            h.masters,
            [
                (mesh.node(8, 0, 1), 2.0 / 6.0),
                (mesh.node(14, 0, 1), 4.0 / 6.0)
            ]
        );
        // The top keeps one node per map point, none hanging.
        assert!(
            mesh.top_nodes()
                .all(|n| mesh.used[n] && !mesh.is_hanging(n))
        );
        // Without the option: the lattice of before.
        assert!(lattice.hanging.is_empty() && lattice.layer_steps == [1; 4]);
    }
}
