//! Polyhedral mass properties of a closed triangle mesh of uniform density.
//!
//! docs/massprops.md §"Mass properties of a polyhedron". Checked by
//! `tests/suite/rigid3d/massprops.rs::massprops_reproduces_the_assignment_body_files` and the unit tests below.

use crate::rigid3d::mesh::TriMesh;
use nalgebra::{Matrix3, Vector3};

/// Mass properties of a uniform solid bounded by a triangle mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// Volume V, m³.
    pub volume: f64,
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Mass m = ρV, kg.
    pub mass: f64,
    /// Centre of mass c in the mesh's frame, m.
    pub center_of_mass: Vector3<f64>,
    /// Inertia about the centre of mass in the mesh's axes, J = ρ(tr(C)I − C), kg·m².
    pub inertia: Matrix3<f64>,
}

/// Second moment of the canonical tetrahedron (0, e1, e2, e3): ∫ x xᵀ dV over it.
fn canonical_covariance() -> Matrix3<f64> {
    Matrix3::new(2.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 2.0) / 120.0
}

/// Mass properties of the solid bounded by `mesh` at `density` (kg/m³).
///
/// The solid is cut into one tetrahedron (o, a, b, c) per triangle with a common apex o; a
/// tetrahedron is the canonical one mapped by A = [a−o b−o c−o], so its volume, first moment and
/// second moment C are det(A) times the canonical ones pushed through A. Summing signed
/// contributions gives the integrals over the solid exactly (up to round-off) for a closed,
/// outward oriented mesh; call [`TriMesh::check_solid`] first. The apex o is the vertex mean, not
/// the mesh origin, so that a mesh far from its origin does not lose digits to cancellation.
/// docs/massprops.md §"Mass properties of a polyhedron".
pub fn mass_properties(mesh: &TriMesh, density: f64) -> MassProperties {
    let apex = mesh.vertices.iter().sum::<Vector3<f64>>() / mesh.vertices.len() as f64;
    let canonical = canonical_covariance();
    let mut volume = 0.0;
    let mut first_moment = Vector3::zeros();
    let mut covariance = Matrix3::zeros();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i] - apex);
        let map = Matrix3::from_columns(&[a, b, c]);
        let det = map.determinant();
        volume += det / 6.0;
        first_moment += (a + b + c) * (det / 24.0);
        covariance += map * canonical * map.transpose() * det;
    }
    let centroid = first_moment / volume; // relative to the apex
    // Parallel-axis shift of the second moment from the apex to the centre of mass.
    let covariance_com = covariance - centroid * centroid.transpose() * volume;
    let inertia = (Matrix3::identity() * covariance_com.trace() - covariance_com) * density;
    MassProperties {
        volume,
        density,
        mass: density * volume,
        center_of_mass: apex + centroid,
        inertia: (inertia + inertia.transpose()) * 0.5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_far_from_the_origin_matches_the_closed_form() {
        let (w, h, d) = (0.4, 0.8, 1.2);
        let lo = Vector3::new(100.0, -50.0, 7.0);
        let mesh = TriMesh::cuboid(lo, lo + Vector3::new(w, h, d));
        assert!(mesh.check_solid("box").unwrap().is_empty());
        let props = mass_properties(&mesh, 1000.0);
        let m = 1000.0 * w * h * d;
        // Closed form for a box: J = m/12 diag(h²+d², w²+d², w²+h²). The 1e-12 relative
        // tolerance is round-off after a shift of ~100 m over a body of ~1 m.
        assert!((props.mass - m).abs() < 1e-12 * m);
        assert!((props.center_of_mass - (lo + Vector3::new(w, h, d) / 2.0)).norm() < 1e-12);
        let expected =
            Matrix3::from_diagonal(&Vector3::new(h * h + d * d, w * w + d * d, w * w + h * h))
                * (m / 12.0);
        assert!(
            (props.inertia - expected).norm() < 1e-11 * expected.norm(),
            "{}",
            props.inertia
        );
    }
}
