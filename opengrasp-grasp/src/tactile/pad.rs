//! The matrix pad: geometry, force–compression characteristic and contact-to-cell mapping.

use nalgebra::{Isometry3, Point3};
use opengrasp_core::model::LinkId;
use serde::{Deserialize, Serialize};

use super::{LinkContact, PadReading, TactileSensor};
use crate::error::{GraspError, Result};

/// Cell layout of a matrix pad.
///
/// The pad frame: the sensing surface passes through the origin with outward normal +x;
/// columns run along +y (centred on the origin), rows along +z starting at `z = 0`. The first
/// `rows − curved_rows` rows are flat; the last `curved_rows` rows (a fingertip) bend
/// cylindrically away from +x about an axis parallel to y at radius `bend_radius`, so a cell's
/// row is found by arc length along the surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PadGeometry {
    /// Number of rows (along the finger).
    pub rows: usize,
    /// Number of columns (across the finger).
    pub columns: usize,
    /// Cell pitch (m), the same in both directions.
    pub pitch: f64,
    /// Number of rows (at the far end) lying on the curved tip section; 0 for a flat pad.
    pub curved_rows: usize,
    /// Radius (m) of the curved tip section (unused when `curved_rows` is 0).
    pub bend_radius: f64,
}

impl PadGeometry {
    /// Width of the sensing area across the columns (m).
    pub fn width(&self) -> f64 {
        self.columns as f64 * self.pitch
    }
    /// Length of the sensing area along the rows, measured along the surface (m).
    pub fn length(&self) -> f64 {
        self.rows as f64 * self.pitch
    }
    /// Arc length (m) where the flat section ends and the curved one starts.
    pub fn flat_length(&self) -> f64 {
        (self.rows - self.curved_rows.min(self.rows)) as f64 * self.pitch
    }
    /// Area of one cell (m²).
    pub fn cell_area(&self) -> f64 {
        self.pitch * self.pitch
    }
    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.rows * self.columns
    }

    /// Surface coordinates `(u, s, offset)` of a point given in the pad frame: `u` across the
    /// columns (0 on the centre line), `s` the arc length along the rows, `offset` the signed
    /// distance from the sensing surface along its outward normal. `None` for a point beyond
    /// the curved section's angular range (e.g. behind the fingertip).
    pub fn surface_coordinates(&self, p: &Point3<f64>) -> Option<(f64, f64, f64)> {
        let flat = self.flat_length();
        if self.curved_rows == 0 || p.z <= flat {
            return Some((p.y, p.z, p.x));
        }
        // Arc centre at (−R, ·, flat); the surface point at angle φ is
        // (−R + R cos φ, ·, flat + R sin φ) with outward normal (cos φ, 0, sin φ).
        let r = self.bend_radius;
        let (dx, dz) = (p.x + r, p.z - flat);
        let phi = dz.atan2(dx);
        let curved = self.length() - flat;
        // Accept a margin of one pitch past the sensing area's end (the patch may still reach it).
        if !(0.0..=(curved + self.pitch) / r).contains(&phi) {
            return None;
        }
        Some((p.y, flat + r * phi, dx.hypot(dz) - r))
    }

    /// Checks the layout.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] / [`GraspError::NonFinite`] for zero rows or columns,
    /// a non-positive pitch, more curved rows than rows, a non-positive bend radius with
    /// curved rows, or cell indices that do not fit `u32`.
    pub fn validate(&self) -> Result<()> {
        crate::error::ensure_finite("pad geometry", [self.pitch, self.bend_radius])?;
        let bad = |name, reason: String| Err(GraspError::InvalidParameter { name, reason });
        if self.rows == 0 || self.columns == 0 || self.cells() > u32::MAX as usize {
            return bad("rows", format!("{} × {} cells", self.rows, self.columns));
        }
        if self.pitch <= 0.0 {
            return bad("pitch", format!("{} is not positive", self.pitch));
        }
        if self.curved_rows > self.rows {
            return bad("curved_rows", format!("{} curved rows of {}", self.curved_rows, self.rows));
        }
        if self.curved_rows > 0 && self.bend_radius <= 0.0 {
            return bad("bend_radius", format!("{} is not positive", self.bend_radius));
        }
        Ok(())
    }
}

/// The linear force–compression characteristic of the pad's elastic layer and the
/// electronics' raw scale.
///
/// A cell carrying normal force `F` reads the pressure `p = F / A` (`A` = pitch²); the layer
/// compresses by the ratio `c = p / E` (linear: `E` is the layer's effective compressive
/// modulus); the module reports `raw = round(raw_max · min(c / c_sat, 1))`, so the raw value
/// saturates at the compression ratio `c_sat`, i.e. at the full-scale pressure `E · c_sat`.
///
/// The contact-patch kernel uses the same characteristic (see [`MatrixPad`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Characteristic {
    /// Effective compressive modulus `E` of the elastic layer (Pa).
    pub modulus: f64,
    /// Thickness `h` of the elastic layer (m).
    pub layer_thickness: f64,
    /// Compression ratio `c_sat` at which the raw value saturates (0 < c_sat ≤ 1).
    pub saturation_compression: f64,
    /// Largest raw value (4095 for the 12-bit DSA modules).
    pub raw_max: u16,
    /// Radius `R` (m) of the nominal indenter used for the contact-patch size of point contacts.
    pub indenter_radius: f64,
}

impl Characteristic {
    /// Full-scale (saturation) pressure `E · c_sat` (Pa).
    pub fn full_scale_pressure(&self) -> f64 {
        self.modulus * self.saturation_compression
    }

    /// Raw value of a cell under pressure `pressure` (Pa): `round(raw_max · min(p / p_fs, 1))`,
    /// 0 for non-positive or NaN pressures.
    pub fn raw(&self, pressure: f64) -> u16 {
        let x = pressure / self.full_scale_pressure();
        if x >= 1.0 {
            self.raw_max
        } else if x > 0.0 {
            (f64::from(self.raw_max) * x).round() as u16
        } else {
            0
        }
    }

    /// Indentation depth `δ` (m) of a point force `force` (N) on the nominal indenter: the
    /// indenter's footprint has area `2πRδ` and carries the layer pressure `E δ / h`, so
    /// `F = 2π R E δ² / h`; capped at the layer thickness.
    pub fn indentation(&self, force: f64) -> f64 {
        let d = (force * self.layer_thickness / (std::f64::consts::TAU * self.indenter_radius * self.modulus)).sqrt();
        d.min(self.layer_thickness)
    }

    /// Half side (m) of the square contact patch of a point force: the square of the same area
    /// as the indenter's footprint `2πRδ`.
    pub fn patch_half_side(&self, force: f64) -> f64 {
        0.5 * (std::f64::consts::TAU * self.indenter_radius * self.indentation(force)).sqrt()
    }

    /// Checks the constants.
    ///
    /// # Errors
    /// [`GraspError::NonFinite`] / [`GraspError::InvalidParameter`] unless every constant is
    /// finite and positive, `c_sat ≤ 1` and `raw_max > 0`.
    pub fn validate(&self) -> Result<()> {
        let v = [self.modulus, self.layer_thickness, self.saturation_compression, self.indenter_radius];
        crate::error::ensure_finite("tactile characteristic", v)?;
        if v.iter().any(|&x| x <= 0.0) || self.saturation_compression > 1.0 || self.raw_max == 0 {
            return Err(GraspError::InvalidParameter {
                name: "characteristic",
                reason: format!("constants must be positive (c_sat ≤ 1, raw_max > 0): {self:?}"),
            });
        }
        Ok(())
    }
}

/// A sensor model: cell layout plus characteristic (e.g. [`super::DSA_9335`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PadModel {
    /// Cell layout.
    pub geometry: PadGeometry,
    /// Force–compression characteristic and raw scale.
    pub characteristic: Characteristic,
}

/// A matrix pad on a link: the stock [`TactileSensor`].
///
/// **Mapping.** A contact on the pad's link is expressed in the pad frame and mapped to surface
/// coordinates `(u, s)` ([`PadGeometry::surface_coordinates`]: arc length on the curved tip);
/// contacts farther than `surface_tolerance` from the sensing surface (the back of a finger,
/// its sides) are ignored.
///
/// **Kernel.** A point contact of normal force `F` is spread uniformly over a square patch
/// centred on it whose area equals the footprint of a sphere of radius `R` (the
/// characteristic's nominal indenter) indenting the layer by `δ`, where the footprint's
/// pressure `E δ / h` balances the force: `F = 2π R E δ² / h` ([`Characteristic::indentation`]).
/// Several contacts sharing a patch id (the points of one contact manifold, e.g. a flat face)
/// spread their summed force uniformly over the bounding box of their surface coordinates,
/// widened to at least the patch of a point contact of that force. Each cell receives the
/// force times the fraction of the patch it overlaps (exact box integrals), so
///
/// * the forces of the cells sum to the applied force exactly (to rounding) when the patch
///   lies inside the sensing area; the part of a patch outside it is not read (the documented
///   error: at most the applied force times the patch fraction beyond the edge);
/// * a small force at a cell centre lights that cell alone, one on the line between two cells
///   splits equally between them.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixPad {
    name: String,
    link: LinkId,
    /// Link frame → pad frame.
    pad_from_link: Isometry3<f64>,
    model: PadModel,
    surface_tolerance: f64,
}

/// Default largest distance (m) of a contact from the sensing surface for it to be read.
pub const DEFAULT_SURFACE_TOLERANCE: f64 = 0.005;

impl MatrixPad {
    /// A pad named `name` on `link`, its frame at `pose` in the link frame.
    ///
    /// # Errors
    /// Invalid geometry or characteristic ([`PadGeometry::validate`],
    /// [`Characteristic::validate`]), a non-finite pose.
    pub fn new(name: impl Into<String>, link: LinkId, pose: Isometry3<f64>, model: PadModel) -> Result<Self> {
        model.geometry.validate()?;
        model.characteristic.validate()?;
        crate::error::ensure_finite(
            "pad pose",
            pose.translation.vector.iter().chain(pose.rotation.coords.iter()).copied(),
        )?;
        Ok(Self {
            name: name.into(),
            link,
            pad_from_link: pose.inverse(),
            model,
            surface_tolerance: DEFAULT_SURFACE_TOLERANCE,
        })
    }

    /// The same pad reading contacts up to `tolerance` (m) from its surface (default
    /// [`DEFAULT_SURFACE_TOLERANCE`]); a negative or NaN tolerance reads nothing.
    #[must_use]
    pub fn with_surface_tolerance(mut self, tolerance: f64) -> Self {
        self.surface_tolerance = tolerance;
        self
    }

    /// The sensor model.
    pub fn model(&self) -> &PadModel {
        &self.model
    }

    /// Surface coordinates `(u, s)` of a contact point in the link frame, if it lies on the
    /// sensing surface (within the tolerance).
    pub fn map_point(&self, point_in_link: &Point3<f64>) -> Option<(f64, f64)> {
        let p = self.pad_from_link * point_in_link;
        let (u, s, off) = self.model.geometry.surface_coordinates(&p)?;
        (off.abs() <= self.surface_tolerance).then_some((u, s))
    }

    /// Adds `force` spread uniformly over the rectangle `[u0, u1] × [s0, s1]` (surface
    /// coordinates) to the cells it overlaps.
    fn deposit(&self, force: &mut [f64], (u0, u1): (f64, f64), (s0, s1): (f64, f64), f: f64) {
        let g = &self.model.geometry;
        let p = g.pitch;
        let (x0, x1) = (u0 / p + 0.5 * g.columns as f64, u1 / p + 0.5 * g.columns as f64);
        let (y0, y1) = (s0 / p, s1 / p);
        let (wx, wy) = (x1 - x0, y1 - y0);
        if !(wx > 0.0 && wy > 0.0) {
            return;
        }
        let c0 = x0.floor().max(0.0) as usize;
        let c1 = (x1.ceil().min(g.columns as f64) as usize).max(c0);
        let r0 = y0.floor().max(0.0) as usize;
        let r1 = (y1.ceil().min(g.rows as f64) as usize).max(r0);
        let scale = f / (wx * wy);
        for r in r0..r1 {
            let oy = (y1.min(r as f64 + 1.0) - y0.max(r as f64)).max(0.0);
            if oy == 0.0 {
                continue;
            }
            let row = &mut force[r * g.columns..(r + 1) * g.columns];
            for (c, cell) in row.iter_mut().enumerate().take(c1).skip(c0) {
                let ox = (x1.min(c as f64 + 1.0) - x0.max(c as f64)).max(0.0);
                *cell += scale * ox * oy;
            }
        }
    }
}

fn usable(c: &LinkContact) -> bool {
    c.force.is_finite() && c.force > 0.0 && c.point.iter().all(|x| x.is_finite())
}

impl TactileSensor for MatrixPad {
    fn name(&self) -> &str {
        &self.name
    }

    fn link(&self) -> LinkId {
        self.link
    }

    fn shape(&self) -> (usize, usize) {
        (self.model.geometry.rows, self.model.geometry.columns)
    }

    fn read(&self, contacts: &[LinkContact], out: &mut PadReading) {
        let g = &self.model.geometry;
        let ch = &self.model.characteristic;
        out.reset(g.rows, g.columns);
        for (i, c) in contacts.iter().enumerate() {
            if c.link != self.link {
                continue;
            }
            if !usable(c) {
                out.ignored += 1;
                continue;
            }
            // Points of one patch are handled together at the patch's first point.
            if c.patch != 0 && contacts[..i].iter().any(|d| d.link == self.link && d.patch == c.patch && usable(d)) {
                continue;
            }
            let members = contacts[i..].iter().filter(|d| {
                d.link == self.link && usable(d) && (std::ptr::eq(*d, c) || (c.patch != 0 && d.patch == c.patch))
            });
            let (mut u0, mut u1, mut s0, mut s1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
            let mut total = 0.0;
            for d in members {
                match self.map_point(&d.point) {
                    Some((u, s)) => {
                        total += d.force;
                        (u0, u1, s0, s1) = (u0.min(u), u1.max(u), s0.min(s), s1.max(s));
                    }
                    None => out.ignored += 1,
                }
            }
            if total <= 0.0 {
                continue;
            }
            let b = ch.patch_half_side(total);
            let widen = |lo: f64, hi: f64| {
                let (m, h) = (0.5 * (lo + hi), (0.5 * (hi - lo)).max(b));
                (m - h, m + h)
            };
            self.deposit(&mut out.force, widen(u0, u1), widen(s0, s1), total);
        }
        let area = g.cell_area();
        for ((f, p), r) in out.force.iter().zip(out.pressure.iter_mut()).zip(out.raw.iter_mut()) {
            *p = (f / area).min(ch.full_scale_pressure());
            *r = ch.raw(f / area);
        }
    }
}
