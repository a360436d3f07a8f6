//! URDF → [`Robot`].

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use super::limits::check_xml;
use super::options::{LoadOptions, LoadWarning, LoadedRobot, Visuals};
use super::resolver::{FileResolver, MeshResolver};
use crate::error::{CoreError, Result};
use crate::model::{Geometry, Inertial, JointKind, JointSpec, Link, Robot, RobotBuilder, Shape, TriangleMesh};

fn malformed(reason: impl Into<String>) -> CoreError {
    CoreError::MalformedUrdf { reason: reason.into() }
}

fn finite(what: impl FnOnce() -> String, values: &[f64]) -> Result<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(malformed(format!("non-finite value in {}", what())))
    }
}

/// Converts a URDF `<origin>` (translation, then fixed-axis roll-pitch-yaw) to a pose.
fn pose(p: &urdf_rs::Pose, what: impl FnOnce() -> String) -> Result<Isometry3<f64>> {
    let (xyz, rpy) = (p.xyz.0, p.rpy.0);
    finite(what, &[xyz[0], xyz[1], xyz[2], rpy[0], rpy[1], rpy[2]])?;
    Ok(Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    ))
}

/// Loaded meshes by (URI, scale bits), so a file used by several shapes is decoded once and
/// shared.
type MeshCache = HashMap<(String, [u64; 3]), Arc<TriangleMesh>>;

fn geometry(
    g: &urdf_rs::Geometry,
    resolver: &dyn MeshResolver,
    cache: &mut MeshCache,
    what: &dyn Fn() -> String,
) -> Result<Geometry> {
    Ok(match g {
        urdf_rs::Geometry::Box { size } => {
            finite(what, &size.0)?;
            Geometry::Box { half_extents: Vector3::from(size.0) * 0.5 }
        }
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere { radius: *radius },
        urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder { radius: *radius, length: *length },
        urdf_rs::Geometry::Capsule { radius, length } => Geometry::Capsule { radius: *radius, length: *length },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map_or([1.0; 3], |s| s.0);
            finite(what, &scale)?;
            let key = (filename.clone(), scale.map(f64::to_bits));
            if let Some(mesh) = cache.get(&key) {
                return Ok(Geometry::Mesh(mesh.clone()));
            }
            let bytes = resolver.resolve(filename)?;
            let mut mesh = crate::mesh_io::read_mesh(&bytes, filename)?;
            if scale != [1.0; 3] {
                mesh = scaled(&mesh, &Vector3::from(scale))?;
            }
            let mesh = Arc::new(mesh);
            cache.insert(key, mesh.clone());
            Geometry::Mesh(mesh)
        }
    })
}

/// `mesh` scaled per axis, dropping faces the scale makes degenerate (an mm → m scale of
/// `0.001` shrinks areas a million times, so sliver faces fall below the area threshold that
/// reading would have dropped them at).
fn scaled(mesh: &TriangleMesh, scale: &Vector3<f64>) -> Result<TriangleMesh> {
    if scale.iter().any(|&f| f == 0.0) {
        return Err(CoreError::DegenerateMesh { reason: format!("zero mesh scale factor in {scale:?}") });
    }
    let vertices = mesh.vertices().iter().map(|v| Point3::from(v.coords.component_mul(scale))).collect();
    let mut triangles = mesh.triangles().to_vec();
    if scale.x * scale.y * scale.z < 0.0 {
        // A mirroring scale flips orientation; swap two indices to keep faces outward.
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    TriangleMesh::new_dropping_degenerate(vertices, triangles)
}

fn inertial(link: &urdf_rs::Link) -> Result<Option<Inertial>> {
    let i = &link.inertial;
    let t = &i.inertia;
    let values = [t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz];
    let what = || format!("inertial of link `{}`", link.name);
    finite(what, &values)?;
    finite(what, &[i.mass.value])?;
    let origin = pose(&i.origin, what)?;
    // urdf-rs fills an absent <inertial> with zeros: treat an all-zero one as "no mass data".
    if i.mass.value == 0.0 && values.iter().all(|&v| v == 0.0) && origin == Isometry3::identity() {
        return Ok(None);
    }
    let inertia = Matrix3::new(t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz);
    Ok(Some(Inertial { origin, mass: i.mass.value, inertia }))
}

fn joint_spec(j: &urdf_rs::Joint, fixed: &HashMap<&str, bool>, warnings: &mut Vec<LoadWarning>) -> Result<JointSpec> {
    let l = &j.limit;
    let kind = match j.joint_type {
        urdf_rs::JointType::Fixed => JointKind::Fixed,
        urdf_rs::JointType::Continuous => JointKind::Continuous,
        urdf_rs::JointType::Prismatic => JointKind::Prismatic,
        // URDF 1.2 writes an omitted revolute limit as (-inf, inf): that is a continuous joint.
        urdf_rs::JointType::Revolute if l.lower == f64::NEG_INFINITY && l.upper == f64::INFINITY => {
            JointKind::Continuous
        }
        urdf_rs::JointType::Revolute => JointKind::Revolute,
        ref other => {
            return Err(malformed(format!(
                "joint `{}` has unsupported type {other:?} (floating, planar and spherical joints are not modelled)",
                j.name
            )))
        }
    };
    let mut spec = JointSpec::new(j.name.clone(), kind, j.parent.link.clone(), j.child.link.clone())
        .origin(pose(&j.origin, || format!("origin of joint `{}`", j.name))?)
        .axis(Vector3::from(j.axis.xyz.0));
    if matches!(kind, JointKind::Revolute | JointKind::Prismatic) {
        // urdf-rs reports an absent <limit> as all zeros; urdfdom rejects it, and so do we.
        if l.lower == 0.0 && l.upper == 0.0 && l.velocity == 0.0 && l.effort == 0.0 {
            return Err(malformed(format!("joint `{}` needs a <limit> element", j.name)));
        }
        if !(l.lower.is_finite() && l.upper.is_finite()) {
            return Err(malformed(format!("joint `{}` needs finite lower and upper limits", j.name)));
        }
        if l.velocity.is_nan() || l.effort.is_nan() {
            return Err(malformed(format!("joint `{}` has a NaN velocity or effort limit", j.name)));
        }
        spec = spec.limits(l.lower, l.upper, l.velocity, l.effort);
    }
    if let Some(m) = &j.mimic {
        let Some(&leader_fixed) = fixed.get(m.joint.as_str()) else {
            return Err(CoreError::UnknownJoint { name: m.joint.clone() });
        };
        if kind == JointKind::Fixed || leader_fixed {
            warnings.push(LoadWarning::MimicIgnored { joint: j.name.clone(), leader: m.joint.clone() });
        } else {
            spec = spec.mimic(m.joint.clone(), m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0));
        }
    }
    Ok(spec)
}

/// Builds a [`Robot`] from a parsed `urdf_rs::Robot`, loading meshes through `resolver`,
/// with the default [`LoadOptions`] (visuals loaded; use [`from_urdf_rs_with`] to see the
/// warnings).
///
/// Mapping: `revolute`, `continuous`, `prismatic` and `fixed` joints map to [`JointKind`]
/// (a URDF 1.2 revolute joint with both limits omitted becomes continuous); `floating`,
/// `planar` and `spherical` joints are rejected. Mimic joints keep multiplier (default 1) and
/// offset (default 0); a `<mimic>` on a fixed joint, or naming a fixed joint, is ignored with
/// [`LoadWarning::MimicIgnored`]. Limits keep lower/upper/velocity/effort for revolute and
/// prismatic joints; continuous joints carry no limits. Box, sphere, cylinder, capsule and mesh
/// (`.stl`, `.obj`, `.dae`, with `scale` applied, faces the scale makes degenerate dropped)
/// geometry is supported; materials are ignored. An all-zero `<inertial>` (which is what
/// urdf-rs reports when the element is absent) becomes `None`.
///
/// # Errors
/// [`CoreError::MalformedUrdf`] for unsupported joint types, missing or non-finite limits
/// (a revolute or prismatic joint whose `<limit>` is absent or all zero counts as missing),
/// non-finite numbers and anything [`RobotBuilder::build`] rejects (bad tree, bad geometry);
/// [`CoreError::UnknownJoint`] if a mimic joint follows a joint that does not exist;
/// [`CoreError::MeshNotFound`], [`CoreError::PackageNotFound`], [`CoreError::MeshFormat`],
/// [`CoreError::DegenerateMesh`] or [`CoreError::Io`] from loading collision meshes (visual
/// meshes that fail are left out with a warning).
pub fn from_urdf_rs(urdf: &urdf_rs::Robot, resolver: &dyn MeshResolver) -> Result<Robot> {
    from_urdf_rs_with(urdf, resolver, &LoadOptions::default()).map(|l| l.robot)
}

/// As [`from_urdf_rs`], with options, returning the load's warnings. Of `options`, only
/// [`LoadOptions::visuals`] applies here (the resolver is given).
///
/// # Errors
/// As [`from_urdf_rs`].
pub fn from_urdf_rs_with(
    urdf: &urdf_rs::Robot,
    resolver: &dyn MeshResolver,
    options: &LoadOptions,
) -> Result<LoadedRobot> {
    let mut cache = MeshCache::new();
    let mut warnings = Vec::new();
    let mut builder = RobotBuilder::new(urdf.name.clone());
    for l in &urdf.links {
        let mut link = Link::new(l.name.clone());
        link.inertial = inertial(l)?;
        if options.visuals == Visuals::Load {
            for (i, v) in l.visual.iter().enumerate() {
                let what = || format!("visual {i} of link `{}`", l.name);
                let shape = pose(&v.origin, what).and_then(|origin| {
                    let g = geometry(&v.geometry, resolver, &mut cache, &what)?;
                    g.validate()?;
                    Ok(Shape::new(origin, g))
                });
                match shape {
                    Ok(shape) => link.visuals.push(shape),
                    Err(e) => warnings.push(LoadWarning::VisualNotLoaded {
                        link: l.name.clone(),
                        index: i,
                        reason: e.to_string(),
                    }),
                }
            }
        }
        for (i, c) in l.collision.iter().enumerate() {
            let what = || format!("collision {i} of link `{}`", l.name);
            let origin = pose(&c.origin, what)?;
            link.collisions.push(Shape::new(origin, geometry(&c.geometry, resolver, &mut cache, &what)?));
        }
        builder = builder.link(link);
    }
    let fixed: HashMap<&str, bool> =
        urdf.joints.iter().map(|j| (j.name.as_str(), matches!(j.joint_type, urdf_rs::JointType::Fixed))).collect();
    for j in &urdf.joints {
        builder = builder.joint(joint_spec(j, &fixed, &mut warnings)?);
    }
    let robot = builder.build().map_err(|e| match e {
        CoreError::InvalidModel { .. }
        | CoreError::InvalidGeometry { .. }
        | CoreError::NonFinite { .. }
        | CoreError::UnknownLink { .. } => malformed(e.to_string()),
        other => other,
    })?;
    Ok(LoadedRobot { robot, warnings })
}

/// Parses URDF text and builds the robot, loading meshes through `resolver`
/// (a [`FileResolver`], an [`super::InMemoryResolver`] or your own), with the default
/// [`LoadOptions`].
///
/// # Errors
/// [`CoreError::LimitExceeded`] if the text exceeds the default [`super::XmlLimits`];
/// [`CoreError::MalformedUrdf`] if it is not well-formed URDF; otherwise as [`from_urdf_rs`].
pub fn from_str(text: &str, resolver: &dyn MeshResolver) -> Result<Robot> {
    from_str_with(text, resolver, &LoadOptions::default()).map(|l| l.robot)
}

/// As [`from_str`], with options, returning the load's warnings. The text is checked against
/// [`LoadOptions::limits`] before urdf-rs parses it; the package options do not apply (the
/// resolver is given).
///
/// # Errors
/// As [`from_str`].
pub fn from_str_with(text: &str, resolver: &dyn MeshResolver, options: &LoadOptions) -> Result<LoadedRobot> {
    check_xml(text.as_bytes(), &options.limits, "urdf", |reason| CoreError::MalformedUrdf { reason })?;
    let urdf = urdf_rs::read_from_string(text).map_err(|e| malformed(e.to_string()))?;
    from_urdf_rs_with(&urdf, resolver, options)
}

/// Loads a URDF file with the default [`LoadOptions`]: mesh paths are resolved relative to the
/// file's directory and `package://` URIs as ROS does (the file's own package and its
/// siblings, then `ROS_PACKAGE_PATH` / `AMENT_PREFIX_PATH`; see [`FileResolver`]). Visuals
/// that fail to load are left out (see [`load_file_with`] for the warnings).
///
/// # Errors
/// [`CoreError::Io`] if the file cannot be read; otherwise as [`from_str`].
pub fn load_file(path: impl AsRef<Path>) -> Result<Robot> {
    load_file_with(path, &LoadOptions::default()).map(|l| l.robot)
}

/// The [`FileResolver`] [`load_file_with`] uses for a URDF file at `path`.
pub fn file_resolver(path: &Path, options: &LoadOptions) -> FileResolver {
    let base = path.parent().map_or_else(|| Path::new(".").to_path_buf(), Path::to_path_buf);
    let mut resolver = FileResolver::new(base);
    for (name, dir) in &options.packages {
        resolver = resolver.with_package(name.clone(), dir.clone());
    }
    for root in &options.search_roots {
        resolver = resolver.with_search_root(root.clone());
    }
    if options.ros_package_path {
        resolver = resolver.with_ros_package_path();
    }
    resolver
}

/// Loads a URDF file with options, returning the load's warnings.
///
/// # Errors
/// [`CoreError::Io`] if the file cannot be read; [`CoreError::LimitExceeded`] if it is larger
/// than [`super::XmlLimits::max_bytes`]; otherwise as [`from_str`].
pub fn load_file_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<LoadedRobot> {
    let path = path.as_ref();
    let io = |source| CoreError::Io { path: path.to_path_buf(), source };
    let size = std::fs::metadata(path).map_err(io)?.len();
    let max = options.limits.max_bytes;
    if size > max as u64 {
        let actual = usize::try_from(size).unwrap_or(usize::MAX);
        return Err(CoreError::LimitExceeded { document: "urdf", what: "size in bytes", limit: max, actual });
    }
    let text = std::fs::read_to_string(path).map_err(io)?;
    from_str_with(&text, &file_resolver(path, options), options)
}

/// Converts a parsed URDF, resolving mesh file names relative to the current working
/// directory (use [`from_urdf_rs`] to choose the resolver).
impl TryFrom<&urdf_rs::Robot> for Robot {
    type Error = CoreError;

    fn try_from(urdf: &urdf_rs::Robot) -> Result<Self> {
        from_urdf_rs(urdf, &FileResolver::new("."))
    }
}
