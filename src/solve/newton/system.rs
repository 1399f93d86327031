//! The problem as the Newton iteration sees it (W by block rows, b, each contact's law and
//! row scales), F and its generalized Jacobian at a point, and the Newton system's solution
//! (dense LU, or faer's sparse LU above [`super::DENSE_ROWS`] rows).

use super::*;

/// W x, block row by block row.
pub(super) fn apply_w<const R: usize>(
    problem: &LocalProblem<R>,
    x: &DVector<f64>,
    out: &mut DVector<f64>,
) {
    for (k, c) in problem.contacts.iter().enumerate() {
        let mut sum = SVector::<f64, R>::zeros();
        for (j, w) in &c.row {
            sum += w * x.fixed_rows::<R>(R * j);
        }
        out.fixed_rows_mut::<R>(R * k).copy_from(&sum);
    }
}

/// The problem as the Newton iteration sees it.
pub(super) struct System<'a, const R: usize> {
    /// W (compliance included), q, μ and bounds.
    pub(super) problem: &'a LocalProblem<R>,
    pub(super) b: DVector<f64>,
    pub(super) laws: Vec<Law>,
    /// Row scales a_r = W_rr (1 where W_rr is zero or round-off, at most
    /// [`crate::solve::residual::ROUND_OFF_DIAGONAL`] times W's largest diagonal entry: a row
    /// no impulse of its own can move).
    pub(super) scales: DVector<f64>,
    /// Rows up to which the Newton system is factorised densely.
    pub(super) dense_rows: usize,
    /// Above `dense_rows`: the Newton matrix's sparsity pattern and its symbolic LU, computed
    /// once per solve (every iteration's matrix has W's block pattern; only the values change),
    /// with the buffers every numeric factorisation reuses.
    pub(super) sparse: Option<SparseLayout>,
    /// The plain runs' regularisation ([`super::NewtonSettings::regularisation`]).
    pub(super) regularisation: Option<super::Regularisation>,
}

/// The Newton matrix's pattern (every entry of every block W_kj, zeros included, so that it
/// never changes) and its symbolic LU factorisation, reused by every numeric factorisation,
/// with the buffers each factorisation writes into (allocated once per solve).
pub(super) struct SparseLayout {
    lu: faer::sparse::linalg::lu::SymbolicLu<usize>,
    /// Where entry e of the block order (block by block, row-major, as [`System::block_rows`]
    /// gives them) sits among the compressed columns' values.
    position: Vec<usize>,
    numeric: std::cell::RefCell<SparseBuffers>,
}

/// What one numeric factorisation and solve write: the matrix's values, the LU factors, the
/// right-hand side and faer's scratch memory.
struct SparseBuffers {
    matrix: faer::sparse::SparseColMat<usize, f64>,
    lu: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    rhs: faer::Mat<f64>,
    scratch: faer::dyn_stack::MemBuffer,
}

impl SparseLayout {
    fn of<const R: usize>(problem: &LocalProblem<R>) -> Option<Self> {
        use faer::sparse::linalg::lu::{LuSymbolicParams, NumericLu, factorize_symbolic_lu};
        use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
        let n = R * problem.contacts.len();
        let mut indices = Vec::new();
        for (k, c) in problem.contacts.iter().enumerate() {
            for (j, _) in &c.row {
                for r in 0..R {
                    for s in 0..R {
                        indices.push(Pair::new(R * k + r, R * j + s));
                    }
                }
            }
        }
        let (pattern, order) = SymbolicSparseColMat::try_new_from_indices(n, n, &indices).ok()?;
        // Each entry's own index as its value (exact in f64): the compressed matrix then says
        // where each entry went.
        let numbered: Vec<f64> = (0..indices.len()).map(|e| e as f64).collect();
        let matrix = SparseColMat::new_from_argsort(pattern, &order, &numbered).ok()?;
        let mut position = vec![0; indices.len()];
        for (at, &e) in matrix.val().iter().enumerate() {
            position[e as usize] = at;
        }
        let lu = factorize_symbolic_lu(matrix.symbolic(), LuSymbolicParams::default()).ok()?;
        let par = faer::Par::Seq;
        let scratch = faer::dyn_stack::MemBuffer::try_new(
            lu.factorize_numeric_lu_scratch::<f64>(par, Default::default())
                .or(lu.solve_in_place_scratch::<f64>(1, par)),
        )
        .ok()?;
        let numeric = SparseBuffers {
            matrix,
            lu: NumericLu::new(),
            rhs: faer::Mat::zeros(n, 1),
            scratch,
        };
        Some(SparseLayout {
            lu,
            position,
            numeric: std::cell::RefCell::new(numeric),
        })
    }
}

impl<'a, const R: usize> System<'a, R> {
    /// max_r |b_r| (m/s), 1 where b is zero: the velocity scale that makes the law norm relative
    /// (the proximal parameter's and the regularisation's; docs/contact.md §"Proximal-point
    /// globalisation" and §"Newton solver", **Regularisation following ‖F‖**).
    pub(super) fn velocity_scale(&self) -> f64 {
        match self.b.amax() {
            s if s > 0.0 => s,
            _ => 1.0,
        }
    }

    pub(super) fn of(problem: &'a LocalProblem<R>, dense_rows: usize) -> Self {
        let n = R * problem.contacts.len();
        let floor = crate::solve::residual::diagonal_floor(problem);
        let mut scales = DVector::zeros(n);
        let mut laws = Vec::with_capacity(problem.contacts.len());
        for (k, c) in problem.contacts.iter().enumerate() {
            let block = problem.diagonal_block(k);
            for r in 0..R {
                let d = block[(r, r)];
                scales[R * k + r] = if d > floor { d } else { 1.0 };
            }
            laws.push(match (c.bounds, problem.friction) {
                (RowBounds::Free, _) => Law::Free,
                (RowBounds::Contact, FrictionModel::Cone) if R == 3 => Law::Disk {
                    mu: c.mu,
                    rho: tangent_scale(&((block + block.transpose()) * 0.5), floor),
                },
                (RowBounds::Contact, _) => Law::Box { mu: c.mu },
            });
        }
        System {
            problem,
            b: problem.dense_q(),
            laws,
            scales,
            dense_rows,
            sparse: if n > dense_rows {
                SparseLayout::of(problem)
            } else {
                None
            },
            regularisation: None,
        }
    }

    pub(super) fn rows(&self) -> usize {
        self.b.len()
    }

    /// The block rows of W.
    pub(super) fn block_rows(
        &self,
    ) -> impl Iterator<Item = &'a [(usize, SMatrix<f64, R, R>)]> + 'a {
        let problem: &'a LocalProblem<R> = self.problem;
        problem.contacts.iter().map(|c| c.row.as_slice())
    }
}

/// A proximal term H (λ − λ_c) added to w, H = η diag(W) (kg⁻¹ per row): the subproblem
/// with W + H and b − H λ_c. Its rows are scaled by W + H's diagonal.
pub(super) struct Proximal<'a> {
    pub(super) eta: f64,
    pub(super) centre: &'a DVector<f64>,
}

/// F at λ (with the proximal term, when given) and the blocks of its generalized Jacobian.
pub(super) fn evaluate<const R: usize>(
    system: &System<R>,
    lambda: &DVector<f64>,
    proximal: Option<&Proximal>,
    w: &mut DVector<f64>,
    f: &mut DVector<f64>,
    blocks: &mut Vec<(SMatrix<f64, R, R>, SMatrix<f64, R, R>)>,
) {
    apply_w(system.problem, lambda, w);
    *w += &system.b;
    let eta = proximal.map_or(0.0, |p| p.eta);
    if let Some(p) = proximal {
        for i in 0..w.len() {
            w[i] += eta * system.scales[i] * (lambda[i] - p.centre[i]);
        }
    }
    blocks.clear();
    for (k, law) in system.laws.iter().enumerate() {
        // The scales of W + H: its diagonal, and for the disk ρ + η max(a_t1, a_t2), a bound on
        // the largest eigenvalue of its tangent block.
        let a: SVector<f64, R> = system.scales.fixed_rows::<R>(R * k) * (1.0 + eta);
        let law = match *law {
            Law::Disk { mu, rho } => Law::Disk {
                mu,
                rho: rho + eta * (1..R).map(|r| system.scales[R * k + r]).fold(0.0, f64::max),
            },
            other => other,
        };
        let l: SVector<f64, R> = lambda.fixed_rows::<R>(R * k).into();
        let wk: SVector<f64, R> = w.fixed_rows::<R>(R * k).into();
        let lin = linearise(law, &a, &l, &wk);
        f.fixed_rows_mut::<R>(R * k).copy_from(&lin.f);
        blocks.push((lin.d_lambda, lin.d_w));
    }
}

/// The largest per-constraint norm of F (m/s): |F_n|, each box row, ‖F_t‖ for the disk, each
/// free row. At a point where no proximal term acts this is the residual of docs/contact.md
/// §"Residual".
pub(super) fn law_norm<const R: usize>(system: &System<R>, f: &DVector<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for (k, law) in system.laws.iter().enumerate() {
        let fk = f.fixed_rows::<R>(R * k);
        worst = match law {
            Law::Disk { .. } => worst
                .max(fk[0].abs())
                .max((1..R).map(|r| fk[r] * fk[r]).sum::<f64>().sqrt()),
            _ => worst.max(fk.amax()),
        };
    }
    worst
}

/// Solves (D_λ + D_w (W + H)) Δ = rhs. `None` when the factorisation fails or gives a
/// non-finite answer.
pub(super) fn solve_newton_system<const R: usize>(
    system: &System<R>,
    blocks: &[(SMatrix<f64, R, R>, SMatrix<f64, R, R>)],
    h: &DVector<f64>,
    rhs: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = system.rows();
    // The block (k, j) of the matrix: D_w,k W_kj, plus D_λ,k + D_w,k H_k on the diagonal.
    let block_of = |k: usize, j: usize, w: &SMatrix<f64, R, R>| {
        let (d_lambda, d_w) = &blocks[k];
        let mut m = d_w * w;
        if j == k {
            m += d_lambda;
            for r in 0..R {
                for s in 0..R {
                    m[(r, s)] += d_w[(r, s)] * h[R * k + s];
                }
            }
        }
        m
    };
    let x = if n <= system.dense_rows {
        let mut m = DMatrix::<f64>::zeros(n, n);
        for (k, row) in system.block_rows().enumerate() {
            for (j, w) in row {
                m.view_mut((R * k, R * j), (R, R))
                    .copy_from(&block_of(k, *j, w));
            }
        }
        m.lu().solve(rhs)?
    } else {
        let layout = system.sparse.as_ref()?;
        let mut buffers = layout.numeric.borrow_mut();
        let SparseBuffers {
            matrix,
            lu,
            rhs: x,
            scratch,
        } = &mut *buffers;
        // The values, written where the pattern put them (entry e in block order).
        let values = matrix.val_mut();
        let mut e = 0;
        for (k, row) in system.block_rows().enumerate() {
            for (j, w) in row {
                let m = block_of(k, *j, w);
                for r in 0..R {
                    for s in 0..R {
                        values[layout.position[e]] = m[(r, s)];
                        e += 1;
                    }
                }
            }
        }
        let par = faer::Par::Seq;
        let stack = faer::dyn_stack::MemStack::new(scratch);
        let factors = layout
            .lu
            .factorize_numeric_lu(lu, matrix.as_ref(), par, stack, Default::default())
            .ok()?;
        for i in 0..n {
            x[(i, 0)] = rhs[i];
        }
        factors.solve_in_place_with_conj(faer::Conj::No, x.as_mut(), par, stack);
        DVector::from_fn(n, |i, _| x[(i, 0)])
    };
    x.iter().all(|v| v.is_finite()).then_some(x)
}
