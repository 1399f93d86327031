//! 3D scenes with their body files, parsed: the input is the scene JSON, the body JSON and the OBJ
//! text, separated by 0xFF bytes; every body's `file_root` finds the two texts. `parse_scene`
//! reads and checks all three (the mesh's solidity, the mass properties, the scene's numbers);
//! nothing may panic. The world made from what parses is the `world3d` target's.
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
    let _ = parse_scene(scene, "fuzz.json", "fuzz", &files, &Overrides::default());
});
