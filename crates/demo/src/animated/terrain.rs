//! The seeds' *terrain* look-alike (Wald, *Handling Dynamic Scenes*, docs/design/seeds.md §5): 661
//! instances of two procedurally grown trees on a hilly ground mesh, more than ten million
//! triangles after instancing, the trees swaying a little every frame (so the top level is rebuilt
//! every frame).

use glam::{Affine3A, Quat, Vec3};
use raystage_scene::ObjectKind;

use super::parts::{cylinder, random_direction};
use super::{AnimatedObject, Animation, View};
use crate::{Mesh, Xorshift64};

/// Instanced trees, as in the seed's figure.
const TREES: usize = 661;
/// Half the ground's edge length and its quads per edge.
const HALF_EXTENT: f32 = 100.0;
const GROUND_QUADS: u32 = 200;

/// The terrain scene.
#[derive(Clone, Debug, Default)]
pub struct Terrain;

/// Height of the ground at `(x, z)`: gentle hills.
fn height(x: f32, z: f32) -> f32 {
    2.5 * (x * 0.05).sin() * (z * 0.06).cos() + 1.2 * (x * 0.13 + z * 0.07).sin()
}

impl Animation for Terrain {
    fn name(&self) -> String {
        "terrain".into()
    }

    fn objects(&self) -> Vec<AnimatedObject> {
        vec![
            AnimatedObject { kind: ObjectKind::Static, mesh: ground() },
            AnimatedObject { kind: ObjectKind::Animated, mesh: tree(3, 4, 100, 11) },
            AnimatedObject { kind: ObjectKind::Animated, mesh: tree(2, 5, 220, 23) },
        ]
    }

    fn instances(&self, frame: u32) -> Vec<(usize, Affine3A)> {
        let mut rng = Xorshift64::new(661);
        let side = (TREES as f32).sqrt().ceil() as usize;
        let spacing = 2.0 * HALF_EXTENT * 0.9 / side as f32;
        let mut out = vec![(0, Affine3A::IDENTITY)];
        for i in 0..TREES {
            let jitter = Vec3::new(rng.next_f32() - 0.5, 0.0, rng.next_f32() - 0.5) * spacing * 0.8;
            let (gx, gz) = ((i % side) as f32 + 0.5, (i / side) as f32 + 0.5);
            let mut at = Vec3::new(gx * spacing - HALF_EXTENT * 0.9, 0.0, gz * spacing - HALF_EXTENT * 0.9) + jitter;
            at.y = height(at.x, at.z) - 0.2;
            let (turn, scale) = (rng.next_f32() * std::f32::consts::TAU, 0.8 + 0.5 * rng.next_f32());
            let sway = 0.03 * (frame as f32 * 0.2 + i as f32).sin();
            let t = Affine3A::from_scale_rotation_translation(
                Vec3::splat(scale),
                Quat::from_rotation_z(sway) * Quat::from_rotation_y(turn),
                at,
            );
            out.push((1 + i % 2, t));
        }
        out
    }

    fn deform(&self, _frame: u32) -> Vec<(usize, Vec<Vec3>)> {
        Vec::new()
    }

    fn view(&self) -> View {
        View { eye: Vec3::new(10.0, 30.0, 110.0), target: Vec3::new(0.0, 0.0, 20.0), fov_y_degrees: 50.0, sun: Vec3::new(-0.5, -1.0, -0.35) }
    }
}

/// The hilly ground.
fn ground() -> Mesh {
    let n = GROUND_QUADS;
    let step = 2.0 * HALF_EXTENT / n as f32;
    let mut mesh = Mesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 * step - HALF_EXTENT, j as f32 * step - HALF_EXTENT);
            mesh.vertices.push(Vec3::new(x, height(x, z), z));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c) = (a + 1, a + n + 1);
            mesh.indices.push([a, c, b]);
            mesh.indices.push([b, c, c + 1]);
        }
    }
    mesh
}

/// A tree grown recursively: a trunk splitting into `branching` branches per level for `depth`
/// levels, each tip carrying `leaves` leaf quads. `seed` varies its shape.
fn tree(branching: u32, depth: u32, leaves: u32, seed: u64) -> Mesh {
    let mut mesh = Mesh::default();
    let mut rng = Xorshift64::new(seed);
    grow(&mut mesh, &mut rng, Affine3A::IDENTITY, 0.35, 3.0, branching, depth, leaves);
    mesh
}

/// Adds a branch of radius `radius` and length `length` at `base` (its +y is the branch
/// direction), then its children or, at the last level, its leaves.
#[allow(clippy::too_many_arguments)]
fn grow(mesh: &mut Mesh, rng: &mut Xorshift64, base: Affine3A, radius: f32, length: f32, branching: u32, depth: u32, leaves: u32) {
    mesh.append(&cylinder(radius, radius * 0.7, length, 8), base);
    let tip = base * Affine3A::from_translation(Vec3::new(0.0, length, 0.0));
    if depth == 0 {
        for _ in 0..leaves {
            let at = tip.transform_point3(random_direction(rng) * 0.9 * rng.next_f32().sqrt());
            let (u, v) = (random_direction(rng) * 0.22, random_direction(rng) * 0.22);
            mesh.quad([at, at + u, at + u + v, at + v]);
        }
        return;
    }
    for k in 0..branching {
        let around = std::f32::consts::TAU * (k as f32 + rng.next_f32() * 0.5) / branching as f32;
        let tilt = 0.5 + 0.3 * rng.next_f32();
        let turn = Affine3A::from_rotation_y(around) * Affine3A::from_rotation_z(tilt);
        grow(mesh, rng, tip * turn, radius * 0.65, length * 0.75, branching, depth - 1, leaves);
    }
}
