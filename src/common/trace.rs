//! What the traces of both systems share: the header's format name and version
//! (docs/trace-format.md).

/// Value of the header's `format` key.
pub const FORMAT_NAME: &str = "rigidref-trace";
/// Value of the header's `version` key; raised on any incompatible change. Version 2 (issue 13):
/// 3D headers name the `collision` method, 3D records carry `penetration`, and a 3D contact's
/// point may be a manifold point rather than a vertex (`collision: complete`).
pub const FORMAT_VERSION: u32 = 2;
