//! The probe's three ray sets, generated once so that every system traces the identical rays:
//! primary rays through the pixel centres, random incoherent rays (seed 777) and diffuse bounce
//! rays from the primary hits (seed 999). Draw order and arithmetic follow `embree_probe.c`.

use glam::Vec3;
use raystage_demo::StandardScene;
use raystage_demo::Xorshift64;
use raystage_demo::probe_math::{add, cross, dot, mul, norm, sub};
use raystage_kernel::Ray;

/// Image width of the probe.
pub const WIDTH: u32 = 1920;
/// Image height of the probe.
pub const HEIGHT: u32 = 1080;

/// One primary ray per pixel centre, row-major from the top-left, for a `width × height` image.
pub fn primary(scene: StandardScene, width: u32, height: u32) -> Vec<Ray> {
    let cam = scene.camera();
    (0..height).flat_map(|y| (0..width).map(move |x| Ray::new(cam.origin, cam.dir(x, y, width, height)))).collect()
}

/// Per-pixel items (rays, their hits) of a `width × height` image reordered into blocks of
/// `bw × bh` pixels (4×2 for packets of eight, 4×4 for groups of sixteen), each block row by
/// row, blocks row by row; `width` and `height` must be multiples of the block's.
pub fn in_blocks<T: Copy>(primary: &[T], width: u32, height: u32, (bw, bh): (usize, usize)) -> Vec<T> {
    let (w, h) = (width as usize, height as usize);
    assert!(w.is_multiple_of(bw) && h.is_multiple_of(bh), "whole {bw}x{bh} blocks");
    (0..h / bh)
        .flat_map(|by| (0..w / bw).map(move |bx| (bx, by)))
        .flat_map(|(bx, by)| (0..bw * bh).map(move |k| (by * bh + k / bw) * w + bx * bw + k % bw))
        .map(|i| primary[i])
        .collect()
}

/// Where the scene's point light is, for its shadow rays: above the sphere grid, behind and to
/// the right of its camera's view; above the soup's cube and in front of it.
pub fn light(scene: StandardScene) -> Vec3 {
    match scene {
        StandardScene::Spheres => Vec3::new(6.0, 14.0, 4.0),
        StandardScene::Soup => Vec3::new(0.9, 1.6, 1.8),
    }
}

/// Shadow rays from `light` to the points `rays` hit (skipping misses), each a segment that
/// stops just short of its point (a ten-thousandth of the way), so that the surface it lies on
/// does not block it.
pub fn shadows(light: Vec3, rays: &[Ray], hits: &[Option<PrimaryHit>]) -> Vec<Ray> {
    rays.iter()
        .zip(hits)
        .filter_map(|(ray, hit)| {
            let point = ray.origin + ray.dir * (*hit)?.t;
            Some(Ray::segment(light, point - light, 0.0, 1.0 - 1e-4))
        })
        .collect()
}

/// `n` rays with origins uniform in the scene's ray box and directions uniform on the sphere
/// (origin drawn x, y, z; then z, then the azimuth, as in the probe).
pub fn incoherent(scene: StandardScene, n: usize) -> Vec<Ray> {
    let (lo, hi) = scene.ray_box();
    let ext = sub(hi.to_array(), lo.to_array());
    let mut rng = Xorshift64::new(777);
    (0..n)
        .map(|_| {
            let ox = lo.x + rng.next_f32() * ext[0];
            let oy = lo.y + rng.next_f32() * ext[1];
            let oz = lo.z + rng.next_f32() * ext[2];
            let z = 1.0 - 2.0 * rng.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let ph = 2.0 * std::f32::consts::PI * rng.next_f32();
            Ray::new(Vec3::new(ox, oy, oz), Vec3::new(r * ph.cos(), r * ph.sin(), z))
        })
        .collect()
}

/// What a primary ray hit: distance and the hit triangle's unit geometric normal.
#[derive(Clone, Copy, Debug)]
pub struct PrimaryHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Unit geometric normal of the hit triangle (either orientation).
    pub normal: [f32; 3],
}

/// The probe's seed of its bounce rays.
pub const PROBE_BOUNCE_SEED: u64 = 999;

/// Cosine-distributed bounce rays from the hits of `rays` (the camera rays, or any rays whose
/// hits `hits` are), in their order, skipping misses: the origin is the hit point pushed
/// 1e-4 along the normal turned towards where the ray came from. The random numbers come from
/// `seed` ([`PROBE_BOUNCE_SEED`] for the probe's rays).
pub fn bounce(rays: &[Ray], hits: &[Option<PrimaryHit>], seed: u64) -> Vec<Ray> {
    let mut rng = Xorshift64::new(seed);
    rays.iter()
        .zip(hits)
        .filter_map(|(ray, hit)| {
            let hit = (*hit)?;
            let d0 = ray.dir.to_array();
            let mut nn = hit.normal;
            if dot(nn, d0) > 0.0 {
                nn = mul(nn, -1.0);
            }
            let o = add(add(ray.origin.to_array(), mul(d0, hit.t)), mul(nn, 1e-4));
            let (r1, r2) = (rng.next_f32(), rng.next_f32());
            let (r, ph) = (r1.sqrt(), 2.0 * std::f32::consts::PI * r2);
            let a = if nn[0].abs() > 0.5 { [0.0, 1.0, 0.0] } else { [1.0, 0.0, 0.0] };
            let t = norm(cross(a, nn));
            let b = cross(nn, t);
            let d = norm(add(add(mul(t, r * ph.cos()), mul(b, r * ph.sin())), mul(nn, (1.0 - r1).sqrt())));
            Some(Ray::new(Vec3::from_array(o), Vec3::from_array(d)))
        })
        .collect()
}

/// The unit geometric normal of a triangle as the probe gets it from Embree: `Ng = e2 × e1` with
/// `e1 = v0 − v1`, `e2 = v2 − v0`, then normalised.
pub fn probe_normal(tri: &[Vec3; 3]) -> [f32; 3] {
    let [v0, v1, v2] = tri.map(|v| v.to_array());
    norm(cross(sub(v2, v0), sub(v0, v1)))
}
