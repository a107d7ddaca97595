//! Bending a placed piece around a user axis before simulation (paper Sec. 4, Fig. 4), so that
//! a flat sleeve is wrapped around the arm instead of its seams cutting through it: rolled
//! onto a cylinder, every length kept ([`roll`], the default), or onto a cone for a tapered
//! limb ([`cone`], `taper_deg` ≠ 0, lengths kept too), or rotated as in the paper ([`rotate`],
//! which stretches the piece: garment files written before open as they were).

mod cone;
mod roll;
mod rotate;

use serde::{Deserialize, Serialize};

use crate::error::{Result, TailorError};

/// A symmetry line in the piece's 2D rest frame (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SymmetryLine {
    pub point: [f64; 2],
    pub direction: [f64; 2],
}

/// Parameters of [`bend_piece`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BendParams {
    /// A point of the axis, metres (world frame).
    pub axis_point: [f64; 3],
    /// Direction of the axis (need not be unit length).
    pub axis_direction: [f64; 3],
    /// Turn of the farthest point, degrees (positive: rolled towards the axis). When `radius`
    /// is given only its sign counts: which way the piece rolls.
    pub angle_deg: f64,
    /// Roll both sides of this rest-frame line (parallel to the axis), in opposite senses.
    pub symmetry: Option<SymmetryLine>,
    /// Points within this distance along the surface of where the rolling starts (metres) do
    /// not move.
    pub threshold: f64,
    /// Radius of the cylinder the piece rolls onto, metres (the angle then follows from it);
    /// `None`: from `angle_deg`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Which bend: files written before the isometric bend have none and keep the paper's.
    #[serde(default = "BendMode::of_older_files")]
    pub mode: BendMode,
    /// Half-angle of the cone the piece rolls onto, degrees (the roll only): its radius is the
    /// cylinder's level with `axis_point` and grows by `sin(taper)` per metre along the axis
    /// (shrinks for a negative taper; see [`cone`]). 0, the default and what files without it
    /// mean: the cylinder; not written when 0, so such files are as before.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub taper_deg: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// How a piece is bent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BendMode {
    /// Rolled onto a cylinder, every length along the piece kept ([`roll`]).
    #[default]
    Roll,
    /// The paper's rotation, which stretches the piece ([`rotate`]): garment files from before.
    Rotate,
}

impl BendMode {
    /// What a garment file without a `mode` meant: the paper's bend, the only one then.
    pub fn of_older_files() -> Self {
        Self::Rotate
    }

    /// `"roll"` or `"rotate"`: the name [`parse`](Self::parse) reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Roll => "roll",
            Self::Rotate => "rotate",
        }
    }

    /// `"roll"` or `"rotate"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "roll" => Ok(Self::Roll),
            "rotate" => Ok(Self::Rotate),
            other => Err(TailorError::setting("mode", other, "expected \"roll\" or \"rotate\"")),
        }
    }
}

type V3 = [f64; 3];

/// Bends `positions` in place by `params.mode`'s formula (see [`roll`] and [`rotate`]).
pub fn bend_piece(positions: &mut [[f32; 3]], rest: &[[f32; 2]], params: &BendParams) -> Result<()> {
    if positions.len() != rest.len() {
        return Err(TailorError::shape(
            "bend",
            format!("{} positions for {} rest points", positions.len(), rest.len()),
        ));
    }
    let d = check(params)?;
    match params.mode {
        BendMode::Roll => roll::roll(positions, rest, params, d),
        BendMode::Rotate => rotate::rotate(positions, rest, params, d),
    }
}

pub(super) fn check(params: &BendParams) -> Result<V3> {
    let d = params.axis_direction;
    let dn = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if !(dn.is_finite() && dn > 1e-12) {
        return Err(TailorError::setting("axis_direction", format!("{d:?}"), "must be a non-zero finite vector"));
    }
    if params.axis_point.iter().any(|c| !c.is_finite()) {
        return Err(TailorError::setting("axis_point", format!("{:?}", params.axis_point), "must be finite"));
    }
    if !params.angle_deg.is_finite() {
        return Err(TailorError::setting("angle_deg", params.angle_deg, "must be finite"));
    }
    if !(params.threshold.is_finite() && params.threshold >= 0.0) {
        return Err(TailorError::setting("threshold", params.threshold, "must be a distance of 0 or more"));
    }
    if let Some(r) = params.radius {
        if !(r.is_finite() && r > 0.0) {
            return Err(TailorError::setting("radius", r, "must be a positive distance"));
        }
    }
    if !(params.taper_deg.is_finite() && params.taper_deg.abs() < 90.0) {
        return Err(TailorError::setting("taper_deg", params.taper_deg, "must be an angle between -90 and 90 degrees"));
    }
    if params.taper_deg != 0.0 && params.mode == BendMode::Rotate {
        return Err(TailorError::setting(
            "taper_deg",
            params.taper_deg,
            "only the roll bends onto a cone (mode \"roll\"), not the paper's rotation",
        ));
    }
    if let Some(line) = params.symmetry {
        let e = line.direction;
        if !((e[0] * e[0] + e[1] * e[1]).sqrt() > 1e-12) || line.point.iter().chain(&e).any(|c| !c.is_finite()) {
            return Err(TailorError::setting(
                "symmetry",
                format!("{line:?}"),
                "needs a finite point and a non-zero direction",
            ));
        }
    }
    Ok(d.map(|c| c / dn))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet() -> (Vec<[f32; 3]>, Vec<[f32; 2]>) {
        let rest: Vec<[f32; 2]> = (0..20).map(|k| [(k % 5) as f32 * 0.1 - 0.2, (k / 5) as f32 * 0.1]).collect();
        (rest.iter().map(|r| [r[0], r[1], 0.0]).collect(), rest)
    }

    /// The bends the tests of both modes use: an axis along y, 10 cm below a sheet in z = 0,
    /// symmetric about the rest line x = 0 when asked.
    /// The edges of a grid of `nx × ny` vertices (row by row) cut into triangles along one
    /// diagonal: its rows, columns and diagonals, for the bends' length tests.
    pub(super) fn grid_edges(nx: usize, ny: usize) -> Vec<[usize; 2]> {
        let mut edges = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let v = j * nx + i;
                if i + 1 < nx {
                    edges.push([v, v + 1]);
                }
                if j + 1 < ny {
                    edges.push([v, v + nx]);
                }
                if i + 1 < nx && j + 1 < ny {
                    edges.push([v, v + nx + 1]);
                }
            }
        }
        edges
    }

    pub(super) fn sheet_params(angle: f64, symmetric: bool, threshold: f64, mode: BendMode) -> BendParams {
        BendParams {
            axis_point: [0.0, 0.0, -0.1],
            axis_direction: [0.0, 1.0, 0.0],
            angle_deg: angle,
            symmetry: symmetric.then_some(SymmetryLine { point: [0.0, 0.0], direction: [0.0, 1.0] }),
            threshold,
            radius: None,
            mode,
            taper_deg: 0.0,
        }
    }

    fn params(angle: f64, mode: BendMode) -> BendParams {
        sheet_params(angle, false, 0.0, mode)
    }

    #[test]
    fn bad_parameters_are_errors_in_either_mode() {
        for mode in [BendMode::Roll, BendMode::Rotate] {
            let (mut pos, rest) = sheet();
            let bad = |q: BendParams, pos: &mut Vec<[f32; 3]>| {
                matches!(bend_piece(pos, &rest, &q), Err(TailorError::InvalidSetting { .. }))
            };
            assert!(bad(BendParams { axis_direction: [0.0; 3], ..params(10.0, mode) }, &mut pos));
            assert!(bad(params(f64::NAN, mode), &mut pos));
            assert!(bad(BendParams { threshold: -1.0, ..params(10.0, mode) }, &mut pos));
            assert!(bad(BendParams { radius: Some(0.0), ..params(10.0, mode) }, &mut pos));
            assert!(matches!(
                bend_piece(&mut pos[..3], &rest, &params(1.0, mode)),
                Err(TailorError::ShapeMismatch { .. })
            ));
        }
        assert!(BendMode::parse("fold").is_err());
        assert_eq!(BendMode::parse("rotate").unwrap(), BendMode::Rotate);
    }

    /// A garment file's bend without a `mode` is the paper's (the only one when it was
    /// written); one with it says which.
    #[test]
    fn bends_of_older_files_rotate() {
        let old = r#"{"axis_point":[0,0,0],"axis_direction":[0,1,0],"angle_deg":40,"symmetry":null,"threshold":0.0}"#;
        assert_eq!(serde_json::from_str::<BendParams>(old).unwrap().mode, BendMode::Rotate);
        let new = serde_json::to_string(&params(40.0, BendMode::Roll)).unwrap();
        assert!(new.contains(r#""mode":"roll""#), "{new}");
        assert_eq!(serde_json::from_str::<BendParams>(&new).unwrap().mode, BendMode::Roll);
        assert_eq!(BendParams { ..params(1.0, BendMode::default()) }.mode, BendMode::Roll);
    }

    /// A file without `taper_deg` is a cylinder; a cone's taper is written and read back, a
    /// cylinder's is not written at all (files without cones are as before).
    #[test]
    fn bend_taper_round_trips_through_files() {
        let old = r#"{"axis_point":[0,0,0],"axis_direction":[0,1,0],"angle_deg":40,"symmetry":null,"threshold":0.0,"mode":"roll"}"#;
        assert_eq!(serde_json::from_str::<BendParams>(old).unwrap().taper_deg, 0.0);
        let cyl = serde_json::to_string(&params(40.0, BendMode::Roll)).unwrap();
        assert!(!cyl.contains("taper"), "{cyl}");
        let cone = BendParams { taper_deg: 3.5, radius: Some(0.04), ..params(40.0, BendMode::Roll) };
        let text = serde_json::to_string(&cone).unwrap();
        assert!(text.contains(r#""taper_deg":3.5"#), "{text}");
        assert_eq!(serde_json::from_str::<BendParams>(&text).unwrap(), cone);
    }
}
