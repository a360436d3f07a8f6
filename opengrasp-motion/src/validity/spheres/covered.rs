//! The sphere covers of a robot's links: one set of spheres per link with collision geometry.

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::model::{Geometry, LinkId, Robot};

use super::MeshCover;
use crate::error::Result;
use crate::validity::cover::{self, cover_box};

fn cover_shape(
    geometry: &Geometry,
    origin: &Isometry3<f64>,
    meshes: MeshCover,
    out: &mut Vec<(Point3<f64>, f64)>,
) -> Result<()> {
    match geometry {
        Geometry::Sphere { radius } => out.push((origin * Point3::origin(), *radius)),
        Geometry::Capsule { radius, length } | Geometry::Cylinder { radius, length } => {
            let n = (length / radius).ceil().max(1.0) as usize;
            let s = length / n as f64;
            let rr = (radius * radius + s * s * 0.25).sqrt();
            for k in 0..=n {
                let z = -length * 0.5 + s * k as f64;
                out.push((origin * Point3::new(0.0, 0.0, z), rr));
            }
        }
        Geometry::Box { half_extents } => cover_box(half_extents, origin, out),
        Geometry::Mesh(mesh) => {
            let cover = match meshes {
                MeshCover::BoundingBox => cover::bounding_box_cover(mesh),
                MeshCover::Voxels { cell } => cover::voxel_cover(mesh, cell)?,
                MeshCover::Greedy(options) => cover::greedy_cover(mesh, &options)?,
                MeshCover::Adaptive { cell, max_overhang } => cover::adaptive_cover(mesh, cell, max_overhang)?,
            };
            out.extend(cover.spheres.iter().map(|(c, r)| (origin * c, *r)));
        }
    }
    Ok(())
}

/// Every link with collision geometry covered by spheres.
#[derive(Debug)]
pub(super) struct Covered {
    pub(super) links: Vec<LinkId>,
    /// (index into `links`, centre in the link frame, radius), grouped by link.
    pub(super) spheres: Vec<(usize, Point3<f64>, f64)>,
    pub(super) ranges: Vec<(usize, usize)>,
    /// Per link, points whose hull holds its spheres (for the motion bound).
    pub(super) points: Vec<Vec<Point3<f64>>>,
}

impl Covered {
    pub(super) fn new(robot: &Robot, meshes: MeshCover) -> Result<Self> {
        let mut this = Self { links: Vec::new(), spheres: Vec::new(), ranges: Vec::new(), points: Vec::new() };
        let mut buf = Vec::new();
        for (i, link) in robot.links().iter().enumerate() {
            if link.collisions.is_empty() {
                continue;
            }
            buf.clear();
            for shape in &link.collisions {
                cover_shape(&shape.geometry, &shape.origin, meshes, &mut buf)?;
            }
            let k = this.links.len();
            let start = this.spheres.len();
            let mut pts = Vec::new();
            for &(c, r) in &buf {
                this.spheres.push((k, c, r));
                // The sphere's bounding-box corners contain it.
                for s in 0..8 {
                    let sign = |b: usize| if s & b == 0 { -r } else { r };
                    pts.push(c + Vector3::new(sign(1), sign(2), sign(4)));
                }
            }
            this.ranges.push((start, this.spheres.len()));
            this.links.push(LinkId(i));
            this.points.push(pts);
        }
        Ok(this)
    }
}
