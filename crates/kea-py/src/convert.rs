//! From Python values to Kea's and back: vectors, quaternions, errors.

use kea3d::dynamics::KeaError;
use kea3d::{Error, Quat, Real, Vec3};
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayLike2, PyArrayLike3, PyUntypedArrayMethods};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::PyErr;

/// A Kea error as the Python exception of its kind, its message naming the argument.
pub fn py_err(e: Error) -> PyErr {
    let text = e.to_string();
    match e {
        Error::StaleCollider { .. }
        | Error::Kea(KeaError::StaleHandle { .. } | KeaError::ForeignHandle { .. }) => {
            PyIndexError::new_err(text)
        }
        Error::Dependency { .. } | Error::Kea(KeaError::Inconsistent { .. }) => {
            PyRuntimeError::new_err(text)
        }
        _ => PyValueError::new_err(text),
    }
}

/// Any Kea result as a Python one.
pub fn py<T, E: Into<Error>>(r: Result<T, E>) -> pyo3::PyResult<T> {
    r.map_err(|e| py_err(e.into()))
}

/// A Python float as Kea's real (f32 unless built with `f64`).
#[allow(clippy::cast_possible_truncation)]
pub fn real(x: f64) -> Real {
    x as Real
}

/// A 3-sequence as a vector.
pub fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(real(v[0]), real(v[1]), real(v[2]))
}

/// A vector as a Python 3-tuple.
pub fn tuple3(v: Vec3) -> (f64, f64, f64) {
    (f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

/// An `(x, y, z, w)` sequence as a quaternion (checked for unit length where it is used).
pub fn quat(q: [f64; 4]) -> Quat {
    Quat::from_xyzw(real(q[0]), real(q[1]), real(q[2]), real(q[3]))
}

/// A `ValueError` naming `arg` and what it must be.
pub fn bad(arg: &str, value: impl std::fmt::Display, expected: &str) -> PyErr {
    PyValueError::new_err(format!("{arg} = {value}: expected {expected}"))
}

/// An `IndexError` for a body, collider or joint number out of range.
pub fn no_such(what: &str, index: usize, count: usize) -> PyErr {
    PyIndexError::new_err(format!(
        "{what} = {index}: there are {count} (numbered 0 to {})",
        count.saturating_sub(1)
    ))
}

/// Any array-like of reals (a list, a numpy array of any real dtype and any layout) as a flat
/// `f64` vector of `len` entries (any length for `None`), refused by name otherwise.
pub fn vector(arg: &str, x: &Bound<'_, PyAny>, len: Option<usize>) -> PyResult<Vec<f64>> {
    let a: PyArrayLike1<'_, f64, AllowTypeChange> = x
        .extract()
        .map_err(|e| bad(arg, e, "a 1-D array of real numbers"))?;
    let v: Vec<f64> = a.as_array().iter().copied().collect();
    if let Some(n) = len {
        if v.len() != n {
            return Err(bad(
                arg,
                format!("{} entries", v.len()),
                &format!("{n} entries"),
            ));
        }
    }
    finite(arg, &v)?;
    Ok(v)
}

/// A 2-D array-like of reals, `columns` wide, as its shape and row-major `f64` entries.
pub fn matrix(arg: &str, x: &Bound<'_, PyAny>, columns: usize) -> PyResult<(usize, Vec<f64>)> {
    let a: PyArrayLike2<'_, f64, AllowTypeChange> = x
        .extract()
        .map_err(|e| bad(arg, e, "a 2-D array of real numbers"))?;
    let shape = a.shape().to_vec();
    if shape[1] != columns {
        return Err(bad(
            arg,
            format!("an array of shape {shape:?}"),
            &format!("{columns} columns"),
        ));
    }
    let v: Vec<f64> = a.as_array().iter().copied().collect();
    finite(arg, &v)?;
    Ok((shape[0], v))
}

/// A 3-D array-like of reals of this shape, row-major `f64` entries.
pub fn block(arg: &str, x: &Bound<'_, PyAny>, shape: [usize; 3]) -> PyResult<Vec<f64>> {
    let (found, v) = any_block(arg, x)?;
    if found != shape {
        return Err(bad(
            arg,
            format!("an array of shape {found:?}"),
            &format!("shape {shape:?}"),
        ));
    }
    Ok(v)
}

/// A 3-D array-like of reals of any shape: its shape and row-major `f64` entries.
pub fn any_block(arg: &str, x: &Bound<'_, PyAny>) -> PyResult<([usize; 3], Vec<f64>)> {
    let a: PyArrayLike3<'_, f64, AllowTypeChange> = x
        .extract()
        .map_err(|e| bad(arg, e, "a 3-D array of real numbers"))?;
    let s = a.shape();
    let shape = [s[0], s[1], s[2]];
    let v: Vec<f64> = a.as_array().iter().copied().collect();
    finite(arg, &v)?;
    Ok((shape, v))
}

fn finite(arg: &str, v: &[f64]) -> PyResult<()> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(bad(arg, format!("entry {i} = {}", v[i]), "finite numbers")),
        None => Ok(()),
    }
}
