//! A recording as Python objects and back: columns as `(name, bytes)` pairs holding native
//! `f64`s (the package turns them into numpy arrays and a DataFrame without a copy per value),
//! metadata as a dict in the file's order. The format's rules stay in the `recording` crate: a
//! recording built from Python is written to memory and read back before it is used.

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use recording::{Column, Meta, Recording, REQUIRED_COLUMNS, TEMP_COLUMN};

use crate::error;

/// Columns in order, each as its name and its values' native-endian `f64` bytes.
pub type Columns<'py> = Vec<(String, Bound<'py, PyBytes>)>;

/// The columns of `rec` named in `names` (the file's header, or [`writer_order`]).
pub fn columns_out<'py>(
    py: Python<'py>,
    rec: &Recording,
    names: &[String],
) -> PyResult<Columns<'py>> {
    names
        .iter()
        .map(|name| {
            let values = rec
                .column(name)
                .ok_or_else(|| error::data(format!("no column `{name}` in the recording")))?;
            let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_ne_bytes()).collect();
            Ok((name.clone(), PyBytes::new(py, &bytes)))
        })
        .collect()
}

/// The column names in the order the writer puts them.
pub fn writer_order(rec: &Recording) -> Vec<String> {
    let temp = rec.temp_c.as_ref().map(|_| TEMP_COLUMN);
    REQUIRED_COLUMNS
        .into_iter()
        .chain(temp)
        .map(str::to_string)
        .chain(rec.extra.iter().map(|c| c.name.clone()))
        .collect()
}

/// The metadata as a dict in the writer's order: the typed keys as floats, the rest as text.
pub fn attrs_out<'py>(py: Python<'py>, meta: &Meta) -> PyResult<Bound<'py, PyDict>> {
    let attrs = PyDict::new(py);
    let numbers = meta.numbers();
    for (key, text) in meta.pairs() {
        match numbers.iter().find(|(k, _)| *k == key) {
            Some((_, v)) => attrs.set_item(key, *v)?,
            None => attrs.set_item(key, text)?,
        }
    }
    Ok(attrs)
}

/// The value of a typed key of `attrs`, if given.
fn number(attrs: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<f64>> {
    let Some(value) = attrs.get_item(key)? else {
        return Ok(None);
    };
    value.extract::<f64>().map(Some).map_err(|_| {
        error::data(format!(
            "DataFrame attrs, key `{key}`: {} is not a number",
            value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })
}

/// Any other value as the text the file holds: a string as it is, a number as the writer
/// formats numbers.
fn text(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(s) = value.extract::<String>() {
        return Ok(s);
    }
    value.extract::<f64>().map(|v| v.to_string()).map_err(|_| {
        error::data(format!(
            "DataFrame attrs, key `{key}`: neither text nor a number"
        ))
    })
}

/// The metadata of `attrs` (as [`attrs_out`] gives them; `format`, if present, must name the
/// format).
pub fn meta_in(attrs: &Bound<'_, PyDict>) -> PyResult<Meta> {
    let mut other = Vec::new();
    let mut source = None;
    for (key, value) in attrs.iter() {
        let key: String = key
            .extract()
            .map_err(|_| error::data("DataFrame attrs: a key that is not text".into()))?;
        let value = text(&key, &value);
        match key.as_str() {
            "format" if value.as_deref().ok() != Some(recording::FORMAT) => {
                return Err(error::data(format!(
                    "DataFrame attrs, key `format`: not `{}`",
                    recording::FORMAT
                )))
            }
            "format" => {}
            "source" => source = Some(value?),
            k if recording::NUMBER_KEYS.contains(&k) => {}
            _ => other.push((key, value?)),
        }
    }
    Meta::from_numbers(
        |key| number(attrs, key),
        |key| {
            error::data(format!(
                "DataFrame attrs: required metadata key `{key}` missing"
            ))
        },
        source,
        other,
    )
}

/// The `f64`s of one column's bytes.
fn values(name: &str, bytes: &Bound<'_, PyBytes>) -> PyResult<Vec<f64>> {
    let bytes = bytes.as_bytes();
    if bytes.len() % 8 != 0 {
        return Err(error::data(format!(
            "column `{name}`: {} bytes is not a whole number of float64 values",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|b| f64::from_ne_bytes(b.try_into().unwrap_or([0xff; 8])))
        .collect())
}

/// The columns as the recording's channels: the required six by name, `temp_C`, the rest as
/// extra columns in their order.
fn recording_of(meta: Meta, columns: &Columns<'_>) -> PyResult<Recording> {
    let mut rec = Recording::new(meta);
    let mut rows = None;
    for (i, (name, bytes)) in columns.iter().enumerate() {
        if columns[..i].iter().any(|(n, _)| n == name) {
            return Err(error::data(format!(
                "DataFrame: column `{name}` named twice"
            )));
        }
        let v = values(name, bytes)?;
        if *rows.get_or_insert(v.len()) != v.len() {
            return Err(error::data(format!(
                "column `{name}`: {} values, the first column has {}",
                v.len(),
                rows.unwrap_or(0)
            )));
        }
        let c = &mut rec.channels;
        match name.as_str() {
            "t_s" => c.t_s = v,
            "rod_mm" => c.rod_mm = v,
            "load_N" => c.load_n = v,
            "fz_V" => c.fz_v = v,
            "mx_V" => c.mx_v = v,
            "my_V" => c.my_v = v,
            TEMP_COLUMN => rec.temp_c = Some(v),
            _ => rec.extra.push(Column {
                name: name.clone(),
                values: v,
            }),
        }
    }
    for (name, v) in rec.channels.required() {
        if v.len() != rows.unwrap_or(0) || !columns.iter().any(|(n, _)| n == name) {
            return Err(error::data(format!(
                "DataFrame: required column `{name}` missing"
            )));
        }
    }
    Ok(rec)
}

/// The file the columns and metadata make, checked by reading it back: the line and field of
/// an error are those of this file.
pub fn file_of(columns: &Columns<'_>, attrs: &Bound<'_, PyDict>) -> PyResult<(Recording, Vec<u8>)> {
    let rec = recording_of(meta_in(attrs)?, columns)?;
    let mut bytes = Vec::new();
    rec.write_to(&mut bytes)
        .map_err(|e| error::raise(Some("DataFrame"), &e))?;
    let checked =
        recording::read_from(&bytes[..]).map_err(|e| error::raise(Some("DataFrame"), &e))?;
    Ok((checked, bytes))
}
