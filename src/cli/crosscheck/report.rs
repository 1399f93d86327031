//! What `rigidref crosscheck` reports: a row per problem, the summary and its verdict.

use rigidref::verify::crosscheck::{Comparison, ProblemCheck};

/// The tolerances the verdict is judged by (the command's options).
pub(crate) struct Limits {
    /// Largest relative λ difference accepted where λ is unique.
    pub(crate) tolerance: f64,
    /// Largest relative objective gap accepted where λ is not unique.
    pub(crate) objective_tolerance: f64,
    /// Unverified problems fail too.
    pub(crate) strict: bool,
}

/// One problem's check and where it came from.
#[derive(serde::Serialize)]
pub(crate) struct Row {
    pub(crate) source: String,
    #[serde(flatten)]
    pub(crate) check: ProblemCheck,
}

#[derive(serde::Serialize)]
pub(crate) struct Summary {
    pub(crate) input: String,
    pub(crate) problems: usize,
    pub(crate) compared: usize,
    pub(crate) unverified: usize,
    pub(crate) compared_by_lambda: usize,
    pub(crate) compared_by_objective: usize,
    pub(crate) max_lambda_difference: f64,
    pub(crate) median_lambda_difference: f64,
    pub(crate) max_objective_gap: f64,
    pub(crate) median_objective_gap: f64,
    pub(crate) worst: Option<String>,
    pub(crate) failures: usize,
    pub(crate) tolerance: f64,
    pub(crate) objective_tolerance: f64,
    /// `agree` (every problem verified within tolerance, or there were none), `unverified`
    /// (none disagrees, but some could not be checked: PGS did not converge) or `disagree`.
    pub(crate) verdict: &'static str,
    /// True only for `agree`.
    pub(crate) passed: bool,
    /// How PGS visited each contact: `rows` or `exact` (docs/contact.md §"Exact local solve").
    pub(crate) pgs_local_solve: &'static str,
    /// Whose answers were checked: `pgs` or `newton`.
    pub(crate) solver: &'static str,
    /// With PGS under test: the exact solver's answers, and the distances to them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) exact: Option<ExactSummary>,
    /// Cone friction: the largest exact Coulomb residual of PGS's answers (m/s; docs/contact.md
    /// §"The exact Coulomb residual").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) worst_coulomb_residual: Option<f64>,
    /// 3D scenes: the deepest interpenetration measured after any step of the run, m
    /// (docs/contact.md §"Penetration measure"), whatever contacts were found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) deepest_penetration: Option<f64>,
    /// The step after which it was measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) deepest_penetration_step: Option<u64>,
    /// 3D scenes: every substep's contacts held against the separating-axis oracle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) detection: Option<DetectionSummary>,
}

/// The detection audit of a 3D run (docs/contact.md §"The oracle campaign").
#[derive(serde::Serialize)]
pub(crate) struct DetectionSummary {
    /// Body pairs checked, summed over the substeps.
    pub(crate) pairs: u64,
    /// Of those, pairs overlapping by the oracle.
    pub(crate) overlapping: u64,
    /// Contacts between bodies checked.
    pub(crate) contacts: u64,
    /// Pairs not checked: a body not convex, or an analytic ellipsoid.
    pub(crate) skipped: u64,
    /// Pairs whose contacts disagree with the oracle.
    pub(crate) disagreements: u64,
    /// With the vertex rule: overlapping pairs its contacts do not reach (its known misses).
    pub(crate) vertex_rule_short: u64,
    /// The first few, with body names, step and substep.
    pub(crate) examples: Vec<String>,
}

impl DetectionSummary {
    pub(crate) fn of(a: &rigidref::rigid3d::collide::audit::DetectionAudit) -> DetectionSummary {
        DetectionSummary {
            pairs: a.pairs,
            overlapping: a.overlapping,
            contacts: a.contacts,
            skipped: a.skipped,
            disagreements: a.disagreements,
            vertex_rule_short: a.vertex_rule_short,
            examples: a.examples.clone(),
        }
    }
}

/// The exact reference over a run (PGS under test).
#[derive(serde::Serialize)]
pub(crate) struct ExactSummary {
    /// Problems the exact solver converged on.
    pub(crate) solved: usize,
    /// The largest distance of PGS's converged answers to the exact solution, max |u⁺ − u⁺_exact|,
    /// over the problems the exact solver converged on.
    pub(crate) max_answer_distance: f64,
    /// The largest distance of the steps' λ (what the run applied) to the exact solution.
    pub(crate) max_step_distance: Option<f64>,
    /// The largest residual of the steps' λ (the contact law's violation), m/s.
    pub(crate) max_step_residual: Option<f64>,
    /// Per unverified problem: where it came from, the distance of PGS's answer and of the
    /// step's λ to the exact solution, and the step λ's residual.
    pub(crate) unverified: Vec<UnverifiedDistance>,
}

/// How far one unverified problem's answers are from the exact solution.
#[derive(serde::Serialize)]
pub(crate) struct UnverifiedDistance {
    pub(crate) source: String,
    pub(crate) exact_converged: bool,
    pub(crate) answer_distance: f64,
    pub(crate) step_distance: Option<f64>,
    pub(crate) step_residual: Option<f64>,
}

/// Some problems could not be checked and none disagrees: exit status 3.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Unverified(pub String);

fn median(v: Vec<f64>) -> f64 {
    rigidref::common::stats::median(v).unwrap_or(0.0)
}

/// PGS converged when its residual is at most this (m/s); the run asks for 1e-12.
const CONVERGED: f64 = 1e-10;

pub(crate) fn summarise(input: &str, rows: &[Row], args: &Limits) -> Summary {
    let compared: Vec<&Row> = rows
        .iter()
        .filter(|r| r.check.residual_answer <= CONVERGED)
        .collect();
    let by = |c: Comparison| {
        compared
            .iter()
            .filter(|r| r.check.comparison == c)
            .map(|r| r.check.disagreement)
            .collect::<Vec<_>>()
    };
    let lambda = by(Comparison::Lambda);
    let objective = by(Comparison::Objective);
    let fails = |r: &&&Row| {
        !(r.check.qp_status == "Solved" || r.check.qp_status == "AlmostSolved")
            || match r.check.comparison {
                Comparison::Lambda => r.check.disagreement > args.tolerance,
                Comparison::Objective => r.check.disagreement > args.objective_tolerance,
            }
    };
    let mut failures = compared.iter().filter(fails).count();
    if args.strict {
        failures += rows.len() - compared.len();
    }
    // The worst relative to its own tolerance.
    let worst = compared
        .iter()
        .max_by(|a, b| {
            let ratio = |r: &Row| {
                r.check.disagreement
                    / match r.check.comparison {
                        Comparison::Lambda => args.tolerance,
                        Comparison::Objective => args.objective_tolerance,
                    }
            };
            ratio(a).total_cmp(&ratio(b))
        })
        .map(|r| {
            format!(
                "{}: {:?} {:.2e}",
                r.source, r.check.comparison, r.check.disagreement
            )
        });
    let verdict = if failures > 0 {
        "disagree"
    } else if rows.len() > compared.len() {
        "unverified"
    } else {
        "agree"
    };
    Summary {
        input: input.to_string(),
        problems: rows.len(),
        compared: compared.len(),
        unverified: rows.len() - compared.len(),
        compared_by_lambda: lambda.len(),
        compared_by_objective: objective.len(),
        max_lambda_difference: lambda.iter().copied().fold(0.0, f64::max),
        median_lambda_difference: median(lambda),
        max_objective_gap: objective.iter().copied().fold(0.0, f64::max),
        median_objective_gap: median(objective),
        worst,
        failures,
        tolerance: args.tolerance,
        objective_tolerance: args.objective_tolerance,
        verdict,
        passed: verdict == "agree",
        pgs_local_solve: rows.first().map_or("rows", |r| r.check.pgs_local_solve),
        solver: if rows.iter().any(|r| r.check.exact.is_none()) && !rows.is_empty() {
            "newton"
        } else {
            "pgs"
        },
        exact: exact_summary(rows),
        worst_coulomb_residual: rows
            .iter()
            .filter_map(|r| r.check.coulomb_residual_answer)
            .reduce(f64::max),
        deepest_penetration: None,
        deepest_penetration_step: None,
        detection: None,
    }
}

/// The exact reference's summary, where PGS was under test.
fn exact_summary(rows: &[Row]) -> Option<ExactSummary> {
    if rows.is_empty() || rows.iter().any(|r| r.check.exact.is_none()) {
        return None;
    }
    let exact = || rows.iter().filter_map(|r| r.check.exact.as_ref());
    let max = |v: Vec<f64>| v.into_iter().reduce(f64::max);
    // Distances to the exact solution count only where the exact solver converged: elsewhere
    // its answer is not a solution (those problems are listed with `exact_converged: false`).
    let solved = || exact().filter(|e| e.converged);
    Some(ExactSummary {
        solved: solved().count(),
        max_answer_distance: max(solved().map(|e| e.answer_distance).collect()).unwrap_or(0.0),
        max_step_distance: max(solved().filter_map(|e| e.step_distance).collect()),
        max_step_residual: max(exact().filter_map(|e| e.step_residual).collect()),
        unverified: rows
            .iter()
            .filter(|r| r.check.residual_answer > CONVERGED)
            .filter_map(|r| {
                let e = r.check.exact.as_ref()?;
                Some(UnverifiedDistance {
                    source: r.source.clone(),
                    exact_converged: e.converged,
                    answer_distance: e.answer_distance,
                    step_distance: e.step_distance,
                    step_residual: e.step_residual,
                })
            })
            .collect(),
    })
}
