//! The Java starter's image reader (`ImageBlocker`), for comparing with student code built on
//! it ([`super::image::ImageReader::Starter`]). docs/blocks2d.md §"Bodies from pixels", and
//! §"The starter preset" for where each rule was read.
//!
//! What it does differently from rigidref's reader, each a fact of the starter's code:
//!
//! - it sweeps the pixels **column by column** (x outer, y inner) and starts a body at the first
//!   non-white pixel it has not visited, so bodies are numbered by their first pixel in
//!   column-major order (on tower10.png the ground, whose leftmost column comes first, is body
//!   0; rigidref's reader makes it body 10);
//! - a body's blocks are listed in the order its breadth-first search reaches them: a queue,
//!   each pixel's neighbours visited x offset outer, y offset inner, every in-image neighbour
//!   not yet visited marked and queued, white ones skipped when taken from the queue;
//! - colour channels are 32-bit floats, k / 255f, so a block's mass 1 − (0.3 r + 0.59 g +
//!   0.11 b) is computed from them (differing from the 64-bit channels by up to 6e-8
//!   relative); a pixel is white when every channel is within the threshold of 1 (in floats);
//!   alpha is ignored;
//! - a block is on the boundary when it lies on the image's edge or one of the neighbours at
//!   offsets (i, j) with i ≠ j is white: the loop skips i = j, meaning to skip the block itself,
//!   and so also skips the diagonals (−1, −1) and (+1, +1).

use std::collections::VecDeque;

/// The starter's colour channels of a pixel: each 8-bit channel as the float k / 255f.
fn float_channels(p: &[u8; 4]) -> [f32; 3] {
    [0, 1, 2].map(|c| f32::from(p[c]) / 255.0f32)
}

/// The starter's colour of a pixel, channels in [0, 1]: the floats k / 255f, widened.
pub fn channels(p: &[u8; 4]) -> [f64; 3] {
    float_channels(p).map(f64::from)
}

/// One body as the starter's reader finds it: its pixels (x, y), in the order its
/// breadth-first search reaches them, and which of them are on its boundary (indices into
/// `cells`).
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Pixels (column, row).
    pub cells: Vec<(usize, usize)>,
    /// Indices into `cells` of the boundary blocks.
    pub boundary: Vec<usize>,
}

/// Splits an RGBA pixel grid (row-major) into bodies as the starter's `ImageBlocker` does
/// (module documentation), with near-white threshold `white_threshold`, in its order.
pub fn starter_components(
    width: usize,
    height: usize,
    pixels: &[[u8; 4]],
    white_threshold: f64,
) -> Vec<Component> {
    // The starter's epsilon is a float, compared with float differences from 1.
    let epsilon = white_threshold as f32;
    let white = |x: usize, y: usize| {
        float_channels(&pixels[y * width + x])
            .iter()
            .all(|&c| (c - 1.0f32).abs() <= epsilon)
    };
    let boundary = |x: usize, y: usize| {
        if x == 0 || y == 0 || x + 1 == width || y + 1 == height {
            return true;
        }
        (-1i64..=1).any(|i| {
            (-1i64..=1).any(|j| i != j && white((x as i64 + i) as usize, (y as i64 + j) as usize))
        })
    };
    let mut visited = vec![false; width * height];
    let mut groups = Vec::new();
    for x in 0..width {
        for y in 0..height {
            if visited[y * width + x] {
                continue;
            }
            visited[y * width + x] = true;
            if white(x, y) {
                continue;
            }
            let (mut cells, mut edge) = (Vec::new(), Vec::new());
            let mut queue = VecDeque::from([(x, y)]);
            while let Some((px, py)) = queue.pop_front() {
                if white(px, py) {
                    continue;
                }
                if boundary(px, py) {
                    edge.push(cells.len());
                }
                cells.push((px, py));
                for i in -1i64..=1 {
                    for j in -1i64..=1 {
                        let (nx, ny) = (px as i64 + i, py as i64 + j);
                        if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                            continue;
                        }
                        let k = ny as usize * width + nx as usize;
                        if !visited[k] {
                            visited[k] = true;
                            queue.push_back((nx as usize, ny as usize));
                        }
                    }
                }
            }
            groups.push(Component {
                cells,
                boundary: edge,
            });
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(width: usize, rows: &[&str]) -> Vec<[u8; 4]> {
        rows.iter()
            .flat_map(|r| {
                r.chars().map(|c| match c {
                    '#' => [0, 0, 0, 255],
                    'b' => [0, 0, 200, 255],
                    _ => [255, 255, 255, 255],
                })
            })
            .take(width * rows.len())
            .collect()
    }

    #[test]
    fn bodies_are_numbered_column_by_column_and_blocks_breadth_first() {
        // A bar on the right, high up, and a blue ground on the left, lower: row by row the bar
        // comes first, column by column the ground.
        let rows = ["....###", "b......", "b......"];
        let groups = starter_components(7, 3, &grid(7, &rows), 0.05);
        assert_eq!(groups.len(), 2);
        assert_eq!(groups[0].cells, [(0, 1), (0, 2)]);
        assert_eq!(groups[1].cells, [(4, 0), (5, 0), (6, 0)]);
    }

    #[test]
    fn the_boundary_test_skips_the_two_diagonals_it_should_look_at() {
        // A 3 × 3 square with its top-left corner missing: the centre block's only white
        // neighbour is (−1, −1), which the starter's loop never looks at.
        let rows = [".....", "..##.", ".###.", ".###.", "....."];
        let groups = starter_components(5, 5, &grid(5, &rows), 0.05);
        let g = &groups[0];
        let centre = g.cells.iter().position(|&c| c == (2, 2)).unwrap();
        assert!(!g.boundary.contains(&centre));
        assert_eq!(g.boundary.len(), g.cells.len() - 1);
    }
}
