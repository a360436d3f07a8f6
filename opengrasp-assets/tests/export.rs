//! Export: URDF files re-load through core to the same models, meshes and the kitchen OBJ
//! re-read, output is byte-for-byte deterministic.

use opengrasp_assets::{export, hands, objects, robots};
use opengrasp_core::{mesh_io, urdf};

/// Same surface (readers may renumber vertices): triangle count, enclosed volume and box.
fn same_mesh(a: &opengrasp_core::model::TriangleMesh, b: &opengrasp_core::model::TriangleMesh, name: &str) {
    assert_eq!(a.triangles().len(), b.triangles().len(), "{name}");
    assert!(a.is_watertight(), "{name}");
    assert!((a.signed_volume() - b.signed_volume()).abs() < 1e-12, "{name}");
    let ((alo, ahi), (blo, bhi)) = (a.aabb(), b.aabb());
    assert!((alo - blo).norm() < 1e-12 && (ahi - bhi).norm() < 1e-12, "{name}");
}

#[test]
fn export_writes_reloadable_urdfs_and_meshes() {
    let dir = std::env::temp_dir().join(format!("opengrasp_assets_export_{}", std::process::id()));
    let report = export::export_to(&dir).unwrap();
    assert_eq!(report.urdfs.len(), 1 + 3 + 9);
    assert_eq!(report.meshes.len(), 2 * 9);
    assert_eq!(report.srdfs.len(), 1 + 3);
    let mut armar = urdf::load_file(&report.urdfs[0]).unwrap();
    let stock = robots::armar3();
    // URDF + SRDF: the same joint groups and allowed-collision matrix as the stock model.
    let srdf = opengrasp_core::srdf::Srdf::load_file(&report.srdfs[0]).unwrap();
    let applied = srdf.apply(&mut armar).unwrap();
    assert_eq!(applied.groups.len(), stock.groups().len());
    assert_eq!(armar.groups(), stock.groups());
    let pairs = |r: &opengrasp_core::model::Robot| {
        let mut p: Vec<_> = r.allowed_collision_pairs().collect();
        p.sort();
        p
    };
    assert_eq!(pairs(&armar), pairs(&stock));
    assert!(armar.group("hip_right_arm").is_ok());
    assert_eq!(armar.dof(), stock.dof());
    assert_eq!(armar.links().len(), stock.links().len());
    let names: Vec<&str> = armar.joints().iter().map(|j| j.name.as_str()).collect();
    let stock_names: Vec<&str> = stock.joints().iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, stock_names);
    let hands = [hands::barrett(), hands::armar3_hand(), hands::sdh()];
    for ((path, srdf), hand) in report.urdfs[1..4].iter().zip(&report.srdfs[1..]).zip(hands) {
        let mut r = urdf::load_file(path).unwrap();
        assert_eq!(r.dof(), hand.robot().dof());
        assert_eq!(r.links().len(), hand.robot().links().len());
        opengrasp_core::srdf::Srdf::load_file(srdf).unwrap().apply(&mut r).unwrap();
        assert_eq!(pairs(&r), pairs(hand.robot()), "{}", path.display());
        assert_eq!(r.groups(), hand.robot().groups());
    }
    // Objects: exact OBJ meshes inside the URDFs, and stand-alone OBJs, read back identically.
    for (path, o) in report.urdfs[4..].iter().zip(objects::all()) {
        let r = urdf::load_file(path).unwrap();
        let link = &r.links()[0];
        let opengrasp_core::model::Geometry::Mesh(m) = &link.collisions[0].geometry else {
            panic!("{} lost its mesh", o.name)
        };
        same_mesh(m, &o.mesh, &o.name);
        let i = link.inertial.as_ref().unwrap();
        assert!((i.mass - o.mass()).abs() < 1e-12);
        assert!((i.inertia - o.inertial.inertia).norm() < 1e-12);
        let obj = std::fs::read(dir.join("objects").join(format!("{}.obj", o.name))).unwrap();
        same_mesh(&mesh_io::read_obj(&obj).unwrap(), &o.mesh, &o.name);
    }
    let kitchen = std::fs::read(&report.kitchen_obj).unwrap();
    let parts = mesh_io::read_obj_objects(&kitchen).unwrap();
    assert!(parts.iter().any(|(n, _)| n == "salt_can"));
    assert!(parts.iter().any(|(n, _)| n.starts_with("armar3/right_hand_")));
    assert!(parts.iter().all(|(_, m)| m.is_watertight()));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn kitchen_obj_is_deterministic_and_complete() {
    let a = export::kitchen_obj().unwrap();
    assert_eq!(a, export::kitchen_obj().unwrap());
    let summary = export::obj_summary(&a);
    let k = opengrasp_assets::scenes::kitchen().unwrap();
    let shapes: usize = k.scene.bodies().iter().map(|b| b.shapes.len()).sum::<usize>()
        + k.scene.objects().len()
        + k.scene.robots()[0].robot.links().iter().map(|l| l.collisions.len()).sum::<usize>();
    assert_eq!(summary.len(), shapes);
    assert!(summary.iter().all(|(_, n)| *n >= 4));
}
