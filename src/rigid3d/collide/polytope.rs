//! A convex piece as a polytope: its polygonal faces (coplanar hull triangles merged), each face's
//! outward plane and vertex loop, and its edges with the two faces they join. This is the data
//! the separating-axis query of `collision: complete` reads ([`super::separating_axes`]).
//! docs/contact.md §"Exact convex contact".

use nalgebra::Vector3;
use std::collections::HashMap;

/// Two hull triangles that share an edge are one face when the far vertex of each lies within
/// this fraction of the piece's bounding radius of the other's plane (and their normals agree):
/// coplanar up to round-off, not merely nearly so.
pub const COPLANAR_TOLERANCE: f64 = 1e-9;

/// A face: a convex polygon on the plane n·x = d.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// Outward unit normal n.
    pub normal: Vector3<f64>,
    /// Plane offset d, m: the largest n·v over the face's vertices.
    pub offset: f64,
    /// Vertex indices, counter-clockwise seen from outside (from the side n points to).
    pub corners: Vec<usize>,
    /// Edge indices: `edges[k]` joins `corners[k]` and `corners[k + 1]` (cyclically).
    pub edges: Vec<usize>,
}

/// An edge between two faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Its end vertices [a, b].
    pub vertices: [usize; 2],
    /// The face that runs a → b counter-clockwise, then the face that runs b → a.
    pub faces: [usize; 2],
}

/// A convex polytope in its body frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Polytope {
    /// Vertex positions, m.
    pub vertices: Vec<Vector3<f64>>,
    /// Faces, merged from the hull's coplanar triangles.
    pub faces: Vec<Face>,
    /// Edges between distinct faces, each once.
    pub edges: Vec<Edge>,
    /// For each vertex, the faces it is a corner of.
    pub vertex_faces: Vec<Vec<usize>>,
    /// The mean of the vertices, m: a point inside.
    pub centroid: Vector3<f64>,
    /// The largest distance of a vertex from the centroid, m.
    pub radius: f64,
}

/// Disjoint sets over triangle indices (the faces being merged).
struct Sets(Vec<usize>);

impl Sets {
    fn find(&mut self, mut t: usize) -> usize {
        while self.0[t] != t {
            self.0[t] = self.0[self.0[t]];
            t = self.0[t];
        }
        t
    }
    fn join(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        // The smaller index is the root, so the grouping does not depend on the join order.
        let (low, high) = (a.min(b), a.max(b));
        self.0[high] = low;
    }
}

impl Polytope {
    /// The polytope of a convex hull given as `vertices` and `triangles` (counter-clockwise seen
    /// from outside, every edge shared by exactly two triangles). `None` when the triangles do
    /// not close into faces with simple boundary loops.
    pub fn from_hull(vertices: Vec<Vector3<f64>>, triangles: &[[usize; 3]]) -> Option<Polytope> {
        let count = vertices.len() as f64;
        let centroid = vertices.iter().sum::<Vector3<f64>>() / count;
        let radius = vertices
            .iter()
            .map(|v| (v - centroid).norm())
            .fold(0.0, f64::max);
        let tolerance = COPLANAR_TOLERANCE * radius;
        let area_normal = |t: &[usize; 3]| {
            let [a, b, c] = t.map(|i| vertices[i]);
            (b - a).cross(&(c - a))
        };
        // Each directed edge's triangle, to find a triangle's neighbours.
        let mut owner: HashMap<(usize, usize), usize> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                if owner.insert((tri[k], tri[(k + 1) % 3]), t).is_some() {
                    return None; // an edge used twice in one direction: not a closed hull
                }
            }
        }
        // Merge neighbours that lie in one plane.
        let mut sets = Sets((0..triangles.len()).collect());
        let flat_with = |t: usize, u: usize| {
            let (nt, nu) = (area_normal(&triangles[t]), area_normal(&triangles[u]));
            let far = |of: usize, plane: usize, n: &Vector3<f64>| {
                let p = vertices[triangles[plane][0]];
                triangles[of]
                    .iter()
                    .map(|&i| (vertices[i] - p).dot(n).abs())
                    .fold(0.0, f64::max)
            };
            let (lt, lu) = (nt.norm(), nu.norm());
            // A triangle of no area has no plane of its own: it belongs to its neighbour.
            if lt == 0.0 || lu == 0.0 {
                return true;
            }
            nt.dot(&nu) > 0.0
                && far(u, t, &(nt / lt)) <= tolerance
                && far(t, u, &(nu / lu)) <= tolerance
        };
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let u = *owner.get(&(tri[(k + 1) % 3], tri[k]))?;
                if u > t && flat_with(t, u) {
                    sets.join(t, u);
                }
            }
        }
        // Each face's boundary: the directed edges of its triangles whose twin is in another face.
        let mut groups: Vec<usize> = Vec::new();
        let mut face_of_root: HashMap<usize, usize> = HashMap::new();
        let mut next: Vec<HashMap<usize, usize>> = Vec::new();
        let mut sums: Vec<Vector3<f64>> = Vec::new();
        for (t, tri) in triangles.iter().enumerate() {
            let root = sets.find(t);
            let face = *face_of_root.entry(root).or_insert_with(|| {
                groups.push(root);
                next.push(HashMap::new());
                sums.push(Vector3::zeros());
                groups.len() - 1
            });
            sums[face] += area_normal(tri);
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let twin = owner[&(b, a)];
                if sets.find(twin) != root && next[face].insert(a, b).is_some() {
                    return None; // a boundary that passes a vertex twice
                }
            }
        }
        let mut faces = Vec::with_capacity(groups.len());
        for (face, boundary) in next.iter().enumerate() {
            let start = *boundary.keys().min()?;
            let mut corners = vec![start];
            let mut at = boundary[&start];
            while at != start {
                if corners.len() > boundary.len() {
                    return None;
                }
                corners.push(at);
                at = *boundary.get(&at)?;
            }
            if corners.len() != boundary.len() || corners.len() < 3 {
                return None;
            }
            let normal = sums[face].try_normalize(0.0)?;
            let offset = corners
                .iter()
                .map(|&i| normal.dot(&vertices[i]))
                .fold(f64::NEG_INFINITY, f64::max);
            faces.push(Face {
                normal,
                offset,
                corners,
                edges: Vec::new(),
            });
        }
        // Edges: each boundary edge a → b of face f meets its twin b → a of face g once.
        let mut at_edge: HashMap<(usize, usize), (usize, usize)> = HashMap::new();
        for (f, face) in faces.iter().enumerate() {
            let n = face.corners.len();
            for k in 0..n {
                at_edge.insert((face.corners[k], face.corners[(k + 1) % n]), (f, k));
            }
        }
        let mut edges = Vec::new();
        let mut edge_ids: Vec<Vec<usize>> =
            faces.iter().map(|f| vec![0; f.corners.len()]).collect();
        for f in 0..faces.len() {
            let n = faces[f].corners.len();
            for k in 0..n {
                let (a, b) = (faces[f].corners[k], faces[f].corners[(k + 1) % n]);
                let &(g, m) = at_edge.get(&(b, a))?;
                if a < b {
                    edge_ids[f][k] = edges.len();
                    edge_ids[g][m] = edges.len();
                    edges.push(Edge {
                        vertices: [a, b],
                        faces: [f, g],
                    });
                }
            }
        }
        for (face, ids) in faces.iter_mut().zip(edge_ids) {
            face.edges = ids;
        }
        let mut vertex_faces = vec![Vec::new(); vertices.len()];
        for (f, face) in faces.iter().enumerate() {
            for &c in &face.corners {
                vertex_faces[c].push(f);
            }
        }
        Some(Polytope {
            vertices,
            faces,
            edges,
            vertex_faces,
            centroid,
            radius,
        })
    }

    /// The vertex graph: for each vertex, the vertices it shares an edge with.
    pub fn neighbours(&self) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); self.vertices.len()];
        for e in &self.edges {
            let [a, b] = e.vertices;
            out[a].push(b);
            out[b].push(a);
        }
        out
    }

    /// Volume, m³ (divergence theorem over the faces, each a fan from its first corner).
    pub fn volume(&self) -> f64 {
        let mut six_v = 0.0;
        for face in &self.faces {
            let p0 = self.vertices[face.corners[0]];
            for k in 1..face.corners.len() - 1 {
                let (p1, p2) = (
                    self.vertices[face.corners[k]],
                    self.vertices[face.corners[k + 1]],
                );
                six_v += p0.dot(&p1.cross(&p2));
            }
        }
        six_v / 6.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hull(points: &[Vector3<f64>]) -> Polytope {
        let p: Vec<_> = points
            .iter()
            .map(|v| parry3d_f64::math::Vector::new(v.x, v.y, v.z))
            .collect();
        let (v, t) = parry3d_f64::transformation::try_convex_hull(&p).unwrap();
        let v = v.iter().map(|q| Vector3::new(q.x, q.y, q.z)).collect();
        let t: Vec<[usize; 3]> = t.iter().map(|t| t.map(|i| i as usize)).collect();
        Polytope::from_hull(v, &t).unwrap()
    }

    fn cube_points(half: f64) -> Vec<Vector3<f64>> {
        let mut out = Vec::new();
        for i in 0..8 {
            let s = |b: usize| if i >> b & 1 == 1 { half } else { -half };
            out.push(Vector3::new(s(0), s(1), s(2)));
        }
        out
    }

    #[test]
    fn a_cube_has_six_square_faces_twelve_edges_and_eulers_count() {
        let p = hull(&cube_points(0.1));
        assert_eq!((p.vertices.len(), p.edges.len(), p.faces.len()), (8, 12, 6));
        for face in &p.faces {
            assert_eq!(face.corners.len(), 4);
            // Axis-aligned faces: the normal is exactly an axis, the offset exactly the half side.
            assert_eq!(face.normal.iter().filter(|x| **x == 0.0).count(), 2);
            assert_eq!(face.offset, 0.1);
            // Counter-clockwise seen from outside: the loop's area vector points along n.
            let c: Vec<_> = face.corners.iter().map(|&i| p.vertices[i]).collect();
            let area = (c[1] - c[0]).cross(&(c[2] - c[0]));
            assert!(area.dot(&face.normal) > 0.0);
        }
        for (e, edge) in p.edges.iter().enumerate() {
            let [f, g] = edge.faces;
            assert_ne!(f, g);
            assert!(p.faces[f].edges.contains(&e) && p.faces[g].edges.contains(&e));
        }
        assert!((p.volume() - 0.008).abs() < 1e-15);
    }

    #[test]
    fn a_tetrahedron_and_an_octahedron_keep_their_triangles() {
        let tet = hull(&[
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ]);
        assert_eq!((tet.edges.len(), tet.faces.len()), (6, 4));
        let octa = hull(&[
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
        ]);
        assert_eq!((octa.edges.len(), octa.faces.len()), (12, 8));
        for p in [&tet, &octa] {
            assert_eq!(
                p.vertices.len() + p.faces.len(),
                p.edges.len() + 2,
                "V − E + F = 2"
            );
        }
    }
}
