//! Boundary conditions as a map from node components to unknowns
//! ("equations"): the base is clamped (no unknowns), a `mirror` face has no
//! unknown for its normal component, and a `periodic` node shares the
//! unknowns of the node one period back (a tie by elimination, which keeps
//! the system symmetric). Contact acts on the z unknowns of the top nodes,
//! one per distinct top node ([`TopNode`]): with periodic faces the tied
//! edge nodes are one contact point.
//!
//! Each node component ("slot" 3n + c) is an affine function of the
//! unknowns: its held value plus a short list of (unknown, weight) terms.
//! No term: held (or an unused lattice node); one of weight 1: an ordinary
//! or tied component; up to four: a hanging node of a laterally coarsened
//! mesh ([`crate::mesh`]), whose component is the bilinear interpolation of
//! its masters' same component (their terms and held values, weighted), so
//! that mirror faces (masters on the face, normal held) and periodic ties
//! (masters tied like any node) carry over to it. Eliminating the hanging
//! components this way keeps the system symmetric and positive definite.

use crate::mesh::{Lateral, Mesh, weighted};

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
    /// Slot s = 3n + c has the terms `terms[term_start[s]..term_start[s + 1]]`.
    term_start: Vec<usize>,
    /// (unknown, weight), by increasing unknown within a slot.
    terms: Vec<(usize, f64)>,
    /// Number of unknowns.
    pub count: usize,
    /// The distinct top nodes.
    pub top: Vec<TopNode>,
    /// For each map point (i * ny + j), its index in `top`.
    pub top_of_point: Vec<usize>,
    /// Held part of each slot, m: 0 under the block's boundary conditions;
    /// set by [`Dofs::prescribed`] (for a hanging node, its masters' held
    /// parts interpolated).
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
        let hanging = hanging_flags(mesh);
        let mut own = vec![None; 3 * n_nodes];
        let mut count = 0;
        for node in (0..n_nodes).filter(|n| mesh.used[*n] && !hanging[*n]) {
            let (i, j, k) = mesh.grid_of(node);
            let held = |c: usize| {
                k == 0
                    || (lateral == Lateral::Mirror
                        && ((c == 0 && (i == 0 || i == nx - 1))
                            || (c == 1 && (j == 0 || j == ny - 1))))
            };
            let m = master(node);
            for c in 0..3 {
                own[3 * node + c] = if held(c) {
                    None
                } else if m != node {
                    // Masters have smaller i or j, hence a smaller number at
                    // the same level: already numbered.
                    own[3 * m + c]
                } else {
                    count += 1;
                    Some(count - 1)
                };
            }
        }
        let (top, top_of_point) = top_nodes(mesh, &own, master);
        let mut held_value_m = vec![0.0; own.len()];
        let (term_start, terms) = slot_terms(mesh, &own, &mut held_value_m);
        Self {
            term_start,
            terms,
            held_value_m,
            count,
            top,
            top_of_point,
        }
    }

    /// Unknowns with prescribed values instead of the block's conditions:
    /// `rule(i, j, k, c)` gives the displacement of component c of node
    /// (i, j, k), or `None` where it is free (asked of every used node but
    /// the hanging ones, which follow their masters). No ties; every top
    /// node is a contact candidate whose z is free (for homogeneous tests
    /// and other set-ups of the same mesh).
    pub fn prescribed(
        mesh: &Mesh,
        rule: impl Fn(usize, usize, usize, usize) -> Option<f64>,
    ) -> Self {
        let mut dofs = Self::new(mesh, Lateral::Mirror);
        let hanging = hanging_flags(mesh);
        let mut own = vec![None; 3 * mesh.nodes_m.len()];
        let mut held_value_m = vec![0.0; own.len()];
        let mut count = 0;
        for node in (0..mesh.nodes_m.len()).filter(|n| mesh.used[*n] && !hanging[*n]) {
            let (i, j, k) = mesh.grid_of(node);
            for c in 0..3 {
                let slot = 3 * node + c;
                match rule(i, j, k, c) {
                    Some(value) => held_value_m[slot] = value,
                    None => {
                        own[slot] = Some(count);
                        count += 1;
                    }
                }
            }
        }
        (dofs.term_start, dofs.terms) = slot_terms(mesh, &own, &mut held_value_m);
        dofs.held_value_m = held_value_m;
        dofs.count = count;
        for top in &mut dofs.top {
            top.equation = own[3 * top.node + 2].unwrap_or(usize::MAX);
        }
        dofs
    }

    /// The (unknown, weight) terms of slot 3n + c.
    pub fn terms(&self, slot: usize) -> &[(usize, f64)] {
        &self.terms[self.term_start[slot]..self.term_start[slot + 1]]
    }

    /// The unknown that slot 3n + c equals (an ordinary or tied component),
    /// `None` if it is held, unused or interpolated.
    pub fn equation(&self, slot: usize) -> Option<usize> {
        match self.terms(slot) {
            [(e, w)] if *w == 1.0 && self.held_value_m[slot] == 0.0 => Some(*e),
            _ => None,
        }
    }

    /// The displacement of slot 3n + c at the unknowns, m.
    pub fn value(&self, slot: usize, unknowns: &[f64]) -> f64 {
        let held = self.held_value_m[slot];
        match self.terms(slot) {
            [] => held,
            [(e, w), rest @ ..] => {
                // From the first term, so an ordinary slot is its unknown's
                // bits exactly.
                let mut sum = w * unknowns[*e];
                for (e, w) in rest {
                    sum += w * unknowns[*e];
                }
                if held != 0.0 { sum + held } else { sum }
            }
        }
    }

    /// Nodal displacements from the unknowns (held components at their
    /// held values, hanging ones interpolated), m.
    pub fn expand(&self, unknowns: &[f64]) -> Vec<[f64; 3]> {
        (0..self.held_value_m.len() / 3)
            .map(|node| [0, 1, 2].map(|c| self.value(3 * node + c, unknowns)))
            .collect()
    }
}

/// Per lattice node: whether it hangs.
fn hanging_flags(mesh: &Mesh) -> Vec<bool> {
    let mut flags = vec![false; mesh.nodes_m.len()];
    for h in &mesh.hanging {
        flags[h.node] = true;
    }
    flags
}

/// The terms of every slot from the unknowns of the corner slots (`own`),
/// with the hanging slots' held parts added to `held_value_m`.
fn slot_terms(
    mesh: &Mesh,
    own: &[Option<usize>],
    held_value_m: &mut [f64],
) -> (Vec<usize>, Vec<(usize, f64)>) {
    let mut term_start = Vec::with_capacity(own.len() + 1);
    let mut terms = Vec::with_capacity(own.len());
    let mut hanging = mesh.hanging.iter().peekable();
    let mut merged: Vec<(usize, f64)> = Vec::with_capacity(4);
    for node in 0..own.len() / 3 {
        let masters = hanging.next_if(|h| h.node == node).map(|h| &h.masters);
        for c in 0..3 {
            term_start.push(terms.len());
            let Some(masters) = masters else {
                terms.extend(own[3 * node + c].map(|e| (e, 1.0)));
                continue;
            };
            // Masters tied to one unknown (a coarse element across a whole
            // period) add their weights.
            merged.clear();
            for &(m, w) in masters {
                if let Some(e) = own[3 * m + c] {
                    match merged.iter_mut().find(|t| t.0 == e) {
                        Some(term) => term.1 += w,
                        None => merged.push((e, w)),
                    }
                }
            }
            merged.sort_by_key(|t| t.0);
            terms.extend_from_slice(&merged);
            let held = weighted(masters, |m| held_value_m[3 * m + c]);
            held_value_m[3 * node + c] = held;
        }
    }
    term_start.push(terms.len());
    (term_start, terms)
}

/// The distinct top nodes (masters of the ties) with their z unknowns and
/// areas, and each map point's index among them.
fn top_nodes(
    mesh: &Mesh,
    own: &[Option<usize>],
    master: impl Fn(usize) -> usize,
) -> (Vec<TopNode>, Vec<usize>) {
    let (nx, ny) = (mesh.nx, mesh.ny);
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
                    equation: own[3 * m + 2].unwrap_or(usize::MAX),
                    area_m2: 0.0,
                });
                top.len() - 1
            });
            top[index].area_m2 += mesh.tributary_area_m2(i, j);
            top_of_point[i * ny + j] = index;
        }
    }
    (top, top_of_point)
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
        assert_eq!(
            (d.equation(3 * corner), d.equation(3 * corner + 1)),
            (None, None)
        );
        assert!(d.equation(3 * corner + 2).is_some());
        let base = m.node(1, 1, 0);
        assert!((0..3).all(|c| d.terms(3 * base + c).is_empty()));
        assert_eq!(d.top.len(), 12);
    }

    #[test]
    fn periodic_ties_opposite_faces() {
        let m = mesh(3, 4);
        let d = Dofs::new(&m, Lateral::Periodic);
        assert_eq!(d.count, 2 * 2 * 3 * 3);
        let equations = |n: usize| [0, 1, 2].map(|c| d.equation(3 * n + c));
        let (a, b) = (m.node(0, 1, 2), m.node(2, 1, 2));
        assert_eq!(equations(a), equations(b));
        let (c, e) = (m.node(0, 0, 1), m.node(2, 3, 1));
        assert_eq!(equations(c), equations(e));
        assert_eq!(d.top.len(), 6);
        let area: f64 = d.top.iter().map(|t| t.area_m2).sum();
        assert!((area - 6.0).abs() < 1e-12);
        assert!(d.top.iter().all(|t| (t.area_m2 - 1.0).abs() < 1e-12));
    }

    /// A linear field prescribed on the faces and the base of a coarsened
    /// mesh, and given to the free unknowns at their nodes, expands to the
    /// linear field at every used node, hanging ones included (on the faces
    /// through their masters' held values).
    #[test]
    fn hanging_nodes_interpolate_a_linear_field() {
        let m = crate::mesh::tests::coarsened(true);
        let field =
            |x: [f64; 3], c: usize| 1e-3 * (c as f64 + 1.0) * (x[0] - 2.0 * x[1] + 0.5 * x[2]);
        let (nx, ny) = (m.nx, m.ny);
        let d = Dofs::prescribed(&m, |i, j, k, c| {
            let face = i == 0 || j == 0 || i == nx - 1 || j == ny - 1 || k == 0;
            face.then(|| field(m.nodes_m[m.node(i, j, k)], c))
        });
        let mut x = vec![f64::NAN; d.count];
        for node in (0..m.nodes_m.len()).filter(|n| m.used[*n] && !m.is_hanging(*n)) {
            for c in 0..3 {
                if let Some(e) = d.equation(3 * node + c) {
                    x[e] = field(m.nodes_m[node], c);
                }
            }
        }
        assert!(x.iter().all(|v| v.is_finite()));
        let u = d.expand(&x);
        let mut on_faces = 0;
        for h in &m.hanging {
            let (i, j, _) = m.grid_of(h.node);
            on_faces += usize::from(i == 0 || j == 0 || i == nx - 1 || j == ny - 1);
        }
        assert!(on_faces > 0);
        for node in (0..m.nodes_m.len()).filter(|n| m.used[*n]) {
            for (c, got) in u[node].iter().enumerate() {
                let want = field(m.nodes_m[node], c);
                assert!((got - want).abs() < 1e-15, "{:?} {c}", m.grid_of(node));
            }
        }
    }

    /// Mirror faces hold a hanging node's normal; periodic ties give a
    /// hanging node on x = (nx − 1)dx its counterpart's terms.
    #[test]
    fn hanging_nodes_keep_mirror_and_periodic_conditions() {
        let m = crate::mesh::tests::coarsened(true);
        let mirror = Dofs::new(&m, Lateral::Mirror);
        let periodic = Dofs::new(&m, Lateral::Periodic);
        let mut checked = 0;
        for h in &m.hanging {
            let (i, j, k) = m.grid_of(h.node);
            if i == 0 {
                assert!(mirror.terms(3 * h.node).is_empty());
                let twin = m.node(m.nx - 1, j, k);
                for c in 0..3 {
                    assert_eq!(periodic.terms(3 * h.node + c), periodic.terms(3 * twin + c));
                }
                checked += 1;
            }
            // Masters above the base: z free at every one.
            assert_eq!(mirror.terms(3 * h.node + 2).len(), h.masters.len());
        }
        assert!(checked > 0);
        // Unused lattice nodes have no unknowns; the unknowns are those of
        // the used corner nodes.
        let free: usize = (0..m.nodes_m.len())
            .filter(|n| m.used[*n] && !m.is_hanging(*n))
            .map(|n| {
                (0..3)
                    .filter(|c| mirror.equation(3 * n + c).is_some())
                    .count()
            })
            .sum();
        assert_eq!(free, mirror.count);
        assert!(
            (0..m.nodes_m.len())
                .filter(|n| !m.used[*n])
                .all(|n| { (0..3).all(|c| mirror.terms(3 * n + c).is_empty()) })
        );
    }
}
