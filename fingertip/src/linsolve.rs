//! Sparse symmetric LDL^T from faer: the symbolic analysis (AMD ordering, elimination tree,
//! supernodes) is done once per pattern and reused for every numeric factorisation.
//!
//! Two numeric precisions share that analysis. A double-precision factor solves exactly (the
//! haptic condensation needs that). A single-precision factor is only a preconditioner for
//! GMRES ([`crate::krylov`]), which restores double-precision accuracy in a few iterations:
//! it costs about half the time to build and to apply (half the bytes through memory, twice the
//! SIMD lanes), and a Newton solve never needed more than a preconditioner.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;
use std::thread::JoinHandle;

/// The call of [`Ldlt::adopt_background`] (one per Newton iteration) at which a background
/// factor is adopted: late enough that it has nearly always finished (a wait at the first call
/// made a compression a third slower), early enough to still be fresh.
const ADOPT_AFTER: usize = 2;

use crate::Error;

/// Which numeric factor is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// f64: an exact solver.
    Double,
    /// f32: a preconditioner.
    Single,
}

/// A symmetric (upper-stored) sparse matrix factoriser with a fixed pattern.
pub struct Ldlt {
    pattern: Arc<SymbolicSparseColMat<usize>>,
    symbolic: Arc<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    l_values_f32: Vec<f32>,
    /// The matrix values rounded to f32 (kept to avoid an allocation per factorisation).
    a_f32: Vec<f32>,
    /// Right-hand sides rounded to f32.
    rhs_f32: Vec<f32>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    par: Par,
    solve_par: Par,
    factored: Option<Precision>,
    /// A single-precision factorisation running on its own thread, and the buffers it will
    /// hand back.
    pending: Option<JoinHandle<Background>>,
    /// Calls of [`Ldlt::adopt_background`] since the pending factorisation started.
    pending_age: usize,
    spare: Option<Background>,
}

/// What a background factorisation owns: the matrix in f32, the factor, its workspace, and
/// whether it succeeded.
struct Background {
    a_f32: Vec<f32>,
    l_f32: Vec<f32>,
    mem: MemBuffer,
    ok: bool,
}

impl std::fmt::Debug for Ldlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ldlt")
            .field("n", &self.symbolic.nrows())
            .field("factor_nnz", &self.symbolic.len_val())
            .field("factored", &self.factored)
            .finish()
    }
}

/// Minimum rayon threads before the numeric factorisation runs in parallel.
const PARALLEL_FACTOR_MIN_THREADS: usize = 4;

/// Parallelism of the factorisation and of the single-column solves. faer splits the
/// elimination tree between threads; on the 2-core machine that cost more in synchronisation
/// (threads yielding and waking) than it gained: the 60 N curve's factorisations took
/// 1.58–1.67 s in parallel against 1.33–1.42 s sequentially, its solves 2.2–2.3 s against
/// 1.5–1.8 s, and the assembly beside them slowed from ~1.2 to ~1.8 s. One-column triangular
/// solves are memory-bound and stay sequential everywhere; the factorisation goes parallel
/// from `PARALLEL_FACTOR_MIN_THREADS` threads. `FINGERTIP_SEQ=1` forces sequential.
fn parallelism() -> (Par, Par) {
    let threads = rayon::current_num_threads();
    if std::env::var_os("FINGERTIP_SEQ").is_some() || threads < PARALLEL_FACTOR_MIN_THREADS {
        (Par::Seq, Par::Seq)
    } else {
        (Par::rayon(threads), Par::Seq)
    }
}

fn workspace(req: StackReq) -> Result<MemBuffer, Error> {
    MemBuffer::try_new(req).map_err(|e| Error::LinearSolver(format!("workspace: {e:?}")))
}

impl Ldlt {
    /// Analyse the pattern (upper triangle, CSC), with a fill-reducing ordering `perm`
    /// (new position -> old index) or AMD when `None`.
    pub fn new(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        perm: Option<&[usize]>,
    ) -> Result<Ldlt, Error> {
        let pattern =
            SymbolicSparseColMat::new_checked(n, n, col_ptr.to_vec(), None, row_idx.to_vec());
        let symbolic = match perm {
            Some(fwd) => {
                if fwd.len() != n {
                    return Err(Error::LinearSolver(format!(
                        "ordering has {} entries for {n} unknowns",
                        fwd.len()
                    )));
                }
                let mut inv = vec![0usize; n];
                for (new, &old) in fwd.iter().enumerate() {
                    inv[old] = new;
                }
                let p = PermRef::new_checked(fwd, &inv, n);
                factorize_symbolic_cholesky(
                    pattern.as_ref(),
                    Side::Upper,
                    SymmetricOrdering::Custom(p),
                    CholeskySymbolicParams::default(),
                )
            }
            None => factorize_symbolic_cholesky(
                pattern.as_ref(),
                Side::Upper,
                SymmetricOrdering::Amd,
                CholeskySymbolicParams::default(),
            ),
        }
        .map_err(|e| Error::LinearSolver(format!("symbolic analysis: {e:?}")))?;
        let (par, solve_par) = parallelism();
        let factor_mem = workspace(
            symbolic
                .factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
                .or(symbolic.factorize_numeric_ldlt_scratch::<f32>(par, Default::default())),
        )?;
        let solve_mem = workspace(
            symbolic
                .solve_in_place_scratch::<f64>(64, par)
                .or(symbolic.solve_in_place_scratch::<f32>(1, solve_par)),
        )?;
        Ok(Ldlt {
            pattern: Arc::new(pattern),
            symbolic: Arc::new(symbolic),
            l_values: Vec::new(),
            l_values_f32: Vec::new(),
            a_f32: Vec::new(),
            rhs_f32: Vec::new(),
            factor_mem,
            solve_mem,
            par,
            solve_par,
            factored: None,
            pending: None,
            pending_age: 0,
            spare: None,
        })
    }

    /// Double-precision numeric factorisation of the matrix with these values in the
    /// analysed pattern.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), Error> {
        self.discard_background();
        self.factored = None;
        self.l_values.resize(self.symbolic.len_val(), 0.0);
        let a = SparseColMatRef::new((*self.pattern).as_ref(), values);
        self.symbolic
            .factorize_numeric_ldlt(
                &mut self.l_values,
                a,
                Side::Upper,
                LdltRegularization::default(),
                self.par,
                MemStack::new(&mut self.factor_mem),
                Default::default(),
            )
            .map_err(|e| Error::LinearSolver(format!("LDLT: {e:?}")))?;
        self.factored = Some(Precision::Double);
        Ok(())
    }

    /// Single-precision numeric factorisation (a preconditioner, see the module notes).
    pub fn factorize_single(&mut self, values: &[f64]) -> Result<(), Error> {
        self.discard_background();
        self.factored = None;
        self.l_values_f32.resize(self.symbolic.len_val(), 0.0);
        self.a_f32.clear();
        self.a_f32.extend(values.iter().map(|&v| v as f32));
        let a = SparseColMatRef::new((*self.pattern).as_ref(), &self.a_f32[..]);
        self.symbolic
            .factorize_numeric_ldlt(
                &mut self.l_values_f32,
                a,
                Side::Upper,
                LdltRegularization::default(),
                self.par,
                MemStack::new(&mut self.factor_mem),
                Default::default(),
            )
            .map_err(|e| Error::LinearSolver(format!("LDLT (f32): {e:?}")))?;
        self.factored = Some(Precision::Single);
        Ok(())
    }

    /// Start a single-precision factorisation of these values on a thread of its own, unless
    /// one is running; the held factor stays in use until [`Ldlt::adopt_background`] swaps
    /// the new one in at the next Newton iteration. Why: the factorisation and the one-column
    /// solves are sequential, so on two cores the second core idles through them; a refreshed
    /// preconditioner a Newton iteration late costs a GMRES iteration or two, far less than
    /// factoring it in the foreground.
    pub fn factorize_single_in_background(&mut self, values: &[f64]) -> Result<(), Error> {
        if self.pending.is_some() {
            return Ok(());
        }
        let mut job = match self.spare.take() {
            Some(b) => b,
            None => Background {
                a_f32: Vec::new(),
                l_f32: Vec::new(),
                mem: workspace(
                    self.symbolic
                        .factorize_numeric_ldlt_scratch::<f32>(Par::Seq, Default::default()),
                )?,
                ok: false,
            },
        };
        job.a_f32.clear();
        job.a_f32.extend(values.iter().map(|&v| v as f32));
        job.l_f32.resize(self.symbolic.len_val(), 0.0);
        let (pattern, symbolic) = (Arc::clone(&self.pattern), Arc::clone(&self.symbolic));
        self.pending_age = 0;
        self.pending = Some(std::thread::spawn(move || {
            let a = SparseColMatRef::new((*pattern).as_ref(), &job.a_f32[..]);
            job.ok = symbolic
                .factorize_numeric_ldlt(
                    &mut job.l_f32,
                    a,
                    Side::Upper,
                    LdltRegularization::default(),
                    Par::Seq,
                    MemStack::new(&mut job.mem),
                    Default::default(),
                )
                .is_ok();
            job
        }));
        Ok(())
    }

    /// Make a background factorisation the held factor at the second call since
    /// it started, waiting for it if it is still running. Returns whether a new factor was
    /// adopted. A fixed call keeps a solve's sequence of preconditioners, and so its Newton
    /// iterations, the same from run to run: adopted "if finished", it depended on the
    /// machine's load, and a 58.6 N step that converged on one run did not on another.
    pub fn adopt_background(&mut self) -> bool {
        if self.pending.is_none() {
            return false;
        }
        self.pending_age += 1;
        if self.pending_age < ADOPT_AFTER {
            return false;
        }
        let Some(Ok(mut job)) = self.pending.take().map(JoinHandle::join) else {
            return false;
        };
        let adopted = job.ok;
        if adopted {
            std::mem::swap(&mut self.l_values_f32, &mut job.l_f32);
            self.factored = Some(Precision::Single);
        }
        self.spare = Some(job);
        adopted
    }

    /// Wait for a running background factorisation and drop its result.
    fn discard_background(&mut self) {
        if let Some(Ok(job)) = self.pending.take().map(JoinHandle::join) {
            self.spare = Some(job);
        }
    }

    /// Solve A X = B in place for the columns of `rhs` (column-major, `n x k`) with the held
    /// factor: exactly with a double factor, approximately with a single one.
    pub fn solve_in_place(&mut self, rhs: &mut [f64], k: usize) {
        let n = self.symbolic.nrows();
        match self.factored {
            Some(Precision::Double) => {
                let ldlt = LdltRef::<'_, usize, f64>::new(&self.symbolic, &self.l_values);
                for chunk in rhs.chunks_mut(n * 64).take(k.div_ceil(64)) {
                    let cols = chunk.len() / n;
                    let m = MatMut::from_column_major_slice_mut(chunk, n, cols);
                    ldlt.solve_in_place_with_conj(
                        Conj::No,
                        m,
                        self.par,
                        MemStack::new(&mut self.solve_mem),
                    );
                }
            }
            Some(Precision::Single) => {
                let ldlt = LdltRef::<'_, usize, f32>::new(&self.symbolic, &self.l_values_f32);
                for col in rhs.chunks_mut(n).take(k) {
                    self.rhs_f32.clear();
                    self.rhs_f32.extend(col.iter().map(|&v| v as f32));
                    let m = MatMut::from_column_major_slice_mut(&mut self.rhs_f32[..], n, 1);
                    ldlt.solve_in_place_with_conj(
                        Conj::No,
                        m,
                        self.solve_par,
                        MemStack::new(&mut self.solve_mem),
                    );
                    col.iter_mut()
                        .zip(&self.rhs_f32)
                        .for_each(|(c, &v)| *c = v as f64);
                }
            }
            None => panic!("solve before factorize"),
        }
    }

    /// Whether a numeric factorisation is available.
    pub fn is_factored(&self) -> bool {
        self.factored.is_some()
    }

    /// The precision of the held factor.
    pub fn precision(&self) -> Option<Precision> {
        self.factored
    }

    /// Number of stored entries of the factor.
    pub fn factor_nnz(&self) -> usize {
        self.symbolic.len_val()
    }
}

/// A fill-reducing ordering of the dofs from AMD on the graph of their owners (nodes):
/// `owner[d]` is the node of dof d. Every node's dofs stay together, in their given order.
pub fn blocked_amd(
    col_ptr: &[usize],
    row_idx: &[usize],
    owner: &[usize],
    n_owners: usize,
) -> Result<Vec<usize>, Error> {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n_owners];
    for c in 0..owner.len() {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            let (a, b) = (owner[r].min(owner[c]), owner[r].max(owner[c]));
            adj[b].push(a);
        }
    }
    let mut cp = vec![0usize];
    let mut ri = Vec::new();
    for list in &mut adj {
        list.sort_unstable();
        list.dedup();
        ri.extend_from_slice(list);
        cp.push(ri.len());
    }
    let nnz = ri.len();
    let graph = SymbolicSparseColMat::new_checked(n_owners, n_owners, cp, None, ri);
    let (mut perm, mut inv) = (vec![0usize; n_owners], vec![0usize; n_owners]);
    let mut mem = workspace(faer::sparse::linalg::amd::order_scratch::<usize>(
        n_owners, nnz,
    ))?;
    faer::sparse::linalg::amd::order(
        &mut perm,
        &mut inv,
        graph.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| Error::LinearSolver(format!("AMD: {e:?}")))?;
    let mut dofs_of: Vec<Vec<usize>> = vec![Vec::new(); n_owners];
    for (d, &o) in owner.iter().enumerate() {
        dofs_of[o].push(d);
    }
    Ok(perm
        .iter()
        .flat_map(|&o| dofs_of[o].iter().copied())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quasi-definite 3x3 (SPD block, negative pressure-like diagonal), upper CSC.
    const COL_PTR: [usize; 4] = [0, 1, 3, 6];
    const ROW_IDX: [usize; 6] = [0, 0, 1, 0, 1, 2];
    const VALS: [f64; 6] = [4.0, 1.0, 3.0, 1.0, 1.0, -0.5];
    const A: [[f64; 3]; 3] = [[4.0, 1.0, 1.0], [1.0, 3.0, 1.0], [1.0, 1.0, -0.5]];

    /// The held factor solves A x = b for a known x to within `tol`.
    fn assert_solves(s: &mut Ldlt, tol: f64) {
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| A[i][j] * x[j]).sum())
            .collect();
        s.solve_in_place(&mut b, 1);
        for i in 0..3 {
            assert!(
                (b[i] - x[i]).abs() < tol,
                "x[{i}] = {} against {}",
                b[i],
                x[i]
            );
        }
    }

    /// The double factor solves the quasi-definite system exactly, the single one to f32
    /// accuracy.
    #[test]
    fn solves_a_quasi_definite_system() {
        let mut s = Ldlt::new(3, &COL_PTR, &ROW_IDX, None).unwrap();
        s.factorize(&VALS).unwrap();
        assert_solves(&mut s, 1e-12);
        s.factorize_single(&VALS).unwrap();
        assert_solves(&mut s, 1e-6);
    }

    /// The node-blocked ordering is a permutation that keeps each node's dofs together.
    #[test]
    fn blocked_amd_keeps_each_nodes_dofs_together() {
        // A path of 4 nodes with 2 dofs each (dof 2k, 2k+1 on node k), upper CSC.
        let owner = [0, 0, 1, 1, 2, 2, 3, 3];
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        for c in 0..8 {
            for r in 0..=c {
                if (owner[r] as i64 - owner[c] as i64).abs() <= 1 {
                    row_idx.push(r);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let perm = blocked_amd(&col_ptr, &row_idx, &owner, 4).unwrap();
        let mut seen = perm.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..8).collect::<Vec<_>>());
        for pair in perm.chunks(2) {
            assert_eq!(owner[pair[0]], owner[pair[1]]);
            assert!(pair[0] < pair[1]);
        }
    }

    /// A factor built in the background is adopted (waited for) and then solves like one
    /// built in the foreground.
    #[test]
    fn background_factor_is_adopted_and_solves() {
        let mut s = Ldlt::new(3, &COL_PTR, &ROW_IDX, None).unwrap();
        s.factorize_single(&[1.0, 0.0, 1.0, 0.0, 0.0, -1.0])
            .unwrap();
        s.factorize_single_in_background(&VALS).unwrap();
        let calls: Vec<bool> = (0..ADOPT_AFTER).map(|_| s.adopt_background()).collect();
        assert_eq!(calls.iter().filter(|&&a| a).count(), 1, "{calls:?}");
        assert!(calls[ADOPT_AFTER - 1], "adopted at its call: {calls:?}");
        assert_solves(&mut s, 1e-6);
        assert!(!s.adopt_background(), "nothing left to adopt");
    }
}
