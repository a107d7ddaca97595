//! Cotangent weights of the quadratic bending model (Bergou, Wardetzky, Harmon, Zorin and
//! Grinspun 2006, "A quadratic bending model for inextensible surfaces").
//!
//! For a hinge with edge `(x₀, x₁)` and opposite vertices `x₂` (triangle 0) and `x₃`
//! (triangle 1), with `e₀ = x₁−x₀, e₁ = x₂−x₀, e₂ = x₃−x₀, e₃ = x₂−x₁, e₄ = x₃−x₁` and
//! `c_{ij} = cot∠(eᵢ, eⱼ)` (`c₀₃`, `c₀₄` using `−e₀`):
//!
//! ```text
//! K = (c₀₃ + c₀₄,  c₀₁ + c₀₂,  −c₀₁ − c₀₃,  −c₀₂ − c₀₄)
//! E = 3k / (A₀ + A₁) · ½‖Σ Kᵢ xᵢ‖²
//! ```
//!
//! `Σ Kᵢ = 0` and `Σ Kᵢ xᵢ = 0` for any planar isometric placement, so the energy is zero on
//! the flat pattern and quadratic (a constant Hessian) for inextensible motion. The weights use
//! only the intrinsic angles of each rest triangle, so a hinge may span two pattern pieces
//! across a seam: each triangle contributes its own angles.

/// A rest triangle seen from a hinge edge: the edge endpoints `e0`, `e1` and the opposite
/// vertex `o`, in 2D pattern coordinates (metres).
#[derive(Debug, Clone, Copy)]
pub struct HingeTriangle {
    pub e0: [f64; 2],
    pub e1: [f64; 2],
    pub o: [f64; 2],
}

impl HingeTriangle {
    fn area(&self) -> f64 {
        0.5 * cross(sub(self.e1, self.e0), sub(self.o, self.e0)).abs()
    }
    /// Cotangent of the angle at `e0` and at `e1`.
    fn cots(&self) -> (f64, f64) {
        let at0 = cot(sub(self.e1, self.e0), sub(self.o, self.e0));
        let at1 = cot(sub(self.e0, self.e1), sub(self.o, self.e1));
        (at0, at1)
    }
}

/// Bergou's `K` for the hinge of two triangles and the sum of their rest areas.
/// `None` when either triangle is degenerate.
pub fn hinge_weights(t0: &HingeTriangle, t1: &HingeTriangle) -> Option<([f64; 4], f64)> {
    let (a0, a1) = (t0.area(), t1.area());
    if a0 < 1e-14 || a1 < 1e-14 {
        return None;
    }
    let (c01, c03) = t0.cots();
    let (c02, c04) = t1.cots();
    Some(([c03 + c04, c01 + c02, -c01 - c03, -c02 - c04], a0 + a1))
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn cot(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] * b[0] + a[1] * b[1]) / cross(a, b).abs().max(1e-300)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_vanish_on_a_flat_hinge_and_sum_to_zero() {
        let (x0, x1, x2, x3) = ([0.0, 0.0], [1.0, 0.1], [0.3, 0.9], [0.6, -0.7]);
        let (k, area) =
            hinge_weights(&HingeTriangle { e0: x0, e1: x1, o: x2 }, &HingeTriangle { e0: x0, e1: x1, o: x3 }).unwrap();
        assert!(area > 0.0);
        assert!(k.iter().sum::<f64>().abs() < 1e-12);
        for d in 0..2 {
            let s = k[0] * x0[d] + k[1] * x1[d] + k[2] * x2[d] + k[3] * x3[d];
            assert!(s.abs() < 1e-12, "flat hinge has curvature {s}");
        }
    }

    #[test]
    fn folding_gives_a_nonzero_vector() {
        let t0 = HingeTriangle { e0: [0.0, 0.0], e1: [1.0, 0.0], o: [0.5, 1.0] };
        let t1 = HingeTriangle { e0: [0.0, 0.0], e1: [1.0, 0.0], o: [0.5, -1.0] };
        let (k, _) = hinge_weights(&t0, &t1).unwrap();
        // Fold triangle 1 up by 90 degrees: x3 = (0.5, 0, 1) in 3D.
        let xs = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 0.0, 1.0]];
        let v: Vec<f64> = (0..3).map(|d| (0..4).map(|i| k[i] * xs[i][d]).sum()).collect();
        assert!(v.iter().map(|c| c * c).sum::<f64>() > 0.1);
    }
}
