//! Pieces both systems use that belong to neither: the broad phase, the validated scene values
//! and the one scene-file reader, and the stopwatch.
//!
//! - [`faults`]: the switch of the teeth tests' deliberate bugs (always off outside them);
//! - [`broad`]: the broad phase on axis-aligned boxes (3D bodies; 2D bodies as flat boxes);
//! - [`hash`]: the warm-start maps' fast deterministic hasher;
//! - [`pair_cache`]: temporal coherence in detection, per body pair (both systems);
//! - [`input`]: the limits on what outside input may make the program allocate;
//! - [`values`]: scene values that check themselves while they are read (positive, fraction, …);
//! - [`scene_json`]: the JSON reader with `file:line:column` errors, and [`scene_json::SceneError`];
//! - [`preset`]: the named starting points of a scene's parameters (`--preset starter`);
//! - [`stats`]: the median;
//! - [`timing`]: wall and thread CPU time of a piece of work;
//! - [`warm_store`]: the warm start's store of last solve's impulses, by contact key (both systems);
//! - [`writer`]: a writer thread, so that formatting a trace is not in the simulation loop;
//! - [`trace`]: the trace format's name and version, for both systems' traces.

pub mod broad;
pub mod faults;
pub mod hash;
pub mod input;
pub mod pair_cache;
pub mod preset;
pub mod scene_json;
pub mod stats;
pub mod timing;
pub mod trace;
pub mod values;
pub mod warm_store;
pub mod writer;
