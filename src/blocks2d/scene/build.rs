//! A 2D scene file made into a world: the image, the parameters, the pins and springs, and the
//! scripted impulses and shakes, each checked.

use super::*;

/// Loads a 2D scene file with `overrides` of its `parameters` (`--set KEY=VALUE`), each checked
/// as the file's value of that key would be.
pub fn load_scene2_with(path: &Path, overrides: &Overrides) -> Result<Scene2, SceneError> {
    let source = path.display().to_string();
    let text = crate::common::input::read_text(path)
        .map_err(|e| SceneError(format!("{source}: cannot read scene: {e}")))?;
    let mut warnings = Vec::new();
    let mut file: SceneFile2 = crate::common::scene_json::from_str(&text, &source, &mut warnings)?;
    if !overrides.is_empty() {
        let numbered = |file: &SceneFile2| {
            let p = &file.parameters;
            p.image_reader
                .unwrap_or_else(|| p.preset.unwrap_or_default().params().image_reader)
        };
        let before = numbered(&file);
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
        // The file's body indices are in its own numbering: an override that renumbers the
        // image would make them name other bodies, silently.
        let indexed = !(file.impulses.is_empty()
            && file.shakes.is_empty()
            && file.pins.is_empty()
            && file.springs.is_empty());
        if indexed && numbered(&file) != before {
            return Err(SceneError(format!(
                "{source}: --set {}: the image's bodies would be numbered {} (image_reader {}), not {} as the file numbers them, so its impulses, shakes, pins and springs would name other bodies; add --set image_reader={} to keep the file's numbering",
                overrides.describe().join(" --set "),
                numbered(&file).numbering(),
                numbered(&file).name(),
                before.numbering(),
                before.name()
            )));
        }
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
pub(super) fn add_pins_and_springs(
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

/// Refuses scripts that would silently do nothing or something else than asked: an impulse on a
/// pinned body (its inverse mass is zero: the impulse would be lost) and a shake of a body that
/// is not pinned (a shake prescribes a pinned body's motion; on a free body it would overwrite
/// the velocity that contacts and gravity give it every substep). docs/blocks2d.md §"Bodies".
pub(super) fn check_scripts(
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
