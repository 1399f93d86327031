//! The 2D parameters a scene file, the command line or `--set` may give: each optional, checked
//! once by [`ParamOverrides2::resolve`] into [`crate::blocks2d::params::Params2`].

use super::*;

/// The 2D parameters a scene file or the command line may set. Each is optional: what is not set
/// keeps [`Params2::default`]'s value. One check, [`ParamOverrides2::resolve`], serves both sources.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamOverrides2 {
    /// The preset the others override (default: [`Preset::Default`]).
    pub preset: Option<Preset>,
    /// Step size.
    pub step: Option<f64>,
    /// Substeps per step.
    pub substeps: Option<u32>,
    /// Gravity magnitude, blocks per time².
    pub gravity: Option<f64>,
    /// Gravity direction, degrees from +x toward +y.
    pub gravity_angle: Option<f64>,
    /// Friction coefficient.
    pub mu: Option<f64>,
    /// Coefficient of restitution, in [0, 1].
    pub restitution: Option<f64>,
    /// PGS sweeps per solve.
    pub iterations: Option<u32>,
    /// Early stop on PGS's residual.
    pub pgs_tolerance: Option<f64>,
    /// Contact order in PGS.
    pub order: Option<ContactOrder>,
    /// Seed of the random order.
    pub seed: Option<u64>,
    /// How a PGS visit updates its contact.
    pub pgs_local_solve: Option<LocalSolve>,
    /// Warm start.
    pub warm_start: Option<bool>,
    /// Post-stabilisation.
    pub post_stabilization: Option<bool>,
    /// Penetration left alone by post-stabilisation, blocks.
    pub slop: Option<f64>,
    /// PGS or penalty contacts.
    pub contact_model: Option<ContactModel>,
    /// Near-white threshold of the image, in [0, 1).
    pub white_threshold: Option<f64>,
    /// Adaptive substeps: the most a block may move per substep, blocks.
    pub max_travel: Option<f64>,
    /// Shock propagation after each velocity solve.
    pub shock_propagation: Option<bool>,
    /// The contact solver: PGS or the exact Newton solver.
    pub solver: Option<Solver>,
    /// Threads of the coloured order's sweeps.
    pub threads: Option<u32>,
    /// Keep candidate lists between steps (the same contacts).
    pub detection_cache: Option<bool>,
    /// Compare cached with fresh detection every substep.
    pub check_detection: Option<bool>,
    /// How bodies' inertia comes from their blocks.
    pub inertia: Option<InertiaRule>,
    /// How disc trees are built and descended.
    pub disc_tree: Option<DiscTreeRule>,
    /// How the image is read into bodies (their numbering).
    pub image_reader: Option<ImageReader>,
}

/// A parameter out of its range: the key (as in a scene file) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The key, e.g. `white_threshold`.
    pub key: &'static str,
    /// What is wrong, e.g. "must be in [0, 1), got 1".
    pub message: String,
}

impl ParamOverrides2 {
    /// The keys that are set.
    pub fn given(&self) -> Vec<&'static str> {
        [
            ("preset", self.preset.is_some()),
            ("step", self.step.is_some()),
            ("substeps", self.substeps.is_some()),
            ("gravity", self.gravity.is_some()),
            ("gravity_angle", self.gravity_angle.is_some()),
            ("mu", self.mu.is_some()),
            ("restitution", self.restitution.is_some()),
            ("iterations", self.iterations.is_some()),
            ("pgs_tolerance", self.pgs_tolerance.is_some()),
            ("order", self.order.is_some()),
            ("seed", self.seed.is_some()),
            ("pgs_local_solve", self.pgs_local_solve.is_some()),
            ("warm_start", self.warm_start.is_some()),
            ("post_stabilization", self.post_stabilization.is_some()),
            ("slop", self.slop.is_some()),
            ("contact_model", self.contact_model.is_some()),
            ("white_threshold", self.white_threshold.is_some()),
            ("max_travel", self.max_travel.is_some()),
            ("shock_propagation", self.shock_propagation.is_some()),
            ("solver", self.solver.is_some()),
            ("threads", self.threads.is_some()),
            ("detection_cache", self.detection_cache.is_some()),
            ("check_detection", self.check_detection.is_some()),
            ("inertia", self.inertia.is_some()),
            ("disc_tree", self.disc_tree.is_some()),
            ("image_reader", self.image_reader.is_some()),
        ]
        .into_iter()
        .filter_map(|(key, set)| set.then_some(key))
        .collect()
    }

    /// The parameters and image settings, with the preset's values filled in where none is
    /// given, after checking every value's range (the one check of 2D parameters, for files and
    /// the command line alike).
    pub fn resolve(&self) -> Result<(Params2, ImageSettings), ParamError> {
        let d = self.preset.unwrap_or_default().params();
        let p = Params2 {
            dt: self.step.unwrap_or(d.dt),
            substeps: self.substeps.unwrap_or(d.substeps),
            gravity: self.gravity.unwrap_or(d.gravity),
            gravity_angle: self.gravity_angle.unwrap_or(d.gravity_angle),
            mu: self.mu.unwrap_or(d.mu),
            restitution: self.restitution.unwrap_or(d.restitution),
            iterations: self.iterations.unwrap_or(d.iterations),
            tolerance: self.pgs_tolerance,
            order: self.order.unwrap_or(d.order),
            seed: self.seed.unwrap_or(d.seed),
            local_solve: self.pgs_local_solve.unwrap_or(d.local_solve),
            warm_start: self.warm_start.unwrap_or(d.warm_start),
            post_stabilization: self.post_stabilization.unwrap_or(d.post_stabilization),
            slop: self.slop.unwrap_or(d.slop),
            contact_model: self.contact_model.unwrap_or(d.contact_model),
            max_travel: self.max_travel.or(d.max_travel),
            shock_propagation: self.shock_propagation.unwrap_or(d.shock_propagation),
            solver: self.solver.unwrap_or(d.solver),
            threads: self.threads.unwrap_or(d.threads),
            detection_cache: self.detection_cache.unwrap_or(d.detection_cache),
            check_detection: self.check_detection.unwrap_or(d.check_detection),
            inertia: self.inertia.unwrap_or(d.inertia),
            disc_tree: self.disc_tree.unwrap_or(d.disc_tree),
            image_reader: self.image_reader.unwrap_or(d.image_reader),
            ..d
        };
        let white_threshold = self
            .white_threshold
            .unwrap_or(ImageSettings::default().white_threshold);
        let fail = |key, message: String| Err(ParamError { key, message });
        let positive = |x: f64| x.is_finite() && x > 0.0;
        let non_negative = |x: f64| x.is_finite() && x >= 0.0;
        if !positive(p.dt) {
            return fail("step", format!("must be a positive number, got {}", p.dt));
        }
        if p.substeps == 0 {
            return fail("substeps", "must be at least 1".into());
        }
        if p.iterations == 0 {
            return fail("iterations", "must be at least 1".into());
        }
        for (key, x) in [
            ("gravity", p.gravity),
            ("mu", p.mu),
            ("restitution", p.restitution),
            ("slop", p.slop),
        ] {
            if !non_negative(x) {
                return fail(key, format!("must be a number ≥ 0, got {x}"));
            }
        }
        if !p.gravity_angle.is_finite() {
            return fail("gravity_angle", "must be finite".into());
        }
        if p.restitution > 1.0 {
            return fail(
                "restitution",
                format!("must be in [0, 1], got {}", p.restitution),
            );
        }
        if let Some(t) = p.tolerance
            && !positive(t)
        {
            return fail(
                "pgs_tolerance",
                format!("must be a positive number, got {t}"),
            );
        }
        if let Some(t) = p.max_travel
            && !positive(t)
        {
            return fail("max_travel", format!("must be a positive number, got {t}"));
        }
        if p.shock_propagation && p.solver == Solver::Newton {
            return fail(
                "shock_propagation",
                "is a pass after PGS; with solver newton every solve is exact already: turn one of them off".into(),
            );
        }
        if !(0.0..1.0).contains(&white_threshold) {
            return fail(
                "white_threshold",
                format!("must be in [0, 1), got {white_threshold}"),
            );
        }
        let settings = ImageSettings {
            white_threshold,
            reader: p.image_reader,
        };
        Ok((p, settings))
    }
}

impl ParamOverrides2 {
    /// These values, with `other`'s where these are not set.
    pub fn or(&self, other: &ParamOverrides2) -> ParamOverrides2 {
        ParamOverrides2 {
            preset: self.preset.or(other.preset),
            step: self.step.or(other.step),
            substeps: self.substeps.or(other.substeps),
            gravity: self.gravity.or(other.gravity),
            gravity_angle: self.gravity_angle.or(other.gravity_angle),
            mu: self.mu.or(other.mu),
            restitution: self.restitution.or(other.restitution),
            iterations: self.iterations.or(other.iterations),
            pgs_tolerance: self.pgs_tolerance.or(other.pgs_tolerance),
            order: self.order.or(other.order),
            seed: self.seed.or(other.seed),
            pgs_local_solve: self.pgs_local_solve.or(other.pgs_local_solve),
            warm_start: self.warm_start.or(other.warm_start),
            post_stabilization: self.post_stabilization.or(other.post_stabilization),
            slop: self.slop.or(other.slop),
            contact_model: self.contact_model.or(other.contact_model),
            threads: self.threads.or(other.threads),
            white_threshold: self.white_threshold.or(other.white_threshold),
            max_travel: self.max_travel.or(other.max_travel),
            shock_propagation: self.shock_propagation.or(other.shock_propagation),
            solver: self.solver.or(other.solver),
            detection_cache: self.detection_cache.or(other.detection_cache),
            check_detection: self.check_detection.or(other.check_detection),
            inertia: self.inertia.or(other.inertia),
            disc_tree: self.disc_tree.or(other.disc_tree),
            image_reader: self.image_reader.or(other.image_reader),
        }
    }
}
