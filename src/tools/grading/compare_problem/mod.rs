//! Comparing two contact-problem files for the same state (the format of `run --dump-problems`,
//! docs/contact-problem-format.md), 3D (6 degrees of freedom per body, 3 rows per contact) or 2D
//! (3 and 2), up to the choice of each contact's tangent basis. docs/grading.md §"Comparing
//! contact problems".
//!
//! Two simulators may pick different tangents at a contact: in 3D any rotation Q of the pair
//! t1, t2 about n, in 2D the tangent's sign (Q = ±1). Under it the friction rows T ((R−1) × 2D)
//! become Q T, the Delassus block A = [[a, cᵀ], [c, B]] becomes [[a, (Q c)ᵀ], [Q c, Q B Qᵀ]],
//! and b's and λ's tangential parts turn by Q. What does not change, and is compared: the normal
//! row and a, b_n, λn exactly; TᵀT (the tangent-plane projector with its lever arms), |c|,
//! trace B and (3D) det B, |b_t| and |λ_t|.

use crate::problem::json::{ContactJson, ProblemFile};
use nalgebra::{DMatrix, DVector};

/// Tolerance of every comparison: relative to the larger magnitude of the two values (or of the
/// quantity's scale), plus an absolute floor for values that should be zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProblemTolerance {
    /// Relative tolerance.
    pub relative: f64,
    /// Absolute floor, in the quantity's unit.
    pub absolute: f64,
}

impl Default for ProblemTolerance {
    /// 1e-6 relative, 1e-9 absolute: round-off of a different but exact computation passes, a
    /// different lever arm, normal or mass does not.
    fn default() -> Self {
        ProblemTolerance {
            relative: 1e-6,
            absolute: 1e-9,
        }
    }
}

/// One difference found.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ProblemDifference {
    /// Where: `body 1 velocity[4]`, `contact 0: normal row, body 1 entry 4 (ω_y)`, ….
    pub quantity: String,
    /// The reference's value.
    pub reference: f64,
    /// The other's value.
    pub other: f64,
}

/// The names of a body's velocity entries, 3D (6) or 2D (3).
fn entry_names(dof: usize) -> &'static [&'static str] {
    if dof == 6 {
        &["v_x", "v_y", "v_z", "ω_x", "ω_y", "ω_z"]
    } else {
        &["v_x", "v_y", "ω"]
    }
}

struct Checker {
    tol: ProblemTolerance,
    out: Vec<ProblemDifference>,
    compared: usize,
}

impl Checker {
    fn check(&mut self, quantity: impl FnOnce() -> String, a: f64, b: f64, scale: f64) {
        self.compared += 1;
        let bound = self.tol.absolute + self.tol.relative * a.abs().max(b.abs()).max(scale);
        let difference = (a - b).abs();
        if difference.is_nan() || difference > bound {
            self.out.push(ProblemDifference {
                quantity: quantity(),
                reference: a,
                other: b,
            });
        }
    }
}

/// The residual (m/s, docs/contact.md §"Residual") of `lambda` on the file's own problem, or
/// `None` when the file is not a well-formed problem or λ has the wrong shape.
fn own_residual(file: &ProblemFile, lambda: &[Vec<f64>]) -> Option<f64> {
    fn of<const D: usize, const R: usize>(file: &ProblemFile, lambda: &[Vec<f64>]) -> Option<f64> {
        let problem = file.to_problem::<D, R>().ok()?;
        if lambda.len() != problem.contacts.len() || lambda.iter().any(|l| l.len() != R) {
            return None;
        }
        let lambda: Vec<nalgebra::SVector<f64, R>> = lambda
            .iter()
            .map(|l| nalgebra::SVector::from_column_slice(l))
            .collect();
        Some(crate::solve::residual(&problem, &lambda))
    }
    match (file.dof_per_body, file.rows_per_contact) {
        (6, 3) => of::<6, 3>(file, lambda),
        (3, 2) => of::<3, 2>(file, lambda),
        _ => None,
    }
}

/// A contact's R × 2D Jacobian [J₁ | J₂] (a side whose body is −1 zeroed).
fn jacobian(p: &ProblemFile, c: &ContactJson) -> DMatrix<f64> {
    let (d, r) = (p.dof_per_body, p.rows_per_contact);
    DMatrix::from_fn(r, 2 * d, |row, k| {
        let side = k / d;
        if c.bodies[side] < 0 {
            0.0
        } else {
            c.jacobian[side][row][k % d]
        }
    })
}

/// The 2D × 2D inverse mass of a contact's two bodies.
fn inverse_mass(p: &ProblemFile, c: &ContactJson) -> DMatrix<f64> {
    let d = p.dof_per_body;
    DMatrix::from_fn(2 * d, 2 * d, |r, k| {
        let (side_r, side_k) = (r / d, k / d);
        let body = c.bodies[side_r];
        if side_r != side_k || body < 0 {
            0.0
        } else {
            p.bodies[body as usize].inverse_mass[r % d][k % d]
        }
    })
}

/// Both files must be well-formed problems of the same system.
fn check_shapes(reference: &ProblemFile, other: &ProblemFile) -> Result<(), String> {
    for (p, what) in [(reference, "reference"), (other, "other")] {
        match (p.dof_per_body, p.rows_per_contact) {
            (6, 3) => p.to_problem::<6, 3>().map(|_| ()),
            (3, 2) => p.to_problem::<3, 2>().map(|_| ()),
            (d, r) => {
                return Err(format!(
                    "the {what} problem has {d} degrees of freedom per body and {r} rows per contact: compare-problem reads 3D (6 and 3) and 2D (3 and 2) problems"
                ));
            }
        }
        .map_err(|e| format!("the {what} problem: {e}"))?;
    }
    if (reference.dof_per_body, reference.rows_per_contact)
        != (other.dof_per_body, other.rows_per_contact)
    {
        return Err(format!(
            "the reference problem is {}D and the other {}D",
            if reference.rows_per_contact == 3 {
                3
            } else {
                2
            },
            if other.rows_per_contact == 3 { 3 } else { 2 }
        ));
    }
    Ok(())
}

/// The norm of the tangential entries (1..R) of a row of numbers.
fn tangential(v: &[f64]) -> f64 {
    v[1..].iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Which contact of `other` each contact of `reference` is: among the other's contacts with
/// the same [body 1, body 2] not yet taken, the nearest by contact point (when both have
/// geometry) or else by normal Jacobian row; in reference order. Two simulators may list a
/// state's contacts in different orders.
fn match_contacts(reference: &ProblemFile, other: &ProblemFile) -> Vec<Option<usize>> {
    let mut taken = vec![false; other.contacts.len()];
    reference
        .contacts
        .iter()
        .map(|ca| {
            let ja = jacobian(reference, ca);
            let distance = |cb: &ContactJson| match (&ca.geometry, &cb.geometry) {
                (Some(ga), Some(gb)) if ga.p.len() == gb.p.len() => {
                    ga.p.iter()
                        .zip(&gb.p)
                        .map(|(a, b)| (a - b).powi(2))
                        .sum::<f64>()
                }
                _ => (ja.row(0) - jacobian(other, cb).row(0)).norm_squared(),
            };
            let best = other
                .contacts
                .iter()
                .enumerate()
                .filter(|(m, cb)| !taken[*m] && cb.bodies == ca.bodies)
                .min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
                .map(|(m, _)| m);
            if let Some(m) = best {
                taken[m] = true;
            }
            best
        })
        .collect()
}

/// Every difference between the two problems beyond `tol`, up to each contact's tangent basis;
/// empty when they agree. Also returns how many values were compared. Contacts are matched by
/// nearest point (or normal row) within the same body pair (see `match_contacts`); names use
/// the reference's contact numbers.
pub fn compare_problems(
    reference: &ProblemFile,
    other: &ProblemFile,
    tol: ProblemTolerance,
) -> Result<(Vec<ProblemDifference>, usize), String> {
    check_shapes(reference, other)?;
    let (dof, rows) = (reference.dof_per_body, reference.rows_per_contact);
    let names = entry_names(dof);
    let mut c = Checker {
        tol,
        out: Vec::new(),
        compared: 0,
    };
    c.check(
        || "number of bodies".into(),
        reference.bodies.len() as f64,
        other.bodies.len() as f64,
        0.0,
    );
    c.check(
        || "number of contacts".into(),
        reference.contacts.len() as f64,
        other.contacts.len() as f64,
        0.0,
    );
    for (i, (a, b)) in reference.bodies.iter().zip(&other.bodies).enumerate() {
        let scale = a.velocity.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, entry) in names.iter().enumerate() {
            c.check(
                || format!("body {i} velocity {entry}"),
                a.velocity[k],
                b.velocity[k],
                scale,
            );
            for m in 0..dof {
                c.check(
                    || format!("body {i} inverse mass [{k}][{m}]"),
                    a.inverse_mass[k][m],
                    b.inverse_mass[k][m],
                    0.0,
                );
            }
        }
    }
    c.check(
        || "friction model (0 box, 1 cone)".into(),
        f64::from(u8::from(
            reference.friction == crate::problem::FrictionModel::Cone,
        )),
        f64::from(u8::from(
            other.friction == crate::problem::FrictionModel::Cone,
        )),
        0.0,
    );
    let matching = match_contacts(reference, other);
    for (k, ca) in reference.contacts.iter().enumerate() {
        let Some(m) = matching[k] else {
            c.compared += 1;
            c.out.push(ProblemDifference {
                quantity: format!(
                    "contact {k} (bodies {:?}): no contact of the other file matches it",
                    ca.bodies
                ),
                reference: 1.0,
                other: 0.0,
            });
            continue;
        };
        let cb = &other.contacts[m];
        if let (Some(ga), Some(gb)) = (&ca.geometry, &cb.geometry)
            && ga.p.len() == gb.p.len()
            && ga.n.len() == gb.n.len()
        {
            for d in 0..ga.p.len().min(ga.n.len()) {
                c.check(
                    || format!("contact {k}: point p[{d}]"),
                    ga.p[d],
                    gb.p[d],
                    1.0,
                );
                c.check(
                    || format!("contact {k}: normal n[{d}]"),
                    ga.n[d],
                    gb.n[d],
                    1.0,
                );
            }
        }
        c.check(|| format!("contact {k}: mu"), ca.mu, cb.mu, 0.0);
        c.check(
            || format!("contact {k}: bounds (0 contact, 1 free)"),
            f64::from(u8::from(ca.bounds == crate::problem::RowBounds::Free)),
            f64::from(u8::from(cb.bounds == crate::problem::RowBounds::Free)),
            0.0,
        );
        c.check(
            || format!("contact {k}: compliance"),
            ca.compliance,
            cb.compliance,
            0.0,
        );
        let (ja, jb) = (jacobian(reference, ca), jacobian(other, cb));
        let scale = ja.abs().max().max(1.0);
        let columns = 2 * dof;
        for e in 0..columns {
            c.check(
                || {
                    format!(
                        "contact {k}: normal row, body {} entry {e} ({})",
                        e / dof + 1,
                        names[e % dof]
                    )
                },
                ja[(0, e)],
                jb[(0, e)],
                scale,
            );
        }
        // The friction rows up to a rotation about n (2D: the tangent's sign): TᵀT is invariant.
        let (ta, tb) = (
            ja.rows(1, rows - 1).into_owned(),
            jb.rows(1, rows - 1).into_owned(),
        );
        let (pa, pb) = (ta.transpose() * &ta, tb.transpose() * &tb);
        for r in 0..columns {
            for e in 0..columns {
                c.check(
                    || {
                        format!(
                            "contact {k}: friction rows' TᵀT [{r}][{e}] (body {} {}, body {} {})",
                            r / dof + 1,
                            names[r % dof],
                            e / dof + 1,
                            names[e % dof]
                        )
                    },
                    pa[(r, e)],
                    pb[(r, e)],
                    scale * scale,
                );
            }
        }
        // The Delassus block's invariants.
        let delassus = |p: &ProblemFile, cj: &ContactJson, j: &DMatrix<f64>| {
            j * inverse_mass(p, cj) * j.transpose()
        };
        let (aa, ab) = (delassus(reference, ca, &ja), delassus(other, cb, &jb));
        let scale_a = aa.abs().max();
        let coupling = |m: &DMatrix<f64>| (1..rows).map(|r| m[(r, 0)].powi(2)).sum::<f64>().sqrt();
        let tangent_trace = |m: &DMatrix<f64>| (1..rows).map(|r| m[(r, r)]).sum::<f64>();
        c.check(
            || format!("contact {k}: Delassus A_nn"),
            aa[(0, 0)],
            ab[(0, 0)],
            scale_a,
        );
        c.check(
            || format!("contact {k}: Delassus |A_nt|"),
            coupling(&aa),
            coupling(&ab),
            scale_a,
        );
        c.check(
            || format!("contact {k}: Delassus trace of the tangent block"),
            tangent_trace(&aa),
            tangent_trace(&ab),
            scale_a,
        );
        if rows == 3 {
            let tangent_det = |m: &DMatrix<f64>| m[(1, 1)] * m[(2, 2)] - m[(1, 2)] * m[(2, 1)];
            c.check(
                || format!("contact {k}: Delassus det of the tangent block"),
                tangent_det(&aa),
                tangent_det(&ab),
                scale_a * scale_a,
            );
        }
        let bscale = DVector::from_column_slice(&ca.b).abs().max();
        c.check(|| format!("contact {k}: b_n"), ca.b[0], cb.b[0], bscale);
        c.check(
            || format!("contact {k}: |b_t|"),
            tangential(&ca.b),
            tangential(&cb.b),
            bscale,
        );
    }
    if let (Some(sa), Some(sb)) = (&reference.solution, &other.solution) {
        // With friction a problem can have several solutions with different λ and different
        // velocities afterwards, even for a positive definite A (docs/contact-problem-format.md):
        // an other λ that solves its own problem (residual within the tolerance of b) is a
        // right answer, whatever the reference chose. Only the problems themselves, compared
        // above, must then agree.
        if let Some(r) = own_residual(other, &sb.lambda) {
            let b_scale = other
                .contacts
                .iter()
                .flat_map(|c| c.b.iter())
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            if r <= c.tol.absolute + c.tol.relative * b_scale {
                c.compared += 1;
                return Ok((c.out, c.compared));
            }
        }
        for (k, la) in sa.lambda.iter().enumerate() {
            let Some(lb) = matching[k].and_then(|m| sb.lambda.get(m)) else {
                continue;
            };
            if la.len() != rows || lb.len() != rows {
                c.compared += 1;
                c.out.push(ProblemDifference {
                    quantity: format!(
                        "contact {k}: λ has {} and {} entries, not {rows}",
                        la.len(),
                        lb.len()
                    ),
                    reference: la.len() as f64,
                    other: lb.len() as f64,
                });
                continue;
            }
            let scale = la.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            c.check(|| format!("contact {k}: λn"), la[0], lb[0], scale);
            c.check(
                || format!("contact {k}: |λ_t|"),
                tangential(la),
                tangential(lb),
                scale,
            );
        }
    }
    Ok((c.out, c.compared))
}
