//! What a scene says it takes (`Scene::memory_bytes`, by which the server budgets scenes)
//! against what it allocates: a counting allocator measures the heap a hundred thousand instances
//! of one triangle take, with the frame that renders them held, and the scene's count must be
//! within 1.5× of it either way. (Before instances were counted, a million of them read as a few
//! hundred bytes while they took 355 MiB.)

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicI64, Ordering};

use glam::{Affine3A, Vec3};
use raystage_scene::{Mesh, ObjectKind, Scene};

/// The system allocator, counting the bytes live on the heap.
struct Counting;

static LIVE: AtomicI64 = AtomicI64::new(0);

// SAFETY: forwards to the system allocator; the counter does not affect the memory handed out.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as i64, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as i64, Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_add(new_size as i64 - layout.size() as i64, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

#[test]
fn instances_are_counted_as_they_take_memory() {
    let mut scene = Scene::new();
    let triangle = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    let object = scene.add_object(ObjectKind::Static, triangle).unwrap();
    let (said_before, live_before) = (scene.memory_bytes(), LIVE.load(Ordering::Relaxed));
    let n = 100_000;
    for i in 0..n {
        let at = Vec3::new((i % 317) as f32 * 2.0, (i / 317) as f32 * 2.0, 0.0);
        scene.add_instance(object, Affine3A::from_translation(at)).unwrap();
    }
    let frame = scene.frame();
    let taken = (LIVE.load(Ordering::Relaxed) - live_before) as f64;
    let said = (scene.memory_bytes() - said_before) as f64;
    drop(frame);
    eprintln!("{n} instances: the scene says {:.0} bytes each, they took {:.0}", said / n as f64, taken / n as f64);
    assert!(taken > 100.0 * n as f64, "{taken} bytes measured for {n} instances");
    assert!(said / taken > 1.0 / 1.5 && said / taken < 1.5, "the scene says {said} bytes, {:.0} per instance; it took {taken}, {:.0} per instance", said / n as f64, taken / n as f64);
}
