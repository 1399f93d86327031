//! What `rigidref crosscheck` prints: the table of problems, the summary and the verdict's line.

use super::report::*;
use rigidref::verify::crosscheck::Comparison;

/// One line per problem.
pub(crate) fn print_table(rows: &[Row]) {
    println!(
        "{:<28} {:>8} {:<36} {:<9} {:>10} {:>10} {:>10} {:>7} {:<12} {:>10}",
        "problem",
        "contacts",
        "formulation",
        "compared",
        "disagree",
        "res answer",
        "res QP",
        "its",
        "clarabel",
        "to exact"
    );
    for r in rows {
        println!(
            "{:<28} {:>8} {:<36} {:<9} {:>10.2e} {:>10.2e} {:>10.2e} {:>7} {:<12} {:>10}",
            r.source,
            r.check.contacts,
            r.check.formulation,
            if r.check.comparison == Comparison::Lambda {
                "λ"
            } else {
                "objective"
            },
            r.check.disagreement,
            r.check.residual_answer,
            r.check.residual_qp,
            r.check.iterations,
            format!("{} ({})", r.check.qp_status, r.check.qp_iterations),
            r.check
                .exact
                .as_ref()
                .map_or("-".to_string(), |e| format!("{:.2e}", e.answer_distance)),
        );
    }
}

pub(crate) fn print_summary(s: &Summary) {
    println!("input            {}", s.input);
    println!(
        "problems         {} ({} compared: {} by λ, {} by objective; {} unverified: the answer did not converge)",
        s.problems, s.compared, s.compared_by_lambda, s.compared_by_objective, s.unverified
    );
    println!(
        "λ difference     max {:.2e}, median {:.2e} (tolerance {:.0e})",
        s.max_lambda_difference, s.median_lambda_difference, s.tolerance
    );
    println!(
        "objective gap    max {:.2e}, median {:.2e} (tolerance {:.0e})",
        s.max_objective_gap, s.median_objective_gap, s.objective_tolerance
    );
    println!("worst            {}", s.worst.as_deref().unwrap_or("-"));
    println!(
        "answers checked  {}",
        match s.solver {
            "newton" => "the Newton solver's (the step's own λ, what the run applied)",
            _ => "PGS's, run to convergence",
        }
    );
    if s.solver == "pgs" {
        println!("PGS visit        {}", s.pgs_local_solve);
    }
    if let Some(e) = &s.exact {
        println!(
            "exact solver     {} of {} problems solved by Newton (docs/contact.md §\"Newton solver\")",
            e.solved, s.problems
        );
        println!(
            "distance to the exact solution, max |u⁺ − u⁺_exact|: PGS converged {:.2e}{}",
            e.max_answer_distance,
            match (e.max_step_distance, e.max_step_residual) {
                (Some(d), Some(r)) => format!(
                    "; the steps' λ {d:.2e} (their residual, the contact law's violation, up to {r:.2e} m/s)"
                ),
                _ => String::new(),
            }
        );
        for u in &e.unverified {
            println!(
                "  unverified {}: distance to the exact solution {:.2e} (PGS after 200 000 sweeps){}{}",
                u.source,
                u.answer_distance,
                match (u.step_distance, u.step_residual) {
                    (Some(d), Some(r)) => format!(", {d:.2e} (the step's λ, residual {r:.2e})"),
                    _ => String::new(),
                },
                if u.exact_converged {
                    ""
                } else {
                    " [the exact solver did not converge either]"
                }
            );
        }
    }
    if let Some(r) = s.worst_coulomb_residual {
        println!(
            "Coulomb residual worst {r:.2e} m/s (the exact Coulomb law, De Saxcé's natural map, of PGS's answers)"
        );
    }
    if let (Some(depth), Some(step)) = (s.deepest_penetration, s.deepest_penetration_step) {
        println!(
            "penetration      deepest {depth:.3e} m, after step {step} (measured between the bodies, whatever contacts were found)"
        );
    }
    if let Some(d) = &s.detection {
        println!(
            "detection        {} pairs checked against the separating-axis oracle ({} overlapping, {} contacts between bodies, {} pairs not convex, not checked): {}",
            d.pairs,
            d.overlapping,
            d.contacts,
            d.skipped,
            if d.disagreements == 0 {
                "agree".to_string()
            } else {
                format!("{} disagree", d.disagreements)
            }
        );
        if d.vertex_rule_short > 0 {
            println!(
                "                 {} overlapping pairs whose vertex-rule contacts do not reach the overlap (the assignment's rule misses edge crossings and faces on faces; `collision: complete` finds them)",
                d.vertex_rule_short
            );
        }
        for e in &d.examples {
            println!("  {e}");
        }
    }
    println!("result           {}", describe_verdict(s));
}

/// The verdict as a sentence: agree, unverified or disagree, with the counts behind it.
pub(crate) fn describe_verdict(s: &Summary) -> String {
    match s.verdict {
        "disagree" => format!(
            "disagree: {} of {} problems beyond the tolerance{}{}",
            s.failures,
            s.problems,
            if s.unverified > 0 {
                format!(" ({} more unverified: not converged)", s.unverified)
            } else {
                String::new()
            },
            match &s.detection {
                Some(d) if d.disagreements > 0 => format!(
                    "; detection disagrees with the oracle on {} pairs",
                    d.disagreements
                ),
                _ => String::new(),
            }
        ),
        "unverified" => format!(
            "unverified: {} of {} problems could not be checked ({}); the {} compared agree{}",
            s.unverified,
            s.problems,
            if s.solver == "newton" {
                "the Newton solver did not converge to 1e-10 m/s"
            } else {
                "PGS did not converge to 1e-10 m/s within 200 000 sweeps"
            },
            s.compared,
            if s.solver == "pgs" {
                "; each one's distance to the exact solution is listed above; --set solver=newton solves every problem exactly and checks those answers"
            } else {
                ""
            }
        ),
        _ if s.problems == 0 => "agree: no contact problems to compare".to_string(),
        _ => format!(
            "agree: all {} problems verified within tolerance",
            s.problems
        ),
    }
}
