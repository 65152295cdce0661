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
    /// the elements around each unknown, with no list of duplicate pairs
    /// (the components of a node share their elements, hence one sorted
    /// union).
    pub fn new(mesh: &Mesh, dofs: &Dofs) -> Self {
        let (element_start, element_unknowns) = all_element_unknowns(mesh, dofs);
        let unknowns_of = |e: usize| &element_unknowns[element_start[e]..element_start[e + 1]];
        let (start, elements) = unknown_elements(dofs.count, &element_start, &element_unknowns);
        let mut col_ptr = Vec::with_capacity(dofs.count + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        let mut union: Vec<usize> = Vec::with_capacity(256);
        let mut previous: &[usize] = &[];
        for column in 0..dofs.count {
            let around = &elements[start[column]..start[column + 1]];
            if around != previous {
                union.clear();
                for &element in around {
                    union.extend_from_slice(unknowns_of(element));
                }
                union.sort_unstable();
                union.dedup();
                previous = around;
            }
            row_idx.extend_from_slice(&union[..union.partition_point(|r| *r <= column)]);
            col_ptr.push(row_idx.len());
        }
        drop((start, elements));
        let mut pattern = Self {
            size: dofs.count,
            col_ptr,
            row_idx,
            entry_start: Vec::with_capacity(mesh.elements.len() + 1),
            entries: Vec::new(),
        };
        pattern.entry_start.push(0);
        for element in 0..mesh.elements.len() {
            let unknowns = unknowns_of(element);
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

    /// The memory its arrays hold, bytes.
    pub fn heap_bytes(&self) -> usize {
        std::mem::size_of::<usize>() * (self.col_ptr.len() + self.row_idx.len())
            + std::mem::size_of::<u32>() * self.entries.len()
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

/// Every element's distinct unknowns ([`element_unknowns`]), as CSR
/// (starts, unknowns).
fn all_element_unknowns(mesh: &Mesh, dofs: &Dofs) -> (Vec<usize>, Vec<usize>) {
    let mut start = Vec::with_capacity(mesh.elements.len() + 1);
    let mut all = Vec::with_capacity(24 * mesh.elements.len());
    let mut unknowns = Vec::with_capacity(96);
    start.push(0);
    for element in &mesh.elements {
        element_unknowns(dofs, element, &mut unknowns);
        all.extend_from_slice(&unknowns);
        start.push(all.len());
    }
    (start, all)
}

/// For each of `count` unknowns, the elements that involve it, as CSR
/// (starts, elements), in element order.
fn unknown_elements(
    count: usize,
    element_start: &[usize],
    element_unknowns: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let mut start = vec![0; count + 1];
    for &e in element_unknowns {
        start[e + 1] += 1;
    }
    for e in 0..count {
        start[e + 1] += start[e];
    }
    let mut fill = start.clone();
    let mut elements = vec![0; start[count]];
    for (index, range) in element_start.windows(2).enumerate() {
        for &e in &element_unknowns[range[0]..range[1]] {
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

    /// The component of each of the m local unknowns if T only selects
    /// (every component one unknown of weight 1 or none, no unknown
    /// twice), else `None`.
    fn selection(&self, m: usize) -> Option<[usize; 24]> {
        if self.start[24] != m {
            return None;
        }
        let mut component = [usize::MAX; 24];
        for p in 0..24 {
            match self.of(p) {
                [] => {}
                [(a, w)] if *w == 1.0 => component[*a] = p,
                _ => return None,
            }
        }
        Some(component)
    }
}

/// Row a of the upper triangle of an m × m matrix starts at
/// a m − a(a − 1)/2.
fn row_start(a: usize, m: usize) -> usize {
    a * m - a * a.saturating_sub(1) / 2
}

/// TᵀKT, upper triangle, when T selects `component[a]` for unknown a: the
/// element's own entries K[p][q] (p, q the components of unknowns a ≤ b).
fn selected_upper(k: &[[f64; 24]; 24], component: &[usize]) -> Vec<f64> {
    let m = component.len();
    let mut upper = Vec::with_capacity(m * (m + 1) / 2);
    for (a, &p) in component.iter().enumerate() {
        upper.extend(component[a..].iter().map(|&q| k[p][q]));
    }
    upper
}

/// TᵀKT, upper triangle, for any T: Σ_pq w_pa w_qb K[p][q], summed in the
/// components' order.
fn weighted_upper(k: &[[f64; 24]; 24], local: &LocalTerms, m: usize) -> Vec<f64> {
    let mut upper = vec![0.0; m * (m + 1) / 2];
    for (p, row) in k.iter().enumerate() {
        for &(a, wa) in local.of(p) {
            let offset = row_start(a, m) - a;
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
    let stiffness = response
        .stiffness
        .as_deref()
        .map(|k| match local.selection(m) {
            Some(component) => selected_upper(k, &component[..m]),
            None => weighted_upper(k, &local, m),
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
