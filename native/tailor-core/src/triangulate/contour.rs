//! The outer contour read back from the final triangles.
//!
//! A boundary edge is an edge of exactly one triangle. Triangles are counter-clockwise, so
//! walking each boundary edge in its triangle's direction goes counter-clockwise around the
//! outer outline (and clockwise around holes). Starting from a vertex known to lie on the
//! outline and following these directed edges gives the ordered outer contour, including any
//! point that refinement inserted on an outline segment.

use std::collections::HashMap;

use crate::error::{Result, TailorError};

/// Drops vertices no triangle uses, keeping the order of the others. Returns the new points,
/// re-indexed triangles, and the old → new index map (`u32::MAX` for dropped vertices).
pub(crate) fn compact<P: Copy>(points: &[P], triangles: &mut [[u32; 3]]) -> (Vec<P>, Vec<u32>) {
    let mut used = vec![false; points.len()];
    for t in triangles.iter() {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut map = vec![u32::MAX; points.len()];
    let mut out = Vec::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        if used[i] {
            map[i] = out.len() as u32;
            out.push(p);
        }
    }
    for t in triangles.iter_mut() {
        for v in t.iter_mut() {
            *v = map[*v as usize];
        }
    }
    (out, map)
}

/// The boundary loop through `start`, counter-clockwise for the outer outline.
pub(crate) fn boundary_loop(piece: &str, triangles: &[[u32; 3]], n_vertices: usize, start: u32) -> Result<Vec<u32>> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 2);
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut next = vec![u32::MAX; n_vertices];
    let mut pinched = vec![false; n_vertices];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if count[&(a.min(b), a.max(b))] == 1 {
                if next[a as usize] != u32::MAX {
                    pinched[a as usize] = true;
                }
                next[a as usize] = b;
            }
        }
    }
    let err = |reason: String| TailorError::shape(format!("piece {piece}"), reason);
    if start as usize >= n_vertices || next[start as usize] == u32::MAX {
        return Err(err("the outline's first point is not on the mesh boundary".into()));
    }
    let mut contour = vec![start];
    let mut v = start;
    loop {
        if pinched[v as usize] {
            return Err(err("the outline touches itself or a hole (a pinched boundary vertex)".into()));
        }
        v = next[v as usize];
        if v == start {
            break;
        }
        if v == u32::MAX || contour.len() > n_vertices {
            return Err(err("the mesh boundary is not a closed loop".into()));
        }
        contour.push(v);
    }
    Ok(contour)
}
