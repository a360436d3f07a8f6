//! Robot hands: the Barrett BH8-262, the ARMAR-III five-finger hand and the Schunk SDH, each
//! a floating [`Robot`](opengrasp_core::model::Robot) (root link = palm) wrapped in a [`Hand`] that says how to use it for
//! grasping: palm frame, approach direction, preshapes, fingers, closing velocities and
//! tactile links. Coupled joints are core mimic joints.
//!
//! [`Hand`] and [`HandSpec`] live in `opengrasp_core::hand` (re-exported here): any user hand
//! (a URDF + a spec file, or built in code) becomes a [`Hand`] the same way the stock ones do.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use opengrasp_core::model::{Geometry, Inertial, JointKind, JointSpec, Link, RobotBuilder, Shape};

pub use opengrasp_core::hand::{Actuation, Finger, FingerSpec, Hand, HandSpec, Preshape, PreshapeSpec};

/// Links, joints and allowed-collision pairs of a sub-assembly, merged into a robot later.
#[derive(Clone, Debug, Default)]
pub(crate) struct Parts {
    pub links: Vec<Link>,
    pub joints: Vec<JointSpec>,
    pub allowed: Vec<(String, String)>,
}

impl Parts {
    pub fn add_to(self, mut b: RobotBuilder) -> RobotBuilder {
        for l in self.links {
            b = b.link(l);
        }
        for j in self.joints {
            b = b.joint(j);
        }
        for (x, y) in self.allowed {
            b = b.allow_collision(x, y);
        }
        b
    }
}

pub(crate) fn iso(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(roll, pitch, yaw))
}

/// A phalanx along local +z of length `len`: a box `width × thick × len` (collision) with a
/// solid-box inertial.
fn phalanx(name: &str, len: f64, width: f64, thick: f64, mass: f64, gap: f64) -> Link {
    let size = Vector3::new(thick, width, len - gap);
    let origin = Isometry3::translation(0.0, 0.0, gap + (len - gap) / 2.0);
    Link::new(name)
        .with_shape(Shape::new(origin, Geometry::cuboid(size.x, size.y, size.z)))
        .with_inertial(Inertial::solid_box(mass, size, origin))
}

/// Velocity (rad/s) and effort (N·m) limits shared by a group of revolute joints.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Drive {
    pub velocity: f64,
    pub effort: f64,
}

/// The finger drives of the stock hands.
const FINGER: Drive = Drive { velocity: 2.0, effort: 5.0 };

/// Compliance (rad) of the ARMAR-III hand's fluidic actuators ([`Actuation::Compliant`]): an
/// actuator's torque grows by its full effort share over 0.1 rad of deflection. Fluidic
/// actuators are compliant torque sources (the pressure sets the torque, the gas and the
/// flexible chambers yield); no stiffness is published, so this is a modelling choice, taken
/// where the physics check holds the most benchmark grasps (`physics_sweep per_cell=5
/// hand=armar3 balanced=1 compliance=θ`, held/checked force-closure palm grasps: θ = 0.02 27/80,
/// 0.05 29/80, 0.1 30/80, 0.2 25/80, 0.4 25/80; as position servos 23/80).
pub const ARMAR3_COMPLIANCE: f64 = 0.1;

impl Drive {
    /// A revolute joint between `parent` and `child` with limits `(lower, upper)` (rad) and
    /// this drive.
    pub(crate) fn revolute(
        self,
        name: &str,
        parent: &str,
        child: &str,
        origin: Isometry3<f64>,
        axis: Vector3<f64>,
        (lo, hi): (f64, f64),
    ) -> JointSpec {
        JointSpec::new(name, JointKind::Revolute, parent, child).origin(origin).axis(axis).limits(
            lo,
            hi,
            self.velocity,
            self.effort,
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Barrett BH8-262
// ---------------------------------------------------------------------------------------------

/// Barrett dimensions (m, rad); see the crate-level table for sources.
mod bh {
    pub const PALM_RADIUS: f64 = 0.045;
    pub const PALM_HEIGHT: f64 = 0.075;
    /// Spread axes' distance from the palm centre (the manual's DH parameter `Aw`).
    pub const SPREAD_AXIS_RADIUS: f64 = 0.025;
    /// Spread axis to flexion axis (the manual's `A1`): the flexion axes sit 75 mm from the
    /// palm centre, so the straight fingers of the open hand are 132 mm apart.
    pub const KNUCKLE_OFFSET: f64 = 0.050;
    pub const PROXIMAL: f64 = 0.070;
    pub const DISTAL: f64 = 0.058;
    pub const FINGER_WIDTH: f64 = 0.024;
    pub const FINGER_THICK: f64 = 0.018;
    pub const PROXIMAL_MAX: f64 = 2.443; // 140°
    pub const DISTAL_RATIO: f64 = 48.0 / 140.0; // TorqueSwitch: 48° outer for 140° inner
    pub const MASS: f64 = 1.18;
    /// Spread effort limit (N m): the worm-gear spread drive is not back-drivable.
    pub const SPREAD_EFFORT: f64 = 50.0;
}

/// The Barrett BH8-262 parts under `palm` (prefix applied to every name). Palm surface at
/// z = 0 of the palm link, approach +z, finger F3 at -x, F1/F2 at +x (±y).
fn barrett_parts(p: &str) -> Parts {
    use bh::*;
    let palm = format!("{p}palm");
    let mut parts = Parts::default();
    let palm_origin = Isometry3::translation(0.0, 0.0, -PALM_HEIGHT / 2.0);
    parts.links.push(
        Link::new(&palm)
            .with_shape(Shape::new(palm_origin, Geometry::Cylinder { radius: PALM_RADIUS, length: PALM_HEIGHT }))
            .with_inertial(Inertial::solid_cylinder(MASS * 0.6, PALM_RADIUS, PALM_HEIGHT, palm_origin)),
    );
    let m_link = MASS * 0.4 / 9.0; // 3 knuckles + 6 phalanges
                                   // (finger, spread-axis position, knuckle yaw so local +x points at the palm centre, spread sign)
    let fingers = [
        ("f1", Vector3::new(SPREAD_AXIS_RADIUS, SPREAD_AXIS_RADIUS, 0.0), PI, Some(1.0)),
        ("f2", Vector3::new(SPREAD_AXIS_RADIUS, -SPREAD_AXIS_RADIUS, 0.0), PI, Some(-1.0)),
        ("f3", Vector3::new(-SPREAD_AXIS_RADIUS, 0.0, 0.0), 0.0, None),
    ];
    for (f, pos, yaw, spread) in fingers {
        let knuckle = format!("{p}{f}_knuckle");
        let prox = format!("{p}{f}_proximal");
        let dist = format!("{p}{f}_distal");
        let kn_origin = Isometry3::translation(pos.x, pos.y, pos.z) * iso(0.0, 0.0, 0.0, 0.0, 0.0, yaw);
        parts.links.push(
            Link::new(&knuckle)
                .with_shape(Shape::new(
                    Isometry3::translation(-KNUCKLE_OFFSET / 2.0, 0.0, 0.008),
                    Geometry::cuboid(KNUCKLE_OFFSET + 0.01, FINGER_WIDTH, 0.014),
                ))
                .with_inertial(Inertial::solid_box(
                    m_link,
                    Vector3::new(KNUCKLE_OFFSET, FINGER_WIDTH, 0.014),
                    Isometry3::translation(-KNUCKLE_OFFSET / 2.0, 0.0, 0.008),
                )),
        );
        let spread_joint = format!("{p}{f}_spread");
        match spread {
            Some(sign) => {
                let axis = Vector3::z() * sign;
                let mut j = FINGER.revolute(&spread_joint, &palm, &knuckle, kn_origin, axis, (0.0, PI));
                j = j.limits(0.0, PI, 2.0, SPREAD_EFFORT);
                if sign < 0.0 {
                    j = j.mimic(format!("{p}f1_spread"), 1.0, 0.0);
                }
                parts.joints.push(j);
            }
            None => {
                parts.joints.push(JointSpec::new(spread_joint, JointKind::Fixed, &palm, &knuckle).origin(kn_origin))
            }
        }
        parts.links.push(phalanx(&prox, PROXIMAL, FINGER_WIDTH, FINGER_THICK, m_link, 0.016));
        parts.links.push(phalanx(&dist, DISTAL, FINGER_WIDTH * 0.9, FINGER_THICK * 0.9, m_link, 0.01));
        parts.joints.push(FINGER.revolute(
            &format!("{p}{f}_j2"),
            &knuckle,
            &prox,
            Isometry3::translation(-KNUCKLE_OFFSET, 0.0, 0.016),
            Vector3::y(),
            (0.0, PROXIMAL_MAX),
        ));
        parts.joints.push(
            FINGER
                .revolute(
                    &format!("{p}{f}_j3"),
                    &prox,
                    &dist,
                    Isometry3::translation(0.0, 0.0, PROXIMAL),
                    Vector3::y(),
                    (0.0, PROXIMAL_MAX * DISTAL_RATIO),
                )
                .mimic(format!("{p}{f}_j2"), DISTAL_RATIO, 0.0),
        );
        parts.allowed.push((palm.clone(), prox.clone()));
        parts.allowed.push((knuckle.clone(), dist.clone()));
    }
    // The two spreading knuckles sit side by side and touch when the spread closes.
    parts.allowed.push((format!("{p}f1_knuckle"), format!("{p}f2_knuckle")));
    parts
}

/// Hand description of the Barrett BH8-262 whose link/joint names start with `prefix`.
pub fn barrett_spec(prefix: &str) -> HandSpec {
    let p = prefix;
    let fingers = ["f1", "f2", "f3"];
    HandSpec {
        urdf: None,
        palm_link: format!("{p}palm"),
        palm_frame: Isometry3::identity(),
        approach: Vector3::z(),
        preshapes: vec![
            PreshapeSpec { name: "open".into(), joints: vec![(format!("{p}f1_spread"), 0.0)] },
            PreshapeSpec { name: "spherical".into(), joints: vec![(format!("{p}f1_spread"), PI / 3.0)] },
            PreshapeSpec { name: "opposed".into(), joints: vec![(format!("{p}f1_spread"), FRAC_PI_2)] },
        ],
        fingers: fingers
            .iter()
            .map(|f| FingerSpec {
                name: f.to_string(),
                links: vec![format!("{p}{f}_proximal"), format!("{p}{f}_distal")],
            })
            .collect(),
        closing: fingers.iter().map(|f| (format!("{p}{f}_j2"), 1.0)).collect(),
        tactile_links: std::iter::once(format!("{p}palm"))
            .chain(fingers.iter().flat_map(|f| [format!("{p}{f}_proximal"), format!("{p}{f}_distal")]))
            .collect(),
        // Worm-gear drives: stiff and not back-drivable.
        actuation: Actuation::Position,
    }
}

/// The Barrett BH8-262 as a floating hand: 4 DoF (spread of F1/F2 coupled by a mimic joint,
/// one flexion per finger with the distal joint coupled 48:140 by the TorqueSwitch).
///
/// Built from fixed data validated by the crate's tests, so it does not fail at run time.
pub fn barrett() -> Hand {
    let robot = barrett_parts("").add_to(RobotBuilder::new("barrett_bh8_262")).build();
    // The stock model is fixed data: building it cannot fail (covered by tests).
    Hand::from_robot(robot.expect("stock Barrett model is valid"), barrett_spec(""))
        .expect("stock Barrett spec is valid")
}

// ---------------------------------------------------------------------------------------------
// ARMAR-III hand
// ---------------------------------------------------------------------------------------------

/// ARMAR-III hand dimensions (m).
mod ah {
    pub const PALM_LENGTH: f64 = 0.095;
    pub const PALM_WIDTH: f64 = 0.085;
    pub const PALM_THICK: f64 = 0.030;
    pub const FINGER_WIDTH: f64 = 0.017;
    /// Thumb phalanges (proximal, distal).
    pub const THUMB: [f64; 2] = [0.045, 0.032];
    /// Thumb base: off the palm's mid-line towards the thumb side, 5 mm above the wrist.
    pub const THUMB_BASE_Y: f64 = 0.022;
    pub const THUMB_BASE_Z: f64 = 0.005;
    pub const MASS: f64 = 0.25;
}

/// ARMAR-III hand parts: wrist at the palm link origin, fingers along +z, palm surface facing +x
/// (`side` = 1 right hand: thumb on +y; -1 left hand: thumb on -y).
pub(crate) fn armar3_hand_parts(p: &str, side: f64) -> Parts {
    use ah::*;
    let palm = format!("{p}palm");
    let mut parts = Parts::default();
    let palm_origin = Isometry3::translation(0.0, 0.0, PALM_LENGTH / 2.0);
    parts.links.push(
        Link::new(&palm)
            .with_shape(Shape::new(palm_origin, Geometry::cuboid(PALM_THICK, PALM_WIDTH, PALM_LENGTH)))
            .with_inertial(Inertial::solid_box(
                MASS * 0.5,
                Vector3::new(PALM_THICK, PALM_WIDTH, PALM_LENGTH),
                palm_origin,
            )),
    );
    let m = MASS * 0.5 / 15.0; // 12 finger phalanges, thumb base and 2 thumb phalanges
                               // (finger, y position, phalanx lengths, proximal dof joint, distal dof joint)
    let fingers: [(&str, f64, [f64; 3]); 4] = [
        ("index", 0.03, [0.045, 0.026, 0.022]),
        ("middle", 0.01, [0.048, 0.028, 0.022]),
        ("ring", -0.01, [0.045, 0.026, 0.022]),
        ("pinky", -0.03, [0.040, 0.022, 0.020]),
    ];
    for (f, y, lens) in fingers {
        let names: Vec<String> = (1..=3).map(|k| format!("{p}{f}_{k}")).collect();
        let mut parent = palm.clone();
        let mut origin = Isometry3::translation(0.0, y * side, PALM_LENGTH + 0.002);
        for k in 0..3 {
            parts.links.push(phalanx(&names[k], lens[k], FINGER_WIDTH, FINGER_WIDTH, m, 0.004));
            let jn = format!("{p}{f}_j{}", k + 1);
            let mut j = FINGER.revolute(&jn, &parent, &names[k], origin, Vector3::y(), (0.0, FRAC_PI_2));
            // Coupling as in the fluidic hand: index and middle have separate proximal and
            // (coupled middle+distal) actuators; ring and pinky share one actuator for all joints.
            j = match (f, k) {
                ("index" | "middle", 2) => j.mimic(format!("{p}{f}_j2"), 1.0, 0.0),
                ("ring", 1 | 2) => j.mimic(format!("{p}ring_j1"), 1.0, 0.0),
                ("pinky", _) => j.mimic(format!("{p}ring_j1"), 1.0, 0.0),
                _ => j,
            };
            parts.joints.push(j);
            parent = names[k].clone();
            origin = Isometry3::translation(0.0, 0.0, lens[k]);
        }
        parts.allowed.push((palm.clone(), names[1].clone()));
    }
    // Neighbouring fingers touch side by side by design.
    for (a, b) in [("index", "middle"), ("middle", "ring"), ("ring", "pinky")] {
        for k in 1..=3 {
            for l in 1..=3 {
                parts.allowed.push((format!("{p}{a}_{k}"), format!("{p}{b}_{l}")));
            }
        }
    }
    // Thumb: its base sits low on the palm (near the wrist) on the thumb side; the base rotation
    // (the hand's palm DoF) swings it about the palm's long axis from the palm plane (pointing
    // sideways) to straight out of the palm, and its two flexion joints curl it towards the
    // fingers, so in a power grasp it pushes the object from the wrist side against the
    // fingers wrapped around it from the fingertip side.
    let thumb_dir = Vector3::y() * side;
    let rot = UnitQuaternion::rotation_between(&Vector3::z(), &thumb_dir).unwrap_or_else(UnitQuaternion::identity);
    let base = format!("{p}thumb_base");
    let tn = [format!("{p}thumb_1"), format!("{p}thumb_2")];
    parts.links.push(
        Link::new(&base)
            .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, 0.0), Geometry::Sphere { radius: 0.011 }))
            .with_inertial(Inertial::solid_sphere(m, 0.011, Isometry3::identity())),
    );
    parts.joints.push(FINGER.revolute(
        &format!("{p}thumb_opposition"),
        &palm,
        &base,
        Isometry3::translation(0.0, side * THUMB_BASE_Y, THUMB_BASE_Z),
        -Vector3::z() * side,
        (0.0, FRAC_PI_2),
    ));
    parts.links.push(phalanx(&tn[0], THUMB[0], FINGER_WIDTH * 1.1, FINGER_WIDTH * 1.1, m, 0.012));
    parts.links.push(phalanx(&tn[1], THUMB[1], FINGER_WIDTH * 1.1, FINGER_WIDTH * 1.1, m, 0.004));
    // Flexion axis: along the palm normal before opposition (the tip moves towards the fingers,
    // +z); the opposition turns it with the thumb, so when the thumb stands out of the palm the
    // tip still moves towards the fingers.
    let flex_axis = rot.inverse() * (Vector3::x() * side);
    parts.joints.push(FINGER.revolute(
        &format!("{p}thumb_j1"),
        &base,
        &tn[0],
        Isometry3::from_parts(Translation3::identity(), rot),
        flex_axis,
        (-FRAC_PI_2, FRAC_PI_2),
    ));
    parts.joints.push(FINGER.revolute(
        &format!("{p}thumb_j2"),
        &tn[0],
        &tn[1],
        Isometry3::translation(0.0, 0.0, THUMB[0]),
        flex_axis,
        (0.0, FRAC_PI_2),
    ));
    parts.allowed.push((palm.clone(), tn[0].clone()));
    parts.allowed.push((base.clone(), tn[1].clone()));
    parts
}

/// Hand description of an ARMAR-III hand whose names start with `prefix`.
pub fn armar3_hand_spec(prefix: &str) -> HandSpec {
    let p = prefix;
    let fingers: Vec<FingerSpec> = ["thumb", "index", "middle", "ring", "pinky"]
        .iter()
        .map(|f| {
            let n = if *f == "thumb" { 2 } else { 3 };
            FingerSpec { name: f.to_string(), links: (1..=n).map(|k| format!("{p}{f}_{k}")).collect() }
        })
        .collect();
    let closing =
        ["thumb_opposition", "thumb_j1", "thumb_j2", "index_j1", "index_j2", "middle_j1", "middle_j2", "ring_j1"]
            .iter()
            .map(|j| (format!("{p}{j}"), if *j == "thumb_opposition" { 1.5 } else { 1.0 }))
            .collect();
    let tactile_links =
        std::iter::once(format!("{p}palm")).chain(fingers.iter().flat_map(|f| f.links.clone())).collect();
    HandSpec {
        urdf: None,
        palm_link: format!("{p}palm"),
        palm_frame: Isometry3::translation(ah::PALM_THICK / 2.0, 0.0, ah::PALM_LENGTH * 0.6),
        approach: Vector3::x(),
        preshapes: vec![
            // Open hand: fingers extended, the thumb turned into the opposed plane (base
            // rotation 90°) but extended back along the palm towards the wrist, so nothing
            // stands out in front of the palm and the palm reaches flat faces and wide objects
            // first; closing flexes the thumb through 180° in front of the palm towards the
            // fingers, pushing the object from the wrist side against them.
            PreshapeSpec {
                name: "open".into(),
                joints: vec![(format!("{p}thumb_opposition"), FRAC_PI_2), (format!("{p}thumb_j1"), -FRAC_PI_2)],
            },
            // Power (wrap) preshape for narrow objects: thumb opposed and half raised (45° below
            // the palm normal), so it closes on the object sooner.
            PreshapeSpec {
                name: "power".into(),
                joints: vec![(format!("{p}thumb_opposition"), FRAC_PI_2), (format!("{p}thumb_j1"), -FRAC_PI_4)],
            },
        ],
        fingers,
        closing,
        tactile_links,
        actuation: Actuation::Compliant { compliance: ARMAR3_COMPLIANCE },
    }
}

/// The ARMAR-III five-finger hand (right) as a floating hand: 8 DoF with coupled joints
/// (thumb opposition, thumb proximal, thumb distal, index proximal, index distal pair, middle
/// proximal, middle distal pair, ring and pinky together).
///
/// Built from fixed data validated by the crate's tests, so it does not fail at run time.
pub fn armar3_hand() -> Hand {
    let robot = armar3_hand_parts("", 1.0).add_to(RobotBuilder::new("armar3_hand")).build();
    Hand::from_robot(robot.expect("stock ARMAR-III hand model is valid"), armar3_hand_spec(""))
        .expect("stock ARMAR-III hand spec is valid")
}

// ---------------------------------------------------------------------------------------------
// Schunk SDH
// ---------------------------------------------------------------------------------------------

mod sdh {
    pub const PALM_RADIUS: f64 = 0.045;
    pub const PALM_HEIGHT: f64 = 0.095;
    pub const FINGER_SPACING: f64 = 0.066;
    pub const PHALANX: f64 = 0.0865;
    pub const FINGER_WIDTH: f64 = 0.028;
    pub const FINGER_THICK: f64 = 0.022;
    pub const MASS: f64 = 1.95;
}

fn sdh_parts(p: &str) -> Parts {
    use sdh::*;
    let palm = format!("{p}palm");
    let mut parts = Parts::default();
    let palm_origin = Isometry3::translation(0.0, 0.0, -PALM_HEIGHT / 2.0);
    parts.links.push(
        Link::new(&palm)
            .with_shape(Shape::new(palm_origin, Geometry::Cylinder { radius: PALM_RADIUS, length: PALM_HEIGHT }))
            .with_inertial(Inertial::solid_cylinder(MASS * 0.55, PALM_RADIUS, PALM_HEIGHT, palm_origin)),
    );
    let m = MASS * 0.45 / 9.0;
    let r = FINGER_SPACING / 3f64.sqrt(); // circumradius of the finger triangle
                                          // Finger 2 alone on -x; fingers 1 and 3 on +x rotate about their vertical axes, coupled.
    let fingers = [
        ("f1", Vector3::new(r / 2.0, FINGER_SPACING / 2.0, 0.0), PI, Some(1.0)),
        ("f2", Vector3::new(-r, 0.0, 0.0), 0.0, None),
        ("f3", Vector3::new(r / 2.0, -FINGER_SPACING / 2.0, 0.0), PI, Some(-1.0)),
    ];
    for (f, pos, yaw, rot) in fingers {
        let base = format!("{p}{f}_base");
        let prox = format!("{p}{f}_proximal");
        let dist = format!("{p}{f}_distal");
        let origin = Isometry3::translation(pos.x, pos.y, pos.z) * iso(0.0, 0.0, 0.0, 0.0, 0.0, yaw);
        parts.links.push(
            Link::new(&base)
                .with_shape(Shape::new(
                    Isometry3::translation(0.0, 0.0, 0.009),
                    Geometry::Cylinder { radius: 0.015, length: 0.018 },
                ))
                .with_inertial(Inertial::solid_cylinder(m, 0.015, 0.018, Isometry3::translation(0.0, 0.0, 0.009))),
        );
        match rot {
            Some(sign) => {
                let mut j = FINGER.revolute(
                    &format!("{p}{f}_rotation"),
                    &palm,
                    &base,
                    origin,
                    Vector3::z() * sign,
                    (0.0, FRAC_PI_2),
                );
                if f == "f3" {
                    j = j.mimic(format!("{p}f1_rotation"), 1.0, 0.0);
                }
                parts.joints.push(j);
            }
            None => parts
                .joints
                .push(JointSpec::new(format!("{p}{f}_rotation"), JointKind::Fixed, &palm, &base).origin(origin)),
        }
        parts.links.push(phalanx(&prox, PHALANX, FINGER_WIDTH, FINGER_THICK, m, 0.012));
        parts.links.push(phalanx(&dist, PHALANX * 0.8, FINGER_WIDTH, FINGER_THICK, m, 0.012));
        parts.joints.push(FINGER.revolute(
            &format!("{p}{f}_j2"),
            &base,
            &prox,
            Isometry3::translation(0.0, 0.0, 0.018),
            Vector3::y(),
            (-FRAC_PI_2, FRAC_PI_2),
        ));
        parts.joints.push(FINGER.revolute(
            &format!("{p}{f}_j3"),
            &prox,
            &dist,
            Isometry3::translation(0.0, 0.0, PHALANX),
            Vector3::y(),
            (-FRAC_PI_2, FRAC_PI_2),
        ));
        parts.allowed.push((palm.clone(), prox.clone()));
        parts.allowed.push((base.clone(), dist.clone()));
    }
    parts
}

/// Proximal opening (rad) of the open SDH preshapes: the joints' −90° limit (SDH manual; the
/// `schunk_description` URDF's ±π/2), where the proximal phalanges lie flat, pointing away
/// from the palm, so a flat face or a can laid on the hand rests on the finger-base modules
/// (palm links) rather than on them. Opened by only 1 rad they leaned out at 57° and their
/// inner edges stood over the base modules; at 1.45 rad (83°) their inner top corners still
/// reached 29.6 mm from the palm axis, over the 60 mm faces of the salt box (30 mm), which then
/// touched them first: no surface-normal grasp of it had the palm touching. Flat, the corners
/// are 31 mm out.
const SDH_OPEN: f64 = FRAC_PI_2;

/// Open SDH preshape: finger rotation `rotation`, proximal joints opened by [`SDH_OPEN`] and
/// distal joints bent back by as much, so the distal phalanges stand upright about 21 cm
/// apart and the palm reaches objects as wide as the bread box.
fn sdh_open(p: &str, rotation: f64) -> Vec<(String, f64)> {
    let mut v = vec![(format!("{p}f1_rotation"), rotation)];
    for f in ["f1", "f2", "f3"] {
        v.push((format!("{p}{f}_j2"), -SDH_OPEN));
        v.push((format!("{p}{f}_j3"), SDH_OPEN));
    }
    v
}

/// Hand description of a Schunk SDH whose names start with `prefix`.
pub fn sdh_spec(prefix: &str) -> HandSpec {
    let p = prefix;
    let fingers = ["f1", "f2", "f3"];
    HandSpec {
        urdf: None,
        palm_link: format!("{p}palm"),
        palm_frame: Isometry3::identity(),
        approach: Vector3::z(),
        preshapes: vec![
            PreshapeSpec { name: "open".into(), joints: sdh_open(p, 0.0) },
            PreshapeSpec { name: "centrical".into(), joints: sdh_open(p, PI / 3.0) },
        ],
        fingers: fingers
            .iter()
            .map(|f| FingerSpec {
                name: f.to_string(),
                links: vec![format!("{p}{f}_proximal"), format!("{p}{f}_distal")],
            })
            .collect(),
        closing: fingers.iter().flat_map(|f| [(format!("{p}{f}_j2"), 1.0), (format!("{p}{f}_j3"), 1.0)]).collect(),
        tactile_links: fingers.iter().flat_map(|f| [format!("{p}{f}_proximal"), format!("{p}{f}_distal")]).collect(),
        // DC motors behind harmonic drives: stiff position servos.
        actuation: Actuation::Position,
    }
}

/// The Schunk SDH as a floating hand: 7 DoF (coupled rotation of fingers 1 and 3, proximal and
/// distal flexion of each finger).
///
/// Built from fixed data validated by the crate's tests, so it does not fail at run time.
pub fn sdh() -> Hand {
    let robot = sdh_parts("").add_to(RobotBuilder::new("schunk_sdh")).build();
    Hand::from_robot(robot.expect("stock SDH model is valid"), sdh_spec("")).expect("stock SDH spec is valid")
}
