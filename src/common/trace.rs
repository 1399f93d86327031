//! What the traces of both systems share: the header's format name and version
//! (docs/trace-format.md).

/// Value of the header's `format` key.
pub const FORMAT_NAME: &str = "rigidref-trace";
/// Value of the header's `version` key; raised on any incompatible change.
pub const FORMAT_VERSION: u32 = 1;
