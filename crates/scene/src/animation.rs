//! Animations of a scene: a node hierarchy, clips of keyframed channels that move its nodes,
//! skins and morph targets that bend meshes, and how all of it poses the scene at a time.
//!
//! This is where glTF 2.0's animation arithmetic lives (its "Animations" section and Appendix C,
//! interpolation); the importer (`raystage-gltf-import`) only reads a file into these types.
//! Posing is an edit like any other ([`Scene::pose`]): nodes' world matrices become their
//! instances' transforms (a node-animated mesh is an [`crate::ObjectKind::Animated`] object,
//! built once), and skinned or morphed meshes get new vertices through
//! [`Scene::set_vertices`], which refits or rebuilds their trees by the scene's policy
//! (docs/design/architecture.md).

use glam::{Affine3A, Mat3, Mat4, Quat, Vec3, Vec4};
use rayon::prelude::*;

use crate::error::SceneError;
use crate::ids::{InstanceId, ObjectId};
use crate::instance::validate_transform;
use crate::scene::Scene;

/// Vertices at which a deformed mesh is recomputed on all cores rather than on one: below it,
/// handing the work out costs more than it saves.
const PARALLEL_VERTICES: usize = 4096;

/// How a sampler's values are interpolated between keyframes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the keyframe at or before the time.
    Step,
    /// Straight between keyframes; rotations by spherical interpolation along the shorter arc.
    Linear,
    /// Cubic Hermite between keyframes, each keyframe an in-tangent, a value and an
    /// out-tangent; the tangents are per second, so they are scaled by the keyframe interval.
    CubicSpline,
}

/// Keyframes: increasing times and, per keyframe, `width` numbers (three of each for
/// [`Interpolation::CubicSpline`]: in-tangent, value, out-tangent).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframes {
    times: Vec<f32>,
    values: Vec<f32>,
    width: usize,
    interpolation: Interpolation,
}

fn invalid(field: &'static str, message: impl Into<String>) -> SceneError {
    SceneError::OutOfRange { field, message: message.into() }
}

impl Keyframes {
    /// Keyframes at `times` (at least one, finite, strictly increasing) with `values`, `width`
    /// numbers per keyframe (times three for cubic splines), all finite.
    pub fn new(times: Vec<f32>, values: Vec<f32>, width: usize, interpolation: Interpolation) -> Result<Keyframes, SceneError> {
        let per_key = if interpolation == Interpolation::CubicSpline { 3 * width } else { width };
        if times.is_empty() || width == 0 {
            return Err(invalid("sampler", "needs at least one keyframe of at least one number"));
        }
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(invalid("sampler", format!("keyframe time {k} is not finite")));
        }
        if let Some(k) = times.windows(2).position(|w| w[0] >= w[1]) {
            return Err(invalid("sampler", format!("keyframe times must increase: time {} is {} and time {} is {}", k, times[k], k + 1, times[k + 1])));
        }
        if values.len() != times.len() * per_key {
            return Err(invalid(
                "sampler",
                format!("{} keyframe times need {} output numbers ({per_key} each), found {}", times.len(), times.len() * per_key, values.len()),
            ));
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(invalid("sampler", "an output value is not finite"));
        }
        Ok(Keyframes { times, values, width, interpolation })
    }

    /// Numbers per keyframe value.
    pub fn width(&self) -> usize {
        self.width
    }

    /// The time of the last keyframe.
    pub fn end(&self) -> f32 {
        *self.times.last().expect("a sampler has a keyframe")
    }

    /// The value of keyframe `k`.
    fn value(&self, k: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => &self.values[(3 * k + 1) * self.width..(3 * k + 2) * self.width],
            _ => &self.values[k * self.width..(k + 1) * self.width],
        }
    }

    /// The value at `time` into `out` (`width` numbers). Before the first keyframe it is the
    /// first value, after the last the last. `rotation` says the value is a unit quaternion
    /// (x, y, z, w): linear interpolation then goes along the shorter arc, and the result is
    /// normalised.
    pub fn sample(&self, time: f32, rotation: bool, out: &mut [f32]) {
        let n = self.times.len();
        let after = self.times.partition_point(|&t| t <= time);
        if after == 0 || after == n || self.interpolation == Interpolation::Step {
            out.copy_from_slice(self.value(after.saturating_sub(1).min(n - 1)));
        } else {
            let k = after - 1;
            let interval = self.times[k + 1] - self.times[k];
            let s = (time - self.times[k]) / interval;
            let (a, b) = (self.value(k), self.value(k + 1));
            match self.interpolation {
                Interpolation::Linear if rotation => {
                    let q = slerp(Vec4::from_slice(a), Vec4::from_slice(b), s);
                    out.copy_from_slice(&q.to_array());
                }
                Interpolation::Linear => out.iter_mut().enumerate().for_each(|(i, o)| *o = a[i] + (b[i] - a[i]) * s),
                _ => {
                    let w = self.width;
                    let out_tangent = &self.values[(3 * k + 2) * w..(3 * k + 3) * w];
                    let in_tangent = &self.values[(3 * (k + 1)) * w..(3 * (k + 1) + 1) * w];
                    let (s2, s3) = (s * s, s * s * s);
                    let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2);
                    for i in 0..w {
                        out[i] = h00 * a[i] + h10 * interval * out_tangent[i] + h01 * b[i] + h11 * interval * in_tangent[i];
                    }
                }
            }
        }
        if rotation {
            let q = Vec4::from_slice(out).normalize_or(Vec4::W);
            out.copy_from_slice(&q.to_array());
        }
    }
}

/// Spherical interpolation of unit quaternions along the shorter arc: `b` is negated when the
/// two are more than 90° apart in 4D, since `q` and `−q` are the same rotation.
fn slerp(a: Vec4, b: Vec4, s: f32) -> Vec4 {
    let mut dot = a.dot(b);
    let b = if dot < 0.0 {
        dot = -dot;
        -b
    } else {
        b
    };
    if dot > 0.9995 {
        // Nearly the same: sin θ is too small to divide by, and a straight line is as close.
        return (a + (b - a) * s).normalize_or(Vec4::W);
    }
    let theta = dot.acos();
    (a * ((1.0 - s) * theta).sin() + b * (s * theta).sin()) / theta.sin()
}

/// What a channel moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The node's translation (3 numbers).
    Translation,
    /// The node's rotation, a unit quaternion x, y, z, w (4 numbers).
    Rotation,
    /// The node's scale (3 numbers).
    Scale,
    /// The weights of the morph targets of the node's mesh (one number per target).
    Weights,
}

/// One keyframed property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node (an index into [`Rig::nodes`]).
    pub node: usize,
    /// What it moves.
    pub target: Target,
    /// Its keyframes.
    pub keyframes: Keyframes,
}

/// A named animation: channels played together.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// Its name (may be empty).
    pub name: String,
    /// Its channels.
    pub channels: Vec<Channel>,
}

impl Clip {
    /// Seconds from 0 to its last keyframe over all channels.
    pub fn duration(&self) -> f32 {
        self.channels.iter().map(|c| c.keyframes.end()).fold(0.0, f32::max)
    }
}

/// A node's transform relative to its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Local {
    /// A fixed matrix (never animated: glTF animates only nodes given as TRS).
    Matrix(Mat4),
    /// Translation, rotation, scale, applied scale first.
    Trs {
        /// Translation.
        translation: Vec3,
        /// Rotation (unit).
        rotation: Quat,
        /// Scale.
        scale: Vec3,
    },
}

impl Local {
    /// The transform as a matrix.
    pub fn matrix(&self) -> Mat4 {
        match *self {
            Local::Matrix(m) => m,
            Local::Trs { translation, rotation, scale } => Mat4::from_scale_rotation_translation(scale, rotation, translation),
        }
    }
}

/// A node of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Its parent, an index into [`Rig::nodes`] before its own.
    pub parent: Option<usize>,
    /// Its transform at rest.
    pub local: Local,
    /// Its morph target weights at rest.
    pub weights: Vec<f32>,
    /// The instances it places (with its world matrix as their transform).
    pub instances: Vec<InstanceId>,
}

/// A skeleton: joints (nodes) and each joint's inverse bind matrix, which takes the mesh from
/// its bind space into the joint's.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// The joints, indices into [`Rig::nodes`].
    pub joints: Vec<usize>,
    /// One per joint.
    pub inverse_bind: Vec<Mat4>,
}

/// How a skinned mesh's vertices follow its joints: `per_vertex` influences per vertex (four
/// per glTF `JOINTS_n`/`WEIGHTS_n` set), each a joint (an index into the skin's joints) and a
/// weight.
#[derive(Clone, Debug, PartialEq)]
pub struct Binding {
    /// The skin, an index into [`Rig::skins`].
    pub skin: usize,
    /// Influences per vertex.
    pub per_vertex: usize,
    /// `per_vertex` joints for each vertex.
    pub joints: Vec<u32>,
    /// `per_vertex` weights for each vertex, not negative; normalised to sum to 1 by
    /// [`Rig::new`] (glTF asks for a sum of 1; files that miss it by rounding are common).
    pub weights: Vec<f32>,
}

/// The displacements of one morph target, per vertex; an empty list for an attribute it does
/// not move.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position displacements.
    pub positions: Vec<Vec3>,
    /// Normal displacements.
    pub normals: Vec<Vec3>,
    /// Tangent displacements (xyz; the handedness stays).
    pub tangents: Vec<Vec3>,
}

/// A mesh whose vertices move: morphed by its node's weights, then skinned.
#[derive(Clone, Debug, PartialEq)]
pub struct Deformer {
    /// The object whose vertices it sets (an unstructured one of its own).
    pub object: ObjectId,
    /// The node that holds the mesh: its weights morph it, and skinned vertices are relative
    /// to its world matrix (its instance's transform).
    pub node: usize,
    /// Positions at rest.
    pub positions: Vec<Vec3>,
    /// Normals at rest (empty for none).
    pub normals: Vec<Vec3>,
    /// Tangents at rest (empty for none).
    pub tangents: Vec<Vec4>,
    /// Its morph targets.
    pub targets: Vec<MorphTarget>,
    /// Its skin, if it has one.
    pub binding: Option<Binding>,
}

/// Everything that animates a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rig {
    /// The nodes, each after its parent.
    pub nodes: Vec<Node>,
    /// The animations.
    pub clips: Vec<Clip>,
    /// The skins.
    pub skins: Vec<Skin>,
    /// The deformed meshes.
    pub deformers: Vec<Deformer>,
}

/// One animation as a list shows it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AnimationInfo {
    /// Its name (may be empty).
    pub name: String,
    /// Seconds to its last keyframe.
    pub duration: f32,
    /// How many channels it has.
    pub channels: usize,
}

/// Which animations a pose plays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Play {
    /// One, by index.
    Clip(usize),
    /// All of them together.
    All,
}

/// An animation as a front end names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimationChoice<'a> {
    /// By its index among the scene's animations.
    Index(usize),
    /// By its name, or `all` for every animation together.
    Name(&'a str),
}

impl Play {
    /// What `choice` plays among `animations` (the first where it names none); `None` where
    /// it names none of them. `all` plays every animation together, so an animation named
    /// `all` is reachable only by its index: one rule for every front end.
    pub fn choose(animations: &[AnimationInfo], choice: Option<AnimationChoice<'_>>) -> Option<Play> {
        match choice {
            _ if animations.is_empty() => None,
            None => Some(Play::Clip(0)),
            Some(AnimationChoice::Name("all")) => Some(Play::All),
            Some(AnimationChoice::Name(name)) => animations.iter().position(|a| a.name == name).map(Play::Clip),
            Some(AnimationChoice::Index(k)) => (k < animations.len()).then_some(Play::Clip(k)),
        }
    }

    /// Seconds from the start to the end of what this plays among `animations`: the clip's
    /// duration, or the longest one's for all of them (0 for a clip that is not there).
    pub fn duration(self, animations: &[AnimationInfo]) -> f32 {
        match self {
            Play::Clip(k) => animations.get(k).map_or(0.0, |a| a.duration),
            Play::All => animations.iter().map(|a| a.duration).fold(0.0, f32::max),
        }
    }
}

/// The instance transforms and deformed vertices of a rig at a time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pose {
    /// Each node's instances with the node's world matrix.
    pub transforms: Vec<(InstanceId, Affine3A)>,
    /// Each deformer's object with its new vertices.
    pub vertices: Vec<Vertices>,
}

/// A rig's nodes at a time, what [`Rig::pose_evaluated`] places instances and deforms meshes
/// from: every node's world matrix and morph weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluated {
    /// The time, seconds.
    time: f32,
    /// Each node's world matrix.
    world: Vec<Mat4>,
    /// Each node's morph weights.
    weights: Vec<Vec<f32>>,
}

/// A deformed object's vertices at a time.
#[derive(Clone, Debug, PartialEq)]
pub struct Vertices {
    /// The object.
    pub object: ObjectId,
    /// Its positions.
    pub positions: Vec<Vec3>,
    /// Its normals (empty where the mesh has none).
    pub normals: Vec<Vec3>,
    /// Its tangents (empty where the mesh has none).
    pub tangents: Vec<Vec4>,
}

impl Rig {
    /// Checks a rig: parents before children, every index in range, samplers as wide as their
    /// targets, skins and deformers consistent with their meshes; normalises skin weights.
    pub fn new(nodes: Vec<Node>, clips: Vec<Clip>, skins: Vec<Skin>, mut deformers: Vec<Deformer>) -> Result<Rig, SceneError> {
        for (k, node) in nodes.iter().enumerate() {
            if node.parent.is_some_and(|p| p >= k) {
                return Err(invalid("animation", format!("node {k} comes before its parent")));
            }
        }
        for (a, clip) in clips.iter().enumerate() {
            for (c, channel) in clip.channels.iter().enumerate() {
                let node = nodes.get(channel.node).ok_or_else(|| invalid("animation", format!("animation {a} channel {c} targets a missing node")))?;
                let width = match channel.target {
                    Target::Translation | Target::Scale => 3,
                    Target::Rotation => 4,
                    Target::Weights => node.weights.len(),
                };
                if channel.keyframes.width() != width {
                    return Err(invalid("animation", format!("animation {a} channel {c} has {} numbers per keyframe, its target takes {width}", channel.keyframes.width())));
                }
                if channel.target != Target::Weights && matches!(node.local, Local::Matrix(_)) {
                    return Err(invalid("animation", format!("animation {a} channel {c} moves node {}, which is given by a matrix", channel.node)));
                }
            }
        }
        for (s, skin) in skins.iter().enumerate() {
            if skin.joints.len() != skin.inverse_bind.len() || skin.joints.iter().any(|&j| j >= nodes.len()) {
                return Err(invalid("animation", format!("skin {s} has joints that are missing or lack an inverse bind matrix")));
            }
        }
        for (d, deformer) in deformers.iter_mut().enumerate() {
            check_deformer(deformer, &nodes, &skins).map_err(|message| invalid("animation", format!("deformed mesh {d}: {message}")))?;
            if let Some(binding) = &mut deformer.binding {
                for weights in binding.weights.chunks_exact_mut(binding.per_vertex) {
                    let sum: f32 = weights.iter().sum();
                    if sum > 0.0 {
                        weights.iter_mut().for_each(|w| *w /= sum);
                    }
                }
            }
        }
        Ok(Rig { nodes, clips, skins, deformers })
    }

    /// The memory the rig holds, for memory budgets: its node hierarchy, keyframes, skins, and
    /// the deformed meshes' rest vertices, morph targets and skin weights. A file's hierarchy
    /// is kept whole when it is animated, so a few megabytes of nodes hold tens of megabytes.
    pub fn memory_bytes(&self) -> u64 {
        fn held<T>(v: &Vec<T>) -> u64 {
            (v.capacity() * size_of::<T>()) as u64
        }
        let nodes = held(&self.nodes) + self.nodes.iter().map(|n| held(&n.weights) + held(&n.instances)).sum::<u64>();
        let keyframes = |k: &Keyframes| held(&k.times) + held(&k.values);
        let clips = held(&self.clips) + self.clips.iter().map(|c| c.name.capacity() as u64 + held(&c.channels) + c.channels.iter().map(|ch| keyframes(&ch.keyframes)).sum::<u64>()).sum::<u64>();
        let skins = held(&self.skins) + self.skins.iter().map(|s| held(&s.joints) + held(&s.inverse_bind)).sum::<u64>();
        let deformers = held(&self.deformers)
            + self
                .deformers
                .iter()
                .map(|d| {
                    let targets: u64 = d.targets.iter().map(|t| held(&t.positions) + held(&t.normals) + held(&t.tangents)).sum();
                    let binding = d.binding.as_ref().map_or(0, |b| held(&b.joints) + held(&b.weights));
                    held(&d.positions) + held(&d.normals) + held(&d.tangents) + held(&d.targets) + targets + binding
                })
                .sum::<u64>();
        nodes + clips + skins + deformers
    }

    /// The animations: name, duration, channels.
    pub fn animations(&self) -> Vec<AnimationInfo> {
        self.clips.iter().map(|c| AnimationInfo { name: c.name.clone(), duration: c.duration(), channels: c.channels.len() }).collect()
    }

    /// The rig at `time` seconds with `play`: every node's world matrix for its instances, every
    /// deformed mesh's vertices. Fails for a clip that is not there, a time that is not finite,
    /// or a node whose world matrix is singular there (a node scaled to zero).
    pub fn pose(&self, play: Play, time: f32) -> Result<Pose, SceneError> {
        self.pose_evaluated(&self.evaluate(play, time)?)
    }

    /// The animation's part of [`Rig::pose`]: the channels `play` names sampled at `time`
    /// seconds, the hierarchy's world matrices and the morph weights. Fails for a clip that is
    /// not there or a time that is not finite.
    pub fn evaluate(&self, play: Play, time: f32) -> Result<Evaluated, SceneError> {
        if !time.is_finite() {
            return Err(invalid("time", format!("{time} is not finite")));
        }
        let clips: &[Clip] = match play {
            Play::All => &self.clips,
            Play::Clip(k) if k < self.clips.len() => std::slice::from_ref(&self.clips[k]),
            Play::Clip(k) => return Err(invalid("animation", format!("there is no animation {k}: the scene has {}", self.clips.len()))),
        };
        let mut locals: Vec<Local> = self.nodes.iter().map(|n| n.local).collect();
        let mut weights: Vec<Vec<f32>> = self.nodes.iter().map(|n| n.weights.clone()).collect();
        let mut value = [0.0f32; 4];
        for channel in clips.iter().flat_map(|c| &c.channels) {
            let sample = |out: &mut [f32]| channel.keyframes.sample(time, channel.target == Target::Rotation, out);
            match (channel.target, &mut locals[channel.node]) {
                (Target::Weights, _) => sample(&mut weights[channel.node]),
                (Target::Rotation, Local::Trs { rotation, .. }) => {
                    sample(&mut value);
                    *rotation = Quat::from_array(value);
                }
                (Target::Translation, Local::Trs { translation: v, .. }) | (Target::Scale, Local::Trs { scale: v, .. }) => {
                    sample(&mut value[..3]);
                    *v = Vec3::from_slice(&value);
                }
                // Rig::new refuses channels that move a node given by a matrix.
                (_, Local::Matrix(_)) => {}
            }
        }
        let mut world: Vec<Mat4> = Vec::with_capacity(self.nodes.len());
        for (node, local) in self.nodes.iter().zip(&locals) {
            world.push(node.parent.map_or(Mat4::IDENTITY, |p| world[p]) * local.matrix());
        }
        Ok(Evaluated { time, world, weights })
    }

    /// The meshes' part of [`Rig::pose`]: the instance transforms and the skinned and morphed
    /// vertices of the nodes as `evaluated` has them. Fails for a node whose world matrix is
    /// singular (a node scaled to zero).
    pub fn pose_evaluated(&self, evaluated: &Evaluated) -> Result<Pose, SceneError> {
        let Evaluated { time, world, weights } = evaluated;
        let mut pose = Pose::default();
        for (k, node) in self.nodes.iter().enumerate().filter(|(_, n)| !n.instances.is_empty()) {
            let affine = validate_transform("node transform", Affine3A::from_mat4(world[k]))
                .map_err(|e| invalid("animation", format!("node {k} cannot place its meshes at time {time}: {e}")))?;
            pose.transforms.extend(node.instances.iter().map(|&i| (i, affine)));
        }
        for deformer in &self.deformers {
            let joints = deformer.binding.as_ref().map(|b| {
                let to_mesh = world[deformer.node].inverse();
                let skin = &self.skins[b.skin];
                skin.joints.iter().zip(&skin.inverse_bind).map(|(&j, ibm)| to_mesh * world[j] * *ibm).collect::<Vec<Mat4>>()
            });
            pose.vertices.push(deform(deformer, &weights[deformer.node], joints.as_deref()));
        }
        Ok(pose)
    }
}

fn check_deformer(d: &Deformer, nodes: &[Node], skins: &[Skin]) -> Result<(), String> {
    let n = d.positions.len();
    let node = nodes.get(d.node).ok_or("its node is missing")?;
    if (!d.normals.is_empty() && d.normals.len() != n) || (!d.tangents.is_empty() && d.tangents.len() != n) {
        return Err("its normals or tangents do not match its positions".into());
    }
    if d.targets.len() != node.weights.len() {
        return Err(format!("it has {} morph targets and its node {} weights", d.targets.len(), node.weights.len()));
    }
    for (k, t) in d.targets.iter().enumerate() {
        let fits = |len: usize, present: bool| len == 0 || (len == n && present);
        if !fits(t.positions.len(), true) || !fits(t.normals.len(), !d.normals.is_empty()) || !fits(t.tangents.len(), !d.tangents.is_empty()) {
            return Err(format!("morph target {k} does not match the mesh's vertices"));
        }
    }
    if let Some(b) = &d.binding {
        let skin = skins.get(b.skin).ok_or("its skin is missing")?;
        if b.per_vertex == 0 || b.joints.len() != n * b.per_vertex || b.weights.len() != n * b.per_vertex {
            return Err("its joints and weights do not match its vertices".into());
        }
        if let Some(&j) = b.joints.iter().find(|&&j| j as usize >= skin.joints.len()) {
            return Err(format!("a vertex names joint {j}, and its skin has {} joints", skin.joints.len()));
        }
        if let Some(w) = b.weights.iter().find(|w| !w.is_finite() || **w < 0.0) {
            return Err(format!("a vertex has joint weight {w}"));
        }
    }
    Ok(())
}

/// A deformed mesh's vertices: morphed by `weights`, then skinned by the `joints` matrices
/// (mesh space), normals by each matrix's inverse transpose. Large meshes are done on all
/// cores.
fn deform(d: &Deformer, weights: &[f32], joints: Option<&[Mat4]>) -> Vertices {
    let vertex = |i: usize| -> (Vec3, Vec3, Vec4) {
        let (mut pos, mut normal, mut tangent) = (d.positions[i], d.normals.get(i).copied().unwrap_or(Vec3::ZERO), d.tangents.get(i).copied().unwrap_or(Vec4::ZERO));
        for (target, &w) in d.targets.iter().zip(weights).filter(|(_, w)| **w != 0.0) {
            pos += target.positions.get(i).copied().unwrap_or(Vec3::ZERO) * w;
            normal += target.normals.get(i).copied().unwrap_or(Vec3::ZERO) * w;
            tangent += (target.tangents.get(i).copied().unwrap_or(Vec3::ZERO) * w).extend(0.0);
        }
        if let (Some(b), Some(joints)) = (&d.binding, joints) {
            let range = i * b.per_vertex..(i + 1) * b.per_vertex;
            let m = b.joints[range.clone()].iter().zip(&b.weights[range]).fold(Mat4::ZERO, |m, (&j, &w)| m + joints[j as usize] * w);
            pos = m.transform_point3(pos);
            let linear = Mat3::from_mat4(m);
            normal = linear.inverse().transpose() * normal;
            tangent = (linear * tangent.truncate()).extend(tangent.w);
        }
        (pos, normal.normalize_or_zero(), tangent.truncate().normalize_or_zero().extend(tangent.w))
    };
    let n = d.positions.len();
    let all: Vec<(Vec3, Vec3, Vec4)> = if n >= PARALLEL_VERTICES { (0..n).into_par_iter().map(vertex).collect() } else { (0..n).map(vertex).collect() };
    let normals = if d.normals.is_empty() { Vec::new() } else { all.iter().map(|v| v.1).collect() };
    let tangents = if d.tangents.is_empty() { Vec::new() } else { all.iter().map(|v| v.2).collect() };
    Vertices { object: d.object, positions: all.into_iter().map(|v| v.0).collect(), normals, tangents }
}

impl Scene {
    /// Gives the scene its animations (replacing any it had). Every instance and object the rig
    /// names must be in the scene. The rig itself is not journalled: a replica (a cluster's
    /// worker) follows the edits that posing makes, not the rig.
    pub fn set_rig(&mut self, rig: Rig) -> Result<(), SceneError> {
        for node in &rig.nodes {
            for &i in &node.instances {
                self.transform(i)?;
            }
        }
        for d in &rig.deformers {
            let vertices = self.mesh(d.object)?.positions.len();
            if vertices != d.positions.len() {
                return Err(SceneError::WrongLength { field: "positions", got: d.positions.len(), expected: vertices });
            }
        }
        self.rig = Some(std::sync::Arc::new(rig));
        self.posed = None;
        Ok(())
    }

    /// What animates the scene, if anything does: to pose it in steps (see
    /// [`Scene::set_pose`]).
    pub fn rig(&self) -> Option<&Rig> {
        self.rig.as_deref()
    }

    /// The scene's animations: name, duration, channel count (none for a scene without).
    pub fn animations(&self) -> Vec<AnimationInfo> {
        self.rig.as_ref().map(|r| r.animations()).unwrap_or_default()
    }

    /// Poses the scene for a shutter open from `open` to `close` seconds of the animations
    /// `play` names: each animated node's instance moves from its transform at `open` to its
    /// transform at `close` while the shutter is open (`Camera::shutter` `[0, 1]` spans the
    /// interval), so that motion blur takes its motion from the animation; skinned and morphed
    /// meshes are posed at `open` (their vertices have one position per frame).
    pub fn pose_over(&mut self, play: Play, open: f32, close: f32) -> Result<(), SceneError> {
        let Some(rig) = self.rig.clone() else { return Ok(()) };
        let end: std::collections::HashMap<InstanceId, Affine3A> = if close == open { Default::default() } else { rig.pose(play, close)?.transforms.into_iter().collect() };
        let start = rig.pose(play, open)?;
        self.apply_pose(play, open, start, &end)
    }

    /// Poses the scene as [`Scene::pose`] does with `pose`, which the scene's rig made at `time`
    /// seconds of `play` ([`Rig::pose`], or [`Rig::evaluate`] then [`Rig::pose_evaluated`]):
    /// for a caller that times the steps apart.
    pub fn set_pose(&mut self, play: Play, time: f32, pose: Pose) -> Result<(), SceneError> {
        self.apply_pose(play, time, pose, &Default::default())
    }

    /// Sets the instance transforms and vertices of `start`, each instance moving to its
    /// transform in `end` over the shutter where it has one there.
    fn apply_pose(&mut self, play: Play, open: f32, start: Pose, end: &std::collections::HashMap<InstanceId, Affine3A>) -> Result<(), SceneError> {
        for (instance, transform) in start.transforms {
            // An instance that does not move over the interval has no motion to blur.
            self.set_motion(instance, transform, end.get(&instance).copied().filter(|e| *e != transform))?;
        }
        for v in start.vertices {
            self.set_vertices(v.object, v.positions, Some(v.normals).filter(|n| !n.is_empty()), Some(v.tangents).filter(|t| !t.is_empty()))?;
        }
        self.posed = Some((play, open));
        Ok(())
    }

    /// The animations and time the scene was last posed at (the shutter's opening, for
    /// [`Scene::pose_over`]); `None` until it is posed. Frames are tagged with the time, so
    /// that a client sees which moment of the animation an image shows.
    pub fn posed(&self) -> Option<(Play, f32)> {
        self.posed
    }

    /// Poses the scene at `time` seconds of the animations `play` names: sets the transforms of
    /// the animated nodes' instances and the vertices of skinned and morphed meshes. A scene
    /// without animations has nothing to pose: `Ok` with no edit.
    pub fn pose(&mut self, play: Play, time: f32) -> Result<(), SceneError> {
        self.pose_over(play, time, time)
    }
}

#[cfg(test)]
mod tests {
    use std::f32::consts::FRAC_PI_2;

    use super::*;

    #[test]
    fn all_plays_every_animation_even_beside_one_named_all() {
        let clip = |name: &str| AnimationInfo { name: name.into(), duration: 1.0, channels: 1 };
        let animations = [clip("walk"), clip("all"), clip("")];
        let choose = |choice| Play::choose(&animations, choice);
        assert_eq!(choose(None), Some(Play::Clip(0)));
        assert_eq!(choose(Some(AnimationChoice::Name("all"))), Some(Play::All));
        assert_eq!(choose(Some(AnimationChoice::Index(1))), Some(Play::Clip(1)), "the one named `all`, by index");
        assert_eq!(choose(Some(AnimationChoice::Name("walk"))), Some(Play::Clip(0)));
        assert_eq!(choose(Some(AnimationChoice::Index(3))), None);
        assert_eq!(choose(Some(AnimationChoice::Name("run"))), None);
        assert_eq!(Play::choose(&[], None), None, "a scene without animations plays none");
        assert_eq!(Play::choose(&[], Some(AnimationChoice::Name("all"))), None);
    }

    #[test]
    fn what_plays_lasts_its_clip_or_the_longest_of_all() {
        let clip = |duration: f32| AnimationInfo { name: String::new(), duration, channels: 1 };
        let animations = [clip(1.5), clip(4.0), clip(2.0)];
        assert_eq!(Play::Clip(0).duration(&animations), 1.5);
        assert_eq!(Play::All.duration(&animations), 4.0);
        assert_eq!(Play::Clip(3).duration(&animations), 0.0);
    }

    fn at(k: &Keyframes, time: f32, rotation: bool) -> Vec<f32> {
        let mut out = vec![0.0; k.width()];
        k.sample(time, rotation, &mut out);
        out
    }

    fn close(a: &[f32], b: &[f32]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
    }

    #[test]
    fn step_holds_each_value_until_the_next_key_and_clamps_outside() {
        let k = Keyframes::new(vec![1.0, 2.0, 4.0], vec![10.0, 20.0, 40.0], 1, Interpolation::Step).unwrap();
        for (t, v) in [(0.0, 10.0), (1.0, 10.0), (1.99, 10.0), (2.0, 20.0), (3.9, 20.0), (4.0, 40.0), (9.0, 40.0)] {
            assert_eq!(at(&k, t, false), [v], "at {t}");
        }
    }

    #[test]
    fn linear_interpolates_and_clamps_outside() {
        let k = Keyframes::new(vec![1.0, 3.0], vec![0.0, 2.0, -4.0, 4.0, 6.0, 0.0], 3, Interpolation::Linear).unwrap();
        assert!(close(&at(&k, 2.0, false), &[2.0, 4.0, -2.0]));
        assert!(close(&at(&k, 2.5, false), &[3.0, 5.0, -1.0]));
        assert!(close(&at(&k, -1.0, false), &[0.0, 2.0, -4.0]), "before the first key");
        assert!(close(&at(&k, 7.0, false), &[4.0, 6.0, 0.0]), "after the last key");
    }

    #[test]
    fn rotations_slerp_along_the_shorter_arc() {
        // 0° and 90° about z: halfway is 45°.
        let (a, b) = (Quat::IDENTITY, Quat::from_rotation_z(FRAC_PI_2));
        let values = [a.to_array(), b.to_array()].concat();
        let k = Keyframes::new(vec![0.0, 1.0], values, 4, Interpolation::Linear).unwrap();
        assert!(close(&at(&k, 0.5, true), &Quat::from_rotation_z(FRAC_PI_2 / 2.0).to_array()));
        // The same end rotation stored as −q: the dot is negative, so the sign flips and the
        // path is still the 45° one (not the long way round through 225°).
        let values = [a.to_array(), (-b).to_array()].concat();
        let k = Keyframes::new(vec![0.0, 1.0], values, 4, Interpolation::Linear).unwrap();
        let half = Quat::from_array(at(&k, 0.5, true).try_into().unwrap());
        assert!(half.angle_between(Quat::from_rotation_z(FRAC_PI_2 / 2.0)) < 1e-3, "{half}");
        // A third of the way: sin-weighted, by hand: angle 30°.
        let third = Quat::from_array(at(&k, 1.0 / 3.0, true).try_into().unwrap());
        assert!(third.angle_between(Quat::from_rotation_z(FRAC_PI_2 / 3.0)) < 1e-3, "{third}");
    }

    #[test]
    fn cubic_splines_scale_tangents_by_the_key_interval() {
        // Keys at 0 and 2 (interval 2): value 0 with out-tangent 1, value 4 with in-tangent 3.
        // At s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = −0.125, so
        // 0.5·0 + 0.125·2·1 + 0.5·4 − 0.125·2·3 = 0.25 + 2 − 0.75 = 1.5.
        let values = vec![9.0, 0.0, 1.0, 3.0, 4.0, 9.0];
        let k = Keyframes::new(vec![0.0, 2.0], values, 1, Interpolation::CubicSpline).unwrap();
        assert!(close(&at(&k, 1.0, false), &[1.5]));
        // At s = 0.25: h00 = 0.84375, h10 = 0.140625, h01 = 0.15625, h11 = −0.046875:
        // 0.28125 + 0.625 − 0.28125 = 0.625.
        assert!(close(&at(&k, 0.5, false), &[0.625]));
        // Outside the keys: the values, never the tangents.
        assert_eq!(at(&k, -1.0, false), [0.0]);
        assert_eq!(at(&k, 3.0, false), [4.0]);
    }

    #[test]
    fn bad_keyframes_are_refused() {
        assert!(Keyframes::new(vec![0.0, 1.0], vec![0.0; 3], 1, Interpolation::Linear).is_err(), "count mismatch");
        assert!(Keyframes::new(vec![0.0, 1.0], vec![0.0; 2], 1, Interpolation::CubicSpline).is_err(), "cubic needs triplets");
        assert!(Keyframes::new(vec![0.0, f32::NAN], vec![0.0; 2], 1, Interpolation::Linear).is_err(), "NaN time");
        assert!(Keyframes::new(vec![1.0, 1.0], vec![0.0; 2], 1, Interpolation::Linear).is_err(), "times not increasing");
        assert!(Keyframes::new(vec![0.0], vec![f32::INFINITY], 1, Interpolation::Step).is_err(), "infinite value");
        assert!(Keyframes::new(vec![], vec![], 1, Interpolation::Step).is_err(), "no keys");
    }

    fn trs(translation: Vec3) -> Local {
        Local::Trs { translation, rotation: Quat::IDENTITY, scale: Vec3::ONE }
    }

    fn node(parent: Option<usize>, local: Local) -> Node {
        Node { parent, local, weights: Vec::new(), instances: Vec::new() }
    }

    /// A strip of vertices along +y, from y = 0 to 2, the lower half bound to joint 0 at the
    /// origin, the upper to joint 1 at y = 1, which the animation turns by 90° about z.
    fn bent_arm(weights: Vec<f32>) -> Rig {
        let positions: Vec<Vec3> = (0..=4).map(|k| Vec3::new(0.1, k as f32 * 0.5, 0.0)).collect();
        let nodes = vec![node(None, trs(Vec3::ZERO)), node(Some(0), trs(Vec3::ZERO)), node(Some(1), trs(Vec3::Y))];
        let skin = Skin { joints: vec![1, 2], inverse_bind: vec![Mat4::IDENTITY, Mat4::from_translation(-Vec3::Y)] };
        let joints = positions.iter().flat_map(|p| if p.y <= 1.0 { [0, 1] } else { [1, 0] }).collect();
        let binding = Binding { skin: 0, per_vertex: 2, joints, weights };
        let deformer = Deformer { object: ObjectId(0), node: 0, positions, normals: vec![Vec3::X; 5], tangents: Vec::new(), targets: Vec::new(), binding: Some(binding) };
        let turn = Quat::from_rotation_z(FRAC_PI_2);
        let channel = Channel {
            node: 2,
            target: Target::Rotation,
            keyframes: Keyframes::new(vec![0.0, 1.0], [Quat::IDENTITY.to_array(), turn.to_array()].concat(), 4, Interpolation::Linear).unwrap(),
        };
        Rig::new(nodes, vec![Clip { name: "bend".into(), channels: vec![channel] }], vec![skin], vec![deformer]).unwrap()
    }

    #[test]
    fn a_two_joint_skin_bends_by_90_degrees() {
        let rig = bent_arm([[1.0, 0.0]; 5].concat());
        assert_eq!(rig.animations(), [AnimationInfo { name: "bend".into(), duration: 1.0, channels: 1 }]);
        let pose = rig.pose(Play::Clip(0), 1.0).unwrap();
        let Vertices { positions, normals, .. } = &pose.vertices[0];
        // By hand: the lower vertices stay; an upper vertex (0.1, y) is (0.1, y − 1) from the
        // joint at (0, 1), which turns it by 90° to (−(y − 1), 0.1): (−(y − 1), 1.1).
        let expected = [Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.1, 0.5, 0.0), Vec3::new(0.1, 1.0, 0.0), Vec3::new(-0.5, 1.1, 0.0), Vec3::new(-1.0, 1.1, 0.0)];
        for (p, e) in positions.iter().zip(expected) {
            assert!(p.abs_diff_eq(e, 1e-5), "{p} != {e}");
        }
        assert!(normals[4].abs_diff_eq(Vec3::Y, 1e-5), "the upper normals turn with the joint: {}", normals[4]);
        assert!(normals[0].abs_diff_eq(Vec3::X, 1e-5));
        // At rest (time 0) nothing moves.
        let rest = rig.pose(Play::Clip(0), 0.0).unwrap();
        assert!(rest.vertices[0].positions.iter().zip(&rig.deformers[0].positions).all(|(a, b)| a.abs_diff_eq(*b, 1e-6)));
    }

    #[test]
    fn posing_in_steps_poses_as_posing_at_once() {
        let rig = bent_arm([[1.0, 0.0]; 5].concat());
        let evaluated = rig.evaluate(Play::Clip(0), 0.5).unwrap();
        assert_eq!(rig.pose_evaluated(&evaluated).unwrap(), rig.pose(Play::Clip(0), 0.5).unwrap());
        let mut scene = Scene::new();
        let object = scene.add_object(crate::ObjectKind::Unstructured, crate::Mesh::new(rig.deformers[0].positions.clone(), vec![[0, 1, 3], [1, 4, 3]])).unwrap();
        scene.add_instance(object, Affine3A::IDENTITY).unwrap();
        let mut rig = rig;
        // The scene's mesh has no normals to pose.
        (rig.deformers[0].object, rig.deformers[0].normals) = (object, Vec::new());
        scene.set_rig(rig).unwrap();
        let mut stepped = scene.clone();
        scene.pose(Play::Clip(0), 0.5).unwrap();
        let rig = stepped.rig().unwrap().clone();
        let pose = rig.pose_evaluated(&rig.evaluate(Play::Clip(0), 0.5).unwrap()).unwrap();
        stepped.set_pose(Play::Clip(0), 0.5, pose).unwrap();
        assert_eq!(stepped.mesh(object).unwrap(), scene.mesh(object).unwrap());
        assert_ne!(stepped.mesh(object).unwrap().positions, rig.deformers[0].positions, "the arm is bent at 0.5 s");
        assert_eq!(stepped.posed(), scene.posed());
    }

    #[test]
    fn skin_weights_that_do_not_sum_to_one_are_normalised() {
        // Weights 0.25 and 0.25 on the top vertex: normalised to 0.5 and 0.5, the vertex lands
        // halfway between where each joint alone takes it.
        let mut weights = [[1.0, 0.0]; 5].concat();
        weights[8..10].copy_from_slice(&[0.25, 0.25]);
        let rig = bent_arm(weights);
        assert_eq!(rig.deformers[0].binding.as_ref().unwrap().weights[8..10], [0.5, 0.5]);
        let pose = rig.pose(Play::Clip(0), 1.0).unwrap();
        let halfway = (Vec3::new(-1.0, 1.1, 0.0) + Vec3::new(0.1, 2.0, 0.0)) * 0.5;
        assert!(pose.vertices[0].positions[4].abs_diff_eq(halfway, 1e-5), "{}", pose.vertices[0].positions[4]);
    }

    #[test]
    fn out_of_range_joints_are_refused() {
        let mut rig = bent_arm([[1.0, 0.0]; 5].concat());
        rig.deformers[0].binding.as_mut().unwrap().joints[0] = 7;
        assert!(Rig::new(rig.nodes, rig.clips, rig.skins, rig.deformers).is_err());
    }

    #[test]
    fn a_morph_target_at_half_weight_moves_halfway() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let target = MorphTarget { positions: vec![Vec3::Z * 2.0, Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)], normals: Vec::new(), tangents: Vec::new() };
        let mut morphed = node(None, trs(Vec3::ZERO));
        morphed.weights = vec![0.0];
        let channel = Channel { node: 0, target: Target::Weights, keyframes: Keyframes::new(vec![0.0, 1.0], vec![0.0, 1.0], 1, Interpolation::Linear).unwrap() };
        let deformer = Deformer { object: ObjectId(0), node: 0, positions, normals: Vec::new(), tangents: Vec::new(), targets: vec![target], binding: None };
        let rig = Rig::new(vec![morphed], vec![Clip { name: String::new(), channels: vec![channel] }], Vec::new(), vec![deformer]).unwrap();
        let pose = rig.pose(Play::All, 0.5).unwrap();
        assert_eq!(pose.vertices[0].positions, [Vec3::Z, Vec3::X, Vec3::new(0.0, 1.0, -0.5)]);
    }

    #[test]
    fn posing_copies_what_a_snapshot_holds() {
        let mut scene = Scene::new();
        let mesh = crate::Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
        let object = scene.add_object(crate::ObjectKind::Unstructured, mesh.clone()).unwrap();
        let instance = scene.add_instance(object, Affine3A::IDENTITY).unwrap();
        let mut root = node(None, trs(Vec3::ZERO));
        (root.weights, root.instances) = (vec![0.0], vec![instance]);
        let target = MorphTarget { positions: vec![Vec3::Z; 3], ..MorphTarget::default() };
        let deformer = Deformer { object, node: 0, positions: mesh.positions.clone(), normals: Vec::new(), tangents: Vec::new(), targets: vec![target], binding: None };
        let channel = Channel { node: 0, target: Target::Weights, keyframes: Keyframes::new(vec![0.0, 1.0], vec![0.0, 1.0], 1, Interpolation::Linear).unwrap() };
        scene.set_rig(Rig::new(vec![root], vec![Clip { name: "lift".into(), channels: vec![channel] }], Vec::new(), vec![deformer]).unwrap()).unwrap();
        let snapshot = scene.clone();
        scene.pose(Play::Clip(0), 1.0).unwrap();
        assert_eq!(scene.mesh(object).unwrap().positions[0], Vec3::Z);
        assert_eq!(snapshot.mesh(object).unwrap().positions[0], Vec3::ZERO, "the snapshot keeps the pose it was taken in");
        assert_eq!(snapshot.animations(), scene.animations());
        assert_eq!((snapshot.posed(), scene.posed()), (None, Some((Play::Clip(0), 1.0))), "a scene says when it was posed");
    }

    #[test]
    fn posing_refits_a_deformed_object_and_never_rebuilds_an_animated_one() {
        // A triangle at x ≥ 0 that a morph target lifts to z = 1, and one at x ≤ 0 (its own,
        // animated object) that a node moves to z = 1; both start at z = 0.
        let mut scene = Scene::new();
        let right = crate::Mesh::new(vec![Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)], vec![[0, 1, 2]]);
        let left = crate::Mesh::new(vec![Vec3::ZERO, Vec3::new(-1.0, 1.0, 0.0), Vec3::new(-1.0, -1.0, 0.0)], vec![[0, 1, 2]]);
        let morphed = scene.add_object(crate::ObjectKind::Unstructured, right.clone()).unwrap();
        let moved = scene.add_object(crate::ObjectKind::Animated, left).unwrap();
        let (a, b) = (scene.add_instance(morphed, Affine3A::IDENTITY).unwrap(), scene.add_instance(moved, Affine3A::IDENTITY).unwrap());
        let mut nodes = vec![node(None, trs(Vec3::ZERO)), node(None, trs(Vec3::ZERO))];
        (nodes[0].weights, nodes[0].instances, nodes[1].instances) = (vec![0.0], vec![a], vec![b]);
        let target = MorphTarget { positions: vec![Vec3::Z; 3], ..MorphTarget::default() };
        let deformer = Deformer { object: morphed, node: 0, positions: right.positions, normals: Vec::new(), tangents: Vec::new(), targets: vec![target], binding: None };
        let linear = |values: Vec<f32>, width| Keyframes::new(vec![0.0, 1.0], values, width, Interpolation::Linear).unwrap();
        let channels = vec![
            Channel { node: 0, target: Target::Weights, keyframes: linear(vec![0.0, 1.0], 1) },
            Channel { node: 1, target: Target::Translation, keyframes: linear(vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0], 3) },
        ];
        scene.set_rig(Rig::new(nodes, vec![Clip { name: "up".into(), channels }], Vec::new(), vec![deformer]).unwrap()).unwrap();
        let rays = [raystage_kernel::Ray::new(Vec3::new(0.5, 0.0, 5.0), Vec3::NEG_Z), raystage_kernel::Ray::new(Vec3::new(-0.5, 0.0, 5.0), Vec3::NEG_Z)];
        let distances = |scene: &Scene| {
            let frame = scene.frame();
            let hits: Vec<f32> = rays.iter().map(|r| frame.intersect(r, 0.0).expect("a hit").t).collect();
            (hits, frame.work())
        };
        let (before, work) = distances(&scene);
        assert_eq!((before, work.built), (vec![5.0, 5.0], 2));
        scene.pose(Play::Clip(0), 1.0).unwrap();
        let (after, work) = distances(&scene);
        assert_eq!(after, [4.0, 4.0], "both moved up by 1");
        assert_eq!((work.built, work.refitted, work.rebuilt), (0, 1, 0), "only the morphed tree is touched, by a refit");
    }

    #[test]
    fn node_animation_moves_children_with_their_parents() {
        let mut nodes = vec![node(None, trs(Vec3::ZERO)), node(Some(0), trs(Vec3::X))];
        nodes[1].instances = vec![InstanceId(3)];
        let channel = Channel { node: 0, target: Target::Translation, keyframes: Keyframes::new(vec![0.0, 2.0], vec![0.0, 0.0, 0.0, 0.0, 4.0, 0.0], 3, Interpolation::Linear).unwrap() };
        let rig = Rig::new(nodes, vec![Clip { name: "up".into(), channels: vec![channel] }], Vec::new(), Vec::new()).unwrap();
        let pose = rig.pose(Play::Clip(0), 1.0).unwrap();
        assert_eq!(pose.transforms, [(InstanceId(3), Affine3A::from_translation(Vec3::new(1.0, 2.0, 0.0)))]);
        assert!(rig.pose(Play::Clip(1), 0.0).is_err());
        assert!(rig.pose(Play::Clip(0), f32::NAN).is_err());
    }
}
