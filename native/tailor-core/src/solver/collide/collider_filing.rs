//! Which hash cells a mesh collider's triangle is filed in (`MeshCollider::prepare`): the
//! cells of its AABB grown by `PAD · l` that the insertion rule keeps, for one position of the
//! triangle or, for a moving collider, for each of the frame's substeps at once (a bit per
//! substep, `SpatialHash::build_with_masks`).
//!
//! The rule is [`keeps_cell`](crate::collision::collider_hash::keeps_cell) with the plane test
//! widened by the pad: [`InsertionRule::Paper`] keeps a cell whose centre is within `l/√2` of
//! a corner (Alg. 1); [`InsertionRule::PaperOrPlane`] also one whose centre lies in the slab
//! `|n̂·(c − a)| ≤ ½·l·‖n̂‖₁ + pad` round the triangle's plane (the plane meets the cell grown
//! by the pad); [`InsertionRule::Aabb`] every cell of the box.

use glam::Vec3;

use crate::collision::collider_hash::InsertionRule;
use crate::collision::hash::{cell_of, Cell};

/// Triangles are filed in the cells of their AABB grown by `PAD · l`, and the plane test of
/// [`InsertionRule::PaperOrPlane`] uses a slab as thick: a triangle lying on a cell face (a
/// floor at z = 0 with cells [−l, 0) and [0, l)) is then also in the cell just behind it, where
/// a particle lands after crossing it within one substep. Without the pad such a particle
/// finds an empty cell and falls through (`tests/collision_mesh.rs`, the two-triangle floor).
pub(crate) const PAD: f32 = 0.25;

/// Most substeps one build files a moving collider for (the bits of an entry's mask).
pub(crate) const MAX_STATES: usize = 32;

/// Cells a moving triangle's filing over a frame gathers in a local grid; a triangle whose
/// cells over the frame span more is filed cell by cell.
const GRID: usize = 512;

/// The cells of triangle `t`'s AABB grown by `pad`.
#[inline]
fn padded_cells(t: [Vec3; 3], l: f32, pad: f32) -> (Cell, Cell) {
    let (lo, hi) = (t[0].min(t[1]).min(t[2]) - pad, t[0].max(t[1]).max(t[2]) + pad);
    (cell_of(lo.into(), l), cell_of(hi.into(), l))
}

/// The rule for one triangle, with what does not depend on the cell (the normal, the slab's
/// half-width) computed once, not once per cell (the filing was 12 % of the T-shirt sample's
/// frame on the walk, where the collider's hash was rebuilt every substep). The padded slab
/// contains `keeps_cell`'s own, so it is tested first (one dot product, and it keeps most of
/// the cells that are kept), then the corners.
#[derive(Clone, Copy)]
struct Filing {
    t: [Vec3; 3],
    n: Vec3,
    slab: f32,
    l: f32,
    rule: InsertionRule,
}

impl Filing {
    #[inline]
    fn new(t: [Vec3; 3], l: f32, pad: f32, rule: InsertionRule) -> Self {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        Self { t, n, slab: 0.5 * l * n.abs().element_sum() + pad * n.length(), l, rule }
    }

    #[inline]
    fn keeps(&self, cell: Cell) -> bool {
        if self.rule == InsertionRule::Aabb {
            return true;
        }
        let centre = (Vec3::new(cell[0] as f32, cell[1] as f32, cell[2] as f32) + 0.5) * self.l;
        if self.rule == InsertionRule::PaperOrPlane && self.n.dot(centre - self.t[0]).abs() <= self.slab {
            return true;
        }
        let r2 = 0.5 * self.l * self.l; // (l/√2)², as in `keeps_cell`
        self.t.iter().any(|v| v.distance_squared(centre) < r2)
    }
}

/// Files a triangle whose corners at state `j` are `at(j)`, for states `0..count`
/// (`count ≤ MAX_STATES`): `emit(cell, bits)` once per cell kept at some state, bit `j` set
/// where state `j` keeps it (all bits when `count` is 1). Each state's cells are exactly those
/// of filing that state alone.
pub(crate) fn file_triangle(
    count: usize,
    at: impl Fn(usize) -> [Vec3; 3],
    l: f32,
    pad: f32,
    rule: InsertionRule,
    emit: &mut dyn FnMut(Cell, u32),
) {
    debug_assert!((1..=MAX_STATES).contains(&count));
    if count == 1 {
        let t = at(0);
        let (clo, chi) = padded_cells(t, l, pad);
        let filing = Filing::new(t, l, pad, rule);
        for z in clo[2]..=chi[2] {
            for y in clo[1]..=chi[1] {
                for x in clo[0]..=chi[0] {
                    if filing.keeps([x, y, z]) {
                        emit([x, y, z], u32::MAX);
                    }
                }
            }
        }
        return;
    }
    let none = Filing { t: [Vec3::ZERO; 3], n: Vec3::ZERO, slab: 0.0, l, rule };
    let mut states = [(none, [0i64; 3], [0i64; 3]); MAX_STATES];
    let (mut clo, mut chi) = ([i64::MAX; 3], [i64::MIN; 3]);
    for (j, s) in states.iter_mut().enumerate().take(count) {
        let t = at(j);
        let (lo, hi) = padded_cells(t, l, pad);
        *s = (Filing::new(t, l, pad, rule), lo, hi);
        clo = [0, 1, 2].map(|k| clo[k].min(lo[k]));
        chi = [0, 1, 2].map(|k| chi[k].max(hi[k]));
    }
    let states = &states[..count];
    let dim = [0, 1, 2].map(|k| (chi[k] - clo[k] + 1) as usize);
    if dim[0] * dim[1] * dim[2] > GRID {
        for z in clo[2]..=chi[2] {
            for y in clo[1]..=chi[1] {
                for x in clo[0]..=chi[0] {
                    let c = [x, y, z];
                    let mut bits = 0u32;
                    for (j, (f, lo, hi)) in states.iter().enumerate() {
                        if (0..3).all(|k| lo[k] <= c[k] && c[k] <= hi[k]) && f.keeps(c) {
                            bits |= 1 << j;
                        }
                    }
                    if bits != 0 {
                        emit(c, bits);
                    }
                }
            }
        }
        return;
    }
    // Each state's cells, their bits gathered in a grid over the union of the states' boxes.
    let mut grid = [0u32; GRID];
    for (j, (f, lo, hi)) in states.iter().enumerate() {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                let row = ((z - clo[2]) as usize * dim[1] + (y - clo[1]) as usize) * dim[0];
                for x in lo[0]..=hi[0] {
                    if f.keeps([x, y, z]) {
                        grid[row + (x - clo[0]) as usize] |= 1 << j;
                    }
                }
            }
        }
    }
    for (i, &bits) in grid[..dim[0] * dim[1] * dim[2]].iter().enumerate() {
        if bits != 0 {
            let (x, y, z) = (i % dim[0], (i / dim[0]) % dim[1], i / (dim[0] * dim[1]));
            emit([clo[0] + x as i64, clo[1] + y as i64, clo[2] + z as i64], bits);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::collider_hash::keeps_cell;
    use crate::test_util::Rng;

    const RULES: [InsertionRule; 3] = [InsertionRule::Paper, InsertionRule::PaperOrPlane, InsertionRule::Aabb];

    /// The filing keeps exactly the cells of `keeps_cell` or of the slab widened by `pad`
    /// (the rule as written before the per-triangle parts were hoisted), for random triangles
    /// (slivers included) over the cells of their padded AABB, every rule.
    #[test]
    fn filing_keeps_the_cells_of_the_padded_rule() {
        let mut rng = Rng::new(3);
        let (l, pad) = (0.01, PAD * 0.01);
        let mut kept = [0usize; 3];
        for round in 0..3000 {
            let o = rng.vec3(0.5);
            let mut t = [o, o + rng.vec3(0.015), o + rng.vec3(0.015)];
            if round % 10 == 0 {
                t[2] = t[0].lerp(t[1], rng.f32()) + rng.vec3(1e-4);
            }
            for (r, rule) in RULES.into_iter().enumerate() {
                let f = Filing::new(t, l, pad, rule);
                let (clo, chi) = padded_cells(t, l, pad);
                for z in clo[2]..=chi[2] {
                    for y in clo[1]..=chi[1] {
                        for x in clo[0]..=chi[0] {
                            let c = [x, y, z];
                            let centre = (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * l;
                            let n = (t[1] - t[0]).cross(t[2] - t[0]);
                            let slab = n.dot(centre - t[0]).abs() <= 0.5 * l * n.abs().element_sum() + pad * n.length();
                            let want = keeps_cell(t, c, l, rule) || (rule == InsertionRule::PaperOrPlane && slab);
                            assert_eq!(f.keeps(c), want, "rule {rule:?}, triangle {t:?}, cell {c:?}");
                            kept[r] += want as usize;
                        }
                    }
                }
            }
        }
        assert!(kept[0] < kept[1] && kept[1] < kept[2], "{kept:?}");
    }

    /// Filed for several states at once, each state's cells (the emitted cells with its bit)
    /// are exactly those of filing that state alone, each cell emitted once: triangles moving
    /// a little (the grid) and far (cell by cell), for every rule and up to `MAX_STATES`
    /// states.
    #[test]
    fn states_filed_together_are_each_filed_as_alone() {
        let mut rng = Rng::new(11);
        let (l, pad) = (0.01, PAD * 0.01);
        let mut saw_far = false;
        for round in 0..400 {
            let count = 2 + (rng.next_u64() % (MAX_STATES as u64 - 1)) as usize;
            let o = rng.vec3(0.3);
            let t0 = [o, o + rng.vec3(0.012), o + rng.vec3(0.012)];
            let reach = if round % 4 == 0 { 0.08 } else { 0.012 };
            let t1 = t0.map(|v| v + rng.vec3(reach));
            let at = |j: usize| {
                let a = (j + 1) as f32 / count as f32;
                [0, 1, 2].map(|k| t0[k].lerp(t1[k], a))
            };
            for rule in RULES {
                let mut together: Vec<(Cell, u32)> = Vec::new();
                file_triangle(count, at, l, pad, rule, &mut |c, bits| together.push((c, bits)));
                let mut cells: Vec<Cell> = together.iter().map(|e| e.0).collect();
                cells.sort();
                cells.dedup();
                assert_eq!(cells.len(), together.len(), "a cell emitted twice");
                for j in 0..count {
                    let mut alone: Vec<Cell> = Vec::new();
                    file_triangle(1, |_| at(j), l, pad, rule, &mut |c, bits| {
                        assert_eq!(bits, u32::MAX);
                        alone.push(c)
                    });
                    let mut mine: Vec<Cell> = together.iter().filter(|e| e.1 & (1 << j) != 0).map(|e| e.0).collect();
                    alone.sort();
                    mine.sort();
                    assert_eq!(mine, alone, "state {j} of {count}, rule {rule:?}");
                }
                let (lo, hi) = (at(0), at(count - 1));
                let span = |t: [Vec3; 3]| padded_cells(t, l, pad);
                let (a, b) = (span(lo), span(hi));
                let union: usize = (0..3).map(|k| (a.1[k].max(b.1[k]) - a.0[k].min(b.0[k]) + 1) as usize).product();
                saw_far |= union > GRID;
            }
        }
        assert!(saw_far, "no triangle took the cell-by-cell path");
    }
}
