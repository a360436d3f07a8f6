//! OpenGRASP-rs facade.
pub use opengrasp_assets as assets;
pub use opengrasp_core as core;
pub use opengrasp_grasp as grasp;
pub use opengrasp_motion as motion;
