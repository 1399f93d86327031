//! The contact problem's JSON file, for external solvers and for `rigidref crosscheck`.
//! Documented field by field in docs/contact-problem-format.md. Matrices are lists of rows.

use super::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// The `format` value of a contact-problem file.
pub const PROBLEM_FORMAT: &str = "rigidref-contact-problem";
/// The current version of the format.
pub const PROBLEM_VERSION: u32 = 1;
/// The `form` value of a local-form problem file ([`super::local_json`]); a body-form file has
/// no `form` key.
pub const LOCAL_FORM: &str = "local";

/// A contact-problem file: the problem, where it came from, and optionally a solution.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Always `rigidref-contact-problem`.
    pub format: String,
    /// Format version (1).
    pub version: u32,
    /// Degrees of freedom per body: 6 (3D) or 3 (2D).
    pub dof_per_body: usize,
    /// Rows per contact: 3 (3D: n, t1, t2) or 2 (2D: n, t).
    pub rows_per_contact: usize,
    /// Scene name, when the problem came from a run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// Frame number (1-based: the frame being computed), when from a run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<u64>,
    /// Substep within the frame (0-based), when from a run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substep: Option<u32>,
    /// The integration step h, s (impulse / h = average force), when from a run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    /// `box` or `cone`.
    pub friction: FrictionModel,
    /// The bodies.
    pub bodies: Vec<BodyJson>,
    /// The contacts.
    pub contacts: Vec<ContactJson>,
    /// A solution, when the writer solved the problem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solution: Option<SolutionJson>,
}

/// Where a problem written by a run came from.
#[derive(Clone, Copy, Debug)]
pub struct RunOrigin<'a> {
    /// The scene's name.
    pub scene: &'a str,
    /// The frame being computed, 1-based.
    pub step: u64,
    /// The substep within it, 0-based.
    pub substep: u32,
    /// The substep length h.
    pub h: f64,
}

/// One body.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BodyJson {
    /// M⁻¹, D × D, rows.
    pub inverse_mass: Vec<Vec<f64>>,
    /// u, D.
    pub velocity: Vec<f64>,
}

/// Whether `bounds` is a contact's (the default, so not written).
fn is_contact(bounds: &RowBounds) -> bool {
    *bounds == RowBounds::Contact
}

/// One contact (or joint).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactJson {
    /// [body 1, body 2]; −1 is the static world.
    pub bodies: [i64; 2],
    /// [J₁, J₂], each R × D, rows.
    pub jacobian: [Vec<Vec<f64>>; 2],
    /// b, R, m/s.
    pub b: Vec<f64>,
    /// Friction coefficient.
    pub mu: f64,
    /// Compliance on the normal row, kg⁻¹.
    pub compliance: f64,
    /// Warm-start λ, R, N·s.
    pub lambda0: Vec<f64>,
    /// How the rows are bounded: `"contact"` (the default, omitted when written) or `"free"`
    /// (a joint: every row unbounded).
    #[serde(default, skip_serializing_if = "is_contact")]
    pub bounds: RowBounds,
    /// Where the contact is, when it came from collision detection (not used by solvers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<GeometryJson>,
}

/// A contact's geometry, for the reader's orientation.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GeometryJson {
    /// Contact point, world frame, m.
    pub p: Vec<f64>,
    /// Unit normal, from body 2 into body 1.
    pub n: Vec<f64>,
    /// Penetration depth, m (positive when penetrating).
    pub depth: f64,
}

/// A solution of the problem.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolutionJson {
    /// Which method produced the solution: `pgs`, `newton`, or `proximal` (the Newton solver's
    /// fallback).
    pub solver: String,
    /// λ per contact, R each, N·s.
    pub lambda: Vec<Vec<f64>>,
    /// Iterations the solver ran.
    pub iterations: u32,
    /// Its residual (docs/contact.md §"Residual"), m/s.
    pub residual: f64,
    /// Cone friction: the exact Coulomb law's residual (docs/contact.md §"The exact Coulomb
    /// residual"), m/s; absent for box friction and in files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coulomb_residual: Option<f64>,
    /// Each contact's physical criteria (docs/contact.md §"Physical criteria"); absent in files
    /// written before they existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub criteria: Option<Vec<crate::problem::ContactCriteria>>,
}

fn rows<const A: usize, const B: usize>(m: &SMatrix<f64, A, B>) -> Vec<Vec<f64>> {
    (0..A)
        .map(|i| (0..B).map(|j| m[(i, j)]).collect())
        .collect()
}

fn matrix<const A: usize, const B: usize>(
    rows: &[Vec<f64>],
    what: &str,
) -> Result<SMatrix<f64, A, B>, String> {
    if rows.len() != A || rows.iter().any(|r| r.len() != B) {
        return Err(format!("{what} must be {A}×{B}"));
    }
    Ok(SMatrix::from_fn(|i, j| rows[i][j]))
}

fn vector<const A: usize>(v: &[f64], what: &str) -> Result<SVector<f64, A>, String> {
    if v.len() != A {
        return Err(format!("{what} must have {A} entries, got {}", v.len()));
    }
    Ok(SVector::from_column_slice(v))
}

fn body_index(i: Option<usize>) -> i64 {
    i.map_or(-1, |i| i as i64)
}

/// A problem file's text as JSON, of either form: errors say what is wrong in words (a UTF-8
/// byte-order mark, which JSON does not allow; text that is not JSON or is cut off, and where),
/// never serde's bare message.
pub fn json_value(text: &str) -> Result<serde_json::Value, String> {
    if text.starts_with('\u{feff}') {
        return Err(
            "the file starts with a UTF-8 byte-order mark (BOM), which JSON does not allow; \
             write it without one"
                .into(),
        );
    }
    serde_json::from_str(text).map_err(|e| {
        format!(
            "not a problem file: {}",
            crate::common::trace::json_problem(&e)
        )
    })
}

/// A problem file's `format` and `version` (of either form) must be this reader's.
pub(super) fn check_format_and_version(format: &str, version: u32) -> Result<(), String> {
    if format != PROBLEM_FORMAT {
        return Err(format!("format is {format:?}, expected {PROBLEM_FORMAT:?}"));
    }
    if version != PROBLEM_VERSION {
        return Err(format!(
            "version {version} is not supported (this rigidref reads version {PROBLEM_VERSION})"
        ));
    }
    Ok(())
}

impl ProblemFile {
    /// The file for `problem`, without provenance or solution (set those fields after).
    pub fn new<const D: usize, const R: usize>(problem: &ContactProblem<D, R>) -> ProblemFile {
        ProblemFile {
            format: PROBLEM_FORMAT.to_string(),
            version: PROBLEM_VERSION,
            dof_per_body: D,
            rows_per_contact: R,
            scene: None,
            step: None,
            substep: None,
            h: None,
            friction: problem.friction,
            bodies: problem
                .bodies
                .iter()
                .map(|b| BodyJson {
                    inverse_mass: rows(&b.inverse_mass),
                    velocity: b.velocity.iter().copied().collect(),
                })
                .collect(),
            contacts: problem
                .contacts
                .iter()
                .map(|c| ContactJson {
                    bodies: c.bodies.map(body_index),
                    jacobian: [rows(&c.jacobian[0]), rows(&c.jacobian[1])],
                    b: c.b.iter().copied().collect(),
                    mu: c.mu,
                    compliance: c.compliance,
                    lambda0: c.lambda0.iter().copied().collect(),
                    bounds: c.bounds,
                    geometry: None,
                })
                .collect(),
            solution: None,
        }
    }

    /// The file of a problem a run solved (`rigidref run --dump-problems`, 3D and 2D): where it
    /// came from (`scene`, frame `step`, `substep`, step size `h`), each contact's geometry (point
    /// and normal in the world frame, depth) and the PGS solution the run applied.
    pub fn of_run<const D: usize, const R: usize>(
        problem: &ContactProblem<D, R>,
        origin: RunOrigin<'_>,
        geometry: impl IntoIterator<Item = GeometryJson>,
        lambda: &[SVector<f64, R>],
        report: &crate::problem::SolveReport,
        criteria: Vec<crate::problem::ContactCriteria>,
    ) -> ProblemFile {
        let mut file = ProblemFile::new(problem);
        file.scene = Some(origin.scene.to_string());
        file.step = Some(origin.step);
        file.substep = Some(origin.substep);
        file.h = Some(origin.h);
        for (json, g) in file.contacts.iter_mut().zip(geometry) {
            json.geometry = Some(g);
        }
        file.solution = Some(SolutionJson {
            solver: report.method.name().into(),
            lambda: lambda.iter().map(|l| l.iter().copied().collect()).collect(),
            iterations: report.iterations,
            residual: report.residual,
            coulomb_residual: report.coulomb_residual,
            criteria: Some(criteria),
        });
        file
    }

    /// The problem in the file, checked: dimensions D and R must match the file's, every array
    /// must have its size, and [`ContactProblem::validate`] must pass.
    pub fn to_problem<const D: usize, const R: usize>(
        &self,
    ) -> Result<ContactProblem<D, R>, String> {
        check_format_and_version(&self.format, self.version)?;
        if self.dof_per_body != D || self.rows_per_contact != R {
            return Err(format!(
                "dof_per_body {} and rows_per_contact {} do not match the expected {D} and {R}",
                self.dof_per_body, self.rows_per_contact
            ));
        }
        let bodies = self
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                Ok(ProblemBody {
                    inverse_mass: matrix(&b.inverse_mass, &format!("bodies[{i}].inverse_mass"))?,
                    velocity: vector(&b.velocity, &format!("bodies[{i}].velocity"))?,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        let contacts = self
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let index = |i: i64| -> Result<Option<usize>, String> {
                    match i {
                        -1 => Ok(None),
                        i if i >= 0 => Ok(Some(i as usize)),
                        i => Err(format!(
                            "contacts[{k}].bodies: index {i} (use −1 for the static world)"
                        )),
                    }
                };
                Ok(ProblemContact {
                    bodies: [index(c.bodies[0])?, index(c.bodies[1])?],
                    jacobian: [
                        matrix(&c.jacobian[0], &format!("contacts[{k}].jacobian[0]"))?,
                        matrix(&c.jacobian[1], &format!("contacts[{k}].jacobian[1]"))?,
                    ],
                    b: vector(&c.b, &format!("contacts[{k}].b"))?,
                    mu: c.mu,
                    compliance: c.compliance,
                    lambda0: vector(&c.lambda0, &format!("contacts[{k}].lambda0"))?,
                    bounds: c.bounds,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        let problem = ContactProblem {
            friction: self.friction,
            bodies,
            contacts,
        };
        problem.validate()?;
        Ok(problem)
    }

    /// Reads a problem file; errors name the file (and for JSON the line and column).
    pub fn read(path: &std::path::Path) -> Result<ProblemFile, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        ProblemFile::parse(&text, &path.display().to_string())
    }

    /// Reads a problem file's text; errors name `source` and what is wrong (a byte-order mark,
    /// JSON that is not, a local-form file, a key the format does not have).
    pub fn parse(text: &str, source: &str) -> Result<ProblemFile, String> {
        let value = json_value(text).map_err(|e| format!("{source}: {e}"))?;
        if value.get("form").and_then(|f| f.as_str()) == Some(LOCAL_FORM) {
            return Err(format!(
                "{source}: a local-form problem (W, q; no bodies or Jacobian): this needs the body \
                 form, a problem with bodies as `rigidref run --dump-problems` writes"
            ));
        }
        match serde_json::from_str(text) {
            Ok(file) => Ok(file),
            Err(e) => Err(format!("{source}: {e}")),
        }
    }
}
