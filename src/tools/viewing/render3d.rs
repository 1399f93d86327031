//! 3D frames: the bodies' meshes, flat-shaded, over a ground grid, seen from a fixed or orbiting
//! camera, with the contacts (points and normals) and a text overlay (time, energy) optional.
//! docs/viewing.md §"Rendering 3D runs".
//!
//! Rasterising is tiny-skia's (anti-aliased filled paths and strokes, the rasteriser of resvg);
//! what is the project's own is small: the camera, near-plane clipping, back-face culling, the
//! shading, and the painter's algorithm (triangles sorted far to near). Painter's order is exact
//! for separate convex bodies and may misorder two triangles that interpenetrate, a fault only
//! where bodies already overlap. The overlay's text is the public-domain 8 × 8 bitmap font of the
//! `font8x8` crate, drawn as squares, so no font file is needed.

use crate::rigid3d::mesh::TriMesh;
use image::RgbaImage;
use nalgebra::{Matrix3, Vector3};
use tiny_skia::{Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// A pinhole camera looking from `eye` at `target` with `up` roughly up. Camera space: x right,
/// y up, z forward (depth), in m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Position, world frame, m.
    pub eye: Vector3<f64>,
    /// The point at the image centre, m.
    pub target: Vector3<f64>,
    /// Vertical field of view, rad.
    pub fov_y: f64,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
}

/// Distance in front of the eye below which geometry is clipped, m.
const NEAR: f64 = 1e-3;

impl Camera {
    /// The camera that sees the sphere (`centre`, `radius`) whole, from the direction given by
    /// `azimuth` (rad, about +y, 0 looking along −z) and `elevation` (rad above the horizon).
    pub fn framing(
        centre: &Vector3<f64>,
        radius: f64,
        azimuth: f64,
        elevation: f64,
        width: u32,
        height: u32,
    ) -> Camera {
        let fov_y = 40f64.to_radians();
        let aspect = f64::from(width) / f64::from(height.max(1));
        // The sphere fits the narrower of the two fields of view.
        let half = (fov_y / 2.0).tan().min((fov_y / 2.0).tan() * aspect).atan();
        let distance = radius.max(1e-6) / half.sin() * 1.05;
        let direction = Vector3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        Camera {
            eye: centre + direction * distance,
            target: *centre,
            fov_y,
            width,
            height,
        }
    }

    /// Rows: the camera's right, up and forward axes in the world frame.
    fn basis(&self) -> Matrix3<f64> {
        let forward = (self.target - self.eye).normalize();
        let mut right = forward.cross(&Vector3::y());
        if right.norm() < 1e-9 {
            // Looking straight down or up: any horizontal right will do.
            right = Vector3::x();
        }
        let right = right.normalize();
        let up = right.cross(&forward);
        Matrix3::from_rows(&[right.transpose(), up.transpose(), forward.transpose()])
    }

    /// Pixels per unit of x/z at depth 1.
    fn focal(&self) -> f64 {
        f64::from(self.height) / 2.0 / (self.fov_y / 2.0).tan()
    }
}

/// A camera-space point projected to pixels (x right, y down) with its depth, m.
fn to_pixels(camera: &Camera, focal: f64, p: &Vector3<f64>) -> (f32, f32) {
    (
        (f64::from(camera.width) / 2.0 + focal * p.x / p.z) as f32,
        (f64::from(camera.height) / 2.0 - focal * p.y / p.z) as f32,
    )
}

/// Clips a camera-space polygon to z ≥ NEAR (Sutherland–Hodgman against one plane).
fn clip_near(polygon: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let mut out = Vec::with_capacity(polygon.len() + 2);
    for (i, a) in polygon.iter().enumerate() {
        let b = &polygon[(i + 1) % polygon.len()];
        let (ina, inb) = (a.z >= NEAR, b.z >= NEAR);
        if ina {
            out.push(*a);
        }
        if ina != inb {
            let t = (NEAR - a.z) / (b.z - a.z);
            out.push(a + (b - a) * t);
        }
    }
    out
}

/// One body to draw: its shape and pose.
#[derive(Clone, Copy, Debug)]
pub struct BodyPose<'a> {
    /// Shape in the body frame, m.
    pub mesh: &'a TriMesh,
    /// Centre of mass, world frame, m.
    pub x: Vector3<f64>,
    /// Rotation body → world.
    pub rotation: Matrix3<f64>,
    /// Base colour, RGB in [0, 1].
    pub colour: [f64; 3],
}

/// A contact to draw: point and unit normal (world frame), normal impulse (N·s).
#[derive(Clone, Copy, Debug)]
pub struct ContactMark {
    /// Contact point, m.
    pub point: Vector3<f64>,
    /// Unit normal.
    pub normal: Vector3<f64>,
}

/// What a frame shows besides the bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameStyle {
    /// Draw the contact points (red) and normals (green).
    pub contacts: bool,
    /// Length of a drawn normal, m.
    pub normal_length: f64,
    /// Half-width of the ground grid drawn about the origin, m; its spacing is chosen from it.
    pub ground_extent: f64,
    /// Draw the ground plane y = 0 and its grid.
    pub ground: bool,
}

/// Direction towards the key light (world frame, unit): up, and from the camera's side.
fn key_light(camera: &Camera) -> Vector3<f64> {
    let towards_eye = (camera.eye - camera.target).normalize();
    (towards_eye + Vector3::new(0.3, 1.5, 0.2)).normalize()
}

fn colour(rgb: [f64; 3], alpha: f64) -> Color {
    let c = |x: f64| x.clamp(0.0, 1.0) as f32;
    Color::from_rgba(c(rgb[0]), c(rgb[1]), c(rgb[2]), c(alpha)).unwrap_or(Color::BLACK)
}

fn paint(rgb: [f64; 3], alpha: f64) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(colour(rgb, alpha));
    p.anti_alias = true;
    p
}

/// Fills a camera-space polygon (clipped to the near plane), with a hairline of the same colour
/// so that neighbouring anti-aliased triangles leave no seam.
fn fill_polygon(
    pixmap: &mut Pixmap,
    camera: &Camera,
    focal: f64,
    poly: &[Vector3<f64>],
    p: &Paint,
) {
    let clipped = clip_near(poly);
    if clipped.len() < 3 {
        return;
    }
    let mut pb = PathBuilder::new();
    for (i, q) in clipped.iter().enumerate() {
        let (x, y) = to_pixels(camera, focal, q);
        if i == 0 {
            pb.move_to(x, y);
        } else {
            pb.line_to(x, y);
        }
    }
    pb.close();
    if let Some(path) = pb.finish() {
        pixmap.fill_path(&path, p, FillRule::Winding, Transform::identity(), None);
        let stroke = Stroke {
            width: 0.6,
            line_join: tiny_skia::LineJoin::Round,
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, p, &stroke, Transform::identity(), None);
    }
}

/// The camera with its axes and focal length worked out once per frame.
struct Projection<'a> {
    camera: &'a Camera,
    basis: Matrix3<f64>,
    focal: f64,
}

/// Draws a world-space segment (clipped to the near plane).
fn segment(
    pixmap: &mut Pixmap,
    view: &Projection,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    p: &Paint,
    width: f32,
) {
    let (camera, basis, focal) = (view.camera, &view.basis, view.focal);
    let (mut ca, mut cb) = (basis * (a - camera.eye), basis * (b - camera.eye));
    if ca.z < NEAR && cb.z < NEAR {
        return;
    }
    if ca.z < NEAR {
        ca = ca + (cb - ca) * ((NEAR - ca.z) / (cb.z - ca.z));
    } else if cb.z < NEAR {
        cb = cb + (ca - cb) * ((NEAR - cb.z) / (ca.z - cb.z));
    }
    let (pa, pb_) = (to_pixels(camera, focal, &ca), to_pixels(camera, focal, &cb));
    let mut pb = PathBuilder::new();
    pb.move_to(pa.0, pa.1);
    pb.line_to(pb_.0, pb_.1);
    if let Some(path) = pb.finish() {
        let stroke = Stroke {
            width,
            line_cap: LineCap::Round,
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, p, &stroke, Transform::identity(), None);
    }
}

/// Draws one frame: the ground and its grid, the bodies (flat-shaded, back faces culled, far
/// triangles first), the contacts when `style.contacts`, and `overlay` lines of text at the top
/// left (none when empty).
pub fn render_frame(
    camera: &Camera,
    bodies: &[BodyPose],
    contacts: &[ContactMark],
    overlay: &[String],
    style: &FrameStyle,
) -> RgbaImage {
    let (w, h) = (camera.width.max(1), camera.height.max(1));
    let mut pixmap = Pixmap::new(w, h).expect("frame size checked by the caller");
    pixmap.fill(colour([0.93, 0.94, 0.96], 1.0));
    let basis = camera.basis();
    let focal = camera.focal();
    let view = Projection {
        camera,
        basis,
        focal,
    };
    let to_camera = |p: &Vector3<f64>| basis * (p - camera.eye);

    if style.ground && camera.eye.y > 0.0 {
        let e = style.ground_extent;
        let corners = [
            Vector3::new(-e, 0.0, -e),
            Vector3::new(e, 0.0, -e),
            Vector3::new(e, 0.0, e),
            Vector3::new(-e, 0.0, e),
        ];
        let quad: Vec<_> = corners.iter().map(to_camera).collect();
        fill_polygon(
            &mut pixmap,
            camera,
            focal,
            &quad,
            &paint([0.84, 0.85, 0.82], 1.0),
        );
        let spacing = grid_spacing(e);
        let lines = (e / spacing).floor() as i64;
        let grid = paint([0.70, 0.71, 0.68], 1.0);
        for k in -lines..=lines {
            let c = k as f64 * spacing;
            let axis = k == 0;
            let p = if axis {
                paint([0.55, 0.56, 0.53], 1.0)
            } else {
                grid.clone()
            };
            let width = if axis { 1.4 } else { 0.8 };
            segment(
                &mut pixmap,
                &view,
                &Vector3::new(c, 0.0, -e),
                &Vector3::new(c, 0.0, e),
                &p,
                width,
            );
            segment(
                &mut pixmap,
                &view,
                &Vector3::new(-e, 0.0, c),
                &Vector3::new(e, 0.0, c),
                &p,
                width,
            );
        }
    }

    // Every front-facing triangle of every body, in camera space, with its shade; drawn far to
    // near (painter's algorithm).
    let light = key_light(camera);
    let mut triangles: Vec<(f64, [Vector3<f64>; 3], [f64; 3])> = Vec::new();
    for body in bodies {
        let world: Vec<Vector3<f64>> = body
            .mesh
            .vertices
            .iter()
            .map(|v| body.x + body.rotation * v)
            .collect();
        for t in &body.mesh.triangles {
            let (a, b, c) = (world[t[0]], world[t[1]], world[t[2]]);
            let normal = (b - a).cross(&(c - a));
            let norm = normal.norm();
            if norm == 0.0 || !norm.is_finite() {
                continue;
            }
            let normal = normal / norm;
            let centroid = (a + b + c) / 3.0;
            if normal.dot(&(camera.eye - centroid)) <= 0.0 {
                continue; // back face
            }
            let lambert = normal.dot(&light).max(0.0);
            let shade = 0.35 + 0.65 * lambert;
            let rgb = body.colour.map(|x| x * shade);
            let cam = [to_camera(&a), to_camera(&b), to_camera(&c)];
            let depth = (cam[0].z + cam[1].z + cam[2].z) / 3.0;
            triangles.push((depth, cam, rgb));
        }
    }
    triangles.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (_, cam, rgb) in &triangles {
        fill_polygon(&mut pixmap, camera, focal, cam, &paint(*rgb, 1.0));
    }

    if style.contacts {
        let normal_paint = paint([0.1, 0.6, 0.2], 1.0);
        let point_paint = paint([0.85, 0.1, 0.1], 1.0);
        for c in contacts {
            let tip = c.point + c.normal * style.normal_length;
            segment(&mut pixmap, &view, &c.point, &tip, &normal_paint, 2.0);
            let cp = to_camera(&c.point);
            if cp.z >= NEAR {
                let (x, y) = to_pixels(camera, focal, &cp);
                if let Some(circle) = PathBuilder::from_circle(x, y, 3.0) {
                    pixmap.fill_path(
                        &circle,
                        &point_paint,
                        FillRule::Winding,
                        Transform::identity(),
                        None,
                    );
                }
            }
        }
    }

    if !overlay.is_empty() {
        draw_text_box(&mut pixmap, overlay);
    }
    to_image(&pixmap)
}

/// A grid spacing of 1, 2 or 5 × 10ᵏ m giving about ten lines each side of the origin.
pub fn grid_spacing(extent: f64) -> f64 {
    let raw = (extent / 10.0).max(1e-6);
    let decade = 10f64.powf(raw.log10().floor());
    let m = raw / decade;
    decade
        * if m < 1.5 {
            1.0
        } else if m < 3.5 {
            2.0
        } else {
            5.0
        }
}

/// Pixels per font pixel of the overlay's 8 × 8 glyphs.
const TEXT_SCALE: f32 = 2.0;

/// Text lines in a translucent white box at the top left.
fn draw_text_box(pixmap: &mut Pixmap, lines: &[String]) {
    let glyph = 8.0 * TEXT_SCALE;
    let widest = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f32;
    let (pad, line_h) = (6.0, glyph + 4.0);
    if let Some(rect) = Rect::from_xywh(
        4.0,
        4.0,
        widest * glyph + 2.0 * pad,
        lines.len() as f32 * line_h + 2.0 * pad - 4.0,
    ) {
        pixmap.fill_rect(
            rect,
            &paint([1.0, 1.0, 1.0], 0.8),
            Transform::identity(),
            None,
        );
    }
    let ink = paint([0.1, 0.1, 0.12], 1.0);
    for (row, line) in lines.iter().enumerate() {
        let y0 = 4.0 + pad + row as f32 * line_h;
        for (col, ch) in line.chars().enumerate() {
            let x0 = 4.0 + pad + col as f32 * glyph;
            let bits = super::pixmap_backend::glyph(ch);
            for (gy, byte) in bits.iter().enumerate() {
                for gx in 0..8 {
                    if byte & (1 << gx) != 0
                        && let Some(r) = Rect::from_xywh(
                            x0 + gx as f32 * TEXT_SCALE,
                            y0 + gy as f32 * TEXT_SCALE,
                            TEXT_SCALE,
                            TEXT_SCALE,
                        )
                    {
                        pixmap.fill_rect(r, &ink, Transform::identity(), None);
                    }
                }
            }
        }
    }
}

/// The pixmap as an `image` RGBA buffer (tiny-skia stores premultiplied alpha; the frame's
/// background is opaque, so every pixel is opaque and the values are the same).
fn to_image(pixmap: &Pixmap) -> RgbaImage {
    let mut img = RgbaImage::new(pixmap.width(), pixmap.height());
    for (dst, src) in img.pixels_mut().zip(pixmap.pixels()) {
        let c = src.demultiply();
        *dst = image::Rgba([c.red(), c.green(), c.blue(), c.alpha()]);
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_spacing_is_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(grid_spacing(10.0), 1.0);
        assert_eq!(grid_spacing(25.0), 2.0);
        assert!((grid_spacing(0.5) - 0.05).abs() < 1e-15);
    }

    #[test]
    fn clipping_keeps_the_part_in_front_of_the_near_plane() {
        let tri = [
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(1.0, 0.0, 1.0),
            Vector3::new(-1.0, 0.0, 1.0),
        ];
        let clipped = clip_near(&tri);
        assert_eq!(clipped.len(), 4);
        assert!(clipped.iter().all(|p| p.z >= NEAR - 1e-12));
    }
}
