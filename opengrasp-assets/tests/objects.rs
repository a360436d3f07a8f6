//! Stock objects: closed, outward-oriented, documented sizes, physical mass properties.

use opengrasp_assets::objects;

/// Documented bounding-box sizes (x, y, z) in mm, see the crate docs.
const SIZES_MM: [(&str, [f64; 3]); 9] = [
    ("bread_box", [245.0, 125.0, 95.0]),
    ("chocolate_box", [210.0, 40.0, 34.641]),
    ("salt_box", [95.0, 60.0, 135.0]),
    ("salt_can", [80.0, 80.0, 140.0]),
    ("detergent_bottle", [163.0, 75.0, 260.0]),
    ("spray_bottle", [102.5, 60.0, 290.0]),
    ("white_cup", [115.5, 82.0, 95.0]),
    ("green_cup", [105.0, 75.0, 88.0]),
    ("measuring_cup", [141.0, 100.0, 120.0]),
];

#[test]
fn every_object_is_closed_outward_and_non_degenerate() {
    let all = objects::all();
    assert_eq!(all.len(), 9);
    for o in &all {
        assert!(o.mesh.is_watertight(), "{} not watertight", o.name);
        assert!(o.mesh.signed_volume() > 0.0, "{} inward", o.name);
        let v = o.mesh.vertices();
        let min_area = o
            .mesh
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| v[i as usize]);
                (b - a).cross(&(c - a)).norm() * 0.5
            })
            .fold(f64::INFINITY, f64::min);
        assert!(min_area > 1e-10, "{} has a sliver of {min_area} m²", o.name);
    }
}

#[test]
fn bounding_boxes_match_documented_sizes() {
    for (name, mm) in SIZES_MM {
        let o = objects::by_name(name).unwrap();
        let s = o.size() * 1000.0;
        for k in 0..3 {
            assert!((s[k] - mm[k]).abs() < 1.0, "{name} axis {k}: {} mm vs {} mm", s[k], mm[k]);
        }
        let (lo, _) = o.mesh.aabb();
        assert!(lo.z.abs() < 1e-12, "{name} must stand on z = 0");
    }
}

#[test]
fn mass_properties_are_physical() {
    for o in objects::all() {
        assert!(o.inertial.is_physical(), "{}", o.name);
        let (lo, hi) = o.mesh.aabb();
        let c = o.center_of_mass();
        for k in 0..3 {
            assert!(c[k] > lo[k] && c[k] < hi[k], "{} centre of mass outside its box", o.name);
        }
        assert!(o.friction > 0.0);
    }
}

#[test]
fn solid_box_inertia_matches_the_analytic_value() {
    let o = objects::by_name("salt_box").unwrap();
    let (m, x, y, z) = (0.52, 0.095, 0.06, 0.135);
    let expect = [m * (y * y + z * z) / 12.0, m * (x * x + z * z) / 12.0, m * (x * x + y * y) / 12.0];
    for (k, e) in expect.iter().enumerate() {
        assert!((o.inertial.inertia[(k, k)] - e).abs() < 1e-12, "{k}");
    }
    assert!((o.center_of_mass().z - z / 2.0).abs() < 1e-12);
    assert!(o.inertial.inertia[(0, 1)].abs() < 1e-12);
}

#[test]
fn cup_is_hollow_with_a_through_handle() {
    let cup = objects::by_name("white_cup").unwrap();
    let solid = std::f64::consts::PI * 0.041 * 0.041 * 0.095;
    // Ceramic shell: far less volume than the solid cylinder it fills.
    assert!(cup.mesh.signed_volume() < 0.4 * solid);
    // A ray along y through the handle opening (x between wall and handle) hits no triangle.
    let x = 0.041 + 0.014;
    let z = 0.050;
    let v = cup.mesh.vertices();
    let hits = cup
        .mesh
        .triangles()
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| v[i as usize]);
            // Project onto the x-z plane and test point-in-triangle.
            let s =
                |p: nalgebra::Point3<f64>, q: nalgebra::Point3<f64>| (q.x - p.x) * (z - p.z) - (q.z - p.z) * (x - p.x);
            let (d1, d2, d3) = (s(a, b), s(b, c), s(c, a));
            (d1 > 0.0 && d2 > 0.0 && d3 > 0.0) || (d1 < 0.0 && d2 < 0.0 && d3 < 0.0)
        })
        .count();
    assert_eq!(hits, 0);
}

#[test]
fn unknown_and_invalid_objects_are_errors() {
    assert!(matches!(objects::by_name("teapot"), Err(opengrasp_assets::AssetError::UnknownAsset { .. })));
    let mesh = objects::by_name("salt_can").unwrap().mesh.as_ref().clone();
    assert!(objects::ObjectModel::from_mesh("mine", mesh.clone(), -1.0, 0.5).is_err());
    assert!(objects::ObjectModel::from_mesh("mine", mesh.clone(), 1.0, f64::NAN).is_err());
    let mine = objects::ObjectModel::from_mesh("mine", mesh, 2.0, 0.3).unwrap();
    assert_eq!(mine.mass(), 2.0);
}

#[test]
fn generation_is_deterministic() {
    assert_eq!(objects::all(), objects::all());
}

mod builders {
    use nalgebra::Vector3;
    use opengrasp_assets::mesh::{handle_shell, lathe, superellipse_ring, MeshBuilder};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Superellipse prisms: closed, outward, exact bounding box and (for e = 2) the
        /// ellipse area within the polygon error.
        #[test]
        fn superellipse_prisms_are_closed_with_exact_boxes(
            a in 0.01f64..0.3, b in 0.01f64..0.3, e in 2.0f64..10.0, h in 0.01f64..0.5,
        ) {
            let mut m = MeshBuilder::new();
            m.ring_stack(&[superellipse_ring(a, b, e, 0.0, 64), superellipse_ring(a, b, e, h, 64)]);
            let mesh = m.build().unwrap();
            prop_assert!(mesh.is_watertight());
            prop_assert!(mesh.signed_volume() > 0.0);
            let (lo, hi) = mesh.aabb();
            prop_assert!(((hi - lo) - Vector3::new(2.0 * a, 2.0 * b, h)).norm() < 1e-12);
            if e == 2.0 {
                let ellipse = std::f64::consts::PI * a * b * h;
                prop_assert!((mesh.signed_volume() - ellipse).abs() < 0.01 * ellipse);
            }
        }

        /// Cups of any proportions with a handle: two closed shells, outward, hollow.
        #[test]
        fn hollow_cups_with_handles_are_closed(
            r in 0.03f64..0.08, h in 0.05f64..0.2, wall in 0.003f64..0.008,
        ) {
            let ri = r - wall;
            let mut m = lathe(&[(r, 0.0), (r, h), (ri, h), (ri, wall)], 48);
            let arc = 0.3 * h;
            handle_shell(&mut m, r, h / 2.0, arc, 0.15 * arc, wall / 2.0);
            let mesh = m.build().unwrap();
            prop_assert!(mesh.is_watertight());
            let solid = std::f64::consts::PI * r * r * h;
            let v = mesh.signed_volume();
            prop_assert!(v > 0.0 && v < solid);
            let (lo, hi) = mesh.aabb();
            prop_assert!((hi.x - (r + arc + 0.15 * arc)).abs() < 1e-12);
            prop_assert!((lo.x + r).abs() < 1e-12);
        }
    }
}
