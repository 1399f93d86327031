//! `collision: complete` against the separating-axis oracle (docs/contact.md §"The oracle
//! campaign"): two of the campaign's built-in convex meshes (the off-centre 0.2 m cube, a 0.5 m
//! cube, a brick, a slab, an octahedron), posed either by the campaign's generator (a pose kind
//! and a seed: faces exactly touching, aligned, turned by multiples of 90°, edge on edge, the
//! same footprint, nudged by ulps) or, from a longer input, by positions and rotation vectors
//! read from the bytes. Any disagreement with the oracle beyond the stated bounds panics.
#![no_main]
use libfuzzer_sys::fuzz_target;
use nalgebra::{Rotation3, Vector3};
use rigidref::verify::detection::{CampaignReport, DetectionCampaign, POSE_KINDS};
use std::cell::RefCell;

thread_local! {
    static CAMPAIGN: RefCell<DetectionCampaign> =
        RefCell::new(DetectionCampaign::new(DetectionCampaign::built_in_meshes()).unwrap());
}

fn f64_at(data: &[u8], k: usize) -> f64 {
    f64::from_le_bytes(data[k * 8..k * 8 + 8].try_into().unwrap())
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 9 {
        return;
    }
    CAMPAIGN.with(|c| {
        let mut campaign = c.borrow_mut();
        let n = campaign.mesh_count();
        if data.len() >= 2 + 12 * 8 {
            let floats = &data[2..];
            let v = |k: usize| Vector3::new(f64_at(floats, k), f64_at(floats, k + 1), f64_at(floats, k + 2));
            let (xa, ra, xb, rb) = (v(0), v(3), v(6), v(9));
            // Poses within reach and representable: a kilometre, rotation vectors of any angle.
            let sane = |w: &Vector3<f64>, limit: f64| w.iter().all(|x| x.is_finite() && x.abs() <= limit);
            if !(sane(&xa, 1e3) && sane(&(xb - xa), 2.0) && sane(&ra, 100.0) && sane(&rb, 100.0)) {
                return;
            }
            let (a, b) = (data[0] as usize % n, data[1] as usize % n);
            let bodies = campaign.bodies(
                (a, xa, *Rotation3::new(ra).matrix()),
                (b, xb, *Rotation3::new(rb).matrix()),
            );
            let check = campaign.check_bodies((a, b), &bodies);
            assert!(check.disagreements.is_empty(), "{:?}: {:?}", bodies.map(|b| (b.x, b.rotation)), check);
        } else {
            let kind = POSE_KINDS[data[0] as usize % POSE_KINDS.len()];
            let seed = u64::from_le_bytes(data[1..9].try_into().unwrap());
            let mut report = CampaignReport::default();
            campaign.check_case(kind, seed, &mut report);
            assert_eq!(report.disagreements, 0, "{:?}", report.examples);
        }
    });
});
