//! Sensor presets (Weiss Robotics DSA 9335 / DSA 9330) and the pad layouts of the stock hands.
//!
//! **Datasheet figures** (Weiss Robotics DSA 9335 / DSA 9330 tactile sensor modules, as fitted
//! to the Schunk SDH; OpenGRASP paper reference \[43\]): DSA 9335 6 × 14 cells at 3.4 mm pitch,
//! sensing area 20.4 × 47.6 mm (SDH proximal phalanx); DSA 9330 6 × 13 cells at 3.4 mm pitch
//! with a curved (cylindrical) tip section (SDH distal phalanx); 12-bit raw values 0 ..= 4095;
//! a silicone elastic layer a few millimetres thick.
//!
//! **Nominal values** (no datasheet number available to us; chosen to be plausible and
//! documented here so results can be compared): elastic layer thickness 3 mm, effective
//! compressive modulus 1 MPa, raw saturation at a compression ratio of 0.25 (full scale
//! 250 kPa, i.e. 2.89 N on one 3.4 mm cell), nominal indenter radius 5 mm for the patch kernel;
//! of the DSA 9330's 13 rows the last 5 lie on the curved tip, of radius 11 mm on the SDH
//! (half the modelled finger thickness). Every number of the Barrett and ARMAR-III layouts is
//! nominal (see [`barrett_specs`], [`armar3_specs`]).

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::{Characteristic, PadGeometry, PadModel};

/// The DSA modules' characteristic: 12-bit raw scale (datasheet); modulus, layer thickness,
/// saturation and indenter nominal (see the module docs).
pub const DSA_CHARACTERISTIC: Characteristic = Characteristic {
    modulus: 1.0e6,
    layer_thickness: 0.003,
    saturation_compression: 0.25,
    raw_max: 4095,
    indenter_radius: 0.005,
};

/// Weiss Robotics DSA 9335 (SDH proximal phalanx): 6 × 14 cells, 3.4 mm pitch, flat.
pub const DSA_9335: PadModel = PadModel {
    geometry: PadGeometry { rows: 14, columns: 6, pitch: 0.0034, curved_rows: 0, bend_radius: 0.0 },
    characteristic: DSA_CHARACTERISTIC,
};

/// Weiss Robotics DSA 9330 (SDH distal phalanx): 6 × 13 cells, 3.4 mm pitch, the last 5 rows
/// (nominal) on a cylindrical tip of radius 11 mm (nominal).
pub const DSA_9330: PadModel = PadModel {
    geometry: PadGeometry { rows: 13, columns: 6, pitch: 0.0034, curved_rows: 5, bend_radius: 0.011 },
    characteristic: DSA_CHARACTERISTIC,
};

/// Characteristic of the Barrett hand's optional capacitive pads (all nominal: full scale
/// 100 kPa, 12-bit scale, 3 mm layer).
pub const BARRETT_CHARACTERISTIC: Characteristic = Characteristic {
    modulus: 0.5e6,
    layer_thickness: 0.003,
    saturation_compression: 0.2,
    raw_max: 4095,
    indenter_radius: 0.005,
};

/// A matrix pad on a named link: what [`super::TactileArray::from_specs`] builds pads from
/// (serde, so layouts can live in JSON files next to a hand's spec).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PadSpec {
    /// Pad name (unique within a hand).
    pub name: String,
    /// Link name.
    pub link: String,
    /// Pad frame in the link frame (see [`PadGeometry`]: surface at x = 0, outward normal +x,
    /// columns along y centred, rows along +z from z = 0).
    pub pose: Isometry3<f64>,
    /// Sensor model.
    pub model: PadModel,
}

/// Pad frame on the +x face (at `x = surface`) of a phalanx along +z, first row at `z0`.
fn on_plus_x(surface: f64, z0: f64) -> Isometry3<f64> {
    Isometry3::translation(surface, 0.0, z0)
}

/// A pad frame whose normal, column and row axes are the given link-frame axes.
fn frame(origin: [f64; 3], normal: [f64; 3], column: [f64; 3], row: [f64; 3]) -> Isometry3<f64> {
    let m = Matrix3::from_columns(&[normal.into(), column.into(), row.into()]);
    let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m));
    Isometry3::from_parts(Translation3::new(origin[0], origin[1], origin[2]), r)
}

/// The Schunk SDH as delivered with tactile sensing (names prefixed with `prefix`): a DSA 9335
/// on the inner (+x) face of each proximal phalanx, centred along it, and a DSA 9330 on each
/// distal phalanx whose curved rows wrap the fingertip (geometry of `opengrasp-assets`'
/// `sdh()`: phalanges 86.5 mm and 69.2 mm long, 22 mm thick, 12 mm joint gap).
pub fn sdh_specs(prefix: &str) -> Vec<PadSpec> {
    const THICK: f64 = 0.022;
    const PHALANX: f64 = 0.0865;
    const GAP: f64 = 0.012;
    let prox_z0 = GAP + 0.5 * (PHALANX - GAP) - 0.5 * DSA_9335.geometry.length();
    // The tip arc ends at the phalanx's end: its centre lies one bend radius below it.
    let g = DSA_9330.geometry;
    let dist_z0 = 0.8 * PHALANX - g.bend_radius - g.flat_length();
    ["f1", "f2", "f3"]
        .iter()
        .flat_map(|f| {
            [
                PadSpec {
                    name: format!("{f}_proximal"),
                    link: format!("{prefix}{f}_proximal"),
                    pose: on_plus_x(THICK / 2.0, prox_z0),
                    model: DSA_9335,
                },
                PadSpec {
                    name: format!("{f}_distal"),
                    link: format!("{prefix}{f}_distal"),
                    pose: on_plus_x(THICK / 2.0, dist_z0),
                    model: DSA_9330,
                },
            ]
        })
        .collect()
}

/// The Barrett BH8-262's optional tactile pads (all numbers nominal): a 3 × 8 pad at 5 mm
/// pitch on the inner face of each distal phalanx (fingertip, from its joint end) and a 4 × 6 pad at 8 mm pitch on
/// the palm (24 cells each, as the BH8 tactile option), with [`BARRETT_CHARACTERISTIC`].
pub fn barrett_specs(prefix: &str) -> Vec<PadSpec> {
    let tip = PadModel {
        geometry: PadGeometry { rows: 8, columns: 3, pitch: 0.005, curved_rows: 0, bend_radius: 0.0 },
        characteristic: BARRETT_CHARACTERISTIC,
    };
    let palm = PadModel {
        geometry: PadGeometry { rows: 6, columns: 4, pitch: 0.008, curved_rows: 0, bend_radius: 0.0 },
        characteristic: BARRETT_CHARACTERISTIC,
    };
    // Distal phalanx: 58 mm long, 16.2 mm thick, 10 mm joint gap; the pad covers the inner
    // face from the joint end (where a wrapped object meets the fingertip).
    let tip_z0 = 0.01;
    let mut specs: Vec<PadSpec> = ["f1", "f2", "f3"]
        .iter()
        .map(|f| PadSpec {
            name: format!("{f}_distal"),
            link: format!("{prefix}{f}_distal"),
            pose: on_plus_x(0.5 * 0.9 * 0.018, tip_z0),
            model: tip,
        })
        .collect();
    // Palm face z = 0 (normal +z), rows from +x (towards F1/F2) to -x (F3), centred.
    let half = 0.5 * palm.geometry.length();
    specs.push(PadSpec {
        name: "palm".into(),
        link: format!("{prefix}palm"),
        pose: frame([half, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]),
        model: palm,
    });
    specs
}

/// The ARMAR-III hand (right hand, `armar3_hand()`), all numbers nominal: DSA-like pads
/// (3.4 mm pitch, [`DSA_CHARACTERISTIC`]) on the inner face of every finger phalanx (4 columns,
/// as many rows as fit) and of both thumb phalanges (5 columns), and a 12 × 14 pad at 5 mm
/// pitch on the palm.
pub fn armar3_specs(prefix: &str) -> Vec<PadSpec> {
    const PITCH: f64 = 0.0034;
    const GAP: f64 = 0.004;
    let model = |rows: usize, columns: usize, pitch: f64| PadModel {
        geometry: PadGeometry { rows, columns, pitch, curved_rows: 0, bend_radius: 0.0 },
        characteristic: DSA_CHARACTERISTIC,
    };
    let mut specs = Vec::new();
    let fingers: [(&str, [f64; 3]); 4] = [
        ("index", [0.045, 0.026, 0.022]),
        ("middle", [0.048, 0.028, 0.022]),
        ("ring", [0.045, 0.026, 0.022]),
        ("pinky", [0.040, 0.022, 0.020]),
    ];
    for (f, lens) in fingers {
        for (k, len) in lens.iter().enumerate() {
            let rows = ((len - GAP) / PITCH).floor() as usize;
            let z0 = GAP + 0.5 * (len - GAP - rows as f64 * PITCH);
            specs.push(PadSpec {
                name: format!("{f}_{}", k + 1),
                link: format!("{prefix}{f}_{}", k + 1),
                pose: on_plus_x(0.5 * 0.017, z0),
                model: model(rows, 4, PITCH),
            });
        }
    }
    // Thumb phalanges flex towards their local -y (the flexion axis is local x).
    for (k, (len, gap)) in [(0.045, 0.012), (0.032, GAP)].into_iter().enumerate() {
        let rows = ((len - gap) / PITCH).floor() as usize;
        let z0 = gap + 0.5 * (len - gap - rows as f64 * PITCH);
        specs.push(PadSpec {
            name: format!("thumb_{}", k + 1),
            link: format!("{prefix}thumb_{}", k + 1),
            pose: frame([0.0, -0.5 * 0.017 * 1.1, z0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            model: model(rows, 5, PITCH),
        });
    }
    // Palm: face x = 15 mm, 95 mm long from the wrist (z = 0), rows along +z, centred.
    let palm = model(14, 12, 0.005);
    specs.push(PadSpec {
        name: "palm".into(),
        link: format!("{prefix}palm"),
        pose: on_plus_x(0.015, 0.5 * (0.095 - palm.geometry.length())),
        model: palm,
    });
    specs
}

/// The stock layout for a robot name of `opengrasp-assets`' stock hands (`schunk_sdh`,
/// `barrett_bh8_262` with its optional pads, `armar3_hand`).
pub fn stock_specs(robot_name: &str) -> Option<Vec<PadSpec>> {
    match robot_name {
        "schunk_sdh" => Some(sdh_specs("")),
        "barrett_bh8_262" => Some(barrett_specs("")),
        "armar3_hand" => Some(armar3_specs("")),
        _ => None,
    }
}
