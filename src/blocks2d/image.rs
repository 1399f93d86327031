//! Bodies from an image: each connected component of non-white pixels is a body made of unit
//! square blocks, one per pixel. docs/blocks2d.md §"Bodies from pixels".
//!
//! World frame: x is the image column, y the image row (so y grows downward, as in the image),
//! one block is one unit of length, the block of pixel (row i, column j) has its centre at
//! (j, i). Angles are measured from +x toward +y (clockwise on screen). Gravity defaults to +y,
//! toward increasing row, so images stand the right way up.

use nalgebra::Vector2;
use std::path::Path;

/// A block: one pixel of a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// Centre in the image frame (column, row).
    pub pixel: Vector2<f64>,
    /// Colour, channels in [0, 1].
    pub colour: [f64; 3],
    /// Mass 1 − (0.3 r + 0.59 g + 0.11 b) (black is 1).
    pub mass: f64,
}

/// The blocks of one connected component.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockGroup {
    /// The blocks, in row-major pixel order.
    pub blocks: Vec<Block>,
    /// Every block is a shade of blue (r = g < b): the body is pinned.
    pub pinned: bool,
}

/// Loading settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSettings {
    /// A pixel is empty when every channel is at least 1 − this (near-white), or it is fully
    /// transparent. Default 0.05, the assignment's starter's.
    pub white_threshold: f64,
}

impl Default for ImageSettings {
    fn default() -> Self {
        ImageSettings {
            white_threshold: 0.05,
        }
    }
}

/// A block's mass from its colour: 1 − (0.3 r + 0.59 g + 0.11 b), channels in [0, 1].
pub fn block_mass(colour: [f64; 3]) -> f64 {
    1.0 - (0.3 * colour[0] + 0.59 * colour[1] + 0.11 * colour[2])
}

/// Whether a colour is a shade of blue: r = g < b (to the 8-bit channel).
pub fn is_blue(colour: [u8; 3]) -> bool {
    colour[0] == colour[1] && colour[1] < colour[2]
}

/// Reads a PNG and splits it into bodies. Errors name the file.
pub fn load_image(path: &Path, settings: &ImageSettings) -> Result<Vec<BlockGroup>, String> {
    crate::common::input::check_size(path)
        .map_err(|e| format!("{}: cannot open: {e}", path.display()))?;
    let reader = image::ImageReader::open(path)
        .map_err(|e| format!("{}: cannot open: {e}", path.display()))?
        .with_guessed_format()
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    // The pixel limit from the header, before anything is decoded.
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| format!("{}: not a readable image: {e}", path.display()))?;
    crate::common::input::check_pixels(u64::from(w), u64::from(h))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let img = image::ImageReader::open(path)
        .map_err(|e| format!("{}: cannot open: {e}", path.display()))?
        .with_guessed_format()
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?
        .decode()
        .map_err(|e| format!("{}: not a readable image: {e}", path.display()))?
        .to_rgba8();
    let (width, height) = (img.width() as usize, img.height() as usize);
    let pixels: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    let groups = blocks_from_pixels(width, height, &pixels, settings);
    if groups.is_empty() {
        return Err(format!(
            "{}: the image has no non-white pixels (threshold {}), so no bodies",
            path.display(),
            settings.white_threshold
        ));
    }
    Ok(groups)
}

/// Splits an RGBA pixel grid (row-major) into bodies: 8-neighbour connected components of
/// non-empty pixels, in the order of their first pixel in row-major order.
pub fn blocks_from_pixels(
    width: usize,
    height: usize,
    pixels: &[[u8; 4]],
    settings: &ImageSettings,
) -> Vec<BlockGroup> {
    let limit = 1.0 - settings.white_threshold;
    let filled = |p: &[u8; 4]| p[3] > 0 && !(0..3).all(|c| f64::from(p[c]) / 255.0 >= limit);
    let mut label = vec![usize::MAX; width * height];
    let mut groups = Vec::new();
    let mut stack = Vec::new();
    for start in 0..width * height {
        if label[start] != usize::MAX || !filled(&pixels[start]) {
            continue;
        }
        let id = groups.len();
        label[start] = id;
        stack.push(start);
        let mut members = Vec::new();
        while let Some(k) = stack.pop() {
            members.push(k);
            let (i, j) = ((k / width) as i64, (k % width) as i64);
            for di in -1..=1 {
                for dj in -1..=1 {
                    let (ni, nj) = (i + di, j + dj);
                    if ni < 0 || nj < 0 || ni >= height as i64 || nj >= width as i64 {
                        continue;
                    }
                    let n = ni as usize * width + nj as usize;
                    if label[n] == usize::MAX && filled(&pixels[n]) {
                        label[n] = id;
                        stack.push(n);
                    }
                }
            }
        }
        members.sort_unstable();
        let pinned = members.iter().all(|&k| {
            let p = pixels[k];
            is_blue([p[0], p[1], p[2]])
        });
        let blocks = members
            .iter()
            .map(|&k| {
                let p = pixels[k];
                let colour = [0, 1, 2].map(|c| f64::from(p[c]) / 255.0);
                Block {
                    pixel: Vector2::new((k % width) as f64, (k / width) as f64),
                    colour,
                    mass: block_mass(colour),
                }
            })
            .collect();
        groups.push(BlockGroup { blocks, pinned });
    }
    groups
}
