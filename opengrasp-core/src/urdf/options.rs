//! Options and outcome of a URDF load.

use std::fmt;
use std::path::PathBuf;

use super::limits::XmlLimits;
use crate::model::Robot;

/// What a load does with `<visual>` geometry (collision geometry is always loaded, and any
/// error in it fails the load).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Visuals {
    /// Load visuals; a visual that cannot be loaded (missing file, undecodable mesh, bad
    /// dimensions) is left out and reported as [`LoadWarning::VisualNotLoaded`]. The default.
    #[default]
    Load,
    /// Skip visuals entirely: no visual mesh file is read (planning and collision only).
    Skip,
}

/// Options of [`load_file_with`](super::load_file_with) and
/// [`from_str_with`](super::from_str_with).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// Visual geometry. Default: [`Visuals::Load`].
    pub visuals: Visuals,
    /// Packages given explicitly, `(name, root directory)`, searched first. Default: none.
    pub packages: Vec<(String, PathBuf)>,
    /// Directories under which packages are found by their `package.xml` name (see
    /// [`FileResolver`](super::FileResolver)). Default: none.
    pub search_roots: Vec<PathBuf>,
    /// Also search `ROS_PACKAGE_PATH` and `AMENT_PREFIX_PATH`. Default: `true`.
    pub ros_package_path: bool,
    /// Limits on the URDF text, checked before it is parsed. Default: [`XmlLimits::default`].
    pub limits: XmlLimits,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            visuals: Visuals::Load,
            packages: Vec::new(),
            search_roots: Vec::new(),
            ros_package_path: true,
            limits: XmlLimits::default(),
        }
    }
}

/// Something a load accepted with a change, reported instead of failing the robot.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LoadWarning {
    /// A visual could not be loaded and was left out (collision geometry is unaffected).
    VisualNotLoaded {
        /// The link.
        link: String,
        /// Index of the `<visual>` within the link.
        index: usize,
        /// Why (the loader's error message).
        reason: String,
    },
    /// A `<mimic>` element was ignored: on a fixed joint, or following a fixed joint, there is
    /// nothing to couple (MoveIt ignores such couplings too, since the degrees of freedom
    /// differ).
    MimicIgnored {
        /// The joint carrying the `<mimic>`.
        joint: String,
        /// The joint it names.
        leader: String,
    },
}

impl fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::VisualNotLoaded { link, index, reason } => {
                write!(f, "visual {index} of link `{link}` left out: {reason}")
            }
            Self::MimicIgnored { joint, leader } => {
                write!(f, "mimic of joint `{joint}` on `{leader}` ignored: a fixed joint cannot be coupled")
            }
        }
    }
}

/// A robot and the warnings of its load.
#[derive(Clone, Debug)]
pub struct LoadedRobot {
    /// The robot.
    pub robot: Robot,
    /// What was accepted with a change, in document order.
    pub warnings: Vec<LoadWarning>,
}
