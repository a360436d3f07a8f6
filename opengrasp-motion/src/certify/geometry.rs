//! The model's primitives (balls, oriented boxes, cylinders) and lower bounds on their
//! distances.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use opengrasp_core::model::{Geometry, Shape};

use crate::validity::cover::slice_balls;

/// Ball spacing along a capsule's axis, as a fraction of its radius: the balls reach at most
/// `r (√(1 + 0.75²/4) − 1)` = 6.8 % of the radius beyond the capsule.
pub(super) const CAPSULE_SPACING: f64 = 0.75;

/// A convex primitive of the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Prim {
    /// Ball: centre, radius.
    Ball(Point3<f64>, f64),
    /// Oriented box: pose of its centre, half extents.
    Box(Isometry3<f64>, Vector3<f64>),
    /// Cylinder along the local z axis of its pose: pose of its centre, radius, half length.
    Cylinder(Isometry3<f64>, f64, f64),
}

impl Prim {
    pub(super) fn transformed(&self, pose: &Isometry3<f64>) -> Prim {
        match self {
            Prim::Ball(c, r) => Prim::Ball(pose * c, *r),
            Prim::Box(p, h) => Prim::Box(pose * p, *h),
            Prim::Cylinder(p, r, l) => Prim::Cylinder(pose * p, *r, *l),
        }
    }

    /// Centre and radius of a ball containing the primitive.
    pub(super) fn bounding_ball(&self) -> (Point3<f64>, f64) {
        match self {
            Prim::Ball(c, r) => (*c, *r),
            Prim::Box(p, h) => (p.translation.vector.into(), h.norm()),
            Prim::Cylinder(p, r, l) => (p.translation.vector.into(), r.hypot(*l)),
        }
    }
}

/// The primitives containing `shape` (in its parent frame).
pub(super) fn shape_prims(shape: &Shape) -> Vec<Prim> {
    match &shape.geometry {
        Geometry::Sphere { radius } => vec![Prim::Ball(shape.origin * Point3::origin(), *radius)],
        Geometry::Cylinder { radius, length } => vec![Prim::Cylinder(shape.origin, *radius, 0.5 * length)],
        Geometry::Capsule { radius, length } => {
            let n = ((length / (CAPSULE_SPACING * radius)).ceil() as usize).max(1);
            // The end caps are balls of the capsule's radius at the segment ends; the
            // cylinder between them is covered by slice balls.
            [-0.5 * length, 0.5 * length]
                .into_iter()
                .map(|z| Prim::Ball(shape.origin * Point3::new(0.0, 0.0, z), *radius))
                .chain(slice_balls(&shape.origin, *radius, *length, n).map(|(c, r)| Prim::Ball(c, r)))
                .collect()
        }
        g => {
            let (lo, hi) = g.local_aabb();
            let centre = nalgebra::center(&lo, &hi);
            vec![Prim::Box(shape.origin * Isometry3::translation(centre.x, centre.y, centre.z), 0.5 * (hi - lo))]
        }
    }
}

/// A primitive placed in the world: a ball (centre, radius) or an oriented box (centre,
/// rotation, half extents).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Placed {
    Ball(Vector3<f64>, f64),
    Box(Vector3<f64>, Matrix3<f64>, Vector3<f64>),
    /// Centre, rotation (axis: third column), radius, half length.
    Cylinder(Vector3<f64>, Matrix3<f64>, f64, f64),
}

impl Placed {
    pub(super) fn new(prim: &Prim, pose: &Isometry3<f64>) -> Self {
        match prim {
            Prim::Ball(c, r) => Placed::Ball((pose * c).coords, *r),
            Prim::Box(p, h) => {
                let p = pose * p;
                Placed::Box(p.translation.vector, p.rotation.to_rotation_matrix().into_inner(), *h)
            }
            Prim::Cylinder(p, r, l) => {
                let p = pose * p;
                Placed::Cylinder(p.translation.vector, p.rotation.to_rotation_matrix().into_inner(), *r, *l)
            }
        }
    }

    /// Centre and radius of a ball containing the primitive (as [`Prim::bounding_ball`]).
    pub(super) fn bounding_ball(&self) -> (Vector3<f64>, f64) {
        match self {
            Placed::Ball(c, r) => (*c, *r),
            Placed::Box(c, _, h) => (*c, h.norm()),
            Placed::Cylinder(c, _, r, l) => (*c, r.hypot(*l)),
        }
    }

    /// Lowest and highest world z of the primitive (`(c.z − e, c.z + e)` with `e` its support
    /// along z).
    pub(super) fn z_range(&self) -> (f64, f64) {
        let (z, e) = match self {
            Placed::Ball(c, r) => (c.z, *r),
            // Support of a box along z: Σ_k h_k |R_zk|.
            Placed::Box(c, r, h) => (c.z, h.x * r[(2, 0)].abs() + h.y * r[(2, 1)].abs() + h.z * r[(2, 2)].abs()),
            // Of a cylinder with unit axis a: l |a_z| + r √(1 − a_z²).
            Placed::Cylinder(c, rot, r, l) => {
                let az = rot[(2, 2)].clamp(-1.0, 1.0);
                (c.z, l * az.abs() + r * (1.0 - az * az).sqrt())
            }
        };
        (z - e, z + e)
    }
}

/// Distance from `p` to a box (0 inside).
pub(super) fn point_box(p: &Vector3<f64>, c: &Vector3<f64>, r: &Matrix3<f64>, h: &Vector3<f64>) -> f64 {
    let l = r.tr_mul(&(p - c));
    Vector3::new((l.x.abs() - h.x).max(0.0), (l.y.abs() - h.y).max(0.0), (l.z.abs() - h.z).max(0.0)).norm()
}

/// Distance from `p` to a cylinder (0 inside).
pub(super) fn point_cylinder(p: &Vector3<f64>, c: &Vector3<f64>, rot: &Matrix3<f64>, r: f64, l: f64) -> f64 {
    let q = rot.tr_mul(&(p - c));
    (q.x.hypot(q.y) - r).max(0.0).hypot((q.z.abs() - l).max(0.0))
}

/// Lower bound on the distance between two boxes: the largest gap along the 15 separating
/// axes (the gap along a unit axis never exceeds the distance). Stops at the first gap of at
/// least `enough`.
pub(super) fn box_box(
    (ca, ra, ha): (&Vector3<f64>, &Matrix3<f64>, &Vector3<f64>),
    (cb, rb, hb): (&Vector3<f64>, &Matrix3<f64>, &Vector3<f64>),
    enough: f64,
) -> f64 {
    // Everything in A's frame: B's axes are the columns of c, the centre offset is t.
    let c = ra.tr_mul(rb);
    let t = ra.tr_mul(&(cb - ca));
    let abs = c.abs();
    let mut best = f64::NEG_INFINITY;
    for i in 0..3 {
        let gap = t[i].abs() - ha[i] - (hb.x * abs[(i, 0)] + hb.y * abs[(i, 1)] + hb.z * abs[(i, 2)]);
        best = best.max(gap);
        if best >= enough {
            return best;
        }
    }
    for j in 0..3 {
        let gap = t.dot(&c.column(j)).abs() - (ha.x * abs[(0, j)] + ha.y * abs[(1, j)] + ha.z * abs[(2, j)]) - hb[j];
        best = best.max(gap);
        if best >= enough {
            return best;
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let axis = Vector3::ith(i, 1.0).cross(&c.column(j));
            let n = axis.norm();
            if n > 1e-9 {
                let u = axis / n;
                let radius_a = ha.x * u.x.abs() + ha.y * u.y.abs() + ha.z * u.z.abs();
                let radius_b = hb.x * u.dot(&c.column(0)).abs()
                    + hb.y * u.dot(&c.column(1)).abs()
                    + hb.z * u.dot(&c.column(2)).abs();
                best = best.max(u.dot(&t).abs() - radius_a - radius_b);
                if best >= enough {
                    return best;
                }
            }
        }
    }
    best
}

/// Support of a solid cylinder (unit axis `axis`, radius `r`, half length `l`, centred at the
/// origin) along the unit direction `u`: `l |a·u| + r √(1 − (a·u)²)`.
fn cylinder_support(axis: &Vector3<f64>, r: f64, l: f64, u: &Vector3<f64>) -> f64 {
    let c = axis.dot(u).clamp(-1.0, 1.0);
    l * c.abs() + r * (1.0 - c * c).max(0.0).sqrt()
}

/// Lower bound on the distance between a cylinder and a box: the largest gap along a few
/// separating axes (the gap along a unit axis never exceeds the distance), with the
/// cylinder's own support (not its box's): the direction from the box's point nearest the
/// cylinder's centre to that centre, the box's face normals, the cylinder's axis and its
/// cross products with the box's axes. Exact for an upright cylinder beside a face or a
/// vertical edge of a box it overlaps in height. Stops at the first gap of at least `enough`.
pub(super) fn cylinder_box(
    (c, rot, r, l): (&Vector3<f64>, &Matrix3<f64>, f64, f64),
    (cb, rb, hb): (&Vector3<f64>, &Matrix3<f64>, &Vector3<f64>),
    enough: f64,
) -> f64 {
    let axis = rot.column(2).into_owned();
    let t = cb - c;
    let gap = |u: &Vector3<f64>| {
        let box_support =
            hb.x * rb.column(0).dot(u).abs() + hb.y * rb.column(1).dot(u).abs() + hb.z * rb.column(2).dot(u).abs();
        t.dot(u).abs() - box_support - cylinder_support(&axis, r, l, u)
    };
    let mut best = f64::NEG_INFINITY;
    let local = rb.tr_mul(&(c - cb));
    let off = rb * (local - local.sup(&-hb).inf(hb));
    let n = off.norm();
    if n > 1e-12 {
        best = gap(&(off / n));
        if best >= enough {
            return best;
        }
    }
    for k in 0..3 {
        best = best.max(gap(&rb.column(k).into_owned()));
        if best >= enough {
            return best;
        }
    }
    best = best.max(gap(&axis));
    for k in 0..3 {
        let u = axis.cross(&rb.column(k));
        let n = u.norm();
        if best >= enough {
            return best;
        }
        if n > 1e-9 {
            best = best.max(gap(&(u / n)));
        }
    }
    best
}

/// Lower bound on the distance between two placed primitives (≤ 0 when they may overlap);
/// any value of at least `enough` may be returned once the bound reaches it.
pub(super) fn distance(a: &Placed, b: &Placed, enough: f64) -> f64 {
    match (a, b) {
        (Placed::Ball(c1, r1), Placed::Ball(c2, r2)) => (c1 - c2).norm() - r1 - r2,
        (Placed::Ball(p, rad), Placed::Box(c, r, h)) | (Placed::Box(c, r, h), Placed::Ball(p, rad)) => {
            point_box(p, c, r, h) - rad
        }
        (Placed::Ball(p, rad), Placed::Cylinder(c, rot, r, l))
        | (Placed::Cylinder(c, rot, r, l), Placed::Ball(p, rad)) => point_cylinder(p, c, rot, *r, *l) - rad,
        (Placed::Cylinder(c, rot, r, l), Placed::Box(cb, rb, hb))
        | (Placed::Box(cb, rb, hb), Placed::Cylinder(c, rot, r, l)) => {
            cylinder_box((c, rot, *r, *l), (cb, rb, hb), enough)
        }
        (Placed::Cylinder(c, rot, r, l), Placed::Cylinder(c2, rot2, r2, l2)) => {
            // The second one's bounding ball, then its box, against the first.
            let ball = point_cylinder(c2, c, rot, *r, *l) - r2.hypot(*l2);
            if ball >= enough {
                return ball;
            }
            cylinder_box((c, rot, *r, *l), (c2, rot2, &Vector3::new(*r2, *r2, *l2)), enough).max(ball)
        }
        (Placed::Box(c1, r1, h1), Placed::Box(c2, r2, h2)) => {
            // The first box's bounding ball against the second box, then the axes.
            let ball = point_box(c1, c2, r2, h2) - h1.norm();
            if ball >= enough {
                ball
            } else {
                box_box((c1, r1, h1), (c2, r2, h2), enough).max(ball)
            }
        }
    }
}
