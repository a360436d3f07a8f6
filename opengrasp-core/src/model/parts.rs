//! The parts of a robot: links with geometry and inertia, joints and their limits.

use nalgebra::{Isometry3, Matrix3, Unit, Vector3};

use super::geometry::Shape;

/// Index of a link in [`Robot::links`](super::Robot::links).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LinkId(pub usize);

/// Index of a joint in [`Robot::joints`](super::Robot::joints).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

/// Mass properties of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Inertial {
    /// Pose of the centre of mass (and inertia frame) in the link frame.
    pub origin: Isometry3<f64>,
    /// Mass (kg).
    pub mass: f64,
    /// Inertia tensor about the centre of mass, in the inertial frame (kg·m²).
    pub inertia: Matrix3<f64>,
}

impl Inertial {
    /// Mass properties of a solid box of full size `size` and mass `mass`, centred at `origin`.
    pub fn solid_box(mass: f64, size: Vector3<f64>, origin: Isometry3<f64>) -> Self {
        let (x2, y2, z2) = (size.x * size.x, size.y * size.y, size.z * size.z);
        let inertia = Matrix3::from_diagonal(&Vector3::new(y2 + z2, x2 + z2, x2 + y2)) * (mass / 12.0);
        Self { origin, mass, inertia }
    }

    /// Mass properties of a solid cylinder along local z.
    pub fn solid_cylinder(mass: f64, radius: f64, length: f64, origin: Isometry3<f64>) -> Self {
        let ixx = mass * (3.0 * radius * radius + length * length) / 12.0;
        let izz = mass * radius * radius / 2.0;
        Self { origin, mass, inertia: Matrix3::from_diagonal(&Vector3::new(ixx, ixx, izz)) }
    }

    /// Mass properties of a solid sphere.
    pub fn solid_sphere(mass: f64, radius: f64, origin: Isometry3<f64>) -> Self {
        let i = 0.4 * mass * radius * radius;
        Self { origin, mass, inertia: Matrix3::from_diagonal_element(i) }
    }

    /// True if the mass is positive and the inertia tensor symmetric positive definite.
    pub fn is_physical(&self) -> bool {
        self.mass.is_finite()
            && self.mass > 0.0
            && (self.inertia - self.inertia.transpose()).norm() <= 1e-9 * self.inertia.norm().max(1e-12)
            && self.inertia.symmetric_eigenvalues().iter().all(|&l| l > 0.0)
    }
}

/// A rigid body of the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// Unique name.
    pub name: String,
    /// Mass properties, if known.
    pub inertial: Option<Inertial>,
    /// Geometry for display.
    pub visuals: Vec<Shape>,
    /// Geometry for collision checking.
    pub collisions: Vec<Shape>,
}

impl Link {
    /// A link with no geometry and no mass.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), inertial: None, visuals: Vec::new(), collisions: Vec::new() }
    }

    /// Adds a shape used both for display and collision.
    pub fn with_shape(mut self, shape: Shape) -> Self {
        self.visuals.push(shape.clone());
        self.collisions.push(shape);
        self
    }

    /// Sets the mass properties.
    pub fn with_inertial(mut self, inertial: Inertial) -> Self {
        self.inertial = Some(inertial);
        self
    }
}

/// The kind of motion a joint allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// No motion.
    Fixed,
    /// Rotation about the axis within limits.
    Revolute,
    /// Unlimited rotation about the axis.
    Continuous,
    /// Translation along the axis within limits.
    Prismatic,
}

/// Position, velocity and effort limits of a joint (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lowest position (rad or m).
    pub lower: f64,
    /// Highest position (rad or m).
    pub upper: f64,
    /// Maximum speed (rad/s or m/s).
    pub velocity: f64,
    /// Maximum effort (N·m or N).
    pub effort: f64,
}

/// A joint whose position follows another: `q = multiplier * q_leader + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mimic {
    /// The joint followed.
    pub leader: JointId,
    /// Coupling ratio.
    pub multiplier: f64,
    /// Offset (rad or m).
    pub offset: f64,
}

/// A joint connecting a parent link to a child link.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Kind of motion.
    pub kind: JointKind,
    /// Parent link.
    pub parent: LinkId,
    /// Child link.
    pub child: LinkId,
    /// Pose of the joint frame in the parent link frame (at zero joint position the child
    /// link frame coincides with it).
    pub origin: Isometry3<f64>,
    /// Unit axis of rotation/translation in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Limits (`None` for fixed and continuous joints).
    pub limits: Option<JointLimits>,
    /// Coupling to a leader joint, for mimic joints.
    pub mimic: Option<Mimic>,
    /// Index in the configuration vector, for actuated joints (movable and not mimic).
    pub dof: Option<usize>,
}

impl Joint {
    /// True for revolute, continuous and prismatic joints.
    pub fn is_movable(&self) -> bool {
        self.kind != JointKind::Fixed
    }

    /// The joint's motion for position `value`: the transform from joint frame to child frame.
    pub fn motion(&self, value: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Fixed => Isometry3::identity(),
            JointKind::Revolute | JointKind::Continuous => Isometry3::from_parts(
                nalgebra::Translation3::identity(),
                nalgebra::UnitQuaternion::from_axis_angle(&self.axis, value),
            ),
            JointKind::Prismatic => {
                Isometry3::translation(self.axis.x * value, self.axis.y * value, self.axis.z * value)
            }
        }
    }
}

/// Description of a joint for [`RobotBuilder::joint`](super::RobotBuilder::joint), using link and joint names.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// Unique name.
    pub name: String,
    /// Kind of motion.
    pub kind: JointKind,
    /// Parent link name.
    pub parent: String,
    /// Child link name.
    pub child: String,
    /// Pose of the joint frame in the parent link frame.
    pub origin: Isometry3<f64>,
    /// Axis in the joint frame (normalised by the builder).
    pub axis: Vector3<f64>,
    /// Limits; required for revolute and prismatic joints.
    pub limits: Option<JointLimits>,
    /// `(leader joint name, multiplier, offset)` for mimic joints.
    pub mimic: Option<(String, f64, f64)>,
}

impl JointSpec {
    /// A joint spec with identity origin, z axis and no limits.
    pub fn new(name: impl Into<String>, kind: JointKind, parent: impl Into<String>, child: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            kind,
            parent: parent.into(),
            child: child.into(),
            origin: Isometry3::identity(),
            axis: Vector3::z(),
            limits: None,
            mimic: None,
        }
    }

    /// Sets the joint origin in the parent frame.
    pub fn origin(mut self, origin: Isometry3<f64>) -> Self {
        self.origin = origin;
        self
    }

    /// Sets the axis.
    pub fn axis(mut self, axis: Vector3<f64>) -> Self {
        self.axis = axis;
        self
    }

    /// Sets position limits, with velocity and effort limits.
    pub fn limits(mut self, lower: f64, upper: f64, velocity: f64, effort: f64) -> Self {
        self.limits = Some(JointLimits { lower, upper, velocity, effort });
        self
    }

    /// Makes this joint follow `leader`.
    pub fn mimic(mut self, leader: impl Into<String>, multiplier: f64, offset: f64) -> Self {
        self.mimic = Some((leader.into(), multiplier, offset));
        self
    }
}
