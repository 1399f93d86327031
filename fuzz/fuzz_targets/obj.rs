//! OBJ meshes: parse, check the solid, mass properties. Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::rigid3d::mesh::TriMesh;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(mesh) = TriMesh::parse_obj(text, "fuzz.obj") {
        let _ = mesh.check_solid("fuzz.obj");
        let _ = rigidref::rigid3d::massprops::mass_properties(&mesh, 1.0);
    }
});
