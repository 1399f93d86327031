//! Limits on what outside input may make the program allocate (docs/scene-format.md §"Input
//! limits"): every file read from outside (scenes, body files, meshes, problem files, traces,
//! images) is judged by its size before it is read, and an image by its pixel count before its
//! blocks are made. Each limit is process-wide, set once by the command line (`--max-input-mb`,
//! `--max-image-pixels`) and read by the readers; a file beyond it is a one-line error naming
//! the option that raises it. Every count that allocates (bodies, triangles, records, contacts)
//! grows at most linearly with the file's bytes, so the byte limit bounds them all; an image's
//! blocks grow with its pixels, which a compressed file does not bound, hence the second limit.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Default largest input file, bytes: 1 GiB (a 3D trace of 20 bodies recorded every step for an
/// hour at 1 ms is ~1 GB; the assignment's largest input is 2 MB).
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 1 << 30;

/// Default largest image, pixels: 4096 × 4096 (the assignment's largest image has 0.2 M pixels; a
/// 2D body is made of a block per non-white pixel, ~200 bytes each with its disc tree).
pub const DEFAULT_MAX_IMAGE_PIXELS: u64 = 4096 * 4096;

static MAX_INPUT_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_INPUT_BYTES);
static MAX_IMAGE_PIXELS: AtomicU64 = AtomicU64::new(DEFAULT_MAX_IMAGE_PIXELS);

/// Sets the largest input file, bytes (`--max-input-mb`).
pub fn set_max_input_bytes(bytes: u64) {
    MAX_INPUT_BYTES.store(bytes, Ordering::Relaxed);
}

/// Sets the largest image, pixels (`--max-image-pixels`).
pub fn set_max_image_pixels(pixels: u64) {
    MAX_IMAGE_PIXELS.store(pixels, Ordering::Relaxed);
}

/// The largest input now allowed, bytes (`--max-input-mb`): also the bound on what a file's
/// header may make a reader allocate.
pub fn max_input_bytes() -> u64 {
    MAX_INPUT_BYTES.load(Ordering::Relaxed)
}

/// The largest image now allowed, pixels.
pub fn max_image_pixels() -> u64 {
    MAX_IMAGE_PIXELS.load(Ordering::Relaxed)
}

/// Fails when the file at `path` is larger than the input limit; the error says by how much and
/// which option raises it (the caller adds the file's name).
pub fn check_size(path: &Path) -> std::io::Result<()> {
    let limit = MAX_INPUT_BYTES.load(Ordering::Relaxed);
    let size = std::fs::metadata(path)?.len();
    if size > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "{} is more than the input limit of {} (raise it with --max-input-mb)",
                bytes(size),
                bytes(limit)
            ),
        ));
    }
    Ok(())
}

/// `std::fs::read_to_string` within the input limit.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    check_size(path)?;
    std::fs::read_to_string(path)
}

/// `std::fs::File::open` within the input limit.
pub fn open(path: &Path) -> std::io::Result<std::fs::File> {
    check_size(path)?;
    std::fs::File::open(path)
}

/// Fails when an image of `width` × `height` is beyond the pixel limit.
pub fn check_pixels(width: u64, height: u64) -> Result<(), String> {
    let limit = max_image_pixels();
    let pixels = width.saturating_mul(height);
    if pixels > limit {
        return Err(format!(
            "the image is {width} × {height} = {pixels} pixels, more than the limit of {limit} (raise it with --max-image-pixels)"
        ));
    }
    Ok(())
}

/// A size in bytes for a message: bytes below 1 kB, kB below 1 MB, else MB (MB = 2²⁰ bytes, as
/// `--max-input-mb` counts them).
fn bytes(n: u64) -> String {
    match n {
        0..1024 => format!("{n} bytes"),
        1024..1048576 => format!("{:.1} kB", n as f64 / 1024.0),
        _ => format!("{:.1} MB", n as f64 / 1048576.0),
    }
}
