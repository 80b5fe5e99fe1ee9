//! A minimal binding of Embree 3 (Debian's `libembree-dev`): one triangle mesh, single-ray
//! queries. Only what the benchmarks trace with; declared by hand from `embree3/rtcore*.h`.

use std::ffi::{CString, c_char, c_void};
use std::time::Instant;

use raystage_demo::Mesh;
use raystage_kernel::Ray;

type RtcDevice = *mut c_void;
type RtcScene = *mut c_void;
type RtcGeometry = *mut c_void;

const GEOMETRY_TYPE_TRIANGLE: u32 = 0;
const GEOMETRY_TYPE_INSTANCE: u32 = 121;
const FORMAT_FLOAT3X4_COLUMN_MAJOR: u32 = 0x9234;
const SCENE_FLAG_DYNAMIC: u32 = 1;
const SCENE_FLAG_ROBUST: u32 = 4;
const BUFFER_TYPE_INDEX: u32 = 0;
const BUFFER_TYPE_VERTEX: u32 = 1;
const FORMAT_UINT3: u32 = 0x5003;
const FORMAT_FLOAT3: u32 = 0x9003;
const INVALID_GEOMETRY_ID: u32 = u32::MAX;
const DEVICE_PROPERTY_VERSION: u32 = 0;

#[repr(C, align(16))]
struct RtcRay {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
struct RtcHit {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C, align(16))]
struct RtcRayHit {
    ray: RtcRay,
    hit: RtcHit,
}

/// `N` rays and their hits, structure of arrays (`RTCRayHit8`, `RTCRayHit16`).
#[repr(C, align(64))]
struct RtcRayHitN<const N: usize> {
    ray: RtcRayN<N>,
    ng: [[f32; N]; 3],
    u: [f32; N],
    v: [f32; N],
    prim_id: [u32; N],
    geom_id: [u32; N],
    inst_id: [u32; N],
}

/// `N` rays, structure of arrays (`RTCRay8`, `RTCRay16`): the first part of [`RtcRayHitN`]
/// (whose size is a multiple of 64 bytes for 8 and 16 rays, so the alignment adds no padding).
#[repr(C, align(64))]
struct RtcRayN<const N: usize> {
    org: [[f32; N]; 3],
    tnear: [f32; N],
    dir: [[f32; N]; 3],
    time: [f32; N],
    tfar: [f32; N],
    mask: [u32; N],
    id: [u32; N],
    flags: [u32; N],
}

impl<const N: usize> RtcRayN<N> {
    /// Up to `N` rays as a packet, lanes past the last repeating it, and the packet's valid
    /// mask.
    fn of(rays: &[Ray]) -> (ValidN<N>, RtcRayN<N>) {
        assert!(!rays.is_empty() && rays.len() <= N, "one to {N} rays");
        let valid = ValidN(std::array::from_fn(|i| if i < rays.len() { -1 } else { 0 }));
        let lane = |i: usize| &rays[i.min(rays.len() - 1)];
        let ray = RtcRayN {
            org: std::array::from_fn(|a| std::array::from_fn(|i| lane(i).origin[a])),
            tnear: std::array::from_fn(|i| lane(i).tnear),
            dir: std::array::from_fn(|a| std::array::from_fn(|i| lane(i).dir[a])),
            time: [0.0; N],
            tfar: std::array::from_fn(|i| lane(i).tfar),
            mask: [u32::MAX; N],
            id: [0; N],
            flags: [0; N],
        };
        (valid, ray)
    }
}

/// The packet's valid mask (−1 active, 0 inactive), aligned as Embree requires.
#[repr(C, align(64))]
struct ValidN<const N: usize>([i32; N]);

#[repr(C)]
struct RtcIntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

impl RtcIntersectContext {
    /// What the header's inline `rtcInitIntersectContext` does.
    fn new() -> Self {
        RtcIntersectContext { flags: 0, filter: std::ptr::null(), inst_id: [INVALID_GEOMETRY_ID] }
    }
}

unsafe extern "C" {
    fn rtcNewDevice(config: *const c_char) -> RtcDevice;
    fn rtcReleaseDevice(device: RtcDevice);
    fn rtcGetDeviceError(device: RtcDevice) -> u32;
    fn rtcGetDeviceProperty(device: RtcDevice, prop: u32) -> isize;
    fn rtcNewScene(device: RtcDevice) -> RtcScene;
    fn rtcSetSceneBuildQuality(scene: RtcScene, quality: u32);
    fn rtcCommitScene(scene: RtcScene);
    fn rtcReleaseScene(scene: RtcScene);
    fn rtcNewGeometry(device: RtcDevice, kind: u32) -> RtcGeometry;
    fn rtcSetGeometryBuildQuality(geometry: RtcGeometry, quality: u32);
    fn rtcSetNewGeometryBuffer(
        geometry: RtcGeometry,
        kind: u32,
        slot: u32,
        format: u32,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: RtcGeometry);
    fn rtcAttachGeometry(scene: RtcScene, geometry: RtcGeometry) -> u32;
    fn rtcReleaseGeometry(geometry: RtcGeometry);
    fn rtcIntersect1(scene: RtcScene, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHit);
    fn rtcOccluded1(scene: RtcScene, context: *mut RtcIntersectContext, ray: *mut RtcRay);
    fn rtcSetSceneFlags(scene: RtcScene, flags: u32);
    fn rtcSetGeometryInstancedScene(geometry: RtcGeometry, scene: RtcScene);
    fn rtcSetGeometryTransform(geometry: RtcGeometry, time_step: u32, format: u32, xfm: *const c_void);
    fn rtcUpdateGeometryBuffer(geometry: RtcGeometry, kind: u32, slot: u32);
    fn rtcIntersect8(valid: *const i32, scene: RtcScene, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHitN<8>);
    fn rtcOccluded8(valid: *const i32, scene: RtcScene, context: *mut RtcIntersectContext, ray: *mut RtcRayN<8>);
    fn rtcIntersect16(valid: *const i32, scene: RtcScene, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHitN<16>);
    fn rtcOccluded16(valid: *const i32, scene: RtcScene, context: *mut RtcIntersectContext, ray: *mut RtcRayN<16>);
}

/// Embree's BVH build quality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// `RTC_BUILD_QUALITY_LOW`: Morton-code build, for geometry rebuilt every frame.
    Low = 0,
    /// `RTC_BUILD_QUALITY_MEDIUM`: binned SAH.
    Medium = 1,
    /// `RTC_BUILD_QUALITY_HIGH`: SAH with spatial splits.
    High = 2,
    /// `RTC_BUILD_QUALITY_REFIT`: refit the existing BVH when geometry changes.
    Refit = 3,
}

impl Quality {
    /// Embree's name for it.
    pub fn name(self) -> &'static str {
        match self {
            Quality::Low => "LOW",
            Quality::Medium => "MEDIUM",
            Quality::High => "HIGH",
            Quality::Refit => "REFIT",
        }
    }
}

/// An Embree device with a fixed number of build threads.
pub struct Device {
    raw: RtcDevice,
}

impl Device {
    /// A device whose builders use `threads` threads (`threads=N` in Embree's config string).
    pub fn new(threads: usize) -> Result<Device, String> {
        let config = CString::new(format!("threads={threads}")).expect("no NUL in config");
        // SAFETY: plain FFI call with a valid C string.
        let raw = unsafe { rtcNewDevice(config.as_ptr()) };
        if raw.is_null() {
            // SAFETY: Embree accepts a null device here and reports the creation error.
            return Err(format!("rtcNewDevice failed with error {}", unsafe { rtcGetDeviceError(std::ptr::null_mut()) }));
        }
        Ok(Device { raw })
    }

    /// Embree's version, e.g. `3.13.5`.
    pub fn version(&self) -> String {
        // SAFETY: valid device.
        let v = unsafe { rtcGetDeviceProperty(self.raw, DEVICE_PROPERTY_VERSION) };
        format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: created by rtcNewDevice, released once.
        unsafe { rtcReleaseDevice(self.raw) }
    }
}

/// A committed Embree scene holding one triangle mesh.
pub struct Scene {
    raw: RtcScene,
}

// SAFETY: a committed Embree scene may be queried from any number of threads at once.
unsafe impl Send for Scene {}
unsafe impl Sync for Scene {}

/// Embree's answer for one ray: distance, primitive and geometric normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmbreeHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Triangle index.
    pub prim: u32,
}

impl Scene {
    /// Builds a scene from `mesh` and returns it with the seconds `rtcCommitScene` took (the
    /// probe's definition of build time: buffers are filled before the clock starts).
    pub fn build(device: &Device, mesh: &Mesh, quality: Quality) -> (Scene, f64) {
        Scene::build_with(device, mesh, quality, false)
    }

    /// [`Scene::build`] with `RTC_SCENE_FLAG_ROBUST`: Embree's robust mode, whose box tests miss
    /// no box by rounding and whose triangle test is watertight, the guarantees raystage's
    /// kernel always gives (Embree's default gives neither, and is faster for it).
    pub fn build_robust(device: &Device, mesh: &Mesh, quality: Quality) -> (Scene, f64) {
        Scene::build_with(device, mesh, quality, true)
    }

    fn build_with(device: &Device, mesh: &Mesh, quality: Quality, robust: bool) -> (Scene, f64) {
        // SAFETY: buffers are sized by Embree for exactly the items written below.
        unsafe {
            let scene = rtcNewScene(device.raw);
            if robust {
                rtcSetSceneFlags(scene, SCENE_FLAG_ROBUST);
            }
            rtcSetSceneBuildQuality(scene, quality as u32);
            let geometry = rtcNewGeometry(device.raw, GEOMETRY_TYPE_TRIANGLE);
            rtcSetGeometryBuildQuality(geometry, quality as u32);
            let vb = rtcSetNewGeometryBuffer(geometry, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT3, 12, mesh.vertices.len())
                .cast::<[f32; 3]>();
            for (i, v) in mesh.vertices.iter().enumerate() {
                vb.add(i).write(v.to_array());
            }
            let ib = rtcSetNewGeometryBuffer(geometry, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12, mesh.indices.len())
                .cast::<[u32; 3]>();
            for (i, t) in mesh.indices.iter().enumerate() {
                ib.add(i).write(*t);
            }
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
            let start = Instant::now();
            rtcCommitScene(scene);
            (Scene { raw: scene }, start.elapsed().as_secs_f64())
        }
    }

    /// `rtcIntersect1`: the closest hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<EmbreeHit> {
        let mut rh = RtcRayHit {
            ray: RtcRay {
                org: ray.origin.to_array(),
                tnear: ray.tnear,
                dir: ray.dir.to_array(),
                time: 0.0,
                tfar: ray.tfar,
                mask: u32::MAX,
                id: 0,
                flags: 0,
            },
            hit: RtcHit { ng: [0.0; 3], u: 0.0, v: 0.0, prim_id: 0, geom_id: INVALID_GEOMETRY_ID, inst_id: [INVALID_GEOMETRY_ID] },
        };
        let mut context = RtcIntersectContext::new();
        // SAFETY: committed scene, valid ray/hit and context structs.
        unsafe { rtcIntersect1(self.raw, &mut context, &mut rh) };
        (rh.hit.geom_id != INVALID_GEOMETRY_ID).then_some(EmbreeHit { t: rh.ray.tfar, prim: rh.hit.prim_id })
    }
}

impl Scene {
    /// `rtcIntersect8`: closest-hit distances of up to eight rays traced as one packet.
    pub fn intersect8(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        intersect_n::<8>(self.raw, rays, out);
    }

    /// `rtcIntersect16`: closest-hit distances of up to sixteen rays traced as one packet.
    pub fn intersect16(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        intersect_n::<16>(self.raw, rays, out);
    }

    /// `rtcOccluded1`: whether anything blocks the segment.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        occluded1(self.raw, ray)
    }

    /// `rtcOccluded16`: which of up to sixteen segments are blocked (bit `i` for `rays[i]`).
    pub fn occluded16(&self, rays: &[Ray]) -> u32 {
        occluded_n::<16>(self.raw, rays)
    }
}

/// `rtcIntersect8` or `rtcIntersect16` (`N`) on a committed scene: closest-hit distances of up
/// to `N` rays.
fn intersect_n<const N: usize>(scene: RtcScene, rays: &[Ray], out: &mut [Option<f32>]) {
    assert!(rays.len() == out.len(), "one result per ray");
    let (valid, ray) = RtcRayN::<N>::of(rays);
    let mut rh = RtcRayHitN::<N> {
        ray,
        ng: [[0.0; N]; 3],
        u: [0.0; N],
        v: [0.0; N],
        prim_id: [0; N],
        geom_id: [INVALID_GEOMETRY_ID; N],
        inst_id: [INVALID_GEOMETRY_ID; N],
    };
    let mut context = RtcIntersectContext::new();
    let hits = (&mut rh as *mut RtcRayHitN<N>).cast();
    // SAFETY: committed scene; `valid` and the packet are 64-byte aligned (Embree needs 32 for
    // eight rays, 64 for sixteen) and laid out as `RTCRayHit8`/`RTCRayHit16` for these `N`.
    match N {
        8 => unsafe { rtcIntersect8(valid.0.as_ptr(), scene, &mut context, hits) },
        16 => unsafe { rtcIntersect16(valid.0.as_ptr(), scene, &mut context, hits.cast()) },
        _ => unreachable!("Embree has packets of 4, 8 and 16; the bench uses 8 and 16"),
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = (rh.geom_id[i] != INVALID_GEOMETRY_ID).then_some(rh.ray.tfar[i]);
    }
}

/// `rtcOccluded8` or `rtcOccluded16` (`N`) on a committed scene: whether each of up to `N`
/// segments is blocked (bit `i` for `rays[i]`).
fn occluded_n<const N: usize>(scene: RtcScene, rays: &[Ray]) -> u32 {
    let (valid, mut r) = RtcRayN::<N>::of(rays);
    let mut context = RtcIntersectContext::new();
    let packet = (&mut r as *mut RtcRayN<N>).cast();
    // SAFETY: as in `intersect_n`, with `RTCRay8`/`RTCRay16`.
    match N {
        8 => unsafe { rtcOccluded8(valid.0.as_ptr(), scene, &mut context, packet) },
        16 => unsafe { rtcOccluded16(valid.0.as_ptr(), scene, &mut context, packet.cast()) },
        _ => unreachable!("Embree has packets of 4, 8 and 16; the bench uses 8 and 16"),
    }
    // Embree marks an occluded ray by setting its tfar to −∞.
    (0..rays.len()).filter(|&i| r.tfar[i] == f32::NEG_INFINITY).fold(0, |m, i| m | 1 << i)
}

/// `rtcOccluded1` on a committed scene: whether anything blocks the segment.
#[inline]
fn occluded1(scene: RtcScene, ray: &Ray) -> bool {
    let mut r = RtcRay::from(ray);
    let mut context = RtcIntersectContext::new();
    // SAFETY: committed scene, valid ray and context structs.
    unsafe { rtcOccluded1(scene, &mut context, &mut r) };
    // Embree marks an occluded ray by setting its tfar to −∞.
    r.tfar == f32::NEG_INFINITY
}

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: created by rtcNewScene, released once.
        unsafe { rtcReleaseScene(self.raw) }
    }
}

impl RtcRay {
    fn from(ray: &Ray) -> RtcRay {
        RtcRay {
            org: ray.origin.to_array(),
            tnear: ray.tnear,
            dir: ray.dir.to_array(),
            time: 0.0,
            tfar: ray.tfar,
            mask: u32::MAX,
            id: 0,
            flags: 0,
        }
    }
}

/// One object of a two-level scene: an Embree scene holding its triangles.
struct ObjectScene {
    scene: RtcScene,
    geometry: RtcGeometry,
    /// Embree's vertex buffer, for moving the vertices of a dynamic object.
    vertices: *mut [f32; 3],
    vertex_count: usize,
}

/// A two-level Embree scene: one scene per object, committed once, and a top-level scene of
/// instances (`RTC_GEOMETRY_TYPE_INSTANCE`) whose transforms change every frame.
pub struct InstancedScene {
    objects: Vec<ObjectScene>,
    instances: Vec<RtcGeometry>,
    top: RtcScene,
}

// SAFETY: a committed Embree scene may be queried from any number of threads at once; updates
// take `&mut self`.
unsafe impl Send for InstancedScene {}
unsafe impl Sync for InstancedScene {}

/// The first three rows of an affine transform, column-major (Embree's 3×4 format).
fn columns(t: &glam::Affine3A) -> [f32; 12] {
    t.to_cols_array()
}

impl InstancedScene {
    /// Builds every object with its quality (`dynamic` objects get Embree's dynamic flag) and
    /// the top level (`top_quality`) over `instances` (object index, object to world), every
    /// scene in robust mode if `robust` (see [`Scene::build_robust`]); returns the scene and the
    /// seconds Embree spent committing.
    pub fn build(
        device: &Device,
        objects: &[(&Mesh, Quality, bool)],
        instances: &[(usize, glam::Affine3A)],
        top_quality: Quality,
        robust: bool,
    ) -> (InstancedScene, f64) {
        let robust_flag = if robust { SCENE_FLAG_ROBUST } else { 0 };
        let mut seconds = 0.0;
        // SAFETY: buffers are sized by Embree for exactly the items written; every handle is
        // released once, in `drop`.
        unsafe {
            let objects: Vec<ObjectScene> = objects
                .iter()
                .map(|&(mesh, quality, dynamic)| {
                    let scene = rtcNewScene(device.raw);
                    rtcSetSceneFlags(scene, robust_flag | if dynamic { SCENE_FLAG_DYNAMIC } else { 0 });
                    rtcSetSceneBuildQuality(scene, if quality == Quality::Refit { Quality::Low as u32 } else { quality as u32 });
                    let geometry = rtcNewGeometry(device.raw, GEOMETRY_TYPE_TRIANGLE);
                    rtcSetGeometryBuildQuality(geometry, quality as u32);
                    let vb = rtcSetNewGeometryBuffer(geometry, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT3, 12, mesh.vertices.len())
                        .cast::<[f32; 3]>();
                    for (i, v) in mesh.vertices.iter().enumerate() {
                        vb.add(i).write(v.to_array());
                    }
                    let ib = rtcSetNewGeometryBuffer(geometry, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12, mesh.indices.len())
                        .cast::<[u32; 3]>();
                    for (i, t) in mesh.indices.iter().enumerate() {
                        ib.add(i).write(*t);
                    }
                    let start = Instant::now();
                    rtcCommitGeometry(geometry);
                    rtcAttachGeometry(scene, geometry);
                    rtcCommitScene(scene);
                    seconds += start.elapsed().as_secs_f64();
                    ObjectScene { scene, geometry, vertices: vb, vertex_count: mesh.vertices.len() }
                })
                .collect();
            let top = rtcNewScene(device.raw);
            rtcSetSceneFlags(top, robust_flag | SCENE_FLAG_DYNAMIC);
            rtcSetSceneBuildQuality(top, top_quality as u32);
            let start = Instant::now();
            let instances = instances
                .iter()
                .map(|(object, t)| {
                    let g = rtcNewGeometry(device.raw, GEOMETRY_TYPE_INSTANCE);
                    rtcSetGeometryInstancedScene(g, objects[*object].scene);
                    rtcSetGeometryBuildQuality(g, top_quality as u32);
                    rtcSetGeometryTransform(g, 0, FORMAT_FLOAT3X4_COLUMN_MAJOR, columns(t).as_ptr().cast());
                    rtcCommitGeometry(g);
                    rtcAttachGeometry(top, g);
                    g
                })
                .collect();
            rtcCommitScene(top);
            seconds += start.elapsed().as_secs_f64();
            (InstancedScene { objects, instances, top }, seconds)
        }
    }

    /// Moves to the next frame: writes the deformed objects' vertices (not timed, like the
    /// probe's own vertex update), then sets every instance transform, commits the changed
    /// geometry and the top level; returns the seconds of those Embree calls.
    pub fn update(&mut self, instances: &[(usize, glam::Affine3A)], deformed: &[(usize, Vec<glam::Vec3>)]) -> f64 {
        // SAFETY: the vertex buffers hold exactly `vertex_count` vertices and stay alive with the
        // geometry; the lengths are checked.
        unsafe {
            for (object, positions) in deformed {
                let o = &self.objects[*object];
                assert_eq!(positions.len(), o.vertex_count, "same vertex count every frame");
                for (i, p) in positions.iter().enumerate() {
                    o.vertices.add(i).write(p.to_array());
                }
            }
            let start = Instant::now();
            for (object, _) in deformed {
                let o = &self.objects[*object];
                rtcUpdateGeometryBuffer(o.geometry, BUFFER_TYPE_VERTEX, 0);
                rtcCommitGeometry(o.geometry);
                rtcCommitScene(o.scene);
            }
            for (g, (_, t)) in self.instances.iter().zip(instances) {
                rtcSetGeometryTransform(*g, 0, FORMAT_FLOAT3X4_COLUMN_MAJOR, columns(t).as_ptr().cast());
                rtcCommitGeometry(*g);
            }
            rtcCommitScene(self.top);
            start.elapsed().as_secs_f64()
        }
    }

    /// `rtcIntersect1` on the top level: the closest hit distance.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        let mut rh = RtcRayHit {
            ray: RtcRay::from(ray),
            hit: RtcHit { ng: [0.0; 3], u: 0.0, v: 0.0, prim_id: 0, geom_id: INVALID_GEOMETRY_ID, inst_id: [INVALID_GEOMETRY_ID] },
        };
        let mut context = RtcIntersectContext::new();
        // SAFETY: committed scene, valid ray/hit and context structs.
        unsafe { rtcIntersect1(self.top, &mut context, &mut rh) };
        (rh.hit.geom_id != INVALID_GEOMETRY_ID).then_some(rh.ray.tfar)
    }

    /// `rtcIntersect8` on the top level: closest-hit distances of up to eight rays as a packet.
    pub fn intersect8(&self, rays: &[Ray], out: &mut [Option<f32>]) {
        intersect_n::<8>(self.top, rays, out);
    }

    /// `rtcOccluded8` on the top level: which of up to eight segments are blocked (bit `i` for
    /// `rays[i]`).
    pub fn occluded8(&self, rays: &[Ray]) -> u32 {
        occluded_n::<8>(self.top, rays)
    }

    /// `rtcOccluded1` on the top level: whether anything blocks the segment.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        occluded1(self.top, ray)
    }
}

impl Drop for InstancedScene {
    fn drop(&mut self) {
        // SAFETY: each handle was created once above and is released once here.
        unsafe {
            for g in &self.instances {
                rtcReleaseGeometry(*g);
            }
            rtcReleaseScene(self.top);
            for o in &self.objects {
                rtcReleaseGeometry(o.geometry);
                rtcReleaseScene(o.scene);
            }
        }
    }
}
