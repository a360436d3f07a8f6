//! Writing the standard world to files that other tools open: URDF robots and hands (through
//! `opengrasp_core::urdf`), object meshes (STL and OBJ) with one-link object URDFs, and the whole
//! kitchen as a single OBJ.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Vector3};
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::mesh_io::{self, MeshFormat};
use opengrasp_core::model::{Geometry, Link, RobotBuilder, Shape, TriangleMesh};
use opengrasp_core::scene::Scene;
use opengrasp_core::srdf;
use opengrasp_core::urdf::{self, ExportOptions};

use crate::error::{AssetError, Result};
use crate::mesh::{box_shell, lathe, MeshBuilder};
use crate::objects::ObjectModel;
use crate::{hands, objects, robots, scenes};

/// Segments used to tessellate cylinders, spheres and capsules for OBJ export.
const SEGMENTS: usize = 24;

/// The files written by [`export_to`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExportReport {
    /// URDF files of the humanoid, the hands and the objects.
    pub urdfs: Vec<PathBuf>,
    /// SRDF files (joint groups, allowed collisions) of the humanoid and the hands, next to
    /// their URDFs.
    pub srdfs: Vec<PathBuf>,
    /// Stand-alone object meshes (`.stl` and `.obj`).
    pub meshes: Vec<PathBuf>,
    /// The kitchen as one OBJ file.
    pub kitchen_obj: PathBuf,
}

/// Writes the standard world under `dir`: `robots/armar3.urdf` and `.srdf`, `hands/<hand>.urdf`
/// and `.srdf` (SRDF: joint groups and the allowed-collision matrix, for MoveIt and for
/// [`opengrasp_core::srdf`]),
/// `objects/<name>.urdf` (one link with mesh and inertial; meshes as exact OBJ under
/// `objects/meshes/`), `objects/<name>.stl` and `.obj`, and `kitchen.obj`.
///
/// # Errors
/// [`AssetError::Core`] / [`AssetError::Io`] if a file cannot be written.
pub fn export_to(dir: impl AsRef<Path>) -> Result<ExportReport> {
    let dir = dir.as_ref();
    let mut report = ExportReport::default();
    let armar = robots::armar3();
    report.urdfs.push(urdf::export(&armar, &dir.join("robots"))?);
    report.srdfs.push(srdf::export(&armar, &dir.join("robots"))?);
    for h in [hands::barrett(), hands::armar3_hand(), hands::sdh()] {
        report.urdfs.push(urdf::export(h.robot(), &dir.join("hands"))?);
        report.srdfs.push(srdf::export(h.robot(), &dir.join("hands"))?);
    }
    let obj_dir = dir.join("objects");
    let exact = ExportOptions { mesh_format: MeshFormat::Obj, ..ExportOptions::default() };
    for o in objects::all() {
        report.urdfs.push(urdf::export_with(&object_robot(&o)?, &obj_dir, &exact)?);
        let stl = obj_dir.join(format!("{}.stl", o.name));
        write(&stl, &mesh_io::write_stl_binary(&o.mesh))?;
        let obj = obj_dir.join(format!("{}.obj", o.name));
        write(&obj, mesh_io::write_obj(&[(o.name.as_str(), &o.mesh)]).as_bytes())?;
        report.meshes.extend([stl, obj]);
    }
    let kitchen = scenes::kitchen()?;
    report.kitchen_obj = dir.join("kitchen.obj");
    write(&report.kitchen_obj, scene_obj(&kitchen.scene)?.as_bytes())?;
    Ok(report)
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| AssetError::Io { path: path.to_path_buf(), source };
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(io)?;
    }
    std::fs::write(path, bytes).map_err(io)
}

/// An object as a one-link robot (mesh visual and collision, inertial), for URDF export.
///
/// # Errors
/// [`AssetError::Core`] if the model is rejected (not for stock objects).
pub fn object_robot(object: &ObjectModel) -> Result<opengrasp_core::model::Robot> {
    let mut link = Link::new(&object.name).with_shape(object.shape()).with_inertial(object.inertial.clone());
    link.visuals.push(object.shape());
    Ok(RobotBuilder::new(&object.name).link(link).build()?)
}

/// The kitchen (static bodies, objects and the humanoid at its start pose) as Wavefront OBJ
/// text, one `o` object per body, object and robot link shape.
///
/// # Errors
/// [`AssetError::Core`] if the kitchen cannot be built.
pub fn kitchen_obj() -> Result<String> {
    scene_obj(&scenes::kitchen()?.scene)
}

/// Any scene as Wavefront OBJ text (primitives tessellated, world coordinates).
///
/// # Errors
/// As [`scene_meshes`].
pub fn scene_obj(scene: &Scene) -> Result<String> {
    let named = scene_meshes(scene)?;
    let refs: Vec<(&str, &TriangleMesh)> = named.iter().map(|(n, m)| (n.as_str(), m)).collect();
    Ok(mesh_io::write_obj(&refs))
}

/// Every shape of a scene as a named triangle mesh in world coordinates (primitives
/// tessellated): static bodies, then objects, then each robot's links at its configuration
/// (`robot/link`). A body or link with several shapes gives `name_0`, `name_1`, ...
///
/// # Errors
/// [`AssetError::Core`] if a robot's configuration is invalid or a shape cannot be
/// tessellated.
pub fn scene_meshes(scene: &Scene) -> Result<Vec<(String, TriangleMesh)>> {
    let mut named: Vec<(String, TriangleMesh)> = Vec::new();
    let mut add = |name: String, pose: &Isometry3<f64>, shapes: &[Shape]| -> Result<()> {
        for (i, s) in shapes.iter().enumerate() {
            let mesh = geometry_mesh(&s.geometry)?.transformed(&(pose * s.origin));
            let n = if shapes.len() == 1 { name.clone() } else { format!("{name}_{i}") };
            named.push((n, mesh));
        }
        Ok(())
    };
    for b in scene.bodies() {
        add(b.name.clone(), &b.pose, &b.shapes)?;
    }
    for o in scene.objects() {
        add(o.name.clone(), &o.pose, &o.shapes)?;
    }
    for r in scene.robots() {
        let poses = forward_kinematics(&r.robot, &r.q)?;
        for (link, pose) in r.robot.links().iter().zip(poses.as_slice()) {
            add(format!("{}/{}", r.name, link.name), &(r.base_pose * pose), &link.collisions)?;
        }
    }
    Ok(named)
}

/// A closed triangle mesh of a geometry in its local frame (URDF conventions: cylinders and
/// capsules along z, centred).
///
/// # Errors
/// [`AssetError::Core`] for invalid dimensions.
pub fn geometry_mesh(geometry: &Geometry) -> Result<TriangleMesh> {
    geometry.validate()?;
    match geometry {
        Geometry::Box { half_extents } => {
            let mut m = MeshBuilder::new();
            box_shell(&mut m, half_extents * 2.0, Vector3::new(0.0, 0.0, -half_extents.z));
            m.build()
        }
        Geometry::Cylinder { radius, length } => {
            lathe(&[(*radius, -length / 2.0), (*radius, length / 2.0)], SEGMENTS).build()
        }
        Geometry::Sphere { radius } => lathe(&round_profile(*radius, 0.0), SEGMENTS).build(),
        Geometry::Capsule { radius, length } => lathe(&round_profile(*radius, *length), SEGMENTS).build(),
        Geometry::Mesh(m) => Ok(m.as_ref().clone()),
    }
}

/// Profile of a capsule (a sphere for `length = 0`): two hemispheres `length` apart.
fn round_profile(radius: f64, length: f64) -> Vec<(f64, f64)> {
    const STEPS: usize = 6;
    let mut p = vec![(0.0, -length / 2.0 - radius)];
    for k in 1..=STEPS {
        let a = TAU / 4.0 * (k as f64 / STEPS as f64); // from the pole to the equator
        p.push((radius * a.sin(), -length / 2.0 - radius * a.cos()));
    }
    for k in (1..=STEPS).rev() {
        let a = TAU / 4.0 * (k as f64 / STEPS as f64);
        if k == STEPS && length == 0.0 {
            continue; // the equator ring is already there
        }
        p.push((radius * a.sin(), length / 2.0 + radius * a.cos()));
    }
    p.push((0.0, length / 2.0 + radius));
    p
}

/// The vertices of every object in `text`, for quick checks: `(name, vertex count)`.
pub fn obj_summary(text: &str) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("o ") {
            out.push((name.to_string(), 0));
        } else if line.starts_with("v ") {
            if let Some(last) = out.last_mut() {
                last.1 += 1;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    #[test]
    fn tessellated_primitives_are_closed_and_sized() {
        let cases = [
            (Geometry::cuboid(0.2, 0.4, 0.6), Vector3::new(0.2, 0.4, 0.6)),
            (Geometry::Cylinder { radius: 0.1, length: 0.5 }, Vector3::new(0.2, 0.2, 0.5)),
            (Geometry::Sphere { radius: 0.1 }, Vector3::new(0.2, 0.2, 0.2)),
            (Geometry::Capsule { radius: 0.05, length: 0.3 }, Vector3::new(0.1, 0.1, 0.4)),
        ];
        for (g, size) in cases {
            let m = geometry_mesh(&g).unwrap();
            assert!(m.is_watertight() && m.signed_volume() > 0.0, "{g:?}");
            let (lo, hi) = m.aabb();
            assert!(((hi - lo) - size).norm() < 1e-9, "{g:?}: {:?}", hi - lo);
            assert!((nalgebra::center(&lo, &hi) - Point3::origin()).norm() < 1e-9);
        }
    }
}
