//! Limits on what outside input may make the program allocate (docs/scene-format.md §"Input
//! limits"): every file read from outside (scenes, body files, meshes, problem files, traces,
//! images) is judged by its size before it is read, and an image by its pixel count before its
//! blocks are made. Each limit is process-wide, set once by the command line (`--max-input-mb`,
//! `--max-image-pixels`) and read by the readers; a file beyond it is a one-line error naming
//! the option that raises it. Every count that allocates (bodies, triangles, records, contacts)
//! grows at most linearly with the file's bytes, so the byte limit bounds them all; an image's
//! blocks grow with its pixels, which a compressed file does not bound, hence the second limit.

use std::io::Read;
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

/// `std::fs::read_to_string` within the input limit: judged by its size first, then counted
/// while it is read (a file whose size the metadata does not tell, such as a device or a file
/// that grows, stops at the limit).
pub fn read_text(path: &Path) -> std::io::Result<String> {
    check_size(path)?;
    let limit = MAX_INPUT_BYTES.load(Ordering::Relaxed);
    let mut text = String::new();
    Capped::new(std::fs::File::open(path)?, limit, "--max-input-mb").read_to_string(&mut text)?;
    Ok(text)
}

/// A reader that fails as soon as more than its limit of bytes has come through it: the
/// streaming half of an input limit, for what a file's metadata does not tell (a device such as
/// /dev/zero reports no size; a file may grow while it is read).
pub struct Capped<R> {
    inner: R,
    left: u64,
    limit: u64,
    option: &'static str,
}

impl<R> Capped<R> {
    /// `inner`, limited to `limit` bytes; `option` is what raises the limit, for the message.
    pub fn new(inner: R, limit: u64, option: &'static str) -> Capped<R> {
        Capped {
            inner,
            left: limit,
            limit,
            option,
        }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        // One byte more than is left, so that reaching the limit exactly is not an error.
        let room = usize::try_from(self.left.saturating_add(1)).unwrap_or(usize::MAX);
        let want = buf.len().min(room);
        let n = self.inner.read(&mut buf[..want])?;
        if n as u64 > self.left {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "more than the limit of {} was read (raise it with {})",
                    bytes(self.limit),
                    self.option
                ),
            ));
        }
        self.left -= n as u64;
        Ok(n)
    }
}

/// Opens `path` for reading only if it is a regular file (after symbolic links) of at most
/// `limit` bytes, and counts what is read against `limit` (`option` raises it). A FIFO, a
/// device or a folder is an error without being read: opening a FIFO for reading waits for a
/// writer, and a device such as /dev/zero never ends. The file is opened without waiting
/// (`O_NONBLOCK`) and judged again from the opened handle, so that a FIFO put in its place
/// between the two looks cannot block either. What `compare`, `compare-problem` and `grade`
/// read traces and problem files with (docs/grading.md §"Untrusted submissions").
pub fn open_regular(
    path: &Path,
    limit: u64,
    option: &'static str,
) -> std::io::Result<Capped<std::fs::File>> {
    let not_regular = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a FIFO, a device or a folder); not read",
        )
    };
    let too_large = |size: u64| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "{} is more than the limit of {} (raise it with {option}); not read",
                bytes(size),
                bytes(limit)
            ),
        )
    };
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    Ok(Capped::new(file, limit, option))
}

/// The text of the regular file at `path` ([`open_regular`]) within `limit` bytes.
pub fn read_regular_text(path: &Path, limit: u64, option: &'static str) -> std::io::Result<String> {
    let mut text = String::new();
    open_regular(path, limit, option)?.read_to_string(&mut text)?;
    Ok(text)
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
