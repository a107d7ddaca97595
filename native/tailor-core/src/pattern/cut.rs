//! Cut quantities: a pattern file draws a piece once and says how many to cut (AAMA's
//! `Quantity:` annotation). A garment needs every piece it is sewn from, so [`cut`] turns each
//! drawn piece into as many pieces as the file asks for.
//!
//! A piece cut twice is a pair, cut from fabric folded face to face: the piece as drawn and its
//! mirror image (a left and a right sleeve, leg, side panel). It is named with `R` and `L`
//! added: the drawn piece `R`, the mirror `L`, as the pattern's outer side is drawn facing up
//! and drafting systems draft the wearer's right side (the arrangement reads the two words and
//! puts each on its own limb; the artist swaps them where a file was drafted the other way).
//! More than two copies alternate drawn and mirrored, numbered `1`, `2`, …; a quantity of 0 is a
//! piece the marker does not cut (an alternative: a one-piece sleeve beside a two-piece one) and
//! is left out. A file where no piece would be cut keeps every piece once, as drawn.
//!
//! The mirror is taken across the vertical line through the middle of the piece's bounding box,
//! so the pair lies where the drawn piece lies. Its outline is reversed to stay counter-clockwise
//! (holes stay clockwise), and everything on the piece is mirrored with it: notches, fixed
//! vertices (renumbered), internal lines, the grain line, named edges.

use super::{OutlineSpan, Piece, Point2};

/// Mirror image of `piece` across the vertical line through its bounding box's middle.
pub fn mirrored(piece: &Piece, name: String) -> Piece {
    let (lo, hi) =
        piece.outline.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
    let axis = 0.5 * (lo + hi);
    let m = |p: &Point2| [2.0 * axis - p[0], p[1]];
    let n = piece.outline.len();
    // New vertex k is old vertex (n − k) mod n: vertex 0 stays first, the walk is reversed.
    let renumber = |i: usize| (n - i % n) % n;
    let outline: Vec<Point2> = (0..n).map(|k| m(&piece.outline[renumber(k)])).collect();
    let mut fixed: Vec<usize> = piece.fixed_vertices.iter().map(|&i| renumber(i)).collect();
    fixed.sort_unstable();
    fixed.dedup();
    Piece {
        name,
        outline,
        fixed_vertices: fixed,
        holes: piece.holes.iter().map(|h| h.iter().rev().map(m).collect()).collect(),
        internal_lines: piece.internal_lines.iter().map(|l| l.iter().map(m).collect()).collect(),
        notches: piece.notches.iter().map(m).collect(),
        grain: piece.grain.map(|[a, b]| [m(&a), m(&b)]),
        placement: piece.placement.clone(),
        // A forward run start..=end walks backwards in the mirror: from end's image to start's.
        edges: piece.edges.iter().map(|e| OutlineSpan { start: renumber(e.end), end: renumber(e.start) }).collect(),
    }
}

/// Every piece as many times as `quantities` says (`None`: once, as drawn); see the module.
pub fn cut(pieces: Vec<Piece>, quantities: &[Option<u32>]) -> Vec<Piece> {
    debug_assert_eq!(pieces.len(), quantities.len());
    if quantities.iter().all(|q| *q == Some(0)) {
        return pieces;
    }
    let mut out = Vec::with_capacity(pieces.len());
    for (piece, q) in pieces.into_iter().zip(quantities) {
        match q.unwrap_or(1) {
            0 => {}
            1 => out.push(piece),
            2 => {
                let left = mirrored(&piece, format!("{} L", piece.name));
                out.push(Piece { name: format!("{} R", piece.name), ..piece });
                out.push(left);
            }
            count => {
                for k in 1..=count {
                    let name = format!("{} {k}", piece.name);
                    out.push(if k % 2 == 1 { Piece { name, ..piece.clone() } } else { mirrored(&piece, name) });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::outline::signed_area;

    /// An L-shaped piece with a notch, a hole, a line, a grain line, fixed vertices and a named
    /// edge: the mirror has the same area and orientation, its vertices are the images of the
    /// drawn ones in reversed order, and what was marked on an edge is marked on its image.
    fn ell() -> Piece {
        Piece {
            name: "LEG".into(),
            outline: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 3.0], [0.0, 3.0]],
            fixed_vertices: vec![0, 1, 3],
            holes: vec![vec![[0.2, 0.2], [0.2, 0.6], [0.6, 0.2]]],
            internal_lines: vec![vec![[0.5, 0.5], [0.5, 2.5]]],
            notches: vec![[2.0, 0.5]],
            grain: Some([[0.5, 0.2], [0.5, 2.8]]),
            placement: None,
            edges: vec![OutlineSpan { start: 1, end: 3 }],
        }
    }

    #[test]
    fn the_mirror_is_the_drawn_piece_turned_over() {
        let p = ell();
        let q = mirrored(&p, "LEG L".into());
        assert_eq!(q.name, "LEG L");
        assert!((signed_area(&q.outline) - signed_area(&p.outline)).abs() < 1e-12);
        assert!(signed_area(&q.outline) > 0.0, "still counter-clockwise");
        assert!(signed_area(&q.holes[0]) < 0.0, "holes still clockwise");
        let img = |v: Point2| [2.0 - v[0], v[1]];
        for i in 0..6 {
            assert_eq!(q.outline[(6 - i) % 6], img(p.outline[i]));
        }
        for &i in &p.fixed_vertices {
            assert!(q.fixed_vertices.contains(&((6 - i) % 6)));
        }
        assert_eq!(q.notches, vec![[0.0, 0.5]]);
        assert_eq!(q.grain, Some([[1.5, 0.2], [1.5, 2.8]]));
        assert_eq!(q.internal_lines, vec![vec![[1.5, 0.5], [1.5, 2.5]]]);
        // Edge 1..=3 of the drawn piece (x = 2 up to the step) is 3..=5 of the mirror, walked forward.
        let e = &q.edges[0];
        assert_eq!((e.start, e.end), (3, 5));
        assert_eq!(q.outline[3], img(p.outline[3]));
        assert_eq!(q.outline[5], img(p.outline[1]));
        assert_eq!(mirrored(&q, "LEG".into()).outline, p.outline, "twice is the piece again");
    }

    #[test]
    fn quantities_make_pairs_and_leave_out_what_is_not_cut() {
        let p = |name: &str| Piece { name: name.into(), ..ell() };
        let got = cut(vec![p("A"), p("B"), p("C"), p("D")], &[Some(1), Some(2), Some(0), None]);
        let names: Vec<&str> = got.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["A", "B R", "B L", "D"]);
        assert_eq!(got[1].outline, ell().outline);
        assert_eq!(got[2].outline, mirrored(&ell(), String::new()).outline);
        let three = cut(vec![p("E")], &[Some(3)]);
        let names: Vec<&str> = three.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["E 1", "E 2", "E 3"]);
        assert_eq!(three[0].outline, three[2].outline);
        assert_ne!(three[0].outline, three[1].outline);
        let none = cut(vec![p("F"), p("G")], &[Some(0), Some(0)]);
        assert_eq!(none.len(), 2, "a file that cuts nothing keeps every piece once");
    }
}
