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

//!
//! The bodies and contacts of the two files are matched first ([`matching`]): by the traces'
//! matching when given, else from the contacts' points; a contact listed with its bodies the
//! other way round is compared with its normal flipped and its Jacobian blocks swapped.

mod matching;

pub use matching::{BodyMatching, Partner, match_problem_bodies};

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

/// A contact's R × 2D Jacobian [J₁ | J₂] (a side whose body is −1 zeroed); with `swapped`,
/// [J₂ | J₁]: the contact as a file listing its bodies the other way round would have it.
fn jacobian(p: &ProblemFile, c: &ContactJson, swapped: bool) -> DMatrix<f64> {
    let (d, r) = (p.dof_per_body, p.rows_per_contact);
    let sides = matching::sides(c, swapped);
    DMatrix::from_fn(r, 2 * d, |row, k| {
        let (body, source) = sides[k / d];
        if body < 0 {
            0.0
        } else {
            c.jacobian[source][row][k % d]
        }
    })
}

/// The 2D × 2D inverse mass of a contact's two bodies (in the order of `jacobian` with the same
/// `swapped`).
fn inverse_mass(p: &ProblemFile, c: &ContactJson, swapped: bool) -> DMatrix<f64> {
    let d = p.dof_per_body;
    let sides = matching::sides(c, swapped);
    DMatrix::from_fn(2 * d, 2 * d, |r, k| {
        let (side_r, side_k) = (r / d, k / d);
        let body = sides[side_r].0;
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

/// What [`compare_problems_matched`] found: every difference beyond the tolerance, how many
/// values were compared, and how bodies and contacts were matched.
#[derive(Clone, Debug, PartialEq)]
pub struct ProblemReport {
    /// The differences, in the reference's body and contact numbers; empty when they agree.
    pub differences: Vec<ProblemDifference>,
    /// How many values were compared.
    pub compared: usize,
    /// How the bodies were matched, and the other file's body of each reference body.
    pub bodies: BodyMatching,
    /// What the reader should know of the matching: bodies found under other numbers, contacts
    /// listed with their bodies the other way round.
    pub notes: Vec<String>,
}

/// Every difference between the two problems beyond `tol`, up to each contact's tangent basis;
/// empty when they agree. Also returns how many values were compared. Bodies and contacts are
/// matched as [`compare_problems_matched`] does without a given matching.
pub fn compare_problems(
    reference: &ProblemFile,
    other: &ProblemFile,
    tol: ProblemTolerance,
) -> Result<(Vec<ProblemDifference>, usize), String> {
    let report = compare_problems_matched(reference, other, None, tol)?;
    Ok((report.differences, report.compared))
}

/// Every difference between the two problems beyond `tol`, up to each contact's tangent basis
/// and the order the files list bodies, contacts and a contact's two bodies in ([`matching`]):
/// `bodies[i]`, when given, is the other file's body of reference body i (the traces'
/// matching, as `grade` uses); else the bodies are matched from the files. Names use the
/// reference's body and contact numbers. An error when a file is not a problem of the same
/// system, or a body's inverse mass makes no sense.
pub fn compare_problems_matched(
    reference: &ProblemFile,
    other: &ProblemFile,
    bodies: Option<&[usize]>,
    tol: ProblemTolerance,
) -> Result<ProblemReport, String> {
    check_shapes(reference, other)?;
    let matched = match bodies {
        Some(map) => BodyMatching {
            map: (0..reference.bodies.len())
                .map(|i| map.get(i).copied().filter(|&j| j < other.bodies.len()))
                .collect(),
            by: "given",
        },
        None => match_problem_bodies(reference, other),
    };
    let mut notes = Vec::new();
    let moved: Vec<String> = (matched.map.iter().enumerate())
        .filter_map(|(i, j)| j.filter(|&j| j != i).map(|j| format!("{i} = {j}")))
        .collect();
    if !moved.is_empty() {
        notes.push(format!(
            "bodies matched by {}: reference body = other file's body: {}",
            match matched.by {
                "given" => "the traces",
                "contacts" => "their contacts' points",
                _ => "likeness",
            },
            moved.join(", ")
        ));
    }
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
    for (i, a) in reference.bodies.iter().enumerate() {
        let Some(b) = matched.map[i].map(|j| &other.bodies[j]) else {
            c.compared += 1;
            c.out.push(ProblemDifference {
                quantity: format!("body {i}: no body of the other file matches it"),
                reference: 1.0,
                other: 0.0,
            });
            continue;
        };
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
    let row = |p: &ProblemFile, k: usize, swapped: bool| -> Vec<f64> {
        jacobian(p, &p.contacts[k], swapped)
            .row(0)
            .iter()
            .copied()
            .collect()
    };
    let matching = matching::match_contacts(reference, other, &matched.map, &row);
    let swapped: Vec<String> = (matching.iter().enumerate())
        .filter_map(|(k, m)| {
            m.filter(|m| m.swapped)
                .map(|m| format!("{k} (= {})", m.contact))
        })
        .collect();
    if !swapped.is_empty() {
        notes.push(format!(
            "contacts the other file lists with their two bodies the other way round, compared \
             with the normal flipped and the Jacobian blocks swapped: {}",
            swapped.join(", ")
        ));
    }
    for (k, ca) in reference.contacts.iter().enumerate() {
        let Some(Partner {
            contact: m,
            swapped,
        }) = matching[k]
        else {
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
            let flip = if swapped { -1.0 } else { 1.0 };
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
                    flip * gb.n[d],
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
        let (ja, jb) = (jacobian(reference, ca, false), jacobian(other, cb, swapped));
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
        let delassus = |p: &ProblemFile, cj: &ContactJson, j: &DMatrix<f64>, swapped: bool| {
            j * inverse_mass(p, cj, swapped) * j.transpose()
        };
        let (aa, ab) = (
            delassus(reference, ca, &ja, false),
            delassus(other, cb, &jb, swapped),
        );
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
                return Ok(ProblemReport {
                    differences: c.out,
                    compared: c.compared,
                    bodies: matched,
                    notes,
                });
            }
        }
        for (k, la) in sa.lambda.iter().enumerate() {
            let Some(lb) = matching[k].and_then(|m| sb.lambda.get(m.contact)) else {
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
    Ok(ProblemReport {
        differences: c.out,
        compared: c.compared,
        bodies: matched,
        notes,
    })
}
