//! Minimum enclosing circle (Welzl's algorithm, in its randomised incremental form: the points
//! shuffled once, then three nested loops; de Berg et al., Computational Geometry, §4.7).
//! docs/blocks2d.md §"Minimum enclosing circle".

use nalgebra::Vector2;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// A circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Centre.
    pub centre: Vector2<f64>,
    /// Radius, ≥ 0.
    pub radius: f64,
}

impl Circle {
    /// Whether `p` is inside or on the circle, with a relative slack of 1e-12 for round-off.
    pub fn contains(&self, p: &Vector2<f64>) -> bool {
        (p - self.centre).norm() <= self.radius * (1.0 + 1e-12) + 1e-12
    }

    fn from_diameter(a: &Vector2<f64>, b: &Vector2<f64>) -> Circle {
        Circle {
            centre: (a + b) / 2.0,
            radius: (a - b).norm() / 2.0,
        }
    }

    /// The circle through three points; for (nearly) collinear points, the circle on the
    /// farthest pair as diameter (the smallest circle containing all three).
    fn through(a: &Vector2<f64>, b: &Vector2<f64>, c: &Vector2<f64>) -> Circle {
        let (ab, ac) = (b - a, c - a);
        let d = 2.0 * (ab.x * ac.y - ab.y * ac.x);
        if d.abs() <= 1e-12 * ab.norm_squared().max(ac.norm_squared()) {
            let pairs = [(a, b), (a, c), (b, c)];
            let (p, q) = pairs
                .iter()
                .max_by(|x, y| (x.0 - x.1).norm().total_cmp(&(y.0 - y.1).norm()))
                .copied()
                .unwrap_or((a, b));
            return Circle::from_diameter(p, q);
        }
        let (b2, c2) = (ab.norm_squared(), ac.norm_squared());
        let offset = Vector2::new(ac.y * b2 - ab.y * c2, ab.x * c2 - ac.x * b2) / d;
        Circle {
            centre: a + offset,
            radius: offset.norm(),
        }
    }
}

/// The smallest circle containing every point (radius 0 for one point; `None` for none).
/// Welzl's expected linear time needs a random order; the order is shuffled by a generator with
/// a fixed seed, so the result is reproducible.
pub fn min_enclosing_circle(points: &[Vector2<f64>]) -> Option<Circle> {
    let mut p: Vec<Vector2<f64>> = points.to_vec();
    p.shuffle(&mut ChaCha8Rng::seed_from_u64(0x5EED));
    let mut c = Circle {
        centre: *p.first()?,
        radius: 0.0,
    };
    for i in 1..p.len() {
        if c.contains(&p[i]) {
            continue;
        }
        c = Circle {
            centre: p[i],
            radius: 0.0,
        };
        for j in 0..i {
            if c.contains(&p[j]) {
                continue;
            }
            c = Circle::from_diameter(&p[i], &p[j]);
            for k in 0..j {
                if !c.contains(&p[k]) {
                    c = Circle::through(&p[i], &p[j], &p[k]);
                }
            }
        }
    }
    Some(c)
}

/// The same by brute force: the smallest of all circles on two points as diameter and through
/// three points that contains every point. O(n⁴); for tests.
pub fn brute_force_enclosing_circle(points: &[Vector2<f64>]) -> Option<Circle> {
    let n = points.len();
    if n == 1 {
        return Some(Circle {
            centre: points[0],
            radius: 0.0,
        });
    }
    let mut best: Option<Circle> = None;
    let mut consider = |c: Circle| {
        if points.iter().all(|p| c.contains(p)) && best.is_none_or(|b| c.radius < b.radius) {
            best = Some(c);
        }
    };
    for i in 0..n {
        for j in i + 1..n {
            consider(Circle::from_diameter(&points[i], &points[j]));
            for k in j + 1..n {
                consider(Circle::through(&points[i], &points[j], &points[k]));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    //! Small exact cases; the randomised comparison with [`brute_force_enclosing_circle`] is
    //! tests/suite/blocks2d/properties.rs::minimum_enclosing_circle_contains_every_point_and_matches_brute_force.

    use super::*;

    fn p(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    #[test]
    fn no_points_have_no_circle_and_one_point_has_radius_zero() {
        assert_eq!(min_enclosing_circle(&[]), None);
        let c = min_enclosing_circle(&[p(3.0, -2.0)]).unwrap();
        assert_eq!((c.centre, c.radius), (p(3.0, -2.0), 0.0));
    }

    #[test]
    fn the_corners_of_a_square_lie_on_the_circle_of_its_diagonal() {
        let c =
            min_enclosing_circle(&[p(0.0, 0.0), p(2.0, 0.0), p(2.0, 2.0), p(0.0, 2.0)]).unwrap();
        // Round-off only: the centre is an average of exact values.
        assert!((c.centre - p(1.0, 1.0)).norm() < 1e-12, "{c:?}");
        assert!((c.radius - 2f64.sqrt()).abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn interior_points_do_not_change_the_circle_of_an_obtuse_triangle() {
        // An obtuse triangle's smallest circle has its longest side as diameter, not the
        // circumcircle; the point inside changes nothing.
        let c =
            min_enclosing_circle(&[p(-3.0, 0.0), p(3.0, 0.0), p(0.0, 1.0), p(0.5, 0.2)]).unwrap();
        assert!((c.centre - p(0.0, 0.0)).norm() < 1e-12, "{c:?}");
        assert!((c.radius - 3.0).abs() < 1e-12, "{c:?}");
    }
}
