//! Pieces cut on the fold: a pattern file draws half of a symmetric piece (a T-shirt's front,
//! a tank's back) with a mirror line along the fold (AAMA layer 6); the garment needs the whole
//! piece. [`unfold`] mirrors the half across the line: the outline becomes the half's boundary
//! off the fold followed by its reflection, and holes, internal lines and marked points are
//! copied across. The fold itself is no longer a boundary (its vertices at the two ends stay,
//! on a straight run).
//!
//! It unfolds only what it can read unambiguously: the outline must lie on one side of the line
//! and touch it along exactly one run of at least two consecutive vertices (the fold edge).
//! Anything else (a mirror line that is a symmetry axis of a whole piece, or that meets the
//! outline at a point) leaves the piece as drawn, and says why.

use super::Point2;

/// What [`unfold`] did with a piece.
#[derive(Debug, Clone, PartialEq)]
pub enum Unfolded {
    /// Mirrored across the line: the new outline has this many vertices.
    Whole(usize),
    /// Left as drawn, for the reason given.
    AsDrawn(&'static str),
}

/// Mirrors a half piece across `line` (two points on the fold), within `tol` metres of it: see
/// the module. `outline` is the piece's boundary (either orientation, kept); `holes`,
/// `internal` (open polylines) and `points` (notches, turn points) gain their mirror images,
/// except what lies on the line.
pub fn unfold(
    outline: &mut Vec<Point2>,
    holes: &mut Vec<Vec<Point2>>,
    internal: &mut Vec<Vec<Point2>>,
    points: &mut [&mut Vec<Point2>],
    line: [Point2; 2],
    tol: f64,
) -> Unfolded {
    let d = [line[1][0] - line[0][0], line[1][1] - line[0][1]];
    let len = d[0].hypot(d[1]);
    if !(len > tol) {
        return Unfolded::AsDrawn("the mirror line has no length");
    }
    let n = [-d[1] / len, d[0] / len];
    let side = |p: Point2| (p[0] - line[0][0]) * n[0] + (p[1] - line[0][1]) * n[1];
    let reflect = |p: Point2| {
        let s = side(p);
        [p[0] - 2.0 * s * n[0], p[1] - 2.0 * s * n[1]]
    };
    let m = outline.len();
    let on: Vec<bool> = outline.iter().map(|&p| side(p).abs() <= tol).collect();
    let (mut above, mut below) = (false, false);
    for (&p, &o) in outline.iter().zip(&on) {
        if !o {
            above |= side(p) > 0.0;
            below |= side(p) < 0.0;
        }
    }
    if above && below {
        return Unfolded::AsDrawn("the outline lies on both sides of the mirror line");
    }
    // Runs of consecutive on-line vertices (cyclic), each as (first, count).
    let Some(start) = (0..m).find(|&i| !on[i]) else {
        return Unfolded::AsDrawn("the outline lies on the mirror line");
    };
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for k in 1..=m {
        let i = (start + k) % m;
        if on[i] {
            let prev = (i + m - 1) % m;
            if on[prev] && prev != start {
                runs.last_mut().expect("a run started").1 += 1;
            } else {
                runs.push((i, 1));
            }
        }
    }
    let folds: Vec<(usize, usize)> = runs.into_iter().filter(|r| r.1 >= 2).collect();
    let [(first, count)] = folds[..] else {
        return Unfolded::AsDrawn(if folds.is_empty() {
            "no edge of the outline lies on the mirror line"
        } else {
            "more than one edge of the outline lies on the mirror line"
        });
    };
    // The half's boundary off the fold, from the fold's last vertex round to its first.
    let last = (first + count - 1) % m;
    let chain: Vec<Point2> = (0..=(m - count + 1)).map(|k| outline[(last + k) % m]).collect();
    let mut whole = chain.clone();
    whole.extend(chain[1..chain.len() - 1].iter().rev().map(|&p| reflect(p)));
    *outline = whole;
    let mirrored: Vec<Vec<Point2>> = holes.iter().map(|h| h.iter().rev().map(|&p| reflect(p)).collect()).collect();
    holes.extend(mirrored);
    let mirrored: Vec<Vec<Point2>> = internal
        .iter()
        .filter(|l| l.iter().any(|&p| side(p).abs() > tol))
        .map(|l| l.iter().map(|&p| reflect(p)).collect())
        .collect();
    internal.extend(mirrored);
    for set in points.iter_mut() {
        let mirrored: Vec<Point2> = set.iter().filter(|&&p| side(p).abs() > tol).map(|&p| reflect(p)).collect();
        set.extend(mirrored);
    }
    Unfolded::Whole(outline.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::outline::signed_area;

    /// The right half of a 2 × 2 square (x from 0 to 1), folded on x = 0, drawn from each
    /// starting vertex and in both orientations: always the whole square, the orientation kept,
    /// the area doubled; a notch, a hole and an internal line copied across, what lies on the
    /// line not.
    #[test]
    fn a_half_square_unfolds_into_the_square() {
        let half = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]];
        for rot in 0..4 {
            for ccw in [true, false] {
                let mut o: Vec<Point2> = (0..4).map(|k| half[(k + rot) % 4]).collect();
                if !ccw {
                    o.reverse();
                }
                let area = signed_area(&o);
                let mut holes = vec![vec![[0.4, 0.4], [0.6, 0.4], [0.6, 0.6]]];
                let mut internal = vec![vec![[0.2, 1.0], [0.8, 1.0]], vec![[0.0, 0.5], [0.0, 1.5]]];
                let mut notches = vec![[1.0, 1.0], [0.0, 2.0]];
                let got =
                    unfold(&mut o, &mut holes, &mut internal, &mut [&mut notches], [[0.0, -1.0], [0.0, 3.0]], 1e-9);
                assert_eq!(got, Unfolded::Whole(6), "start {rot}, ccw {ccw}");
                assert!((signed_area(&o) - 2.0 * area).abs() < 1e-12, "start {rot}, ccw {ccw}: {o:?}");
                let (lo, hi) = o.iter().fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), p| {
                    ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
                });
                assert_eq!((lo, hi), ([-1.0, 0.0], [1.0, 2.0]));
                assert_eq!(holes.len(), 2);
                assert!(
                    (signed_area(&holes[1]) - signed_area(&holes[0])).abs() < 1e-12,
                    "the copy keeps its orientation"
                );
                assert_eq!(internal.len(), 3, "the line on the fold is not copied");
                assert_eq!(internal[2], vec![[-0.2, 1.0], [-0.8, 1.0]]);
                assert_eq!(notches, vec![[1.0, 1.0], [0.0, 2.0], [-1.0, 1.0]]);
            }
        }
    }

    /// A fold edge with a vertex in its middle (a notch on the fold) unfolds the same; what
    /// cannot be read as a half is left as drawn, saying why.
    #[test]
    fn only_a_half_with_one_fold_edge_unfolds() {
        let mut o = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0], [0.0, 1.0]];
        let got = unfold(&mut o, &mut vec![], &mut vec![], &mut [], [[0.0, 0.0], [0.0, 1.0]], 1e-9);
        assert_eq!(got, Unfolded::Whole(6));
        let square = vec![[-1.0, 0.0], [1.0, 0.0], [1.0, 2.0], [-1.0, 2.0]];
        let cases: [(Vec<Point2>, [Point2; 2], &str); 4] = [
            (square.clone(), [[0.0, 0.0], [0.0, 1.0]], "both sides"),
            (vec![[0.0, 0.0], [1.0, 1.0], [0.0, 2.0], [-0.5, 1.0]], [[0.0, 0.0], [0.0, 1.0]], "both sides"),
            (vec![[0.0, 0.0], [1.0, 1.0], [0.5, 2.0]], [[0.0, 0.0], [0.0, 1.0]], "no edge"),
            (square, [[0.0, 0.0], [0.0, 0.0]], "no length"),
        ];
        for (mut o, line, why) in cases {
            let before = o.clone();
            match unfold(&mut o, &mut vec![], &mut vec![], &mut [], line, 1e-9) {
                Unfolded::AsDrawn(reason) => assert!(reason.contains(why), "{reason}"),
                other => panic!("{before:?} unfolded: {other:?}"),
            }
            assert_eq!(o, before);
        }
    }
}
