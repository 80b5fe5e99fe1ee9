//! What a scene says it takes (`Scene::memory_bytes`, by which the server budgets scenes)
//! against what it allocates: a counting allocator measures the heap that a hundred thousand
//! instances of one triangle, or lights, or the nodes of an animated hierarchy take, with the
//! frame that renders them held, and the scene's count must be within 1.5× of it either way.
//! (Before instances were counted, a million of them read as a few hundred bytes while they took
//! 355 MiB; an animated glTF file's hierarchy, kept whole to pose it, was not counted at all.)
//! A server's resident memory is measured in `tests/serve_memory.rs` at the root, where the
//! allocator's keeping of freed memory blurs what these measure exactly.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicI64, Ordering};

use glam::{Affine3A, Quat, Vec3};
use raystage_scene::{Channel, Clip, InstanceId, Interpolation, Keyframes, Light, Local, Mesh, Node, ObjectKind, Rig, Scene, Target};

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

/// The tests one at a time: the counter counts every thread's allocations.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// This test's turn to allocate, a scene of one triangle's object, and the object (bound in
/// this order, the turn is given up after the scene is dropped).
fn triangle_scene() -> (std::sync::MutexGuard<'static, ()>, Scene, raystage_scene::ObjectId) {
    let turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut scene = Scene::new();
    let triangle = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    let object = scene.add_object(ObjectKind::Static, triangle).unwrap();
    (turn, scene, object)
}

/// Checks that `n` of `what`, which `add` puts into `scene`, take (with a frame of the scene
/// held) what the scene says they do, within 1.5× either way, and at least `least` bytes each
/// (so that the measurement is of something).
fn says_what_it_takes(what: &str, n: usize, least: f64, scene: &mut Scene, add: impl FnOnce(&mut Scene)) {
    let (said_before, live_before) = (scene.memory_bytes(), LIVE.load(Ordering::Relaxed));
    add(scene);
    let frame = scene.frame();
    let taken = (LIVE.load(Ordering::Relaxed) - live_before) as f64;
    let said = (scene.memory_bytes() - said_before) as f64;
    drop(frame);
    eprintln!("{n} {what}: the scene says {:.0} bytes each, they took {:.0}", said / n as f64, taken / n as f64);
    assert!(taken > least * n as f64, "{taken} bytes measured for {n} {what}");
    assert!(said / taken > 1.0 / 1.5 && said / taken < 1.5, "the scene says {said} bytes, {:.0} per one of {what}; it took {taken}, {:.0} per one", said / n as f64, taken / n as f64);
}

#[test]
fn instances_are_counted_as_they_take_memory() {
    let (_turn, mut scene, object) = triangle_scene();
    says_what_it_takes("instances", 100_000, 100.0, &mut scene, |scene| {
        for i in 0..100_000 {
            let at = Vec3::new((i % 317) as f32 * 2.0, (i / 317) as f32 * 2.0, 0.0);
            scene.add_instance(object, Affine3A::from_translation(at)).unwrap();
        }
    });
}

/// Lights are counted with the copy a frame takes of them.
#[test]
fn lights_are_counted_as_they_take_memory() {
    let (_turn, mut scene, _) = triangle_scene();
    says_what_it_takes("lights", 100_000, 50.0, &mut scene, |scene| {
        for i in 0..100_000 {
            scene.add_light(Light::Point { position: Vec3::new(i as f32, 1.0, 0.0), intensity: Vec3::ONE }).unwrap();
        }
    });
}

/// An animated hierarchy is counted as its nodes take memory: 400 chains of 256 nodes (as deep
/// as the glTF importer takes), each placing one instance at its end, the first moved by an
/// animation.
#[test]
fn a_rigs_nodes_are_counted_as_they_take_memory() {
    const LEVELS: usize = 256;
    const CHAINS: usize = 400;
    let (_turn, mut scene, object) = triangle_scene();
    let placed: Vec<InstanceId> = (0..CHAINS).map(|_| scene.add_instance(object, Affine3A::IDENTITY).unwrap()).collect();
    says_what_it_takes("nodes", CHAINS * LEVELS, 50.0, &mut scene, |scene| {
        let nodes = (0..CHAINS * LEVELS)
            .map(|k| Node {
                parent: (k % LEVELS != 0).then(|| k - 1),
                local: Local::Trs { translation: Vec3::Y * 1e-3, rotation: Quat::IDENTITY, scale: Vec3::ONE },
                weights: Vec::new(),
                instances: if k % LEVELS == LEVELS - 1 { vec![placed[k / LEVELS]] } else { Vec::new() },
            })
            .collect();
        let keyframes = Keyframes::new(vec![0.0, 1.0], vec![0.0, 0.0, 0.0, 0.0, 1.0, 0.0], 3, Interpolation::Linear).unwrap();
        let clip = Clip { name: String::new(), channels: vec![Channel { node: 0, target: Target::Translation, keyframes }] };
        scene.set_rig(Rig::new(nodes, vec![clip], Vec::new(), Vec::new()).unwrap()).unwrap();
    });
}
