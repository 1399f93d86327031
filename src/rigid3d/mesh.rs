//! Triangle meshes: reading OBJ files (with `tobj`) and checking that a mesh bounds a solid.
//!
//! Both the mass properties and (later) the signed-distance contact queries assume a closed,
//! consistently and outward oriented triangle mesh; [`TriMesh::topology`] reports every way a
//! mesh can fail that, and [`TriMesh::check_solid`] turns the report into an error or warnings.

use nalgebra::Vector3;
use std::collections::HashMap;
use std::path::Path;

/// A triangle mesh in its own frame. Units: metres.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions in m.
    pub vertices: Vec<Vector3<f64>>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside.
    pub triangles: Vec<[usize; 3]>,
    /// For a mesh read from an OBJ file, each vertex's number in the file (from 0: the order of
    /// its `v` lines); empty for a mesh made in code, whose vertex i is number i. The reader
    /// numbers vertices in the order the faces first use them and keeps only those; libigl's
    /// reader, the 3D Python starter's, keeps the file's order, in which `collision: starter`
    /// visits them ([`TriMesh::file_order`]; docs/contact.md §"The starter's collision
    /// detection").
    pub file_numbers: Vec<usize>,
    /// The number of `v` lines of the OBJ file (0 for a mesh made in code): more than
    /// `vertices.len()` when the file has vertices no face uses, which libigl keeps.
    pub file_vertex_count: usize,
}

/// What [`TriMesh::topology`] found. A mesh bounds a solid when every count here is zero and the
/// signed volume is positive.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Topology {
    /// Edges used by exactly one triangle: holes in the surface.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges whose two triangles traverse them in the same direction: the orientation flips there.
    pub inconsistent_edges: usize,
    /// Triangles with (near) zero area, or repeated vertex indices.
    pub degenerate_triangles: usize,
    /// Signed volume by the divergence theorem, m³; negative when the mesh is inside out.
    pub signed_volume: f64,
}

/// A mesh problem that makes the mesh unusable as a solid.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct MeshError(pub String);

impl TriMesh {
    /// Reads an OBJ file's first object and triangulates its faces. Errors name the file.
    pub fn load_obj(path: &Path) -> Result<TriMesh, MeshError> {
        let text = crate::common::input::read_text(path)
            .map_err(|e| MeshError(format!("{}: cannot read mesh: {e}", path.display())))?;
        Self::parse_obj(&text, &path.display().to_string())
    }

    /// Parses OBJ text; `origin` names the source in error messages.
    pub fn parse_obj(text: &str, origin: &str) -> Result<TriMesh, MeshError> {
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ..Default::default()
        };
        let mut reader = std::io::BufReader::new(text.as_bytes());
        let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
            Ok((Vec::new(), Default::default()))
        })
        .map_err(|e| MeshError(format!("{origin}: not a readable OBJ mesh: {e}")))?;
        match models.len() {
            0 => return Err(MeshError(format!("{origin}: the OBJ file has no faces"))),
            1 => {}
            n => {
                return Err(MeshError(format!(
                    "{origin}: the OBJ file has {n} objects or groups; a body mesh must be one object"
                )));
            }
        }
        let mesh = &models[0].mesh;
        let vertices: Vec<Vector3<f64>> = mesh
            .positions
            .chunks_exact(3)
            .map(|p| Vector3::new(p[0], p[1], p[2]))
            .collect();
        if let Some(i) = vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError(format!(
                "{origin}: vertex {} is not finite",
                i + 1
            )));
        }
        let triangles: Vec<[usize; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
            .collect();
        if triangles.is_empty() {
            return Err(MeshError(format!("{origin}: the OBJ file has no faces")));
        }
        if let Some(t) = triangles
            .iter()
            .find(|t| t.iter().any(|&i| i >= vertices.len()))
        {
            return Err(MeshError(format!(
                "{origin}: a face refers to vertex {} of {}",
                t.iter().max().unwrap() + 1,
                vertices.len()
            )));
        }
        let (file_numbers, file_vertex_count) = obj_numbering(text);
        if file_numbers.len() != vertices.len() {
            return Err(MeshError(format!(
                "{origin}: the faces use {} vertices but {} were read: the file's vertex numbering could not be followed",
                file_numbers.len(),
                vertices.len()
            )));
        }
        Ok(TriMesh {
            vertices,
            triangles,
            file_numbers,
            file_vertex_count,
        })
    }

    /// The vertex indices in the OBJ file's order (by [`TriMesh::file_numbers`]; in index order
    /// for a mesh made in code).
    pub fn file_order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.vertices.len()).collect();
        if self.file_numbers.len() == order.len() {
            order.sort_by_key(|&k| self.file_numbers[k]);
        }
        order
    }

    /// The number of vertices the starter's reader (libigl) reads: the file's `v` lines, or the
    /// vertices of a mesh made in code.
    pub fn file_vertex_count(&self) -> usize {
        self.file_vertex_count.max(self.vertices.len())
    }

    /// Writes the mesh as OBJ text, vertices with round-trip precision.
    pub fn to_obj(&self) -> String {
        let mut out = String::new();
        for v in &self.vertices {
            out.push_str(&format!("v {:?} {:?} {:?}\n", v.x, v.y, v.z));
        }
        for t in &self.triangles {
            out.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
        }
        out
    }

    /// Counts boundary, non-manifold and inconsistently oriented edges and degenerate triangles,
    /// and computes the signed volume.
    pub fn topology(&self) -> Topology {
        // Each undirected edge → (uses in the direction low→high, uses in the direction high→low).
        let mut edges: HashMap<(usize, usize), (u32, u32)> = HashMap::new();
        let mut report = Topology::default();
        let scale = self.bounding_radius().max(f64::MIN_POSITIVE);
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i]);
            let doubled_area = (b - a).cross(&(c - a)).norm();
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || doubled_area <= 1e-12 * scale * scale
            {
                report.degenerate_triangles += 1;
            }
            report.signed_volume += a.dot(&b.cross(&c)) / 6.0;
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                let entry = edges.entry((i.min(j), i.max(j))).or_default();
                if i < j { entry.0 += 1 } else { entry.1 += 1 }
            }
        }
        for &(forward, backward) in edges.values() {
            match forward + backward {
                1 => report.boundary_edges += 1,
                2 if forward != 1 => report.inconsistent_edges += 1,
                2 => {}
                _ => report.non_manifold_edges += 1,
            }
        }
        report
    }

    /// Checks that the mesh bounds a solid. Open, non-manifold, inconsistently oriented,
    /// inside-out or zero-volume meshes are errors (any inertia computed from them would be
    /// silently wrong); degenerate triangles on an otherwise closed mesh are returned as a warning.
    pub fn check_solid(&self, origin: &str) -> Result<Vec<String>, MeshError> {
        let topo = self.topology();
        let mut problems = Vec::new();
        if topo.boundary_edges > 0 {
            problems.push(format!(
                "open surface ({} boundary edges)",
                topo.boundary_edges
            ));
        }
        if topo.non_manifold_edges > 0 {
            problems.push(format!(
                "{} edges shared by more than two triangles",
                topo.non_manifold_edges
            ));
        }
        if topo.inconsistent_edges > 0 {
            problems.push(format!(
                "inconsistently oriented triangles ({} edges traversed twice in the same direction)",
                topo.inconsistent_edges
            ));
        }
        if !problems.is_empty() {
            return Err(MeshError(format!(
                "{origin}: mesh does not bound a solid: {}",
                problems.join("; ")
            )));
        }
        let scale = self.bounding_radius();
        if topo.signed_volume <= 1e-12 * scale * scale * scale {
            let why = if topo.signed_volume < 0.0 {
                "its triangles are oriented clockwise seen from outside (inside out)"
            } else {
                "it encloses no volume"
            };
            return Err(MeshError(format!(
                "{origin}: mesh volume is {:e} m³: {why}",
                topo.signed_volume
            )));
        }
        let mut warnings = Vec::new();
        if topo.degenerate_triangles > 0 {
            warnings.push(format!(
                "{origin}: {} degenerate (zero-area) triangles; they add nothing to the volume but may upset contact normals",
                topo.degenerate_triangles
            ));
        }
        Ok(warnings)
    }

    /// An axis-aligned box with opposite corners `lo` and `hi` (m), 8 vertices and 12 outward
    /// oriented triangles.
    pub fn cuboid(lo: Vector3<f64>, hi: Vector3<f64>) -> TriMesh {
        let corner = |i: usize| {
            Vector3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        TriMesh {
            file_numbers: Vec::new(),
            file_vertex_count: 0,
            vertices: (0..8).map(corner).collect(),
            triangles: vec![
                [0, 2, 1],
                [1, 2, 3],
                [4, 5, 6],
                [5, 7, 6], // −z, +z
                [0, 1, 4],
                [1, 5, 4],
                [2, 6, 3],
                [3, 6, 7], // −y, +y
                [0, 4, 2],
                [2, 4, 6],
                [1, 3, 5],
                [3, 7, 5], // −x, +x
            ],
        }
    }

    /// True when no vertex lies more than `tolerance` (m) in front of any triangle's plane.
    pub fn is_convex(&self, tolerance: f64) -> bool {
        self.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| self.vertices[i]);
            let normal = (b - a).cross(&(c - a));
            let length = normal.norm();
            length == 0.0
                || self
                    .vertices
                    .iter()
                    .all(|v| normal.dot(&(v - a)) <= tolerance * length)
        })
    }

    /// The largest distance of a vertex from the mesh origin, m.
    pub fn bounding_radius(&self) -> f64 {
        self.vertices.iter().map(|v| v.norm()).fold(0.0, f64::max)
    }

    /// The same mesh moved by `offset` (m).
    pub fn translated(&self, offset: &Vector3<f64>) -> TriMesh {
        TriMesh {
            vertices: self.vertices.iter().map(|v| v + offset).collect(),
            triangles: self.triangles.clone(),
            file_numbers: self.file_numbers.clone(),
            file_vertex_count: self.file_vertex_count,
        }
    }
}

/// The file number (from 0) of each vertex in the order the OBJ reader (tobj, one object, faces
/// triangulated, positions not merged) first meets it in the `f` and `l` lines, with tobj's
/// index rules (1-based; negative counts back from the `v` lines read so far; `v/vt/vn`), and
/// the number of `v` lines.
fn obj_numbering(text: &str) -> (Vec<usize>, usize) {
    let mut positions = 0usize;
    let mut seen = std::collections::HashSet::new();
    let mut order = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => positions += 1,
            Some("f") | Some("l") => {
                for word in words {
                    let Some(Ok(x)) = word.split('/').next().map(str::parse::<isize>) else {
                        continue;
                    };
                    let index = if x < 0 { positions as isize + x } else { x - 1 };
                    if index >= 0 && seen.insert(index as usize) {
                        order.push(index as usize);
                    }
                }
            }
            _ => {}
        }
    }
    (order, positions)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    #[test]
    fn closed_outward_tetrahedron_is_a_solid() {
        let mesh = TriMesh::parse_obj(TETRA, "tetra").unwrap();
        let topo = mesh.topology();
        assert_eq!(
            topo.boundary_edges + topo.inconsistent_edges + topo.non_manifold_edges,
            0
        );
        assert!((topo.signed_volume - 1.0 / 6.0).abs() < 1e-15);
        assert!(mesh.check_solid("tetra").unwrap().is_empty());
    }

    #[test]
    fn open_flipped_and_inverted_meshes_are_rejected_with_the_reason() {
        let open = TETRA.replace("f 2 3 4\n", "");
        let err = TriMesh::parse_obj(&open, "open.obj")
            .unwrap()
            .check_solid("open.obj")
            .unwrap_err();
        assert!(err.0.contains("open surface (3 boundary edges)"), "{err}");

        let flipped = TETRA.replace("f 2 3 4", "f 2 4 3");
        let err = TriMesh::parse_obj(&flipped, "flip.obj")
            .unwrap()
            .check_solid("flip.obj")
            .unwrap_err();
        assert!(err.0.contains("inconsistently oriented"), "{err}");

        let inverted = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
        let err = TriMesh::parse_obj(inverted, "inv.obj")
            .unwrap()
            .check_solid("inv.obj")
            .unwrap_err();
        assert!(err.0.contains("inside out"), "{err}");
    }

    #[test]
    fn vertices_keep_their_numbers_in_the_file() {
        // The faces use the vertices in the order 4, 2, 1, 3 (negative and v/vt/vn indices too);
        // vertex 5 is used by no face.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 9 9 9\nvt 0 0\nf 4/1 3 -4\nf 4 2 1\nf 1 3 2\nf 2 3 -2\n";
        let mesh = TriMesh::parse_obj(text, "numbered").unwrap();
        assert_eq!(mesh.file_numbers, vec![3, 2, 1, 0]);
        assert_eq!(mesh.vertices[0], Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(mesh.file_order(), vec![3, 2, 1, 0]);
        assert_eq!(mesh.file_vertex_count(), 5);
        let made = TriMesh::cuboid(Vector3::repeat(-1.0), Vector3::repeat(1.0));
        assert_eq!(made.file_order(), (0..8).collect::<Vec<_>>());
        assert_eq!(made.file_vertex_count(), 8);
    }

    #[test]
    fn faces_referring_to_missing_vertices_are_an_error_not_a_panic() {
        let err =
            TriMesh::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "bad.obj").unwrap_err();
        assert!(err.0.starts_with("bad.obj:"), "{err}");
    }
}
