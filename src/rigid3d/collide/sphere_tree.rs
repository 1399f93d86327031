//! Sphere trees: a hierarchy of spheres covering a mesh's solid, for culling the vertex tests of
//! mesh–mesh collision (scene key `culling: "sphere_tree"`). docs/contact.md §"Sphere trees".
//!
//! Built from an octree over the mesh's bounding cube, seeded by the signed distance d(c) at
//! each cell's centre c (half-diagonal s of the cell):
//!
//! - d(c) > s: the cell is wholly outside the solid and is dropped;
//! - d(c) < −s: the cell is wholly inside; its leaf is the ball of radius |d(c)| about c, the
//!   largest ball about c inside the solid (a sample of the medial-axis transform: maximal balls
//!   inside the solid, large deep inside and small near the surface), which covers the cell;
//! - otherwise the cell straddles the surface: it is split, down to `depth` levels; at the last
//!   level its leaf is the cell's circumscribed sphere (radius s), which holds the part of the
//!   surface in the cell and reaches at most s beyond it.
//!
//! Every point of the solid is in some leaf (its cell is kept, and each kept cell's leaf covers
//! the cell), so a point in no leaf is outside the mesh: skipping it cannot drop a contact. Each
//! inner node's sphere is centred on its cell and encloses its children's spheres, so a query
//! descends only into spheres that contain the point.

use super::closest_point::brute_force_signed_distance;
use crate::rigid3d::mesh::TriMesh;
use nalgebra::Vector3;

/// A cell is classified whole when |d(c)| exceeds its half-diagonal by this relative margin
/// (round-off in d and s is ~1e-15 relative; the margin keeps a classification exact).
const MARGIN: f64 = 1e-9;

/// One sphere of the tree, in the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereNode {
    /// Centre, m.
    pub centre: Vector3<f64>,
    /// Radius, m.
    pub radius: f64,
    /// Index of the first child in [`SphereTree::nodes`] and the number of children (0 for a
    /// leaf).
    pub children: (u32, u32),
    /// Whether the leaf is a cell on the surface (circumscribed sphere) rather than an inside
    /// ball.
    pub on_surface: bool,
}

/// A sphere tree of one mesh: nodes in breadth-first order, the root first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereTree {
    /// The spheres; children of a node are contiguous.
    pub nodes: Vec<SphereNode>,
}

/// The default octree depth: leaves on the surface 1/16 of the bounding cube's side (measured
/// trade-off in docs/contact.md §"Sphere trees": depth 6 culls more but takes megabytes).
pub const DEFAULT_DEPTH: u32 = 4;

/// A cell of the octree during the build.
struct Cell {
    centre: Vector3<f64>,
    half_side: f64,
}

impl SphereTree {
    /// Builds the tree of `mesh` (closed, outward-oriented) to `depth` octree levels, with the
    /// signed distance `distance` (negative inside; e.g. the BVH's, or the brute force's).
    pub fn build(
        mesh: &TriMesh,
        depth: u32,
        distance: &dyn Fn(&Vector3<f64>) -> f64,
    ) -> SphereTree {
        let (lo, hi) = mesh.vertices.iter().fold(
            (
                Vector3::repeat(f64::INFINITY),
                Vector3::repeat(f64::NEG_INFINITY),
            ),
            |(lo, hi), v| (lo.inf(v), hi.sup(v)),
        );
        let root = Cell {
            centre: (lo + hi) * 0.5,
            half_side: (hi - lo).max() * 0.5,
        };
        let mut tree = SphereTree::default();
        tree.nodes.push(SphereNode {
            centre: root.centre,
            radius: 0.0,
            children: (0, 0),
            on_surface: false,
        });
        // Breadth-first: each level's kept cells become the next level's parents.
        let mut level = vec![(0usize, root)];
        for d in 0..=depth {
            let mut next = Vec::new();
            for (node, cell) in level {
                let s = cell.half_side * 3f64.sqrt();
                let dc = distance(&cell.centre);
                let whole = dc.abs() > s * (1.0 + MARGIN);
                if whole || d == depth {
                    // A leaf: the inside ball, or the straddling cell's circumscribed sphere.
                    let n = &mut tree.nodes[node];
                    let inside = whole && dc < 0.0;
                    n.radius = if inside { -dc } else { s };
                    n.on_surface = !inside;
                    continue;
                }
                let first = tree.nodes.len();
                let mut count = 0;
                for corner in 0..8 {
                    let offset = Vector3::new(
                        if corner & 1 == 0 { -0.5 } else { 0.5 },
                        if corner & 2 == 0 { -0.5 } else { 0.5 },
                        if corner & 4 == 0 { -0.5 } else { 0.5 },
                    ) * cell.half_side;
                    let child = Cell {
                        centre: cell.centre + offset,
                        half_side: cell.half_side * 0.5,
                    };
                    // Wholly outside: no leaf.
                    let sc = child.half_side * 3f64.sqrt();
                    if distance(&child.centre) > sc * (1.0 + MARGIN) {
                        continue;
                    }
                    tree.nodes.push(SphereNode {
                        centre: child.centre,
                        radius: 0.0,
                        children: (0, 0),
                        on_surface: false,
                    });
                    next.push((first + count, child));
                    count += 1;
                }
                tree.nodes[node].children = (first as u32, count as u32);
            }
            level = next;
        }
        tree.enclose_children();
        tree
    }

    /// The tree of `mesh` with the brute-force signed distance (tests; the world uses the BVH's).
    pub fn build_brute_force(mesh: &TriMesh, depth: u32) -> SphereTree {
        SphereTree::build(mesh, depth, &|p| {
            brute_force_signed_distance(mesh, p).distance
        })
    }

    /// Sets every inner node's radius to enclose its children's spheres, from the leaves up
    /// (children come after their parent, so a reverse pass sees children first).
    fn enclose_children(&mut self) {
        for i in (0..self.nodes.len()).rev() {
            let (first, count) = self.nodes[i].children;
            if count == 0 {
                continue;
            }
            let centre = self.nodes[i].centre;
            let radius = (first..first + count)
                .map(|c| {
                    let child = &self.nodes[c as usize];
                    (child.centre - centre).norm() + child.radius
                })
                .fold(0.0, f64::max);
            self.nodes[i].radius = radius;
        }
    }

    /// Whether body-frame point `p` is in some leaf sphere: false means `p` is outside the
    /// solid. Descends only into spheres that hold `p`.
    pub fn may_contain(&self, p: &Vector3<f64>) -> bool {
        let Some(root) = self.nodes.first() else {
            return false;
        };
        if (p - root.centre).norm_squared() > root.radius * root.radius {
            return false;
        }
        // A small explicit stack: at most 8 entries per level, and trees here are ≤ 15 deep.
        let mut stack = [0u32; 128];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            let (first, count) = node.children;
            if count == 0 {
                return true;
            }
            for c in first..first + count {
                let child = &self.nodes[c as usize];
                if (p - child.centre).norm_squared() <= child.radius * child.radius {
                    if top == stack.len() {
                        // Deeper than the stack (never for the depths built here): answer safe.
                        return true;
                    }
                    stack[top] = c;
                    top += 1;
                }
            }
        }
        false
    }

    /// The leaves.
    pub fn leaves(&self) -> impl Iterator<Item = &SphereNode> {
        self.nodes.iter().filter(|n| n.children.1 == 0)
    }

    /// Bytes the nodes take.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<SphereNode>()
    }
}
