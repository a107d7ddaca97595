//! Shared test helpers: a seeded RNG, synthetic meshes, the location of the shared data.

use std::path::PathBuf;

use glam::Vec3;

/// SplitMix64: tiny, seeded, good enough for property tests.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform in `[-s, s)³`.
    pub fn vec3(&mut self, s: f32) -> Vec3 {
        Vec3::new(self.f32() * 2.0 - 1.0, self.f32() * 2.0 - 1.0, self.f32() * 2.0 - 1.0) * s
    }
}

/// Subdivided icosahedron on a sphere of `radius`, outward winding: `10·4^k + 2` vertices.
pub fn icosphere(subdiv: u32, radius: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from(*p).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdiv {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        let mut nf = Vec::with_capacity(f.len() * 4);
        for &[a, b, c] in &f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            nf.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = nf;
    }
    (v.iter().map(|p| (*p * radius).into()).collect(), f)
}

/// Axis-aligned box `[lo, hi]`, 12 outward triangles.
pub fn box_mesh(lo: [f32; 3], hi: [f32; 3]) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = (0..8).map(|i| [[lo[0], hi[0]][i & 1], [lo[1], hi[1]][(i >> 1) & 1], [lo[2], hi[2]][i >> 2]]).collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3], // z = lo
        [4, 5, 6],
        [5, 7, 6], // z = hi
        [0, 1, 4],
        [1, 5, 4], // y = lo
        [2, 6, 3],
        [3, 6, 7], // y = hi
        [0, 4, 2],
        [2, 4, 6], // x = lo
        [1, 3, 5],
        [3, 7, 5], // x = hi
    ];
    (v, t)
}

pub fn mean_edge_length(v: &[[f32; 3]], t: &[[u32; 3]]) -> f32 {
    let mut sum = 0.0;
    for tri in t {
        for k in 0..3 {
            sum += Vec3::from(v[tri[k] as usize]).distance(Vec3::from(v[tri[(k + 1) % 3] as usize]));
        }
    }
    sum / (3 * t.len()) as f32
}

/// `shared/data` next to the checkout (`TAILOR_DATA` overrides), `None` when absent so that
/// data-driven tests skip cleanly.
pub fn data_dir() -> Option<PathBuf> {
    if let Ok(d) = std::env::var("TAILOR_DATA") {
        let p = PathBuf::from(d);
        return p.is_dir().then_some(p);
    }
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest.ancestors().map(|a| a.join("shared").join("data")).find(|p| p.is_dir())
}

/// A scratch directory unique to one test.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tailor-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}
