//! Cloth-cloth collisions: a sphere of radius `r` per particle, tested pairwise after each
//! solver iteration (Nylén et al. 2020, section 6, after Macklin et al. 2014).
//!
//! Pairs come from [`SelfCollision::find_pairs`] (same bucket and `cell_id`, cell side the mean
//! rest edge, at least `2r`). Each overlapping pair is pushed apart along the line of centres
//! by the overlap `2r − d`, split by inverse mass (pinned particles do not move), and friction
//! acts at the position level (Macklin et al. 2014, Eq. 24): the pair's relative tangential
//! displacement over the substep is removed when it is under `μs·overlap`, else shortened by
//! `μk·overlap`. Corrections of one pass are accumulated and averaged per particle (a Jacobi
//! pass with constraint averaging), so the result does not depend on pair order or threads.
//!
//! Pairs never repel when their particles share a triangle (hence an edge), when they are
//! sewn together, or when one is a triangle neighbour of the other's sewn partner (once a seam
//! closes, the two pieces' triangles meet there as if welded); nor when their collision levels
//! do not collide. Nor, more generally, when they are close along the sewn cloth: where three
//! or more pieces meet (an underarm: sleeve front, sleeve back, bodice front, bodice back), the
//! corner of each piece is sewn only to its two neighbours' corners, yet all of them close onto
//! one point, so corners two seams apart and their neighbours must not repel either (they held
//! the sample shirt-and-hoody's junctions 15 mm open and pumped a four-piece test junction up
//! 0.3 m). The rule ([`welded_neighbours`]): the shortest path between them through the cloth
//! at rest, crossing seams at no cost, is no longer than the longest rest edge at one of them,
//! or than the spheres' diameter `2r`: particles closer than that along the cloth overlap when
//! it lies flat and unstretched, so pushing them apart could only stretch it (a radius set
//! larger than the edges, or pieces finer than the mean edge the default radius follows).

use glam::Vec3;

use super::levels::levels_collide;
use super::self_movers::{max_movers, merged, Movers};
use crate::collision::self_collision::{ExclusionSet, SelfCollision};
use crate::error::{Result, TailorError};
use crate::solver::model::soa::Vec3Soa;
use crate::solver::model::Model;

/// Self-collision settings. Off by default: a single-layer garment does not need the pass, and
/// near a closing seam the spheres of the two sides fight the seam (measured on the demo sleeve:
/// max strain 0.14 without, 0.96 with); turn it on for layered garments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfCollisionSettings {
    pub enabled: bool,
    /// Spheres: the sphere radius, metres (`None` = half the mean rest edge length); triangles:
    /// the distance kept between a particle and a triangle (`None` =
    /// [`DEFAULT_THICKNESS`](crate::solver::model::settings::DEFAULT_THICKNESS)).
    pub radius: Option<f32>,
    /// What collides: particle spheres, or particles against triangles.
    pub contacts: SelfContacts,
    /// Friction between cloth particles (when no per-particle coefficients are set).
    pub static_friction: f32,
    pub kinetic_friction: f32,
}

impl Default for SelfCollisionSettings {
    fn default() -> Self {
        Self {
            enabled: false,
            radius: None,
            contacts: SelfContacts::default(),
            static_friction: 0.3,
            kinetic_friction: 0.2,
        }
    }
}

/// The cloth-cloth contact model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SelfContacts {
    /// A sphere per particle, pairs pushed apart (the paper's model, `self_collide.rs`).
    #[default]
    Spheres,
    /// Each particle kept off the cloth's triangles on the side it started the substep on
    /// (`self_triangles.rs`): does not miss a crossing between iterations.
    Triangles,
}

impl SelfContacts {
    pub const ALL: [SelfContacts; 2] = [SelfContacts::Spheres, SelfContacts::Triangles];

    pub fn name(self) -> &'static str {
        match self {
            SelfContacts::Spheres => "spheres",
            SelfContacts::Triangles => "triangles",
        }
    }

    /// The model named `name`, or an error listing the names.
    pub fn named(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|c| c.name()).collect();
            TailorError::setting("self_collision.contacts", name, format!("must be one of {}", names.join(", ")))
        })
    }
}

impl SelfCollisionSettings {
    pub fn validate(&self) -> Result<()> {
        if let Some(r) = self.radius {
            if !(r.is_finite() && r > 0.0) {
                return Err(TailorError::setting("self_collision.radius", r, "must be positive and finite"));
            }
        }
        for (name, v) in [
            ("self_collision.static_friction", self.static_friction),
            ("self_collision.kinetic_friction", self.kinetic_friction),
        ] {
            crate::solver::model::settings::non_negative(name, v)?;
        }
        Ok(())
    }
}

#[derive(Debug, Default)]
pub(crate) struct SelfCollide {
    finder: SelfCollision,
    exclusions: Option<ExclusionSet>,
    /// Seam count and radius the exclusions were built for.
    built_seams: usize,
    built_radius: f32,
    delta: Vec<Vec3>,
    count: Vec<u32>,
    pub last_pairs: usize,
    /// One-thread pool for small cloths (see `SMALL`).
    serial: Option<rayon::ThreadPool>,
    /// Candidate pairs (closer than `2r + margin` at `x_ref`) and the radius they were
    /// searched for; empty `x_ref` = no valid list.
    x_ref: Vec3Soa,
    searched_radius: f32,
    pub searches: u32,
    /// Passes that searched the movers alone (`self_movers.rs`), and the movers of a pass.
    pub partial_searches: u32,
    movers: Vec<u32>,
}

/// Search margin as a fraction of the radius (see [`SelfCollide::pass`]). A wider margin lists
/// more pairs but searches everything less often: a substep's prediction moves every particle
/// of a walking garment about a millimetre, past half of a margin of `r/2`. Measured on the
/// layered outfit's walk: 0.5 -> 117 ms of self-collision a frame, 1.0 -> 93, 1.5 -> 111.
const MARGIN: f32 = 1.0;

/// Below this many particles the pair search runs on one thread: its half-dozen parallel
/// phases cost more in thread wake-ups than the work (measured: a 369-particle strip spent
/// ~0.3 ms per pass on two busy cores, four times the rest of its step).
const SMALL: usize = 4096;

/// Vertices sewn to each vertex (every vertex of a seam point with non-zero weight is sewn to
/// every such vertex of the other side).
pub(crate) fn seam_partners(model: &Model) -> Vec<Vec<u32>> {
    let mut partners = vec![Vec::new(); model.n()];
    for seam in &model.seams {
        for (a, b) in &seam.pairs {
            for (i, &va) in a.verts.iter().enumerate() {
                for (j, &vb) in b.verts.iter().enumerate() {
                    if a.weights[i] > 0.0 && b.weights[j] > 0.0 && va != vb {
                        partners[va as usize].push(vb);
                        partners[vb as usize].push(va);
                    }
                }
            }
        }
    }
    partners
}

/// Pairs of particles close along the sewn cloth: `v` and every `w` whose shortest path from `v`
/// through the rest mesh and the seams is at most the longest rest edge at `v` or `diameter`,
/// whichever is longer (a bounded Dijkstra from each particle; run from both ends, a pair is
/// found when the path is within either end's bound).
///
/// Mesh edges weigh their rest (pattern) length. A seam pair `(A, B)`, each point a vertex or a
/// point on a contour edge (`A = Σ wᵢ·aᵢ`), links every `aᵢ` to every `bⱼ` with the rest
/// distance from each vertex to its point: `(1 − wᵢ)·|a₀a₁| + (1 − wⱼ)·|b₀b₁|` (0 between
/// sewn vertices). Without seams this is the 1-ring (plus, on irregular meshes, a vertex or two
/// a shorter way round than the longest edge); with seams it is the 1-ring of the welded mesh
/// the closed seams make, however many pieces meet at a point. Two separate layers have no
/// path between them: their particles always collide.
pub(crate) fn welded_neighbours(model: &Model, diameter: f32) -> Vec<[u32; 2]> {
    let n = model.n();
    let rest = model.mesh.rest();
    let len = |a: u32, b: u32| {
        let (p, q) = (rest[a as usize], rest[b as usize]);
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
    };
    let mut adj: Vec<Vec<(u32, f32)>> = vec![Vec::new(); n];
    let mut reach = vec![diameter.max(0.0); n];
    for &[a, b] in &model.mesh.topology().edges {
        let l = len(a, b);
        adj[a as usize].push((b, l));
        adj[b as usize].push((a, l));
        reach[a as usize] = reach[a as usize].max(l);
        reach[b as usize] = reach[b as usize].max(l);
    }
    for seam in &model.seams {
        for (a, b) in &seam.pairs {
            let (la, lb) = (len(a.verts[0], a.verts[1]), len(b.verts[0], b.verts[1]));
            for i in 0..2 {
                for j in 0..2 {
                    let (va, vb) = (a.verts[i], b.verts[j]);
                    if a.weights[i] > 0.0 && b.weights[j] > 0.0 && va != vb {
                        let l = (1.0 - a.weights[i]) * la + (1.0 - b.weights[j]) * lb;
                        adj[va as usize].push((vb, l));
                        adj[vb as usize].push((va, l));
                    }
                }
            }
        }
    }
    let mut pairs = Vec::new();
    let mut dist = vec![f32::INFINITY; n];
    let mut touched: Vec<u32> = Vec::new();
    let mut heap = std::collections::BinaryHeap::new();
    for v in 0..n {
        let bound = reach[v];
        dist[v] = 0.0;
        touched.push(v as u32);
        // Max-heap on the negated distance's bits: non-negative f32s order like their bits.
        heap.push((std::cmp::Reverse(0u32), v as u32));
        while let Some((std::cmp::Reverse(bits), u)) = heap.pop() {
            let du = f32::from_bits(bits);
            if du > dist[u as usize] {
                continue;
            }
            if u as usize != v {
                pairs.push([v as u32, u]);
            }
            for &(w, l) in &adj[u as usize] {
                let dw = du + l;
                if dw <= bound && dw < dist[w as usize] {
                    if dist[w as usize].is_infinite() {
                        touched.push(w);
                    }
                    dist[w as usize] = dw;
                    heap.push((std::cmp::Reverse(dw.to_bits()), w));
                }
            }
        }
        for &t in &touched {
            dist[t as usize] = f32::INFINITY;
        }
        touched.clear();
    }
    pairs
}

/// Every pair that never repels (see the module doc) for spheres of radius `radius`.
pub(crate) fn build_exclusions(model: &Model, radius: f32) -> Result<ExclusionSet> {
    let partners = seam_partners(model);
    let mut pairs: Vec<[u32; 2]> = welded_neighbours(model, 2.0 * radius);
    for &[a, b, c] in model.mesh.triangles() {
        for (u, w) in [(a, b), (b, c), (c, a)] {
            pairs.push([u, w]);
            // A triangle neighbour of a sewn partner: welded neighbours once the seam closes.
            for &pu in &partners[u as usize] {
                pairs.push([pu, w]);
            }
            for &pw in &partners[w as usize] {
                pairs.push([u, pw]);
            }
        }
    }
    for (v, ps) in partners.iter().enumerate() {
        for &p in ps {
            pairs.push([v as u32, p]);
        }
    }
    ExclusionSet::from_pairs(model.n(), pairs)
}

/// Inputs of one pass.
pub(crate) struct PassInput<'a> {
    pub model: &'a Model,
    pub levels: &'a [i32],
    pub x_start: &'a Vec3Soa,
    pub radius: f32,
    pub cell: f32,
    pub friction: &'a dyn Fn(usize) -> (f32, f32),
    /// Keep the candidate list across passes (off: search every pass, same result).
    pub reuse: bool,
}

impl SelfCollide {
    /// Heap bytes of the per-particle buffers (not the pair finder).
    pub fn particle_bytes(&self) -> usize {
        use crate::solver::model::soa::vec_bytes;
        vec_bytes(&self.delta) + vec_bytes(&self.count) + self.x_ref.memory_bytes() + vec_bytes(&self.movers)
    }

    /// One pass of pair corrections on `x`.
    ///
    /// The hash search is not redone every pass: it looks for pairs closer than `2r + m`
    /// (`m = MARGIN·r`), and the list serves every later pass. A pair it lacks that is now
    /// closer than `2r` has a particle that moved more than `m/2` since the search: while there
    /// are few of those, their pairs alone are searched ([`self_movers`](super::self_movers)),
    /// else everything is searched again. The corrections are exactly those of a search every
    /// pass (tested), at a fraction of the cost: particles move little between iterations.
    pub fn pass(&mut self, inp: &PassInput<'_>, x: &mut Vec3Soa) {
        let model = inp.model;
        if self.exclusions.is_none() || self.built_seams != model.seams.len() || self.built_radius != inp.radius {
            // Indices were validated when the mesh and seams were built.
            self.exclusions = build_exclusions(model, inp.radius).ok();
            self.built_seams = model.seams.len();
            self.built_radius = inp.radius;
            self.x_ref = Vec3Soa::zeros(0);
        }
        let margin = MARGIN * inp.radius;
        let listed = inp.reuse && self.x_ref.len() == x.len() && self.searched_radius == inp.radius;
        self.movers.clear();
        let most = max_movers(x.len());
        if listed {
            let lim2 = 0.25 * margin * margin;
            for i in 0..x.len() {
                if x.get(i).distance_squared(self.x_ref.get(i)) >= lim2 {
                    self.movers.push(i as u32);
                    if self.movers.len() > most {
                        break;
                    }
                }
            }
        }
        let mut missing = Vec::new();
        if !listed || self.movers.len() > most {
            if !self.search(inp, x, margin) {
                return;
            }
            self.x_ref.clone_from(x);
            self.searched_radius = inp.radius;
            self.searches += 1;
        } else if !self.movers.is_empty() {
            let Some(ex) = self.exclusions.as_ref() else { return };
            let levels = inp.levels;
            let search_radius = inp.radius + 0.5 * margin;
            let movers = Movers {
                x,
                x_ref: &self.x_ref,
                hash: self.finder.hash(),
                movers: &self.movers,
                two_r: 2.0 * inp.radius,
                listed_d2: 4.0 * search_radius * search_radius,
            };
            missing = movers
                .missing_pairs(|a, b| ex.contains(a, b) || !levels_collide(levels[a as usize], levels[b as usize]));
            self.partial_searches += 1;
        }
        self.correct(inp, x, &missing);
    }

    /// Forgets the candidate list (levels changed).
    pub fn forget_pairs(&mut self) {
        self.x_ref = Vec3Soa::zeros(0);
    }

    fn search(&mut self, inp: &PassInput<'_>, x: &Vec3Soa, margin: f32) -> bool {
        let Some(ex) = self.exclusions.as_ref() else { return false };
        let levels = inp.levels;
        let exclude = |a: u32, b: u32| ex.contains(a, b) || !levels_collide(levels[a as usize], levels[b as usize]);
        let finder = &mut self.finder;
        let (xs, ys, zs) = (&x.x, &x.y, &x.z);
        let radius = inp.radius + 0.5 * margin;
        let cell = inp.cell.max(2.0 * radius);
        let found = if x.len() < SMALL {
            if self.serial.is_none() {
                self.serial = rayon::ThreadPoolBuilder::new().num_threads(1).build().ok();
            }
            match &self.serial {
                Some(pool) => pool.install(|| finder.find_pairs(xs, ys, zs, radius, cell, exclude).is_ok()),
                None => finder.find_pairs(xs, ys, zs, radius, cell, exclude).is_ok(),
            }
        } else {
            finder.find_pairs(xs, ys, zs, radius, cell, exclude).is_ok()
        };
        found
    }

    /// The corrections of the listed pairs and of the `missing` ones (sorted, none listed),
    /// in one sorted order.
    fn correct(&mut self, inp: &PassInput<'_>, x: &mut Vec3Soa, missing: &[[u32; 2]]) {
        let model = inp.model;
        let pairs = self.finder.pairs();
        if pairs.is_empty() && missing.is_empty() {
            self.last_pairs = 0;
            return;
        }
        let n = x.len();
        self.delta.clear();
        self.delta.resize(n, Vec3::ZERO);
        self.count.clear();
        self.count.resize(n, 0);
        let two_r = 2.0 * inp.radius;
        let mut overlapping = 0;
        let (delta, count) = (&mut self.delta, &mut self.count);
        merged(pairs, missing, |[i, j]| {
            let (i, j) = (i as usize, j as usize);
            if x.get(i).distance_squared(x.get(j)) >= two_r * two_r {
                return;
            }
            overlapping += 1;
            let wi = if model.pinned[i] { 0.0 } else { 1.0 / model.mass[i] };
            let wj = if model.pinned[j] { 0.0 } else { 1.0 / model.mass[j] };
            let w = wi + wj;
            if w <= 0.0 {
                return;
            }
            let d = x.get(i) - x.get(j);
            let len = d.length();
            // Coincident particles: separate along z, the usual layering direction.
            let nrm = if len > 1e-9 { d / len } else { Vec3::Z };
            let overlap = two_r - len;
            let mut corr = nrm * overlap;
            // Position-level friction on the relative tangential motion of the substep.
            let rel = (x.get(i) - inp.x_start.get(i)) - (x.get(j) - inp.x_start.get(j));
            let rel_t = rel - nrm * rel.dot(nrm);
            let lt = rel_t.length();
            let (si, ki) = (inp.friction)(i);
            let (sj, kj) = (inp.friction)(j);
            let (mu_s, mu_k) = (0.5 * (si + sj), 0.5 * (ki + kj));
            if lt > 0.0 {
                corr -= if lt <= mu_s * overlap { rel_t } else { rel_t * (mu_k * overlap / lt).min(1.0) };
            }
            delta[i] += corr * (wi / w);
            delta[j] -= corr * (wj / w);
            count[i] += 1;
            count[j] += 1;
        });
        self.last_pairs = overlapping;
        for i in 0..n {
            if self.count[i] > 0 {
                x.set(i, x.get(i) + self.delta[i] / self.count[i] as f32);
            }
        }
    }

    /// Forgets the exclusions (the mesh or its seams changed).
    pub fn invalidate(&mut self) {
        self.exclusions = None;
        self.x_ref = Vec3Soa::zeros(0);
    }
}
