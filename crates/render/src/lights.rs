//! The scene's lights as the integrators use them: sampled from a surface point (next-event
//! estimation), and met by rays that hit an area light or escape to the environment, with the
//! densities multiple importance sampling needs to weigh the two ways of finding the same light.
//!
//! Delta lights (point, spot, directional) can only be sampled; the ambient term is added
//! without a shadow ray; area lights are sampled uniformly over their area; environments by
//! the cosine around the normal, or, for an image, by the image's brightness (a piecewise-
//! constant 2D distribution over the latitude-longitude map, as in pbrt's image infinite light).
//!
//! Geometry that emits is light too: every instanced triangle whose material emits joins one
//! light, [`Emitters`], which picks a triangle in proportion to its power and a point uniformly
//! on it. A scene that nothing lights (no light, no emitting surface) gets a default: the sky
//! as an environment light, which lights open and enclosed scenes alike.

use std::borrow::Cow;
use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};
use raystage_scene::{Distribution, EnvironmentTables, Frame, Image, Light, Texture, WorldTriangle};

use crate::material::{Materials, Slot};
use crate::warp::{Frame3, cosine_hemisphere, power_heuristic};

/// Texels of the default sky environment's latitude-longitude image: fine enough that its
/// gradient lights as the analytic sky does, small enough to bake at every frame start.
const DEFAULT_SKY_SIZE: (u32, u32) = (64, 32);

/// Light arriving at a point from one sampled position of a light.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightSample {
    /// Unit direction from the point towards the light.
    pub wi: Vec3,
    /// Distance to the sampled position (infinite for directional and environment light).
    pub distance: f32,
    /// Incident radiance divided by the sampling density: for a delta light its irradiance
    /// facing it; for an extended light radiance / pdf.
    pub weighted: Vec3,
    /// Solid-angle density of the sample, or 0 for a delta light (which no ray can hit, so it
    /// takes no part in multiple importance sampling).
    pub pdf: f32,
}

/// How a ray that meets an emitter was chosen, which decides how much of the emission it counts.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Seen {
    /// A camera ray, or a ray that only mirrors and glass bent on its way from the camera: the
    /// emitter is seen, fully.
    Directly,
    /// A ray sampled from the BSDF at a surface with shading normal `normal`, with density
    /// `pdf`, where lights were also sampled: the emission is weighted against the light's own
    /// sampling density (multiple importance sampling).
    Scattered { normal: Vec3, pdf: f32 },
    /// A ray whose emitters were already accounted for by light sampling: no emission.
    Not,
}

/// The frame's lights, prepared for sampling.
pub(crate) struct SceneLights<'f> {
    lights: Vec<Prepared<'f>>,
    ambient: Vec3,
    environment: bool,
    area: bool,
    /// The light of emitting triangles, by its index in `lights`.
    emitters: Option<usize>,
    /// Whether the scene had no light of its own and was given the default sky.
    defaulted: bool,
    /// Samples taken of each extended light per shading point: the light-sampling density that
    /// multiple importance sampling weighs a BSDF sample against is this many times the
    /// density of one.
    samples: f32,
}

/// A light every point sees from one direction only (a delta light).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Delta {
    /// A point or a spot.
    Positional(Positional),
    /// A distant light: the unit direction towards it, and its irradiance facing it.
    Directional { towards: Vec3, intensity: Vec3 },
}

/// A point or spot light: where it is, its intensity and, for a spot, its cone.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Positional {
    pub position: Vec3,
    pub intensity: Vec3,
    pub cone: Option<Cone>,
}

/// A spot light's cone: full intensity within `cos_falloff` of its unit `axis`, none beyond
/// `cos_cone`, a smooth step between.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cone {
    pub axis: Vec3,
    pub cos_cone: f32,
    pub cos_falloff: f32,
}

impl Cone {
    /// The fraction of the intensity that leaves in direction `-wi` (`wi` pointing from a
    /// point to the light).
    pub fn fade(&self, wi: Vec3) -> f32 {
        let cos = (-wi).dot(self.axis);
        if cos >= self.cos_falloff {
            1.0
        } else if cos <= self.cos_cone {
            0.0
        } else {
            let s = (cos - self.cos_cone) / (self.cos_falloff - self.cos_cone);
            s * s * (3.0 - 2.0 * s)
        }
    }
}

/// One light with what sampling needs precomputed.
enum Prepared<'f> {
    Point { position: Vec3, intensity: Vec3 },
    Spot { position: Vec3, intensity: Vec3, cone: Cone },
    Directional { towards: Vec3, intensity: Vec3 },
    Area { corner: Vec3, edge_u: Vec3, edge_v: Vec3, normal: Vec3, area: f32, radiance: Vec3 },
    Environment { radiance: Vec3, map: Option<EnvironmentMap<'f>> },
    Emitters(Emitters<'f>),
}

/// Every emitting triangle of a frame as one light: a triangle is picked in proportion to its
/// power (luminance of its radiance × area), then a point uniformly over its area. The density
/// over the area of all of them is then the same for every point of one radiance, the
/// triangle's luminance over the total power, which a ray that hits an emitter needs for
/// multiple importance sampling without knowing which triangle of the list it hit.
struct Emitters<'f> {
    triangles: Vec<Emitter<'f>>,
    /// Picks a triangle by power.
    by_power: Distribution,
}

/// One emitting triangle in the world. Kept small (72 bytes): a scene may have millions, and
/// every frame gathers them.
struct Emitter<'f> {
    corner: Vec3,
    edge_u: Vec3,
    edge_v: Vec3,
    /// Unit normal of its front.
    normal: Vec3,
    /// Whether it emits from its back as well ([`Materials::emits_behind`]).
    two_sided: bool,
    area: f32,
    /// Its shader's emission, before a texture multiplies it: what it is picked by.
    radiance: Vec3,
    /// The texture that multiplies the emission, and where the triangle lies on it (boxed:
    /// most emitters have none).
    texture: Option<Box<(Slot<'f>, WorldTriangle)>>,
}

impl<'f> Emitter<'f> {
    /// Triangle `t` emitting `radiance` (times `texture`) from its front, and from its back too
    /// if `two_sided`, or `None` if it emits nothing.
    fn new(t: &WorldTriangle, radiance: Vec3, texture: Option<Slot<'f>>, two_sided: bool) -> Option<Emitter<'f>> {
        (luminance(radiance) > 0.0).then(|| Emitter {
            corner: t.corners[0],
            edge_u: t.corners[1] - t.corners[0],
            edge_v: t.corners[2] - t.corners[0],
            normal: t.front,
            two_sided,
            area: t.area,
            radiance,
            texture: texture.map(|slot| Box::new((slot, *t))),
        })
    }

    /// The radiance emitted at barycentrics `(1 − a − b, a, b)` of the triangle.
    fn radiance_at(&self, a: f32, b: f32) -> Vec3 {
        let Some(textured) = &self.texture else { return self.radiance };
        let (slot, t) = &**textured;
        let at = |corners: [Vec3; 3]| corners[0] * (1.0 - a - b) + corners[1] * a + corners[2] * b;
        let uv = |set: Option<[Vec2; 3]>| set.map(|c| c[0] * (1.0 - a - b) + c[1] * a + c[2] * b);
        // A point light sample has no footprint: the image itself.
        self.radiance * slot.at(at(t.local), [uv(t.uvs[0]), uv(t.uvs[1])], [0.0; 2]).truncate()
    }
}

impl<'f> Emitters<'f> {
    /// The light of `triangles`, or `None` if none emits.
    fn new(triangles: Vec<Emitter<'f>>) -> Option<Emitters<'f>> {
        let by_power = Distribution::new(triangles.iter().map(|e| luminance(e.radiance) * e.area).collect());
        (by_power.total > 0.0 && by_power.total.is_finite()).then_some(Emitters { triangles, by_power })
    }

    /// The density over area of the point of a triangle of `radiance` (its shader's emission,
    /// before a texture multiplies it).
    fn area_density(&self, radiance: Vec3) -> f32 {
        luminance(radiance) / self.by_power.total
    }

    /// A point on a triangle picked by power as seen from `p`: its sample, unless the point
    /// faces away.
    fn sample(&self, p: Vec3, u: [f32; 2]) -> Option<LightSample> {
        // The first number picks the triangle and, stretched over the triangle's share, the
        // point's first coordinate (pbrt's reuse of a sample): one 2D sample does both.
        let (index, u0) = self.by_power.pick(u[0]);
        let e = &self.triangles[index];
        // Uniform over the triangle: the square folded onto it along its diagonal. Which half a
        // point falls in is a coin toss, which a branch would mispredict half the time (2 % of
        // the Cornell room's path-traced frame): both folds are worked out and one is kept.
        let fold = u0 + u[1] > 1.0;
        let (a, b) = (std::hint::select_unpredictable(fold, 1.0 - u0, u0), std::hint::select_unpredictable(fold, 1.0 - u[1], u[1]));
        let q = e.corner + e.edge_u * a + e.edge_v * b;
        let (wi, distance) = towards(p, q)?;
        // The cosine on the side `p` sees.
        let facing = e.normal.dot(-wi);
        let cos_light = if e.two_sided { facing.abs() } else { facing };
        if cos_light <= 0.0 {
            return None;
        }
        // The density the triangle was really picked with (its rounded share of the list),
        // so that the estimate stays unbiased; hits weigh against [`Emitters::area_density`].
        let pdf = self.by_power.density(index) / e.area * distance * distance / cos_light;
        Some(LightSample { wi, distance, weighted: e.radiance_at(a, b) / pdf, pdf })
    }
}

impl<'f> SceneLights<'f> {
    /// The lights of `frame`, the triangles whose `materials` emit among them, each extended
    /// light sampled `samples` times per shading point. With `defaults`, a scene that nothing
    /// lights gets the sky as an environment light.
    pub fn of(frame: &Frame<'f>, materials: &Materials<'f>, samples: u32, defaults: bool) -> SceneLights<'f> {
        let mut ambient = Vec3::ZERO;
        let mut lights = Vec::new();
        for light in frame.lights() {
            let prepared = match *light {
                Light::Ambient { intensity } => {
                    ambient += intensity;
                    continue;
                }
                Light::Point { position, intensity } => Prepared::Point { position, intensity },
                Light::Spot { position, direction, intensity, cone_degrees, falloff_degrees } => Prepared::Spot {
                    position,
                    intensity,
                    cone: Cone {
                        axis: direction.normalize(),
                        cos_cone: cone_degrees.to_radians().cos(),
                        cos_falloff: falloff_degrees.to_radians().cos(),
                    },
                },
                Light::Directional { direction, intensity } => Prepared::Directional { towards: -direction.normalize(), intensity },
                Light::Area { corner, edge_u, edge_v, radiance } => {
                    let cross = edge_u.cross(edge_v);
                    Prepared::Area { corner, edge_u, edge_v, normal: cross.normalize(), area: cross.length(), radiance }
                }
                Light::Environment { radiance, map, rotate_degrees } => {
                    let image = map.and_then(|id| frame.texture(id)).and_then(|t| match t {
                        Texture::Image(image) => Some(&**image),
                        _ => None,
                    });
                    Prepared::Environment { radiance, map: image.and_then(|i| EnvironmentMap::new(Cow::Borrowed(i), rotate_degrees)) }
                }
            };
            lights.push(prepared);
        }
        let emitting = frame.world_triangles(
            |id, _| materials.emission(id).is_some(),
            |t| Emitter::new(t, materials.emission(t.shader_id)?, materials.emission_texture(t.shader_id), materials.emits_behind(t.shader_id)),
        );
        let emitters = Emitters::new(emitting);
        let emitters = emitters.map(|e| {
            lights.push(Prepared::Emitters(e));
            lights.len() - 1
        });
        let defaulted = defaults && lights.is_empty() && ambient == Vec3::ZERO;
        if defaulted {
            lights.push(Prepared::Environment { radiance: Vec3::ONE, map: EnvironmentMap::new(Cow::Owned(default_sky()), 0.0) });
        }
        let environment = lights.iter().any(|l| matches!(l, Prepared::Environment { .. }));
        let area = lights.iter().any(|l| matches!(l, Prepared::Area { .. }));
        SceneLights { lights, ambient, environment, area, emitters, defaulted, samples: samples as f32 }
    }

    /// Whether the scene had no light and was given the default sky.
    pub fn defaulted(&self) -> bool {
        self.defaulted
    }

    /// Whether some light has an extent (area, environment, emitting triangles), so that soft
    /// shadows need it sampled over it.
    pub fn has_extended(&self) -> bool {
        (0..self.lights.len()).any(|i| self.is_extended(i))
    }

    /// Whether light `index` is the emitting triangles, which even Whitted's rays sample at
    /// random points (they have no one centre).
    pub fn is_emitters(&self, index: usize) -> bool {
        self.emitters == Some(index)
    }

    /// Radiance `emitted` by a surface a ray of unit direction `dir` hit after `distance`, at
    /// the cosine `cos_light` between the ray and the surface's normal on the side it emits
    /// from, weighted by how the ray was `seen`: in full if directly, against the density with
    /// which light sampling would have picked the point if scattered (light sampling picks it by
    /// `picked_by`, its shader's emission before any texture), not at all if its light was
    /// sampled already. Nothing from the back of the surface.
    pub fn surface_emission(&self, emitted: Vec3, picked_by: Vec3, distance: f32, cos_light: f32, seen: Seen) -> Vec3 {
        if cos_light <= 0.0 {
            return Vec3::ZERO;
        }
        match seen {
            Seen::Directly => emitted,
            Seen::Not => Vec3::ZERO,
            Seen::Scattered { pdf, .. } => {
                let Some(Prepared::Emitters(e)) = self.emitters.map(|i| &self.lights[i]) else { return emitted };
                let light_pdf = e.area_density(picked_by) * distance * distance / cos_light;
                emitted * power_heuristic(pdf, self.samples * light_pdf)
            }
        }
    }

    /// How many lights there are to sample (the ambient term is not sampled).
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    /// The sum of the ambient lights' intensities.
    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// Whether an environment surrounds the scene (which then replaces the sky backdrop).
    pub fn has_environment(&self) -> bool {
        self.environment
    }

    /// Whether there are area lights (which rays can meet).
    pub fn has_area(&self) -> bool {
        self.area
    }

    /// Whether light `index` has an extent (so sampling it takes random numbers).
    pub fn is_extended(&self, index: usize) -> bool {
        matches!(self.lights[index], Prepared::Area { .. } | Prepared::Environment { .. } | Prepared::Emitters(_))
    }

    /// Light `index` if it is a point, spot or directional light: every shadow ray towards it
    /// ends at its position or leaves in its direction, so rays of neighbouring points can be
    /// traced as a packet, and neighbouring points can be lit by it together.
    pub fn delta(&self, index: usize) -> Option<Delta> {
        match self.lights[index] {
            Prepared::Point { position, intensity } => Some(Delta::Positional(Positional { position, intensity, cone: None })),
            Prepared::Spot { position, intensity, cone } => Some(Delta::Positional(Positional { position, intensity, cone: Some(cone) })),
            Prepared::Directional { towards, intensity } => Some(Delta::Directional { towards, intensity }),
            _ => None,
        }
    }

    /// Samples light `index` as seen from `p` with shading normal `n`, using the two uniform
    /// numbers `u`. With `u = [0.5, 0.5]` (Whitted's deterministic rays) an area light is
    /// sampled at its centre and an environment along the normal.
    pub fn sample(&self, index: usize, p: Vec3, n: Vec3, u: [f32; 2], deterministic: bool) -> Option<LightSample> {
        let sample = match &self.lights[index] {
            Prepared::Point { position, intensity } => {
                let (wi, distance) = towards(p, *position)?;
                LightSample { wi, distance, weighted: *intensity / (distance * distance), pdf: 0.0 }
            }
            Prepared::Spot { position, intensity, cone } => {
                let (wi, distance) = towards(p, *position)?;
                LightSample { wi, distance, weighted: *intensity * cone.fade(wi) / (distance * distance), pdf: 0.0 }
            }
            Prepared::Directional { towards, intensity } => LightSample { wi: *towards, distance: f32::INFINITY, weighted: *intensity, pdf: 0.0 },
            Prepared::Area { corner, edge_u, edge_v, normal, area, radiance } => {
                let q = *corner + *edge_u * u[0] + *edge_v * u[1];
                let (wi, distance) = towards(p, q)?;
                let cos_light = normal.dot(-wi);
                if cos_light <= 0.0 {
                    return None;
                }
                let pdf = distance * distance / (area * cos_light);
                LightSample { wi, distance, weighted: *radiance / pdf, pdf }
            }
            Prepared::Environment { radiance, map } => {
                let (wi, pdf, texel) = match map {
                    Some(map) if !deterministic => map.sample(u)?,
                    _ => {
                        let wi = Frame3::around(n).to_world(cosine_hemisphere(u));
                        (wi, wi.dot(n).max(0.0) / PI, map.as_ref().map_or(Vec3::ONE, |m| m.radiance(wi)))
                    }
                };
                if pdf <= 0.0 {
                    return None;
                }
                LightSample { wi, distance: f32::INFINITY, weighted: *radiance * texel / pdf, pdf }
            }
            Prepared::Emitters(emitters) => emitters.sample(p, u)?,
        };
        (sample.weighted.max_element() > 0.0).then_some(sample)
    }

    /// Emission from area lights that a ray from `origin` in unit direction `dir` meets before
    /// `tmax`, weighted by how it was `seen`.
    pub fn emission_along(&self, origin: Vec3, dir: Vec3, tmax: f32, seen: Seen) -> Vec3 {
        if matches!(seen, Seen::Not) {
            return Vec3::ZERO;
        }
        let mut sum = Vec3::ZERO;
        for light in &self.lights {
            let Prepared::Area { corner, edge_u, edge_v, normal, area, radiance } = light else { continue };
            let Some(t) = hit_parallelogram(origin, dir, *corner, *edge_u, *edge_v) else { continue };
            let cos_light = normal.dot(-dir);
            if t >= tmax || cos_light <= 0.0 {
                continue;
            }
            let weight = match seen {
                Seen::Scattered { pdf, .. } => power_heuristic(pdf, self.samples * t * t / (area * cos_light)),
                _ => 1.0,
            };
            sum += *radiance * weight;
        }
        sum
    }

    /// Radiance from the environment along unit direction `dir`, weighted by how it was `seen`.
    pub fn environment(&self, dir: Vec3, seen: Seen) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for light in &self.lights {
            let Prepared::Environment { radiance, map } = light else { continue };
            // The texel the direction looks at, found once for its radiance and its density.
            let texel = map.as_ref().map(|m| (m, m.texel_of(dir)));
            let emitted = *radiance * texel.map_or(Vec3::ONE, |(m, (x, y))| m.texel_radiance(x, y));
            let weight = match seen {
                Seen::Directly => 1.0,
                Seen::Not => 0.0,
                Seen::Scattered { normal, pdf } => {
                    let light_pdf = match texel {
                        Some((map, (x, y))) => map.texel_pdf(x, y),
                        None => dir.dot(normal).max(0.0) / PI,
                    };
                    power_heuristic(pdf, self.samples * light_pdf)
                }
            };
            sum += emitted * weight;
        }
        sum
    }
}

/// The unit direction and distance from `p` to `q`, unless they coincide.
fn towards(p: Vec3, q: Vec3) -> Option<(Vec3, f32)> {
    let d = q - p;
    let distance = d.length();
    (distance > 0.0 && distance.is_finite()).then(|| (d / distance, distance))
}

/// Where a ray meets the parallelogram `corner + s·edge_u + t·edge_v`, s, t in [0, 1], from
/// either side.
fn hit_parallelogram(origin: Vec3, dir: Vec3, corner: Vec3, edge_u: Vec3, edge_v: Vec3) -> Option<f32> {
    let p = dir.cross(edge_v);
    let det = edge_u.dot(p);
    if det == 0.0 {
        return None;
    }
    let to_origin = origin - corner;
    let s = to_origin.dot(p) / det;
    let q = to_origin.cross(edge_u);
    let t = dir.dot(q) / det;
    let distance = edge_v.dot(q) / det;
    ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) && distance > 0.0).then_some(distance)
}

/// A latitude-longitude environment image with the distribution that samples it by brightness.
/// Row 0 looks straight up (+y); column `x` looks at azimuth `φ = 2π (x / width − 1/2 − turn)`
/// measured from −z towards +x.
struct EnvironmentMap<'f> {
    /// The scene's image, or one baked for the frame (the default sky).
    image: Cow<'f, Image>,
    /// How far the image is turned about +y, in turns (the light's degrees / 360).
    turn: f32,
}

impl<'f> EnvironmentMap<'f> {
    /// The map of `image`, or `None` if it is black everywhere.
    fn new(image: Cow<'f, Image>, rotate_degrees: f32) -> Option<EnvironmentMap<'f>> {
        (image.environment_tables().rows.total > 0.0).then_some(EnvironmentMap { image, turn: rotate_degrees / 360.0 })
    }

    /// The image's tables of texels by brightness, kept with it.
    fn tables(&self) -> &EnvironmentTables {
        self.image.environment_tables()
    }

    /// The texel `dir` looks at (unfiltered, so that lookup and sampling density agree).
    fn radiance(&self, dir: Vec3) -> Vec3 {
        let (x, y) = self.texel_of(dir);
        self.texel_radiance(x, y)
    }

    /// The radiance of texel `(x, y)`.
    fn texel_radiance(&self, x: usize, y: usize) -> Vec3 {
        self.image.texel(x as i64, y as i64)
    }

    /// The column and row `dir` looks at.
    fn texel_of(&self, dir: Vec3) -> (usize, usize) {
        let (w, h) = (self.image.width() as usize, self.image.height() as usize);
        let v = dir.y.clamp(-1.0, 1.0).acos() / PI;
        let u = (dir.x.atan2(-dir.z) / TAU + 0.5 + self.turn).rem_euclid(1.0);
        (((u * w as f32) as usize).min(w - 1), ((v * h as f32) as usize).min(h - 1))
    }

    /// A direction by brightness, its solid-angle density and the texel it looks at. The texel
    /// and its density are the ones picked, not found again from the direction (the inverse
    /// trigonometry of [`EnvironmentMap::texel_of`], twice, was 6 % of the instructions of a
    /// path-traced sample of the sphere grid under the studio); a direction on a texel's very
    /// edge may round into its neighbour there, a set of directions of measure zero.
    fn sample(&self, u: [f32; 2]) -> Option<(Vec3, f32, Vec3)> {
        let tables = self.tables();
        let (row, v) = tables.rows.sample(u[1]);
        let (column, uu) = tables.columns[row].sample(u[0]);
        let theta = v * PI;
        let phi = (uu - 0.5 - self.turn) * TAU;
        let dir = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
        let pdf = self.texel_pdf(column, row);
        (pdf > 0.0).then(|| (dir, pdf, self.texel_radiance(column, row)))
    }

    /// The solid-angle density of the directions [`sample`](Self::sample) picks in texel
    /// `(x, y)` (a direction's is that of the texel [`EnvironmentMap::texel_of`] finds).
    fn texel_pdf(&self, x: usize, y: usize) -> f32 {
        let (w, h) = (self.image.width() as f32, self.image.height() as f32);
        let sin = (PI * (y as f32 + 0.5) / h).sin();
        // Density over the unit square of (u, v), then per solid angle: dω = 2π² sin θ du dv.
        let tables = self.tables();
        let unit_square = tables.rows.density(y) * h * tables.columns[y].density(x) * w;
        if sin <= 0.0 { 0.0 } else { unit_square / (2.0 * PI * PI * sin) }
    }
}

/// The sky backdrop baked into a latitude-longitude image (each texel the sky at its centre),
/// to light a scene that has no light of its own.
fn default_sky() -> Image {
    let (w, h) = DEFAULT_SKY_SIZE;
    let texels = (0..h)
        .flat_map(|y| {
            let theta = PI * (y as f32 + 0.5) / h as f32;
            (0..w).map(move |x| {
                let phi = TAU * ((x as f32 + 0.5) / w as f32 - 0.5);
                crate::sky(Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos()))
            })
        })
        .collect();
    Image::new(w, h, texels).expect("a valid sky image")
}

/// The luminance of a linear-RGB colour (Rec. 709 weights), one definition for the whole renderer.
pub(crate) use raystage_scene::luminance;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallelograms_are_hit_inside_only() {
        let (corner, eu, ev) = (Vec3::new(-1.0, 2.0, -1.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
        assert_eq!(hit_parallelogram(Vec3::ZERO, Vec3::Y, corner, eu, ev), Some(2.0));
        assert_eq!(hit_parallelogram(Vec3::new(1.5, 0.0, 0.0), Vec3::Y, corner, eu, ev), None);
        assert_eq!(hit_parallelogram(Vec3::ZERO, -Vec3::Y, corner, eu, ev), None);
    }

    /// The density with which `map` samples `dir`.
    fn density(map: &EnvironmentMap<'_>, dir: Vec3) -> f32 {
        let (x, y) = map.texel_of(dir);
        map.texel_pdf(x, y)
    }

    /// The environment map's sampling density integrates to one over the sphere and matches
    /// the direction sampling produces, and sampled directions look at bright texels.
    #[test]
    fn environment_sampling_density_is_consistent() {
        let (w, h) = (16, 8);
        let texels = (0..w * h).map(|i| if i % w == 3 && i / w == 2 { Vec3::splat(50.0) } else { Vec3::splat(0.5) }).collect();
        let image = Image::new(w as u32, h as u32, texels).unwrap();
        let map = EnvironmentMap::new(Cow::Borrowed(&image), 0.0).unwrap();
        let n = 400;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let v = (i as f32 + 0.5) / n as f32;
                let u = (j as f32 + 0.5) / n as f32;
                let (theta, phi) = (v * PI, (u - 0.5) * TAU);
                let dir = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
                integral += density(&map, dir) * 2.0 * PI * PI * theta.sin() / (n * n) as f32;
            }
        }
        assert!((integral - 1.0).abs() < 0.01, "{integral}");
        let mut bright = 0;
        for k in 0..1000 {
            let (dir, pdf, texel) = map.sample([((k * 7919) % 1000) as f32 / 1000.0, k as f32 / 1000.0]).unwrap();
            assert!((pdf - density(&map, dir)).abs() <= 1e-3 * pdf);
            assert_eq!(texel, map.radiance(dir), "the texel picked is the one the direction looks at");
            bright += (map.texel_of(dir) == (3, 2)) as u32;
        }
        assert!(bright > 500, "{bright} of 1000 samples in the bright texel");
    }

    /// A turned map looks the same everywhere but turned: counter-clockwise seen from above, so
    /// that what lay towards −z lies towards −x after a quarter turn, and its samples follow.
    #[test]
    fn a_turned_environment_turns_lookups_and_samples_alike() {
        let (w, h) = (16, 8);
        // One bright texel in the middle column (towards −z), just above the horizon.
        let texels = (0..w * h).map(|i| if i % w == 8 && i / w == 3 { Vec3::splat(50.0) } else { Vec3::splat(0.5) }).collect();
        let image = Image::new(w as u32, h as u32, texels).unwrap();
        let (plain, turned) = (EnvironmentMap::new(Cow::Borrowed(&image), 0.0).unwrap(), EnvironmentMap::new(Cow::Borrowed(&image), 90.0).unwrap());
        let up = 0.2;
        assert_eq!(plain.radiance(Vec3::new(0.0, up, -1.0)), Vec3::splat(50.0));
        assert_eq!(turned.radiance(Vec3::new(-1.0, up, 0.0)), Vec3::splat(50.0), "a quarter turn counter-clockwise");
        assert_eq!(turned.radiance(Vec3::new(0.0, up, -1.0)), Vec3::splat(0.5));
        for k in 0..200 {
            let u = [((k * 7919) % 200) as f32 / 200.0, k as f32 / 200.0];
            let (a, pa, _) = plain.sample(u).unwrap();
            let (b, pb, _) = turned.sample(u).unwrap();
            let quarter = Vec3::new(a.z, a.y, -a.x);
            assert!((b - quarter).length() < 1e-4 && (pa - pb).abs() <= 1e-3 * pa, "{a} turned is {quarter}, sampled {b}");
            assert!((pb - density(&turned, b)).abs() <= 1e-3 * pb);
        }
    }

    /// Veach's test of multiple importance sampling: a small bright emitter and a large dim one
    /// over a point, seen by a matte and by a glossy surface. Light sampling alone, BSDF
    /// sampling alone (each ray looked up against the emitters by brute force) and the two
    /// weighed by the power heuristic, with the density [`Emitters::area_density`] gives a
    /// hit, must estimate the same direct light, within their noise. Again with the large
    /// emitter turned to face away and emitting from its back as well (a double-sided glTF
    /// emitter): the three still agree, and the point gets the light it got facing it.
    #[test]
    fn light_sampling_bsdf_sampling_and_mis_agree() {
        let facing = direct_light_three_ways(false);
        let two_sided_back = direct_light_three_ways(true);
        for (a, b) in facing.iter().zip(&two_sided_back) {
            assert!((a - b).abs() <= 0.02 * a, "the back of a two-sided emitter lights as its front: {a} and {b}");
        }
    }

    /// The direct light of [`light_sampling_bsdf_sampling_and_mis_agree`] at the point, for each
    /// BSDF, once the three estimates are shown to agree; `turned`: the large emitter faces
    /// away from the point and is two-sided.
    fn direct_light_three_ways(turned: bool) -> Vec<f32> {
        use crate::bsdf::Bsdf;
        let quad = |centre: Vec3, half: f32, up: bool| {
            let c = [Vec3::new(-half, 0.0, -half), Vec3::new(half, 0.0, -half), Vec3::new(half, 0.0, half), Vec3::new(-half, 0.0, half)].map(|d| centre + d);
            // Wound to face down, towards the point below, or up, away from it.
            let triangles = if up { [[c[0], c[2], c[1]], [c[0], c[3], c[2]]] } else { [[c[0], c[1], c[2]], [c[0], c[2], c[3]]] };
            triangles.map(|corners| {
                let front = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                WorldTriangle { corners, front: front.normalize(), area: front.length() / 2.0, shader_id: None, local: corners, uvs: [None; 2] }
            })
        };
        let small = quad(Vec3::new(0.6, 2.0, 0.0), 0.05, false).map(|t| Emitter::new(&t, Vec3::splat(400.0), None, false).unwrap());
        let large = quad(Vec3::new(-1.0, 2.0, 0.0), 1.5, turned).map(|t| Emitter::new(&t, Vec3::splat(0.5), None, turned).unwrap());
        assert!(small.iter().all(|e| e.normal.y < 0.0) && large.iter().all(|e| (e.normal.y > 0.0) == turned));
        let emitters = Emitters::new(small.into_iter().chain(large).collect()).unwrap();
        let (p, frame) = (Vec3::ZERO, Frame3::around(Vec3::Y));
        // What a ray from `p` in direction `wi` meets first: the radiance, distance and cosine.
        let meet = |wi: Vec3| -> Option<(Vec3, f32, f32)> {
            emitters
                .triangles
                .iter()
                .filter_map(|e| {
                    let t = hit_parallelogram(p, wi, e.corner, e.edge_u, e.edge_v)?;
                    let q = p + wi * t - e.corner;
                    // Inside the triangle half of the parallelogram.
                    let (uu, vv) = (e.edge_u.length_squared(), e.edge_v.length_squared());
                    let uv = e.edge_u.dot(e.edge_v);
                    let det = uu * vv - uv * uv;
                    let a = (vv * q.dot(e.edge_u) - uv * q.dot(e.edge_v)) / det;
                    let b = (uu * q.dot(e.edge_v) - uv * q.dot(e.edge_u)) / det;
                    let cos = if e.two_sided { e.normal.dot(-wi).abs() } else { e.normal.dot(-wi) };
                    (a + b <= 1.0 && cos > 0.0).then_some((e.radiance, t, cos))
                })
                .min_by(|x, y| x.1.total_cmp(&y.1))
        };
        let wo = Vec3::new(-0.5, 0.7, 0.2).normalize();
        let mut direct = Vec::new();
        for bsdf in [Bsdf::Lambert { albedo: Vec3::splat(0.8) }, Bsdf::Glossy { reflectance: Vec3::splat(0.9), alpha: 0.15 }] {
            let n = 256;
            let (mut light, mut scattered, mut mis) = (Vec::new(), Vec::new(), Vec::new());
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let wo_local = frame.to_local(wo);
                    let from_light = emitters.sample(p, u).map_or(0.0, |ls| {
                        let f = bsdf.eval(wo_local, frame.to_local(ls.wi)).x;
                        let weight = power_heuristic(ls.pdf, bsdf.pdf(wo_local, frame.to_local(ls.wi)));
                        light.push(f * ls.weighted.x);
                        f * ls.weighted.x * weight
                    });
                    let u2 = [u[1], u[0]];
                    let from_bsdf = bsdf.sample(wo_local, u2, u[0]).and_then(|s| {
                        let wi = frame.to_world(s.wi);
                        let (radiance, t, cos) = meet(wi)?;
                        let light_pdf = emitters.area_density(radiance) * t * t / cos;
                        Some((s.weight.x * radiance.x, power_heuristic(s.pdf, light_pdf)))
                    });
                    scattered.push(from_bsdf.map_or(0.0, |(v, _)| v));
                    mis.push(from_light + from_bsdf.map_or(0.0, |(v, w)| v * w));
                }
            }
            light.resize(n * n, 0.0);
            let stats = |v: &[f32]| {
                let mean = v.iter().sum::<f32>() / v.len() as f32;
                let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / (v.len() - 1) as f32;
                (mean, (var / v.len() as f32).sqrt())
            };
            let ((a, ea), (b, eb), (c, ec)) = (stats(&light), stats(&scattered), stats(&mis));
            let agree = |x: f32, ex: f32, y: f32, ey: f32| (x - y).abs() <= 4.0 * (ex * ex + ey * ey).sqrt() + 1e-3 * x.abs();
            assert!(agree(a, ea, c, ec) && agree(b, eb, c, ec) && agree(a, ea, b, eb), "{bsdf:?}: light {a} ± {ea}, BSDF {b} ± {eb}, MIS {c} ± {ec}");
            assert!(a > 0.1, "{bsdf:?}: the emitters light the point: {a}");
            direct.push(c);
        }
        direct
    }
}
