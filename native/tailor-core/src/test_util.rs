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

pub use crate::scenes::{box_mesh, icosphere};

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
