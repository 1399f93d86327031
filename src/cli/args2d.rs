//! The 2D system's option group (`--step`, `--mu`, `--impulse`, …; clap `flatten`) and the
//! parsers of its scripted impulses and shakes.

use super::args::{HEADING_2D, SceneSets};

use clap::Args;
use nalgebra::Vector2;
use rigidref::blocks2d::scene::{LoadOptions2, ParamOverrides2};
use rigidref::blocks2d::world::{ScriptedImpulse, Shake};

/// The 2D system's physics options (for an image; a 2D scene file sets its own parameters).
#[derive(Args, Clone, Debug, Default)]
#[command(next_help_heading = HEADING_2D)]
pub struct Blocks2dOptions {
    /// 2D: the parameters to start from: `default` (the demonstration settings: 4 substeps, 200
    /// sweeps in random order, warm start, post-stabilisation) or `starter` (everything the Java
    /// starter's code does: 1 substep, 10 sweeps in the order found, no warm start, no
    /// post-stabilisation, point-mass inertia, its body numbering and disc trees;
    /// docs/blocks2d.md §"The starter preset"); the options below override it [default: default].
    /// A 3D scene takes it too, as `--set preset=NAME` (the 3D Python starter's behaviour:
    /// docs/scene-format.md §"The starter preset").
    #[arg(long, value_enum)]
    pub preset: Option<rigidref::blocks2d::params::Preset>,
    /// 2D: step size [default: 0.05, the starter's].
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// 2D: substeps per step [default: 4; starter: 1].
    #[arg(long)]
    pub substeps: Option<u32>,
    /// 2D: gravity magnitude, blocks per time² [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f64>,
    /// 2D: gravity direction, degrees from +x (image column) toward +y (image row, down)
    /// [default: 90, toward increasing row].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity_angle: Option<f64>,
    /// 2D: friction coefficient [default: 0.33].
    #[arg(long, allow_negative_numbers = true)]
    pub mu: Option<f64>,
    /// 2D: coefficient of restitution in [0, 1] [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub restitution: Option<f64>,
    /// 2D: PGS iterations per solve [default: 200; starter: 10, with which the demonstration
    /// images do not come to rest: docs/blocks2d.md §"Demonstration settings"].
    #[arg(long)]
    pub iterations: Option<u32>,
    /// 2D: stop PGS when its residual is below this.
    #[arg(long, allow_negative_numbers = true)]
    pub pgs_tolerance: Option<f64>,
    /// 2D: contact order in PGS [default: random; starter: sequential].
    #[arg(long, value_enum)]
    pub order: Option<rigidref::solve::ContactOrder>,
    /// 2D: seed of the random order [default: 0].
    #[arg(long)]
    pub seed: Option<u64>,
    /// 2D: how a PGS visit updates its contact: `rows` (normal row, then friction row) or `exact`
    /// (the contact's 2 × 2 problem solved exactly) [default: rows].
    #[arg(long, value_enum)]
    pub pgs_local_solve: Option<rigidref::solve::LocalSolve>,
    /// 2D: start each solve cold (the starter preset does; `--set warm_start=true` turns it on).
    #[arg(long)]
    pub no_warm_start: bool,
    /// 2D: no post-stabilisation of penetration (the starter preset has none).
    #[arg(long)]
    pub no_post_stabilization: bool,
    /// 2D: penetration left alone by post-stabilisation, blocks [default: 0.01].
    #[arg(long, allow_negative_numbers = true)]
    pub slop: Option<f64>,
    /// 2D: contact model [default: pgs].
    #[arg(long, value_enum)]
    pub contact_model: Option<rigidref::blocks2d::params::ContactModel>,
    /// 2D: near-white threshold: a pixel is empty when every channel is ≥ 1 − this [default: 0.05].
    #[arg(long, allow_negative_numbers = true)]
    pub white_threshold: Option<f64>,
    /// 2D: a body's inertia: `blocks` (Σ m (r² + 1/6), each block a unit square) or
    /// `block_centres` (Σ m r², point masses, one block m/6: the starter's) [default: blocks;
    /// starter: block_centres].
    #[arg(long, value_enum)]
    pub inertia: Option<rigidref::blocks2d::body::InertiaRule>,
    /// 2D: how bodies are numbered and their blocks read: `rigidref` (row by row) or `starter`
    /// (column by column, as the starter's ImageBlocker) [default: rigidref; starter: starter].
    #[arg(long, value_enum)]
    pub image_reader: Option<rigidref::blocks2d::image::ImageReader>,
    /// 2D: disc trees, and so the order contacts are found in: `median` (rigidref's) or
    /// `starter` (the starter's BVNode and descent) [default: median; starter: starter].
    #[arg(long, value_enum)]
    pub disc_tree: Option<rigidref::blocks2d::disc_tree::DiscTreeRule>,
    /// 2D: adaptive substeps: take enough substeps each step that no block moves more than this
    /// many blocks per substep (fast bodies then cannot pass through a one-block wall; at most
    /// 4096 substeps) [default: off, the fixed --substeps].
    #[arg(long, allow_negative_numbers = true)]
    pub max_travel: Option<f64>,
    /// 2D: shock propagation after each velocity solve: bodies re-solved layer by layer from the
    /// pinned ones up, each layer's supports treated as fixed (stiffer stacks; docs/blocks2d.md
    /// §"Shock propagation") [default: off].
    #[arg(long)]
    pub shock_propagation: bool,
    /// 2D: apply an impulse TIME:BODY:JX,JY[:PX,PY] (at the body's centre of mass unless a world
    /// point is given); repeatable.
    #[arg(long)]
    pub impulse: Vec<String>,
    /// 2D: prescribed motion BODY:VX,VY:OMEGA:FREQ: the body's velocity is (VX,VY)·cos(2π FREQ t)
    /// and its angular velocity OMEGA·cos(2π FREQ t) (shaking the nut bag's container).
    #[arg(long)]
    pub shake: Vec<String>,
}

impl Blocks2dOptions {
    /// The options as the 2D loader takes them (impulses and shakes parsed), with the names of
    /// the flags given.
    pub fn command_line(&self, sets: &SceneSets) -> anyhow::Result<LoadOptions2> {
        let impulses = self.impulse.iter().map(|t| parse_impulse(t));
        let shakes = self.shake.iter().map(|t| parse_shake(t));
        Ok(LoadOptions2 {
            parameters: self.parameters(),
            impulses: impulses
                .collect::<Result<_, _>>()
                .map_err(anyhow::Error::msg)?,
            shakes: shakes
                .collect::<Result<_, _>>()
                .map_err(anyhow::Error::msg)?,
            given: self.given(),
            overrides: sets.overrides()?,
        })
    }

    /// The names of the flags given, in the order `--help` lists them.
    pub fn given(&self) -> Vec<String> {
        let mut given: Vec<String> = self
            .parameters()
            .given()
            .iter()
            .map(|key| match *key {
                "warm_start" => "--no-warm-start".to_string(),
                "post_stabilization" => "--no-post-stabilization".to_string(),
                key => format!("--{}", key.replace('_', "-")),
            })
            .collect();
        given.extend((!self.impulse.is_empty()).then(|| "--impulse".to_string()));
        given.extend((!self.shake.is_empty()).then(|| "--shake".to_string()));
        given
    }

    /// The physics options as 2D parameters.
    fn parameters(&self) -> ParamOverrides2 {
        ParamOverrides2 {
            preset: self.preset,
            step: self.step,
            substeps: self.substeps,
            gravity: self.gravity,
            gravity_angle: self.gravity_angle,
            mu: self.mu,
            restitution: self.restitution,
            iterations: self.iterations,
            pgs_tolerance: self.pgs_tolerance,
            order: self.order,
            seed: self.seed,
            pgs_local_solve: self.pgs_local_solve,
            warm_start: self.no_warm_start.then_some(false),
            post_stabilization: self.no_post_stabilization.then_some(false),
            slop: self.slop,
            contact_model: self.contact_model,
            white_threshold: self.white_threshold,
            max_travel: self.max_travel,
            shock_propagation: self.shock_propagation.then_some(true),
            solver: None,
            threads: None,
            detection_cache: None,
            check_detection: None,
            inertia: self.inertia,
            disc_tree: self.disc_tree,
            image_reader: self.image_reader,
        }
    }
}

/// Parses `T:BODY:JX,JY` or `T:BODY:JX,JY:PX,PY`.
pub(crate) fn parse_impulse(text: &str) -> Result<ScriptedImpulse, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let pair = |s: &str| -> Result<Vector2<f64>, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{s:?}: {e}"))?;
        match v.as_slice() {
            [x, y] if x.is_finite() && y.is_finite() => Ok(Vector2::new(*x, *y)),
            _ => Err(format!("{s:?} is not two finite numbers X,Y")),
        }
    };
    if !(parts.len() == 3 || parts.len() == 4) {
        return Err(format!(
            "--impulse {text:?}: expected TIME:BODY:JX,JY[:PX,PY]"
        ));
    }
    let time: f64 = parts[0]
        .parse()
        .map_err(|e| format!("--impulse {text:?}: time: {e}"))?;
    let body: usize = parts[1]
        .parse()
        .map_err(|e| format!("--impulse {text:?}: body: {e}"))?;
    if !(time.is_finite() && time >= 0.0) {
        return Err(format!("--impulse {text:?}: time must be ≥ 0"));
    }
    Ok(ScriptedImpulse {
        time,
        body,
        impulse: pair(parts[2]).map_err(|e| format!("--impulse {text:?}: impulse {e}"))?,
        point: if parts.len() == 4 {
            Some(pair(parts[3]).map_err(|e| format!("--impulse {text:?}: point {e}"))?)
        } else {
            None
        },
    })
}

/// Parses `BODY:VX,VY:OMEGA:FREQ`.
pub(crate) fn parse_shake(text: &str) -> Result<Shake, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let bad = || format!("--shake {text:?}: expected BODY:VX,VY:OMEGA:FREQ");
    if parts.len() != 4 {
        return Err(bad());
    }
    let body: usize = parts[0].parse().map_err(|_| bad())?;
    let v: Vec<f64> = parts[1]
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let angular: f64 = parts[2].parse().map_err(|_| bad())?;
    let frequency: f64 = parts[3].parse().map_err(|_| bad())?;
    if v.len() != 2
        || !v
            .iter()
            .chain([angular, frequency].iter())
            .all(|x| x.is_finite())
        || frequency < 0.0
    {
        return Err(bad());
    }
    Ok(Shake {
        body,
        velocity: Vector2::new(v[0], v[1]),
        angular,
        frequency,
    })
}
