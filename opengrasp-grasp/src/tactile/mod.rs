//! Tactile sensor simulation: matrix pads on hand links read contact forces as cell pressures
//! and raw values, after the OpenGRASP tactile plugin (Ulbrich et al. 2011, section III-C):
//! "simulation models of the Weiss Robotics DSA 9330 and DSA 9335 tactile matrix sensor
//! modules … the mapping of contact locations to the sensor matrix cells of the sensing
//! surface … a linear characteristic between contact force and compression ratio of the
//! deformable sensing surface to emulate pressure readings similar to the real sensor".
//!
//! * A [`TactileSensor`] (object safe, `Send + Sync`: implement it for your own sensor types)
//!   turns the [`LinkContact`]s of its link into a [`PadReading`]. The stock one is the
//!   [`MatrixPad`]: a rectangular cell grid, optionally with a cylindrically curved tip
//!   section, a linear force–compression [`Characteristic`] and a documented contact-patch
//!   kernel (see [`MatrixPad`]).
//! * Presets: [`DSA_9335`] and [`DSA_9330`]; stock layouts for the Schunk SDH (fitted with
//!   them as on the real hand), the Barrett BH8-262 (its optional tactile pads) and the
//!   ARMAR-III hand ([`stock`]).
//! * A [`TactileArray`] holds the pads of a hand and reads a whole [`TactileFrame`].
//! * Two contact sources ([`sources`]): the static grasp evaluator (contacts of a
//!   [`GraspEvaluation`](crate::evaluator::GraspEvaluation) with normal forces from the force
//!   closure solver's force distribution for a given grip force) and a physics engine
//!   (contact normal forces per link each step), whence a tactile time series of a simulated
//!   grasp ([`sources::physics_tactile_series`]).
//! * [`CompactFrame`]: nonzero raw cells per pad, the form stored in results files.
//!
//! ```
//! use nalgebra::{Isometry3, Point3};
//! use opengrasp_core::model::LinkId;
//! use opengrasp_grasp::tactile::{LinkContact, MatrixPad, PadReading, TactileSensor, DSA_9335};
//!
//! # fn main() -> opengrasp_grasp::Result<()> {
//! let pad = MatrixPad::new("proximal", LinkId(1), Isometry3::identity(), DSA_9335)?;
//! // 0.5 N at the centre of the cell in row 2, column 3 (pad frame = link frame here).
//! let pitch = DSA_9335.geometry.pitch;
//! let contact = LinkContact::point(LinkId(1), Point3::new(0.0, 0.5 * pitch, 2.5 * pitch), 0.5);
//! let mut reading = PadReading::default();
//! pad.read(&[contact], &mut reading);
//! assert!((reading.force[2 * 6 + 3] - 0.5).abs() < 1e-12);
//! assert_eq!(reading.raw[2 * 6 + 3], 708); // 0.5 N / (3.4 mm)² = 43.3 kPa of 250 kPa full scale
//! # Ok(())
//! # }
//! ```

mod pad;
pub mod sources;
pub mod stock;

use nalgebra::Point3;
use opengrasp_core::hand::Hand;
use opengrasp_core::model::LinkId;
use serde::{Deserialize, Serialize};

pub use pad::{Characteristic, MatrixPad, PadGeometry, PadModel, DEFAULT_SURFACE_TOLERANCE};
pub use stock::{PadSpec, DSA_9330, DSA_9335};

use crate::error::Result;

/// A contact force on a hand link, the input of every [`TactileSensor`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkContact {
    /// The link touched.
    pub link: LinkId,
    /// Contact point in the link frame (m).
    pub point: Point3<f64>,
    /// Normal force pressing on the link (N); non-positive or non-finite forces are ignored.
    pub force: f64,
    /// Patch id: contacts on the same link sharing a non-zero id are the points of one contact
    /// area (a contact manifold), read as their summed force spread over their extent; 0 is a
    /// point contact.
    pub patch: u32,
}

impl LinkContact {
    /// A point contact.
    pub fn point(link: LinkId, point: Point3<f64>, force: f64) -> Self {
        Self { link, point, force, patch: 0 }
    }
}

/// One pad's reading, cells in row-major order (`index = row × columns + column`, row 0 at
/// the pad's proximal end).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PadReading {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub columns: usize,
    /// Normal force per cell (N), before saturation: they sum to the force read.
    pub force: Vec<f64>,
    /// Pressure per cell (Pa) as the sensor reports it: saturates at the full-scale pressure.
    pub pressure: Vec<f64>,
    /// The module's raw value per cell (0 ..= raw max, saturating).
    pub raw: Vec<u16>,
    /// Contacts on the pad's link that were not read (off the sensing surface, non-finite or
    /// non-positive force).
    pub ignored: u32,
}

impl PadReading {
    /// Clears the reading for a `rows × columns` pad, reusing its buffers.
    pub fn reset(&mut self, rows: usize, columns: usize) {
        let n = rows * columns;
        self.rows = rows;
        self.columns = columns;
        for v in [&mut self.force, &mut self.pressure] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.raw.clear();
        self.raw.resize(n, 0);
        self.ignored = 0;
    }

    /// Total force read (N), the sum of the cell forces.
    pub fn total_force(&self) -> f64 {
        self.force.iter().sum()
    }

    /// Number of cells with a non-zero raw value.
    pub fn active_cells(&self) -> usize {
        self.raw.iter().filter(|&&r| r > 0).count()
    }
}

/// A tactile sensor on one link. Object safe: a [`TactileArray`] holds any mix of them.
pub trait TactileSensor: Send + Sync + std::fmt::Debug {
    /// The sensor's name (unique within an array, e.g. `"f1_distal"`).
    fn name(&self) -> &str;
    /// The link it is attached to.
    fn link(&self) -> LinkId;
    /// `(rows, columns)` of its cell grid.
    fn shape(&self) -> (usize, usize);
    /// Reads the contacts (all links; the sensor picks those on its link) into `out`,
    /// replacing its content. Never panics on bad contacts: they are skipped.
    fn read(&self, contacts: &[LinkContact], out: &mut PadReading);
}

/// The readings of every pad of an array at one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TactileFrame {
    /// Simulation time (s), 0 for static frames.
    pub time: f64,
    /// One reading per pad, in the array's order.
    pub pads: Vec<PadReading>,
}

impl TactileFrame {
    /// The compact form: nonzero raw cells per pad, time rounded to the microsecond.
    pub fn compact(&self, array: &TactileArray) -> CompactFrame {
        CompactFrame {
            time: (self.time * 1e6).round() / 1e6,
            pads: array
                .sensors()
                .iter()
                .zip(&self.pads)
                .map(|(s, r)| CompactPad {
                    name: s.name().to_string(),
                    rows: r.rows as u32,
                    columns: r.columns as u32,
                    cells: r
                        .raw
                        .iter()
                        .enumerate()
                        .filter(|(_, &v)| v > 0)
                        .map(|(i, &v)| [i as u32, u32::from(v)])
                        .collect(),
                })
                .collect(),
        }
    }
}

/// A frame as stored in results files: per pad its shape and the nonzero cells as
/// `[index, raw]` pairs (row-major index).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CompactFrame {
    /// Simulation time (s), 0 for static frames.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub time: f64,
    /// The pads.
    pub pads: Vec<CompactPad>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// One pad of a [`CompactFrame`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CompactPad {
    /// Pad name.
    pub name: String,
    /// Rows.
    pub rows: u32,
    /// Columns.
    pub columns: u32,
    /// Nonzero cells as `[row-major index, raw value]`.
    pub cells: Vec<[u32; 2]>,
}

impl CompactPad {
    /// The full raw grid (row-major), ignoring out-of-range indices.
    pub fn dense(&self) -> Vec<u32> {
        let mut out = vec![0; self.rows as usize * self.columns as usize];
        for &[i, v] in &self.cells {
            if let Some(x) = out.get_mut(i as usize) {
                *x = v;
            }
        }
        out
    }
}

/// The tactile pads of a hand.
#[derive(Debug, Default)]
pub struct TactileArray {
    sensors: Vec<Box<dyn TactileSensor>>,
}

impl TactileArray {
    /// An array of the given sensors.
    pub fn new(sensors: Vec<Box<dyn TactileSensor>>) -> Self {
        Self { sensors }
    }

    /// Matrix pads on `hand` from their specs (link names resolved on the hand's robot).
    ///
    /// # Errors
    /// [`crate::GraspError::Core`] for an unknown link, the errors of [`MatrixPad::new`].
    pub fn from_specs(hand: &Hand, specs: &[PadSpec]) -> Result<Self> {
        let mut sensors: Vec<Box<dyn TactileSensor>> = Vec::with_capacity(specs.len());
        for s in specs {
            let link = hand.robot().link_id(&s.link)?;
            sensors.push(Box::new(MatrixPad::new(s.name.clone(), link, s.pose, s.model)?));
        }
        Ok(Self { sensors })
    }

    /// The stock layout of a stock hand (recognised by its robot's name, see [`stock`]), or
    /// `None` for other hands. The Barrett hand gets its optional tactile pads.
    pub fn stock(hand: &Hand) -> Option<Self> {
        let specs = stock::stock_specs(hand.robot().name())?;
        Self::from_specs(hand, &specs).ok()
    }

    /// Adds a sensor.
    pub fn push(&mut self, sensor: Box<dyn TactileSensor>) {
        self.sensors.push(sensor);
    }

    /// The sensors.
    pub fn sensors(&self) -> &[Box<dyn TactileSensor>] {
        &self.sensors
    }

    /// Reads every pad into `out` (reusing its buffers).
    pub fn read_into(&self, contacts: &[LinkContact], out: &mut TactileFrame) {
        out.pads.resize_with(self.sensors.len(), PadReading::default);
        for (s, r) in self.sensors.iter().zip(&mut out.pads) {
            s.read(contacts, r);
        }
    }

    /// Reads every pad.
    pub fn read(&self, contacts: &[LinkContact]) -> TactileFrame {
        let mut out = TactileFrame::default();
        self.read_into(contacts, &mut out);
        out
    }
}
