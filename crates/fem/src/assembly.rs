//! Assembly of the global residual and tangent in a fixed order. Element
//! responses are computed in parallel (rayon) in chunks, then added into
//! the global arrays one element after another in element order, so every
//! sum is formed in the same order on any number of threads and the results
//! are the same bits.
//!
//! An element's 24 components map to its distinct unknowns through the
//! slots' (unknown, weight) terms ([`Dofs`]): with T that map, the element
//! adds Tᵀf to the residual and TᵀKT to the tangent (for ordinary
//! components T selects, and the entries are the element's own; a hanging
//! node spreads its rows over its masters, the standard elimination of
//! linear constraints). The reduction runs in the parallel part, per
//! element, in a fixed order.
//!
//! The tangent is stored as the upper triangle (row ≤ column) of a
//! compressed-sparse-column matrix whose pattern ([`Pattern`]) depends only
//! on the mesh and the boundary conditions, so one symbolic factorisation
//! serves every Newton iteration and every step.

use rayon::prelude::*;

use crate::dofs::Dofs;
use crate::hexahedron::{self, ElementFailure, ElementOutput};
use crate::law::Law;
use crate::mesh::Mesh;

/// Elements evaluated in parallel before their ordered scatter: large enough
/// to feed the threads, small enough that the buffered element matrices
/// (2.4 kB each, reduced) stay in cache-sized memory.
const CHUNK: usize = 512;

/// The upper-triangular CSC pattern of the tangent over the unknowns, with
/// the value index of each element matrix entry (computed once: looking
/// them up at every assembly took half its time).
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    pub size: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// Element e's entries are `entries[entry_start[e]..entry_start[e + 1]]`.
    entry_start: Vec<usize>,
    /// Per element, the value index of each pair a ≤ b of its distinct
    /// unknowns (ascending; [`element_unknowns`]), row by row: m(m + 1)/2
    /// for m unknowns, 300 for an element with 24 (the symmetric half).
    entries: Vec<u32>,
}

impl Pattern {
    /// The pattern of `mesh` under `dofs`: column c holds every unknown
    /// r ≤ c that shares an element with c. Built column by column from
    /// the elements around each unknown, with no list of duplicate pairs.
    pub fn new(mesh: &Mesh, dofs: &Dofs) -> Self {
        let elements_of = unknown_elements(mesh, dofs);
        let mut col_ptr = Vec::with_capacity(dofs.count + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        let mut unknowns = Vec::with_capacity(96);
        let mut rows = Vec::with_capacity(256);
        for column in 0..dofs.count {
            rows.clear();
            for &element in &elements_of.1[elements_of.0[column]..elements_of.0[column + 1]] {
                element_unknowns(dofs, &mesh.elements[element], &mut unknowns);
                rows.extend(unknowns.iter().filter(|r| **r <= column));
            }
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend_from_slice(&rows);
            col_ptr.push(row_idx.len());
        }
        drop(elements_of);
        let mut pattern = Self {
            size: dofs.count,
            col_ptr,
            row_idx,
            entry_start: Vec::with_capacity(mesh.elements.len() + 1),
            entries: Vec::new(),
        };
        pattern.entry_start.push(0);
        for element in &mesh.elements {
            element_unknowns(dofs, element, &mut unknowns);
            for (a, &row) in unknowns.iter().enumerate() {
                for &col in &unknowns[a..] {
                    let index = pattern
                        .position(row, col)
                        .and_then(|k| u32::try_from(k).ok())
                        .expect("the pattern holds every element pair within u32 indices");
                    pattern.entries.push(index);
                }
            }
            pattern.entry_start.push(pattern.entries.len());
        }
        pattern.entries.shrink_to_fit();
        pattern
    }

    /// A pattern from CSC arrays alone, without element entries (for
    /// solver tests).
    pub fn from_csc(size: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Self {
        Self {
            size,
            col_ptr,
            row_idx,
            entry_start: vec![0],
            entries: Vec::new(),
        }
    }

    /// The value index of entry (row, col), row ≤ col.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let start = self.col_ptr[col];
        let rows = &self.row_idx[start..self.col_ptr[col + 1]];
        rows.binary_search(&row).ok().map(|k| start + k)
    }

    /// The index of the diagonal entry of each column.
    pub fn diagonal_positions(&self) -> Vec<usize> {
        // The diagonal is the last (largest) row of each upper column.
        (0..self.size).map(|c| self.col_ptr[c + 1] - 1).collect()
    }

    /// Bytes of the element entry table (for memory accounting).
    pub fn entry_bytes(&self) -> usize {
        self.entries.len() * std::mem::size_of::<u32>()
            + self.entry_start.len() * std::mem::size_of::<usize>()
    }
}

/// For each unknown, the elements whose components involve it, as CSR
/// (starts, elements), in element order.
fn unknown_elements(mesh: &Mesh, dofs: &Dofs) -> (Vec<usize>, Vec<usize>) {
    let mut unknowns = Vec::with_capacity(96);
    let mut start = vec![0; dofs.count + 1];
    for element in &mesh.elements {
        element_unknowns(dofs, element, &mut unknowns);
        for &e in &unknowns {
            start[e + 1] += 1;
        }
    }
    for e in 0..dofs.count {
        start[e + 1] += start[e];
    }
    let mut fill = start.clone();
    let mut elements = vec![0; start[dofs.count]];
    for (index, element) in mesh.elements.iter().enumerate() {
        element_unknowns(dofs, element, &mut unknowns);
        for &e in &unknowns {
            elements[fill[e]] = index;
            fill[e] += 1;
        }
    }
    (start, elements)
}

/// The distinct unknowns of an element's 24 components, ascending, into
/// `out`.
pub fn element_unknowns(dofs: &Dofs, element: &[usize; 8], out: &mut Vec<usize>) {
    out.clear();
    for p in 0..24 {
        out.extend(dofs.terms(3 * element[p / 3] + p % 3).iter().map(|t| t.0));
    }
    out.sort_unstable();
    out.dedup();
}

/// The assembled state at one set of unknowns.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Π, J.
    pub energy_j: f64,
    /// ∂Π/∂x per unknown: internal force, N (at a held contact unknown, the
    /// reaction the plane exerts, sign reversed).
    pub residual_n: Vec<f64>,
    /// Tangent values on [`Pattern`], if asked for.
    pub tangent: Option<Vec<f64>>,
}

/// An element without a response, with its number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Failure {
    pub element: usize,
    pub failure: ElementFailure,
}

/// An element's response on its distinct unknowns.
struct Reduced {
    energy_j: f64,
    /// Its unknowns, ascending.
    unknowns: Vec<usize>,
    /// Tᵀf per unknown, N.
    force_n: Vec<f64>,
    /// TᵀKT, pairs a ≤ b row by row (the order of [`Pattern`]'s entries).
    stiffness: Option<Vec<f64>>,
}

/// Residual (and tangent, with `pattern`) at the unknowns `x`.
pub fn evaluate(
    mesh: &Mesh,
    dofs: &Dofs,
    law: &Law,
    pattern: Option<&Pattern>,
    x: &[f64],
) -> Result<Evaluation, Failure> {
    let displacement = dofs.expand(x);
    let mut out = Evaluation {
        energy_j: 0.0,
        residual_n: vec![0.0; dofs.count],
        tangent: pattern.map(|p| vec![0.0; p.row_idx.len()]),
    };
    let with_tangent = pattern.is_some();
    let numbered: Vec<(usize, &[usize; 8])> = mesh.elements.iter().enumerate().collect();
    for chunk in numbered.chunks(CHUNK) {
        let responses: Vec<Result<Reduced, Failure>> = chunk
            .par_iter()
            .map(|&(index, element)| {
                let reference = element.map(|n| mesh.nodes_m[n]);
                let u = element.map(|n| displacement[n]);
                hexahedron::evaluate(law, &reference, &u, with_tangent)
                    .map(|response| reduce(dofs, element, &response))
                    .map_err(|failure| Failure {
                        element: index,
                        failure,
                    })
            })
            .collect();
        for (&(index, _), response) in chunk.iter().zip(responses) {
            scatter(pattern, index, &response?, &mut out);
        }
    }
    Ok(out)
}

/// The terms of an element's 24 components on its local unknowns (indices
/// into its ascending unknown list): component p's are
/// `terms[start[p]..start[p + 1]]`. Fixed arrays: a slot has at most four
/// terms (a hanging node's bilinear masters).
struct LocalTerms {
    start: [usize; 25],
    terms: [(usize, f64); 96],
}

impl LocalTerms {
    fn new(dofs: &Dofs, element: &[usize; 8], unknowns: &[usize]) -> Self {
        let mut local = Self {
            start: [0; 25],
            terms: [(0, 0.0); 96],
        };
        let mut next = 0;
        for p in 0..24 {
            for &(e, w) in dofs.terms(3 * element[p / 3] + p % 3) {
                local.terms[next] = (unknowns.partition_point(|u| *u < e), w);
                next += 1;
            }
            local.start[p + 1] = next;
        }
        local
    }

    fn of(&self, p: usize) -> &[(usize, f64)] {
        &self.terms[self.start[p]..self.start[p + 1]]
    }
}

/// Tᵀf and TᵀKT of one element (module docs), each entry summed over the
/// element's components in their local order.
fn reduce(dofs: &Dofs, element: &[usize; 8], response: &ElementOutput) -> Reduced {
    let mut unknowns = Vec::with_capacity(24);
    element_unknowns(dofs, element, &mut unknowns);
    let m = unknowns.len();
    let local = LocalTerms::new(dofs, element, &unknowns);
    let mut force_n = vec![0.0; m];
    for (p, force) in response.force_n.iter().enumerate() {
        for &(a, w) in local.of(p) {
            force_n[a] += w * force;
        }
    }
    let stiffness = response.stiffness.as_deref().map(|k| {
        // Row a of the upper triangle starts at a m − a(a − 1)/2.
        let row_start = |a: usize| a * m - a * a.saturating_sub(1) / 2;
        let mut upper = vec![0.0; m * (m + 1) / 2];
        for (p, row) in k.iter().enumerate() {
            for &(a, wa) in local.of(p) {
                let offset = row_start(a) - a;
                for (q, value) in row.iter().enumerate() {
                    for &(b, wb) in local.of(q) {
                        if b >= a {
                            upper[offset + b] += wa * wb * value;
                        }
                    }
                }
            }
        }
        upper
    });
    Reduced {
        energy_j: response.energy_j,
        unknowns,
        force_n,
        stiffness,
    }
}

fn scatter(pattern: Option<&Pattern>, index: usize, response: &Reduced, out: &mut Evaluation) {
    out.energy_j += response.energy_j;
    for (e, force) in response.unknowns.iter().zip(&response.force_n) {
        out.residual_n[*e] += force;
    }
    let (Some(pattern), Some(values), Some(k)) =
        (pattern, out.tangent.as_mut(), response.stiffness.as_deref())
    else {
        return;
    };
    let entries = &pattern.entries[pattern.entry_start[index]..pattern.entry_start[index + 1]];
    for (&position, value) in entries.iter().zip(k) {
        values[position as usize] += value;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Lateral;

    /// Every pair (r ≤ c) of every element's unknowns, collected with
    /// duplicates and sorted: the pattern by its definition.
    fn pairs(mesh: &Mesh, dofs: &Dofs) -> (Vec<usize>, Vec<usize>) {
        let mut columns: Vec<Vec<usize>> = vec![Vec::new(); dofs.count];
        let mut unknowns = Vec::new();
        for element in &mesh.elements {
            element_unknowns(dofs, element, &mut unknowns);
            for &c in &unknowns {
                columns[c].extend(unknowns.iter().filter(|r| **r <= c));
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for column in &mut columns {
            column.sort_unstable();
            column.dedup();
            row_idx.extend_from_slice(column);
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx)
    }

    #[test]
    fn pattern_holds_every_element_pair_once() {
        for coarsen in [false, true] {
            let mesh = crate::mesh::tests::coarsened(coarsen);
            for lateral in [Lateral::Mirror, Lateral::Periodic] {
                let dofs = Dofs::new(&mesh, lateral);
                let pattern = Pattern::new(&mesh, &dofs);
                let (col_ptr, row_idx) = pairs(&mesh, &dofs);
                assert_eq!(pattern.col_ptr, col_ptr);
                assert_eq!(pattern.row_idx, row_idx);
                // m(m + 1)/2 entries per element, 300 for 24 unknowns.
                let mut unknowns = Vec::new();
                let expected: usize = (mesh.elements.iter())
                    .map(|e| {
                        element_unknowns(&dofs, e, &mut unknowns);
                        unknowns.len() * (unknowns.len() + 1) / 2
                    })
                    .sum();
                assert_eq!(pattern.entries.len(), expected);
                assert!(
                    pattern
                        .entries
                        .iter()
                        .all(|p| (*p as usize) < row_idx.len())
                );
            }
        }
    }
}
