//! The local form's problem file: W by blocks, q, μ (docs/contact-problem-format.md §"The local
//! form"). A variant of the contact-problem file, told apart by `"form": "local"`; the body
//! form ([`super::json::ProblemFile`]) has no `form` key.

pub use super::json::LOCAL_FORM;
use super::json::{PROBLEM_FORMAT, PROBLEM_VERSION, ProblemFile, SolutionJson};
use super::{FrictionModel, LocalContact, LocalProblem, RowBounds};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// A local-form problem file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LocalProblemFile {
    /// Always `rigidref-contact-problem`.
    pub format: String,
    /// Format version (1).
    pub version: u32,
    /// Always `local`.
    pub form: String,
    /// Rows per contact: 3 (n, t1, t2) or 2 (n, t).
    pub rows_per_contact: usize,
    /// Where the problem came from (free text: a scene and step, or a file it was converted
    /// from), when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// `box` or `cone`.
    pub friction: FrictionModel,
    /// W's blocks that are not structurally zero, every diagonal block among them.
    #[serde(rename = "W")]
    pub w: Vec<BlockJson>,
    /// The contacts.
    pub contacts: Vec<LocalContactJson>,
    /// A solution, when the writer solved the problem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solution: Option<SolutionJson>,
}

/// One block W_kj.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlockJson {
    /// k, the block row (a contact).
    pub row: usize,
    /// j, the block column (a contact).
    pub col: usize,
    /// W_kj, R × R, rows, kg⁻¹.
    pub block: Vec<Vec<f64>>,
}

/// One contact (or joint) of a local-form file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LocalContactJson {
    /// q, R, m/s.
    pub q: Vec<f64>,
    /// Friction coefficient.
    pub mu: f64,
    /// Warm-start λ, R, N·s; zeros when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lambda0: Option<Vec<f64>>,
    /// `"contact"` (the default, omitted) or `"free"`.
    #[serde(default, skip_serializing_if = "is_contact")]
    pub bounds: RowBounds,
}

fn is_contact(bounds: &RowBounds) -> bool {
    *bounds == RowBounds::Contact
}

impl LocalProblemFile {
    /// The file for `problem`, without source or solution.
    pub fn new<const R: usize>(problem: &LocalProblem<R>) -> LocalProblemFile {
        let rows = |m: &SMatrix<f64, R, R>| -> Vec<Vec<f64>> {
            (0..R)
                .map(|i| (0..R).map(|j| m[(i, j)]).collect())
                .collect()
        };
        LocalProblemFile {
            format: PROBLEM_FORMAT.into(),
            version: PROBLEM_VERSION,
            form: LOCAL_FORM.into(),
            rows_per_contact: R,
            source: None,
            friction: problem.friction,
            w: problem
                .contacts
                .iter()
                .enumerate()
                .flat_map(|(k, c)| {
                    c.row.iter().map(move |(j, block)| BlockJson {
                        row: k,
                        col: *j,
                        block: rows(block),
                    })
                })
                .collect(),
            contacts: problem
                .contacts
                .iter()
                .map(|c| LocalContactJson {
                    q: c.q.iter().copied().collect(),
                    mu: c.mu,
                    lambda0: c
                        .lambda0
                        .iter()
                        .any(|x| *x != 0.0)
                        .then(|| c.lambda0.iter().copied().collect()),
                    bounds: c.bounds,
                })
                .collect(),
            solution: None,
        }
    }

    /// The problem in the file, checked: R must match, every array must have its size, each
    /// block given once, and [`LocalProblem::validate`] must pass.
    pub fn to_problem<const R: usize>(&self) -> Result<LocalProblem<R>, String> {
        super::json::check_format_and_version(&self.format, self.version)?;
        if self.form != LOCAL_FORM {
            return Err(format!("form is {:?}, expected {LOCAL_FORM:?}", self.form));
        }
        if self.rows_per_contact != R {
            return Err(format!(
                "rows_per_contact {} does not match the expected {R}",
                self.rows_per_contact
            ));
        }
        let n = self.contacts.len();
        let mut contacts = self
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let vector = |v: &[f64], what: &str| -> Result<SVector<f64, R>, String> {
                    if v.len() != R {
                        return Err(format!(
                            "contacts[{k}].{what} must have {R} entries, got {}",
                            v.len()
                        ));
                    }
                    Ok(SVector::from_column_slice(v))
                };
                Ok(LocalContact {
                    row: Vec::new(),
                    q: vector(&c.q, "q")?,
                    mu: c.mu,
                    lambda0: match &c.lambda0 {
                        Some(l) => vector(l, "lambda0")?,
                        None => SVector::zeros(),
                    },
                    bounds: c.bounds,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        for (i, b) in self.w.iter().enumerate() {
            if b.row >= n || b.col >= n {
                return Err(format!(
                    "W[{i}]: block ({}, {}) out of range (there are {n} contacts)",
                    b.row, b.col
                ));
            }
            if b.block.len() != R || b.block.iter().any(|r| r.len() != R) {
                return Err(format!("W[{i}].block must be {R}×{R}"));
            }
            let block = SMatrix::<f64, R, R>::from_fn(|r, s| b.block[r][s]);
            let row = &mut contacts[b.row].row;
            if row.iter().any(|(j, _)| *j == b.col) {
                return Err(format!("W[{i}]: block ({}, {}) given twice", b.row, b.col));
            }
            row.push((b.col, block));
        }
        for c in &mut contacts {
            c.row.sort_by_key(|(j, _)| *j);
        }
        let problem = LocalProblem {
            friction: self.friction,
            contacts,
        };
        problem.validate()?;
        Ok(problem)
    }
}

/// A contact-problem file of either form.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyProblemFile {
    /// Bodies, Jacobian, b ([`ProblemFile`]).
    Body(ProblemFile),
    /// W, q ([`LocalProblemFile`]).
    Local(LocalProblemFile),
}

impl AnyProblemFile {
    /// Parses a problem file's text: the local form where `form` is `"local"`, else the body
    /// form. Errors give the line and column.
    pub fn parse(text: &str) -> Result<AnyProblemFile, String> {
        let value = super::json::json_value(text)?;
        match value.get("form") {
            Some(serde_json::Value::String(f)) if f == LOCAL_FORM => serde_json::from_str(text)
                .map(AnyProblemFile::Local)
                .map_err(|e| e.to_string()),
            Some(other) => Err(format!(
                "form {other} is not known (\"local\", or no form key for the body form)"
            )),
            None => serde_json::from_str(text)
                .map(AnyProblemFile::Body)
                .map_err(|e| e.to_string()),
        }
    }

    /// Reads a problem file of either form; errors name the file.
    pub fn read(path: &std::path::Path) -> Result<AnyProblemFile, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        AnyProblemFile::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The local form of the file's problem (a body-form file converted by
    /// [`super::ContactProblem::to_local`]), with R rows per contact; for a body-form file D is
    /// 6 when R is 3 and 3 when R is 2.
    pub fn to_local<const R: usize>(&self) -> Result<LocalProblem<R>, String> {
        match self {
            AnyProblemFile::Local(file) => file.to_problem::<R>(),
            AnyProblemFile::Body(file) => match (file.dof_per_body, R) {
                (6, 3) => Ok(cast_rows(file.to_problem::<6, 3>()?.to_local())),
                (3, 2) => Ok(cast_rows(file.to_problem::<3, 2>()?.to_local())),
                (d, r) => Err(format!(
                    "dof_per_body {d} with rows_per_contact {} cannot be read with {r} rows \
                     per contact",
                    file.rows_per_contact
                )),
            },
        }
    }

    /// Rows per contact.
    pub fn rows_per_contact(&self) -> usize {
        match self {
            AnyProblemFile::Body(f) => f.rows_per_contact,
            AnyProblemFile::Local(f) => f.rows_per_contact,
        }
    }
}

/// A local problem of R₁ rows as one of R₂ rows, where R₁ = R₂ (checked by the caller's match:
/// const generics cannot say it).
fn cast_rows<const A: usize, const B: usize>(problem: LocalProblem<A>) -> LocalProblem<B> {
    assert_eq!(A, B, "rows per contact");
    LocalProblem {
        friction: problem.friction,
        contacts: problem
            .contacts
            .into_iter()
            .map(|c| LocalContact {
                row: c
                    .row
                    .into_iter()
                    .map(|(j, m)| (j, SMatrix::from_iterator(m.iter().copied())))
                    .collect(),
                q: SVector::from_iterator(c.q.iter().copied()),
                mu: c.mu,
                lambda0: SVector::from_iterator(c.lambda0.iter().copied()),
                bounds: c.bounds,
            })
            .collect(),
    }
}
