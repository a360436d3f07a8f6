//! Forward kinematics compiled for one planning group: only the frames the group's joints
//! move, each its parent frame times a fixed 3×4 transform times one joint motion, in plain
//! `f64` arrays (no quaternions, no allocation). Links rigidly attached to a frame (fixed
//! joints, joints outside the group) ride on it. Sines and cosines are [`trig`]'s (plain
//! arithmetic, the same bits on every machine), a chain's joints at once.

use nalgebra::Isometry3;
use opengrasp_core::model::{JointGroup, JointKind, LinkId, Robot};

/// A rigid transform as a row-major 3×4 matrix `[R | t]`.
pub(super) type Mat34 = [f64; 12];

/// The identity transform.
pub(super) const IDENTITY: Mat34 = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// `a ∘ b`.
#[inline(always)]
pub(super) fn compose(a: &Mat34, b: &Mat34) -> Mat34 {
    let mut out = [0.0; 12];
    for r in 0..3 {
        let (a0, a1, a2, a3) = (a[4 * r], a[4 * r + 1], a[4 * r + 2], a[4 * r + 3]);
        for c in 0..3 {
            out[4 * r + c] = a0 * b[c] + a1 * b[4 + c] + a2 * b[8 + c];
        }
        out[4 * r + 3] = a0 * b[3] + a1 * b[7] + a2 * b[11] + a3;
    }
    out
}

/// The transform of an isometry.
pub(super) fn mat34(iso: &Isometry3<f64>) -> Mat34 {
    let m = iso.to_homogeneous();
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(0, 3)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(1, 3)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
        m[(2, 3)],
    ]
}

/// One moving frame: `parent ∘ fixed ∘ motion(scale · q[dof] + offset)`.
#[derive(Clone, Debug)]
struct Frame {
    /// Index of the parent frame (frame 0 is the world).
    parent: usize,
    fixed: Mat34,
    axis: [f64; 3],
    prismatic: bool,
    /// For a revolute joint about a coordinate axis `sign · e_i`: `(i, sign)`, which
    /// [`Frame::moved`] turns about with a third of the general composition's arithmetic.
    aligned: Option<(usize, f64)>,
    /// Index of the driving joint in the group's values.
    dof: usize,
    scale: f64,
    offset: f64,
    /// How [`Chain::frames`] composes the parent frame with `fixed`.
    place: Place,
}

/// How a frame's parent pose is composed with its fixed transform: the same numbers as
/// [`compose`], skipping products with the transform's exact zeros.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Place {
    /// The parent is the world (the identity): `compose(IDENTITY, fixed)`, computed once.
    World(Mat34),
    /// The fixed rotation leaves coordinate axis `e_i` alone (row and column `i` zero off the
    /// diagonal, as URDF origins turned about one axis are): [`compose_block`].
    Block(usize),
    /// Any other fixed transform: [`compose`].
    General,
}

impl Place {
    fn of(parent: usize, fixed: &Mat34) -> Self {
        if parent == 0 {
            return Self::World(compose(&IDENTITY, fixed));
        }
        let block = (0..3).find(|&i| (0..3).all(|m| m == i || (fixed[4 * i + m] == 0.0 && fixed[4 * m + i] == 0.0)));
        block.map_or(Self::General, Self::Block)
    }
}

/// [`compose`] for a `b` whose rotation has row and column `I` zero off the diagonal: the
/// products with those exact zeros dropped (adding `±0` to a sum leaves its value), so every
/// entry equals [`compose`]'s (up to the sign of a zero entry).
#[inline(always)]
fn compose_block<const I: usize>(a: &Mat34, b: &Mat34) -> Mat34 {
    let (i, j, k) = (I, (I + 1) % 3, (I + 2) % 3);
    let mut out = [0.0; 12];
    for r in (0..12).step_by(4) {
        let (ai, aj, ak) = (a[r + i], a[r + j], a[r + k]);
        out[r + i] = ai * b[4 * i + i];
        out[r + j] = aj * b[4 * j + j] + ak * b[4 * k + j];
        out[r + k] = aj * b[4 * j + k] + ak * b[4 * k + k];
        out[r + 3] = a[r] * b[3] + a[r + 1] * b[7] + a[r + 2] * b[11] + a[r + 3];
    }
    out
}

/// The compiled kinematics: frame 0 is the world (fixed), frames `1..` move.
#[derive(Clone, Debug)]
pub(super) struct Chain {
    frames: Vec<Frame>,
    /// Per link of the robot: its frame and its pose in that frame.
    links: Vec<(usize, Mat34)>,
}

impl Chain {
    /// The kinematics of `robot` at the base pose, moved by `group`, the other joints at
    /// `q_full` (a valid full configuration).
    pub fn new(robot: &Robot, group: &JointGroup, q_full: &[f64], base_pose: &Isometry3<f64>) -> Self {
        let mut links = vec![(0usize, IDENTITY); robot.links().len()];
        links[robot.root().0] = (0, mat34(base_pose));
        let mut frames = Vec::new();
        for &j in robot.joints_topological() {
            let joint = robot.joint(j);
            let (pf, parent) = links[joint.parent.0];
            let at_origin = compose(&parent, &mat34(&joint.origin));
            let driven = robot
                .driving_dof(j)
                .and_then(|(d, _)| group.dofs().iter().position(|&g| g == d).map(|gi| (d, gi)))
                .filter(|_| joint.kind != JointKind::Fixed);
            links[joint.child.0] = match driven {
                Some((d, gi)) => {
                    // The joint value is affine in the driving value: exact for direct joints
                    // (scale 1, offset 0), multiplier and offset for mimic joints.
                    let mut q = q_full.to_vec();
                    q[d] = 0.0;
                    let offset = robot.joint_position(&q, j);
                    q[d] = 1.0;
                    let scale = robot.joint_position(&q, j) - offset;
                    let axis = [joint.axis.x, joint.axis.y, joint.axis.z];
                    let prismatic = joint.kind == JointKind::Prismatic;
                    frames.push(Frame {
                        parent: pf,
                        fixed: at_origin,
                        axis,
                        prismatic,
                        aligned: if prismatic { None } else { coordinate_axis(axis) },
                        dof: gi,
                        scale,
                        offset,
                        place: Place::of(pf, &at_origin),
                    });
                    (frames.len(), IDENTITY)
                }
                None => (pf, compose(&at_origin, &mat34(&joint.motion(robot.joint_position(q_full, j))))),
            };
        }
        Self { frames, links }
    }

    /// The frame link `l` rides on and its pose in that frame.
    pub fn link(&self, l: LinkId) -> (usize, Mat34) {
        self.links[l.0]
    }

    /// Moving frame `f` (≥ 1): its parent frame, the group value driving it, and for a
    /// revolute joint its axis (in the frame's own coordinates, through its origin) and the
    /// joint's scale (joint angle = scale · value + offset); `None` for a prismatic joint.
    pub fn joint(&self, f: usize) -> (usize, usize, Option<([f64; 3], f64)>) {
        let fr = &self.frames[f - 1];
        (fr.parent, fr.dof, (!fr.prismatic).then_some((fr.axis, fr.scale)))
    }

    /// Moving frame `f`'s pose in its parent frame at driving value `q`.
    pub fn local(&self, f: usize, q: f64) -> Mat34 {
        let fr = &self.frames[f - 1];
        let v = fr.angle(q);
        let (s, c) = trig::sin_cos(v);
        fr.moved(&fr.fixed, v, s, c)
    }

    /// Everything [`Chain::local`] of frame `f` depends on, as numbers (to tell whether two
    /// chains move the frame alike).
    pub fn joint_key(&self, f: usize) -> impl Iterator<Item = f64> + '_ {
        let fr = &self.frames[f - 1];
        fr.fixed.iter().chain(&fr.axis).copied().chain([fr.scale, fr.offset, f64::from(u8::from(fr.prismatic))])
    }

    /// The world poses of every frame for group values `q` into `out` (frame 0 the identity).
    #[inline]
    pub fn frames(&self, q: &[f64], out: &mut Vec<Mat34>) {
        out.resize(self.frames.len() + 1, IDENTITY);
        out[0] = IDENTITY;
        for (first, chunk) in (1..).step_by(TRIG_BATCH).zip(self.frames.chunks(TRIG_BATCH)) {
            // The joints' sines and cosines first, together (they vectorise), then the poses.
            let mut angles = [0.0; TRIG_BATCH];
            for (v, f) in angles.iter_mut().zip(chunk) {
                *v = f.angle(q[f.dof]);
            }
            let (sin, cos) = trig::sin_cos_n(&angles);
            for (j, f) in chunk.iter().enumerate() {
                let m = match f.place {
                    Place::World(m) => m,
                    Place::Block(0) => compose_block::<0>(&out[f.parent], &f.fixed),
                    Place::Block(1) => compose_block::<1>(&out[f.parent], &f.fixed),
                    Place::Block(_) => compose_block::<2>(&out[f.parent], &f.fixed),
                    Place::General => compose(&out[f.parent], &f.fixed),
                };
                out[first + j] = f.moved(&m, angles[j], sin[j], cos[j]);
            }
        }
    }

    /// [`Chain::frames`] of [`LANES`] states at once, struct of arrays: `qs[d][l]` is group
    /// value `d` of state `l`, and `out[f][i][l]` entry `i` of frame `f`'s pose in state `l`.
    /// Every lane's arithmetic is the scalar one, operation for operation (so the poses are
    /// bit-identical), with the lanes innermost so the compositions vectorise.
    pub fn frames_lanes(&self, qs: &[Lanes], out: &mut Vec<[Lanes; 12]>) {
        out.clear();
        out.push(IDENTITY.map(|v| [v; LANES]));
        for f in &self.frames {
            let m = compose_lanes(&out[f.parent], &f.fixed.map(|v| [v; LANES]));
            if let Some((i, sign)) = f.aligned {
                let (s, c) = trig::sin_cos_n(&qs[f.dof].map(|q| f.angle(q)));
                let sc = [s.map(|s| s * sign), c];
                // The axis a compile-time constant, so the index arithmetic folds away.
                out.push(match i {
                    0 => turn_lanes::<0>(&m, &sc[0], &sc[1]),
                    1 => turn_lanes::<1>(&m, &sc[0], &sc[1]),
                    _ => turn_lanes::<2>(&m, &sc[0], &sc[1]),
                });
                continue;
            }
            let mut motion = [[0.0; LANES]; 12];
            for l in 0..LANES {
                let one = f.motion(qs[f.dof][l]);
                for (row, v) in motion.iter_mut().zip(one) {
                    row[l] = v;
                }
            }
            out.push(compose_lanes(&m, &motion));
        }
    }
}

/// Joints whose sines and cosines [`Chain::frames`] computes together.
const TRIG_BATCH: usize = 8;

/// States checked together by the batched kernels.
pub(super) const LANES: usize = 4;

/// One value per lane.
pub(super) type Lanes = [f64; LANES];

/// [`compose`] in every lane (same operations, lanes innermost).
#[inline(always)]
fn compose_lanes(a: &[Lanes; 12], b: &[Lanes; 12]) -> [Lanes; 12] {
    let mut out = [[0.0; LANES]; 12];
    for r in 0..3 {
        for c in 0..3 {
            for l in 0..LANES {
                out[4 * r + c][l] =
                    a[4 * r][l] * b[c][l] + a[4 * r + 1][l] * b[4 + c][l] + a[4 * r + 2][l] * b[8 + c][l];
            }
        }
        for l in 0..LANES {
            out[4 * r + 3][l] =
                a[4 * r][l] * b[3][l] + a[4 * r + 1][l] * b[7][l] + a[4 * r + 2][l] * b[11][l] + a[4 * r + 3][l];
        }
    }
    out
}

/// `(i, sign)` if `axis` is `sign · e_i` exactly (as URDF axes `0 0 1`, `0 -1 0` are).
fn coordinate_axis(axis: [f64; 3]) -> Option<(usize, f64)> {
    let i = axis.iter().position(|v| v.abs() == 1.0)?;
    let others_zero = axis.iter().enumerate().all(|(j, &v)| j == i || v == 0.0);
    others_zero.then_some((i, axis[i]))
}

/// `a ∘ R` for the rotation `R` about coordinate axis `e_i` with `ss` = sign · sin, `c` =
/// cos: the entries [`compose`] gives with [`Frame::motion`]'s Rodrigues matrix, bit for bit
/// (the terms multiplied by an exact zero dropped, `c + (1 − c)` kept as Rodrigues rounds it).
#[inline(always)]
fn turn<const I: usize>(a: &Mat34, ss: f64, c: f64) -> Mat34 {
    let (i, j, k) = (I, (I + 1) % 3, (I + 2) % 3);
    let d = c + (1.0 - c);
    let mut out = *a;
    for r in (0..12).step_by(4) {
        out[r + i] = a[r + i] * d;
        out[r + j] = a[r + j] * c + a[r + k] * ss;
        out[r + k] = a[r + k] * c - a[r + j] * ss;
    }
    out
}

/// [`turn`] in every lane (same operations, lanes innermost).
#[inline(always)]
fn turn_lanes<const I: usize>(a: &[Lanes; 12], ss: &Lanes, c: &Lanes) -> [Lanes; 12] {
    let (i, j, k) = (I, (I + 1) % 3, (I + 2) % 3);
    let mut out = *a;
    for r in (0..12).step_by(4) {
        for l in 0..LANES {
            let d = c[l] + (1.0 - c[l]);
            out[r + i][l] = a[r + i][l] * d;
            out[r + j][l] = a[r + j][l] * c[l] + a[r + k][l] * ss[l];
            out[r + k][l] = a[r + k][l] * c[l] - a[r + j][l] * ss[l];
        }
    }
    out
}

impl Frame {
    /// The joint value (angle or displacement) at driving value `q`.
    #[inline(always)]
    fn angle(&self, q: f64) -> f64 {
        self.scale * q + self.offset
    }

    /// `m ∘ motion` at joint value `v` (`s`, `c` its [`trig::sin_cos`]), the same numbers as
    /// [`compose`] with [`Frame::motion`] but cheaper for a joint about a coordinate axis.
    #[inline(always)]
    fn moved(&self, m: &Mat34, v: f64, s: f64, c: f64) -> Mat34 {
        match self.aligned {
            Some((i, sign)) => match i {
                0 => turn::<0>(m, s * sign, c),
                1 => turn::<1>(m, s * sign, c),
                _ => turn::<2>(m, s * sign, c),
            },
            None => compose(m, &self.motion_at(v, s, c)),
        }
    }

    /// The joint motion at driving value `q`.
    #[inline(always)]
    fn motion(&self, q: f64) -> Mat34 {
        let v = self.angle(q);
        let (s, c) = trig::sin_cos(v);
        self.motion_at(v, s, c)
    }

    /// The joint motion at joint value `v` (`s`, `c` its sine and cosine, unused for a
    /// prismatic joint).
    #[inline(always)]
    fn motion_at(&self, v: f64, s: f64, c: f64) -> Mat34 {
        let [x, y, z] = self.axis;
        if self.prismatic {
            [1.0, 0.0, 0.0, x * v, 0.0, 1.0, 0.0, y * v, 0.0, 0.0, 1.0, z * v]
        } else {
            // Rodrigues: R = cI + s[u]× + (1 − c)uuᵀ.
            let k = 1.0 - c;
            [
                c + k * x * x,
                k * x * y - s * z,
                k * x * z + s * y,
                0.0,
                k * x * y + s * z,
                c + k * y * y,
                k * y * z - s * x,
                0.0,
                k * x * z - s * y,
                k * y * z + s * x,
                c + k * z * z,
                0.0,
            ]
        }
    }
}

mod trig;

#[cfg(test)]
mod tests;
