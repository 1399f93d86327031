//! What the 3D fuzz targets share: their input (a scene JSON, a body JSON and an OBJ, separated
//! by 0xFF bytes) parsed as `rigidref run` parses a scene, every body's `file_root` finding the
//! same two texts.

use rigidref::rigid3d::scene::{Overrides, SameBodyFiles, Scene, parse_scene};

/// The scene the input holds, when its three parts are text and it parses.
pub fn scene(data: &[u8]) -> Option<Scene> {
    let parts: Vec<&[u8]> = data.splitn(3, |&b| b == 0xFF).collect();
    let [scene, json, obj] = parts[..] else { return None };
    let (Ok(scene), Ok(json), Ok(obj)) =
        (std::str::from_utf8(scene), std::str::from_utf8(json), std::str::from_utf8(obj))
    else {
        return None;
    };
    let files = SameBodyFiles { json: json.into(), obj: obj.into() };
    parse_scene(scene, "fuzz.json", "fuzz", &files, &Overrides::default()).ok()
}
