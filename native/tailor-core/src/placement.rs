//! Initial 3D positions of piece meshes: by the pattern's [`Placement`], or laid out flat.
//!
//! GarmentCode places a panel by rotating its 2D frame (`z = 0`) with XYZ Euler angles in
//! degrees and then translating: `x_world = R · (x, y, 0) + t`. The rotation is *intrinsic*
//! XYZ: pygarment builds it with `scipy.spatial.transform.Rotation.from_euler('XYZ', angles,
//! degrees=True)` (upper-case axes are intrinsic in scipy) and serialises it back with
//! `as_euler('XYZ')`. Intrinsic XYZ is the matrix product `R = Rx(a) · Ry(b) · Rz(c)` applied
//! to column vectors (rotate about z first in world terms, x last). The frame is the pattern
//! file's (GarmentCode: y up); converting to Blender's z-up is the add-on's job.
//!
//! Pieces without a placement are laid side by side in the `z = 0` plane along +x with a gap,
//! each piece's bounding box starting at `y = 0`.

use crate::error::{Result, TailorError};
use crate::pattern::{Piece, Placement};
use crate::triangulate::PieceMesh;

/// `Rx(a) · Ry(b) · Rz(c)` for intrinsic XYZ Euler angles in degrees, row-major.
pub fn euler_xyz_intrinsic(deg: [f64; 3]) -> [[f64; 3]; 3] {
    let [a, b, c] = deg.map(f64::to_radians);
    let (sa, ca) = a.sin_cos();
    let (sb, cb) = b.sin_cos();
    let (sc, cc) = c.sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]];
    let ry = [[cb, 0.0, sb], [0.0, 1.0, 0.0], [-sb, 0.0, cb]];
    let rz = [[cc, -sc, 0.0], [sc, cc, 0.0], [0.0, 0.0, 1.0]];
    mul(mul(rx, ry), rz)
}

fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// World positions of a piece's rest vertices under `placement`.
pub fn place_piece(mesh: &PieceMesh, placement: &Placement) -> Result<Vec<[f32; 3]>> {
    if placement.translation.iter().chain(&placement.rotation_deg).any(|c| !c.is_finite()) {
        return Err(TailorError::setting("placement", format!("{placement:?}"), "must be finite"));
    }
    let r = euler_xyz_intrinsic(placement.rotation_deg);
    let t = placement.translation;
    Ok(mesh
        .rest
        .iter()
        .map(|p| {
            let (x, y) = (p[0] as f64, p[1] as f64);
            [0, 1, 2].map(|i| (r[i][0] * x + r[i][1] * y + t[i]) as f32)
        })
        .collect())
}

/// Initial positions of every piece: its placement when it has one, otherwise the flat layout
/// (side by side along +x in `z = 0`, `gap` metres apart).
pub fn place_pieces(pieces: &[Piece], meshes: &[PieceMesh], gap: f64) -> Result<Vec<Vec<[f32; 3]>>> {
    if pieces.len() != meshes.len() {
        return Err(TailorError::shape("placement", format!("{} pieces but {} meshes", pieces.len(), meshes.len())));
    }
    if !(gap.is_finite() && gap >= 0.0) {
        return Err(TailorError::setting("gap", gap, "must be a distance of 0 or more"));
    }
    let mut cursor = 0.0f64;
    let mut out = Vec::with_capacity(meshes.len());
    for (piece, mesh) in pieces.iter().zip(meshes) {
        if let Some(pl) = &piece.placement {
            out.push(place_piece(mesh, pl)?);
            continue;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.rest {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k] as f64);
                hi[k] = hi[k].max(p[k] as f64);
            }
        }
        let shift = [cursor - lo[0], -lo[1]];
        out.push(
            mesh.rest.iter().map(|p| [(p[0] as f64 + shift[0]) as f32, (p[1] as f64 + shift[1]) as f32, 0.0]).collect(),
        );
        cursor += (hi[0] - lo[0]) + gap;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply(r: [[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| (0..3).map(|k| r[i][k] * v[k]).sum())
    }

    #[test]
    fn intrinsic_xyz_rotates_about_the_moving_axes() {
        // R = Rx(90°) · Ry(90°): Ry(90°) x̂ = -ẑ, then Rx(90°)(-ẑ) = +ŷ.
        let r = euler_xyz_intrinsic([90.0, 90.0, 0.0]);
        let v = apply(r, [1.0, 0.0, 0.0]);
        assert!((v[0]).abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12 && v[2].abs() < 1e-12, "{v:?}");
        // Extrinsic xyz (Rz · Ry · Rx) would give -ẑ instead.
        let z = apply(euler_xyz_intrinsic([0.0, 0.0, 90.0]), [1.0, 0.0, 0.0]);
        assert!((z[1] - 1.0).abs() < 1e-12);
    }
}
