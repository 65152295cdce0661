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
//!
//! A factorisation outlives its matrix: [`LinearSolver::solve_preconditioned`]
//! solves a later matrix on the same pattern (the next Newton iteration's
//! tangent, with another contact set) by conjugate gradients preconditioned
//! with the last Cholesky factor. The two matrices differ by the change of
//! the tangent over a Newton step and by the rows of the nodes that entered
//! or left contact, a perturbation of low rank, so a few iterations, each a
//! pair of triangular solves and a sparse product (a twentieth of a
//! factorisation on a 48² × 8 block), replace a numeric factorisation
//! (Knoll & Keyes, J. Comput. Phys. 193, 2004, § 3: a frozen or "lagged"
//! factorisation as the Newton–Krylov preconditioner).

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

/// The controls of [`LinearSolver::solve_preconditioned`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Krylov {
    /// Converged when ‖b − A x‖₂ ≤ this × ‖b‖₂.
    pub tolerance: f64,
    /// Iterations before the solve gives up (the caller then factorises).
    pub max_iterations: usize,
}

/// Why [`LinearSolver::solve_preconditioned`] gave up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KrylovStop {
    /// No Cholesky factor to precondition with.
    NoFactor,
    /// A direction of non-positive curvature (the matrix is not positive
    /// definite there).
    Indefinite,
    /// Not converged in the iterations allowed.
    Slow,
}

/// A sparse symmetric solver bound to one pattern.
pub struct LinearSolver {
    /// The pattern with 32-bit indices, as the factor's symbolic structure:
    /// half the memory of machine words for the same speed.
    upper: SymbolicSparseColMat<u32>,
    symbolic: SymbolicCholesky<u32>,
    factor_values: Vec<f64>,
    kind: Factorization,
    /// Whether a numeric factorisation is held.
    factored: bool,
    full: Option<FullMatrix>,
    lu: Option<Lu<usize, f64>>,
    /// Work space of the numeric factorisations and solves, allocated once:
    /// a fresh one per Newton iteration cost its allocation and page faults
    /// every time.
    scratch: MemBuffer,
    /// Its size, bytes.
    scratch_bytes: usize,
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
        let narrow = |values: &[usize]| -> Result<Vec<u32>, FemError> {
            values
                .iter()
                .map(|&v| u32::try_from(v))
                .collect::<Result<_, _>>()
                .map_err(|_| {
                    FemError::Solver(format!(
                        "{} stored tangent entries exceed the solver's 32-bit indices",
                        pattern.row_idx.len()
                    ))
                })
        };
        let upper = SymbolicSparseColMat::new_checked(
            n,
            n,
            narrow(&pattern.col_ptr)?,
            None,
            narrow(&pattern.row_idx)?,
        );
        let forward = order.map(narrow).transpose()?;
        let inverse = forward.as_ref().map(|forward| {
            let mut inverse = vec![0_u32; forward.len()];
            for (k, &e) in (0_u32..).zip(forward) {
                inverse[e as usize] = k;
            }
            inverse
        });
        let ordering = match (&forward, &inverse) {
            (Some(forward), Some(inverse)) if forward.len() == n => {
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, n))
            }
            _ => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(upper.as_ref(), Side::Upper, ordering, Default::default())
                .map_err(|e| solver_error("symbolic Cholesky", e))?;
        let par = Par::Seq;
        let scratch_req = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()))
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(Self {
            scratch_bytes: scratch_req.size_bytes(),
            scratch: MemBuffer::new(scratch_req),
            factor_values: vec![0.0; symbolic.len_val()],
            upper,
            symbolic,
            kind: Factorization::Cholesky,
            factored: false,
            full: None,
            lu: None,
        })
    }

    /// Stored values of the Cholesky factor (fill included).
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The memory a Cholesky factorisation holds: the factor's values and
    /// the work space of the factorisation, bytes (the index structures,
    /// 4 bytes per stored entry of the pattern, aside; an LU fallback, for
    /// an indefinite tangent, needs more).
    pub fn factor_bytes(&self) -> usize {
        8 * self.factor_len() + self.scratch_bytes
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
        self.factored = true;
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

impl LinearSolver {
    /// Solves `values` · x = `rhs` in place by conjugate gradients
    /// preconditioned with the last factorisation (which must be a Cholesky
    /// factor: an indefinite preconditioner breaks the method), from x = 0;
    /// returns the iterations. On failure `rhs` is left as it was.
    /// Every sum runs in index order: the same bits on any thread pool.
    pub fn solve_preconditioned(
        &mut self,
        values: &[f64],
        rhs: &mut [f64],
        control: Krylov,
    ) -> Result<usize, KrylovStop> {
        if control.max_iterations == 0 {
            return Err(KrylovStop::Slow);
        }
        if self.kind != Factorization::Cholesky || !self.factored {
            return Err(KrylovStop::NoFactor);
        }
        let n = rhs.len();
        let goal = control.tolerance * dot(rhs, rhs).sqrt();
        let mut x = vec![0.0; n];
        let mut r = rhs.to_vec();
        let mut z = r.clone();
        self.solve(&mut z);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let mut q = vec![0.0; n];
        for iteration in 1..=control.max_iterations {
            symmetric_product(self.upper.as_ref(), values, &p, &mut q);
            let curvature = dot(&p, &q);
            // NaN counts as indefinite too.
            if curvature.is_nan() || curvature <= 0.0 {
                return Err(KrylovStop::Indefinite);
            }
            let alpha = rz / curvature;
            for ((xi, ri), (pi, qi)) in x.iter_mut().zip(&mut r).zip(p.iter().zip(&q)) {
                *xi += alpha * pi;
                *ri -= alpha * qi;
            }
            if dot(&r, &r).sqrt() <= goal {
                rhs.copy_from_slice(&x);
                return Ok(iteration);
            }
            z.copy_from_slice(&r);
            self.solve(&mut z);
            let rz_next = dot(&r, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            for (pi, zi) in p.iter_mut().zip(&z) {
                *pi = zi + beta * *pi;
            }
        }
        Err(KrylovStop::Slow)
    }
}

/// Σ a_i b_i in index order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// y = A x for the symmetric A whose upper triangle (with the diagonal) is
/// `values` on `upper`, in column order.
fn symmetric_product(
    upper: SymbolicSparseColMatRef<'_, u32>,
    values: &[f64],
    x: &[f64],
    y: &mut [f64],
) {
    y.fill(0.0);
    for (col, &x_col) in x.iter().enumerate() {
        let range = upper.col_range(col);
        let mut below = 0.0;
        for (value, &row) in values[range.clone()].iter().zip(&upper.row_idx()[range]) {
            let row = row as usize;
            y[row] += value * x_col;
            if row != col {
                below += value * x[row];
            }
        }
        y[col] += below;
    }
}

impl FullMatrix {
    /// Mirrors the upper pattern to both triangles.
    fn new(upper: SymbolicSparseColMatRef<'_, u32>) -> Result<Self, FemError> {
        let n = upper.ncols();
        let mut columns: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for col in 0..n {
            let range = upper.col_range(col);
            for (offset, &row) in upper.row_idx()[range.clone()].iter().enumerate() {
                let (k, row) = (range.start + offset, row as usize);
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

    /// The upper triangle of a dense symmetric matrix as CSC: its pattern
    /// and values.
    fn upper_csc(a: &[Vec<f64>]) -> (Pattern, Vec<f64>) {
        let n = a.len();
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for (c, column) in a.iter().enumerate() {
            for (r, value) in column.iter().enumerate().take(c + 1) {
                row_idx.push(r);
                values.push(*value);
            }
            col_ptr.push(row_idx.len());
        }
        (Pattern::from_csc(n, col_ptr, row_idx), values)
    }

    /// A matrix factorised, then changed by a rank-two term: conjugate
    /// gradients preconditioned with the old factor solve the new matrix to
    /// the tolerance in at most rank + 1 iterations (exact arithmetic would
    /// take rank + 1; Saad, Iterative Methods for Sparse Linear Systems,
    /// § 6.11), and the answer is that of a fresh factorisation.
    #[test]
    fn kept_factor_preconditions_a_low_rank_change() {
        let n = 30;
        // A 1-D Laplacian plus a diagonal: SPD and not trivially scaled.
        let entry = |r: usize, c: usize| match r.abs_diff(c) {
            0 => 2.5 + 0.1 * r as f64,
            1 => -1.0,
            _ => 0.0,
        };
        let a: Vec<Vec<f64>> = (0..n)
            .map(|c| (0..n).map(|r| entry(r, c)).collect())
            .collect();
        let u: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
        let v: Vec<f64> = (0..n).map(|k| (k as f64 * 0.11).cos()).collect();
        let changed: Vec<Vec<f64>> = (0..n)
            .map(|c| {
                (0..n)
                    .map(|r| a[c][r] + 3.0 * u[r] * u[c] + v[r] * v[c])
                    .collect()
            })
            .collect();
        let (pattern, old) = upper_csc(&a);
        let (_, new) = upper_csc(&changed);
        let mut solver = LinearSolver::new(&pattern, None).unwrap();
        let rhs: Vec<f64> = (0..n).map(|k| 1.0 + (k % 3) as f64).collect();
        let control = Krylov {
            tolerance: 1e-12,
            max_iterations: 10,
        };
        let mut x = rhs.clone();
        assert_eq!(
            solver.solve_preconditioned(&new, &mut x, control),
            Err(KrylovStop::NoFactor)
        );
        solver.factor(&old).unwrap();
        let iterations = solver.solve_preconditioned(&new, &mut x, control).unwrap();
        assert!(iterations <= 3, "{iterations} iterations");
        solver.factor(&new).unwrap();
        let mut exact = rhs.clone();
        solver.solve(&mut exact);
        for (got, want) in x.iter().zip(&exact) {
            assert!(
                (got - want).abs() < 1e-10 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
        // An indefinite matrix is refused, the right-hand side kept.
        let indefinite: Vec<f64> = new.iter().map(|v| -v).collect();
        let mut y = rhs.clone();
        assert_eq!(
            solver.solve_preconditioned(&indefinite, &mut y, control),
            Err(KrylovStop::Indefinite)
        );
        assert_eq!(y, rhs);
    }

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
