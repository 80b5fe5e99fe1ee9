//! The animation benchmark (`raystage-bench animation`): a skinned glTF asset played frame by
//! frame at 24 frames per second, as `raystage render --frames` plays it, timing each step of a
//! frame apart: *evaluation* (the animation's channels sampled, the node hierarchy's world
//! matrices: `Rig::evaluate`), *skinning* (joint matrices, the skinned vertices on all cores,
//! handed to the scene: `Rig::pose_evaluated`, `Scene::set_pose`), the *tree update* (the
//! skinned object's tree refitted or rebuilt as the scene's policy chooses, lazily inside the
//! frame; the counts say which) and the eye-light preview's *render* at 1280×720, one sample
//! per pixel, then the same frame's primary rays traced alone (closest hits).
//!
//! With the `embree` feature, Embree 3 takes the very same skinned vertices each frame, its
//! object committed with `RTC_BUILD_QUALITY_REFIT` in one scene and rebuilt
//! (`RTC_BUILD_QUALITY_LOW`, Embree's choice for geometry rebuilt every frame) in another, and
//! traces the same primary rays (`rtcIntersect1`); the systems go one after the other within
//! each frame, and raystage's update and trace over Embree's are medians of the frames' ratios,
//! each pair having met the same phase of a shared machine. Frame 0 (the first builds) is left
//! out; figures are medians over the other frames.

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use raystage_gltf_import::Limits;
use raystage_kernel::Ray;
use raystage_render::{Integrator, RenderSettings, render};
use raystage_scene::{Frame, ObjectId, Play, Scene};
use serde::Serialize;

use crate::dynamic::{HEIGHT, WIDTH, primary_rays};
use crate::kernel::median;

/// Rings and sides of the generated tube, 99,840 triangles (`raystage_demo::animated_assets::skinned_tube`).
const TUBE: (usize, usize) = (196, 256);
/// Frames per second the animation is played at.
const FPS: f32 = 24.0;

/// A skinned asset of the benchmark.
#[derive(Clone, Debug, PartialEq)]
pub enum Asset {
    /// Khronos' RiggedSimple, a cylinder of two joints (188 triangles), checked in.
    RiggedSimple,
    /// The generated skinned tube of [`TUBE`] rings and sides (99,840 triangles, 8 joints).
    Tube,
    /// A glTF file.
    File(PathBuf),
}

impl Asset {
    /// `rigged`, `tube`, or the path of a `.glb` or `.gltf` file.
    pub fn from_name(name: &str) -> Option<Asset> {
        match name {
            "rigged" => Some(Asset::RiggedSimple),
            "tube" => Some(Asset::Tube),
            path if path.ends_with(".glb") || path.ends_with(".gltf") => Some(Asset::File(PathBuf::from(path))),
            _ => None,
        }
    }

    /// The name in tables.
    pub fn name(&self) -> String {
        match self {
            Asset::RiggedSimple => "rigged-simple".into(),
            Asset::Tube => "tube-100k".into(),
            Asset::File(path) => path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned()),
        }
    }

    /// The asset imported into a scene (posed at time 0 of its first animation, as it opens).
    fn scene(&self) -> Result<Scene, String> {
        let import = match self {
            Asset::RiggedSimple => raystage_gltf_import::read(&raystage_demo::animated_assets::AnimatedAsset::RiggedSimple.glb(), None, &Limits::default()),
            Asset::Tube => raystage_gltf_import::read(&raystage_demo::animated_assets::skinned_tube(TUBE.0, TUBE.1), None, &Limits::default()),
            Asset::File(path) => raystage_gltf_import::read_file(path, &Limits::default()),
        };
        let scene = import.and_then(|i| i.into_scene()).map_err(|e| format!("{}: {e}", self.name()))?;
        if scene.animations().is_empty() {
            return Err(format!("{}: has no animations", self.name()));
        }
        Ok(scene)
    }
}

/// One system's medians over the frames of one asset at one thread count.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct AnimationReport {
    /// `raystage`, `embree-refit` or `embree-low` (rebuilt).
    pub system: String,
    /// The asset.
    pub asset: String,
    /// Threads of every step.
    pub threads: usize,
    /// Triangles of the skinned objects.
    pub triangles: usize,
    /// Frames measured (after frame 0).
    pub frames: u32,
    /// Milliseconds evaluating the animation (raystage's, which feeds every system).
    pub evaluate_ms: f64,
    /// Milliseconds skinning and handing the vertices over (raystage's, which feeds every system).
    pub skin_ms: f64,
    /// Milliseconds bringing the trees up to date: raystage's lazy refits or rebuilds, Embree's
    /// commits.
    pub update_ms: f64,
    /// Frames whose skinned objects raystage refitted, over [`AnimationReport::frames`] (0 for Embree).
    pub refitted: u32,
    /// Frames whose skinned objects raystage rebuilt, its policy judging a refit too poor.
    pub rebuilt: u32,
    /// Milliseconds of the eye-light preview at 1280×720 but the tree update (raystage only).
    pub render_ms: Option<f64>,
    /// Frames per second of the preview: evaluation, skinning, update and render (raystage only).
    pub preview_fps: Option<f64>,
    /// Milliseconds tracing the 1280×720 primary rays (closest hits) on the updated trees.
    pub trace_ms: f64,
    /// Raystage's tree update over this system's, the median over the frames of the two in the
    /// same frame (none for raystage itself).
    pub raystage_update_ratio: Option<f64>,
    /// Raystage's trace over this system's, likewise.
    pub raystage_trace_ratio: Option<f64>,
}

/// One frame of one system, seconds.
#[derive(Clone, Copy, Debug, Default)]
struct FrameTime {
    evaluate: f64,
    skin: f64,
    update: f64,
    render: f64,
    trace: f64,
    refitted: bool,
    rebuilt: bool,
}

/// Closest hits of `rays` on the current thread pool, each ray handed to `closest`; returns how
/// many hit, so that the work is not optimised away and the systems can be checked against each
/// other.
fn trace(rays: &[Ray], closest: &(dyn Fn(&Ray) -> Option<f32> + Sync)) -> usize {
    rays.par_chunks(4096).map(|chunk| chunk.iter().filter(|r| closest(r).is_some()).count()).sum()
}

/// Plays `asset` over `frames` frames after frame 0 on `threads` threads: one report per
/// system (raystage, then Embree refitted and rebuilt with the `embree` feature).
pub fn run(asset: &Asset, threads: usize, frames: u32) -> Result<Vec<AnimationReport>, String> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
    let mut scene = asset.scene()?;
    let rig = scene.rig().cloned().expect("a scene with animations has a rig");
    let play = Play::Clip(0);
    let skinned: Vec<ObjectId> = rig.deformers.iter().map(|d| d.object).collect();
    let triangles = skinned.iter().map(|&id| scene.mesh(id).map_or(0, |m| m.indices.len())).sum();
    let rays = primary_rays(scene.camera());
    let settings = RenderSettings { width: WIDTH, height: HEIGHT, integrator: Integrator::EyeLight, samples_per_pixel: 1, ..RenderSettings::default() };

    #[cfg(feature = "embree")]
    let device = crate::embree::Device::new(threads)?;
    #[cfg(feature = "embree")]
    let mut embree: Vec<(String, crate::embree::InstancedScene, Vec<FrameTime>)> =
        [("embree-refit", crate::embree::Quality::Refit), ("embree-low", crate::embree::Quality::Low)]
            .into_iter()
            .map(|(name, quality)| (name.to_string(), embree_scene(&device, &scene, &skinned, quality), Vec::new()))
            .collect();

    let mut ours = Vec::new();
    for f in 0..=frames {
        let time = f as f32 / FPS;
        let mut step = FrameTime::default();
        let start = Instant::now();
        // Sequential: not handed to the pool, whose hand-over would be timed with it.
        let evaluated = rig.evaluate(play, time).map_err(|e| e.to_string())?;
        step.evaluate = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let pose = pool.install(|| rig.pose_evaluated(&evaluated)).map_err(|e| e.to_string())?;
        scene.set_pose(play, time, pose).map_err(|e| e.to_string())?;
        step.skin = start.elapsed().as_secs_f64();
        // Embree's copy of the skinned vertices, made outside the timing.
        #[cfg(feature = "embree")]
        let deformed: Vec<(usize, Vec<glam::Vec3>)> =
            skinned.iter().map(|&id| (embree_object(&scene, id), scene.mesh(id).expect("skinned objects exist").positions.clone())).collect();
        let frame: Frame<'_> = scene.frame();
        let (_, stats) = pool.install(|| render(&frame, &settings)).map_err(|e| e.to_string())?;
        step.update = stats.work.build_seconds;
        step.render = stats.seconds - stats.work.build_seconds;
        step.refitted = stats.work.refitted > 0;
        step.rebuilt = stats.work.built + stats.work.rebuilt > 0;
        let start = Instant::now();
        let hits = pool.install(|| trace(&rays, &|r| frame.intersect(r, 0.0).map(|h| h.t)));
        step.trace = start.elapsed().as_secs_f64();
        if f > 0 {
            ours.push(step);
        }
        #[cfg(feature = "embree")]
        for (name, embree, times) in &mut embree {
            let instances: Vec<(usize, glam::Affine3A)> = scene.instances().enumerate().map(|(k, (_, _, t))| (k, t)).collect();
            let update = embree.update(&instances, &deformed);
            let start = Instant::now();
            let theirs = pool.install(|| trace(&rays, &|r| embree.intersect(r)));
            let trace = start.elapsed().as_secs_f64();
            if hits.abs_diff(theirs) * 1000 > rays.len() {
                return Err(format!("{name} hits {theirs} primary rays of frame {f}, raystage {hits}"));
            }
            if f > 0 {
                times.push(FrameTime { update, trace, ..step });
            }
        }
        std::hint::black_box(hits);
    }
    // Each frame's pair met the same phase of a shared machine (see `dynamic::paired_ratio`).
    let paired = |theirs: &[FrameTime], of: fn(&FrameTime) -> f64| median(&ours.iter().zip(theirs).map(|(a, b)| of(a) / of(b)).collect::<Vec<_>>());
    let report = |system: &str, times: &[FrameTime], preview: bool| {
        let pick = |of: fn(&FrameTime) -> f64| 1e3 * median(&times.iter().map(of).collect::<Vec<_>>());
        let frame_ms = pick(|t| t.evaluate + t.skin + t.update + t.render);
        AnimationReport {
            system: system.into(),
            asset: asset.name(),
            threads,
            triangles,
            frames,
            evaluate_ms: pick(|t| t.evaluate),
            skin_ms: pick(|t| t.skin),
            update_ms: pick(|t| t.update),
            refitted: if preview { times.iter().filter(|t| t.refitted).count() as u32 } else { 0 },
            rebuilt: if preview { times.iter().filter(|t| t.rebuilt).count() as u32 } else { 0 },
            render_ms: preview.then(|| pick(|t| t.render)),
            preview_fps: preview.then(|| 1e3 / frame_ms),
            trace_ms: pick(|t| t.trace),
            raystage_update_ratio: (!preview).then(|| paired(times, |t| t.update)),
            raystage_trace_ratio: (!preview).then(|| paired(times, |t| t.trace)),
        }
    };
    let reports = std::iter::once(report("raystage", &ours, true));
    #[cfg(feature = "embree")]
    let reports = reports.chain(embree.iter().map(|(name, _, times)| report(name, times, false)));
    Ok(reports.collect())
}

/// The index of `object` among the scene's objects, as [`embree_scene`] lists them.
#[cfg(feature = "embree")]
fn embree_object(scene: &Scene, object: ObjectId) -> usize {
    scene.object_ids().position(|id| id == object).expect("a deformed object is in the scene")
}

/// The scene's objects and instances as Embree's two-level scene: the skinned objects at
/// `quality` (dynamic), the others at MEDIUM, the top level LOW.
#[cfg(feature = "embree")]
fn embree_scene(device: &crate::embree::Device, scene: &Scene, skinned: &[ObjectId], quality: crate::embree::Quality) -> crate::embree::InstancedScene {
    let ids: Vec<ObjectId> = scene.object_ids().collect();
    let meshes: Vec<raystage_demo::Mesh> = ids
        .iter()
        .map(|&id| {
            let mesh = scene.mesh(id).expect("listed objects exist");
            raystage_demo::Mesh { vertices: mesh.positions.clone(), indices: mesh.indices.clone() }
        })
        .collect();
    let specs: Vec<_> = ids
        .iter()
        .zip(&meshes)
        .map(|(id, mesh)| if skinned.contains(id) { (mesh, quality, true) } else { (mesh, crate::embree::Quality::Medium, false) })
        .collect();
    let instances: Vec<(usize, glam::Affine3A)> = scene.instances().map(|(_, object, t)| (ids.iter().position(|&id| id == object).expect("instances name objects"), t)).collect();
    crate::embree::InstancedScene::build(device, &specs, &instances, crate::embree::Quality::Low, false).0
}

/// The reports as a Markdown table, one row per system and thread count, with raystage's
/// tree update and trace over each Embree system's, frame by frame in the same run.
pub fn table(reports: &[AnimationReport]) -> String {
    let mut out = String::from(
        "| asset | triangles | threads | system | evaluate ms | skin ms | update ms | refits / rebuilds | render ms | preview fps | trace ms | raystage update / this | raystage trace / this |\n|---|---:|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|\n",
    );
    for r in reports {
        let optional = |v: Option<f64>, digits: usize| v.map_or("–".to_string(), |v| format!("{v:.digits$}"));
        let counts = if r.system == "raystage" { format!("{} / {}", r.refitted, r.rebuilt) } else { "–".into() };
        out += &format!(
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {counts} | {} | {} | {:.2} | {} | {} |\n",
            r.asset,
            r.triangles,
            r.threads,
            r.system,
            r.evaluate_ms,
            r.skin_ms,
            r.update_ms,
            optional(r.render_ms, 2),
            optional(r.preview_fps, 1),
            r.trace_ms,
            optional(r.raystage_update_ratio, 2),
            optional(r.raystage_trace_ratio, 2)
        );
    }
    out
}
