//! [`Robot`] → URDF text and mesh files.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use nalgebra::Isometry3;

use super::resolver::InMemoryResolver;
use crate::error::{CoreError, Result};
use crate::mesh_io::{self, MeshFormat};
use crate::model::{Geometry, JointKind, Robot, Shape, TriangleMesh};

/// How [`to_urdf_string`] and [`export_with`] write a robot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportOptions {
    /// Directory, relative to the URDF file, that mesh files are written to and referenced
    /// from (`/`-separated, no `..`). Default: `"meshes"`.
    pub mesh_dir: String,
    /// File format of mesh files. Default: [`MeshFormat::Stl`] (binary STL, the most widely
    /// read format, but vertices are rounded to `f32`); [`MeshFormat::Obj`] keeps `f64`
    /// coordinates exactly.
    pub mesh_format: MeshFormat,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self { mesh_dir: "meshes".to_string(), mesh_format: MeshFormat::Stl }
    }
}

/// A robot written as URDF: the document and the mesh files it references.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UrdfDocument {
    /// The URDF XML text.
    pub urdf: String,
    /// Mesh files as (path relative to the URDF file, exactly as written in its `filename`
    /// attributes; file contents).
    pub mesh_files: Vec<(String, Vec<u8>)>,
}

impl UrdfDocument {
    /// A resolver serving this document's mesh files from memory, for
    /// [`super::from_str`]`(&doc.urdf, &doc.resolver())`.
    pub fn resolver(&self) -> InMemoryResolver {
        let mut r = InMemoryResolver::new();
        for (name, bytes) in &self.mesh_files {
            r.insert(name.clone(), bytes.clone());
        }
        r
    }
}

/// Escapes text for an XML attribute value.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// A file-name-safe version of `s` (ASCII letters, digits, `-`, `_`; others become `_`).
fn sanitize(s: &str) -> String {
    let out: String =
        s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
    if out.is_empty() {
        "robot".to_string()
    } else {
        out
    }
}

/// `<origin>` with exactly round-tripping numbers (`{:?}` is Rust's shortest representation
/// that parses back to the same `f64`); `-0.0` is written as `0.0`.
fn origin(out: &mut String, indent: &str, pose: &Isometry3<f64>) {
    let t = pose.translation.vector + nalgebra::Vector3::zeros();
    let (r, p, y) = pose.rotation.euler_angles();
    let (r, p, y) = (r + 0.0, p + 0.0, y + 0.0);
    let _ = writeln!(out, "{indent}<origin xyz=\"{:?} {:?} {:?}\" rpy=\"{r:?} {p:?} {y:?}\"/>", t.x, t.y, t.z);
}

struct MeshFiles<'a> {
    options: &'a ExportOptions,
    by_ptr: HashMap<*const TriangleMesh, String>,
    names: HashSet<String>,
    files: Vec<(String, Vec<u8>)>,
}

impl MeshFiles<'_> {
    /// The relative file name of `mesh`, writing it the first time it is seen.
    fn file_for(&mut self, mesh: &std::sync::Arc<TriangleMesh>, stem: String) -> String {
        let ptr = std::sync::Arc::as_ptr(mesh);
        if let Some(name) = self.by_ptr.get(&ptr) {
            return name.clone();
        }
        let ext = self.options.mesh_format.extension();
        let dir = self.options.mesh_dir.trim_matches('/');
        let mut name = String::new();
        for n in 0.. {
            let suffix = if n == 0 { String::new() } else { format!("_{n}") };
            let file = format!("{stem}{suffix}.{ext}");
            name = if dir.is_empty() { file } else { format!("{dir}/{file}") };
            if !self.names.contains(&name) {
                break;
            }
        }
        let bytes = match self.options.mesh_format {
            MeshFormat::Stl => mesh_io::write_stl_binary(mesh),
            MeshFormat::Obj => mesh_io::write_obj(&[(stem.as_str(), mesh)]).into_bytes(),
        };
        self.names.insert(name.clone());
        self.by_ptr.insert(ptr, name.clone());
        self.files.push((name.clone(), bytes));
        name
    }
}

fn shape(out: &mut String, tag: &str, s: &Shape, files: &mut MeshFiles<'_>, stem: String) {
    let _ = writeln!(out, "    <{tag}>");
    origin(out, "      ", &s.origin);
    out.push_str("      <geometry>\n");
    let _ = match &s.geometry {
        Geometry::Box { half_extents: h } => {
            let size = h * 2.0;
            writeln!(out, "        <box size=\"{:?} {:?} {:?}\"/>", size.x, size.y, size.z)
        }
        Geometry::Sphere { radius } => writeln!(out, "        <sphere radius=\"{radius:?}\"/>"),
        Geometry::Cylinder { radius, length } => {
            writeln!(out, "        <cylinder radius=\"{radius:?}\" length=\"{length:?}\"/>")
        }
        Geometry::Capsule { radius, length } => {
            writeln!(out, "        <capsule radius=\"{radius:?}\" length=\"{length:?}\"/>")
        }
        Geometry::Mesh(mesh) => {
            let file = files.file_for(mesh, stem);
            writeln!(out, "        <mesh filename=\"{}\"/>", escape(&file))
        }
    };
    out.push_str("      </geometry>\n");
    let _ = writeln!(out, "    </{tag}>");
}

/// Writes `robot` as URDF text plus the mesh files its mesh geometry needs.
///
/// Numbers are written with shortest round-trip formatting, so reading the document back
/// ([`super::from_str`] with [`UrdfDocument::resolver`]) reproduces every length, limit, mass,
/// inertia and mimic coupling bit for bit; rotations pass through roll-pitch-yaw (error
/// ~1e-16) and mesh vertices through the chosen mesh format (binary STL rounds them to `f32`).
/// Meshes shared between shapes (the same `Arc`) are written once; meshes are always written
/// already scaled. Capsules are written as `<capsule radius length>` elements, which urdf-rs
/// (and so [`super::from_str`]) reads but ROS urdfdom ignores. Infinite velocity or effort limits
/// are written as `inf` (read by urdf-rs, not by urdfdom). Joint groups and allowed collision
/// pairs have no URDF representation: [`crate::srdf::export`] writes them as SRDF.
pub fn to_urdf_string(robot: &Robot, options: &ExportOptions) -> UrdfDocument {
    let mut files = MeshFiles { options, by_ptr: HashMap::new(), names: HashSet::new(), files: Vec::new() };
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<robot name=\"{}\">", escape(robot.name()));
    let robot_stem = sanitize(robot.name());
    for link in robot.links() {
        let _ = writeln!(out, "  <link name=\"{}\">", escape(&link.name));
        if let Some(i) = &link.inertial {
            out.push_str("    <inertial>\n");
            origin(&mut out, "      ", &i.origin);
            let _ = writeln!(out, "      <mass value=\"{:?}\"/>", i.mass);
            let m = &i.inertia;
            let _ = writeln!(
                out,
                "      <inertia ixx=\"{:?}\" ixy=\"{:?}\" ixz=\"{:?}\" iyy=\"{:?}\" iyz=\"{:?}\" izz=\"{:?}\"/>",
                m[(0, 0)],
                m[(0, 1)],
                m[(0, 2)],
                m[(1, 1)],
                m[(1, 2)],
                m[(2, 2)]
            );
            out.push_str("    </inertial>\n");
        }
        let link_stem = format!("{robot_stem}_{}", sanitize(&link.name));
        for (i, s) in link.visuals.iter().enumerate() {
            shape(&mut out, "visual", s, &mut files, format!("{link_stem}_visual{i}"));
        }
        for (i, s) in link.collisions.iter().enumerate() {
            shape(&mut out, "collision", s, &mut files, format!("{link_stem}_collision{i}"));
        }
        out.push_str("  </link>\n");
    }
    for joint in robot.joints() {
        let kind = match joint.kind {
            JointKind::Fixed => "fixed",
            JointKind::Revolute => "revolute",
            JointKind::Continuous => "continuous",
            JointKind::Prismatic => "prismatic",
        };
        let _ = writeln!(out, "  <joint name=\"{}\" type=\"{kind}\">", escape(&joint.name));
        origin(&mut out, "    ", &joint.origin);
        let _ = writeln!(out, "    <parent link=\"{}\"/>", escape(&robot.link(joint.parent).name));
        let _ = writeln!(out, "    <child link=\"{}\"/>", escape(&robot.link(joint.child).name));
        let a = joint.axis;
        let _ = writeln!(out, "    <axis xyz=\"{:?} {:?} {:?}\"/>", a.x, a.y, a.z);
        if let Some(l) = joint.limits {
            let _ = writeln!(
                out,
                "    <limit lower=\"{:?}\" upper=\"{:?}\" effort=\"{:?}\" velocity=\"{:?}\"/>",
                l.lower, l.upper, l.effort, l.velocity
            );
        }
        if let Some(m) = joint.mimic {
            let _ = writeln!(
                out,
                "    <mimic joint=\"{}\" multiplier=\"{:?}\" offset=\"{:?}\"/>",
                escape(&robot.joint(m.leader).name),
                m.multiplier,
                m.offset
            );
        }
        out.push_str("  </joint>\n");
    }
    out.push_str("</robot>\n");
    UrdfDocument { urdf: out, mesh_files: files.files }
}

/// Writes `robot` to `dir/<name>.urdf` with its meshes under `dir/meshes/` as binary STL
/// ([`ExportOptions::default`]); returns the URDF file's path. See [`export_with`].
///
/// # Errors
/// As [`export_with`].
pub fn export(robot: &Robot, dir: &Path) -> Result<PathBuf> {
    export_with(robot, dir, &ExportOptions::default())
}

pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| CoreError::Io { path: path.to_path_buf(), source };
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(io)?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".tmp{}", std::process::id()));
    let tmp = PathBuf::from(tmp);
    std::fs::write(&tmp, bytes).map_err(|source| CoreError::Io { path: tmp.clone(), source })?;
    std::fs::rename(&tmp, path).map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        CoreError::Io { path: path.to_path_buf(), source }
    })
}

/// Writes `robot` to `dir/<name>.urdf` (the name made file-safe) and its mesh files under
/// `dir/<options.mesh_dir>/`, creating directories as needed; returns the URDF file's path.
/// Each file is written to a temporary name and renamed into place, meshes first, so a reader
/// never sees a partial file or a URDF whose meshes are missing. Load it back with
/// [`super::load_file`].
///
/// # Errors
/// [`CoreError::InvalidParameter`] if `mesh_dir` is absolute or contains `..`;
/// [`CoreError::Io`] if a file cannot be written.
pub fn export_with(robot: &Robot, dir: &Path, options: &ExportOptions) -> Result<PathBuf> {
    if Path::new(&options.mesh_dir).components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(CoreError::InvalidParameter {
            name: "mesh_dir".to_string(),
            reason: format!("`{}` must be a relative path without `..`", options.mesh_dir),
        });
    }
    let doc = to_urdf_string(robot, options);
    for (name, bytes) in &doc.mesh_files {
        write_atomically(&dir.join(name), bytes)?;
    }
    let path = dir.join(format!("{}.urdf", sanitize(robot.name())));
    write_atomically(&path, doc.urdf.as_bytes())?;
    Ok(path)
}
