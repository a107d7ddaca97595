//! Cloth-cloth contacts between particles and triangles (issue 23): the pass that keeps every
//! particle at least `h` from every cloth triangle near it, on the side it started the substep
//! on ([`point_triangle`](super::point_triangle) has the projection and its maths).
//!
//! **Candidates found once, projected every iteration** (issue 22). A search lists every
//! (particle, triangle) pair closer than `h + m` (`m` the margin); later passes project the
//! list alone. A pair the list lacks was at least `h + m` apart at the search; while every
//! particle's displacement since, less the cloth's common translation, is under `m/2`
//! ([`find_movers`]), it is still at least `h` apart and has nothing to correct. While a few
//! particles have moved farther (the movers), their pairs alone are searched
//! ([`self_triangle_movers`](super::self_triangle_movers)) and corrected with the list in one
//! sorted order; past [`max_triangle_movers`] the search runs again. The search files the particles in the spatial hash
//! (one cell each, side at least `h + m`) and visits, for each triangle, the cells of its
//! bounding box grown by `h + m`; a pair is kept when the particle's true distance to the
//! triangle is under `h + m`.
//!
//! **Sides.** At each substep's start every listed pair takes the side of the triangle's plane
//! the particle is on then (`x_start`), except that a pair listed before keeps the side it had
//! while the particle starts the substep over the triangle: a particle that something other
//! than this pass carried through (the body's correction at the end of a substep, squeezing
//! two layers against it) is brought back instead of being held on the wrong side.
//!
//! **Seam-aware.** A pair never acts when the particle is a corner of the triangle, or is sewn
//! to one, directly or through one more seam (the corners of three or more pieces close onto
//! one point): once the seams close these touch by construction. Nothing else is left out.
//! Unlike spheres, which push apart any two particles closer than a diameter and so must spare
//! the whole welded 1-ring, a particle beside a triangle in the cloth's own surface is not over
//! it and is not pushed: a fold is pushed open only once it is folded flatter than `h`.
//! Leaving out the 1-ring as the spheres do left the samples' folds and seams to cross (the
//! skirt on the walk: 245 intersecting pairs, 4 without). A pair whose levels do not collide
//! ([`levels`](super::levels): the particle's level against the one the triangle's corners
//! share, 0 where they differ) is left out.
//!
//! What it does not cover: two edges crossing with every particle on its own side (no
//! edge-edge contacts yet). Corrections of one pass are accumulated and averaged per particle
//! (Jacobi with constraint averaging), so the result does not depend on pair order or threads.

use glam::Vec3;
use rayon::prelude::*;

use super::levels::levels_collide;
use super::point_triangle::{project, side_of, side_over, touches, PointTriangle};
use super::self_collide::seam_partners;
use super::self_triangle_movers::{TriangleMovers, VertexTriangles};
use crate::collision::geometry::closest_point_on_triangle;
use crate::collision::hash::{cell_of, SpatialHash};
use crate::collision::self_collision::ExclusionSet;
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::Model;

/// Triangles per work item of the search.
const BLOCK: usize = 256;

/// One listed contact: particle, triangle, and the side `σ` the particle keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Candidate {
    particle: u32,
    triangle: u32,
    side: f32,
}

/// Inputs of one pass.
pub(crate) struct TrianglePassInput<'a> {
    pub model: &'a Model,
    pub levels: &'a [i32],
    /// Positions at the substep's start: the sides.
    pub x_start: &'a Vec3Soa,
    /// `h`: the distance kept between a particle and a triangle.
    pub thickness: f32,
    /// `m`: how much farther than `h` the search looks.
    pub margin: f32,
    pub friction: &'a (dyn Fn(usize) -> (f32, f32) + Sync),
    /// Keep the candidate list across the substep's passes (off: search every pass, same result).
    pub reuse: bool,
}

#[derive(Debug, Default)]
pub(crate) struct SelfTriangles {
    hash: SpatialHash,
    exclusions: Option<ExclusionSet>,
    built_seams: usize,
    built_thickness: f32,
    blocks: Vec<Vec<Candidate>>,
    list: Vec<Candidate>,
    /// The list before the last search (its sides carry over).
    previous: Vec<Candidate>,
    /// Positions at the last search; empty = search on the next pass.
    x_ref: Vec3Soa,
    searched: (f32, f32),
    /// The acting pairs of a pass (index in the list) and their corrections.
    corrections: Vec<(u32, [Vec3; 4])>,
    delta: Vec<Vec3>,
    count: Vec<u32>,
    /// Whether the list's sides are this substep's.
    sides_current: bool,
    /// The particles that moved at least `m/2` since the search (the translation taken out).
    movers: Vec<u32>,
    /// The list and the movers' pairs it lacks, merged, for a pass with movers.
    merged: Vec<Candidate>,
    vertex_triangles: Option<VertexTriangles>,
    pub searches: u32,
    /// Passes that searched the movers' pairs alone.
    pub partial_searches: u32,
    /// Contacts that acted in the last pass.
    pub last_contacts: usize,
}

/// The level of a triangle for the level rule: the one its corners share, else 0.
#[inline]
fn triangle_level(levels: &[i32], t: [u32; 3]) -> i32 {
    let l = levels[t[0] as usize];
    if levels[t[1] as usize] == l && levels[t[2] as usize] == l {
        l
    } else {
        0
    }
}

/// The cloth's common translation since the search (the mean displacement), and into
/// `movers` the particles whose displacement less it is at least `m/2` (up to `most + 1` of
/// them, ascending). With no mover, the list still holds every pair now closer than `h`: for a
/// particle `p` and a point `Σ uᵢvᵢ` of a triangle, `|d_p − Σ uᵢd_vᵢ| ≤ |d_p − s| + Σ uᵢ|d_vᵢ −
/// s| < m` whatever `s`, so their distance fell by less than `m`. A garment carried by a
/// walking body moves centimetres a frame but its parts little relative to each other, so
/// taking the translation out saves most searches; the mean leaves the few particles that move
/// apart from the rest as the movers.
fn find_movers(x: &Vec3Soa, x_ref: &Vec3Soa, margin: f32, most: usize, movers: &mut Vec<u32>) -> Vec3 {
    movers.clear();
    let n = x.len();
    if n == 0 {
        return Vec3::ZERO;
    }
    let mut sum = glam::DVec3::ZERO;
    for i in 0..n {
        sum += (x.get(i) - x_ref.get(i)).as_dvec3();
    }
    let shift = (sum / n as f64).as_vec3();
    let lim2 = 0.25 * margin * margin;
    for i in 0..n {
        if (x.get(i) - x_ref.get(i) - shift).length_squared() >= lim2 {
            movers.push(i as u32);
            if movers.len() > most {
                break;
            }
        }
    }
    shift
}

/// Most movers whose pairs a pass searches alone among `n` particles; more, and the whole
/// search runs again. A mover costs far more here than a sphere's (the cells round it out to
/// `h + m` plus the longest edge, every triangle of every particle there; each triangle at a
/// mover corner against the cells round it): at the spheres' bound (`n/8`, up to 512) the
/// skirt's walk took 0.9 s a frame instead of 0.1. On the samples' walk a pass has 1-3 movers
/// most of the time.
fn max_triangle_movers(n: usize) -> usize {
    (n / 256).clamp(16, 64)
}

/// The particles each particle is sewn to, directly or through one more seam (the corners of
/// the pieces that close onto one point where three or more meet): a triangle with one of
/// them as a corner touches the particle once the seams close, and never pushes it.
fn sewn_to(model: &Model) -> crate::error::Result<ExclusionSet> {
    let partners = seam_partners(model);
    let mut pairs = Vec::new();
    for (v, ps) in partners.iter().enumerate() {
        for &p in ps {
            pairs.push([v as u32, p]);
            for &q in &partners[p as usize] {
                if q as usize != v {
                    pairs.push([v as u32, q]);
                }
            }
        }
    }
    ExclusionSet::from_pairs(model.n(), pairs)
}

impl SelfTriangles {
    /// Heap bytes of the per-particle state: the hash of the particles, the list and the
    /// buffers of a pass.
    pub fn particle_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        self.hash.memory_bytes()
            + self.blocks.iter().map(vec_bytes).sum::<usize>()
            + vec_bytes(&self.list)
            + vec_bytes(&self.previous)
            + vec_bytes(&self.movers)
            + vec_bytes(&self.merged)
            + self.vertex_triangles.as_ref().map_or(0, VertexTriangles::memory_bytes)
            + self.x_ref.memory_bytes()
            + vec_bytes(&self.corrections)
            + vec_bytes(&self.delta)
            + vec_bytes(&self.count)
    }

    /// A new substep: the sides are taken again, from its start.
    pub fn begin_substep(&mut self) {
        self.sides_current = false;
    }

    /// Forgets the exclusions (the mesh or its seams changed) and the list.
    pub fn invalidate(&mut self) {
        self.exclusions = None;
        self.vertex_triangles = None;
        self.x_ref = Vec3Soa::zeros(0);
        self.list.clear();
    }

    /// One pass of contact corrections on `x`.
    pub fn pass(&mut self, inp: &TrianglePassInput<'_>, x: &mut Vec3Soa) {
        let model = inp.model;
        if self.exclusions.is_none() || self.built_seams != model.seams.len() || self.built_thickness != inp.thickness {
            // Indices were validated when the mesh and seams were built.
            self.exclusions = sewn_to(model).ok();
            self.built_seams = model.seams.len();
            self.built_thickness = inp.thickness;
            self.x_ref = Vec3Soa::zeros(0);
        }
        let mut listed = inp.reuse && self.x_ref.len() == x.len() && self.searched == (inp.thickness, inp.margin);
        let most = max_triangle_movers(x.len());
        let mut shift = Vec3::ZERO;
        if listed {
            shift = find_movers(x, &self.x_ref, inp.margin, most, &mut self.movers);
            listed = self.movers.len() <= most;
        }
        if !listed {
            if !self.search(inp, x) {
                return;
            }
            self.x_ref.clone_from(x);
            self.searched = (inp.thickness, inp.margin);
            self.searches += 1;
            self.movers.clear();
            self.sides_current = false;
        }
        if !self.sides_current {
            self.decide_sides(inp);
            self.sides_current = true;
        }
        if self.movers.is_empty() {
            self.correct(inp, x, false);
        } else {
            self.add_missing(inp, x, shift);
            self.partial_searches += 1;
            self.correct(inp, x, true);
        }
    }

    /// Into `merged`: the list and the pairs with a mover it lacks that are closer than
    /// `h + m` now ([`self_triangle_movers`](super::self_triangle_movers)), in one sorted order,
    /// the new pairs with their sides from the substep's start.
    fn add_missing(&mut self, inp: &TrianglePassInput<'_>, x: &Vec3Soa, shift: Vec3) {
        let model = inp.model;
        let tris = model.mesh.triangles();
        if self.vertex_triangles.as_ref().is_none_or(|v| v.len() != x.len()) {
            self.vertex_triangles = Some(VertexTriangles::new(x.len(), tris));
        }
        let (Some(ex), Some(vt)) = (self.exclusions.as_ref(), self.vertex_triangles.as_ref()) else { return };
        let longest = model
            .mesh
            .topology()
            .edges
            .iter()
            .map(|&[a, b]| x.get(a as usize).distance_squared(x.get(b as usize)))
            .fold(0.0f32, f32::max)
            .sqrt();
        let reach = inp.thickness + inp.margin;
        let movers = TriangleMovers {
            x,
            hash: &self.hash,
            cell: self.hash.cell_size(),
            triangles: tris,
            vertex_triangles: vt,
            shift,
            movers: &self.movers,
            reach,
            margin: inp.margin,
            longest,
        };
        let (levels, x_start, list) = (inp.levels, inp.x_start, &self.list);
        let missing = movers.candidates().into_iter().filter_map(|(p, t)| {
            let tri = tris[t as usize];
            if tri.contains(&p)
                || list.binary_search_by_key(&(p, t), |c| (c.particle, c.triangle)).is_ok()
                || !levels_collide(levels[p as usize], triangle_level(levels, tri))
                || tri.iter().any(|&v| ex.contains(p.min(v), p.max(v)))
            {
                return None;
            }
            let [a, b, c] = tri.map(|v| x.get(v as usize));
            let xp = x.get(p as usize);
            if xp.distance_squared(closest_point_on_triangle(xp, a, b, c).0) >= reach * reach {
                return None;
            }
            let [s0, s1, s2] = tri.map(|v| x_start.get(v as usize));
            let side = side_of(x_start.get(p as usize), s0, s1, s2).unwrap_or(0.0);
            Some(Candidate { particle: p, triangle: t, side })
        });
        let missing: Vec<Candidate> = missing.collect();
        self.merged.clear();
        let mut extra = missing.iter().peekable();
        for c in &self.list {
            while let Some(m) = extra.next_if(|m| (m.particle, m.triangle) < (c.particle, c.triangle)) {
                self.merged.push(*m);
            }
            self.merged.push(*c);
        }
        self.merged.extend(extra);
    }

    /// Lists every non-excluded pair closer than `h + m` at `x`, with its side at `x_start`.
    fn search(&mut self, inp: &TrianglePassInput<'_>, x: &Vec3Soa) -> bool {
        let Some(ex) = self.exclusions.as_ref() else { return false };
        let model = inp.model;
        let tris = model.mesh.triangles();
        let reach = inp.thickness + inp.margin;
        let cell = (model.mesh.mean_edge_length() as f32).max(reach);
        if self.hash.build_points(&x.x, &x.y, &x.z, cell).is_err() {
            return false;
        }
        let num_blocks = tris.len().div_ceil(BLOCK);
        if self.blocks.len() < num_blocks {
            self.blocks.resize_with(num_blocks, Vec::new);
        }
        let (hash, levels) = (&self.hash, inp.levels);
        let reach2 = reach * reach;
        self.blocks[..num_blocks].par_iter_mut().enumerate().for_each(|(b, out)| {
            out.clear();
            for t in b * BLOCK..((b + 1) * BLOCK).min(tris.len()) {
                let tri = tris[t];
                let [a, bb, c] = tri.map(|v| x.get(v as usize));
                let (lo_p, hi_p) = (a.min(bb).min(c) - reach, a.max(bb).max(c) + reach);
                let (lo, hi) = (cell_of(lo_p.into(), cell), cell_of(hi_p.into(), cell));
                let level = triangle_level(levels, tri);
                for cz in lo[2]..=hi[2] {
                    for cy in lo[1]..=hi[1] {
                        for cx in lo[0]..=hi[0] {
                            for p in hash.query_cell([cx, cy, cz]) {
                                let xp = x.get(p as usize);
                                if xp.cmplt(lo_p).any() || xp.cmpgt(hi_p).any() || tri.contains(&p) {
                                    continue;
                                }
                                let (q, _) = closest_point_on_triangle(xp, a, bb, c);
                                if xp.distance_squared(q) >= reach2
                                    || !levels_collide(levels[p as usize], level)
                                    || tri.iter().any(|&v| ex.contains(p.min(v), p.max(v)))
                                {
                                    continue;
                                }
                                out.push(Candidate { particle: p, triangle: t as u32, side: 0.0 });
                            }
                        }
                    }
                }
            }
        });
        std::mem::swap(&mut self.list, &mut self.previous);
        self.list.clear();
        for out in &self.blocks[..num_blocks] {
            self.list.extend_from_slice(out);
        }
        // By particle, then triangle: the same order whatever the threads.
        self.list.par_sort_unstable_by_key(|c| (c.particle, c.triangle));
        // Pairs listed before keep their side (a merge of the two sorted lists).
        let mut old = self.previous.iter().peekable();
        for c in &mut self.list {
            let key = (c.particle, c.triangle);
            while old.next_if(|o| (o.particle, o.triangle) < key).is_some() {}
            if let Some(o) = old.next_if(|o| (o.particle, o.triangle) == key) {
                c.side = o.side;
            }
        }
        true
    }

    /// Each listed pair's side for this substep: a pair that had one keeps it while the
    /// particle starts the substep over the triangle, whichever side it is on then (so a
    /// particle that something else carried through, the body's own correction at the end of
    /// a substep, is brought back rather than held on the wrong side); otherwise the side of
    /// the triangle's plane the particle starts on (none, 0, when it lies in the plane: the
    /// contact then takes the side the particle is on when it acts).
    fn decide_sides(&mut self, inp: &TrianglePassInput<'_>) {
        let tris = inp.model.mesh.triangles();
        let x_start = inp.x_start;
        self.list.par_iter_mut().with_min_len(1024).for_each(|c| {
            let t = tris[c.triangle as usize].map(|v| x_start.get(v as usize));
            let p = x_start.get(c.particle as usize);
            if c.side == 0.0 || side_over(p, t[0], t[1], t[2]).is_none() {
                c.side = side_of(p, t[0], t[1], t[2]).unwrap_or(0.0);
            }
        });
    }

    /// One pass of corrections over the list, or over `merged` (the list and the movers' pairs).
    fn correct(&mut self, inp: &TrianglePassInput<'_>, x: &mut Vec3Soa, with_missing: bool) {
        let model = inp.model;
        let tris = model.mesh.triangles();
        let inv_mass = |i: usize| if model.pinned[i] { 0.0 } else { 1.0 / model.mass[i] };
        let xs = &*x;
        self.corrections.clear();
        // Most listed pairs do not act in a pass: they are tested on positions alone first.
        let pairs = if with_missing { &self.merged } else { &self.list };
        self.corrections.par_extend(pairs.par_iter().enumerate().with_min_len(512).filter_map(|(k, c)| {
            let t = tris[c.triangle as usize];
            let corners = t.map(|v| xs.get(v as usize));
            if !touches(xs.get(c.particle as usize), corners, c.side, inp.thickness) {
                return None;
            }
            let ids = [c.particle, t[0], t[1], t[2]].map(|v| v as usize);
            let fr = ids.map(|i| (inp.friction)(i));
            let tri_mu = ((fr[1].0 + fr[2].0 + fr[3].0) / 3.0, (fr[1].1 + fr[2].1 + fr[3].1) / 3.0);
            let d = project(&PointTriangle {
                x: ids.map(|i| xs.get(i)),
                x_start: ids.map(|i| inp.x_start.get(i)),
                inv_mass: ids.map(inv_mass),
                side: c.side,
                thickness: inp.thickness,
                friction: (0.5 * (fr[0].0 + tri_mu.0), 0.5 * (fr[0].1 + tri_mu.1)),
            })?;
            Some((k as u32, d))
        }));
        let n = x.len();
        self.delta.clear();
        self.delta.resize(n, Vec3::ZERO);
        self.count.clear();
        self.count.resize(n, 0);
        let acting = self.corrections.len();
        for (k, d) in &self.corrections {
            let c = pairs[*k as usize];
            let t = tris[c.triangle as usize];
            for (v, dv) in [c.particle, t[0], t[1], t[2]].into_iter().zip(d) {
                self.delta[v as usize] += *dv;
                self.count[v as usize] += 1;
            }
        }
        self.last_contacts = acting;
        if acting == 0 {
            return;
        }
        for i in 0..n {
            if self.count[i] > 0 {
                x.set(i, x.get(i) + self.delta[i] / self.count[i] as f32);
            }
        }
    }
}
