//! The contact problem in local (Delassus) form: the operator W, the free velocity q and μ per
//! contact, with no bodies and no Jacobian. docs/contact.md §"The local form";
//! the file variant in docs/contact-problem-format.md §"The local form".
//!
//! With λ the impulses (N·s) and w = W λ + q the constraint velocities after them (m/s), each
//! contact obeys the same law as in [`super::ContactProblem`] (row 0 normal, rows 1..R friction,
//! [`RowBounds`] per constraint). This is the form of FCLIB's `fclib_local` problems and of
//! Siconos' `FrictionContactProblem` (there W is called M, λ is r, w is u); a problem of a run
//! converts to it by [`ContactProblem::to_local`]: W = J M⁻¹ Jᵀ + C, q = b.
//!
//! W is stored by block rows, R × R blocks, only the blocks that are not structurally zero: in a
//! run's problem, contacts that share a body. It need not be symmetric (Siconos' files print W
//! to round-off, and some are not symmetric beyond it): every solver reads it as it is, and only
//! the convex reformulation for clarabel needs symmetry ([`LocalProblem::asymmetry`]).

use super::{ContactProblem, FrictionModel, RowBounds};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// One contact (or joint) of a local problem.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalContact<const R: usize> {
    /// The contact's block row of W: (j, W_kj) for the contacts j it is coupled to, j strictly
    /// ascending, the diagonal block (j = k) always present; kg⁻¹, compliance included.
    pub row: Vec<(usize, SMatrix<f64, R, R>)>,
    /// q: the constraint velocity without contact impulses, m/s (b of the body form).
    pub q: SVector<f64, R>,
    /// Friction coefficient μ (dimensionless).
    pub mu: f64,
    /// Initial guess for λ (warm start), N·s.
    pub lambda0: SVector<f64, R>,
    /// How the rows are bounded.
    pub bounds: RowBounds,
}

/// A contact problem in local form. Plain data; solvers read it and never change it.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalProblem<const R: usize> {
    /// How friction rows are bounded.
    pub friction: FrictionModel,
    /// The contacts, each with its block row of W.
    pub contacts: Vec<LocalContact<R>>,
}

impl<const R: usize> LocalProblem<R> {
    /// A problem with a dense W (R·n square, kg⁻¹) cut into blocks, keeping the blocks that are
    /// not all zero (and every diagonal block); q stacked (m/s), μ per contact, all contacts
    /// (`RowBounds::Contact`), cold start.
    pub fn from_dense(
        friction: FrictionModel,
        w: &DMatrix<f64>,
        q: &DVector<f64>,
        mu: &[f64],
    ) -> Result<LocalProblem<R>, String> {
        let n = mu.len();
        if w.nrows() != R * n || w.ncols() != R * n {
            return Err(format!(
                "W is {}×{}, expected {}×{} for {n} contacts of {R} rows",
                w.nrows(),
                w.ncols(),
                R * n,
                R * n
            ));
        }
        if q.len() != R * n {
            return Err(format!("q has {} entries, expected {}", q.len(), R * n));
        }
        let contacts = (0..n)
            .map(|k| LocalContact {
                row: (0..n)
                    .filter_map(|j| {
                        let block: SMatrix<f64, R, R> =
                            w.fixed_view::<R, R>(R * k, R * j).into_owned();
                        (j == k || block.iter().any(|x| *x != 0.0)).then_some((j, block))
                    })
                    .collect(),
                q: q.fixed_rows::<R>(R * k).into_owned(),
                mu: mu[k],
                lambda0: SVector::zeros(),
                bounds: RowBounds::Contact,
            })
            .collect();
        let problem = LocalProblem { friction, contacts };
        problem.validate()?;
        Ok(problem)
    }

    /// A problem of `mu.len()` contacts from W's entries (row, column, value; 0-based scalar
    /// indices below R·contacts, each at most once), q stacked and μ per contact; all contacts
    /// (`RowBounds::Contact`), cold start. A block is stored where any of its entries is given
    /// (a given zero too, so that a block structure survives a round trip); every diagonal block
    /// is. Checked by [`LocalProblem::validate`].
    pub fn from_entries(
        friction: FrictionModel,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
        q: &[f64],
        mu: &[f64],
    ) -> Result<LocalProblem<R>, String> {
        let n = R * mu.len();
        if q.len() != n {
            return Err(format!("q has {} entries, expected {n}", q.len()));
        }
        let mut blocks: std::collections::BTreeMap<
            (usize, usize),
            (SMatrix<f64, R, R>, SMatrix<u8, R, R>),
        > = std::collections::BTreeMap::new();
        for (i, j, v) in entries {
            if i >= n || j >= n {
                return Err(format!("W entry ({i}, {j}) out of range (W is {n}×{n})"));
            }
            let (block, seen) = blocks
                .entry((i / R, j / R))
                .or_insert_with(|| (SMatrix::zeros(), SMatrix::zeros()));
            if seen[(i % R, j % R)] != 0 {
                return Err(format!("W entry ({i}, {j}) given twice"));
            }
            seen[(i % R, j % R)] = 1;
            block[(i % R, j % R)] = v;
        }
        let mut contacts: Vec<LocalContact<R>> = (0..mu.len())
            .map(|k| LocalContact {
                row: Vec::new(),
                q: SVector::from_column_slice(&q[R * k..R * k + R]),
                mu: mu[k],
                lambda0: SVector::zeros(),
                bounds: RowBounds::Contact,
            })
            .collect();
        for ((k, j), (block, _)) in blocks {
            contacts[k].row.push((j, block));
        }
        for (k, c) in contacts.iter_mut().enumerate() {
            if c.row.binary_search_by_key(&k, |(j, _)| *j).is_err() {
                c.row.push((k, SMatrix::zeros()));
                c.row.sort_by_key(|(j, _)| *j);
            }
        }
        let problem = LocalProblem { friction, contacts };
        problem.validate()?;
        Ok(problem)
    }

    /// The diagonal block W_kk (kg⁻¹, compliance included).
    pub fn diagonal_block(&self, k: usize) -> &SMatrix<f64, R, R> {
        let row = &self.contacts[k].row;
        let i = row.binary_search_by_key(&k, |(j, _)| *j).unwrap_or(0);
        &row[i].1
    }

    /// w = W λ + q per contact, m/s.
    pub fn velocity(&self, lambda: &[SVector<f64, R>]) -> Vec<SVector<f64, R>> {
        self.contacts
            .iter()
            .map(|c| {
                let mut w = c.q;
                for (j, block) in &c.row {
                    w += block * lambda[*j];
                }
                w
            })
            .collect()
    }

    /// The dense W (R·n square, kg⁻¹).
    pub fn dense_w(&self) -> DMatrix<f64> {
        let n = R * self.contacts.len();
        let mut w = DMatrix::zeros(n, n);
        for (k, c) in self.contacts.iter().enumerate() {
            for (j, block) in &c.row {
                w.fixed_view_mut::<R, R>(R * k, R * j).copy_from(block);
            }
        }
        w
    }

    /// The stacked q, m/s.
    pub fn dense_q(&self) -> DVector<f64> {
        DVector::from_iterator(
            R * self.contacts.len(),
            self.contacts.iter().flat_map(|c| c.q.iter().copied()),
        )
    }

    /// Blocks stored, diagonal included.
    pub fn blocks(&self) -> usize {
        self.contacts.iter().map(|c| c.row.len()).sum()
    }

    /// The problem without the contacts where `left_out[k]` is true: their rows and columns of W,
    /// their q and μ removed, the others renumbered in order (`kept[i]` is the i-th kept
    /// contact's number in `self`), each starting from `start[kept[i]]` (N·s). Plain data, as
    /// `self`. docs/contact.md §"Near-duplicate contacts left out".
    pub fn without(
        &self,
        left_out: &[bool],
        start: &[SVector<f64, R>],
    ) -> (LocalProblem<R>, Vec<usize>) {
        let kept: Vec<usize> = (0..self.contacts.len()).filter(|&k| !left_out[k]).collect();
        // Each contact's new number (usize::MAX for one left out).
        let mut number = vec![usize::MAX; self.contacts.len()];
        for (i, &k) in kept.iter().enumerate() {
            number[k] = i;
        }
        let contacts = kept
            .iter()
            .map(|&k| {
                let c = &self.contacts[k];
                LocalContact {
                    row: c
                        .row
                        .iter()
                        .filter(|(j, _)| !left_out[*j])
                        .map(|(j, block)| (number[*j], *block))
                        .collect(),
                    q: c.q,
                    mu: c.mu,
                    lambda0: start[k],
                    bounds: c.bounds,
                }
            })
            .collect();
        let problem = LocalProblem {
            friction: self.friction,
            contacts,
        };
        (problem, kept)
    }

    /// max |W − Wᵀ| / max |W| (0 for a symmetric W, or an empty one).
    pub fn asymmetry(&self) -> f64 {
        let mut largest: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for (k, c) in self.contacts.iter().enumerate() {
            for (j, block) in &c.row {
                largest = largest.max(block.amax());
                let mirror = self.contacts[*j]
                    .row
                    .binary_search_by_key(&k, |(i, _)| *i)
                    .map(|i| self.contacts[*j].row[i].1.transpose())
                    .unwrap_or_else(|_| SMatrix::zeros());
                worst = worst.max((block - mirror).amax());
            }
        }
        if largest > 0.0 { worst / largest } else { 0.0 }
    }

    /// Checks the problem is well formed: block indices in range and strictly ascending, the
    /// diagonal block present, every number finite, μ ≥ 0 (0 on free rows), W_kk's diagonal
    /// ≥ 0. Returns what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.contacts.len();
        for (k, c) in self.contacts.iter().enumerate() {
            let mut previous: Option<usize> = None;
            for (j, block) in &c.row {
                if *j >= n {
                    return Err(format!(
                        "contact {k}: block column {j} out of range (there are {n} contacts)"
                    ));
                }
                if previous.is_some_and(|p| p >= *j) {
                    return Err(format!(
                        "contact {k}: block columns must be strictly ascending ({} then {j})",
                        previous.unwrap_or(0)
                    ));
                }
                previous = Some(*j);
                if block.iter().any(|x| !x.is_finite()) {
                    return Err(format!(
                        "contact {k}: non-finite entry in block W[{k}][{j}]"
                    ));
                }
            }
            if c.row.binary_search_by_key(&k, |(j, _)| *j).is_err() {
                return Err(format!(
                    "contact {k}: the diagonal block W[{k}][{k}] is missing"
                ));
            }
            let diagonal = self.diagonal_block(k);
            if (0..R).any(|r| diagonal[(r, r)] < 0.0) {
                return Err(format!(
                    "contact {k}: W[{k}][{k}] has a negative diagonal entry (W must be positive \
                     semi-definite)"
                ));
            }
            if c.q.iter().chain(c.lambda0.iter()).any(|x| !x.is_finite()) {
                return Err(format!("contact {k}: non-finite q or lambda0"));
            }
            if !(c.mu.is_finite() && c.mu >= 0.0) {
                return Err(format!("contact {k}: mu must be ≥ 0, got {}", c.mu));
            }
            if c.bounds == RowBounds::Free && c.mu != 0.0 {
                return Err(format!(
                    "contact {k}: mu has no meaning on free rows (bounds \"free\"); give 0, got {}",
                    c.mu
                ));
            }
        }
        Ok(())
    }
}

impl<const D: usize, const R: usize> ContactProblem<D, R> {
    /// The problem in local form: W = J M⁻¹ Jᵀ + C by blocks (a block for each pair of contacts
    /// that share a body; the diagonal blocks averaged with their transposes, as
    /// [`ContactProblem::delassus_block`], so that they are symmetric to the bit), q = b, the
    /// same μ, warm start and bounds. docs/contact.md §"The local form".
    pub fn to_local(&self) -> LocalProblem<R> {
        // The contacts touching each body, with the side they touch it on.
        let mut touching: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.bodies.len()];
        for (k, c) in self.contacts.iter().enumerate() {
            for (side, body) in c.bodies.iter().enumerate() {
                if let Some(b) = body {
                    touching[*b].push((k, side));
                }
            }
        }
        let mut rows: Vec<Vec<(usize, SMatrix<f64, R, R>)>> = vec![Vec::new(); self.contacts.len()];
        for (b, list) in touching.iter().enumerate() {
            let inverse_mass = &self.bodies[b].inverse_mass;
            for &(k, sk) in list {
                let left = self.contacts[k].jacobian[sk] * inverse_mass;
                for &(j, sj) in list {
                    let block = left * self.contacts[j].jacobian[sj].transpose();
                    match rows[k].iter_mut().find(|(jj, _)| *jj == j) {
                        Some((_, w)) => *w += block,
                        None => rows[k].push((j, block)),
                    }
                }
            }
        }
        let contacts = rows
            .into_iter()
            .enumerate()
            .map(|(k, mut row)| {
                if !row.iter().any(|(j, _)| *j == k) {
                    row.push((k, SMatrix::zeros()));
                }
                row.sort_by_key(|(j, _)| *j);
                let c = &self.contacts[k];
                for (j, w) in row.iter_mut() {
                    if *j == k {
                        *w = (*w + w.transpose()) * 0.5;
                        for r in 0..R {
                            w[(r, r)] += c.row_compliance(r);
                        }
                    }
                }
                LocalContact {
                    row,
                    q: c.b,
                    mu: c.mu,
                    lambda0: c.lambda0,
                    bounds: c.bounds,
                }
            })
            .collect();
        LocalProblem {
            friction: self.friction,
            contacts,
        }
    }
}
