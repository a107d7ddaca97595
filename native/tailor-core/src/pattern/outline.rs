//! Polygon helpers shared by the readers: orientation, clean-up, chaining loose segments into
//! loops, nesting (which loop is a hole of which), and finding corner vertices.

use super::Point2;
use std::collections::HashMap;

/// Most flattened points one file may produce; real patterns have tens of thousands.
pub const MAX_POINTS: usize = 20_000_000;
/// Most closed outlines one file (or one AAMA block) may hold; nesting them is quadratic.
pub const MAX_LOOPS: usize = 20_000;

/// The signed area (positive = counter-clockwise) of a closed polygon.
pub fn signed_area(poly: &[Point2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        * 0.5
}

/// Perimeter of a closed polygon.
pub fn perimeter(poly: &[Point2]) -> f64 {
    let n = poly.len();
    (0..n).map(|i| dist(poly[i], poly[(i + 1) % n])).sum()
}

pub fn dist(a: Point2, b: Point2) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Drops consecutive points closer than `eps` and a closing point that repeats the first.
pub fn dedup_closed(poly: &mut Vec<Point2>, eps: f64) {
    poly.dedup_by(|b, a| dist(*a, *b) <= eps);
    while poly.len() > 1 && dist(poly[0], *poly.last().unwrap_or(&poly[0])) <= eps {
        poly.pop();
    }
}

/// True when every coordinate is finite.
pub fn all_finite(poly: &[Point2]) -> bool {
    poly.iter().all(|p| p[0].is_finite() && p[1].is_finite())
}

/// Bounding box `[min x, min y, max x, max y]`.
pub fn bbox(poly: &[Point2]) -> [f64; 4] {
    poly.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |b, p| {
        [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])]
    })
}

/// Even-odd point-in-polygon test.
pub fn contains(poly: &[Point2], p: Point2) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0] {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// Joins open polylines that share endpoints (within `eps`, either direction) into chains.
/// Returns each chain with a flag telling whether it closed on itself. Endpoints are looked up
/// in a grid hash, so thousands of loose LINEs chain in linear time.
pub fn chain(mut parts: Vec<Vec<Point2>>, eps: f64) -> Vec<(Vec<Point2>, bool)> {
    parts.retain(|p| !p.is_empty() && all_finite(p));
    let cell = eps.max(1e-12);
    let key = |p: Point2| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in parts.iter().enumerate() {
        grid.entry(key(p[0])).or_default().push(i);
        let k = key(p[p.len() - 1]);
        if k != key(p[0]) {
            grid.entry(k).or_default().push(i);
        }
    }
    let mut used = vec![false; parts.len()];
    // Finds an unused part with an end within eps of `q`.
    let find = |q: Point2, used: &[bool], parts: &[Vec<Point2>]| -> Option<usize> {
        let (kx, ky) = key(q);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = grid.get(&(kx.saturating_add(dx), ky.saturating_add(dy))) {
                    for &i in list {
                        let p = &parts[i];
                        if !used[i] && (dist(q, p[0]) <= eps || dist(q, p[p.len() - 1]) <= eps) {
                            return Some(i);
                        }
                    }
                }
            }
        }
        None
    };
    let mut out = Vec::new();
    for start in 0..parts.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut cur = parts[start].clone();
        // Grow at the end, then at the front; each part is used once, so this terminates.
        for front in [false, true] {
            loop {
                let (first, last) = (cur[0], cur[cur.len() - 1]);
                if cur.len() > 2 && dist(first, last) <= eps {
                    break;
                }
                let tip = if front { first } else { last };
                let Some(i) = find(tip, &used, &parts) else { break };
                used[i] = true;
                let mut p = parts[i].clone();
                if front {
                    if dist(tip, p[0]) <= eps {
                        p.reverse();
                    }
                    p.pop();
                    p.extend_from_slice(&cur);
                    cur = p;
                } else {
                    if dist(tip, p[0]) > eps {
                        p.reverse();
                    }
                    cur.extend_from_slice(&p[1..]);
                }
            }
        }
        let closed = cur.len() > 2 && dist(cur[0], cur[cur.len() - 1]) <= eps;
        if closed {
            cur.pop();
        }
        out.push((cur, closed));
    }
    out
}

/// Makes `poly` counter-clockwise (`ccw = true`) or clockwise; returns whether it reversed it.
pub fn orient(poly: &mut [Point2], ccw: bool) -> bool {
    let a = signed_area(poly);
    if (a > 0.0) != ccw && a != 0.0 {
        poly.reverse();
        true
    } else {
        false
    }
}

/// Indices of vertices where the outline turns by more than `min_turn_deg`.
pub fn sharp_corners(poly: &[Point2], min_turn_deg: f64) -> Vec<usize> {
    let n = poly.len();
    if n < 3 {
        return (0..n).collect();
    }
    let cos_max = min_turn_deg.to_radians().cos();
    (0..n)
        .filter(|&i| {
            let (p, c, q) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            let (u, v) = ([c[0] - p[0], c[1] - p[1]], [q[0] - c[0], q[1] - c[1]]);
            let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
            lu > 0.0 && lv > 0.0 && (u[0] * v[0] + u[1] * v[1]) / (lu * lv) < cos_max
        })
        .collect()
}

/// The index of the outline vertex at `p` (within `eps`); when `p` lies on an edge instead, a
/// vertex is inserted there (so that notches become vertices). `None` when `p` is off the
/// outline.
pub fn vertex_at(poly: &mut Vec<Point2>, p: Point2, eps: f64) -> Option<usize> {
    if let Some(i) = poly.iter().position(|q| dist(*q, p) <= eps) {
        return Some(i);
    }
    let n = poly.len();
    let best = (0..n)
        .map(|i| (i, super::flatten::distance_to_segment(p, poly[i], poly[(i + 1) % n])))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    if best.1 <= eps {
        poly.insert(best.0 + 1, p);
        Some(best.0 + 1)
    } else {
        None
    }
}

/// Groups closed loops into (outer, holes): a loop inside another is a hole of the innermost
/// loop that contains it; loops nested two deep are outers again (islands). Outers come back
/// counter-clockwise, holes clockwise.
pub fn nest(loops: Vec<Vec<Point2>>) -> Vec<(Vec<Point2>, Vec<Vec<Point2>>)> {
    nest_indices(&loops)
        .into_iter()
        .map(|(o, hs)| {
            let mut outer = loops[o].clone();
            orient(&mut outer, true);
            let holes = hs
                .into_iter()
                .map(|h| {
                    let mut hole = loops[h].clone();
                    orient(&mut hole, false);
                    hole
                })
                .collect();
            (outer, holes)
        })
        .collect()
}

/// [`nest`] by index: (outer loop, its holes), outers in input order.
pub fn nest_indices(loops: &[Vec<Point2>]) -> Vec<(usize, Vec<usize>)> {
    let n = loops.len();
    let areas: Vec<f64> = loops.iter().map(|l| signed_area(l).abs()).collect();
    let boxes: Vec<[f64; 4]> = loops.iter().map(|l| bbox(l)).collect();
    let inside_box = |b: &[f64; 4], p: Point2| p[0] >= b[0] && p[0] <= b[2] && p[1] >= b[1] && p[1] <= b[3];
    // parent = smallest larger loop that contains this loop's first vertex.
    let parent: Vec<Option<usize>> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| {
                    j != i && !loops[i].is_empty() && areas[j] > areas[i] && inside_box(&boxes[j], loops[i][0])
                })
                .filter(|&j| contains(&loops[j], loops[i][0]))
                .min_by(|&a, &b| areas[a].total_cmp(&areas[b]))
        })
        .collect();
    // Parents are strictly larger, so walking up terminates; the cap is belt and braces.
    let depth = |mut i: usize| {
        let mut d = 0;
        while let Some(p) = parent[i] {
            d += 1;
            i = p;
            if d > n {
                break;
            }
        }
        d
    };
    let depths: Vec<usize> = (0..n).map(depth).collect();
    let mut out: Vec<(usize, Vec<usize>)> = (0..n).filter(|&i| depths[i] % 2 == 0).map(|i| (i, Vec::new())).collect();
    for i in (0..n).filter(|&i| depths[i] % 2 == 1) {
        if let Some(o) = out.iter_mut().find(|o| Some(o.0) == parent[i]) {
            o.1.push(i);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_reversed_segments_into_a_closed_loop() {
        let parts =
            vec![vec![[0.0, 0.0], [1.0, 0.0]], vec![[1.0, 1.0], [1.0, 0.0]], vec![[1.0, 1.0], [0.0, 1.0], [0.0, 0.0]]];
        let loops = chain(parts, 1e-9);
        assert_eq!(loops.len(), 1);
        assert!(loops[0].1);
        assert_eq!(loops[0].0.len(), 4);
        assert!((signed_area(&loops[0].0).abs() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn nests_holes_and_orients() {
        let outer = vec![[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]];
        let hole = vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]];
        let r = nest(vec![hole, outer]);
        assert_eq!(r.len(), 1);
        assert!(signed_area(&r[0].0) > 0.0);
        assert!(signed_area(&r[0].1[0]) < 0.0);
    }

    #[test]
    fn inserts_a_notch_on_an_edge() {
        let mut sq = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(vertex_at(&mut sq, [0.5, 0.0], 1e-6), Some(1));
        assert_eq!(sq.len(), 5);
        assert_eq!(vertex_at(&mut sq, [0.5, 0.5], 1e-6), None);
        assert_eq!(sharp_corners(&sq, 30.0), vec![0, 2, 3, 4]);
    }
}
