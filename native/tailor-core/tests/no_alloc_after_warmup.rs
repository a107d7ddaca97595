//! The per-substep collision stages must not allocate once warmed up: a counting global
//! allocator (only possible in its own test binary) checks the rebuilds of the point hash,
//! the collider hash and the self-collision pair search.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use tailor_core::collision::collider_hash::{ColliderHash, InsertionRule};
use tailor_core::collision::{SelfCollision, SpatialHash};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn rebuilds_do_not_allocate() {
    // A wavy 100 x 100 sheet, 1 cm spacing, and a collider made of its triangles below it.
    let n = 100;
    let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
    for i in 0..n {
        for j in 0..n {
            x.push(i as f32 * 0.01);
            y.push(j as f32 * 0.01);
            z.push(0.003 * ((i * 7 + j * 3) as f32).sin());
        }
    }
    let verts: Vec<[f32; 3]> = (0..n * n).map(|k| [x[k], y[k], z[k] - 0.05]).collect();
    let mut tris = vec![];
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let a = (i * n + j) as u32;
            tris.push([a, a + n as u32, a + 1]);
            tris.push([a + 1, a + n as u32, a + n as u32 + 1]);
        }
    }
    let mut hash = SpatialHash::new();
    let mut collider = ColliderHash::new();
    let mut pairs = SelfCollision::new();
    let mut step = |dz: f32| {
        for v in z.iter_mut() {
            *v += dz;
        }
        hash.build_points(&x, &y, &z, 0.01).unwrap();
        collider.build(&verts, &tris, 0.01, InsertionRule::PaperOrPlane).unwrap();
        pairs.find_pairs(&x, &y, &z, 0.005, 0.01, |a, b| b == a + 1).unwrap().len()
    };
    // On one thread the count is exact: our buffers are reused.
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    single.install(|| {
        for _ in 0..3 {
            step(0.0);
        }
        let before = ALLOCS.load(Ordering::Relaxed);
        let found = step(0.0);
        let after = ALLOCS.load(Ordering::Relaxed);
        assert!(found > 0);
        assert_eq!(after - before, 0, "{} allocations in a warmed-up substep", after - before);
    });
    // With several threads rayon's work-stealing deques occasionally grow (an allocation
    // inside the scheduler, not ours): allow that, but nothing proportional to the work.
    for _ in 0..3 {
        step(0.0);
    }
    let before = ALLOCS.load(Ordering::Relaxed);
    for _ in 0..10 {
        step(0.0);
    }
    let per_step = (ALLOCS.load(Ordering::Relaxed) - before) as f64 / 10.0;
    assert!(per_step <= 2.0, "{per_step} allocations per warmed-up substep");
}
