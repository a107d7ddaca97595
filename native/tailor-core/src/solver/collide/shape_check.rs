//! Checks of an analytic collider's shape before it joins a simulation.
//!
//! A sphere with a NaN centre or a negative radius was accepted and then silently did nothing
//! (every distance test against NaN is false): the cloth fell through what the caller believed
//! was a body. Each field is checked and named instead.

use crate::error::{Result, TailorError};
use crate::solver::collide::contacts::Shape;

/// The largest coordinate or radius accepted, metres: far beyond any scene, small enough that
/// squared distances stay finite in f32.
const MAX_EXTENT: f32 = 1.0e6;

fn point(name: &'static str, p: [f32; 3]) -> Result<()> {
    if p.iter().all(|c| c.is_finite() && c.abs() <= MAX_EXTENT) {
        Ok(())
    } else {
        Err(TailorError::setting(name, format!("{p:?}"), format!("must be finite coordinates within {MAX_EXTENT:e} m")))
    }
}

fn radius(r: f32) -> Result<()> {
    if r.is_finite() && r > 0.0 && r <= MAX_EXTENT {
        Ok(())
    } else {
        Err(TailorError::setting("radius", r, "must be a positive length in metres"))
    }
}

impl Shape {
    /// Every coordinate finite and bounded, radii positive, a plane's normal non-zero.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Shape::Plane { point: p, normal } => {
                point("point", p)?;
                point("normal", normal)?;
                if normal.iter().map(|c| c * c).sum::<f32>() <= 1e-12 {
                    return Err(TailorError::setting("normal", format!("{normal:?}"), "must not be zero"));
                }
                Ok(())
            }
            Shape::Sphere { center, radius: r } => {
                point("center", center)?;
                radius(r)
            }
            Shape::Capsule { a, b, radius: r } => {
                point("a", a)?;
                point("b", b)?;
                radius(r)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_centres_negative_radii_and_zero_normals_are_named() {
        let nan = f32::NAN;
        let cases = [
            (Shape::Sphere { center: [nan, 0.0, 0.0], radius: 0.1 }, "center"),
            (Shape::Sphere { center: [0.0; 3], radius: -1.0 }, "radius"),
            (Shape::Sphere { center: [0.0; 3], radius: 0.0 }, "radius"),
            (Shape::Capsule { a: [0.0; 3], b: [f32::INFINITY, 0.0, 0.0], radius: 0.1 }, "b"),
            (Shape::Capsule { a: [0.0; 3], b: [1.0, 0.0, 0.0], radius: nan }, "radius"),
            (Shape::Plane { point: [0.0; 3], normal: [0.0; 3] }, "normal"),
            (Shape::Plane { point: [0.0, 1e30, 0.0], normal: [0.0, 1.0, 0.0] }, "point"),
        ];
        for (shape, name) in cases {
            let e = shape.validate().unwrap_err();
            assert!(matches!(e, TailorError::InvalidSetting { name: n, .. } if n == name), "{shape:?}: {e}");
        }
        assert!(Shape::Sphere { center: [0.0, 1.0, 0.0], radius: 0.2 }.validate().is_ok());
        assert!(Shape::Plane { point: [0.0; 3], normal: [0.0, 0.0, 2.0] }.validate().is_ok());
    }
}
