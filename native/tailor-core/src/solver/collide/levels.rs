//! Collision levels (Nylén et al. 2020, Fig. 5): an integer painted per cloth particle and per
//! collider triangle that switches chosen collisions off.
//!
//! The rule, for a cloth particle of level `a` and a collider triangle (or another cloth
//! particle) of level `b`:
//!
//! ```text
//! collide(a, b) ⇔ a = 0  ∨  b = 0  ∨  a = b
//! ```
//!
//! Level 0 (the default everywhere) collides with everything; two non-zero levels collide only
//! when equal. The paper's use: paint the left sleeve and the left arm 1, the right ones 2, and
//! the trouser legs 3 and 4, so a sleeve never catches on the torso's other arm while the body
//! (0) still collides with all of them.
//!
//! A collider given levels per vertex gives each triangle the level its three vertices share,
//! or 0 (collides with everything) where they differ: the seam between two painted regions
//! stays solid for both.

/// Levels lie in `-MAX_LEVEL..=MAX_LEVEL`: a handful are painted in practice, and a bound keeps
/// a value read from a file from meaning something else after a wrap (2^32 + 1 arrived as 1,
/// silently the same level as the left sleeve).
pub const MAX_LEVEL: i32 = 1 << 16;

/// Checks that every level is within [`MAX_LEVEL`]; `name` says which levels in the error.
pub fn check_levels(name: &'static str, levels: &[i32]) -> crate::error::Result<()> {
    match levels.iter().position(|l| l.unsigned_abs() > MAX_LEVEL as u32) {
        Some(i) => Err(crate::error::TailorError::setting(
            name,
            levels[i],
            format!("entry {i} is out of range (levels lie within ±{MAX_LEVEL})"),
        )),
        None => Ok(()),
    }
}

/// Whether primitives of levels `a` and `b` collide.
#[inline(always)]
pub fn levels_collide(a: i32, b: i32) -> bool {
    a == 0 || b == 0 || a == b
}

/// Per-triangle levels from per-vertex levels (see the module docs).
pub fn triangle_levels_from_vertices(vertex_levels: &[i32], triangles: &[[u32; 3]]) -> Vec<i32> {
    triangles
        .iter()
        .map(|t| {
            let l = t.map(|v| vertex_levels[v as usize]);
            if l[0] == l[1] && l[1] == l[2] {
                l[0]
            } else {
                0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_table() {
        assert!(levels_collide(0, 0) && levels_collide(0, 3) && levels_collide(3, 0) && levels_collide(2, 2));
        assert!(!levels_collide(1, 2) && !levels_collide(-1, 1));
        assert_eq!(triangle_levels_from_vertices(&[1, 1, 1, 2], &[[0, 1, 2], [1, 2, 3]]), vec![1, 0]);
    }

    #[test]
    fn levels_are_bounded() {
        assert!(check_levels("particle levels", &[0, 3, -MAX_LEVEL, MAX_LEVEL]).is_ok());
        let e = check_levels("particle levels", &[0, MAX_LEVEL + 1]).unwrap_err().to_string();
        assert!(e.contains("particle levels") && e.contains("entry 1"), "{e}");
        assert!(check_levels("collider levels", &[i32::MIN]).is_err());
    }
}
