//! 3D worlds from small scenes: the input is as `scene3d`'s (scene JSON, body JSON, OBJ,
//! separated by 0xFF bytes). What parses with at most 4 bodies of at most 64 vertices each is
//! made into a world (the convex pieces, the BVHs) and stepped twice: detection, assembly, the
//! solve and the integration on whatever numbers the parser let through. Nothing may panic. The
//! size bound keeps an execution short (the convex decomposition of a large mesh is what made
//! the single target of earlier runs slow); `scene3d` parses the larger meshes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::rigid3d::scene::{BodyFileTexts, BodyFiles, Overrides, SceneError, parse_scene};

struct InMemory {
    json: String,
    obj: String,
}

impl BodyFiles for InMemory {
    fn find(&self, _file_root: &str) -> Result<BodyFileTexts, SceneError> {
        Ok(BodyFileTexts {
            json: (self.json.clone(), "body.json".into()),
            obj: (self.obj.clone(), "body.obj".into()),
        })
    }
}

fuzz_target!(|data: &[u8]| {
    let parts: Vec<&[u8]> = data.splitn(3, |&b| b == 0xFF).collect();
    let [scene, json, obj] = parts[..] else { return };
    let (Ok(scene), Ok(json), Ok(obj)) =
        (std::str::from_utf8(scene), std::str::from_utf8(json), std::str::from_utf8(obj))
    else {
        return;
    };
    let files = InMemory { json: json.into(), obj: obj.into() };
    let Ok(scene) = parse_scene(scene, "fuzz.json", "fuzz", &files, &Overrides::default()) else {
        return;
    };
    if scene.bodies.len() > 4 || scene.bodies.iter().any(|b| b.mesh.vertices.len() > 64) {
        return;
    }
    if let Ok(mut world) = rigidref::rigid3d::world::World::new(&scene) {
        for _ in 0..2 {
            if rigidref::sim::Simulation::step(&mut world).is_err() {
                break;
            }
        }
    }
});
