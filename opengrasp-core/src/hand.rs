//! Hands: a robot model plus what grasping needs to know about it.
//!
//! Any hand — a stock one of `opengrasp-assets`, a URDF of your own, a model built in code —
//! becomes a [`Hand`] through [`Hand::from_robot`] and a [`HandSpec`]: palm frame, approach
//! direction, preshapes, fingers, closing velocities and tactile links. Coupled joints are
//! mimic joints of the robot.
//!
//! A hand on disk is "a URDF + a small spec file": [`Hand::load`] reads a JSON [`HandSpec`] whose
//! `"urdf"` key gives the robot description's path relative to the spec file:
//!
//! ```json
//! {
//!   "urdf": "gripper.urdf",
//!   "palm_link": "palm",
//!   "palm_frame": {"xyz": [0, 0, 0.02], "rpy": [0, 0, 0]},
//!   "approach": [0, 0, 1],
//!   "preshapes": [{"name": "open", "joints": {"finger_joint": 0.0}}],
//!   "fingers": [{"name": "left", "links": ["left_finger"]}],
//!   "closing": {"finger_joint": 0.5},
//!   "tactile_links": [],
//!   "actuation": "position"
//! }
//! ```
//!
//! `rpy` is URDF's fixed-axis roll-pitch-yaw (rad); `closing` values are velocities (rad/s or
//! m/s) whose sign gives the closing direction; `actuation` (optional) is [`Actuation`]. Unknown keys are rejected, so a typo is an
//! error rather than a silently ignored setting.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::{Isometry3, Unit, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{CoreError, Result};
use crate::model::{LinkId, Robot};
use crate::spec_file::{self, named_values, xyz_rpy};

/// A named hand configuration given as joint values (joints not listed keep their value).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreshapeSpec {
    /// Name (`open`, `spherical`, `pinch`, ...).
    pub name: String,
    /// `(joint name, value)` pairs for actuated joints (a JSON object in spec files).
    #[serde(with = "named_values")]
    pub joints: Vec<(String, f64)>,
}

/// A finger given by the names of its links, from the palm outwards.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FingerSpec {
    /// Name (`f1`, `thumb`, ...).
    pub name: String,
    /// Link names of the finger's phalanges.
    pub links: Vec<String>,
}

/// Everything [`Hand::from_robot`] needs besides the robot model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HandSpec {
    /// The robot description (URDF) in a spec file, relative to it; [`Hand::load`] reads it,
    /// [`Hand::from_robot`] ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<PathBuf>,
    /// Name of the palm link.
    pub palm_link: String,
    /// Palm frame in the palm link frame: origin at the centre of the palm surface
    /// (`{"xyz": [..], "rpy": [..]}` in spec files; identity if absent).
    #[serde(with = "xyz_rpy", default = "Isometry3::identity")]
    pub palm_frame: Isometry3<f64>,
    /// Approach direction in the palm frame (need not be normalised).
    pub approach: Vector3<f64>,
    /// Named preshapes; the first one is the default open hand.
    #[serde(default)]
    pub preshapes: Vec<PreshapeSpec>,
    /// The fingers.
    pub fingers: Vec<FingerSpec>,
    /// `(actuated joint name, closing velocity in rad/s or m/s)`; the sign gives the closing
    /// direction. Actuated joints not listed (e.g. a spread joint) do not close. A JSON object
    /// in spec files.
    #[serde(with = "named_values")]
    pub closing: Vec<(String, f64)>,
    /// Links carrying tactile sensor pads.
    #[serde(default)]
    pub tactile_links: Vec<String>,
    /// How the closing actuators act on the fingers in simulation. Default: position servos.
    #[serde(default)]
    pub actuation: Actuation,
}

/// How a hand's closing actuators act on its fingers: what a simulation of the hand (the grasp
/// physics check) drives them as. In spec files `"actuation": "position"` (the default) or
/// `"actuation": {"compliant": {"compliance": 0.1}}`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Actuation {
    /// Stiff position servos (geared, non-back-drivable drives such as worm gears): commanded
    /// past the closed configuration, they press up to their effort limits.
    #[default]
    Position,
    /// Compliant torque sources (fluidic or series-elastic actuators): each actuator presses
    /// with a torque of its choosing within its effort limit and yields as a spring that gains
    /// its full effort share over `compliance` (rad, or m for a prismatic joint) of deflection.
    Compliant {
        /// Deflection (rad or m) over which an actuator's force grows by its effort share.
        compliance: f64,
    },
}

/// A named preshape as a sparse configuration `(dof index, value)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Preshape {
    /// Name.
    pub name: String,
    /// `(configuration index, value)` pairs.
    pub values: Vec<(usize, f64)>,
}

/// One finger: its links and the closing degrees of freedom that move them.
#[derive(Clone, Debug, PartialEq)]
pub struct Finger {
    /// Name.
    pub name: String,
    /// Phalanx links from the palm outwards.
    pub links: Vec<LinkId>,
    /// Configuration indices with a non-zero closing velocity that move this finger's links.
    pub closing_dofs: Vec<usize>,
}

/// A robot hand ready for grasp planning (standalone floating hand or mounted on an arm).
#[derive(Clone, Debug)]
pub struct Hand {
    name: String,
    robot: Arc<Robot>,
    palm: LinkId,
    palm_frame: Isometry3<f64>,
    approach: Unit<Vector3<f64>>,
    preshapes: Vec<Preshape>,
    fingers: Vec<Finger>,
    closing_velocity: Vec<f64>,
    tactile_links: Vec<LinkId>,
    actuation: Actuation,
}

impl Hand {
    /// Wraps `robot` (e.g. a user URDF) as a hand described by `spec`.
    ///
    /// # Errors
    /// [`CoreError::UnknownLink`] / [`CoreError::UnknownJoint`] / [`CoreError::NotActuated`]
    /// for a bad name in the spec; [`CoreError::InvalidParameter`] for a zero or non-finite
    /// approach, non-finite values, or no fingers.
    pub fn from_robot(robot: impl Into<Arc<Robot>>, spec: HandSpec) -> Result<Self> {
        let robot: Arc<Robot> = robot.into();
        let invalid = |name: &str, reason: String| CoreError::InvalidParameter { name: name.into(), reason };
        let palm = robot.link_id(&spec.palm_link)?;
        let approach = Unit::try_new(spec.approach, 1e-12)
            .filter(|a| a.iter().all(|c| c.is_finite()))
            .ok_or_else(|| invalid("approach", format!("must be a finite non-zero vector, got {:?}", spec.approach)))?;
        if spec.fingers.is_empty() {
            return Err(invalid("fingers", "a hand needs at least one finger".into()));
        }
        let dof_of = |joint: &str| robot.dof_index(joint);
        let mut closing_velocity = vec![0.0; robot.dof()];
        for (joint, v) in &spec.closing {
            if !v.is_finite() {
                return Err(invalid("closing", format!("velocity of `{joint}` is {v}")));
            }
            closing_velocity[dof_of(joint)?] = *v;
        }
        let mut preshapes = Vec::with_capacity(spec.preshapes.len());
        for p in &spec.preshapes {
            let mut values = Vec::with_capacity(p.joints.len());
            for (joint, v) in &p.joints {
                if !v.is_finite() {
                    return Err(invalid("preshape", format!("`{}` sets `{joint}` to {v}", p.name)));
                }
                values.push((dof_of(joint)?, *v));
            }
            preshapes.push(Preshape { name: p.name.clone(), values });
        }
        let mut fingers = Vec::with_capacity(spec.fingers.len());
        for f in &spec.fingers {
            let links = f.links.iter().map(|l| robot.link_id(l)).collect::<std::result::Result<Vec<_>, _>>()?;
            let mut dofs = BTreeSet::new();
            for &l in &links {
                for j in robot.chain_to(l) {
                    if let Some((d, _)) = robot.driving_dof(j) {
                        if closing_velocity[d] != 0.0 {
                            dofs.insert(d);
                        }
                    }
                }
            }
            fingers.push(Finger { name: f.name.clone(), links, closing_dofs: dofs.into_iter().collect() });
        }
        if let Actuation::Compliant { compliance } = spec.actuation {
            if !(compliance.is_finite() && compliance > 0.0) {
                return Err(invalid("actuation", format!("compliance must be finite and positive, got {compliance}")));
            }
        }
        let tactile_links =
            spec.tactile_links.iter().map(|l| robot.link_id(l)).collect::<std::result::Result<Vec<_>, _>>()?;
        Ok(Self {
            name: robot.name().to_string(),
            robot,
            palm,
            palm_frame: spec.palm_frame,
            approach,
            preshapes,
            fingers,
            closing_velocity,
            tactile_links,
            actuation: spec.actuation,
        })
    }

    /// Loads a hand from a JSON spec file naming its URDF (see the [module docs](self)); the
    /// URDF is read with [`crate::urdf::load_file`].
    ///
    /// # Errors
    /// [`CoreError::Io`] / [`CoreError::FileTooLarge`] reading the spec,
    /// [`CoreError::MalformedSpec`] for JSON that is not a hand spec, the URDF loader's errors,
    /// and those of [`Hand::from_robot`].
    pub fn load(spec_path: impl AsRef<Path>) -> Result<Self> {
        let spec_path = spec_path.as_ref();
        let spec: HandSpec = spec_file::read_json(spec_path)?;
        let urdf = spec.urdf.as_ref().ok_or_else(|| CoreError::MalformedSpec {
            path: spec_path.to_path_buf(),
            reason: "missing key `urdf` (the hand's robot description)".into(),
        })?;
        let robot = crate::urdf::load_file(spec_file::relative_to(spec_path, urdf))?;
        Self::from_robot(robot, spec)
    }

    /// The same hand under another name (the name benchmarks and results use).
    #[must_use]
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Name of the hand: its robot's name unless set with [`Hand::with_name`].
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The kinematic model.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }
    /// The kinematic model, shared (for adding the hand to a scene).
    pub fn robot_arc(&self) -> Arc<Robot> {
        self.robot.clone()
    }
    /// The palm link.
    pub fn palm(&self) -> LinkId {
        self.palm
    }
    /// The palm frame in the palm link frame (origin at the centre of the palm surface).
    pub fn palm_frame(&self) -> Isometry3<f64> {
        self.palm_frame
    }
    /// Unit approach direction in the palm frame.
    pub fn approach(&self) -> Unit<Vector3<f64>> {
        self.approach
    }
    /// The named preshapes (the first is the default open hand).
    pub fn preshapes(&self) -> &[Preshape] {
        &self.preshapes
    }
    /// The fingers.
    pub fn fingers(&self) -> &[Finger] {
        &self.fingers
    }
    /// Closing velocity of every configuration index (0 for joints that do not close).
    pub fn closing_velocity(&self) -> &[f64] {
        &self.closing_velocity
    }
    /// Links carrying tactile pads.
    pub fn tactile_links(&self) -> &[LinkId] {
        &self.tactile_links
    }

    /// How the closing actuators act on the fingers in simulation.
    pub fn actuation(&self) -> Actuation {
        self.actuation
    }
    /// How joint `joint` follows the configuration: `(dof index, multiplier)` (coupled joints
    /// are mimic joints; see [`Robot::driving_dof`]).
    pub fn coupling(&self, joint: &str) -> Result<Option<(usize, f64)>> {
        Ok(self.robot.driving_dof(self.robot.joint_id(joint)?))
    }

    /// `q` with the preshape `name` applied.
    ///
    /// # Errors
    /// [`CoreError::UnknownPreshape`] for an unknown preshape, [`CoreError::DimensionMismatch`]
    /// if `q` has the wrong length.
    pub fn preshape_configuration(&self, name: &str, q: &[f64]) -> Result<Vec<f64>> {
        self.check_len(q)?;
        let p = self
            .preshapes
            .iter()
            .find(|p| p.name == name)
            .ok_or_else(|| CoreError::UnknownPreshape { name: name.to_string() })?;
        let mut out = q.to_vec();
        for &(d, v) in &p.values {
            out[d] = v;
        }
        Ok(out)
    }

    /// The default open configuration: home configuration with the first preshape applied.
    pub fn open_configuration(&self) -> Vec<f64> {
        let mut q = self.robot.home_configuration();
        if let Some(p) = self.preshapes.first() {
            for &(d, v) in &p.values {
                q[d] = v;
            }
        }
        self.robot.clamp_configuration(&mut q);
        q
    }

    /// Moves the closing dofs of the fingers for which `active[finger]` is true by
    /// `step × closing velocity`, clamped to the joint limits.
    ///
    /// # Errors
    /// [`CoreError::DimensionMismatch`] if `q` has the wrong length,
    /// [`CoreError::InvalidParameter`] if `active` does not have one entry per finger.
    pub fn close_step(&self, q: &[f64], step: f64, active: &[bool]) -> Result<Vec<f64>> {
        self.check_len(q)?;
        if active.len() != self.fingers.len() {
            return Err(CoreError::InvalidParameter {
                name: "active".into(),
                reason: format!("{} entries for {} fingers", active.len(), self.fingers.len()),
            });
        }
        let mut out = q.to_vec();
        let mut moved = BTreeSet::new();
        for (f, _) in self.fingers.iter().zip(active).filter(|(_, &a)| a) {
            for &d in &f.closing_dofs {
                if moved.insert(d) {
                    out[d] += step * self.closing_velocity[d];
                }
            }
        }
        self.robot.clamp_configuration(&mut out);
        Ok(out)
    }

    fn check_len(&self, q: &[f64]) -> Result<()> {
        if q.len() != self.robot.dof() {
            return Err(CoreError::DimensionMismatch { expected: self.robot.dof(), actual: q.len() });
        }
        Ok(())
    }
}
