//! Graspable objects: a closed mesh with mass properties and friction.
//!
//! Any object becomes an [`ObjectModel`] through [`ObjectModel::from_mesh`]. On disk an object is
//! "a mesh + a small metadata file": [`ObjectModel::load`] takes either the JSON metadata
//! ([`ObjectMetadata`], whose `mesh` key names the mesh relative to it) or the mesh itself
//! (`.stl` / `.obj`) with the metadata beside it under the same stem (`mug.stl` + `mug.json`):
//!
//! ```json
//! {"name": "mug", "mesh": "mug.stl", "mass": 0.35, "friction": 0.5, "scale": 0.001}
//! ```
//!
//! `scale` (default 1) converts the mesh's units to metres (0.001 for a mesh in millimetres).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{CoreError, Result};
use crate::model::{Geometry, Inertial, Shape, TriangleMesh};
use crate::scene::SceneObject;
use crate::spec_file;

/// Largest mesh file [`ObjectModel::load`] reads (256 MiB).
pub const MAX_MESH_BYTES: u64 = 256 << 20;

/// A graspable rigid object: closed triangle mesh, mass properties and friction.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectModel {
    /// Unique name (`salt_can`, `white_cup`, ...).
    pub name: String,
    /// Closed, outward-oriented surface in the object frame (m).
    pub mesh: Arc<TriangleMesh>,
    /// Mass (kg), centre of mass and inertia about it (object axes).
    pub inertial: Inertial,
    /// Coulomb friction coefficient against the hand's finger pads.
    pub friction: f64,
}

/// The metadata file of an object on disk (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectMetadata {
    /// Name; default: the file stem.
    #[serde(default)]
    pub name: Option<String>,
    /// The mesh, relative to the metadata file; default: the mesh the object was loaded from.
    #[serde(default)]
    pub mesh: Option<PathBuf>,
    /// Mass (kg), spread uniformly over the enclosed volume.
    pub mass: f64,
    /// Coulomb friction coefficient against the finger pads.
    pub friction: f64,
    /// Factor from mesh units to metres; default 1.
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

impl ObjectModel {
    /// An object from a closed mesh (e.g. read with [`crate::mesh_io`]), with the mass spread
    /// uniformly over the enclosed volume.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a non-positive or non-finite mass, a negative
    /// friction, or a mesh that is not closed and outward-oriented (its signed volume must be
    /// positive).
    pub fn from_mesh(name: impl Into<String>, mesh: TriangleMesh, mass: f64, friction: f64) -> Result<Self> {
        let bad = |name: &str, reason: String| CoreError::InvalidParameter { name: name.into(), reason };
        if !(mass.is_finite() && mass > 0.0) {
            return Err(bad("mass", format!("must be finite and > 0, got {mass}")));
        }
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(bad("friction", format!("must be finite and >= 0, got {friction}")));
        }
        if !mesh.is_watertight() || mesh.signed_volume() <= 0.0 {
            return Err(bad(
                "mesh",
                format!("must be closed and outward-oriented (signed volume {:e} m³)", mesh.signed_volume()),
            ));
        }
        let (_, com, inertia) = mass_properties(&mesh, mass);
        let inertial = Inertial { origin: Isometry3::translation(com.x, com.y, com.z), mass, inertia };
        Ok(Self { name: name.into(), mesh: Arc::new(mesh), inertial, friction })
    }

    /// Loads an object from its metadata file (`.json`) or from its mesh with the metadata
    /// beside it (see the [module docs](self)).
    ///
    /// # Errors
    /// [`CoreError::Io`] / [`CoreError::FileTooLarge`] for unreadable files,
    /// [`CoreError::MalformedSpec`] for bad metadata (or no mesh named),
    /// [`CoreError::MeshFormat`] and the other mesh reader errors, and those of
    /// [`ObjectModel::from_mesh`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let metadata_path = if is_json { path.to_path_buf() } else { path.with_extension("json") };
        let meta: ObjectMetadata = spec_file::read_json(&metadata_path)?;
        let mesh_path = match (&meta.mesh, is_json) {
            (Some(m), _) => spec_file::relative_to(&metadata_path, m),
            (None, false) => path.to_path_buf(),
            (None, true) => {
                return Err(CoreError::MalformedSpec {
                    path: metadata_path,
                    reason: "missing key `mesh` (the object's mesh file)".into(),
                })
            }
        };
        if !(meta.scale.is_finite() && meta.scale > 0.0) {
            return Err(CoreError::InvalidParameter {
                name: "scale".into(),
                reason: format!("must be finite and > 0, got {}", meta.scale),
            });
        }
        let bytes = spec_file::read_bytes_limited(&mesh_path, MAX_MESH_BYTES)?;
        let mesh = crate::mesh_io::read_mesh(&bytes, &mesh_path)?;
        let mesh = if meta.scale == 1.0 { mesh } else { mesh.scaled(&Vector3::repeat(meta.scale))? };
        let stem = || path.file_stem().map_or_else(|| "object".to_string(), |s| s.to_string_lossy().into_owned());
        Self::from_mesh(meta.name.unwrap_or_else(stem), mesh, meta.mass, meta.friction)
    }

    /// The object's metadata (name, mass, friction; no mesh path, scale 1).
    pub fn metadata(&self) -> ObjectMetadata {
        ObjectMetadata {
            name: Some(self.name.clone()),
            mesh: None,
            mass: self.mass(),
            friction: self.friction,
            scale: 1.0,
        }
    }

    /// Mass (kg).
    pub fn mass(&self) -> f64 {
        self.inertial.mass
    }

    /// Centre of mass in the object frame.
    pub fn center_of_mass(&self) -> Point3<f64> {
        Point3::from(self.inertial.origin.translation.vector)
    }

    /// Axis-aligned size of the mesh (m).
    pub fn size(&self) -> Vector3<f64> {
        let (lo, hi) = self.mesh.aabb();
        hi - lo
    }

    /// The mesh as a shape at the object origin.
    pub fn shape(&self) -> Shape {
        Shape::at_origin(Geometry::Mesh(self.mesh.clone()))
    }

    /// The object as a movable scene object at `pose`.
    pub fn to_scene_object(&self, pose: Isometry3<f64>) -> SceneObject {
        SceneObject {
            name: self.name.clone(),
            pose,
            shapes: vec![self.shape()],
            mass: self.inertial.mass,
            center_of_mass: self.center_of_mass(),
            inertia: self.inertial.inertia,
            friction: self.friction,
        }
    }
}

/// Mass properties of a closed, outward-oriented mesh of uniform density and total `mass`:
/// `(volume, centre of mass, inertia about the centre of mass)`.
pub fn mass_properties(mesh: &TriangleMesh, mass: f64) -> (f64, Point3<f64>, Matrix3<f64>) {
    let canonical = Matrix3::new(2.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 2.0) / 120.0;
    let mut cov = Matrix3::zeros();
    let mut vol = 0.0;
    let mut first = Vector3::zeros();
    let v = mesh.vertices();
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| v[i as usize].coords);
        let am = Matrix3::from_columns(&[a, b, c]);
        let det = am.determinant();
        cov += am * canonical * am.transpose() * det;
        vol += det / 6.0;
        first += (a + b + c) * (det / 24.0);
    }
    let com = first / vol;
    let cov_c = cov - com * com.transpose() * vol;
    let density = mass / vol;
    let inertia = (Matrix3::identity() * cov_c.trace() - cov_c) * density;
    (vol, Point3::from(com), (inertia + inertia.transpose()) * 0.5)
}
