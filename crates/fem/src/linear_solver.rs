//! The Newton systems' sparse direct solver: faer's supernodal Cholesky
//! LLᵀ on the upper triangle with an approximate-minimum-degree ordering,
//! its symbolic analysis computed once per pattern and reused for every
//! numeric factorisation. The condensed tangent with the boundary
//! conditions is symmetric, and positive definite wherever the material is
//! stable; where it is not (an Ogden law past its Drucker limit, a state far
//! from equilibrium) LLᵀ fails and the same symbolic analysis serves an
//! LDLᵀ factorisation, and if that meets a zero pivot, a sparse LU with
//! partial pivoting of the full matrix takes over.
//!
//! All factorisations run on one thread (`Par::Seq`): their results are
//! then the same bits whatever the thread pool, and the parallel work is
//! the element loop.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::SolveCore;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::FemError;
use crate::assembly::Pattern;

/// Which factorisation the last [`LinearSolver::factor`] produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factorization {
    Cholesky,
    Ldlt,
    Lu,
}

/// A sparse symmetric solver bound to one pattern.
pub struct LinearSolver {
    upper: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    factor_values: Vec<f64>,
    kind: Factorization,
    full: Option<FullMatrix>,
    lu: Option<Lu<usize, f64>>,
    /// Work space of the numeric factorisations and solves, allocated once:
    /// a fresh one per Newton iteration cost its allocation and page faults
    /// every time.
    scratch: MemBuffer,
}

/// The full (both triangles) pattern for LU, with the source of each value
/// in the upper triangle.
struct FullMatrix {
    pattern: SymbolicSparseColMat<usize>,
    source: Vec<usize>,
    symbolic: SymbolicLu<usize>,
}

fn solver_error(what: &str, e: impl std::fmt::Debug) -> FemError {
    FemError::Solver(format!("{what}: {e:?}"))
}

impl LinearSolver {
    /// The symbolic analysis of `pattern`, in the elimination `order`
    /// (`order[k]` eliminated k-th; e.g. [`crate::ordering`]) or, without
    /// one, approximate minimum degree.
    pub fn new(pattern: &Pattern, order: Option<&[usize]>) -> Result<Self, FemError> {
        let n = pattern.size;
        let upper = SymbolicSparseColMat::new_checked(
            n,
            n,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let inverse = order.map(|forward| {
            let mut inverse = vec![0; forward.len()];
            for (k, &e) in forward.iter().enumerate() {
                inverse[e] = k;
            }
            inverse
        });
        let ordering = match (order, &inverse) {
            (Some(forward), Some(inverse)) if forward.len() == n => {
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, n))
            }
            _ => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(upper.as_ref(), Side::Upper, ordering, Default::default())
                .map_err(|e| solver_error("symbolic Cholesky", e))?;
        let par = Par::Seq;
        let scratch = MemBuffer::new(
            symbolic
                .factorize_numeric_llt_scratch::<f64>(par, Default::default())
                .or(symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()))
                .or(symbolic.solve_in_place_scratch::<f64>(1, par)),
        );
        Ok(Self {
            scratch,
            factor_values: vec![0.0; symbolic.len_val()],
            upper,
            symbolic,
            kind: Factorization::Cholesky,
            full: None,
            lu: None,
        })
    }

    /// Stored values of the Cholesky factor (fill included).
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Factorises the matrix with `values` on the pattern.
    pub fn factor(&mut self, values: &[f64]) -> Result<Factorization, FemError> {
        let matrix = SparseColMatRef::new(self.upper.as_ref(), values);
        let par = Par::Seq;
        let stack = MemStack::new(&mut self.scratch);
        let llt = self.symbolic.factorize_numeric_llt(
            &mut self.factor_values,
            matrix,
            Side::Upper,
            LltRegularization::default(),
            par,
            stack,
            Default::default(),
        );
        if llt.is_ok() {
            self.kind = Factorization::Cholesky;
            return Ok(self.kind);
        }
        let ldlt = self.symbolic.factorize_numeric_ldlt(
            &mut self.factor_values,
            matrix,
            Side::Upper,
            LdltRegularization::default(),
            par,
            stack,
            Default::default(),
        );
        if ldlt.is_ok() && self.factor_values.iter().all(|v| v.is_finite()) {
            self.kind = Factorization::Ldlt;
            return Ok(self.kind);
        }
        self.factor_lu(values)?;
        self.kind = Factorization::Lu;
        Ok(self.kind)
    }

    fn factor_lu(&mut self, values: &[f64]) -> Result<(), FemError> {
        if self.full.is_none() {
            self.full = Some(FullMatrix::new(self.upper.as_ref())?);
        }
        let full = self
            .full
            .as_ref()
            .ok_or_else(|| FemError::Solver("no LU pattern".into()))?;
        let full_values: Vec<f64> = full.source.iter().map(|&k| values[k]).collect();
        let matrix = SparseColMatRef::new(full.pattern.as_ref(), &full_values);
        self.lu = Some(
            Lu::try_new_with_symbolic(full.symbolic.clone(), matrix)
                .map_err(|e| solver_error("sparse LU", e))?,
        );
        Ok(())
    }

    /// Solves in place with the last factorisation.
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let par = Par::Seq;
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match self.kind {
            Factorization::Lu => {
                if let Some(lu) = &self.lu {
                    lu.solve_in_place_with_conj(Conj::No, rhs);
                }
            }
            kind => {
                let stack = MemStack::new(&mut self.scratch);
                if kind == Factorization::Cholesky {
                    LltRef::new(&self.symbolic, &self.factor_values).solve_in_place_with_conj(
                        Conj::No,
                        rhs,
                        par,
                        stack,
                    );
                } else {
                    LdltRef::new(&self.symbolic, &self.factor_values).solve_in_place_with_conj(
                        Conj::No,
                        rhs,
                        par,
                        stack,
                    );
                }
            }
        }
    }
}

impl FullMatrix {
    /// Mirrors the upper pattern to both triangles.
    fn new(upper: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, FemError> {
        let n = upper.ncols();
        let mut columns: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for col in 0..n {
            let range = upper.col_range(col);
            for (offset, &row) in upper.row_idx()[range.clone()].iter().enumerate() {
                let k = range.start + offset;
                columns[col].push((row, k));
                if row != col {
                    columns[row].push((col, k));
                }
            }
        }
        let mut col_ptr = vec![0];
        let (mut row_idx, mut source) = (Vec::new(), Vec::new());
        for column in &mut columns {
            column.sort_unstable();
            for &(row, k) in column.iter() {
                row_idx.push(row);
                source.push(k);
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic =
            SymbolicLu::try_new(pattern.as_ref()).map_err(|e| solver_error("symbolic LU", e))?;
        Ok(Self {
            pattern,
            source,
            symbolic,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1-D Laplacian (SPD) and an indefinite matrix on one pattern:
    /// both solved to round-off, the second by a fallback.
    #[test]
    fn solves_definite_and_indefinite_systems() {
        let n = 6;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for c in 0..n {
            if c > 0 {
                row_idx.push(c - 1);
            }
            row_idx.push(c);
            col_ptr.push(row_idx.len());
        }
        let pattern = Pattern::from_csc(n, col_ptr.clone(), row_idx.clone());
        let mut solver = LinearSolver::new(&pattern, None).unwrap();
        let diagonal_of = |c: usize, d: f64| if c.is_multiple_of(2) { d } else { -d };
        for (definite, expected) in [
            (true, Factorization::Cholesky),
            (false, Factorization::Ldlt),
        ] {
            let values: Vec<f64> = (0..n)
                .flat_map(|c| {
                    let d = if definite { 2.0 } else { diagonal_of(c, 3.0) };
                    if c > 0 { vec![-1.0, d] } else { vec![d] }
                })
                .collect();
            assert_eq!(solver.factor(&values).unwrap(), expected);
            let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
            // b = A x with A symmetric from its upper triangle.
            let mut b = vec![0.0; n];
            for c in 0..n {
                for k in col_ptr[c]..col_ptr[c + 1] {
                    let r = row_idx[k];
                    b[r] += values[k] * x[c];
                    if r != c {
                        b[c] += values[k] * x[r];
                    }
                }
            }
            solver.solve(&mut b);
            for (got, want) in b.iter().zip(&x) {
                assert!((got - want).abs() < 1e-12, "{got} vs {want}");
            }
        }
        // A zero leading pivot defeats LDLᵀ without pivoting: LU solves it.
        let mut values = vec![0.0; row_idx.len()];
        for c in 0..n {
            values[col_ptr[c + 1] - 1] = if c == 0 { 0.0 } else { 1.0 };
            if c > 0 {
                values[col_ptr[c]] = 1.0;
            }
        }
        let kind = solver.factor(&values).unwrap();
        let mut b = vec![1.0; n];
        solver.solve(&mut b);
        let mut check = vec![0.0; n];
        for c in 0..n {
            for k in col_ptr[c]..col_ptr[c + 1] {
                let r = row_idx[k];
                check[r] += values[k] * b[c];
                if r != c {
                    check[c] += values[k] * b[r];
                }
            }
        }
        assert!(
            check.iter().all(|v| (v - 1.0).abs() < 1e-12),
            "{kind:?}: {check:?}"
        );
    }
}
