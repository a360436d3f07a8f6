//! Checks of a problem set that need no robot, and its shapes and poses as core types.

use std::collections::HashSet;
use std::sync::Arc;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::model::{Geometry, Shape, TriangleMesh};
use opengrasp_core::scene::StaticBody;

use super::{GoalSpec, Obstacle, PoseSpec, ProblemSet, ShapeSpec, FORMAT, MAX_PROBLEMS, VERSION};
use crate::error::Result;

/// Most inline mesh vertices (or triangles) per obstacle.
const MAX_INLINE: usize = 1_000_000;

impl ProblemSet {
    /// Checks what can be checked without the robot: format and version, problem count,
    /// finite numbers, positive sizes, unique obstacle names, non-zero quaternions.
    ///
    /// # Errors
    /// [`MotionError::ProblemSetInvalid`](crate::MotionError::ProblemSetInvalid) naming the field.
    pub fn validate(&self) -> Result<()> {
        if self.format != FORMAT {
            return Err(self.invalid("format", format!("`{}` is not `{FORMAT}`", self.format)));
        }
        if self.version != VERSION {
            return Err(
                self.invalid("version", format!("{} is not supported (this build reads {VERSION})", self.version))
            );
        }
        if self.problems.is_empty() {
            return Err(self.invalid("problems", "the set has no problem"));
        }
        if self.problems.len() > MAX_PROBLEMS {
            return Err(self.invalid("problems", format!("{} problems, more than {MAX_PROBLEMS}", self.problems.len())));
        }
        let r = &self.robot;
        if r.urdf.is_some() == r.stock.is_some() {
            return Err(self.invalid("robot", "give exactly one of `urdf` and `stock`"));
        }
        if r.stock.is_some() && r.srdf.is_some() {
            return Err(self.invalid("robot.srdf", "a stock robot takes no SRDF"));
        }
        if let Some(p) = &self.base_pose {
            self.pose(p, "base_pose")?;
        }
        for (i, p) in self.problems.iter().enumerate() {
            let f = |s: &str| format!("problems[{i}].{s}");
            self.finite(&p.start.numbers(), &f("start"))?;
            match &p.goal {
                GoalSpec::Configuration(q) => self.finite(&q.numbers(), &f("goal.configuration"))?,
                GoalSpec::Configurations(qs) => {
                    if qs.is_empty() {
                        return Err(self.invalid(f("goal.configurations"), "empty goal set"));
                    }
                    for (k, q) in qs.iter().enumerate() {
                        self.finite(&q.numbers(), &f(&format!("goal.configurations[{k}]")))?;
                    }
                }
                GoalSpec::Pose(g) => {
                    self.pose(&PoseSpec { position: g.position, orientation: g.orientation }, &f("goal.pose"))?;
                    for (name, v) in [
                        ("position_tolerance", g.position_tolerance),
                        ("orientation_tolerance", g.orientation_tolerance),
                    ] {
                        if !(v.is_finite() && v > 0.0) {
                            return Err(self.invalid(f(&format!("goal.pose.{name}")), format!("{v} is not > 0")));
                        }
                    }
                }
            }
            for (name, v) in &p.joints {
                if !v.is_finite() {
                    return Err(self.invalid(f(&format!("joints.{name}")), "not a finite number"));
                }
            }
            let mut names = HashSet::new();
            for (k, o) in p.obstacles.iter().enumerate() {
                if !names.insert(o.name.as_str()) {
                    return Err(self.invalid(f(&format!("obstacles[{k}].name")), format!("`{}` is used twice", o.name)));
                }
                self.pose(&o.pose, &f(&format!("obstacles[{k}].pose")))?;
            }
        }
        Ok(())
    }

    fn finite(&self, q: &[f64], field: &str) -> Result<()> {
        match q.iter().position(|v| !v.is_finite()) {
            Some(k) => Err(self.invalid(format!("{field}[{k}]"), "not a finite number")),
            None => Ok(()),
        }
    }

    /// The pose as an isometry (quaternion normalised).
    pub(crate) fn pose(&self, p: &PoseSpec, field: &str) -> Result<Isometry3<f64>> {
        if p.position.iter().chain(&p.orientation).any(|v| !v.is_finite()) {
            return Err(self.invalid(field, "not a finite pose"));
        }
        let [x, y, z, w] = p.orientation;
        let q = Quaternion::new(w, x, y, z);
        if q.norm() < 1e-9 {
            return Err(self.invalid(format!("{field}.orientation"), "zero quaternion"));
        }
        let t = Translation3::new(p.position[0], p.position[1], p.position[2]);
        Ok(Isometry3::from_parts(t, UnitQuaternion::from_quaternion(q)))
    }

    /// An obstacle as a static body (mesh files read, sizes checked).
    pub(crate) fn body(&self, o: &Obstacle, field: &str) -> Result<StaticBody> {
        let pose = self.pose(&o.pose, &format!("{field}.pose"))?;
        let bad = |what: &str, v: f64, zero_ok: bool| {
            let ok = v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0));
            if ok {
                Ok(())
            } else {
                Err(self.invalid(format!("{field}.{what}"), format!("{v} is not a finite size > 0")))
            }
        };
        let geometry = match &o.shape {
            ShapeSpec::Box { size } => {
                for v in size {
                    bad("size", *v, false)?;
                }
                Geometry::cuboid(size[0], size[1], size[2])
            }
            ShapeSpec::Sphere { radius } => {
                bad("radius", *radius, false)?;
                Geometry::Sphere { radius: *radius }
            }
            ShapeSpec::Cylinder { radius, length } => {
                bad("radius", *radius, false)?;
                bad("length", *length, false)?;
                Geometry::Cylinder { radius: *radius, length: *length }
            }
            ShapeSpec::Capsule { radius, length } => {
                bad("radius", *radius, false)?;
                bad("length", *length, true)?;
                Geometry::Capsule { radius: *radius, length: *length }
            }
            ShapeSpec::Mesh { path, vertices, triangles, scale } => {
                Geometry::Mesh(Arc::new(self.mesh(path.as_deref(), vertices, triangles, *scale, field)?))
            }
        };
        Ok(StaticBody::new(o.name.clone(), pose, vec![Shape::at_origin(geometry)]))
    }

    fn mesh(
        &self,
        path: Option<&std::path::Path>,
        vertices: &[[f64; 3]],
        triangles: &[[u32; 3]],
        scale: Option<[f64; 3]>,
        field: &str,
    ) -> Result<TriangleMesh> {
        let invalid = |what: &str, reason: String| self.invalid(format!("{field}.{what}"), reason);
        let mesh = match path {
            Some(p) => {
                if !vertices.is_empty() || !triangles.is_empty() {
                    return Err(invalid("path", "give a `path` or inline `vertices`, not both".into()));
                }
                let file = self.resolve(p);
                let bytes = std::fs::read(&file)
                    .map_err(|source| crate::MotionError::ProblemSetIo { path: file.clone(), source })?;
                opengrasp_core::mesh_io::read_mesh(&bytes, &file)?
            }
            None => {
                if vertices.len() > MAX_INLINE || triangles.len() > MAX_INLINE {
                    return Err(invalid("vertices", format!("more than {MAX_INLINE} vertices or triangles")));
                }
                if vertices.iter().flatten().any(|v| !v.is_finite()) {
                    return Err(invalid("vertices", "not finite".into()));
                }
                let points = vertices.iter().map(|v| nalgebra::Point3::new(v[0], v[1], v[2])).collect();
                TriangleMesh::new(points, triangles.to_vec()).map_err(|e| invalid("triangles", e.to_string()))?
            }
        };
        match scale {
            Some(s) => {
                if s.iter().any(|v| !(v.is_finite() && *v != 0.0)) {
                    return Err(invalid("scale", "must be finite and non-zero".into()));
                }
                Ok(mesh.scaled(&Vector3::new(s[0], s[1], s[2]))?)
            }
            None => Ok(mesh),
        }
    }
}
