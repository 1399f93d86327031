//! The known-answer scenes `rigidref validate` runs (docs/validation.md §"Scenes"): each canonical
//! scene with a closed form or an exact statement about its outcome, how long it runs, and which
//! observables judge it.

/// What a scene's answer is known to be, which picks its observables ([`super::observe`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known {
    /// A body sliding on the ground at v₀ with friction μ stops after v₀/(μg), having travelled
    /// v₀²/(2μg).
    Slide,
    /// A body pulled by F = Ḟ t sticks until μ m g / Ḟ, then v = Ḟ (t − t₀)² / (2m).
    Drag,
    /// A solid ball on an incline (gravity tilted by θ) rolls at (5/7) g sin θ without slipping.
    Rolls,
    /// The same ball with μ < (2/7) tan θ slides at g (sin θ − μ cos θ) and spins up at
    /// μ m g cos θ r / J.
    Slides,
    /// A torque-free body spun near its intermediate axis flips (against RK4).
    Flip,
    /// A body in free flight under gravity: x₀ + v₀ t + g t²/2.
    Projectile,
    /// A heavy body resting on a light one on the ground: both stay, each layer carries the weight
    /// above it (Σλn = m g h per step).
    HeavyOnLight,
    /// A body dropped on the ground comes to rest on it, carrying m g h per step.
    Rest,
    /// A stack of bodies stands.
    Stack,
}

/// One scene of the set.
#[derive(Clone, Copy, Debug)]
pub struct KnownScene {
    /// The file in the scene folder.
    pub file: &'static str,
    /// How long it runs, s (seconds per engine and setting: long enough for its answer).
    pub seconds: f64,
    /// What is known about it.
    pub known: Known,
}

/// The 3D set, in report order.
pub const SCENES_3D: [KnownScene; 10] = [
    KnownScene {
        file: "sliding_cube.json",
        seconds: 0.4,
        known: Known::Slide,
    },
    KnownScene {
        file: "sliding_box.json",
        seconds: 1.5,
        known: Known::Slide,
    },
    KnownScene {
        file: "dragged_cube.json",
        seconds: 0.5,
        known: Known::Drag,
    },
    KnownScene {
        file: "ball_incline_rolls.json",
        seconds: 1.0,
        known: Known::Rolls,
    },
    KnownScene {
        file: "ball_incline_slides.json",
        seconds: 1.0,
        known: Known::Slides,
    },
    KnownScene {
        file: "dzhanibekov.json",
        seconds: 10.0,
        known: Known::Flip,
    },
    KnownScene {
        file: "projectile.json",
        seconds: 2.0,
        known: Known::Projectile,
    },
    KnownScene {
        file: "heavy_on_light.json",
        seconds: 1.0,
        known: Known::HeavyOnLight,
    },
    KnownScene {
        file: "sphere_drop.json",
        seconds: 2.0,
        known: Known::Rest,
    },
    KnownScene {
        file: "box_stack.json",
        seconds: 2.0,
        known: Known::Stack,
    },
];

/// The scene of the set named `name` (its file name, with or without `.json`).
pub fn known_scene(name: &str) -> Option<KnownScene> {
    let stem = name.strip_suffix(".json").unwrap_or(name);
    SCENES_3D
        .iter()
        .find(|s| s.file.strip_suffix(".json") == Some(stem))
        .copied()
}
