//! Drawing a 2D world: blocks in their colours, centre-of-mass circles that turn solid when a
//! body comes to rest, optional contacts and bounding discs. docs/blocks2d.md §"Rendering".

use crate::blocks2d::disc_tree::BLOCK_RADIUS;
use crate::blocks2d::world::World2;
use image::{Rgba, RgbaImage};
use nalgebra::Vector2;

/// What to draw and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Pixels per block.
    pub scale: f64,
    /// Top-left corner of the view, world units.
    pub origin: Vector2<f64>,
    /// View size, world units.
    pub size: Vector2<f64>,
    /// Block opacity in [0, 1] (0.5 shows overlaps, as the assignment asks).
    pub opacity: f64,
    /// Draw each contact's point (red) and normal.
    pub contacts: bool,
    /// Draw each body's root bounding disc.
    pub discs: bool,
    /// Kinetic energy below which a body's centre-of-mass circle is solid.
    pub rest_threshold: f64,
}

impl RenderSettings {
    /// A view of the world as it starts: its blocks' bounding box plus two blocks of margin.
    pub fn fit(world: &World2, scale: f64) -> RenderSettings {
        let (mut lo, mut hi) = (
            Vector2::repeat(f64::INFINITY),
            Vector2::repeat(f64::NEG_INFINITY),
        );
        for b in &world.bodies {
            for block in &b.blocks {
                let p = b.to_world(&block.local);
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        let margin = Vector2::repeat(2.0);
        RenderSettings {
            scale,
            origin: lo - margin,
            size: hi - lo + margin * 2.0,
            opacity: 1.0,
            contacts: false,
            discs: false,
            rest_threshold: 1e-3,
        }
    }
}

fn blend(img: &mut RgbaImage, x: i64, y: i64, colour: [f64; 3], alpha: f64) {
    if x < 0 || y < 0 || x >= img.width() as i64 || y >= img.height() as i64 {
        return;
    }
    let p = img.get_pixel_mut(x as u32, y as u32);
    for (channel, c) in p.0.iter_mut().zip(colour) {
        let v = f64::from(*channel) * (1.0 - alpha) + c * 255.0 * alpha;
        *channel = v.round().clamp(0.0, 255.0) as u8;
    }
}

fn circle(img: &mut RgbaImage, centre: (f64, f64), radius: f64, colour: [f64; 3], filled: bool) {
    let r = radius.max(1.0);
    let (x0, x1) = (
        (centre.0 - r - 1.0).floor() as i64,
        (centre.0 + r + 1.0).ceil() as i64,
    );
    let (y0, y1) = (
        (centre.1 - r - 1.0).floor() as i64,
        (centre.1 + r + 1.0).ceil() as i64,
    );
    for y in y0..=y1 {
        for x in x0..=x1 {
            let d =
                ((x as f64 + 0.5 - centre.0).powi(2) + (y as f64 + 0.5 - centre.1).powi(2)).sqrt();
            if (filled && d <= r) || (d - r).abs() <= 0.6 {
                blend(img, x, y, colour, 1.0);
            }
        }
    }
}

fn line(img: &mut RgbaImage, a: (f64, f64), b: (f64, f64), colour: [f64; 3]) {
    let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).max(1);
    for k in 0..=n {
        let t = k as f64 / n as f64;
        blend(
            img,
            (a.0 + (b.0 - a.0) * t) as i64,
            (a.1 + (b.1 - a.1) * t) as i64,
            colour,
            1.0,
        );
    }
}

/// Draws the world.
pub fn render(world: &World2, s: &RenderSettings) -> RgbaImage {
    let (w, h) = (
        (s.size.x * s.scale).ceil().max(1.0) as u32,
        (s.size.y * s.scale).ceil().max(1.0) as u32,
    );
    let mut img = RgbaImage::from_pixel(w, h, Rgba([255, 255, 255, 255]));
    let to_px = |p: &Vector2<f64>| ((p.x - s.origin.x) * s.scale, (p.y - s.origin.y) * s.scale);
    for body in &world.bodies {
        let r = body.rotation();
        for block in &body.blocks {
            let c = body.to_world(&block.local);
            let (cx, cy) = to_px(&c);
            let reach = s.scale * std::f64::consts::FRAC_1_SQRT_2 + 1.0;
            for y in (cy - reach).floor() as i64..=(cy + reach).ceil() as i64 {
                for x in (cx - reach).floor() as i64..=(cx + reach).ceil() as i64 {
                    // The pixel centre in the block's frame: inside the unit square?
                    let p = Vector2::new(x as f64 + 0.5, y as f64 + 0.5);
                    let world = s.origin + p / s.scale;
                    let local = r.transpose() * (world - c);
                    if local.x.abs() <= 0.5 && local.y.abs() <= 0.5 {
                        blend(&mut img, x, y, block.colour, s.opacity);
                    }
                }
            }
        }
    }
    for body in &world.bodies {
        if s.discs
            && let Some(root) = body.tree.root()
        {
            circle(
                &mut img,
                to_px(&body.to_world(&root.centre)),
                root.radius * s.scale,
                [0.6, 0.6, 0.6],
                false,
            );
        }
        if !body.pinned {
            let at_rest = body.kinetic_energy() < s.rest_threshold;
            circle(
                &mut img,
                to_px(&body.x),
                (0.35 * s.scale).max(2.0),
                [0.1, 0.3, 0.9],
                at_rest,
            );
        }
    }
    if s.contacts {
        for c in &world.contacts {
            let p = to_px(&c.point);
            let q = to_px(&(c.point + c.normal * BLOCK_RADIUS));
            line(&mut img, p, q, [0.0, 0.6, 0.0]);
            circle(&mut img, p, 1.0, [0.9, 0.0, 0.0], true);
        }
    }
    img
}
