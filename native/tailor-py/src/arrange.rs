//! `tailor.body_places`, `tailor.place_on_body`, `tailor.suggest_place` and
//! `tailor.suggest_places`: arrangement round
//! the body (`tailor_core::arrange`). Logic lives in the core; this file converts places to
//! and from dicts (so that they can be kept in JSON, e.g. in a .blend) and parses the options.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tailor_core::arrange::{self, Along, Place, PlaceOptions, Reach, Side};
use tailor_core::TailorError;

use crate::convert::{points2, points3, triangles};
use crate::errors::to_py;
use crate::garment::bend_dict;
use crate::patterns::rows;

/// `"x"`, `"-z"`… or a 3-vector.
fn direction(obj: &Bound<'_, PyAny>, name: &'static str) -> PyResult<[f64; 3]> {
    if let Ok(s) = obj.extract::<String>() {
        let (sign, axis) = match s.strip_prefix('-') {
            Some(rest) => (-1.0, rest.to_string()),
            None => (1.0, s.trim_start_matches('+').to_string()),
        };
        let k = match axis.as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => {
                return Err(to_py(TailorError::setting(
                    name,
                    s,
                    "expected \"x\", \"y\", \"z\" (or \"-x\"…) or a 3-vector",
                )))
            }
        };
        let mut v = [0.0; 3];
        v[k] = sign;
        return Ok(v);
    }
    obj.extract::<[f64; 3]>()
        .map_err(|_| to_py(TailorError::setting(name, obj.to_string(), "expected an axis name or a 3-vector")))
}

fn place_dict<'py>(py: Python<'py>, p: &Place) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &p.name)?;
    d.set_item("origin", p.origin.to_vec())?;
    d.set_item("axis", p.axis.to_vec())?;
    d.set_item("facing", p.facing.to_vec())?;
    d.set_item("left", p.left.to_vec())?;
    d.set_item("up", p.up.to_vec())?;
    d.set_item("length", p.length)?;
    d.set_item("radius", p.radius)?;
    let reach = PyDict::new(py);
    reach.set_item("start", p.reach.start)?;
    reach.set_item("step", p.reach.step)?;
    let values = PyArray1::from_vec(py, p.reach.values.clone()).reshape([p.reach.bins(), p.reach.sectors])?;
    reach.set_item("values", values)?;
    d.set_item("reach", reach)?;
    Ok(d)
}

fn item<'py>(d: &Bound<'py, PyDict>, key: &'static str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(key)?.ok_or_else(|| to_py(TailorError::setting("place", key, "missing from the place dict")))
}

fn place_from(d: &Bound<'_, PyDict>) -> PyResult<Place> {
    let vec3 = |key: &'static str| -> PyResult<[f64; 3]> {
        item(d, key)?.extract().map_err(|_| to_py(TailorError::setting("place", key, "expected 3 numbers")))
    };
    let num = |key: &'static str| -> PyResult<f64> {
        item(d, key)?.extract().map_err(|_| to_py(TailorError::setting("place", key, "expected a number")))
    };
    let reach = item(d, "reach")?;
    let reach = reach.cast::<PyDict>().map_err(|_| to_py(TailorError::setting("place", "reach", "expected a dict")))?;
    let np = d.py().import("numpy")?;
    let values = np.call_method1("asarray", (item(reach, "values")?, "float64"))?;
    let shape: Vec<usize> = values.getattr("shape")?.extract()?;
    if shape.len() != 2 {
        return Err(to_py(TailorError::setting("place", "reach.values", "expected a 2D array (bins, sectors)")));
    }
    let flat = np.call_method1("ascontiguousarray", (values.call_method0("ravel")?,))?;
    let flat: PyReadonlyArray1<f64> = flat.extract()?;
    let number = |key: &'static str| -> PyResult<f64> {
        item(reach, key)?.extract().map_err(|_| to_py(TailorError::setting("place", key, "expected a number")))
    };
    Ok(Place {
        name: item(d, "name")?.extract()?,
        origin: vec3("origin")?,
        axis: vec3("axis")?,
        facing: vec3("facing")?,
        left: vec3("left")?,
        up: vec3("up")?,
        length: num("length")?,
        radius: num("radius")?,
        reach: Reach {
            start: number("start")?,
            step: number("step")?,
            sectors: shape[1],
            values: flat
                .as_slice()
                .map_err(|e| to_py(TailorError::setting("place", "reach.values", e.to_string())))?
                .to_vec(),
        },
    })
}

/// The arrangement places on a humanoid body mesh (standing along `up`, "y" when None, facing
/// `front` when given, else found from its feet; each an axis name such as "-z" or a 3-vector), as dicts in the order torso_front, torso_back, waist,
/// left_arm, right_arm, left_leg, right_leg.
#[pyfunction]
#[pyo3(signature = (vertices, triangles_, up=None, front=None))]
pub fn body_places<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    triangles_: &Bound<'py, PyAny>,
    up: Option<Bound<'py, PyAny>>,
    front: Option<Bound<'py, PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    crate::errors::guard(|| {
        let v = points3(vertices, "vertices")?;
        let t = triangles(triangles_, "triangles")?;
        let up = up.map(|u| direction(&u, "up")).transpose()?.unwrap_or([0.0, 1.0, 0.0]);
        let front = front.map(|f| direction(&f, "front")).transpose()?;
        let places = py.detach(|| arrange::body_places(&v, &t, up, front)).map_err(to_py)?;
        places.iter().map(|p| place_dict(py, p)).collect()
    })
}

fn side_of(s: &str) -> PyResult<Side> {
    match s {
        "centre" | "center" => Ok(Side::Centre),
        "left" => Ok(Side::Left),
        "right" => Ok(Side::Right),
        other => Err(to_py(TailorError::setting("side", other, "expected \"centre\", \"left\" or \"right\""))),
    }
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::Centre => "centre",
        Side::Left => "left",
        Side::Right => "right",
    }
}

fn along_name(a: Along) -> &'static str {
    match a {
        Along::Vertical => "vertical",
        Along::Longest => "longest",
        Along::Shortest => "shortest",
    }
}

/// Puts the flat piece `rest` ((n, 2) pattern points, metres) on `place` (a dict from
/// `body_places`): facing the body `clearance` metres off it and rolled round the place's axis
/// (nothing stretched). Returns {"positions": (n, 3), "radius", "bend"} (the bend as
/// `Garment.set_bend` takes it, to roll the flat piece again).
#[pyfunction]
#[pyo3(signature = (
    rest, place, clearance=0.03, side="centre", around_deg=0.0, along=None, offset=0.0, min_radius=0.0, grain=None
))]
#[allow(clippy::too_many_arguments)]
pub fn place_on_body<'py>(
    py: Python<'py>,
    rest: &Bound<'py, PyAny>,
    place: &Bound<'py, PyDict>,
    clearance: f64,
    side: &str,
    around_deg: f64,
    along: Option<&str>,
    offset: f64,
    min_radius: f64,
    grain: Option<[f64; 2]>,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let r = points2(rest, "rest")?;
        let p = place_from(place)?;
        let defaults = PlaceOptions::for_place(&p);
        let along = match along {
            None => defaults.along,
            Some("vertical") => Along::Vertical,
            Some("longest") => Along::Longest,
            Some("shortest") => Along::Shortest,
            Some(other) => {
                return Err(to_py(TailorError::setting(
                    "along",
                    other,
                    "expected \"vertical\", \"longest\" or \"shortest\"",
                )))
            }
        };
        let grain = match grain {
            None => None,
            Some(g) => {
                if !(g[0].is_finite() && g[1].is_finite() && g[0].hypot(g[1]) > 0.0) {
                    return Err(to_py(TailorError::setting(
                        "grain",
                        format!("{g:?}"),
                        "must be a non-zero 2D direction",
                    )));
                }
                Some(g)
            }
        };
        let options = PlaceOptions { clearance, side: side_of(side)?, around_deg, along, offset, min_radius, grain };
        let placed = arrange::place_piece(&r, &p, &options).map_err(to_py)?;
        let d = PyDict::new(py);
        d.set_item("positions", rows(py, &placed.positions)?)?;
        d.set_item("radius", placed.radius)?;
        d.set_item("bend", bend_dict(py, &placed.bend)?)?;
        Ok(d)
    })
}

/// Which place a piece called `name` with 2D `shape` ((n, 2) outline or rest points) goes on:
/// {"place", "side", "around_deg", "along", "offset"}, the keywords of `place_on_body`. With
/// `place` (the artist's choice): on that place, with what of the suggestion still applies.
#[pyfunction]
#[pyo3(signature = (name, shape, place=None))]
pub fn suggest_place<'py>(
    py: Python<'py>,
    name: &str,
    shape: &Bound<'py, PyAny>,
    place: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::guard(|| {
        let shape = points2(shape, "shape")?;
        let s = match place {
            None => arrange::suggest(name, &shape),
            Some(p) => arrange::suggest_on(name, &shape, p).map_err(to_py)?,
        };
        suggestion_dict(py, &s)
    })
}

fn suggestion_dict<'py>(py: Python<'py>, s: &arrange::Suggestion) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("place", s.place)?;
    d.set_item("side", side_name(s.side))?;
    d.set_item("around_deg", s.around_deg)?;
    d.set_item("along", along_name(s.along))?;
    d.set_item("offset", s.offset)?;
    Ok(d)
}

/// `suggest_place` for every piece of a pattern (`names[i]`, `shapes[i]`), the words all the
/// names start with (the style's name) left out before the names are read.
#[pyfunction]
pub fn suggest_places<'py>(
    py: Python<'py>,
    names: Vec<String>,
    shapes: Vec<Bound<'py, PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    crate::errors::guard(|| {
        if names.len() != shapes.len() {
            return Err(to_py(TailorError::setting(
                "shapes",
                shapes.len(),
                format!("must give one shape per name ({} names)", names.len()),
            )));
        }
        let pts = shapes.iter().map(|s| points2(s, "shape")).collect::<PyResult<Vec<_>>>()?;
        let pieces: Vec<(&str, &[[f32; 2]])> =
            names.iter().map(String::as_str).zip(pts.iter().map(Vec::as_slice)).collect();
        arrange::suggest_all(&pieces).iter().map(|s| suggestion_dict(py, s)).collect()
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PLACE_NAMES", arrange::PLACE_NAMES.to_vec())?;
    m.add_function(wrap_pyfunction!(body_places, m)?)?;
    m.add_function(wrap_pyfunction!(place_on_body, m)?)?;
    m.add_function(wrap_pyfunction!(suggest_place, m)?)?;
    m.add_function(wrap_pyfunction!(suggest_places, m)?)
}
