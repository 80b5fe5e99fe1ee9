//! Objects: geometry with its own acceleration structure, built lazily, the first time a ray
//! reaches the object (seed: Wald, *Handling Dynamic Scenes*, docs/design/seeds.md §1.3 and §4).

use std::ops::Range;
use std::sync::{Arc, Mutex, OnceLock};

use raystage_kernel::{Aabb, BuildOptions, BuildQuality, Bvh8};

use crate::builds::{BuildCounters, BuildOutcome};
use crate::ids::ShaderId;
use crate::mesh::Mesh;

/// How an object's geometry changes over time, which decides how its tree is built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ObjectKind {
    /// Never changes: the best (binned SAH) tree, built once.
    #[default]
    Static,
    /// Moves only through its instances' transforms: built once like a static object, never
    /// rebuilt; rays are transformed into its space instead.
    Animated,
    /// Its geometry is redefined through the same id (every instance follows): the tree is
    /// refitted while its degradation (see [`Bvh8::refit`]) stays below
    /// [`REBUILD_DEGRADATION`], else rebuilt with the fast builder (RT-DEFORM's policy).
    Unstructured,
}

impl ObjectKind {
    /// How an object of this kind builds its tree: binned SAH for static and animated objects,
    /// built once; the fast builder, refittable, for unstructured ones, rebuilt often.
    pub fn build_options(self) -> BuildOptions {
        match self {
            ObjectKind::Static | ObjectKind::Animated => BuildOptions::default(),
            ObjectKind::Unstructured => BuildOptions { quality: BuildQuality::Fast, refittable: true, ..BuildOptions::default() },
        }
    }
}

/// Degradation (see [`Bvh8::refit`]) past which a refitted tree is rebuilt: once rays do 40 %
/// more box tests than in a fresh tree, a rebuild (a few milliseconds for tens of thousands of
/// triangles) pays for itself within a frame or two.
pub const REBUILD_DEGRADATION: f32 = 0.4;

/// Most redefinitions in a row rebuilt without trying a refit first. A refit that ends in a
/// rebuild costs both, so it is avoided twice over: a tree whose refits so far, extrapolated,
/// would pass [`REBUILD_DEGRADATION`] at the next one is rebuilt at once; and when refits of
/// fresh trees keep failing (geometry that changes fast, as the museum's triangles do halfway
/// between cloud and sphere), the next attempts are spaced out 1, 2, 4 and then this many
/// redefinitions apart, until a refit that holds brings them back to every redefinition.
const MAX_REFIT_BACKOFF: u32 = 8;

/// The distinct shaders a mesh's triangles use, and whether some use none (the default).
fn shaders_of(mesh: &Mesh) -> (Vec<ShaderId>, bool) {
    let mut used = mesh.shaders.clone();
    used.sort_unstable();
    used.dedup();
    (used, mesh.shaders.is_empty())
}

/// Most runs an object keeps (see [`Object::shader_runs`]): an object whose shaders change
/// more often than that along its triangles is gathered triangle by triangle.
const MAX_SHADER_RUNS: usize = 64;

/// The runs of consecutive triangles of `mesh` that share a shader, each as its first triangle
/// and the shader, in triangle order; empty if the mesh has no shaders or more than
/// [`MAX_SHADER_RUNS`] runs.
fn shader_runs_of(mesh: &Mesh) -> Vec<(u32, ShaderId)> {
    let mut runs: Vec<(u32, ShaderId)> = Vec::new();
    for (prim, &id) in mesh.shaders.iter().enumerate() {
        if runs.last().is_none_or(|&(_, last)| last != id) {
            if runs.len() == MAX_SHADER_RUNS {
                return Vec::new();
            }
            runs.push((prim as u32, id));
        }
    }
    runs
}

/// The cover of an object of `kind` (see [`Object::cover`]).
fn cover_of(kind: ObjectKind, mesh: &Mesh, bounds: &Aabb) -> Vec<Aabb> {
    if kind == ObjectKind::Unstructured { Vec::new() } else { mesh.cover(bounds) }
}

/// An object: its mesh, its kind, and its acceleration structure once a ray needed it.
///
/// Scenes hold objects behind `Arc`s, so that a frame renders from a snapshot of the scene while
/// edits go on: an edit of an object a snapshot still holds works on a copy (see the `Clone`
/// impl), and the copy shares the tree until its geometry changes.
#[derive(Debug)]
pub(crate) struct Object {
    pub mesh: Mesh,
    pub kind: ObjectKind,
    pub bounds: Aabb,
    /// Boxes around parts of the geometry ([`Mesh::cover`]) that give a turned instance a
    /// tight world box; empty for unstructured objects, whose geometry changes too often for
    /// the extra pass over it to pay (they keep the box around their turned `bounds`).
    pub cover: Vec<Aabb>,
    /// The distinct shaders its triangles use, and whether some use the scene's default.
    pub shaders_used: Vec<ShaderId>,
    pub uses_default_shader: bool,
    /// The mesh's shaders as runs of triangles (see [`shader_runs_of`]): a glTF mesh has one
    /// per primitive. (Looking a hit's shader up among them measured no faster than reading
    /// the per-triangle list, so hits read the list.)
    run_starts: Vec<(u32, ShaderId)>,
    /// The tree for the current geometry, built by the first ray that needs it; shared with
    /// copies of the object that have the same geometry.
    accel: Arc<OnceLock<Bvh8>>,
    /// An unstructured object's tree for earlier geometry with the same triangles, waiting to be
    /// refitted by the first ray that needs the new one, and how refits have fared.
    previous: Mutex<Refits>,
}

/// An unstructured object's refit state.
#[derive(Clone, Debug, Default)]
struct Refits {
    /// The tree to refit, if the triangles are still the ones it was built over (shared with a
    /// snapshot that still renders the old geometry, in which case the refit works on a copy).
    tree: Option<Arc<OnceLock<Bvh8>>>,
    /// Redefinitions still to rebuild without trying a refit (see [`MAX_REFIT_BACKOFF`]).
    skip: u32,
    /// How many the next failed refit makes that.
    backoff: u32,
    /// Refits since the tree was last built, and the degradation they brought it to.
    since_build: u32,
    degradation: f32,
}

impl Refits {
    /// The degradation one more refit is expected to bring: the growth per refit so far,
    /// extrapolated (geometry that keeps moving keeps loosening the tree at about its pace).
    fn predicted(&self) -> f32 {
        if self.since_build == 0 { 0.0 } else { self.degradation / self.since_build as f32 * (self.since_build + 1) as f32 }
    }
}

impl Object {
    /// A new object; nothing is built yet.
    pub fn new(kind: ObjectKind, mesh: Mesh) -> Object {
        let (shaders_used, uses_default_shader) = shaders_of(&mesh);
        let bounds = mesh.bounds();
        Object {
            bounds,
            cover: cover_of(kind, &mesh, &bounds),
            shaders_used,
            uses_default_shader,
            run_starts: shader_runs_of(&mesh),
            mesh,
            kind,
            accel: Arc::default(),
            previous: Mutex::new(Refits::default()),
        }
    }

    /// Replaces the geometry. An unstructured object with the same number of triangles keeps its
    /// current tree for a refit; anything else starts over.
    pub fn redefine(&mut self, mesh: Mesh) {
        let same_triangles = mesh.indices.len() == self.mesh.indices.len();
        self.replace(mesh, same_triangles);
    }

    /// Moves the vertices (same count), keeping the triangles, and replaces the normals and
    /// tangents where given (same count as the mesh has): a redefinition that keeps the
    /// topology, so an unstructured object's tree can be refitted.
    pub fn move_vertices(&mut self, positions: Vec<glam::Vec3>, normals: Option<Vec<glam::Vec3>>, tangents: Option<Vec<glam::Vec4>>) {
        let mut mesh = std::mem::take(&mut self.mesh);
        mesh.positions = positions;
        mesh.normals = normals.unwrap_or(mesh.normals);
        mesh.tangents = tangents.unwrap_or(mesh.tangents);
        self.retire_tree(true);
        // Same triangles, same shaders: only the bounds move.
        self.bounds = mesh.bounds();
        self.cover = cover_of(self.kind, &mesh, &self.bounds);
        self.mesh = mesh;
    }

    /// Installs `mesh`; `same_triangles` says whether it has the triangles of the mesh it
    /// replaces (so that a tree built for that one can be refitted to it).
    fn replace(&mut self, mesh: Mesh, same_triangles: bool) {
        self.retire_tree(same_triangles);
        self.bounds = mesh.bounds();
        self.cover = cover_of(self.kind, &mesh, &self.bounds);
        (self.shaders_used, self.uses_default_shader) = shaders_of(&mesh);
        self.run_starts = shader_runs_of(&mesh);
        self.mesh = mesh;
    }

    /// Drops the current tree for new geometry, keeping it for a refit if the object is
    /// unstructured and the triangles stay the same (`same_triangles`).
    fn retire_tree(&mut self, same_triangles: bool) {
        let previous = self.previous.get_mut().unwrap_or_else(|e| e.into_inner());
        let tree = std::mem::take(&mut self.accel);
        match (self.kind, same_triangles, tree.get().is_some()) {
            (ObjectKind::Unstructured, true, true) => previous.tree = Some(tree),
            (ObjectKind::Unstructured, true, false) => {}
            _ => *previous = Refits::default(),
        }
    }

    /// The shader of triangle `prim`, `None` for the scene's default.
    #[inline]
    pub fn shader(&self, prim: u32) -> Option<ShaderId> {
        self.mesh.shaders.get(prim as usize).copied()
    }

    /// The object's triangles in runs that share a shader, in triangle order, each as its
    /// triangles and their shader (`None` for the scene's default); `None` where the runs are
    /// too many to keep (over [`MAX_SHADER_RUNS`]): then [`Object::shader`] tells each
    /// triangle's. What lets a frame gather the triangles of a few shaders (its emitters) without
    /// visiting every other triangle.
    pub fn shader_runs(&self) -> Option<Vec<(Range<u32>, Option<ShaderId>)>> {
        let count = self.mesh.indices.len() as u32;
        if self.mesh.shaders.is_empty() {
            return Some(vec![(0..count, None)]);
        }
        let runs = &self.run_starts;
        (!runs.is_empty()).then(|| runs.iter().enumerate().map(|(k, &(first, id))| (first..runs.get(k + 1).map_or(count, |r| r.0), Some(id))).collect())
    }

    /// The memory its shader runs take.
    pub fn shader_runs_bytes(&self) -> u64 {
        (self.run_starts.len() * size_of::<(u32, ShaderId)>()) as u64
    }

    /// Whether the tree for the current geometry exists.
    pub fn is_built(&self) -> bool {
        self.accel.get().is_some()
    }

    /// The tree for the current geometry, building (or refitting) it now if no ray has needed it
    /// yet. Exactly one thread has it built, on the build pool with every core (see
    /// [`crate::builds`]); the others wait for it.
    pub fn accel<'o>(self: &'o Arc<Object>, counters: &BuildCounters) -> &'o Bvh8 {
        self.accel.get_or_init(|| {
            let object = Arc::clone(self);
            counters.run(move || object.build())
        })
    }

    fn build(&self) -> (Bvh8, BuildOutcome) {
        if self.kind != ObjectKind::Unstructured {
            return (Bvh8::build(&self.mesh, &self.kind.build_options()), BuildOutcome::Built);
        }
        let fast = self.kind.build_options();
        let mut refits = self.previous.lock().unwrap_or_else(|e| e.into_inner());
        let Some(mut tree) = refits.tree.take().and_then(owned) else {
            return (Bvh8::build(&self.mesh, &fast), BuildOutcome::Built);
        };
        if refits.skip > 0 {
            refits.skip -= 1;
        } else if refits.predicted() > REBUILD_DEGRADATION {
            // The refit would most likely end in a rebuild: rebuild now.
        } else {
            let degradation = tree.refit(&self.mesh);
            if degradation <= REBUILD_DEGRADATION {
                refits.backoff = 0;
                refits.since_build += 1;
                refits.degradation = degradation;
                return (tree, BuildOutcome::Refitted);
            }
            refits.backoff = (2 * refits.backoff).clamp(1, MAX_REFIT_BACKOFF);
            refits.skip = refits.backoff;
        }
        tree.rebuild(&self.mesh, &fast);
        (refits.since_build, refits.degradation) = (0, 0.0);
        (tree, BuildOutcome::Rebuilt)
    }
}

/// A tree to refit, owned: taken if nothing else holds it, else copied (a snapshot in flight
/// still traces the old geometry with it).
fn owned(tree: Arc<OnceLock<Bvh8>>) -> Option<Bvh8> {
    match Arc::try_unwrap(tree) {
        Ok(cell) => cell.into_inner(),
        Err(shared) => shared.get().cloned(),
    }
}

impl Clone for Object {
    /// A copy for an edit while a snapshot holds the object: the same geometry, so the same
    /// (shared) tree, and the same refit state.
    fn clone(&self) -> Object {
        Object {
            mesh: self.mesh.clone(),
            kind: self.kind,
            bounds: self.bounds,
            cover: self.cover.clone(),
            shaders_used: self.shaders_used.clone(),
            uses_default_shader: self.uses_default_shader,
            run_starts: self.run_starts.clone(),
            accel: Arc::clone(&self.accel),
            previous: Mutex::new(self.previous.lock().unwrap_or_else(|e| e.into_inner()).clone()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An object of `shaders.len()` triangles (or one, without shaders) with these shaders.
    fn object(triangles: usize, shaders: Vec<ShaderId>) -> Object {
        let positions = vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y];
        let mesh = Mesh { shaders, ..Mesh::new(positions, vec![[0, 1, 2]; triangles]) };
        Object::new(ObjectKind::Static, mesh)
    }

    #[test]
    fn shader_runs_cover_every_triangle_with_its_shader() {
        let (a, b) = (ShaderId(3), ShaderId(7));
        let cases = [vec![], vec![a; 10], vec![a, a, b, b, b, a], vec![b]];
        for shaders in cases {
            let o = object(shaders.len().max(1), shaders.clone());
            let runs = o.shader_runs().expect("few runs are kept");
            assert_eq!(runs.first().map(|r| r.0.start), Some(0), "{shaders:?}");
            assert_eq!(runs.last().map(|r| r.0.end), Some(o.mesh.indices.len() as u32), "{shaders:?}");
            for pair in runs.windows(2) {
                assert_eq!(pair[0].0.end, pair[1].0.start, "runs follow each other: {shaders:?}");
                assert_ne!(pair[0].1, pair[1].1, "runs are maximal: {shaders:?}");
            }
            for (range, id) in runs {
                assert!(!range.is_empty());
                assert!(range.into_iter().all(|prim| o.shader(prim) == id), "{shaders:?}");
            }
        }
    }

    #[test]
    fn shaders_that_change_too_often_keep_no_runs() {
        let alternating: Vec<ShaderId> = (0..=MAX_SHADER_RUNS as u32).map(|k| ShaderId(k % 2)).collect();
        assert!(object(alternating.len(), alternating.clone()).shader_runs().is_none());
        let just_enough = alternating[..MAX_SHADER_RUNS].to_vec();
        assert_eq!(object(just_enough.len(), just_enough).shader_runs().map(|r| r.len()), Some(MAX_SHADER_RUNS));
    }
}
