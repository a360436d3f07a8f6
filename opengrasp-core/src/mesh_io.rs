//! Reading and writing triangle meshes: STL (binary and ASCII, via `stl_io`) and Wavefront OBJ
//! (via `tobj`); reading COLLADA `.dae` (via openrr's `mesh-loader`), the usual ROS visual
//! format.
//!
//! Readers return indexed [`TriangleMesh`]es: identical vertex positions are welded (STL has no
//! index at all; OBJ files often split vertices by normal or texture coordinate), so closed
//! meshes pass [`TriangleMesh::is_watertight`]. Zero-area faces, common in files exported from
//! CAD tools, are dropped ([`TriangleMesh::new_dropping_degenerate`]).
//!
//! ```
//! use opengrasp_core::mesh_io;
//! # use opengrasp_core::model::TriangleMesh;
//! # use opengrasp_core::nalgebra::Point3;
//! # fn main() -> opengrasp_core::Result<()> {
//! # let tetra = TriangleMesh::new(
//! #     vec![Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0), Point3::new(0.0, 0.0, 1.0)],
//! #     vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
//! # )?;
//! let bytes = mesh_io::write_stl_binary(&tetra);
//! let back = mesh_io::read_stl(&bytes)?;
//! assert_eq!(back.vertices().len(), 4);
//! assert!(back.is_watertight());
//! # Ok(())
//! # }
//! ```

use std::collections::HashMap;
use std::io::{BufReader, Cursor};
use std::path::Path;

use nalgebra::Point3;

use crate::error::{CoreError, Result};
use crate::model::TriangleMesh;

/// A mesh file format this module reads and writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// STL: binary or ASCII when reading, binary when writing (vertices stored as `f32`).
    #[default]
    Stl,
    /// Wavefront OBJ (vertices written and read as exact `f64` text).
    Obj,
}

impl MeshFormat {
    /// The format implied by a file name's extension (case-insensitive), if supported.
    pub fn from_path(path: impl AsRef<Path>) -> Option<Self> {
        let ext = path.as_ref().extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Self::Stl),
            "obj" => Some(Self::Obj),
            _ => None,
        }
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Stl => "stl",
            Self::Obj => "obj",
        }
    }
}

/// Reads a mesh file's bytes, choosing the decoder from `path`'s extension (`.stl`, `.obj` or
/// `.dae`, case-insensitive). `path` is only used to pick the format and to name the file in
/// errors.
///
/// # Errors
/// [`CoreError::MeshFormat`] for an unsupported extension or undecodable bytes;
/// [`CoreError::DegenerateMesh`] if no usable triangle remains.
pub fn read_mesh(bytes: &[u8], path: impl AsRef<Path>) -> Result<TriangleMesh> {
    let path = path.as_ref();
    match MeshFormat::from_path(path) {
        Some(MeshFormat::Stl) => read_stl_at(bytes, path),
        Some(MeshFormat::Obj) => merge_objects(read_obj_objects_at(bytes, path)?),
        None if is_collada(path) => read_collada_at(bytes, path),
        None => Err(CoreError::MeshFormat {
            path: path.to_path_buf(),
            reason: "unsupported mesh format (expected .stl, .obj or .dae)".to_string(),
        }),
    }
}

/// Reads a binary or ASCII STL file, welding identical vertices into an indexed mesh.
///
/// # Errors
/// [`CoreError::MeshFormat`] if the bytes are not STL; [`CoreError::DegenerateMesh`] if no
/// triangle with non-zero area remains.
pub fn read_stl(bytes: &[u8]) -> Result<TriangleMesh> {
    read_stl_at(bytes, Path::new("<stl bytes>"))
}

/// Reads a Wavefront OBJ file, merging all its objects into one mesh (objects are concatenated,
/// not welded to each other). Polygons are triangulated as fans; points, lines, normals,
/// texture coordinates and materials are ignored. Within each object, vertices are welded by
/// position and numbered in order of first use by the faces.
///
/// # Errors
/// [`CoreError::MeshFormat`] if the text cannot be parsed; [`CoreError::DegenerateMesh`] if no
/// triangle with non-zero area remains.
pub fn read_obj(bytes: &[u8]) -> Result<TriangleMesh> {
    merge_objects(read_obj_objects_at(bytes, Path::new("<obj bytes>"))?)
}

/// Reads a Wavefront OBJ file as separate named objects (`o`/`g` statements), in file order.
/// Objects without any non-degenerate triangle are skipped.
///
/// # Errors
/// [`CoreError::MeshFormat`] if the text cannot be parsed; [`CoreError::DegenerateMesh`] if no
/// object has a usable triangle.
pub fn read_obj_objects(bytes: &[u8]) -> Result<Vec<(String, TriangleMesh)>> {
    read_obj_objects_at(bytes, Path::new("<obj bytes>"))
}

fn is_collada(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("dae"))
}

/// Reads a COLLADA (`.dae`) document as one mesh: every `<geometry>` of the document, each
/// placed by the transforms of the `<node>` that instances it (`<matrix>`, `<translate>`,
/// `<rotate>`, `<scale>`) and scaled by `<asset><unit meter>`, concatenated (welded by
/// position within each geometry). `up_axis` is ignored, as ROS tools do; a geometry instanced
/// by several nodes is placed once, by the last. Known limit of the reader (mesh-loader 0.1):
/// with nested nodes, or a unit other than 1 together with node translations, transforms are
/// composed in reverse order (parent before child, unit before translation), so such files
/// load displaced; ROS exports (one level, metres) are unaffected. Lines, normals, texture coordinates and
/// materials are ignored; zero-area faces are dropped.
///
/// The text is first checked against the default [`crate::urdf::XmlLimits`], so a deeply
/// nested hostile file is rejected before the parser's recursion sees it. A parser panic on an
/// inconsistent document (out-of-range accessor, unsupported reference) is caught and reported
/// as an error.
///
/// # Errors
/// [`CoreError::LimitExceeded`] for hostile input; [`CoreError::MeshFormat`] if the bytes are
/// not COLLADA; [`CoreError::DegenerateMesh`] if no triangle with non-zero area remains.
pub fn read_collada(bytes: &[u8]) -> Result<TriangleMesh> {
    read_collada_at(bytes, Path::new("<collada bytes>"))
}

fn read_collada_at(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let format_err = |reason: String| CoreError::MeshFormat { path: path.to_path_buf(), reason };
    crate::urdf::check_xml(bytes, &crate::urdf::XmlLimits::default(), "collada", format_err)?;
    // mesh-loader asserts on some inconsistent documents; a panic there must not take the
    // caller down (bad input never panics out of this crate).
    let scene = std::panic::catch_unwind(|| mesh_loader::collada::from_slice(bytes))
        .map_err(|_| format_err("inconsistent COLLADA document (reader failed)".to_string()))?
        .map_err(|e| format_err(e.to_string()))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for mesh in &scene.meshes {
        let mut welder = Welder::default();
        for face in &mesh.faces {
            let mut t = [[0.0; 3]; 3];
            for (k, &i) in face.iter().enumerate() {
                let v = mesh
                    .vertices
                    .get(i as usize)
                    .ok_or_else(|| format_err(format!("face index {i} out of range in geometry `{}`", mesh.name)))?;
                t[k] = v.map(f64::from);
            }
            welder.triangle(t, path)?;
        }
        let offset =
            u32::try_from(vertices.len()).map_err(|_| format_err("more than u32::MAX vertices".to_string()))?;
        vertices.extend(welder.vertices);
        triangles.extend(welder.triangles.into_iter().map(|t| t.map(|i| i + offset)));
    }
    if triangles.is_empty() {
        return Err(CoreError::DegenerateMesh { reason: format!("{} has no triangles", path.display()) });
    }
    TriangleMesh::new_dropping_degenerate(vertices, triangles)
}

/// Encodes a mesh as binary STL (vertices rounded to `f32`, face normals from the geometry).
pub fn write_stl_binary(mesh: &TriangleMesh) -> Vec<u8> {
    let tris = mesh.triangles();
    let mut out = Vec::with_capacity(84 + 50 * tris.len());
    let mut header = [0u8; 80];
    let tag = b"binary STL written by opengrasp-core";
    header[..tag.len()].copy_from_slice(tag);
    out.extend_from_slice(&header);
    // A mesh with more than u32::MAX triangles cannot exist in memory on supported targets.
    out.extend_from_slice(&(u32::try_from(tris.len()).unwrap_or(u32::MAX)).to_le_bytes());
    let v = mesh.vertices();
    for t in tris {
        let [a, b, c] = t.map(|i| v[i as usize]);
        let n = (b - a).cross(&(c - a)).try_normalize(0.0).unwrap_or_default();
        for p in [n.x, n.y, n.z, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z] {
            out.extend_from_slice(&(p as f32).to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// Writes several named meshes into one Wavefront OBJ text (one `o` statement each, face
/// indices offset so each object refers to its own vertices). Coordinates are written with
/// shortest round-trip formatting, so [`read_obj`] gives back the exact `f64` values. Whitespace
/// in names is replaced by `_`; an empty name becomes `object`.
pub fn write_obj(objects: &[(&str, &TriangleMesh)]) -> String {
    use std::fmt::Write as _;
    let mut out = String::from("# written by opengrasp-core\n");
    let mut offset = 1usize;
    for (name, mesh) in objects {
        let _ = writeln!(out, "o {}", sanitize_obj_name(name));
        for v in mesh.vertices() {
            let _ = writeln!(out, "v {:?} {:?} {:?}", v.x, v.y, v.z);
        }
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|i| i as usize + offset);
            let _ = writeln!(out, "f {a} {b} {c}");
        }
        offset += mesh.vertices().len();
    }
    out
}

fn sanitize_obj_name(name: &str) -> String {
    let s: String = name.chars().map(|c| if c.is_whitespace() || c.is_control() { '_' } else { c }).collect();
    if s.is_empty() {
        "object".to_string()
    } else {
        s
    }
}

/// Welds bit-identical positions (`-0.0` and `0.0` count as equal), numbering vertices in order
/// of first use.
#[derive(Default)]
struct Welder {
    index: HashMap<[u64; 3], u32>,
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
}

impl Welder {
    fn vertex(&mut self, p: [f64; 3], path: &Path) -> Result<u32> {
        // Adding 0.0 turns -0.0 into 0.0 so both weld together.
        let key = p.map(|c| (c + 0.0).to_bits());
        if let Some(&i) = self.index.get(&key) {
            return Ok(i);
        }
        let i = u32::try_from(self.vertices.len()).map_err(|_| CoreError::MeshFormat {
            path: path.to_path_buf(),
            reason: "more than u32::MAX vertices".to_string(),
        })?;
        self.index.insert(key, i);
        self.vertices.push(Point3::new(p[0], p[1], p[2]));
        Ok(i)
    }

    fn triangle(&mut self, t: [[f64; 3]; 3], path: &Path) -> Result<()> {
        let tri = [self.vertex(t[0], path)?, self.vertex(t[1], path)?, self.vertex(t[2], path)?];
        self.triangles.push(tri);
        Ok(())
    }

    fn finish(self) -> Result<TriangleMesh> {
        TriangleMesh::new_dropping_degenerate(self.vertices, self.triangles)
    }
}

fn read_stl_at(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let format_err = |e: std::io::Error| CoreError::MeshFormat { path: path.to_path_buf(), reason: e.to_string() };
    let mut cursor = Cursor::new(bytes);
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(format_err)?;
    let mut welder = Welder::default();
    for tri in reader {
        let tri = tri.map_err(format_err)?;
        let t = tri.vertices.map(|v| [f64::from(v[0]), f64::from(v[1]), f64::from(v[2])]);
        welder.triangle(t, path)?;
    }
    welder.finish()
}

fn read_obj_objects_at(bytes: &[u8], path: &Path) -> Result<Vec<(String, TriangleMesh)>> {
    // The update syntax keeps this compiling if optional tobj features add fields.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = BufReader::new(Cursor::new(bytes));
    // Materials are irrelevant for geometry: report every material library as unavailable.
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| CoreError::MeshFormat { path: path.to_path_buf(), reason: e.to_string() })?;
    let mut objects = Vec::with_capacity(models.len());
    let mut last_error = None;
    for model in models {
        let mesh = &model.mesh;
        let pos = &mesh.positions;
        let mut welder = Welder::default();
        for tri in mesh.indices.chunks_exact(3) {
            let mut t = [[0.0; 3]; 3];
            for (k, &i) in tri.iter().enumerate() {
                let i = i as usize * 3;
                let p = pos.get(i..i + 3).ok_or_else(|| CoreError::MeshFormat {
                    path: path.to_path_buf(),
                    reason: format!("face index out of range in object `{}`", model.name),
                })?;
                t[k] = [p[0], p[1], p[2]];
            }
            welder.triangle(t, path)?;
        }
        if welder.triangles.is_empty() {
            continue;
        }
        match welder.finish() {
            Ok(m) => objects.push((model.name, m)),
            Err(e) => last_error = Some(e),
        }
    }
    if objects.is_empty() {
        return Err(last_error
            .unwrap_or_else(|| CoreError::DegenerateMesh { reason: format!("{} has no triangles", path.display()) }));
    }
    Ok(objects)
}

/// Concatenates objects into one mesh (indices offset, no welding across objects).
fn merge_objects(mut objects: Vec<(String, TriangleMesh)>) -> Result<TriangleMesh> {
    if objects.len() == 1 {
        if let Some((_, mesh)) = objects.pop() {
            return Ok(mesh);
        }
    }
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (_, m) in &objects {
        let offset = u32::try_from(vertices.len())
            .map_err(|_| CoreError::DegenerateMesh { reason: "more than u32::MAX vertices".to_string() })?;
        vertices.extend_from_slice(m.vertices());
        triangles.extend(m.triangles().iter().map(|t| t.map(|i| i + offset)));
    }
    TriangleMesh::new(vertices, triangles)
}
