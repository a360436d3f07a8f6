//! numpy ⇄ Rust conversions: configurations, batches of configurations and poses.
//!
//! Inputs accept anything numpy turns into a float64 array (arrays of any float dtype, lists,
//! tuples); float64 C-contiguous arrays are read without a copy. Poses are 4×4 homogeneous
//! matrices.

use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, Translation3, UnitQuaternion, Vector3};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use opengrasp_core::model::TriangleMesh;
use pyo3::prelude::*;

use crate::errors::{Error, Result};

/// `obj` as a read-only float64 array of dimension 1 (converted by numpy if needed).
pub fn array1<'py>(obj: &Bound<'py, PyAny>, what: &str) -> Result<PyReadonlyArray1<'py, f64>> {
    float_array(obj, what, 1)
}

/// `obj` as a read-only float64 array of dimension 2 (converted by numpy if needed).
pub fn array2<'py>(obj: &Bound<'py, PyAny>, what: &str) -> Result<PyReadonlyArray2<'py, f64>> {
    float_array(obj, what, 2)
}

/// `obj` as a read-only float64 array of dimension `D` (`rank` for the message), converted by
/// numpy (`ascontiguousarray(obj, "float64")`) when it is not one already.
fn float_array<'py, D: numpy::ndarray::Dimension>(
    obj: &Bound<'py, PyAny>,
    what: &str,
    rank: usize,
) -> Result<PyReadonlyArray<'py, f64, D>> {
    if let Ok(a) = obj.extract::<PyReadonlyArray<'py, f64, D>>() {
        return Ok(a);
    }
    let converted = obj
        .py()
        .import("numpy")
        .and_then(|np| np.call_method1("ascontiguousarray", (obj, "float64")))
        .map_err(|e| Error::input(format!("{what}: not a float array ({e})")))?;
    converted
        .extract::<PyReadonlyArray<'py, f64, D>>()
        .map_err(|_| Error::input(format!("{what}: expected a {rank}-D array, got {}", shape_of(&converted))))
}

fn shape_of(obj: &Bound<'_, PyAny>) -> String {
    obj.getattr("shape")
        .and_then(|s| s.str())
        .map_or_else(|_| "an object without a shape".into(), |s| format!("shape {s}"))
}

/// A vector of `f64` from an array-like, checked to have `len` finite entries if given.
pub fn vector(obj: &Bound<'_, PyAny>, what: &str, len: Option<usize>) -> Result<Vec<f64>> {
    let a = array1(obj, what)?;
    let v: Vec<f64> = match a.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => a.as_array().iter().copied().collect(),
    };
    if let Some(n) = len {
        if v.len() != n {
            return Err(Error::input(format!("{what}: expected {n} values, got {}", v.len())));
        }
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::input(format!("{what}: entry {i} is not finite ({})", v[i])));
    }
    Ok(v)
}

/// A row-major `N × cols` batch of `f64` from a 2-D array-like (borrowed when the array is a
/// C-contiguous float64 array), calling `f` with the flat data and the row count.
pub fn with_rows<T>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    cols: usize,
    f: impl FnOnce(&[f64], usize) -> Result<T>,
) -> Result<T> {
    let a = array2(obj, what)?;
    let shape = a.shape();
    let (rows, width) = (shape[0], shape[1]);
    if width != cols {
        return Err(Error::input(format!("{what}: expected {cols} columns, got shape ({rows}, {width})")));
    }
    // `as_slice` also accepts Fortran-ordered arrays (in memory order): row-major only.
    let copy;
    let data = match a.as_slice() {
        Ok(s) if a.is_c_contiguous() => s,
        _ => {
            copy = a.as_array().iter().copied().collect::<Vec<f64>>();
            &copy[..]
        }
    };
    if let Some(i) = data.iter().position(|x| !x.is_finite()) {
        return Err(Error::input(format!("{what}: row {}, column {} is not finite", i / cols.max(1), i % cols.max(1))));
    }
    f(data, rows)
}

/// A list of rows from a 2-D array-like (each checked finite, `cols` wide if given).
pub fn rows(obj: &Bound<'_, PyAny>, what: &str, cols: Option<usize>) -> Result<Vec<Vec<f64>>> {
    let a = array2(obj, what)?;
    let width = a.shape()[1];
    with_rows(obj, what, cols.unwrap_or(width), |data, _| Ok(data.chunks(width.max(1)).map(<[f64]>::to_vec).collect()))
}

/// A rigid transform from a 4×4 homogeneous matrix (rotation orthonormal within 1e-6, last
/// row `0 0 0 1`).
pub fn isometry(obj: &Bound<'_, PyAny>, what: &str) -> Result<Isometry3<f64>> {
    let a = array2(obj, what)?;
    let view = a.as_array();
    if view.shape() != [4, 4] {
        return Err(Error::input(format!("{what}: expected a 4x4 matrix, got shape {:?}", view.shape())));
    }
    let m = Matrix4::from_fn(|r, c| view[[r, c]]);
    if m.iter().any(|x| !x.is_finite()) {
        return Err(Error::input(format!("{what}: not finite")));
    }
    let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
    if (last[0].abs() + last[1].abs() + last[2].abs() + (last[3] - 1.0).abs()) > 1e-9 {
        return Err(Error::input(format!("{what}: last row must be 0 0 0 1, got {last:?}")));
    }
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    let err = (r.transpose() * r - Matrix3::identity()).abs().max();
    if err > 1e-6 || r.determinant() < 0.0 {
        return Err(Error::input(format!("{what}: the 3x3 block is not a rotation (orthonormality error {err:.2e})")));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Isometry3::from_parts(Translation3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]), rotation))
}

/// A 3-vector from an array-like.
pub fn vector3(obj: &Bound<'_, PyAny>, what: &str) -> Result<Vector3<f64>> {
    let v = vector(obj, what, Some(3))?;
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// A 4×4 homogeneous matrix of `pose`.
pub fn matrix<'py>(py: Python<'py>, pose: &Isometry3<f64>) -> Result<Bound<'py, PyArray2<f64>>> {
    let m = pose.to_homogeneous();
    let rows: Vec<Vec<f64>> = (0..4).map(|r| (0..4).map(|c| m[(r, c)]).collect()).collect();
    array_2d(py, &rows, 4)
}

/// A 1-D float64 array of `v`.
pub fn array<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// A 2-D float64 array of equally long rows (`cols` columns, also when `rows` is empty).
pub fn array_2d<'py>(py: Python<'py>, rows: &[Vec<f64>], cols: usize) -> Result<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat)
        .reshape([rows.len(), cols])
        .map_err(|e| Error::input(format!("rows of unequal length: {e}")))
}

/// A JSON value (from serde) as plain Python objects (dicts, lists, floats, ...).
pub fn json_to_py<'py>(py: Python<'py>, text: &str) -> Result<Bound<'py, PyAny>> {
    Ok(py.import("json")?.call_method1("loads", (text,))?)
}

/// Any serde-serialisable value as plain Python objects.
pub fn to_py<'py, T: serde::Serialize>(py: Python<'py>, value: &T) -> Result<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)?;
    json_to_py(py, &text)
}

/// A mesh's vertices as a `(V, 3)` float64 array.
pub fn mesh_vertices<'py>(py: Python<'py>, mesh: &TriangleMesh) -> Result<Bound<'py, PyArray2<f64>>> {
    let v: Vec<Vec<f64>> = mesh.vertices().iter().map(|p| vec![p.x, p.y, p.z]).collect();
    array_2d(py, &v, 3)
}

/// A mesh's triangles as a `(T, 3)` int64 array of vertex indices.
pub fn mesh_triangles<'py>(py: Python<'py>, mesh: &TriangleMesh) -> Result<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = mesh.triangles().iter().flat_map(|t| t.map(i64::from)).collect();
    PyArray1::from_vec(py, flat).reshape([mesh.triangles().len(), 3]).map_err(Error::input)
}
