//! The kitchen objects of the KIT ObjectModels set used by the OpenGRASP benchmarks
//! (seed paper, Fig. 2), as procedural triangle meshes with real-world sizes and masses.
//!
//! Every object frame has its origin at the centre of the bottom face (the object stands on
//! `z = 0`), +z up and, for objects with a handle, the handle towards +x.

use nalgebra::{Matrix3, Point3, Vector3};
use opengrasp_core::model::TriangleMesh;

use crate::error::{AssetError, Result};
use crate::mesh::{box_shell, circle_ring, handle_shell, lathe, superellipse_ring, MeshBuilder};

/// Segments of every circle of revolution (a multiple of 4, so bounding boxes are exact).
const SEGMENTS: usize = 48;

pub use opengrasp_core::object::ObjectModel;

/// Names of the stock objects, in the order of [`all`].
pub const NAMES: [&str; 9] = [
    "bread_box",
    "chocolate_box",
    "salt_box",
    "salt_can",
    "detergent_bottle",
    "spray_bottle",
    "white_cup",
    "green_cup",
    "measuring_cup",
];

/// All nine stock objects (see the crate docs for their dimensions and sources).
pub fn all() -> Vec<ObjectModel> {
    NAMES.iter().filter_map(|n| by_name(n).ok()).collect()
}

/// One stock object by name (see [`NAMES`]).
///
/// # Errors
/// [`AssetError::UnknownAsset`] for an unknown name.
pub fn by_name(name: &str) -> Result<ObjectModel> {
    let (mesh, mass, friction) = match name {
        "bread_box" => (bread_box()?, 0.50, 0.6),
        "chocolate_box" => (chocolate_box()?, 0.10, 0.5),
        "salt_box" => (salt_box()?, 0.52, 0.5),
        "salt_can" => (salt_can()?, 0.55, 0.5),
        "detergent_bottle" => (detergent_bottle()?, 1.10, 0.4),
        "spray_bottle" => (spray_bottle()?, 0.55, 0.4),
        "white_cup" => (cup(0.041, 0.095, 0.004, 0.006, 0.050, 0.028, 0.0055)?, 0.32, 0.5),
        "green_cup" => (cup(0.0375, 0.088, 0.004, 0.006, 0.046, 0.025, 0.005)?, 0.27, 0.5),
        "measuring_cup" => (measuring_cup()?, 0.12, 0.4),
        _ => return Err(AssetError::UnknownAsset { kind: "object", name: name.to_string() }),
    };
    Ok(ObjectModel::from_mesh(name, mesh, mass, friction)?)
}

/// Bread box: 245 × 125 × 95 mm rounded carton.
fn bread_box() -> Result<TriangleMesh> {
    let rings = [superellipse_ring(0.1225, 0.0625, 8.0, 0.0, 64), superellipse_ring(0.1225, 0.0625, 8.0, 0.095, 64)];
    let mut m = MeshBuilder::new();
    m.ring_stack(&rings);
    m.build()
}

/// Prismatic chocolate box: triangular prism 210 mm long (x), equilateral section of 40 mm side.
fn chocolate_box() -> Result<TriangleMesh> {
    let (len, side) = (0.21, 0.04);
    let h = side * 3f64.sqrt() / 2.0;
    let ring = |x: f64| vec![Point3::new(x, -side / 2.0, 0.0), Point3::new(x, side / 2.0, 0.0), Point3::new(x, 0.0, h)];
    let mut m = MeshBuilder::new();
    m.ring_stack(&[ring(-len / 2.0), ring(len / 2.0)]);
    m.build()
}

/// Rectangular salt box: 95 × 60 × 135 mm.
fn salt_box() -> Result<TriangleMesh> {
    let mut m = MeshBuilder::new();
    box_shell(&mut m, Vector3::new(0.095, 0.06, 0.135), Vector3::zeros());
    m.build()
}

/// Cylindrical salt can: Ø 80 mm × 140 mm with a slightly bevelled lid.
fn salt_can() -> Result<TriangleMesh> {
    lathe(&[(0.038, 0.0), (0.04, 0.002), (0.04, 0.136), (0.038, 0.14)], SEGMENTS).build()
}

/// Detergent bottle: rounded body 120 × 75 mm, shoulders tapering to a Ø 36 mm neck and
/// cap (total height 260 mm), a grip handle on +x between 107 and 193 mm.
fn detergent_bottle() -> Result<TriangleMesh> {
    let n = 64;
    let (a, b) = (0.06, 0.0375);
    let mut rings = vec![superellipse_ring(a - 0.003, b - 0.003, 4.0, 0.0, n), superellipse_ring(a, b, 4.0, 0.004, n)];
    rings.push(superellipse_ring(a, b, 4.0, 0.200, n));
    // Shoulder: blend to a circle of radius 18 mm.
    for k in 1..=4 {
        let t = k as f64 / 4.0;
        let e = 4.0 + (2.0 - 4.0) * t;
        let r = |v: f64| v + (0.018 - v) * t;
        rings.push(superellipse_ring(r(a), r(b), e, 0.200 + 0.030 * t, n));
    }
    rings.push(circle_ring(0.018, 0.260, n));
    let mut m = MeshBuilder::new();
    m.ring_stack(&rings);
    handle_shell(&mut m, a, 0.150, 0.035, 0.008, 0.004);
    m.build()
}

/// Spray bottle: body 95 × 60 × 200 mm, neck, and a trigger head reaching 290 mm with its
/// nozzle pointing towards +x.
fn spray_bottle() -> Result<TriangleMesh> {
    let n = 48;
    let rings = vec![
        superellipse_ring(0.0455, 0.0285, 3.0, 0.0, n),
        superellipse_ring(0.0475, 0.03, 3.0, 0.003, n),
        superellipse_ring(0.0475, 0.03, 3.0, 0.170, n),
        superellipse_ring(0.030, 0.022, 2.5, 0.195, n),
        circle_ring(0.015, 0.205, n),
        circle_ring(0.015, 0.235, n),
    ];
    let mut m = MeshBuilder::new();
    m.ring_stack(&rings);
    // Trigger head (separate closed shell overlapping the neck).
    box_shell(&mut m, Vector3::new(0.085, 0.030, 0.060), Vector3::new(0.0125, 0.0, 0.230));
    m.build()
}

/// A ceramic cup: outer radius `r`, height `h`, wall and bottom thickness, a handle centred at
/// height `zc` with arc radius `arc` and tube radius `tube`.
fn cup(r: f64, h: f64, wall: f64, bottom: f64, zc: f64, arc: f64, tube: f64) -> Result<TriangleMesh> {
    let ri = r - wall;
    let mut m =
        lathe(&[(r - 0.002, 0.0), (r, 0.002), (r, h), (ri, h), (ri, bottom + 0.003), (ri - 0.003, bottom)], SEGMENTS);
    handle_shell(&mut m, r, zc, arc, tube, wall / 2.0);
    m.build()
}

/// Measuring cup: straight plastic jug Ø 100 mm, 120 mm high, 2.5 mm wall, with a handle.
fn measuring_cup() -> Result<TriangleMesh> {
    let (r, h, wall) = (0.05, 0.12, 0.0025);
    let mut m = lathe(&[(r, 0.0), (r, h), (r - wall, h), (r - wall, 0.003)], SEGMENTS);
    handle_shell(&mut m, r, 0.065, 0.035, 0.006, 0.0012);
    m.build()
}

/// Inertia of a closed mesh scaled to `mass`, exposed for user meshes.
pub fn mesh_inertia(mesh: &TriangleMesh, mass: f64) -> (Point3<f64>, Matrix3<f64>) {
    let (_, com, inertia) = opengrasp_core::object::mass_properties(mesh, mass);
    (com, inertia)
}
