//! 2D scene files: a JSON file naming an image and its parameters. docs/blocks2d.md §"Scene files".
//!
//! ```json
//! {"image": "stack.png",
//!  "parameters": {"substeps": 4, "iterations": 50, "order": "random"},
//!  "impulses": [{"time": 20, "body": 0, "impulse": [30, 0]}],
//!  "shakes": [{"body": 0, "velocity": [3, 0], "angular": 0, "frequency": 1}],
//!  "pins": [{"bodies": [2, null], "point": [10, 4.5]}],
//!  "springs": [{"bodies": [3, 1], "points": [[4, 2], [4, 8]], "stiffness": 5, "damping": 0.5}]}
//! ```
//!
//! `image` is relative to the scene file's folder. Pins and springs name bodies by index (`null`
//! is the world) and their anchors as world points at t = 0, blocks (pixel centres are integer
//! points, y down); a spring's `rest_length` defaults to its initial length. Every parameter is optional and defaults as on
//! the command line; unknown keys are warnings; bad values are errors naming file, line, column.

use super::image::{ImageSettings, load_image};
use super::joints::{Anchor, Pin2, Spring2};
use super::params::{ContactModel, Params2, Preset};
use super::world::{ScriptedImpulse, Shake, World2};
use crate::common::scene_json::{Overrides, SceneError};
use crate::common::values::{Count, NonNegative, Positive};
use crate::solve::{ContactOrder, LocalSolve, Solver};
use nalgebra::Vector2;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
struct SceneFile2 {
    image: String,
    #[serde(default)]
    parameters: ParametersFile2,
    #[serde(default)]
    impulses: Vec<ImpulseFile>,
    #[serde(default)]
    shakes: Vec<ShakeFile>,
    #[serde(default)]
    pins: Vec<PinFile>,
    #[serde(default)]
    springs: Vec<SpringFile>,
}

#[derive(Deserialize)]
struct PinFile {
    bodies: [Option<usize>; 2],
    point: [f64; 2],
}

#[derive(Deserialize)]
struct SpringFile {
    bodies: [Option<usize>; 2],
    points: [[f64; 2]; 2],
    stiffness: NonNegative,
    #[serde(default)]
    damping: Option<NonNegative>,
    #[serde(default)]
    rest_length: Option<NonNegative>,
}

#[derive(Deserialize, Default)]
struct ParametersFile2 {
    preset: Option<Preset>,
    step: Option<Positive>,
    substeps: Option<Count>,
    gravity: Option<NonNegative>,
    gravity_angle: Option<f64>,
    mu: Option<NonNegative>,
    restitution: Option<NonNegative>,
    iterations: Option<Count>,
    pgs_tolerance: Option<Positive>,
    order: Option<ContactOrder>,
    seed: Option<u64>,
    pgs_local_solve: Option<LocalSolve>,
    warm_start: Option<bool>,
    post_stabilization: Option<bool>,
    slop: Option<NonNegative>,
    contact_model: Option<ContactModel>,
    white_threshold: Option<NonNegative>,
    max_travel: Option<Positive>,
    shock_propagation: Option<bool>,
    solver: Option<Solver>,
}

#[derive(Deserialize)]
struct ImpulseFile {
    time: NonNegative,
    body: usize,
    impulse: [f64; 2],
    point: Option<[f64; 2]>,
}

#[derive(Deserialize)]
struct ShakeFile {
    body: usize,
    velocity: [f64; 2],
    #[serde(default)]
    angular: f64,
    frequency: NonNegative,
}

/// A loaded 2D scene.
pub struct Scene2 {
    /// The image's path.
    pub image: PathBuf,
    /// The world, ready to run.
    pub world: World2,
    /// Warnings (unknown keys).
    pub warnings: Vec<String>,
    /// The parameters set on the command line (`--set KEY=VALUE`), as `KEY=VALUE`.
    pub overrides: Vec<String>,
}

/// Whether a JSON text is a 2D scene (has a top-level `image` key).
pub fn is_scene2(text: &str) -> bool {
    match serde_json::from_str::<serde_json::Value>(text) {
        Ok(v) => v.get("image").is_some(),
        // Unparsable (e.g. a number out of range): a 2D scene if it names an image, so that the
        // 2D reader reports what is wrong rather than the 3D one.
        Err(_) => text.contains("\"image\""),
    }
}

/// The 2D parameters a scene file or the command line may set. Each is optional: what is not set
/// keeps [`Params2::default`]'s value. One check, [`Parameters2::resolve`], serves both sources.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Parameters2 {
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
}

/// A parameter out of its range: the key (as in a scene file) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The key, e.g. `white_threshold`.
    pub key: &'static str,
    /// What is wrong, e.g. "must be in [0, 1), got 1".
    pub message: String,
}

impl Parameters2 {
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
        Ok((p, ImageSettings { white_threshold }))
    }
}

impl Parameters2 {
    /// These values, with `other`'s where these are not set.
    pub fn or(&self, other: &Parameters2) -> Parameters2 {
        Parameters2 {
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
            white_threshold: self.white_threshold.or(other.white_threshold),
            max_travel: self.max_travel.or(other.max_travel),
            shock_propagation: self.shock_propagation.or(other.shock_propagation),
            solver: self.solver.or(other.solver),
        }
    }
}

impl ParametersFile2 {
    /// The values read, as plain parameters.
    fn plain(self) -> Parameters2 {
        let p = self;
        Parameters2 {
            preset: p.preset,
            step: p.step.map(|x| x.0),
            substeps: p.substeps.map(|x| x.0),
            gravity: p.gravity.map(|x| x.0),
            gravity_angle: p.gravity_angle,
            mu: p.mu.map(|x| x.0),
            restitution: p.restitution.map(|x| x.0),
            iterations: p.iterations.map(|x| x.0),
            pgs_tolerance: p.pgs_tolerance.map(|x| x.0),
            order: p.order,
            seed: p.seed,
            pgs_local_solve: p.pgs_local_solve,
            warm_start: p.warm_start,
            post_stabilization: p.post_stabilization,
            slop: p.slop.map(|x| x.0),
            contact_model: p.contact_model,
            white_threshold: p.white_threshold.map(|x| x.0),
            max_travel: p.max_travel.map(|x| x.0),
            shock_propagation: p.shock_propagation,
            solver: p.solver,
        }
    }
}

/// Whether `path` is a 2D scene: a .png image, or a JSON file with an `image` key.
pub fn is_2d_scene(path: &Path) -> bool {
    let has = |ext: &str| {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    };
    has("png")
        || (has("json") && crate::common::input::read_text(path).is_ok_and(|t| is_scene2(&t)))
}

/// What the command line adds to a 2D scene: parameters (for images only: a scene file sets its
/// own) and scripted impulses and shakes (likewise).
#[derive(Clone, Debug, Default)]
pub struct CommandLine2 {
    /// Parameters given as options.
    pub parameters: Parameters2,
    /// `--impulse` values.
    pub impulses: Vec<ScriptedImpulse>,
    /// `--shake` values.
    pub shakes: Vec<Shake>,
    /// The option names given (`--step`, `--impulse`, …), for the message that refuses them on a
    /// scene file.
    pub given: Vec<String>,
    /// `--set KEY=VALUE`: keys of a 2D scene file's `parameters`, for images and scene files.
    pub overrides: Overrides,
}

/// A 2D scene ready to run: an image with the command line's parameters, or a scene file with
/// its own (then giving 2D physics options as well is an error rather than a silent choice
/// between the two). Warnings are returned, not printed.
pub fn load_2d(path: &Path, cli: &CommandLine2) -> Result<Scene2, SceneError> {
    let source = path.display().to_string();
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        if !cli.given.is_empty() {
            return Err(SceneError(format!(
                "{source}: a 2D scene file sets its own parameters; {} on the command line apply to .png scenes only",
                cli.given.join(", ")
            )));
        }
        return load_scene2_with(path, &cli.overrides);
    }
    let parameters = with_overrides(&cli.parameters, &cli.overrides)?;
    let (params, settings) = parameters.resolve().map_err(|e| {
        // Name the option the value came from: `--set KEY=VALUE` or `--KEY VALUE`.
        match cli.overrides.0.iter().find(|(k, _)| k == e.key) {
            Some((k, v)) => SceneError(format!("--set {k}={v}: {k} {}", e.message)),
            None => SceneError(format!("--{} {}", e.key.replace('_', "-"), e.message)),
        }
    })?;
    let groups = load_image(path, &settings).map_err(SceneError)?;
    let mut world = World2::new(&groups, params);
    let n = world.bodies.len();
    for i in &cli.impulses {
        if i.body >= n {
            return Err(SceneError(format!(
                "--impulse: body {} does not exist ({n} bodies in {source})",
                i.body
            )));
        }
    }
    for s in &cli.shakes {
        if s.body >= n {
            return Err(SceneError(format!(
                "--shake: body {} does not exist ({n} bodies in {source})",
                s.body
            )));
        }
    }
    world.impulses.extend(cli.impulses.iter().copied());
    world.shakes.extend(cli.shakes.iter().copied());
    check_scripts(&world, "--impulse", "--shake", &source)?;
    Ok(Scene2 {
        image: path.to_path_buf(),
        world,
        warnings: Vec::new(),
        overrides: cli.overrides.describe(),
    })
}

/// The command line's parameters with `--set` overrides added, each checked as a scene file's
/// value of that key; a key given both ways is an error.
fn with_overrides(flags: &Parameters2, overrides: &Overrides) -> Result<Parameters2, SceneError> {
    if overrides.is_empty() {
        return Ok(flags.clone());
    }
    overrides.check::<ParametersFile2>("a 2D scene's parameters")?;
    let mut map = serde_json::Map::new();
    overrides.apply(&mut map);
    let set: ParametersFile2 = serde_json::from_value(serde_json::Value::Object(map))
        .map_err(|e| SceneError(format!("--set: {e}")))?;
    let set = set.plain();
    let both: Vec<&str> = set
        .given()
        .into_iter()
        .filter(|k| flags.given().contains(k))
        .collect();
    if let Some(key) = both.first() {
        return Err(SceneError(format!(
            "--set {key} and --{} both set {key}; give it once",
            key.replace('_', "-")
        )));
    }
    Ok(set.or(flags))
}

/// Loads a 2D scene file.
pub fn load_scene2(path: &Path) -> Result<Scene2, SceneError> {
    load_scene2_with(path, &Overrides::default())
}

/// Loads a 2D scene file with `overrides` of its `parameters` (`--set KEY=VALUE`), each checked
/// as the file's value of that key would be.
pub fn load_scene2_with(path: &Path, overrides: &Overrides) -> Result<Scene2, SceneError> {
    let source = path.display().to_string();
    let text = crate::common::input::read_text(path)
        .map_err(|e| SceneError(format!("{source}: cannot read scene: {e}")))?;
    let mut warnings = Vec::new();
    let mut file: SceneFile2 = crate::common::scene_json::from_str(&text, &source, &mut warnings)?;
    if !overrides.is_empty() {
        overrides.check::<ParametersFile2>("a 2D scene's parameters")?;
        // The file is valid and so is each override: set them in its parameters and read again.
        let mut value: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| SceneError(format!("{source}: {e}")))?;
        if let Some(object) = value.as_object_mut() {
            let parameters = object
                .entry("parameters")
                .or_insert_with(|| serde_json::Value::Object(Default::default()));
            if let Some(map) = parameters.as_object_mut() {
                overrides.apply(map);
            }
        }
        file = serde_json::from_value(value).map_err(|e| SceneError(format!("{source}: {e}")))?;
    }
    let (params, settings) = file
        .parameters
        .plain()
        .resolve()
        .map_err(|e| SceneError(format!("{source}: parameters.{} {}", e.key, e.message)))?;
    let image = path.parent().unwrap_or(Path::new(".")).join(&file.image);
    let groups =
        load_image(&image, &settings).map_err(|e| SceneError(format!("{source}: image: {e}")))?;
    let mut world = World2::new(&groups, params);
    let n = world.bodies.len();
    for (k, i) in file.impulses.iter().enumerate() {
        if i.body >= n {
            return Err(SceneError(format!(
                "{source}: impulses[{k}]: body {} does not exist (the image has {n} bodies, 0 to {})",
                i.body,
                n - 1
            )));
        }
        if !i
            .impulse
            .iter()
            .chain(i.point.iter().flatten())
            .all(|x| x.is_finite())
        {
            return Err(SceneError(format!(
                "{source}: impulses[{k}]: the impulse and point must be finite"
            )));
        }
        world.impulses.push(ScriptedImpulse {
            time: i.time.0,
            body: i.body,
            impulse: Vector2::from(i.impulse),
            point: i.point.map(Vector2::from),
        });
    }
    for (k, s) in file.shakes.iter().enumerate() {
        if s.body >= n
            || !s
                .velocity
                .iter()
                .chain([s.angular].iter())
                .all(|x| x.is_finite())
        {
            return Err(SceneError(format!(
                "{source}: shakes[{k}]: body {} of {n}, or a non-finite value",
                s.body
            )));
        }
        world.shakes.push(Shake {
            body: s.body,
            velocity: Vector2::from(s.velocity),
            angular: s.angular,
            frequency: s.frequency.0,
        });
    }
    check_scripts(&world, "impulses", "shakes", &source)?;
    add_pins_and_springs(&mut world, &file.pins, &file.springs, &source)?;
    Ok(Scene2 {
        image,
        world,
        warnings,
        overrides: overrides.describe(),
    })
}

/// Adds a scene file's pins and springs, checking that each joins two different bodies (or a
/// body and the world) that exist, at finite points.
fn add_pins_and_springs(
    world: &mut World2,
    pins: &[PinFile],
    springs: &[SpringFile],
    source: &str,
) -> Result<(), SceneError> {
    let n = world.bodies.len();
    let check = |what: String, bodies: [Option<usize>; 2], points: &[[f64; 2]]| {
        if let Some(b) = bodies.iter().flatten().find(|&&b| b >= n) {
            return Err(SceneError(format!(
                "{source}: {what}: body {b} does not exist (the image has {n} bodies, 0 to {})",
                n - 1
            )));
        }
        if bodies[0] == bodies[1] {
            return Err(SceneError(format!(
                "{source}: {what}: joins {} to itself; give two different bodies (null is the world)",
                bodies[0].map_or("the world".to_string(), |b| format!("body {b}"))
            )));
        }
        if !points.iter().flatten().all(|x| x.is_finite()) {
            return Err(SceneError(format!(
                "{source}: {what}: the points must be finite"
            )));
        }
        // End 1 is a body: the world, if named, goes second.
        Ok(if bodies[0].is_none() {
            [bodies[1], bodies[0]]
        } else {
            bodies
        })
    };
    for (k, p) in pins.iter().enumerate() {
        let bodies = check(format!("pins[{k}]"), p.bodies, &[p.point])?;
        let point = Vector2::from(p.point);
        world.pins.push(Pin2 {
            ends: bodies.map(|b| Anchor::at(&world.bodies, b, &point)),
        });
    }
    for (k, s) in springs.iter().enumerate() {
        let swapped = s.bodies[0].is_none();
        let bodies = check(format!("springs[{k}]"), s.bodies, &s.points)?;
        let mut points = s.points.map(Vector2::from);
        if swapped {
            points.swap(0, 1);
        }
        let ends = [
            Anchor::at(&world.bodies, bodies[0], &points[0]),
            Anchor::at(&world.bodies, bodies[1], &points[1]),
        ];
        world.springs.push(Spring2 {
            ends,
            stiffness: s.stiffness.0,
            damping: s.damping.map_or(0.0, |c| c.0),
            rest_length: s
                .rest_length
                .map_or((points[0] - points[1]).norm(), |l| l.0),
        });
    }
    Ok(())
}

/// Parses `T:BODY:JX,JY` or `T:BODY:JX,JY:PX,PY`.
pub fn parse_impulse(text: &str) -> Result<ScriptedImpulse, String> {
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
pub fn parse_shake(text: &str) -> Result<Shake, String> {
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

/// Refuses scripts that would silently do nothing or something else than asked: an impulse on a
/// pinned body (its inverse mass is zero: the impulse would be lost) and a shake of a body that
/// is not pinned (a shake prescribes a pinned body's motion; on a free body it would overwrite
/// the velocity that contacts and gravity give it every substep). docs/blocks2d.md §"Bodies".
fn check_scripts(
    world: &World2,
    impulses: &str,
    shakes: &str,
    source: &str,
) -> Result<(), SceneError> {
    for i in &world.impulses {
        if world.bodies[i.body].pinned {
            return Err(SceneError(format!(
                "{source}: {impulses}: body {} is pinned (all blue): an impulse cannot move it",
                i.body
            )));
        }
    }
    for s in &world.shakes {
        if !world.bodies[s.body].pinned {
            return Err(SceneError(format!(
                "{source}: {shakes}: body {} is not pinned: a shake prescribes a pinned (all-blue) body's motion",
                s.body
            )));
        }
    }
    Ok(())
}
