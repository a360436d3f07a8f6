//! Grasp analysis for OpenGRASP-rs: contact models, grasp wrench spaces and quality metrics.
//!
//! [`contact`] and [`quality`] are pure mathematics on contacts (no robot or scene needed);
//! the evaluator, planners and benchmark build on them:
//!
//! * [`contact`]: [`Contact`] (point + inward normal), the [`ContactModel`] (Coulomb
//!   friction μ, default 0.5, linearised with k = 8 cone edges; optional soft-finger
//!   torsional friction) and the [`GraspWrenchSpace`] of primitive wrenches about the
//!   object's centre of mass, torques scaled by 1/ρ with ρ the object's maximum radius
//!   ([`ObjectFrame`]).
//! * [`quality`]: one entry point, [`GraspQuality::evaluate`], returning a
//!   [`QualityReport`] with force closure (strict, plus the min-norm QP distance solved
//!   with clarabel), the Ferrari-Canny epsilon and the wrench-space volume from a pure-Rust
//!   d-dimensional convex hull ([`quality::hull`]); plus GraspNet's friction score
//!   ([`GraspQuality::friction_score`]) and Dex-Net's robust epsilon
//!   ([`GraspQuality::robust_epsilon`]).
//! * [`evaluator`]: the shared grasp evaluator that turns a hand pose on an object into
//!   contacts and grades them with the metrics above.
//! * [`planners`]: the [`planners::GraspPlanner`] trait and the reference planners.
//! * [`benchmark`]: runs planners × hands × objects through the one evaluator.
//! * [`tactile`]: tactile matrix pads (Weiss DSA 9335 / 9330 presets) read from evaluator or
//!   physics contacts.
//!
//! Bad input never panics: non-finite values, invalid options and solver failures are
//! [`GraspError`]s, and degenerate grasps (no contacts, one contact, wrench sets of rank
//! below 6) simply report no force closure with zero epsilon and volume.
//!
//! # Example
//!
//! Four fingers at the vertices of a regular tetrahedron on a sphere of radius 5 cm, each
//! pushing towards the centre:
//!
//! ```
//! use nalgebra::{Point3, Vector3};
//! use opengrasp_grasp::{Contact, GraspQuality, ObjectFrame, QualityOptions};
//!
//! # fn main() -> opengrasp_grasp::Result<()> {
//! let radius = 0.05;
//! let directions = [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]];
//! let contacts = directions
//!     .iter()
//!     .map(|d| {
//!         let u = Vector3::from(*d).normalize();
//!         Contact::new(Point3::from(radius * u), -u)
//!     })
//!     .collect::<Result<Vec<_>, _>>()?;
//! let frame = ObjectFrame::new(Point3::origin(), radius)?;
//!
//! let report = GraspQuality::evaluate(&contacts, &frame, &QualityOptions::default())?;
//! assert!(report.force_closure);
//! assert!(report.epsilon > 0.05);
//! // The hull's volume and facet count are opt-in statistics (the full 6-D hull).
//! let stats = QualityOptions { hull_statistics: true, ..QualityOptions::default() };
//! let report = GraspQuality::evaluate(&contacts, &frame, &stats)?;
//! assert!(report.volume.is_some_and(|v| v > 0.0));
//!
//! // The friction needed for force closure (GraspNet-1Billion's score; lower is better).
//! let mu = GraspQuality::friction_score(&contacts, &frame, &QualityOptions::default())?;
//! assert_eq!(mu, Some(0.2));
//! # Ok(())
//! # }
//! ```

/// The version of this crate (recorded in results files' provenance).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub mod benchmark;
pub mod contact;
pub mod error;
pub mod evaluator;
pub mod planners;
pub mod quality;
pub mod tactile;

pub use contact::{Contact, ContactModel, ContactType, GraspWrenchSpace, ObjectFrame, Wrench};
pub use error::{GraspError, Result};
pub use quality::hull::{ConvexHull, HullOptions};
pub use quality::{GraspQuality, QualityOptions, QualityReport, RobustEpsilon, RobustOptions};
