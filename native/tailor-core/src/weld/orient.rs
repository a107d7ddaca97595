//! Consistent winding across seams: whole pieces are flipped so that the two triangles of every
//! welded seam edge run along it in opposite directions (one normal side for the whole garment).
//!
//! Pieces are sewn in whatever winding their placement gave them (a GarmentCode back panel may
//! face the other way from the front it is sewn to), and an exporter's normals would then flip
//! across that seam. The input's connected components (the pieces) are the unit: each seam edge
//! between two of them votes "same winding" or "opposite"; the majority vote of each pair of
//! pieces decides, a breadth-first walk gives every piece a flip, and in each group of sewn
//! pieces the winding of the larger part (by triangle count) is kept. A set of seams that
//! cannot be satisfied (a Möbius strip) keeps the edges it cannot fix; the census counts them.

use std::collections::{HashMap, VecDeque};

use super::points::key;
use crate::mesh::union_find::UnionFind;

/// The connected component of each input triangle (components numbered 0..k).
pub(super) fn components(triangles: &[[u32; 3]], n: usize) -> (Vec<u32>, usize) {
    let mut uf = UnionFind::new(n);
    for t in triangles {
        uf.union(t[0], t[1]);
        uf.union(t[1], t[2]);
    }
    let mut ids: HashMap<u32, u32> = HashMap::new();
    let comp = triangles
        .iter()
        .map(|t| {
            let next = ids.len() as u32;
            *ids.entry(uf.find(t[0])).or_insert(next)
        })
        .collect();
    (comp, ids.len())
}

/// Flips the triangles (and their corner weights) of the pieces that need it; `piece[t]` is
/// welded triangle `t`'s component, of `count`. Returns the number of pieces flipped.
pub(super) fn orient(triangles: &mut [[u32; 3]], corners: &mut [[[f32; 3]; 3]], piece: &[u32], count: usize) -> usize {
    // Welded edge -> (triangle, runs from lower to higher index) of its triangles.
    let mut edges: HashMap<(u32, u32), Vec<(u32, bool)>> = HashMap::with_capacity(triangles.len() * 2);
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges.entry(key(a, b)).or_default().push((t as u32, a < b));
        }
    }
    // Votes per pair of pieces: (same direction = one must flip, opposite = consistent).
    let mut votes: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    for list in edges.values() {
        if let [(t0, d0), (t1, d1)] = list.as_slice() {
            let (p0, p1) = (piece[*t0 as usize], piece[*t1 as usize]);
            if p0 != p1 {
                let v = votes.entry(key(p0, p1)).or_insert((0, 0));
                if d0 == d1 {
                    v.0 += 1;
                } else {
                    v.1 += 1;
                }
            }
        }
    }
    let mut adjacent: Vec<Vec<(u32, bool)>> = vec![Vec::new(); count];
    for (&(p0, p1), &(same, opposite)) in &votes {
        let flip = same > opposite;
        adjacent[p0 as usize].push((p1, flip));
        adjacent[p1 as usize].push((p0, flip));
    }
    let mut size = vec![0usize; count];
    piece.iter().for_each(|&p| size[p as usize] += 1);
    let mut flip: Vec<Option<bool>> = vec![None; count];
    for start in 0..count {
        if flip[start].is_some() {
            continue;
        }
        flip[start] = Some(false);
        let (mut group, mut queue) = (vec![start], VecDeque::from([start]));
        while let Some(p) = queue.pop_front() {
            let f = flip[p].expect("visited");
            for &(q, rel) in &adjacent[p] {
                if flip[q as usize].is_none() {
                    flip[q as usize] = Some(f ^ rel);
                    group.push(q as usize);
                    queue.push_back(q as usize);
                }
            }
        }
        let flipped: usize = group.iter().filter(|&&p| flip[p] == Some(true)).map(|&p| size[p]).sum();
        let kept: usize = group.iter().filter(|&&p| flip[p] == Some(false)).map(|&p| size[p]).sum();
        if flipped > kept {
            group.iter().for_each(|&p| flip[p] = flip[p].map(|f| !f));
        }
    }
    for ((tri, c), &p) in triangles.iter_mut().zip(corners.iter_mut()).zip(piece) {
        if flip[p as usize] == Some(true) {
            tri.swap(1, 2);
            c.swap(1, 2);
        }
    }
    flip.iter().filter(|f| **f == Some(true)).count()
}
