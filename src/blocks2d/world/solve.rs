//! Stage 5 and 6 of the 2D step ([`super`]): the contact solve of one substep (assemble → solve
//! → apply → warm-start store → post-stabilise), the pins' rows, and the penalty model's contact
//! forces. docs/blocks2d.md §"The step".

use super::*;

impl World2 {
    /// The velocity-level contact solve of one substep: assemble → solve (timed) → apply
    /// u⁺ = u + M⁻¹Jᵀλ → keep λ for the warm start → post-stabilise. Returns the record, its
    /// buffers taken from the pool of earlier steps'.
    pub(super) fn solve_contacts(&mut self, substep: u32, contacts: &[Contact2], h: f64) -> Solve2 {
        let clock = Instant::now();
        let mut solve = self.spare_solves.pop().unwrap_or_else(|| SubstepSolve {
            substep,
            contacts: Vec::new(),
            problem: empty_problem2(),
            lambda: Vec::new(),
            report: SolveReport::default(),
            solve_seconds: 0.0,
            solve_cpu_seconds: 0.0,
        });
        solve.substep = substep;
        solve.contacts.clear();
        solve.contacts.extend_from_slice(contacts);
        let warm = self.params.warm_start.then_some(&self.warm);
        assemble_problem2(
            &self.bodies,
            &self.before_kick,
            contacts,
            &self.params,
            warm,
            &mut solve.problem,
        );
        self.append_pins(&mut solve.problem);
        self.phase_times.assemble += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let settings = self.solver_settings();
        let (report, wall, cpu) = crate::common::timing::timed(|| {
            crate::solve::solve(
                &solve.problem,
                &settings,
                &mut self.workspace,
                &mut solve.lambda,
            )
        });
        solve.report = report;
        (solve.solve_seconds, solve.solve_cpu_seconds) = (wall, cpu.unwrap_or(0.0));
        if self.params.shock_propagation {
            // On a copy of λ: the record and the next warm start keep PGS's λ, which gives the
            // velocities through u⁺ = u + M⁻¹Jᵀλ; the pass's own impulses do not (its supports
            // feel no reaction), and warm-starting from them pushed each support down by the
            // load the pass had hidden from it (tower100 at 5–7 sweeps fell).
            self.shock_lambda.clone_from(&solve.lambda);
            let shock = propagate_shock(
                &solve.problem,
                &settings.pgs,
                &mut self.workspace.pgs,
                &mut self.shock_lambda,
            );
            self.shock_layers = self.shock_layers.max(shock.layers);
            solve.report.method = crate::problem::SolveMethod::PgsShock;
        }
        self.phase_times.solve += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        for (i, b) in self.bodies.iter_mut().enumerate() {
            let du = self.workspace.delta_velocity(i);
            b.v += Vector2::new(du[0], du[1]);
            b.omega += du[2];
        }
        self.warm.store(contacts, &solve.lambda);
        self.pin_warm.clear();
        self.pin_warm
            .extend_from_slice(&solve.lambda[contacts.len()..]);
        self.phase_times.apply += clock.elapsed().as_secs_f64();
        if self.params.post_stabilization {
            let clock = Instant::now();
            self.post_stabilize(contacts, &solve.problem, h);
            self.phase_times.measure += clock.elapsed().as_secs_f64();
        }
        solve
    }

    /// Appends the pins' rows to an assembled problem (after the contacts), b = J u, warm-started
    /// from the last solve's pin impulses. docs/blocks2d.md §"Springs, dampers and pins".
    pub(super) fn append_pins(&self, problem: &mut ContactProblem2) {
        if self.pins.is_empty() {
            return;
        }
        let velocities: Vec<Vector3<f64>> = problem.bodies.iter().map(|b| b.velocity).collect();
        for (k, pin) in self.pins.iter().enumerate() {
            let warm = match self.params.warm_start {
                true => self.pin_warm.get(k).copied().unwrap_or_default(),
                false => SVector::zeros(),
            };
            problem.contacts.push(pin.constraint(
                &self.bodies,
                &velocities,
                &Vector2::zeros(),
                warm,
            ));
        }
    }

    /// Cline and Pai's post-stabilisation: solve the same constraint rows for a velocity that
    /// would remove the penetration beyond the slop (and the pins' error) in one substep, μ = 0,
    /// for the position update alone; the velocity change is left in `normal_workspace` or
    /// `position_workspace` ([`World2::post_stabilization_rows`]). With PGS row by row and no
    /// pin, the normal rows alone: the same bits as both rows, since a tangent row bounded by
    /// μ λn = 0 never moves. docs/blocks2d.md §"Post-stabilisation".
    pub(super) fn post_stabilize(
        &mut self,
        contacts: &[Contact2],
        velocity_problem: &ContactProblem2,
        h: f64,
    ) {
        let settings = self.solver_settings();
        let normal_rows = self.post_stabilization_rows() == 1;
        let slop = self.params.slop;
        let report = if normal_rows {
            let problem = &mut self.normal_problem;
            velocity_problem.normal_rows_into(problem);
            for (pc, c) in problem.contacts.iter_mut().zip(contacts) {
                pc.b = SVector::<f64, 1>::new(-(c.depth - slop).max(0.0) / h);
                pc.mu = 0.0;
                pc.lambda0 = SVector::zeros();
            }
            if !self.stabilised_normal_rows {
                (self.normal_workspace.pgs).continue_orders_of(&self.position_workspace.pgs);
            }
            crate::solve::solve(
                &self.normal_problem,
                &settings,
                &mut self.normal_workspace,
                &mut self.normal_lambda,
            )
        } else {
            let problem = &mut self.position_problem;
            problem.friction = velocity_problem.friction;
            problem.bodies.clone_from(&velocity_problem.bodies);
            problem.contacts.clone_from(&velocity_problem.contacts);
            for (pc, c) in problem.contacts.iter_mut().zip(contacts) {
                pc.b = SVector::<f64, 2>::new(-(c.depth - slop).max(0.0) / h, 0.0);
                pc.mu = 0.0;
                pc.lambda0 = SVector::zeros();
            }
            // A pin's rows: J δu = −C/h, so that the position update closes the pin's error C.
            for (pc, pin) in problem.contacts[contacts.len()..]
                .iter_mut()
                .zip(&self.pins)
            {
                pc.b = pin.error(&self.bodies) / h;
                pc.lambda0 = SVector::zeros();
            }
            if self.stabilised_normal_rows {
                (self.position_workspace.pgs).continue_orders_of(&self.normal_workspace.pgs);
            }
            crate::solve::solve(
                &self.position_problem,
                &settings,
                &mut self.position_workspace,
                &mut self.position_lambda,
            )
        };
        self.stabilised_normal_rows = normal_rows;
        self.post_stabilization_residual = self.post_stabilization_residual.max(report.residual);
    }

    /// The rows per contact the next post-stabilisation solves: 1 (the normal rows alone)
    /// where the solve is PGS row by row and no pin adds its two free rows (and
    /// [`World2::set_normal_rows_post_stabilization`] has not turned it off), else 2.
    /// docs/blocks2d.md §"Post-stabilisation", "Normal rows only".
    pub fn post_stabilization_rows(&self) -> usize {
        let settings = self.solver_settings();
        let normal_rows = self.normal_rows_post_stabilization
            && self.pins.is_empty()
            && settings.solver == Solver::Pgs
            && settings.pgs.local == LocalSolve::Rows;
        if normal_rows { 1 } else { 2 }
    }

    /// Whether post-stabilisation may solve the normal rows alone where it can (on by
    /// default); off, it solves both rows of every contact. The same bits either way: for
    /// comparing the two (tests/suite/blocks2d/physics.rs).
    pub fn set_normal_rows_post_stabilization(&mut self, on: bool) {
        self.normal_rows_post_stabilization = on;
    }

    /// The starter's penalty contact: a spring k d plus damping c (approach speed) along the
    /// normal, equal and opposite on the two bodies at the contact point.
    pub(super) fn add_penalty_forces(&mut self, contacts: &[Contact2]) {
        for c in contacts {
            let (b1, b2) = (&self.bodies[c.body1], &self.bodies[c.body2]);
            let v1 = b1.v + Vector2::new(-(c.point - b1.x).y, (c.point - b1.x).x) * b1.omega;
            let v2 = b2.v + Vector2::new(-(c.point - b2.x).y, (c.point - b2.x).x) * b2.omega;
            let approach = (v1 - v2).dot(&c.normal);
            let magnitude = (self.params.penalty_stiffness * c.depth
                - self.params.penalty_damping * approach)
                .max(0.0);
            let f = c.normal * magnitude;
            self.bodies[c.body1].add_force_at(&f, &c.point);
            self.bodies[c.body2].add_force_at(&-f, &c.point);
        }
    }
}
