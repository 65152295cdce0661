//! Assembly of the global residual and tangent in a fixed order. Element
//! responses are computed in parallel (rayon) in chunks, then added into
//! the global arrays one element after another in element order, so every
//! sum is formed in the same order on any number of threads and the results
//! are the same bits.
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
/// (4.6 kB each) stay in cache-sized memory.
const CHUNK: usize = 512;

/// Marks an element entry that is not stored (a held component, or the
/// lower triangle).
const NOT_STORED: u32 = u32::MAX;

/// The upper-triangular CSC pattern of the tangent over the unknowns, with
/// the value index of each element matrix entry (computed once: looking
/// them up at every assembly took half its time).
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    pub size: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// Per element, 24 × 24 value indices (row-major in the element's local
    /// numbering), [`NOT_STORED`] where none.
    entries: Vec<u32>,
}

impl Pattern {
    pub fn new(mesh: &Mesh, dofs: &Dofs) -> Self {
        let mut columns: Vec<Vec<usize>> = vec![Vec::new(); dofs.count];
        for element in &mesh.elements {
            let eqs = element_equations(dofs, element);
            for c in eqs.iter().flatten() {
                for r in eqs.iter().flatten() {
                    if r <= c {
                        columns[*c].push(*r);
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(dofs.count + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for column in &mut columns {
            column.sort_unstable();
            column.dedup();
            row_idx.extend_from_slice(column);
            col_ptr.push(row_idx.len());
        }
        let mut pattern = Self {
            size: dofs.count,
            col_ptr,
            row_idx,
            entries: Vec::with_capacity(mesh.elements.len() * 576),
        };
        for element in &mesh.elements {
            let eqs = element_equations(dofs, element);
            for row in &eqs {
                for col in &eqs {
                    let index = match (row, col) {
                        (Some(r), Some(c)) if r <= c => {
                            pattern.position(*r, *c).and_then(|k| u32::try_from(k).ok())
                        }
                        _ => None,
                    };
                    pattern.entries.push(index.unwrap_or(NOT_STORED));
                }
            }
        }
        pattern
    }

    /// A pattern from CSC arrays alone, without element entries (for
    /// solver tests).
    pub fn from_csc(size: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Self {
        Self {
            size,
            col_ptr,
            row_idx,
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
}

/// The unknown of each of an element's 24 components.
pub fn element_equations(dofs: &Dofs, element: &[usize; 8]) -> [Option<usize>; 24] {
    std::array::from_fn(|p| dofs.equation_of[3 * element[p / 3] + p % 3])
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
        let responses: Vec<Result<ElementOutput, Failure>> = chunk
            .par_iter()
            .map(|&(index, element)| {
                let reference = element.map(|n| mesh.nodes_m[n]);
                let u = element.map(|n| displacement[n]);
                hexahedron::evaluate(law, &reference, &u, with_tangent).map_err(|failure| Failure {
                    element: index,
                    failure,
                })
            })
            .collect();
        for (&numbered, response) in chunk.iter().zip(responses) {
            let response = response?;
            scatter(dofs, pattern, numbered, &response, &mut out);
        }
    }
    Ok(out)
}

fn scatter(
    dofs: &Dofs,
    pattern: Option<&Pattern>,
    (index, element): (usize, &[usize; 8]),
    response: &ElementOutput,
    out: &mut Evaluation,
) {
    let eqs = element_equations(dofs, element);
    out.energy_j += response.energy_j;
    for (eq, force) in eqs.iter().zip(&response.force_n) {
        if let Some(e) = eq {
            out.residual_n[*e] += force;
        }
    }
    let (Some(pattern), Some(values), Some(k)) =
        (pattern, out.tangent.as_mut(), response.stiffness.as_deref())
    else {
        return;
    };
    let entries = &pattern.entries[576 * index..576 * (index + 1)];
    for (row, positions) in k.iter().zip(entries.chunks_exact(24)) {
        for (value, &position) in row.iter().zip(positions) {
            if position != NOT_STORED {
                values[position as usize] += value;
            }
        }
    }
}
