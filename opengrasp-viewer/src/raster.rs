//! A headless software rasteriser: z-buffered, flat-shaded triangles, depth-tested or overlaid
//! lines and dots, written as PNG. No GPU, no display.
//!
//! The camera looks along its `forward` axis; image x goes along its `right` axis and image y
//! (downwards) against its `up` axis. An orthographic camera maps a world length `l` across the
//! view to `l · height / (2 · half_height)` pixels, so a box seen along an axis covers exactly
//! its projected rectangle — what the silhouette tests check.

use std::path::Path;

use nalgebra::{Point3, Unit, Vector3};

use crate::error::{Result, ViewerError};

/// An RGB colour.
pub type Rgb = [u8; 3];

/// How a camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Parallel projection; `half_height` is half the world height the image shows (m).
    Orthographic {
        /// Half the visible height (m).
        half_height: f64,
    },
    /// Pinhole projection with vertical field of view `fov_y` (rad, in (0, π)).
    Perspective {
        /// Vertical field of view (rad).
        fov_y: f64,
    },
}

/// A camera: pose, projection and image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (world, m).
    pub eye: Point3<f64>,
    /// Viewing direction (unit).
    pub forward: Unit<Vector3<f64>>,
    /// Image-up direction (unit, orthogonal to `forward`).
    pub up: Unit<Vector3<f64>>,
    /// Projection.
    pub projection: Projection,
    /// Image width (pixels).
    pub width: u32,
    /// Image height (pixels).
    pub height: u32,
    /// Triangles with a vertex nearer than this (m along the view) are not drawn: a cutaway
    /// through walls between the eye and what is looked at. Lines and dots are not clipped.
    pub near: f64,
}

/// Points closer than this to a perspective eye (m) are not drawn.
const NEAR: f64 = 1e-3;

/// How far lines are pulled towards the eye for the depth test (m).
const LINE_PULL: f64 = 0.01;

impl Camera {
    /// A camera at `eye` looking at `target`, image up as close to `up` as possible.
    ///
    /// # Errors
    /// [`ViewerError::InvalidCamera`] if `eye == target`, `up` is parallel to the view, a
    /// size is zero or the projection is degenerate.
    pub fn look_at(
        eye: Point3<f64>,
        target: Point3<f64>,
        up: Vector3<f64>,
        projection: Projection,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        let bad = |reason: &str| ViewerError::InvalidCamera { reason: reason.into() };
        if width == 0 || height == 0 || width > 16_384 || height > 16_384 {
            return Err(bad("image size must be 1..=16384 pixels"));
        }
        match projection {
            Projection::Orthographic { half_height } if !(half_height.is_finite() && half_height > 0.0) => {
                return Err(bad("orthographic half height must be positive"))
            }
            Projection::Perspective { fov_y } if !(fov_y > 0.0 && fov_y < std::f64::consts::PI) => {
                return Err(bad("field of view must be in (0, π)"))
            }
            _ => {}
        }
        let forward = Unit::try_new(target - eye, 1e-12).ok_or_else(|| bad("eye and target coincide"))?;
        let up = up - forward.into_inner() * up.dot(&forward);
        let up = Unit::try_new(up, 1e-9).ok_or_else(|| bad("up is parallel to the view direction"))?;
        if !eye.iter().all(|v| v.is_finite()) {
            return Err(bad("eye is not finite"));
        }
        Ok(Self { eye, forward, up, projection, width, height, near: NEAR })
    }

    /// A camera looking along `direction` that frames the box `[lo, hi]` with a margin of 5 %.
    /// An orthographic camera is placed outside the box; a perspective one (`fov_y`) far
    /// enough back to see the box's bounding sphere.
    ///
    /// # Errors
    /// As [`Camera::look_at`]; also for an empty or non-finite box.
    pub fn framing(
        lo: Point3<f64>,
        hi: Point3<f64>,
        direction: Vector3<f64>,
        up: Vector3<f64>,
        perspective_fov: Option<f64>,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        if !(lo.iter().chain(hi.iter()).all(|v| v.is_finite()) && (0..3).all(|i| lo[i] <= hi[i])) {
            return Err(ViewerError::InvalidCamera { reason: "nothing to frame (empty or non-finite box)".into() });
        }
        let centre = nalgebra::center(&lo, &hi);
        let radius = ((hi - lo).norm() / 2.0).max(1e-3);
        let dir = Unit::try_new(direction, 1e-12)
            .ok_or_else(|| ViewerError::InvalidCamera { reason: "zero view direction".into() })?;
        let aspect = f64::from(width) / f64::from(height);
        match perspective_fov {
            Some(fov) => {
                // Distance at which the bounding sphere fits the narrower field of view.
                let half = (fov / 2.0).tan().min((fov / 2.0).tan() * aspect).atan();
                let dist = radius * 1.05 / half.sin();
                let eye = centre - dir.into_inner() * dist;
                Self::look_at(eye, centre, up, Projection::Perspective { fov_y: fov }, width, height)
            }
            None => {
                let eye = centre - dir.into_inner() * (2.0 * radius + 1.0);
                let half_height = 1.05 * radius / aspect.min(1.0);
                Self::look_at(eye, centre, up, Projection::Orthographic { half_height }, width, height)
            }
        }
    }

    fn right(&self) -> Vector3<f64> {
        self.forward.cross(&self.up)
    }

    /// Image position (pixels, x right, y down, continuous: pixel `(i, j)` covers
    /// `[i, i+1) × [j, j+1)`) and depth along the view (m) of a world point; `None` behind a
    /// perspective eye.
    pub fn project(&self, p: &Point3<f64>) -> Option<(f64, f64, f64)> {
        let d = p - self.eye;
        let (x, y, z) = (d.dot(&self.right()), d.dot(&self.up), d.dot(&self.forward));
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let (nx, ny) = match self.projection {
            Projection::Orthographic { half_height } => (x / (half_height * w / h), y / half_height),
            Projection::Perspective { fov_y } => {
                if z < NEAR {
                    return None;
                }
                let t = (fov_y / 2.0).tan();
                (x / (z * t * w / h), y / (z * t))
            }
        };
        Some(((nx + 1.0) / 2.0 * w, (1.0 - ny) / 2.0 * h, z))
    }

    /// The depth key interpolated linearly across the screen: depth (orthographic) or
    /// `-1/depth` (perspective); smaller is nearer in both.
    fn key(&self, z: f64) -> f64 {
        match self.projection {
            Projection::Orthographic { .. } => z,
            Projection::Perspective { .. } => -1.0 / z,
        }
    }
}

/// How [`Canvas::fill`] treats depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fill {
    /// Depth-tested and written.
    Surface,
    /// Depth-tested, not written.
    Line,
    /// Painted over everything.
    Overlay,
}

/// An RGB image with a depth buffer.
#[derive(Clone, Debug)]
pub struct Canvas {
    camera: Camera,
    rgb: Vec<u8>,
    depth: Vec<f64>,
    light: Unit<Vector3<f64>>,
}

/// Share of a surface's colour lit regardless of the light direction.
const AMBIENT: f64 = 0.35;

impl Canvas {
    /// A canvas of the camera's size filled with `background`. Surfaces are lit by a light
    /// from over the camera's shoulder (up-left-behind).
    pub fn new(camera: Camera, background: Rgb) -> Self {
        let n = camera.width as usize * camera.height as usize;
        let light = Unit::new_normalize(
            camera.forward.into_inner() * -1.0 + camera.up.into_inner() * 0.6 - camera.right() * 0.3,
        );
        Self { camera, rgb: background.repeat(n), depth: vec![f64::INFINITY; n], light }
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The colour of pixel `(x, y)` (x right, y down), `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgb> {
        (x < self.camera.width && y < self.camera.height).then(|| {
            let i = 3 * (y as usize * self.camera.width as usize + x as usize);
            [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
        })
    }

    /// Depth (m along the view) of the nearest surface at pixel `(x, y)`, `None` if none.
    pub fn depth(&self, x: u32, y: u32) -> Option<f64> {
        if x >= self.camera.width || y >= self.camera.height {
            return None;
        }
        let k = self.depth[y as usize * self.camera.width as usize + x as usize];
        k.is_finite().then(|| match self.camera.projection {
            Projection::Orthographic { .. } => k,
            Projection::Perspective { .. } => -1.0 / k,
        })
    }

    /// Raw RGB bytes, row by row from the top.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// Lambert shade of `colour` for a face with normal `n` (two-sided).
    fn shade(&self, colour: Rgb, n: &Vector3<f64>) -> Rgb {
        let lit = n.dot(&self.light).abs();
        let f = AMBIENT + (1.0 - AMBIENT) * lit;
        colour.map(|c| (f64::from(c) * f).round().clamp(0.0, 255.0) as u8)
    }

    /// Fills a triangle (world coordinates) with `colour`, flat-shaded, depth-tested.
    pub fn triangle(&mut self, a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, colour: Rgb) {
        let n = (b - a).cross(&(c - a));
        let Some(n) = n.try_normalize(1e-18) else { return };
        let shaded = self.shade(colour, &n);
        let (Some(pa), Some(pb), Some(pc)) = (self.camera.project(a), self.camera.project(b), self.camera.project(c))
        else {
            return;
        };
        if [pa.2, pb.2, pc.2].iter().any(|&z| z < self.camera.near) {
            return;
        }
        let pts = [pa, pb, pc].map(|(x, y, z)| (x, y, self.camera.key(z)));
        self.fill(pts, shaded, Fill::Surface);
    }

    /// Scan-converts a screen triangle `(x, y, key)`: pixels whose centre is inside (edges
    /// shared by two triangles go to exactly one: the top-left rule). Depth-tested (key minus
    /// and written to the depth buffer ([`Fill::Surface`]), depth-tested only ([`Fill::Line`]),
    /// or painted over everything ([`Fill::Overlay`]).
    fn fill(&mut self, p: [(f64, f64, f64); 3], colour: Rgb, mode: Fill) {
        let edge =
            |a: (f64, f64, f64), b: (f64, f64, f64), x: f64, y: f64| (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0);
        let area = edge(p[0], p[1], p[2].0, p[2].1);
        if area.abs() < 1e-12 || !area.is_finite() {
            return;
        }
        let (w, h) = (self.camera.width as f64, self.camera.height as f64);
        let min_x = p.iter().map(|q| q.0).fold(f64::INFINITY, f64::min).floor().max(0.0);
        let max_x = p.iter().map(|q| q.0).fold(f64::NEG_INFINITY, f64::max).ceil().min(w);
        let min_y = p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min).floor().max(0.0);
        let max_y = p.iter().map(|q| q.1).fold(f64::NEG_INFINITY, f64::max).ceil().min(h);
        if min_x >= max_x || min_y >= max_y {
            return;
        }
        // Top-left rule on the sign-normalised edges: a pixel centre exactly on an edge is
        // inside only for top or left edges.
        let s = area.signum();
        let owns = |a: (f64, f64, f64), b: (f64, f64, f64)| {
            let (dx, dy) = ((b.0 - a.0) * s, (b.1 - a.1) * s);
            (dy == 0.0 && dx < 0.0) || dy > 0.0
        };
        let tl = [owns(p[1], p[2]), owns(p[2], p[0]), owns(p[0], p[1])];
        let width = self.camera.width as usize;
        for y in (min_y as usize)..(max_y as usize) {
            let cy = y as f64 + 0.5;
            for x in (min_x as usize)..(max_x as usize) {
                let cx = x as f64 + 0.5;
                let ws = [edge(p[1], p[2], cx, cy) * s, edge(p[2], p[0], cx, cy) * s, edge(p[0], p[1], cx, cy) * s];
                if ws.iter().zip(tl).any(|(&e, top_left)| e < 0.0 || (e == 0.0 && !top_left)) {
                    continue;
                }
                let sum = area.abs();
                let i = y * width + x;
                let key = (ws[0] * p[0].2 + ws[1] * p[1].2 + ws[2] * p[2].2) / sum;
                let paint = match mode {
                    Fill::Overlay => true,
                    Fill::Line => key < self.depth[i],
                    Fill::Surface => {
                        let nearer = key < self.depth[i];
                        if nearer {
                            self.depth[i] = key;
                        }
                        nearer
                    }
                };
                if paint {
                    self.rgb[3 * i..3 * i + 3].copy_from_slice(&colour);
                }
            }
        }
    }

    /// Draws a world segment `thickness` pixels wide. Depth-tested (pulled 1 cm towards the
    /// eye so lines on a surface show; not written to the depth buffer) unless `overlay`.
    pub fn segment(&mut self, a: &Point3<f64>, b: &Point3<f64>, colour: Rgb, thickness: f64, overlay: bool) {
        let (Some(pa), Some(pb)) = (self.camera.project(a), self.camera.project(b)) else { return };
        // Pulled towards the eye so that lines lying on a surface show.
        let pull = |z: f64| self.camera.key((z - LINE_PULL).max(NEAR));
        let (ka, kb) = (pull(pa.2), pull(pb.2));
        let d = (pb.0 - pa.0, pb.1 - pa.1);
        let len = (d.0 * d.0 + d.1 * d.1).sqrt();
        let (nx, ny) = if len < 1e-9 {
            (0.0, thickness / 2.0)
        } else {
            (-d.1 / len * thickness / 2.0, d.0 / len * thickness / 2.0)
        };
        let (tx, ty) = if len < 1e-9 { (thickness / 2.0, 0.0) } else { (d.0 / len * 0.5, d.1 / len * 0.5) };
        let q = [
            (pa.0 + nx - tx, pa.1 + ny - ty, ka),
            (pb.0 + nx + tx, pb.1 + ny + ty, kb),
            (pb.0 - nx + tx, pb.1 - ny + ty, kb),
            (pa.0 - nx - tx, pa.1 - ny - ty, ka),
        ];
        let mode = if overlay { Fill::Overlay } else { Fill::Line };
        self.fill([q[0], q[1], q[2]], colour, mode);
        self.fill([q[0], q[2], q[3]], colour, mode);
    }

    /// Draws a filled disc of `radius` pixels at a world point, over everything.
    pub fn dot(&mut self, p: &Point3<f64>, colour: Rgb, radius: f64) {
        let Some((x, y, _)) = self.camera.project(p) else { return };
        let n = 12;
        let ring: Vec<(f64, f64, f64)> = (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / n as f64;
                (x + radius * t.cos(), y + radius * t.sin(), 0.0)
            })
            .collect();
        for i in 1..n - 1 {
            self.fill([ring[0], ring[i], ring[i + 1]], colour, Fill::Overlay);
        }
    }

    /// Encodes the image as an 8-bit RGB PNG.
    ///
    /// # Errors
    /// [`ViewerError::Png`] if encoding fails.
    pub fn to_png(&self) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut out, self.camera.width, self.camera.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header().map_err(png_err)?;
            writer.write_image_data(&self.rgb).map_err(png_err)?;
        }
        Ok(out)
    }

    /// Writes the image as a PNG file.
    ///
    /// # Errors
    /// [`ViewerError::Png`] or [`ViewerError::Io`].
    pub fn save_png(&self, path: &Path) -> Result<()> {
        let bytes = self.to_png()?;
        std::fs::write(path, bytes).map_err(|source| ViewerError::Io { path: path.to_path_buf(), source })
    }
}

fn png_err(e: png::EncodingError) -> ViewerError {
    ViewerError::Png { reason: e.to_string() }
}
