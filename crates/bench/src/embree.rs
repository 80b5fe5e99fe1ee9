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

/// Eight rays and their hits, structure of arrays (`RTCRayHit8`).
#[repr(C, align(32))]
struct RtcRayHit8 {
    org: [[f32; 8]; 3],
    tnear: [f32; 8],
    dir: [[f32; 8]; 3],
    time: [f32; 8],
    tfar: [f32; 8],
    mask: [u32; 8],
    id: [u32; 8],
    flags: [u32; 8],
    ng: [[f32; 8]; 3],
    u: [f32; 8],
    v: [f32; 8],
    prim_id: [u32; 8],
    geom_id: [u32; 8],
    inst_id: [u32; 8],
}

/// The packet's valid mask (−1 active, 0 inactive), aligned as Embree requires.
#[repr(C, align(32))]
struct Valid8([i32; 8]);

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
    fn rtcIntersect8(valid: *const i32, scene: RtcScene, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHit8);
}

/// Embree's BVH build quality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// `RTC_BUILD_QUALITY_MEDIUM`: binned SAH.
    Medium = 1,
    /// `RTC_BUILD_QUALITY_HIGH`: SAH with spatial splits.
    High = 2,
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
        // SAFETY: buffers are sized by Embree for exactly the items written below.
        unsafe {
            let scene = rtcNewScene(device.raw);
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
        assert!(rays.len() <= 8 && rays.len() == out.len(), "up to eight rays, one result each");
        let valid = Valid8(std::array::from_fn(|i| if i < rays.len() { -1 } else { 0 }));
        let lane = |i: usize| &rays[i.min(rays.len() - 1)];
        let mut rh = RtcRayHit8 {
            org: std::array::from_fn(|a| std::array::from_fn(|i| lane(i).origin[a])),
            tnear: std::array::from_fn(|i| lane(i).tnear),
            dir: std::array::from_fn(|a| std::array::from_fn(|i| lane(i).dir[a])),
            time: [0.0; 8],
            tfar: std::array::from_fn(|i| lane(i).tfar),
            mask: [u32::MAX; 8],
            id: [0; 8],
            flags: [0; 8],
            ng: [[0.0; 8]; 3],
            u: [0.0; 8],
            v: [0.0; 8],
            prim_id: [0; 8],
            geom_id: [INVALID_GEOMETRY_ID; 8],
            inst_id: [INVALID_GEOMETRY_ID; 8],
        };
        let mut context = RtcIntersectContext::new();
        // SAFETY: committed scene; `valid` and the packet are 32-byte aligned as Embree requires.
        unsafe { rtcIntersect8(valid.0.as_ptr(), self.raw, &mut context, &mut rh) };
        for (i, o) in out.iter_mut().enumerate() {
            *o = (rh.geom_id[i] != INVALID_GEOMETRY_ID).then_some(rh.tfar[i]);
        }
    }
}

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: created by rtcNewScene, released once.
        unsafe { rtcReleaseScene(self.raw) }
    }
}
