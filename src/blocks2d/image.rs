//! Bodies from an image: each connected component of non-white pixels is a body made of unit
//! square blocks, one per pixel. docs/blocks2d.md §"Bodies from pixels".
//!
//! World frame: x is the image column, y the image row (so y grows downward, as in the image),
//! one block is one unit of length, the block of pixel (row i, column j) has its centre at
//! (j, i). Angles are measured from +x toward +y (clockwise on screen). Gravity defaults to +y,
//! toward increasing row, so images stand the right way up.
//!
//! Two readers ([`ImageReader`]): rigidref's (bodies numbered row by row) and the Java starter's
//! `ImageBlocker` (bodies numbered column by column, and its other conventions), for comparing
//! with student code built on the starter. docs/blocks2d.md §"Bodies from pixels".

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
    /// The blocks: in row-major pixel order (rigidref's reader), or in the order the starter's
    /// breadth-first search reaches them ([`ImageReader::Starter`]).
    pub blocks: Vec<Block>,
    /// Every block is a shade of blue (r = g < b): the body is pinned.
    pub pinned: bool,
    /// The indices of the blocks on the body's boundary, the only ones in its collision tree,
    /// as the reader decided them; `None`: the blocks with a neighbour (of 8) not in the body,
    /// decided by [`crate::blocks2d::body::Body2::from_group`].
    pub boundary: Option<Vec<usize>>,
}

/// How an image is read into bodies (scene key `image_reader`).
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
pub enum ImageReader {
    /// rigidref's: bodies numbered by their first pixel row by row (body 0 nearest the top
    /// left), blocks in row-major order, colour channels as 64-bit numbers, a fully
    /// transparent pixel empty, a block on the boundary when one of its 8 neighbours is not in
    /// the body.
    #[default]
    Rigidref,
    /// The Java starter's `ImageBlocker`: bodies numbered by their first pixel column by
    /// column (x outer, y inner, as its sweep runs), blocks in the order its breadth-first
    /// search from that pixel reaches them, colour channels as 32-bit floats (k / 255f: a
    /// block's mass agrees with rigidref's to about 6e-8 relative), alpha ignored, and a block
    /// on the boundary when it is on the image's edge or one of six neighbours is white (the
    /// starter's loop skips i = j, so the diagonal neighbours (−1, −1) and (+1, +1) are never
    /// looked at).
    Starter,
}

impl ImageReader {
    /// The name a scene file gives it (`rigidref`, `starter`).
    pub fn name(self) -> &'static str {
        match self {
            ImageReader::Rigidref => "rigidref",
            ImageReader::Starter => "starter",
        }
    }

    /// How it numbers the bodies.
    pub fn numbering(self) -> &'static str {
        match self {
            ImageReader::Rigidref => "row by row",
            ImageReader::Starter => "column by column",
        }
    }
}

/// Loading settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSettings {
    /// A pixel is empty when every channel is at least 1 − this (near-white), or it is fully
    /// transparent. Default 0.05, the assignment's starter's.
    pub white_threshold: f64,
    /// Which reader numbers the bodies and decides their blocks (default rigidref's).
    pub reader: ImageReader,
}

impl Default for ImageSettings {
    fn default() -> Self {
        ImageSettings {
            white_threshold: 0.05,
            reader: ImageReader::Rigidref,
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
/// non-empty pixels, numbered as `settings.reader` numbers them.
pub fn blocks_from_pixels(
    width: usize,
    height: usize,
    pixels: &[[u8; 4]],
    settings: &ImageSettings,
) -> Vec<BlockGroup> {
    match settings.reader {
        ImageReader::Rigidref => rigidref_blocks(width, height, pixels, settings),
        ImageReader::Starter => starter_blocks(width, height, pixels, settings.white_threshold),
    }
}

/// The starter's reader ([`super::starter_image`]): its components in its order, each block's
/// colour the starter's float channels, its mass from them, pinned when every block is blue.
fn starter_blocks(
    width: usize,
    height: usize,
    pixels: &[[u8; 4]],
    white_threshold: f64,
) -> Vec<BlockGroup> {
    use super::starter_image::{channels, starter_components};
    starter_components(width, height, pixels, white_threshold)
        .into_iter()
        .map(|component| {
            let byte = |&(x, y): &(usize, usize)| pixels[y * width + x];
            let blocks = component
                .cells
                .iter()
                .map(|cell| {
                    let colour = channels(&byte(cell));
                    Block {
                        pixel: Vector2::new(cell.0 as f64, cell.1 as f64),
                        colour,
                        mass: block_mass(colour),
                    }
                })
                .collect();
            // r = g < b on the starter's float channels is the same test as on the bytes.
            let pinned = component.cells.iter().all(|cell| {
                let p = byte(cell);
                is_blue([p[0], p[1], p[2]])
            });
            BlockGroup {
                blocks,
                pinned,
                boundary: Some(component.boundary),
            }
        })
        .collect()
}

/// rigidref's reader: components in the order of their first pixel in row-major order.
fn rigidref_blocks(
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
        groups.push(BlockGroup {
            blocks,
            pinned,
            boundary: None,
        });
    }
    groups
}
