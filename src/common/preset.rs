//! The named starting points of a scene's parameters, in either system (`--preset`, or
//! `"preset"` in a 2D scene's `parameters` or a 3D scene's `sim_parameters`): the project's
//! defaults, or everything the assignment's starter code does, for comparison with student code
//! built on it. Each system says what a preset sets: `crate::blocks2d::params::Params2::starter`
//! (docs/blocks2d.md §"The starter preset") and the 3D scene reader (docs/scene-format.md).

/// A named set of parameters to start from; single keys and options override it.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The project's defaults (2D: the demonstration settings under which the assignment's four
    /// demonstration images come to rest).
    #[default]
    Default,
    /// The starter code's own behaviour, for comparison with student code.
    Starter,
}
