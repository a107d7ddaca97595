//! Structure-of-arrays storage for per-particle 3-vectors.
//!
//! Positions, velocities, predictions and right-hand sides are three `Vec<f32>` each, so that
//! the per-coordinate loops vectorise and the GPU backend can upload the same buffers.

use glam::Vec3;

/// Heap bytes a `Vec` holds (its capacity, not its length), for the memory reports.
#[inline]
pub fn vec_bytes<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

/// Three parallel `f32` arrays, one per coordinate.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Vec3Soa {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl Vec3Soa {
    pub fn zeros(n: usize) -> Self {
        Self { x: vec![0.0; n], y: vec![0.0; n], z: vec![0.0; n] }
    }

    pub fn from_aos(points: &[[f32; 3]]) -> Self {
        Self {
            x: points.iter().map(|p| p[0]).collect(),
            y: points.iter().map(|p| p[1]).collect(),
            z: points.iter().map(|p| p[2]).collect(),
        }
    }

    pub fn to_aos(&self) -> Vec<[f32; 3]> {
        (0..self.len()).map(|i| [self.x[i], self.y[i], self.z[i]]).collect()
    }

    /// Writes the interleaved `[x0, y0, z0, x1, …]` layout into `out` (length 3·n).
    pub fn write_interleaved(&self, out: &mut [f32]) {
        for (i, o) in out.chunks_exact_mut(3).enumerate() {
            o[0] = self.x[i];
            o[1] = self.y[i];
            o[2] = self.z[i];
        }
    }

    /// Reads the interleaved layout (length 3·n).
    pub fn read_interleaved(&mut self, src: &[f32]) {
        for (i, s) in src.chunks_exact(3).enumerate() {
            self.x[i] = s[0];
            self.y[i] = s[1];
            self.z[i] = s[2];
        }
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Heap bytes of the three arrays.
    pub fn memory_bytes(&self) -> usize {
        vec_bytes(&self.x) + vec_bytes(&self.y) + vec_bytes(&self.z)
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    #[inline(always)]
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    pub fn set(&mut self, i: usize, v: Vec3) {
        self.x[i] = v.x;
        self.y[i] = v.y;
        self.z[i] = v.z;
    }

    pub fn copy_from(&mut self, other: &Vec3Soa) {
        self.x.copy_from_slice(&other.x);
        self.y.copy_from_slice(&other.y);
        self.z.copy_from_slice(&other.z);
    }

    pub fn all_finite(&self) -> bool {
        self.x.iter().chain(&self.y).chain(&self.z).all(|v| v.is_finite())
    }

    /// The largest vector length (NaN if any component is NaN).
    pub fn max_length(&self) -> f32 {
        let mut m2 = 0.0f32;
        for i in 0..self.len() {
            let l2 = self.x[i] * self.x[i] + self.y[i] * self.y[i] + self.z[i] * self.z[i];
            if l2.is_nan() {
                return f32::NAN;
            }
            m2 = m2.max(l2);
        }
        m2.sqrt()
    }
}

/// A raw view of a [`Vec3Soa`] that parallel kernels write through.
///
/// Safety contract: callers write only indices no other thread reads or writes in the same
/// parallel region. The Gauss-Seidel sweep guarantees this through the graph colouring (no two
/// particles of one colour share a constraint, so an update reads only other colours), and
/// per-particle passes write only their own index.
#[derive(Clone, Copy)]
pub(crate) struct SoaPtr {
    x: *mut f32,
    y: *mut f32,
    z: *mut f32,
    len: usize,
}

unsafe impl Send for SoaPtr {}
unsafe impl Sync for SoaPtr {}

impl SoaPtr {
    pub fn new(v: &mut Vec3Soa) -> Self {
        Self { x: v.x.as_mut_ptr(), y: v.y.as_mut_ptr(), z: v.z.as_mut_ptr(), len: v.len() }
    }

    #[inline(always)]
    pub unsafe fn set(&self, i: usize, v: Vec3) {
        debug_assert!(i < self.len);
        *self.x.add(i) = v.x;
        *self.y.add(i) = v.y;
        *self.z.add(i) = v.z;
    }
}
