//! Whether the convex hulls of two point sets overlap, with a certificate either way: the
//! Gilbert–Johnson–Keerthi (GJK) iteration on their Minkowski difference. The penetration
//! measure's oracle asks it before pruning (docs/contact.md §"Penetration measure").
//!
//! The hulls A and B overlap exactly when the origin lies in A − B = {a − b}. GJK keeps a simplex
//! of up to four points of A − B (support points: the farthest a of A minus the farthest b of B
//! in opposite directions) and moves towards the origin:
//! - if the farthest point of A − B along the search direction d falls short of the origin
//!   (max over A of d·x < min over B of d·x), d separates the hulls: **apart**, certified by that
//!   inequality alone;
//! - if the simplex becomes a tetrahedron that contains the origin (each face's plane has the
//!   origin on the same side as the opposite corner, or on it), the hulls share a point:
//!   **overlap** (touching included), certified by those four sign tests, made afresh;
//! - otherwise, after [`MAX_ITERATIONS`] or on a degenerate simplex, **undecided**, and the
//!   caller must not rely on either.
//!
//! Only the two certificates are trusted; the steps between them choose where to look (the
//! simplex cases of Muratori's formulation) and cannot make a verdict wrong, only late. Both
//! certificates are computed in floating point, so either can be wrong only for hulls within
//! round-off of touching (what that means for the oracle: docs/contact.md §"Penetration
//! measure", "Overlap first").

use nalgebra::Vector3;

/// What [`hulls_overlap`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The hulls share a point (they overlap or touch).
    Overlap,
    /// An axis separates the hulls.
    Apart,
    /// Neither certificate within [`MAX_ITERATIONS`] (or the simplex degenerated).
    Undecided,
}

/// The most support points taken before answering [`Verdict::Undecided`]. The cap stops a
/// cycle, which round-off can cause when the origin sits on the boundary of A − B (the random
/// poses of the test suite never reached it: 0 undecided of 250).
pub const MAX_ITERATIONS: usize = 64;

/// The support point of A − B along `d` and how far A − B reaches along it (max over A of d·x
/// minus min over B of d·x; negative: `d` separates the hulls).
fn support(a: &[Vector3<f64>], b: &[Vector3<f64>], d: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let farthest = |points: &[Vector3<f64>], sign: f64| {
        let mut best = (points[0], sign * points[0].dot(d));
        for p in &points[1..] {
            let s = sign * p.dot(d);
            if s > best.1 {
                best = (*p, s);
            }
        }
        best
    };
    let (pa, reach_a) = farthest(a, 1.0);
    let (pb, reach_b) = farthest(b, -1.0);
    (pa - pb, reach_a + reach_b)
}

/// Whether the convex hulls of `a` and `b` (each non-empty) overlap, starting the search along
/// `first` (any direction; the penetration measure passes a's centre minus b's, where A − B lies
/// from the origin).
pub fn hulls_overlap(a: &[Vector3<f64>], b: &[Vector3<f64>], first: &Vector3<f64>) -> Verdict {
    let mut d = if first.norm_squared() > 0.0 {
        *first
    } else {
        Vector3::x()
    };
    let mut simplex = Simplex::default();
    for _ in 0..MAX_ITERATIONS {
        let (p, reach) = support(a, b, &d);
        if reach < 0.0 {
            return Verdict::Apart;
        }
        simplex.push(p);
        match simplex.towards_origin() {
            Some(next) if next.norm_squared() > 0.0 => d = next,
            // The origin on the simplex's line or plane, or a flat simplex: no direction to go.
            Some(_) => return Verdict::Undecided,
            None if simplex.contains_origin() => return Verdict::Overlap,
            None => return Verdict::Undecided,
        }
    }
    Verdict::Undecided
}

/// Up to four points of A − B, the newest last.
#[derive(Default)]
struct Simplex {
    points: [Vector3<f64>; 4],
    len: usize,
}

impl Simplex {
    fn push(&mut self, p: Vector3<f64>) {
        self.points[self.len] = p;
        self.len += 1;
    }

    fn set(&mut self, points: &[Vector3<f64>]) {
        self.points[..points.len()].copy_from_slice(points);
        self.len = points.len();
    }

    /// Reduces the simplex to the part nearest the origin and returns the direction to search
    /// next, or `None` when a tetrahedron encloses the origin (to be certified).
    fn towards_origin(&mut self) -> Option<Vector3<f64>> {
        match self.len {
            1 => Some(-self.points[0]),
            2 => Some(self.line()),
            3 => Some(self.triangle()),
            _ => self.tetrahedron(),
        }
    }

    /// The newest point a and b: towards the origin from the segment, or from a alone.
    fn line(&mut self) -> Vector3<f64> {
        let [b, a] = [self.points[0], self.points[1]];
        let (ab, ao) = (b - a, -a);
        if ab.dot(&ao) > 0.0 {
            let towards = ab.cross(&ao).cross(&ab);
            if towards == Vector3::zeros() {
                // The origin on the segment's line (two opposite support points of a
                // symmetric A − B): look sideways, for a triangle with the origin in its plane.
                let side = if ab.x.abs() < ab.y.abs() {
                    Vector3::x()
                } else {
                    Vector3::y()
                };
                ab.cross(&side)
            } else {
                towards
            }
        } else {
            self.set(&[a]);
            ao
        }
    }

    /// The newest point a, and b, c.
    fn triangle(&mut self) -> Vector3<f64> {
        let [c, b, a] = [self.points[0], self.points[1], self.points[2]];
        let (ab, ac, ao) = (b - a, c - a, -a);
        let abc = ab.cross(&ac);
        if abc == Vector3::zeros() {
            // Three points on a line: keep the newest two.
            self.set(&[b, a]);
            return self.line();
        }
        if abc.cross(&ac).dot(&ao) > 0.0 {
            if ac.dot(&ao) > 0.0 {
                self.set(&[c, a]);
                ac.cross(&ao).cross(&ac)
            } else {
                self.set(&[b, a]);
                self.line()
            }
        } else if ab.cross(&abc).dot(&ao) > 0.0 {
            self.set(&[b, a]);
            self.line()
        } else if abc.dot(&ao) > 0.0 {
            abc
        } else {
            // The origin below the triangle: turn it so that its normal faces the origin.
            self.set(&[b, c, a]);
            -abc
        }
    }

    /// The newest point a over the triangle (d, c, b) whose normal faces it: the face the origin
    /// is beyond, as a triangle, or `None` when it is beyond none.
    fn tetrahedron(&mut self) -> Option<Vector3<f64>> {
        let [d, c, b, a] = self.points;
        let ao = -a;
        for face in [[c, b, a], [d, c, a], [b, d, a]] {
            let [p, q, r] = face;
            let normal = (q - r).cross(&(p - r));
            if normal.dot(&ao) > 0.0 {
                self.set(&face);
                return Some(self.triangle());
            }
        }
        None
    }

    /// Whether the tetrahedron holds the origin: for each face, the origin is on the side of the
    /// opposite corner or on the face's plane (sign tests only, independent of the steps above).
    fn contains_origin(&self) -> bool {
        let t = &self.points;
        for (i, j, k, l) in [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)] {
            let normal = (t[j] - t[i]).cross(&(t[k] - t[i]));
            let corner = normal.dot(&(t[l] - t[i]));
            let origin = -normal.dot(&t[i]);
            if corner == 0.0 || origin * corner < 0.0 {
                return false;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron(points: [[f64; 3]; 4]) -> Simplex {
        let mut simplex = Simplex::default();
        for p in points {
            simplex.push(Vector3::from(p));
        }
        simplex
    }

    /// The overlap certificate's own sign tests, apart from the steps that lead to them: a
    /// tetrahedron about the origin holds it, also with the origin on a face; one beside the
    /// origin (by 1e-9 m) or flat does not.
    #[test]
    fn the_overlap_certificate_holds_the_origin_only_inside_or_on_the_tetrahedron() {
        let about = [
            [1.0, 0.0, -1.0],
            [-1.0, 0.0, -1.0],
            [0.0, 1.0, 1.0],
            [0.0, -1.0, 1.0],
        ];
        assert!(tetrahedron(about).contains_origin());
        let on_a_face = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-1.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert!(tetrahedron(on_a_face).contains_origin());
        let beside = on_a_face.map(|[x, y, z]| [x, y, z + 1e-9]);
        assert!(!tetrahedron(beside).contains_origin());
        let flat = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert!(!tetrahedron(flat).contains_origin());
    }

    /// The apart certificate: two unit cubes 1e-9 m apart are apart, and GJK says so; the same
    /// cubes overlapping by 1e-9 m are not.
    #[test]
    fn cubes_a_nanometre_apart_are_apart_and_a_nanometre_into_each_other_overlap() {
        let cube = |dx: f64| -> Vec<Vector3<f64>> {
            (0..8)
                .map(|k| Vector3::new((k & 1) as f64 + dx, ((k >> 1) & 1) as f64, (k >> 2) as f64))
                .collect()
        };
        let first = Vector3::new(-1.0, 0.0, 0.0);
        assert_eq!(
            hulls_overlap(&cube(0.0), &cube(1.0 + 1e-9), &first),
            Verdict::Apart
        );
        assert_eq!(
            hulls_overlap(&cube(0.0), &cube(1.0 - 1e-9), &first),
            Verdict::Overlap
        );
    }
}
