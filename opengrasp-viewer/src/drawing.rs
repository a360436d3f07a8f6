//! What to draw, independent of where: coloured world-frame meshes, polylines, segments and
//! dots. The PNG rasteriser ([`Drawing::render`]) and the rerun logger both read a
//! [`Drawing`], so a snapshot and a recording show the same things.

use nalgebra::{Point3, Vector3};
use opengrasp_core::model::TriangleMesh;
use opengrasp_core::scene::Scene;

use crate::error::Result;
use crate::raster::{Camera, Canvas, Rgb};

/// What a mesh belongs to (chooses its colour and its entity path in rerun).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Static environment (furniture, obstacles).
    Environment,
    /// A movable object.
    Object,
    /// A robot link at the drawn state.
    Robot,
    /// A robot link at a second state (goal or final), drawn lighter.
    Ghost,
    /// A link in collision.
    Colliding,
}

impl Kind {
    /// The default colour of the kind.
    pub fn colour(self) -> Rgb {
        match self {
            Kind::Environment => [190, 170, 140],
            Kind::Object => [70, 150, 90],
            Kind::Robot => [90, 120, 180],
            Kind::Ghost => [185, 200, 230],
            Kind::Colliding => [220, 30, 30],
        }
    }
}

/// A named mesh in world coordinates.
#[derive(Clone, Debug)]
pub struct MeshItem {
    /// Name (`body`, `object`, `robot/link`).
    pub name: String,
    /// What it is.
    pub kind: Kind,
    /// Colour.
    pub colour: Rgb,
    /// The mesh (world frame, m).
    pub mesh: TriangleMesh,
}

/// A named polyline (a path of the tip, a friction-cone edge, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Name.
    pub name: String,
    /// Colour.
    pub colour: Rgb,
    /// Vertices (world frame, m).
    pub points: Vec<Point3<f64>>,
}

/// A named dot (a contact point, an invalid state's tip).
#[derive(Clone, Debug, PartialEq)]
pub struct Dot {
    /// Name.
    pub name: String,
    /// Colour.
    pub colour: Rgb,
    /// Position (world frame, m).
    pub position: Point3<f64>,
}

/// Everything to draw.
#[derive(Clone, Debug, Default)]
pub struct Drawing {
    /// Surfaces.
    pub meshes: Vec<MeshItem>,
    /// Lines, drawn over the surfaces.
    pub lines: Vec<Polyline>,
    /// Dots, drawn over everything.
    pub dots: Vec<Dot>,
}

/// Background of rendered images.
pub const BACKGROUND: Rgb = [255, 255, 255];

impl Drawing {
    /// An empty drawing.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds every shape of a scene ([`opengrasp_assets::export::scene_meshes`]): static bodies
    /// as [`Kind::Environment`], objects as [`Kind::Object`], robot links as `robot_kind`.
    ///
    /// # Errors
    /// As [`opengrasp_assets::export::scene_meshes`].
    pub fn add_scene(&mut self, scene: &Scene, robot_kind: Kind) -> Result<()> {
        let named = opengrasp_assets::export::scene_meshes(scene)?;
        let bodies: usize = scene.bodies().iter().map(|b| b.shapes.len()).sum();
        let objects: usize = scene.objects().iter().map(|o| o.shapes.len()).sum();
        for (i, (name, mesh)) in named.into_iter().enumerate() {
            let kind = if i < bodies {
                Kind::Environment
            } else if i < bodies + objects {
                Kind::Object
            } else {
                robot_kind
            };
            self.meshes.push(MeshItem { name, kind, colour: kind.colour(), mesh });
        }
        Ok(())
    }

    /// Adds the robots of a scene only (their links at the scene's configurations) as `kind`,
    /// names prefixed with `prefix/`.
    ///
    /// # Errors
    /// As [`opengrasp_assets::export::scene_meshes`].
    pub fn add_robots(&mut self, scene: &Scene, kind: Kind, prefix: &str) -> Result<()> {
        let mut robots_only = Scene::new("robots");
        for r in scene.robots() {
            let id = robots_only.add_robot(r.name.clone(), r.robot.clone(), r.base_pose)?;
            robots_only.set_robot_configuration(id, &r.q)?;
        }
        for (name, mesh) in opengrasp_assets::export::scene_meshes(&robots_only)? {
            self.meshes.push(MeshItem { name: format!("{prefix}/{name}"), kind, colour: kind.colour(), mesh });
        }
        Ok(())
    }

    /// Recolours meshes whose name is in `names` as [`Kind::Colliding`].
    pub fn mark_colliding(&mut self, names: &[String]) {
        for m in self.meshes.iter_mut().filter(|m| names.contains(&m.name)) {
            m.kind = Kind::Colliding;
            m.colour = Kind::Colliding.colour();
        }
    }

    /// Axis-aligned bounds of everything drawn, `None` if empty.
    pub fn bounds(&self) -> Option<(Point3<f64>, Point3<f64>)> {
        let points = self
            .meshes
            .iter()
            .flat_map(|m| m.mesh.vertices().iter())
            .chain(self.lines.iter().flat_map(|l| l.points.iter()))
            .chain(self.dots.iter().map(|d| &d.position));
        let mut out: Option<(Point3<f64>, Point3<f64>)> = None;
        for p in points {
            let (lo, hi) = out.get_or_insert((*p, *p));
            *lo = lo.inf(p);
            *hi = hi.sup(p);
        }
        out
    }

    /// Rasterises the drawing: meshes z-buffered and shaded, then lines (2 px, depth-tested
    /// against the meshes, and again thin over them so hidden parts still show), then dots
    /// (radius 4 px).
    pub fn render(&self, camera: Camera) -> Canvas {
        let mut canvas = Canvas::new(camera, BACKGROUND);
        for m in &self.meshes {
            let v = m.mesh.vertices();
            for t in m.mesh.triangles() {
                canvas.triangle(&v[t[0] as usize], &v[t[1] as usize], &v[t[2] as usize], m.colour);
            }
        }
        for l in &self.lines {
            let faint = l.colour.map(|c| ((u16::from(c) + 2 * 255) / 3) as u8);
            for w in l.points.windows(2) {
                canvas.segment(&w[0], &w[1], faint, 1.0, true);
            }
        }
        for l in &self.lines {
            for w in l.points.windows(2) {
                canvas.segment(&w[0], &w[1], l.colour, 2.5, false);
            }
        }
        for d in &self.dots {
            canvas.dot(&d.position, d.colour, 4.0);
        }
        canvas
    }

    /// Renders the drawing in perspective (40° field of view, world z up) from the
    /// front-left-above, framed on the robots, paths and dots. When the rest of the scene is
    /// much larger (a kitchen around a robot), the view looks down more steeply and cuts away
    /// everything nearer to the eye than the framed part (walls, shelves above it).
    ///
    /// # Errors
    /// [`crate::ViewerError::InvalidCamera`] for an empty drawing or a zero size.
    pub fn render_framed(&self, width: u32, height: u32) -> Result<Canvas> {
        let all =
            self.bounds().ok_or_else(|| crate::ViewerError::InvalidCamera { reason: "nothing to draw".into() })?;
        let focus = self.focus_bounds().unwrap_or(all);
        let radius = |(lo, hi): (Point3<f64>, Point3<f64>)| (hi - lo).norm() / 2.0;
        let fov = Some(40f64.to_radians());
        if radius(all) <= 2.0 * radius(focus) {
            let camera =
                Camera::framing(all.0, all.1, Vector3::new(1.0, 0.6, -0.55), Vector3::z(), fov, width, height)?;
            return Ok(self.render(camera));
        }
        // Frame the focus with a margin; clip what lies between the eye and it.
        let margin = Vector3::repeat(0.25 * radius(focus).max(0.1));
        let (lo, hi) = (focus.0 - margin, focus.1 + margin);
        let mut camera = Camera::framing(lo, hi, Vector3::new(0.8, 0.5, -1.1), Vector3::z(), fov, width, height)?;
        let centre = nalgebra::center(&lo, &hi);
        camera.near = (centre - camera.eye).dot(&camera.forward) - radius((lo, hi));
        Ok(self.render(camera))
    }

    /// Bounds of the robots (all robot kinds), lines and dots, `None` if there are none.
    fn focus_bounds(&self) -> Option<(Point3<f64>, Point3<f64>)> {
        let focus = Drawing {
            meshes: self
                .meshes
                .iter()
                .filter(|m| !matches!(m.kind, Kind::Environment | Kind::Object))
                .cloned()
                .collect(),
            lines: self.lines.clone(),
            dots: self.dots.clone(),
        };
        focus.bounds()
    }
}
