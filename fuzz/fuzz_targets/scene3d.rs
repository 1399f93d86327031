//! 3D scenes with their body files, parsed: the input is the scene JSON, the body JSON and the OBJ
//! text, separated by 0xFF bytes; every body's `file_root` finds the two texts. `parse_scene`
//! reads and checks all three (the mesh's solidity, the mass properties, the scene's numbers);
//! nothing may panic. The world made from what parses is the `world3d` target's.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "scene_input.rs"]
mod scene_input;

fuzz_target!(|data: &[u8]| {
    let _ = scene_input::scene(data);
});
