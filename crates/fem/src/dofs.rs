//! Boundary conditions as a map from node components to unknowns
//! ("equations"): the base is clamped (no unknowns), a `mirror` face has no
//! unknown for its normal component, and a `periodic` node shares the
//! unknowns of the node one period back (a tie by elimination, which keeps
//! the system symmetric). Contact acts on the z unknowns of the top nodes,
//! one per distinct top node ([`TopNode`]): with periodic faces the tied
//! edge nodes are one contact point.

use crate::mesh::{Lateral, Mesh};

/// A top node where the plane may press: its z unknown and what it stands
/// for.
#[derive(Clone, Debug, PartialEq)]
pub struct TopNode {
    /// The node whose reference height decides contact (the master of a tie).
    pub node: usize,
    /// Its z equation.
    pub equation: usize,
    /// The reference area it carries (its own tributary area plus that of
    /// the nodes tied to it), m².
    pub area_m2: f64,
}

/// The unknowns of a mesh under its boundary conditions.
#[derive(Clone, Debug, PartialEq)]
pub struct Dofs {
    /// For node n, component c: `equation_of[3n + c]`, `None` if held at 0.
    pub equation_of: Vec<Option<usize>>,
    /// Number of unknowns.
    pub count: usize,
    /// The distinct top nodes.
    pub top: Vec<TopNode>,
    /// For each map point (i * ny + j), its index in `top`.
    pub top_of_point: Vec<usize>,
    /// Values of the held components (`3n + c`), m: 0 under the block's
    /// boundary conditions; set by [`Dofs::prescribed`].
    pub held_value_m: Vec<f64>,
}

impl Dofs {
    pub fn new(mesh: &Mesh, lateral: Lateral) -> Self {
        let (nx, ny) = (mesh.nx, mesh.ny);
        let n_nodes = mesh.nodes_m.len();
        let master = |node: usize| -> usize {
            let (i, j, k) = mesh.grid_of(node);
            match lateral {
                Lateral::Mirror => node,
                Lateral::Periodic => mesh.node(i % (nx - 1), j % (ny - 1), k),
            }
        };
        let mut equation_of = vec![None; 3 * n_nodes];
        let mut count = 0;
        for node in 0..n_nodes {
            let (i, j, k) = mesh.grid_of(node);
            let held = |c: usize| {
                k == 0
                    || (lateral == Lateral::Mirror
                        && ((c == 0 && (i == 0 || i == nx - 1))
                            || (c == 1 && (j == 0 || j == ny - 1))))
            };
            let m = master(node);
            for c in 0..3 {
                equation_of[3 * node + c] = if held(c) {
                    None
                } else if m != node {
                    // Masters have smaller i or j, hence a smaller number at
                    // the same level: already numbered.
                    equation_of[3 * m + c]
                } else {
                    count += 1;
                    Some(count - 1)
                };
            }
        }
        let mut top: Vec<TopNode> = Vec::new();
        let mut top_of_point = vec![0; nx * ny];
        let mut index_of_master = std::collections::BTreeMap::new();
        for i in 0..nx {
            for j in 0..ny {
                let node = mesh.node(i, j, mesh.layers);
                let m = master(node);
                let index = *index_of_master.entry(m).or_insert_with(|| {
                    top.push(TopNode {
                        node: m,
                        equation: equation_of[3 * m + 2].unwrap_or(usize::MAX),
                        area_m2: 0.0,
                    });
                    top.len() - 1
                });
                top[index].area_m2 += mesh.tributary_area_m2(i, j);
                top_of_point[i * ny + j] = index;
            }
        }
        Self {
            held_value_m: vec![0.0; equation_of.len()],
            equation_of,
            count,
            top,
            top_of_point,
        }
    }

    /// Unknowns with prescribed values instead of the block's conditions:
    /// `rule(i, j, k, c)` gives the displacement of component c of node
    /// (i, j, k), or `None` where it is free. No ties; every top node is a
    /// contact candidate whose z is free (for homogeneous tests and other
    /// set-ups of the same mesh).
    pub fn prescribed(
        mesh: &Mesh,
        rule: impl Fn(usize, usize, usize, usize) -> Option<f64>,
    ) -> Self {
        let mut dofs = Self::new(mesh, Lateral::Mirror);
        let mut count = 0;
        for node in 0..mesh.nodes_m.len() {
            let (i, j, k) = mesh.grid_of(node);
            for c in 0..3 {
                let slot = 3 * node + c;
                match rule(i, j, k, c) {
                    Some(value) => {
                        dofs.equation_of[slot] = None;
                        dofs.held_value_m[slot] = value;
                    }
                    None => {
                        dofs.equation_of[slot] = Some(count);
                        count += 1;
                    }
                }
            }
        }
        dofs.count = count;
        for top in &mut dofs.top {
            top.equation = dofs.equation_of[3 * top.node + 2].unwrap_or(usize::MAX);
        }
        dofs
    }

    /// Nodal displacements from the unknowns (held components at their
    /// held values).
    pub fn expand(&self, unknowns: &[f64]) -> Vec<[f64; 3]> {
        (self
            .equation_of
            .chunks_exact(3)
            .zip(self.held_value_m.chunks_exact(3)))
        .map(|(eq, held)| [0, 1, 2].map(|c| eq[c].map_or(held[c], |e| unknowns[e])))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{HeightMap, MeshOptions};

    fn mesh(nx: usize, ny: usize) -> Mesh {
        let h = vec![0.0; nx * ny];
        let map = HeightMap {
            heights_m: &h,
            nx,
            ny,
            dx_m: 1.0,
            dy_m: 1.0,
        };
        Mesh::new(
            &map,
            &MeshOptions {
                layers: 2,
                ..Default::default()
            },
        )
        .unwrap()
    }

    #[test]
    fn mirror_holds_normals_and_the_base() {
        let m = mesh(3, 4);
        let d = Dofs::new(&m, Lateral::Mirror);
        // 2 levels above the base × 12 nodes × 3, less x-normals on 2 × 4
        // nodes per level and y-normals on 2 × 3.
        assert_eq!(d.count, 2 * (36 - 8 - 6));
        let corner = m.node(0, 0, 1);
        assert_eq!(&d.equation_of[3 * corner..3 * corner + 2], &[None, None]);
        assert!(d.equation_of[3 * corner + 2].is_some());
        assert!(
            d.equation_of[3 * m.node(1, 1, 0)..][..3]
                .iter()
                .all(Option::is_none)
        );
        assert_eq!(d.top.len(), 12);
    }

    #[test]
    fn periodic_ties_opposite_faces() {
        let m = mesh(3, 4);
        let d = Dofs::new(&m, Lateral::Periodic);
        assert_eq!(d.count, 2 * 2 * 3 * 3);
        let (a, b) = (m.node(0, 1, 2), m.node(2, 1, 2));
        assert_eq!(
            d.equation_of[3 * a..3 * a + 3],
            d.equation_of[3 * b..3 * b + 3]
        );
        let (c, e) = (m.node(0, 0, 1), m.node(2, 3, 1));
        assert_eq!(
            d.equation_of[3 * c..3 * c + 3],
            d.equation_of[3 * e..3 * e + 3]
        );
        assert_eq!(d.top.len(), 6);
        let area: f64 = d.top.iter().map(|t| t.area_m2).sum();
        assert!((area - 6.0).abs() < 1e-12);
        assert!(d.top.iter().all(|t| (t.area_m2 - 1.0).abs() < 1e-12));
    }
}
