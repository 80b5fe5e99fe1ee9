//! BART *robots* look-alike: sixteen articulated robots walk the streets of a city of box
//! buildings. Every robot part is an object of its own, placed by a transform hierarchy (hips,
//! knees, shoulders, elbows) every frame: purely hierarchical motion, as in the seed's Table of
//! BART scenes (16 robots × 10 parts + the city = 161 objects, about 100,000 triangles).

use glam::{Affine3A, Vec3};
use raystage_scene::ObjectKind;

use super::parts::{grid_box, uv_sphere};
use super::{AnimatedObject, Animation, View};
use crate::{Mesh, Xorshift64};

/// Number of robots.
const ROBOTS: usize = 16;
/// City blocks along each axis, and their spacing (block plus street).
const BLOCKS: i32 = 5;
const PERIOD: f32 = 12.0;
/// Quads per box face edge of a robot part: 12·7² = 588 triangles a part.
const PART_DETAIL: u32 = 7;

/// The parts of a robot, in object order.
#[derive(Clone, Copy)]
enum Part {
    Torso,
    Head,
    UpperArm(Side),
    LowerArm(Side),
    UpperLeg(Side),
    LowerLeg(Side),
}

#[derive(Clone, Copy)]
enum Side {
    Left,
    Right,
}

impl Side {
    /// −1 left, +1 right (in the robot's frame, facing −z).
    fn sign(self) -> f32 {
        match self {
            Side::Left => -1.0,
            Side::Right => 1.0,
        }
    }
}

const PARTS: [Part; 10] = [
    Part::Torso,
    Part::Head,
    Part::UpperArm(Side::Left),
    Part::UpperArm(Side::Right),
    Part::LowerArm(Side::Left),
    Part::LowerArm(Side::Right),
    Part::UpperLeg(Side::Left),
    Part::UpperLeg(Side::Right),
    Part::LowerLeg(Side::Left),
    Part::LowerLeg(Side::Right),
];

/// The robots scene.
#[derive(Clone, Debug, Default)]
pub struct Robots;

impl Robots {
    /// Where robot `robot` walks: a point of its lane at the city's edge, and its unit direction.
    /// Even robots walk along x, odd ones along −z, each in a lane of an inner street.
    fn route(robot: usize) -> (Vec3, Vec3) {
        let lane = robot / 2;
        let street = [-1.5, -0.5, 0.5, 1.5][lane % 4] * PERIOD + if lane < 4 { -1.0 } else { 1.0 };
        let edge = -(BLOCKS as f32) * PERIOD * 0.5;
        if robot.is_multiple_of(2) { (Vec3::new(edge, 0.0, street), Vec3::X) } else { (Vec3::new(street, 0.0, -edge), Vec3::NEG_Z) }
    }
}

impl Animation for Robots {
    fn name(&self) -> String {
        "robots".into()
    }

    fn objects(&self) -> Vec<AnimatedObject> {
        let mut objects = vec![AnimatedObject { kind: ObjectKind::Static, mesh: city() }];
        for robot in 0..ROBOTS {
            let scale = robot_scale(robot);
            for part in PARTS {
                let mut mesh = part_mesh(part);
                mesh.vertices.iter_mut().for_each(|v| *v *= scale);
                objects.push(AnimatedObject { kind: ObjectKind::Animated, mesh });
            }
        }
        objects
    }

    fn instances(&self, frame: u32) -> Vec<(usize, Affine3A)> {
        let span = BLOCKS as f32 * PERIOD;
        let mut out = vec![(0, Affine3A::IDENTITY)];
        for robot in 0..ROBOTS {
            let scale = robot_scale(robot);
            let (start, dir) = Robots::route(robot);
            // Walk along the lane, wrapping around at the city's far edge.
            let position = start + dir * (frame as f32 * 0.08 + robot as f32 * 7.3).rem_euclid(span);
            let heading = dir.x.atan2(-dir.z);
            let root = Affine3A::from_translation(position) * Affine3A::from_rotation_y(-heading) * Affine3A::from_scale(Vec3::splat(scale));
            let phase = frame as f32 * 0.35 + robot as f32;
            for (k, part) in PARTS.iter().enumerate() {
                out.push((1 + robot * PARTS.len() + k, root * pose(*part, phase) * Affine3A::from_scale(Vec3::splat(1.0 / scale))));
            }
        }
        out
    }

    fn deform(&self, _frame: u32) -> Vec<(usize, Vec<Vec3>)> {
        Vec::new()
    }

    fn view(&self) -> View {
        View { eye: Vec3::new(6.0, 15.0, 36.0), target: Vec3::new(4.0, 0.0, 4.0), fov_y_degrees: 50.0, sun: Vec3::new(-0.45, -1.0, -0.3) }
    }
}

/// How big robot `robot` is: about 3.5 units tall, a little more or less for each.
fn robot_scale(robot: usize) -> f32 {
    1.6 + 0.4 * (robot as f32 * 0.37).fract()
}

/// The city: a ground plane and a grid of blocks of four box buildings each.
fn city() -> Mesh {
    let mut mesh = Mesh::default();
    let half = BLOCKS as f32 * PERIOD * 0.5 + 4.0;
    mesh.quad([Vec3::new(-half, 0.0, half), Vec3::new(half, 0.0, half), Vec3::new(half, 0.0, -half), Vec3::new(-half, 0.0, -half)]);
    let mut rng = Xorshift64::new(2000);
    for bx in 0..BLOCKS {
        for bz in 0..BLOCKS {
            let centre = Vec3::new((bx - BLOCKS / 2) as f32 * PERIOD, 0.0, (bz - BLOCKS / 2) as f32 * PERIOD);
            for (dx, dz) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                let height = 3.0 + 9.0 * rng.next_f32();
                let footprint = 3.0 + 0.6 * rng.next_f32();
                let building = grid_box(Vec3::new(footprint, height, footprint), 3);
                let at = centre + Vec3::new(dx * 2.1, height * 0.5, dz * 2.1);
                mesh.append(&building, Affine3A::from_translation(at));
            }
        }
    }
    mesh
}

/// A part's mesh, centred on its own origin.
fn part_mesh(part: Part) -> Mesh {
    match part {
        Part::Torso => grid_box(Vec3::new(0.6, 0.7, 0.35), PART_DETAIL),
        Part::Head => uv_sphere(0.18, 24, 12),
        Part::UpperArm(_) => grid_box(Vec3::new(0.14, 0.35, 0.14), PART_DETAIL),
        Part::LowerArm(_) => grid_box(Vec3::new(0.12, 0.35, 0.12), PART_DETAIL),
        Part::UpperLeg(_) => grid_box(Vec3::new(0.18, 0.45, 0.18), PART_DETAIL),
        Part::LowerLeg(_) => grid_box(Vec3::new(0.16, 0.45, 0.16), PART_DETAIL),
    }
}

/// Where a part is in the robot's frame at walk phase `phase`: a transform hierarchy from the
/// hips (swinging legs, bending knees) and shoulders (swinging arms, bending elbows).
fn pose(part: Part, phase: f32) -> Affine3A {
    let t = Affine3A::from_translation;
    let swing = |side: Side, amount: f32| Affine3A::from_rotation_x(amount * phase.sin() * side.sign());
    let bob = t(Vec3::new(0.0, 0.03 * (2.0 * phase).sin().abs(), 0.0));
    let hips = bob * t(Vec3::new(0.0, 0.9, 0.0));
    let torso = hips * t(Vec3::new(0.0, 0.35, 0.0));
    match part {
        Part::Torso => torso,
        Part::Head => torso * t(Vec3::new(0.0, 0.55, 0.0)),
        Part::UpperArm(side) => torso * t(Vec3::new(0.38 * side.sign(), 0.3, 0.0)) * swing(side, -0.6) * t(Vec3::new(0.0, -0.175, 0.0)),
        Part::LowerArm(side) => {
            let elbow = torso * t(Vec3::new(0.38 * side.sign(), 0.3, 0.0)) * swing(side, -0.6) * t(Vec3::new(0.0, -0.35, 0.0));
            elbow * Affine3A::from_rotation_x(-0.5) * t(Vec3::new(0.0, -0.175, 0.0))
        }
        Part::UpperLeg(side) => hips * t(Vec3::new(0.12 * side.sign(), 0.0, 0.0)) * swing(side, 0.5) * t(Vec3::new(0.0, -0.225, 0.0)),
        Part::LowerLeg(side) => {
            let knee = hips * t(Vec3::new(0.12 * side.sign(), 0.0, 0.0)) * swing(side, 0.5) * t(Vec3::new(0.0, -0.45, 0.0));
            let bend = 0.4 * (1.0 + (phase + side.sign() * 1.2).sin());
            knee * Affine3A::from_rotation_x(bend) * t(Vec3::new(0.0, -0.225, 0.0))
        }
    }
}
