//! The one simulation interface both systems implement ([`Simulation`]), what one substep's
//! contact solve leaves behind ([`SubstepSolve`]), the one error a step can end in
//! ([`NonFinite`]), and the one driver loop ([`drive`]) with the one rule that turns a time into a
//! number of steps ([`steps_in`]). Every command and test that runs a world runs it through
//! [`drive`]. docs/architecture.md §"One interface, one loop".

use crate::problem::ContactProblem;
use crate::problem::SolveReport;
use crate::problem::json::{GeometryJson, ProblemFile, RunOrigin};
use nalgebra::SVector;

/// A simulation whose contact problems have `D` degrees of freedom per body and `R` rows per
/// contact: the 3D [`crate::rigid3d::world::World`] (6, 3) and the 2D
/// [`crate::blocks2d::world::World2`] (3, 2).
pub trait Simulation<const D: usize, const R: usize> {
    /// A contact as collision detection found it.
    type Contact: ContactGeometry + Clone;
    /// The energies, as a struct (J in 3D; mass · blocks² / time² in 2D).
    type Energy;
    /// The momenta, as a struct.
    type Momentum;

    /// Advances one step of [`Simulation::dt`] (all its substeps). On error the world holds the
    /// non-finite state, for inspection, and must not be stepped again.
    fn step(&mut self) -> Result<(), NonFinite>;
    /// Steps completed.
    fn steps_done(&self) -> u64;
    /// Simulated time, `steps_done · dt` (not a running sum, so it has no round-off drift).
    fn time(&self) -> f64;
    /// The step size (s in 3D, time units in 2D).
    fn dt(&self) -> f64;
    /// The substep size h = dt / substeps.
    fn h(&self) -> f64;
    /// The last step's contact solves, one per substep that solved a contact problem, in order.
    fn solves(&self) -> &[SubstepSolve<Self::Contact, D, R>];
    /// Energies now.
    fn energy(&self) -> Self::Energy;
    /// Momenta now.
    fn momentum(&self) -> Self::Momentum;
    /// Fails, naming the body and quantity, when a state component (or an energy) is not finite.
    fn check_finite(&self) -> Result<(), NonFinite>;
}

/// What a contact contributes to a problem file's geometry (docs/contact-problem-format.md).
pub trait ContactGeometry {
    /// The contact point, world frame (m in 3D, blocks in 2D).
    fn point(&self) -> Vec<f64>;
    /// The unit normal, from body 2 into body 1.
    fn normal(&self) -> Vec<f64>;
    /// Penetration depth, ≥ 0.
    fn depth(&self) -> f64;
}

/// Wall time per phase of a step, summed over the steps since the world was made, s
/// (`rigidref bench`, docs/performance.md). Both systems fill the phases they have.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Collision detection (3D: ground, broad phase, vertex and manifold contacts; 2D: broad
    /// phase and disc trees).
    pub detect: f64,
    /// Assembling the contact problem (Jacobians, Delassus diagonals, b, warm start).
    pub assemble: f64,
    /// PGS (2D: with shock propagation when it is on).
    pub solve: f64,
    /// Applying the impulses, storing the warm start and the record.
    pub apply: f64,
    /// Forces, velocity and position updates.
    pub integrate: f64,
    /// 3D: the penetration measure after each step. 2D: post-stabilisation's solve.
    pub measure: f64,
}

impl PhaseTimes {
    /// The phases in table order: detect, assemble, solve, apply, integrate, measure.
    pub fn as_array(&self) -> [f64; 6] {
        [
            self.detect,
            self.assemble,
            self.solve,
            self.apply,
            self.integrate,
            self.measure,
        ]
    }
}

/// One substep's contact solve: the contacts found, the problem assembled from them, the
/// impulses PGS returned, its report and how long it took. Kept for the trace,
/// `--dump-problems`, `rigidref contacts`, the crosscheck and the scaling report.
#[derive(Clone, Debug)]
pub struct SubstepSolve<C, const D: usize, const R: usize> {
    /// The substep within its step (0-based).
    pub substep: u32,
    /// The contacts collision detection found.
    pub contacts: Vec<C>,
    /// The problem assembled from them.
    pub problem: ContactProblem<D, R>,
    /// The impulses PGS returned and the world applied, one per contact (normal first).
    pub lambda: Vec<SVector<f64, R>>,
    /// What PGS did.
    pub report: SolveReport,
    /// Wall time of the PGS solve, s.
    pub solve_seconds: f64,
    /// CPU time this thread spent in the PGS solve, s: unlike the wall time it does not count
    /// time the thread was preempted on a shared machine. 0 where the platform cannot measure it.
    pub solve_cpu_seconds: f64,
}

/// A PGS solve counts as unresolved when its residual exceeds this fraction of the solve's
/// velocity scale (docs/contact.md §"Unresolved solves").
pub const UNRESOLVED_FRACTION: f64 = 0.1;

impl<C, const D: usize, const R: usize> SubstepSolve<C, D, R> {
    /// The velocity scale of the solve: max(|g| h, max_k ‖b_k‖∞), the speed gravity gives a body
    /// in one substep or the fastest constraint velocity the solve starts from (m/s in 3D).
    pub fn velocity_scale(&self, gravity_h: f64) -> f64 {
        self.problem
            .contacts
            .iter()
            .map(|c| c.b.amax())
            .fold(gravity_h, f64::max)
    }

    /// Whether the answer is too far from a solution to trust: the Newton solver did not
    /// converge, or PGS ended with a residual above [`UNRESOLVED_FRACTION`] of the velocity
    /// scale (and above its tolerance, when one was set and not reached). docs/contact.md
    /// §"Unresolved solves".
    pub fn unresolved(&self, gravity_h: f64) -> bool {
        match self.report.method {
            crate::problem::SolveMethod::Pgs | crate::problem::SolveMethod::PgsShock => {
                !self.report.converged
                    && self.report.residual > UNRESOLVED_FRACTION * self.velocity_scale(gravity_h)
            }
            _ => !self.report.converged,
        }
    }
}

impl<C: ContactGeometry, const D: usize, const R: usize> SubstepSolve<C, D, R> {
    /// The problem as a contact-problem file (docs/contact-problem-format.md), with the contacts'
    /// geometry, where it came from (`scene`, step `step`, substep length `h`) and the solution.
    pub fn problem_file(&self, scene: &str, step: u64, h: f64) -> ProblemFile {
        let origin = RunOrigin {
            scene,
            step,
            substep: self.substep,
            h,
        };
        let geometry = self.contacts.iter().map(|c| GeometryJson {
            p: c.point(),
            n: c.normal(),
            depth: c.depth(),
        });
        let criteria = crate::solve::criteria::criteria(&self.problem, &self.lambda).0;
        ProblemFile::of_run(
            &self.problem,
            origin,
            geometry,
            &self.lambda,
            &self.report,
            criteria,
        )
    }
}

/// A step's solves summed over its substeps: what the scaling report and the summaries use.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveTotals {
    /// Contacts solved, summed over the substeps.
    pub contacts: usize,
    /// The most contacts in one substep.
    pub most_contacts: usize,
    /// PGS sweeps, summed over the substeps.
    pub sweeps: u64,
    /// The largest residual of a solve.
    pub worst_residual: f64,
    /// Wall time of the PGS solves, s.
    pub solve_seconds: f64,
    /// Thread CPU time of the PGS solves, s (0 where not measurable).
    pub solve_cpu_seconds: f64,
}

impl SolveTotals {
    /// The totals of `solves`.
    pub fn of<C, const D: usize, const R: usize>(solves: &[SubstepSolve<C, D, R>]) -> SolveTotals {
        let mut t = SolveTotals::default();
        for s in solves {
            t.contacts += s.contacts.len();
            t.most_contacts = t.most_contacts.max(s.contacts.len());
            t.sweeps += u64::from(s.report.iterations);
            t.worst_residual = t.worst_residual.max(s.report.residual);
            t.solve_seconds += s.solve_seconds;
            t.solve_cpu_seconds += s.solve_cpu_seconds;
        }
        t
    }
}

/// A run's solves summed over its steps: what the run summaries of both systems report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunTotals {
    /// Steps with at least one contact solve.
    pub steps_with_contacts: u64,
    /// Contact solves (one per substep with contacts).
    pub solves: u64,
    /// The most contacts in one solve.
    pub most_contacts: usize,
    /// PGS sweeps, summed over the solves.
    pub sweeps: u64,
    /// The largest residual a solve ended with.
    pub worst_residual: f64,
    /// Cone friction: the largest exact Coulomb residual a solve ended with (m/s in 3D;
    /// docs/contact.md §"The exact Coulomb residual"); `None` when no solve reported one.
    pub worst_coulomb_residual: Option<f64>,
    /// The deepest penetration of a contact found (m in 3D, blocks in 2D).
    pub deepest: f64,
    /// The deepest interpenetration the system measured between bodies, whatever contacts were
    /// found (3D's penetration measure, m); `None` where the system has no such measure (2D).
    pub measured: Option<f64>,
    /// Solves answered by the Newton solver (its fallback's included).
    pub newton: u64,
    /// Solves answered by the Newton solver's proximal-point fallback.
    pub proximal: u64,
    /// Unresolved solves ([`SubstepSolve::unresolved`]).
    pub unresolved: u64,
    /// The largest residual of an unresolved solve, and the step it ended.
    pub worst_unresolved: Option<(f64, u64)>,
    /// Exact local-solve visits that took the best candidate (`SolveReport::local_fallbacks`),
    /// summed over the run.
    pub local_fallbacks: u64,
    /// The largest of each physical criterion over every contact of the run (docs/contact.md
    /// §"Physical criteria"); `None` before the first solve.
    pub criteria: Option<crate::problem::ContactCriteria>,
}

impl RunTotals {
    /// Adds step `step`'s solves; `gravity_h` is |g| times the substep (the velocity scale's
    /// floor, [`SubstepSolve::velocity_scale`]).
    pub fn add<C: ContactGeometry, const D: usize, const R: usize>(
        &mut self,
        solves: &[SubstepSolve<C, D, R>],
        step: u64,
        gravity_h: f64,
    ) {
        if !solves.is_empty() {
            self.steps_with_contacts += 1;
        }
        self.solves += solves.len() as u64;
        let t = SolveTotals::of(solves);
        self.most_contacts = self.most_contacts.max(t.most_contacts);
        self.sweeps += t.sweeps;
        self.worst_residual = self.worst_residual.max(t.worst_residual);
        for s in solves {
            self.local_fallbacks += u64::from(s.report.local_fallbacks);
            match s.report.method {
                crate::problem::SolveMethod::Pgs | crate::problem::SolveMethod::PgsShock => {}
                crate::problem::SolveMethod::Newton => self.newton += 1,
                crate::problem::SolveMethod::Proximal => {
                    self.newton += 1;
                    self.proximal += 1;
                }
            }
            let worst = crate::solve::criteria::criteria(&s.problem, &s.lambda).1;
            self.criteria = Some(self.criteria.map_or(worst, |c| c.max(&worst)));
            if s.unresolved(gravity_h) {
                self.unresolved += 1;
                // The measure that failed: a cone Newton solve can fail on the exact Coulomb
                // residual alone.
                let r = s
                    .report
                    .residual
                    .max(s.report.coulomb_residual.unwrap_or(0.0));
                if self.worst_unresolved.is_none_or(|(w, _)| r > w) {
                    self.worst_unresolved = Some((r, step));
                }
            }
            if let Some(r) = s.report.coulomb_residual {
                self.worst_coulomb_residual =
                    Some(self.worst_coulomb_residual.map_or(r, |w: f64| w.max(r)));
            }
            for c in &s.contacts {
                self.deepest = self.deepest.max(c.depth());
            }
        }
    }

    /// The summary line: solves, the most contacts, PGS's mean sweeps and worst residual, the
    /// deepest penetration (the measured one where the system measures it, with the deepest
    /// contact beside it); `velocity` and `length` name the units.
    pub fn describe(&self, velocity: &str, length: &str) -> String {
        let penetration = match self.measured {
            Some(m) => format!(
                "deepest penetration {m:.3e} {length} (measured between the bodies; deepest contact found {:.3e} {length})",
                self.deepest
            ),
            None => format!("deepest penetration {:.3e} {length}", self.deepest),
        };
        if self.solves == 0 {
            return match self.measured {
                Some(m) if m > 0.0 => format!("none found; {penetration}"),
                _ => "none".to_string(),
            };
        }
        let coulomb = match self.worst_coulomb_residual {
            Some(r) => format!(" (exact Coulomb residual {r:.3e} {velocity})"),
            None => String::new(),
        };
        let solver = match (self.newton, self.proximal) {
            (0, _) => "PGS {:.1} sweeps on average".to_string(),
            (_, 0) => "Newton {:.1} iterations on average".to_string(),
            (_, p) => {
                format!("Newton {{:.1}} iterations on average ({p} by its proximal fallback)")
            }
        }
        .replace(
            "{:.1}",
            &format!("{:.1}", self.sweeps as f64 / self.solves as f64),
        );
        let mut unresolved = match self.unresolved {
            0 => String::new(),
            n => format!("; {n} unresolved ({})", self.unresolved_reason()),
        };
        if self.local_fallbacks > 0 {
            unresolved.push_str(&format!(
                "; the exact local solve took its best candidate in {} visits (no case exact to round-off)",
                self.local_fallbacks
            ));
        }
        format!(
            "{} solves in {} steps, up to {} contacts; {solver}, worst residual {:.3e} {velocity}{coulomb}{unresolved}, {penetration}",
            self.solves, self.steps_with_contacts, self.most_contacts, self.worst_residual,
        )
    }

    /// The summary's criteria line (docs/contact.md §"Physical criteria"): the largest of each
    /// over the run; `impulse`, `velocity` and `energy` name the units.
    pub fn describe_criteria(&self, impulse: &str, velocity: &str, energy: &str) -> Option<String> {
        let c = self.criteria?;
        Some(format!(
            "primal {:.2e} {impulse}, dual {:.2e} {velocity}, complementarity {:.2e} {energy} (signorini {:.2e}, cone boundary {:.2e}, max dissipation {:.2e}); largest over every contact, against Coulomb's cone",
            c.primal, c.dual, c.complementarity, c.signorini, c.cone_boundary, c.max_dissipation
        ))
    }

    /// What made the unresolved solves unresolved, in a few words.
    fn unresolved_reason(&self) -> &'static str {
        if self.newton > 0 {
            "Newton did not converge"
        } else {
            "PGS residual above a tenth of the solve's velocity scale"
        }
    }

    /// The run's one warning about unresolved solves, if there were any: how many, the worst
    /// residual and its step, and what helps. `velocity` names the unit.
    pub fn unresolved_warning(&self, velocity: &str) -> Option<String> {
        let (worst, step) = self.worst_unresolved?;
        let help = if self.newton > 0 {
            "the answers of those solves are the best the Newton solver found, not solutions; see docs/contact.md §\"Unresolved solves\""
        } else {
            "their impulses are far from the contact law's; `--set solver=newton` solves every contact problem exactly (or raise the sweeps: pgs_iterations in 3D, iterations in 2D)"
        };
        Some(format!(
            "warning: {} of {} contact solves unresolved ({}), worst residual {worst:.3e} {velocity} at step {step}: {help}",
            self.unresolved,
            self.solves,
            self.unresolved_reason()
        ))
    }
}

/// A state component or an energy became NaN or infinite; the run must stop there (contacts of
/// a non-finite body are meaningless, and JSON has no NaN).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("non-finite {quantity}{} at step {step}{} (t = {})",
    .body.as_ref().map_or(String::new(), |b| b.describe()),
    .substep.map_or(String::new(), |s| format!(", substep {s}")),
    readable(*.time))]
pub struct NonFinite {
    /// Which quantity, e.g. "angular velocity ω" or "energy (kinetic 1e308, potential inf)".
    pub quantity: String,
    /// The body it belongs to (none for a system quantity such as the energy).
    pub body: Option<BodyId>,
    /// The step in which it happened (1-based: the step being computed).
    pub step: u64,
    /// The substep within that step, where the system checks per substep (3D).
    pub substep: Option<u32>,
    /// The time of the state found non-finite: the start of the substep in 3D (checked per
    /// substep), the end of the step in 2D (checked per step).
    pub time: f64,
}

/// A body named in a message: its index and, where it has one, its name.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyId {
    /// Index in the scene.
    pub index: usize,
    /// Its name (3D scenes name their bodies; 2D bodies have none).
    pub name: Option<String>,
}

impl BodyId {
    fn describe(&self) -> String {
        match &self.name {
            Some(name) => format!(" in body {} ({name:?})", self.index),
            None => format!(" in body {}", self.index),
        }
    }
}

/// A number for a message: as written when moderate, in exponent form when huge or tiny (an
/// absurd step of 1e300 must not print 300 digits).
pub fn readable(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The most steps one run may take: far beyond any useful run (a day at a microsecond a step),
/// so that a step size like 1e-300 is an error rather than a run that never ends.
pub const MAX_STEPS: f64 = 1e11;

/// Refuses a run of more than [`MAX_STEPS`] steps of size `dt`.
pub fn check_step_count(steps: f64, dt: f64) -> Result<(), String> {
    if steps > MAX_STEPS {
        return Err(format!(
            "{steps:.3e} steps of {dt:.3e} is more than the limit of {MAX_STEPS:.0e}; ask for fewer steps (a larger step size or a shorter time)"
        ));
    }
    Ok(())
}

/// The one time-to-steps rule: the whole steps of size `dt` in `time`, at least 1. The 1e-9
/// guards quotients such as 0.3 / 0.1 = 2.9999999999999996 against losing a step. Fails when
/// `time` is not a positive number (`unit` names its unit in the message, e.g. " of seconds") or
/// the count is beyond [`MAX_STEPS`].
pub fn steps_in(time: f64, dt: f64, unit: &str) -> Result<u64, String> {
    if !(time.is_finite() && time > 0.0) {
        return Err(format!(
            "--time must be a positive number{unit}, got {time}"
        ));
    }
    let steps = whole_steps(time, dt).max(1.0);
    check_step_count(steps, dt)?;
    Ok(steps as u64)
}

/// The whole steps of size `dt` in `time`, as a float (no minimum, no limit): the rule of
/// [`steps_in`] for callers that must compare counts before converting them.
pub fn whole_steps(time: f64, dt: f64) -> f64 {
    (time / dt + 1e-9).floor()
}

/// Whether step `k` of a run of `steps` is recorded when recording every `every`-th step: the
/// multiples of `every` and the last step (the initial state, step 0, is recorded by the caller).
pub fn is_recorded(k: u64, steps: u64, every: u64) -> bool {
    k.is_multiple_of(every) || k == steps
}

/// What the driver does after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on to the next step.
    Continue,
    /// Stop after this step (e.g. `stop_on_contact`, a first contact found, a factory that is done).
    Stop,
}

/// The one driver loop: steps `sim` up to `steps` times, calling `after(sim, k)` after step k
/// (1-based) to record, report or decide to stop (and, for a run that changes its world between
/// steps such as the factory's drops, to change it). Returns the number of steps run. A step that
/// ends in a non-finite state stops the run with that error (converted into the caller's error
/// type); whatever `after` wrote for the earlier steps stays written.
pub fn drive<S, E, const D: usize, const R: usize>(
    sim: &mut S,
    steps: u64,
    mut after: impl FnMut(&mut S, u64) -> Result<Flow, E>,
) -> Result<u64, E>
where
    S: Simulation<D, R>,
    E: From<NonFinite>,
{
    for k in 1..=steps {
        sim.step()?;
        if after(sim, k)? == Flow::Stop {
            return Ok(k);
        }
    }
    Ok(steps)
}

impl From<NonFinite> for String {
    fn from(e: NonFinite) -> String {
        e.to_string()
    }
}

/// What the contact solves of a recorded frame did: a trace record's `solver` key
/// (docs/trace-format.md), absent when the frame solved no contact problem. Both systems.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverRecord {
    /// The method that produced the frame's answers: `pgs`, `newton`, or `proximal` when the
    /// Newton solver's proximal fallback produced at least one of them (docs/contact.md §"Newton
    /// solver"). Traces written before the Newton solver have no key: `pgs`.
    #[serde(default)]
    pub solver: crate::problem::SolveMethod,
    /// Contact solves in the frame (one per substep with contacts).
    pub solves: u32,
    /// Iterations, summed over the frame's solves: PGS sweeps, or Newton iterations.
    pub sweeps: u64,
    /// The largest residual a solve of the frame ended with (m/s in 3D, blocks/time in 2D).
    pub residual: f64,
    /// Cone friction: the largest exact Coulomb residual of the frame's solves (same unit;
    /// docs/contact.md §"The exact Coulomb residual"); absent with box friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coulomb_residual: Option<f64>,
    /// The largest of each physical criterion over the frame's contacts (docs/contact.md
    /// §"Physical criteria"): `primal` N·s, `dual` m/s, the others J (2D: the system's units).
    /// Absent in traces written before the criteria existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub criteria: Option<crate::problem::ContactCriteria>,
}

impl SolverRecord {
    /// The record of a frame's `solves`; `None` when there were none.
    pub fn of<C, const D: usize, const R: usize>(
        solves: &[SubstepSolve<C, D, R>],
    ) -> Option<SolverRecord> {
        if solves.is_empty() {
            return None;
        }
        let method = solves
            .iter()
            .map(|s| s.report.method)
            .max_by_key(|m| *m as u8)
            .unwrap_or_default();
        let mut r = SolverRecord {
            solver: method,
            solves: solves.len() as u32,
            sweeps: 0,
            residual: 0.0,
            coulomb_residual: None,
            criteria: None,
        };
        let mut worst = crate::solve::criteria::ContactCriteria::default();
        for s in solves {
            worst = worst.max(&crate::solve::criteria::criteria(&s.problem, &s.lambda).1);
            r.sweeps += u64::from(s.report.iterations);
            r.residual = r.residual.max(s.report.residual);
            if let Some(c) = s.report.coulomb_residual {
                r.coulomb_residual = Some(r.coulomb_residual.map_or(c, |w| w.max(c)));
            }
        }
        r.criteria = Some(worst);
        Some(r)
    }
}
