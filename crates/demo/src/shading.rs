//! Scenes that show the shader classes and lights: a closed Cornell room lit by an area light in
//! its ceiling, a showroom of spheres in every material under a sky, a sun-like spot and a
//! soft area light, and the accuracy report's small scenes (spheres under area lights, a glass
//! sphere over a checkered floor).

use glam::{Vec2, Vec3};
use raystage_scene::{Camera, Light, Mesh, ObjectKind, ParamValue, Scene, SceneError, ShaderId, Texture};

/// The Cornell room's extent: x in [−1, 1], y in [0, 2], z from the back wall at −1 to the wall
/// behind the camera at 3.
const ROOM_MIN: Vec3 = Vec3::new(-1.0, 0.0, -1.0);
const ROOM_MAX: Vec3 = Vec3::new(1.0, 2.0, 3.0);

/// A closed Cornell-style room: white floor, ceiling, back and front walls, a red wall on the
/// left and a green one on the right, a square area light just below the ceiling, a glass sphere
/// and a white box. Closed, so that no path escapes: every path tracing estimate converges to
/// the same image whatever the background.
pub fn cornell_room() -> Result<Scene, SceneError> {
    let mut scene = Scene::new();
    let white = shader(&mut scene, "Diffuse", &[("diffuse", color(0.73, 0.73, 0.73))])?;
    let red = shader(&mut scene, "Diffuse", &[("diffuse", color(0.63, 0.065, 0.05))])?;
    let green = shader(&mut scene, "Diffuse", &[("diffuse", color(0.14, 0.45, 0.091))])?;
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))])?;
    let (lo, hi) = (ROOM_MIN, ROOM_MAX);
    let mut room = MeshBuilder::default();
    // Inward-facing walls: corners counter-clockwise as seen from inside.
    room.quad([Vec3::new(lo.x, lo.y, hi.z), Vec3::new(hi.x, lo.y, hi.z), Vec3::new(hi.x, lo.y, lo.z), Vec3::new(lo.x, lo.y, lo.z)], white);
    room.quad([Vec3::new(lo.x, hi.y, lo.z), Vec3::new(hi.x, hi.y, lo.z), Vec3::new(hi.x, hi.y, hi.z), Vec3::new(lo.x, hi.y, hi.z)], white);
    room.quad([Vec3::new(lo.x, lo.y, lo.z), Vec3::new(hi.x, lo.y, lo.z), Vec3::new(hi.x, hi.y, lo.z), Vec3::new(lo.x, hi.y, lo.z)], white);
    room.quad([Vec3::new(hi.x, lo.y, hi.z), Vec3::new(lo.x, lo.y, hi.z), Vec3::new(lo.x, hi.y, hi.z), Vec3::new(hi.x, hi.y, hi.z)], white);
    room.quad([Vec3::new(lo.x, lo.y, hi.z), Vec3::new(lo.x, lo.y, lo.z), Vec3::new(lo.x, hi.y, lo.z), Vec3::new(lo.x, hi.y, hi.z)], red);
    room.quad([Vec3::new(hi.x, lo.y, lo.z), Vec3::new(hi.x, lo.y, hi.z), Vec3::new(hi.x, hi.y, hi.z), Vec3::new(hi.x, hi.y, lo.z)], green);
    room.cuboid(Vec3::new(-0.75, 0.0, -0.75), Vec3::new(-0.15, 1.2, -0.2), white);
    room.sphere(Vec3::new(0.42, 0.38, -0.2), 0.38, 48, 24, glass);
    let room = scene.add_object(ObjectKind::Static, room.mesh)?;
    scene.add_instance(room, glam::Affine3A::IDENTITY)?;
    let size = 0.5;
    scene.add_light(Light::Area {
        corner: Vec3::new(-size / 2.0, hi.y - 1e-3, -size / 2.0),
        edge_u: Vec3::new(size, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, size),
        radiance: Vec3::new(17.0, 12.0, 4.0),
    })?;
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.0, 2.9), Vec3::new(0.0, 1.0, 0.0), Vec3::Y, 40.0)?)?;
    Ok(scene)
}

/// A showroom: a row of spheres in every material (diffuse with solid noise, Phong plastic,
/// mirror, rough metal, glass, an emitter and ambient occlusion) and a vertex-coloured box on
/// a checkered floor, under a pale blue sky, a spot light and a soft area light.
pub fn materials() -> Result<Scene, SceneError> {
    let mut scene = Scene::new();
    let checker = scene.add_texture(Texture::Checker { a: Vec3::splat(0.8), b: Vec3::splat(0.25), scale: 1.0 })?;
    let noise = scene.add_texture(Texture::Noise { a: Vec3::new(0.75, 0.45, 0.2), b: Vec3::new(0.25, 0.1, 0.05), scale: 6.0 })?;
    let floor = shader(&mut scene, "Diffuse", &[("diffuse_texture", ParamValue::Texture(Some(checker)))])?;
    let spheres = [
        shader(&mut scene, "Diffuse", &[("diffuse_texture", ParamValue::Texture(Some(noise)))])?,
        shader(&mut scene, "Phong", &[("diffuse", color(0.05, 0.25, 0.6)), ("specular", color(0.35, 0.35, 0.35)), ("shininess", ParamValue::Float(120.0))])?,
        shader(&mut scene, "Mirror", &[("reflectance", color(0.95, 0.95, 0.95))])?,
        shader(&mut scene, "Glossy", &[("reflectance", color(0.95, 0.64, 0.54)), ("roughness", ParamValue::Float(0.25))])?,
        shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5)), ("absorption", color(0.6, 0.15, 0.05))])?,
        shader(&mut scene, "Emissive", &[("emission", color(4.0, 2.2, 0.8))])?,
        shader(&mut scene, "AmbientOcclusion", &[("diffuse", color(0.8, 0.8, 0.8))])?,
    ];
    let painted = shader(&mut scene, "VertexColor", &[])?;
    let mut mesh = MeshBuilder::default();
    let r = 20.0;
    mesh.quad_uv([Vec3::new(-r, 0.0, r), Vec3::new(r, 0.0, r), Vec3::new(r, 0.0, -r), Vec3::new(-r, 0.0, -r)], floor, 2.0 * r);
    for (k, &s) in spheres.iter().enumerate() {
        let x = (k as f32 - 3.0) * 1.25;
        mesh.sphere(Vec3::new(x, 0.5, -0.25 * (k as f32 - 3.0).abs()), 0.5, 64, 32, s);
    }
    mesh.painted_cube(Vec3::new(-0.4, 0.0, 1.2), 0.6, painted);
    let object = scene.add_object(ObjectKind::Static, mesh.mesh)?;
    scene.add_instance(object, glam::Affine3A::IDENTITY)?;
    scene.add_light(Light::Environment { radiance: Vec3::new(0.35, 0.45, 0.6), map: None, rotate_degrees: 0.0 })?;
    scene.add_light(Light::Spot {
        position: Vec3::new(4.0, 6.0, 5.0),
        direction: Vec3::new(-4.0, -6.0, -5.0),
        intensity: Vec3::splat(60.0),
        cone_degrees: 30.0,
        falloff_degrees: 20.0,
    })?;
    scene.add_light(Light::Area {
        corner: Vec3::new(-3.0, 5.0, 1.0),
        // edge_u × edge_v points down: area lights emit on one side.
        edge_u: Vec3::new(2.0, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 2.0),
        radiance: Vec3::splat(2.0),
    })?;
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 2.2, 6.0), Vec3::new(0.0, 0.4, 0.0), Vec3::Y, 45.0)?)?;
    Ok(scene)
}

/// Three spheres (white and red diffuse, a rough copper) on a grey floor, lit only by two area
/// lights of different sizes and colours against a black sky: soft shadows, the light-sampling
/// knob's scene. Small (about 6,000 triangles).
pub fn area_lit_spheres() -> Result<Scene, SceneError> {
    let mut scene = Scene::new();
    let floor = shader(&mut scene, "Diffuse", &[("diffuse", color(0.5, 0.5, 0.5))])?;
    let spheres = [
        shader(&mut scene, "Diffuse", &[("diffuse", color(0.8, 0.8, 0.8))])?,
        shader(&mut scene, "Diffuse", &[("diffuse", color(0.7, 0.1, 0.08))])?,
        shader(&mut scene, "Glossy", &[("reflectance", color(0.95, 0.64, 0.54)), ("roughness", ParamValue::Float(0.3))])?,
    ];
    let mut mesh = MeshBuilder::default();
    let r = 8.0;
    mesh.quad([Vec3::new(-r, 0.0, r), Vec3::new(r, 0.0, r), Vec3::new(r, 0.0, -r), Vec3::new(-r, 0.0, -r)], floor);
    for (k, &s) in spheres.iter().enumerate() {
        let x = (k as f32 - 1.0) * 1.3;
        mesh.sphere(Vec3::new(x, 0.55, -0.3 * k as f32), 0.55, 48, 24, s);
    }
    let object = scene.add_object(ObjectKind::Static, mesh.mesh)?;
    scene.add_instance(object, glam::Affine3A::IDENTITY)?;
    // A large warm light to the left, a small bright cool one to the right.
    scene.add_light(Light::Area {
        corner: Vec3::new(-3.5, 3.0, -0.5),
        // edge_u × edge_v points down, at the spheres: area lights emit on one side.
        edge_u: Vec3::new(1.5, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 1.5),
        radiance: Vec3::new(6.0, 4.5, 3.0),
    })?;
    scene.add_light(Light::Area {
        corner: Vec3::new(2.0, 2.5, 0.5),
        edge_u: Vec3::new(0.4, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 0.4),
        radiance: Vec3::new(30.0, 36.0, 48.0),
    })?;
    scene.add_light(Light::Environment { radiance: Vec3::ZERO, map: None, rotate_degrees: 0.0 })?;
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.6, 4.5), Vec3::new(0.0, 0.5, -0.2), Vec3::Y, 40.0)?)?;
    Ok(scene)
}

/// A glass sphere over a checkered floor under a pale sky: lit by the environment only, so the
/// light the glass focuses onto the floor is a smooth glow a path tracer resolves, not the sharp
/// caustic of a small light it cannot. The depth knob's scene: every bounce through the glass
/// counts. Small (about 4,600 triangles).
pub fn glass_over_checker() -> Result<Scene, SceneError> {
    let mut scene = Scene::new();
    let checker = scene.add_texture(Texture::Checker { a: Vec3::splat(0.8), b: Vec3::splat(0.1), scale: 1.0 })?;
    let floor = shader(&mut scene, "Diffuse", &[("diffuse_texture", ParamValue::Texture(Some(checker)))])?;
    let glass = shader(&mut scene, "Glass", &[("ior", ParamValue::Float(1.5))])?;
    let mut mesh = MeshBuilder::default();
    let r = 10.0;
    mesh.quad_uv([Vec3::new(-r, 0.0, r), Vec3::new(r, 0.0, r), Vec3::new(r, 0.0, -r), Vec3::new(-r, 0.0, -r)], floor, 2.0 * r);
    mesh.sphere(Vec3::new(0.0, 0.9, 0.0), 0.8, 64, 32, glass);
    let object = scene.add_object(ObjectKind::Static, mesh.mesh)?;
    scene.add_instance(object, glam::Affine3A::IDENTITY)?;
    scene.add_light(Light::Environment { radiance: Vec3::new(0.9, 0.95, 1.0), map: None, rotate_degrees: 0.0 })?;
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 2.2, 4.0), Vec3::new(0.0, 0.6, 0.0), Vec3::Y, 40.0)?)?;
    Ok(scene)
}

/// A UV sphere of `su × sv` segments facing outwards, with smooth normals and texture
/// coordinates, shaded by the scene's default shader until given one.
pub fn sphere_mesh(centre: Vec3, radius: f32, su: u32, sv: u32) -> Mesh {
    let mut b = MeshBuilder::default();
    b.sphere(centre, radius, su, sv, ShaderId(0));
    Mesh { shaders: Vec::new(), ..b.mesh }
}

/// An axis-aligned box from `lo` to `hi` facing outwards, shaded by the scene's default shader
/// until given one.
pub fn box_mesh(lo: Vec3, hi: Vec3) -> Mesh {
    let mut b = MeshBuilder::default();
    b.cuboid(lo, hi, ShaderId(0));
    Mesh { shaders: Vec::new(), ..b.mesh }
}

/// A named parameter value that is a colour.
fn color(r: f32, g: f32, b: f32) -> ParamValue {
    ParamValue::Color(Vec3::new(r, g, b))
}

/// A shader of class `class` with parameters set.
fn shader(scene: &mut Scene, class: &str, params: &[(&str, ParamValue)]) -> Result<ShaderId, SceneError> {
    let id = scene.add_shader(class)?;
    for (name, value) in params {
        scene.set_param(id, name, *value)?;
    }
    Ok(id)
}

/// Gathers shapes with shaders, normals and texture coordinates into one scene mesh.
#[derive(Default)]
struct MeshBuilder {
    mesh: Mesh,
}

impl MeshBuilder {
    /// A flat quad, counter-clockwise from the front.
    fn quad(&mut self, corners: [Vec3; 4], shader: ShaderId) {
        self.quad_uv(corners, shader, 1.0);
    }

    /// A flat quad with texture coordinates running from 0 to `repeat` along its edges.
    fn quad_uv(&mut self, corners: [Vec3; 4], shader: ShaderId, repeat: f32) {
        let base = self.mesh.positions.len() as u32;
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize();
        self.mesh.positions.extend(corners);
        self.mesh.normals.extend([normal; 4]);
        self.mesh.uvs.extend([Vec2::ZERO, Vec2::new(repeat, 0.0), Vec2::new(repeat, repeat), Vec2::new(0.0, repeat)]);
        self.push([base, base + 1, base + 2], shader);
        self.push([base, base + 2, base + 3], shader);
    }

    /// An axis-aligned box from `lo` to `hi`, facing outwards.
    fn cuboid(&mut self, lo: Vec3, hi: Vec3, shader: ShaderId) {
        for [a, b, c, d] in cuboid_faces(lo, hi) {
            self.quad([a, b, c, d], shader);
        }
    }

    /// A cube of edge `size` standing on the floor at `base`, its corners coloured by position
    /// (for the VertexColor class).
    fn painted_cube(&mut self, base: Vec3, size: f32, shader: ShaderId) {
        let lo = base - Vec3::new(size / 2.0, 0.0, size / 2.0);
        let hi = lo + Vec3::splat(size);
        for corners in cuboid_faces(lo, hi) {
            let first = self.mesh.positions.len();
            self.quad(corners, shader);
            let painted = self.mesh.positions[first..].iter().map(|p| ((*p - lo) / size).clamp(Vec3::ZERO, Vec3::ONE)).collect::<Vec<_>>();
            self.mesh.colors.resize(first, Vec3::ONE);
            self.mesh.colors.extend(painted);
        }
    }

    /// A UV sphere, facing outwards, with smooth normals (no degenerate triangles at the poles).
    fn sphere(&mut self, centre: Vec3, radius: f32, su: u32, sv: u32, shader: ShaderId) {
        let base = self.mesh.positions.len() as u32;
        for j in 0..=sv {
            for i in 0..=su {
                let (v, u) = (j as f32 / sv as f32, i as f32 / su as f32);
                let (theta, phi) = (std::f32::consts::PI * v, std::f32::consts::TAU * u);
                let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
                self.mesh.positions.push(centre + n * radius);
                self.mesh.normals.push(n);
                self.mesh.uvs.push(Vec2::new(u, v));
            }
        }
        for j in 0..sv {
            for i in 0..su {
                let a = base + j * (su + 1) + i;
                let (b, c) = (a + 1, a + su + 1);
                // The first ring's `a b` and the last ring's `c c+1` are the same pole point.
                if j > 0 {
                    self.push([a, c, b], shader);
                }
                if j + 1 < sv {
                    self.push([b, c, c + 1], shader);
                }
            }
        }
    }

    /// One triangle, keeping the colour array in step when it is in use.
    fn push(&mut self, triangle: [u32; 3], shader: ShaderId) {
        self.mesh.indices.push(triangle);
        self.mesh.shaders.push(shader);
        if !self.mesh.colors.is_empty() {
            self.mesh.colors.resize(self.mesh.positions.len(), Vec3::ONE);
        }
    }
}

/// The six faces of the box from `lo` to `hi`, each counter-clockwise seen from outside.
fn cuboid_faces(lo: Vec3, hi: Vec3) -> [[Vec3; 4]; 6] {
    let p = |x: bool, y: bool, z: bool| Vec3::new(if x { hi.x } else { lo.x }, if y { hi.y } else { lo.y }, if z { hi.z } else { lo.z });
    [
        [p(false, false, true), p(true, false, true), p(true, true, true), p(false, true, true)],
        [p(true, false, false), p(false, false, false), p(false, true, false), p(true, true, false)],
        [p(true, false, true), p(true, false, false), p(true, true, false), p(true, true, true)],
        [p(false, false, false), p(false, false, true), p(false, true, true), p(false, true, false)],
        [p(false, true, true), p(true, true, true), p(true, true, false), p(false, true, false)],
        [p(false, false, false), p(true, false, false), p(true, false, true), p(false, false, true)],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle of a closed shape faces away from its centre (so glass is entered
    /// through the front).
    #[test]
    fn shapes_face_outwards() {
        let mut b = MeshBuilder::default();
        let s = ShaderId(0);
        b.sphere(Vec3::new(1.0, 2.0, 3.0), 0.5, 16, 8, s);
        let sphere_end = b.mesh.indices.len();
        b.cuboid(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(0.0, 0.5, 2.0), s);
        for (k, tri) in b.mesh.indices.iter().enumerate() {
            let [a, bb, c] = tri.map(|i| b.mesh.positions[i as usize]);
            let centre = if k < sphere_end { Vec3::new(1.0, 2.0, 3.0) } else { Vec3::new(-0.5, -0.25, 0.5) };
            let normal = (bb - a).cross(c - a);
            if normal.length() > 1e-9 {
                assert!(normal.dot((a + bb + c) / 3.0 - centre) > 0.0, "triangle {k} faces inwards");
            }
        }
    }

    #[test]
    fn the_room_is_closed_and_the_showroom_lit() {
        let room = cornell_room().unwrap();
        assert_eq!(room.lights().count(), 1);
        let showroom = materials().unwrap();
        assert!(showroom.lights().count() >= 3);
        assert_eq!(area_lit_spheres().unwrap().lights().count(), 3);
        assert_eq!(glass_over_checker().unwrap().lights().count(), 1);
    }
}
