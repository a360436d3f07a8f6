//! Small JSON description files (hand specs, object metadata): bounded reading, paths relative
//! to the file, and the serde formats they share.

use std::io::Read;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use crate::error::{CoreError, Result};

/// Largest description file accepted (1 MiB): they are a few hundred bytes, so anything larger
/// is a mistake (or hostile) and is refused before it is read.
pub const MAX_SPEC_BYTES: u64 = 1 << 20;

/// Reads a file of at most `limit` bytes. The limit is enforced on the bytes actually read,
/// so pipes and devices (which report no size) are bounded too.
///
/// # Errors
/// [`CoreError::Io`] if the file cannot be read, [`CoreError::FileTooLarge`] past `limit`.
pub fn read_bytes_limited(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let io = |source| CoreError::Io { path: path.to_path_buf(), source };
    let mut bytes = Vec::new();
    std::fs::File::open(path).map_err(io)?.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(CoreError::FileTooLarge { path: path.to_path_buf(), limit });
    }
    Ok(bytes)
}

/// As [`read_bytes_limited`], for UTF-8 text.
///
/// # Errors
/// As [`read_bytes_limited`]; [`CoreError::Io`] for text that is not UTF-8.
pub fn read_text_limited(path: &Path, limit: u64) -> Result<String> {
    String::from_utf8(read_bytes_limited(path, limit)?).map_err(|e| CoreError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
    })
}

/// Parses a JSON description file into `T`.
///
/// # Errors
/// As [`read_text_limited`]; [`CoreError::MalformedSpec`] for JSON that is not a `T`.
pub fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let text = read_text_limited(path, MAX_SPEC_BYTES)?;
    serde_json::from_str(&text).map_err(|e| malformed(path, e))
}

/// `relative` taken relative to the directory of `file` (absolute paths stay as they are).
pub fn relative_to(file: &Path, relative: impl AsRef<Path>) -> PathBuf {
    file.parent().unwrap_or(Path::new("")).join(relative)
}

fn malformed(path: &Path, reason: impl ToString) -> CoreError {
    CoreError::MalformedSpec { path: path.to_path_buf(), reason: reason.to_string() }
}

/// Serde format of `Vec<(String, f64)>` as a JSON object `{"name": value, ...}`, in order.
pub mod named_values {
    use std::fmt;

    use serde::de::{MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use serde::{Deserializer, Serializer};

    /// Serialises the pairs as a map.
    pub fn serialize<S: Serializer>(pairs: &[(String, f64)], s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(pairs.len()))?;
        for (k, v) in pairs {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }

    /// Reads a map into pairs in document order; a repeated name is an error.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<(String, f64)>, D::Error> {
        struct Pairs;
        impl<'de> Visitor<'de> for Pairs {
            type Value = Vec<(String, f64)>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of names to numbers")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out: Vec<(String, f64)> = Vec::new();
                while let Some((k, v)) = map.next_entry::<String, f64>()? {
                    if out.iter().any(|(n, _)| *n == k) {
                        return Err(serde::de::Error::custom(format!("`{k}` appears twice")));
                    }
                    out.push((k, v));
                }
                Ok(out)
            }
        }
        d.deserialize_map(Pairs)
    }
}

/// Serde format of an `Isometry3<f64>` as URDF writes an origin: `{"xyz": [x, y, z], "rpy":
/// [roll, pitch, yaw]}` (m, rad; fixed-axis roll-pitch-yaw; either key may be left out).
pub mod xyz_rpy {
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Origin {
        #[serde(default)]
        xyz: [f64; 3],
        #[serde(default)]
        rpy: [f64; 3],
    }

    /// Writes `{"xyz", "rpy"}`.
    pub fn serialize<S: Serializer>(pose: &Isometry3<f64>, s: S) -> Result<S::Ok, S::Error> {
        let t = pose.translation.vector;
        let (r, p, y) = pose.rotation.euler_angles();
        Origin { xyz: [t.x, t.y, t.z], rpy: [r, p, y] }.serialize(s)
    }

    /// Reads `{"xyz", "rpy"}`.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Isometry3<f64>, D::Error> {
        let o = Origin::deserialize(d)?;
        let [x, y, z] = o.xyz;
        let [roll, pitch, yaw] = o.rpy;
        Ok(Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(roll, pitch, yaw)))
    }
}
