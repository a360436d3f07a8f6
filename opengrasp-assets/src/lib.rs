//! # opengrasp-assets
//!
//! The standard world of the OpenGRASP benchmarks, shipped inside the crate and generated
//! deterministically at load time (no files, no network; the same numbers every time):
//!
//! * [`robots::armar3`] — an ARMAR-III-like humanoid: holonomic platform as base joints
//!   (`base_x`, `base_y`, `base_yaw`), `hip_yaw`, torso and head, two 7-DoF arms (3 shoulder,
//!   1 elbow, 3 wrist) with an ARMAR-III hand on each wrist, joint groups `right_arm`,
//!   `hip_right_arm`, `base_hip_right_arm` (the motion benchmarks' groups), `left_arm`,
//!   `right_hand`, `left_hand`, and allowed-collision pairs for links that touch by design;
//! * [`hands`] — the Barrett BH8-262, the ARMAR-III five-finger hand and the Schunk SDH as
//!   floating [`hands::Hand`]s (palm frame, approach direction, preshapes, fingers, closing
//!   velocities, couplings as mimic joints, tactile links);
//! * [`objects`] — the nine KIT ObjectModels kitchen objects of the seed paper's Fig. 2 as
//!   closed, outward-oriented triangle meshes with real sizes, masses, centres of mass,
//!   inertias and friction;
//! * [`scenes::kitchen`] — the kitchen (walls, floor, counter with sink, wall cabinets,
//!   fridge, the red table and green sideboard of "Clean the Table") with the objects and the
//!   humanoid at named locations, and [`scenes::table_top`] for grasp benchmarks;
//! * [`export`] — URDF (with SRDF for groups and allowed collisions), STL and OBJ files of all
//!   of it for other tools (any URDF viewer, MuJoCo, MoveIt).
//!
//! Everything stock can be swapped for the user's own: [`objects::ObjectModel::from_mesh`]
//! wraps any closed mesh (e.g. read with `opengrasp_core::mesh_io`), [`hands::Hand::from_robot`]
//! turns any robot (e.g. from `opengrasp_core::urdf::load_file`) into a hand, and scenes are
//! plain `opengrasp_core::scene::Scene`s.
//!
//! ```
//! use std::sync::Arc;
//! use nalgebra::Isometry3;
//! use opengrasp_assets::{hands, objects, robots, scenes};
//! use opengrasp_core::collision::CollisionWorld;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // The humanoid in the kitchen, at its start pose, is collision-free.
//! let kitchen = scenes::kitchen()?;
//! let world = CollisionWorld::new(&kitchen.scene)?;
//! assert!(!world.in_collision(kitchen.robot, &kitchen.start_configuration)?);
//! assert_eq!(robots::armar3().group("hip_right_arm")?.len(), 8);
//!
//! // A grasp benchmark scene: one object on a table, a floating Barrett hand above it.
//! let can = objects::by_name("salt_can")?;
//! assert!((can.size().z - 0.140).abs() < 1e-9);
//! let mut scene = scenes::table_top(&can)?;
//! let barrett = hands::barrett();
//! let above = Isometry3::translation(0.0, 0.0, 1.2) * Isometry3::rotation(nalgebra::Vector3::x() * std::f64::consts::PI);
//! let hand = scene.add_robot("barrett", barrett.robot_arc(), above)?;
//! let q = barrett.preshape_configuration("spherical", &barrett.open_configuration())?;
//! assert!(!CollisionWorld::new(&scene)?.in_collision(hand, &q)?);
//! # Ok(())
//! # }
//! ```
//!
//! ## Dimensions and their sources
//!
//! Values marked *checked* were confirmed against the cited document while writing this
//! crate; *nominal* values are the cited source's figures as commonly quoted (or, for the
//! objects, typical sizes of the product shown in the database) and were not re-measured from
//! the primary document; *design* values are our choice where no public figure exists.
//!
//! | Asset | Quantity | Value | Source | Status |
//! |---|---|---|---|---|
//! | Barrett BH8-262 | fingers / actuators | 3 fingers, 4 motors: F1 and F2 spread synchronously and symmetrically about the palm, one motor per finger driving both finger joints through the TorqueSwitch | Barrett BH8-Series User Manual (doc. D3000) and support wiki, `support.barrett.com/wiki/Hand/280/SystemComponentList` | checked |
//! | Barrett BH8-262 | joint ranges | spread 0–180°, inner joint 0–140°, outer joint 0–48° (coupling 48/140) | BH8-Series User Manual, joint specifications | nominal |
//! | Barrett BH8-262 | joint efforts (simulation) | per motor: flexion 5 N m (shared by the inner and outer joint, 4.47 and 1.53 N m, where coupled actuators are simulated: `PhysicsOptions::coupled_actuators`, on in the grasp physics check); spread 50 N m (25 N m per spread joint when shared), standing for its non-back-drivable worm drive (holds its angle under contact loads) | BH8-Series User Manual (worm-gear drives); efforts are modelling choices | design |
//! | Barrett BH8-262 | palm, links | palm Ø 90 mm × 75 mm, spread axes 25 mm from the centre (DH `Aw`), knuckle 50 mm from spread to flexion axis (DH `A1`; flexion axes 75 mm from the centre, straight fingers of the open hand 132 mm apart — the earlier 25 mm knuckle left 82 mm, narrower than the bread box, so the fingers touched before the palm), inner link 70 mm (`A2`), outer link 58 mm, mass 1.18 kg | BH8-Series manual kinematics (DH table `Aw`, `A1`, `A2`, `A3`); palm collision cylinder r = 45 mm as in the `barrett_model` URDF (jhu-lcsr) | nominal |
//! | Schunk SDH | DoF | 7: coupled rotation of fingers 1 and 3 (0–90°), proximal and distal joint per finger (±90°) | SCHUNK SDH manual / SDHLibrary documentation | nominal |
//! | Schunk SDH | mass, sizes | 1.95 kg; phalanx 86.5 mm (distal 69 mm), fingers on a 66 mm triangle, base Ø 90 × 95 mm | mass: `schunk_description` SDH URDF ("final total mass of 1.95"); lengths: SDH manual | mass checked, lengths nominal |
//! | ARMAR-III | structure | holonomic platform (3 DoF), hip, 7-DoF arms, 8-DoF five-finger fluidic hands | T. Asfour et al., "ARMAR-III: An integrated humanoid platform for sensory-motor control", Humanoids 2006, pp. 169–175 | nominal |
//! | ARMAR-III | arm | upper arm 311 mm, forearm 276 mm; shoulder 1.30 m above the floor | Asfour et al. 2006 (arm kinematics) | nominal |
//! | ARMAR-III | platform, torso | platform Ø 700 mm to 0.45 m, hip column Ø 300 mm, hip at 0.85 m, torso 240 × 320 × 500 mm, head Ø 200 mm | proportions of Asfour et al. 2006, Fig. 1 | design |
//! | ARMAR-III hand | DoF, coupling | 8 actuators: thumb opposition (palm), thumb proximal, thumb distal, index proximal, index middle+distal, middle proximal, middle middle+distal, ring+pinky together | S. Schulz, C. Pylatiuk, G. Bretthauer, "A new ultralight anthropomorphic hand", ICRA 2001; Asfour et al. 2006 | nominal |
//! | ARMAR-III hand | actuator efforts (simulation) | 5 N m per actuator (no public stall torque for the fluidic actuators); shared by its coupled joints where coupled actuators are simulated: middle+distal 2.5 N m each, ring+pinky 0.83 N m for each of 6 joints | modelling choice | design |
//! | ARMAR-III hand | actuation (simulation) | compliant torque sources (`Actuation::Compliant`, full effort share over 0.1 rad, `hands::ARMAR3_COMPLIANCE`): the physics check presses the balanced grip torques through joint springs; Barrett and SDH are position servos (worm gears; harmonic drives) | fluidic actuators (Asfour et al. 2006, above); the compliance is a modelling choice | design |
//! | ARMAR-III hand | sizes | palm 95 × 85 × 30 mm, fingers 17 mm wide, middle finger 48 + 28 + 22 mm, mass 0.25 kg | human-hand proportions of the same paper | design |
//! | ARMAR-III hand | joint ranges, thumb, preshapes | every finger joint 0–90°; thumb (45 + 32 mm) based low on the palm near the wrist (22 mm off the mid-line), its base rotation (0–90°) swings it from the palm plane into the plane of the palm normal, where its proximal joint (−90° to 90°: extended back towards the wrist to flexed over the palm) and distal joint (0–90°) curl it towards the fingers so it opposes them in a power grasp; `open` (default) has the thumb opposed but extended along the palm, so nothing stands in front of the palm (the earlier model's thumb stood 77 mm out and touched wide objects before the palm); `power` raises it to 45° for narrow objects | Schulz et al. 2001 (thumb opposition by the palm actuator); human power-grasp kinematics | design |
//! | Objects | models | bread box, chocolate (prismatic) box, rectangular salt box, cylindrical salt can, detergent bottle with handle, spray bottle, white cup, green cup, measuring cup | seed paper Fig. 2; KIT ObjectModels Web Database (A. Kasper, Z. Xue, R. Dillmann, IJRR 31(8), 2012) | checked (list) |
//! | Objects | sizes (x × y × z, mm, handle along +x) | bread box 245 × 125 × 95; chocolate box 210 long, 40 mm equilateral section; salt box 95 × 60 × 135; salt can Ø 80 × 140; detergent bottle 163 × 75 × 260; spray bottle 102.5 × 60 × 290; white cup Ø 82 × 95 (115.5 with handle); green cup Ø 75 × 88 (105); measuring cup Ø 100 × 120 (141) | typical dimensions of the products in the KIT database | nominal |
//! | Objects | masses (kg), friction | 0.50, 0.10, 0.52, 0.55, 1.10, 0.55, 0.32, 0.27, 0.12; μ 0.4 (plastic) – 0.6 (cardboard) | filled retail packages; common dry friction tables | nominal |
//! | Kitchen | furniture | worktop 0.90 m high, 0.60 m deep; table 0.75 m; fridge 0.60 × 0.65 × 1.80 m; sideboard 0.85 m | common European kitchen sizes (EN 1116 co-ordinating sizes) | nominal |
//!
//! ## Geometry conventions
//! Meshes are built procedurally: stacks of rings (extrusions, lathes with closed caps,
//! tapered bottles) and swept tubes. Objects with a handle are two closed shells in one mesh:
//! the body and a half-torus tube whose capped ends are buried in the wall, so the handle's
//! hole goes through; each shell is watertight and outward-oriented on its own, so the union
//! passes `TriangleMesh::is_watertight`, and mass properties integrate the (tiny) overlap twice.
//! Robot links use boxes, cylinders, spheres and capsules. Mass properties of objects assume a
//! uniform density over the enclosed volume (a filled salt can counts as solid).

/// The version of this crate (recorded in results files' provenance).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub mod error;
pub mod export;
pub mod hands;
pub mod mesh;
pub mod objects;
pub mod robots;
pub mod scenes;

pub use error::{AssetError, Result};
pub use export::export_to;
