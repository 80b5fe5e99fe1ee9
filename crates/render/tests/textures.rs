//! Image textures and environment maps from encoded files, as the C ABI and the HTTP API load
//! them: decoded to linear light, looked up by the renderer, and gone from the frame after the
//! texture is removed.

mod common;

use common::{pixels, render_with, shader};
use glam::{Affine3A, Vec2, Vec3};
use raystage_render::Integrator;
use raystage_scene::{Camera, Image, Light, Mesh, ObjectKind, ParamValue, Scene, Texture};

/// `image` encoded as a file of `format`.
fn file(image: image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).unwrap();
    bytes.into_inner()
}

/// A 2 × 2 quad facing +z at the origin, texture coordinates (0, 0) at its top left.
fn quad() -> Mesh {
    let corners = [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)];
    let mut mesh = Mesh::new(corners.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(), vec![[0, 3, 2], [0, 2, 1]]);
    mesh.uvs = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    mesh
}

#[test]
fn a_png_texture_colours_a_quad_until_it_is_removed() {
    // Left half red, right half blue (sRGB 255 is linear 1).
    let png = image::RgbImage::from_fn(8, 8, |x, _| if x < 4 { image::Rgb([255, 0, 0]) } else { image::Rgb([0, 0, 255]) });
    let mut scene = Scene::new();
    let texture = scene.add_texture(Texture::Image(Image::decode(&file(png.into(), image::ImageFormat::Png)).unwrap().into())).unwrap();
    let white = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE)), ("diffuse_texture", ParamValue::Texture(Some(texture)))]);
    let object = scene.add_object(ObjectKind::Static, quad().with_shader(white)).unwrap();
    scene.add_instance(object, Affine3A::IDENTITY).unwrap();
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();

    // The eye light faces the quad: the colour is the texel's, within the cosine's falloff.
    let (film, _) = render_with(&scene, Integrator::EyeLight, 32, 32, 1);
    let (left, right) = (film.pixel(12, 16), film.pixel(20, 16));
    assert!(left.x > 0.97 && left.y == 0.0 && left.z == 0.0, "left of the quad: {left}");
    assert!(right.z > 0.97 && right.x == 0.0 && right.y == 0.0, "right of the quad: {right}");

    // Shaders refer to textures by id: without it, the quad is plain white.
    scene.remove_texture(texture).unwrap();
    let (film, _) = render_with(&scene, Integrator::EyeLight, 32, 32, 1);
    let (left, right) = (film.pixel(12, 16), film.pixel(20, 16));
    assert!(left.min_element() > 0.97 && right.min_element() > 0.97, "untextured: {left} {right}");
}

#[test]
fn a_radiance_hdr_environment_map_is_seen_at_its_linear_values() {
    let sky = Vec3::new(3.0, 1.0, 0.5);
    let hdr = image::Rgb32FImage::from_pixel(16, 8, image::Rgb(sky.to_array()));
    let mut scene = Scene::new();
    let map = scene.add_texture(Texture::Image(Image::decode(&file(hdr.into(), image::ImageFormat::Hdr)).unwrap().into())).unwrap();
    scene.add_light(Light::Environment { radiance: Vec3::splat(2.0), map: Some(map), rotate_degrees: 0.0 }).unwrap();
    scene.set_camera(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, Integrator::Path, 8, 8, 1);
    for pixel in pixels(&film) {
        // The map scaled by the light's radiance, to Radiance's 8 bits per channel.
        assert!((pixel - 2.0 * sky).abs().max_element() < 0.05, "{pixel}");
    }
}

/// What a row of a 32 × 32 eye-light image shows of a quad whose physically based shader samples
/// a 2 × 1 texture (a red texel, then a green one) with `params`: the quad's texture coordinates
/// run from 0 to 2 left to right (its second set from 0.5 to 2.5), so that its right half shows
/// the texture's wrapping. The camera sees the whole quad, u ≈ 0.25 at pixel 7, 0.5 at 10, 1.25
/// at 18 and 1.75 at 24.
fn wrapped_row(params: &[(&str, ParamValue)]) -> Vec<Vec3> {
    let mut scene = Scene::new();
    let texture = scene.add_texture(Texture::Image(Image::new(2, 1, vec![Vec3::X, Vec3::Y]).unwrap().into())).unwrap();
    let mut all = vec![("metallic", ParamValue::Float(0.0)), ("base_color_texture", ParamValue::Texture(Some(texture)))];
    all.extend_from_slice(params);
    let pbr = shader(&mut scene, "PhysicallyBased", &all);
    let mut mesh = quad();
    mesh.uvs.iter_mut().for_each(|uv| uv.x *= 2.0);
    mesh.uvs1 = mesh.uvs.iter().map(|uv| *uv + Vec2::new(0.5, 0.0)).collect();
    common::place(&mut scene, mesh, pbr);
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 40.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, Integrator::EyeLight, 32, 32, 1);
    (0..32).map(|x| film.pixel(x, 16)).collect()
}

/// Whether `c` is red (`true`) or green (`false`), and clearly so.
fn is_red(c: Vec3) -> bool {
    assert!(c.z == 0.0 && (c.x - c.y).abs() > 0.5 * c.max_element(), "neither red nor green: {c}");
    c.x > c.y
}

#[test]
fn wrap_modes_filters_and_transforms_are_seen_on_pixels() {
    let float = ParamValue::Float;
    let nearest = ("base_color_filter", float(9728.0));
    // Repeat (the default): u = 1.25 is red again, 1.75 green.
    let repeat = wrapped_row(&[nearest]);
    assert_eq!([7, 18, 24].map(|x| is_red(repeat[x])), [true, true, false]);
    // Clamp to edge: beyond 1 the last texel, green.
    let clamp = wrapped_row(&[nearest, ("base_color_wrap_s", float(33071.0))]);
    assert_eq!([7, 18, 24].map(|x| is_red(clamp[x])), [true, false, false]);
    // Mirrored repeat: the second copy runs green, then red.
    let mirror = wrapped_row(&[nearest, ("base_color_wrap_s", float(33648.0))]);
    assert_eq!([7, 18, 24].map(|x| is_red(mirror[x])), [true, false, true]);
    // Bilinear magnification blends the two texels where they meet; nearest does not.
    let blend = wrapped_row(&[])[10];
    assert!((blend.x - blend.y).abs() < 0.1 * blend.x && blend.x > 0.2, "half red, half green: {blend}");
    // (`is_red` asserts that the pixel is clearly one of the two.)
    is_red(repeat[10]);
    // KHR_texture_transform: an offset of half the texture moves green where red was.
    let offset = wrapped_row(&[nearest, ("base_color_offset_u", float(0.5))]);
    assert_eq!([7, 18, 24].map(|x| is_red(offset[x])), [false, false, true]);
    // A scale of 0.5 shows the red half across the whole left half of the quad.
    let scaled = wrapped_row(&[nearest, ("base_color_scale_u", float(0.5))]);
    assert_eq!([7, 10, 14].map(|x| is_red(scaled[x])), [true, true, true]);
    // The second texture coordinates (shifted by half the texture): as the offset.
    let second = wrapped_row(&[nearest, ("base_color_texcoord", float(1.0))]);
    let on_quad = |row: &[Vec3]| row[6..26].iter().map(|&c| is_red(c)).collect::<Vec<_>>();
    assert_eq!(on_quad(&second), on_quad(&offset));
}

/// The quad of [`quad`] with a physically based matte white shader whose normal map is one
/// texel, `normal` (a unit vector in tangent space), lit by a directional light travelling along
/// `light` (none for the eye light), rendered by `integrator`: the centre pixel, and whether
/// every pixel is finite. `mesh` may spoil the quad's tangent frame.
fn normal_mapped(normal: Option<Vec3>, light: Vec3, integrator: Integrator, mesh: impl FnOnce(&mut Mesh)) -> (Vec3, bool) {
    normal_mapped_with(&[], normal, light, integrator, mesh)
}

/// [`normal_mapped`] with more parameters of the shader.
fn normal_mapped_with(extra: &[(&str, ParamValue)], normal: Option<Vec3>, light: Vec3, integrator: Integrator, mesh: impl FnOnce(&mut Mesh)) -> (Vec3, bool) {
    let mut scene = Scene::new();
    let mut params = vec![("metallic", ParamValue::Float(0.0)), ("specular", ParamValue::Float(0.0))];
    params.extend_from_slice(extra);
    if let Some(normal) = normal {
        // Stored as glTF stores it: components in [−1, 1] as texels in [0, 1].
        let map = scene.add_texture(Texture::Image(Image::new(1, 1, vec![(normal + Vec3::ONE) * 0.5]).unwrap().into())).unwrap();
        params.push(("normal_texture", ParamValue::Texture(Some(map))));
    }
    let pbr = shader(&mut scene, "PhysicallyBased", &params);
    let mut quad = quad();
    mesh(&mut quad);
    common::place(&mut scene, quad, pbr);
    if integrator != Integrator::EyeLight {
        scene.add_light(Light::Directional { direction: light, intensity: Vec3::ONE }).unwrap();
    }
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, integrator, 16, 16, 4);
    (film.pixel(8, 8), pixels(&film).iter().all(|p| p.is_finite()))
}

#[test]
fn a_normal_map_turns_the_shading_towards_where_it_points() {
    // Tilted 40° towards +u (+x on the quad), and towards +Y (up the image, +y).
    let (s, c) = 40f32.to_radians().sin_cos();
    let (right, up) = (Vec3::new(s, 0.0, c), Vec3::new(0.0, s, c));
    let from_right = Vec3::new(-1.0, 0.0, -1.0);
    for integrator in [Integrator::Whitted, Integrator::Distribution, Integrator::Path] {
        let flat = normal_mapped(None, from_right, integrator, |_| {}).0.x;
        let towards = normal_mapped(Some(right), from_right, integrator, |_| {}).0.x;
        let away = normal_mapped(Some(-right * Vec3::new(1.0, 1.0, -1.0)), from_right, integrator, |_| {}).0.x;
        // Lambert: cos 45° flat, cos 5° tilted towards the light, cos 85° away from it.
        let expected = |degrees: f32| degrees.to_radians().cos() * std::f32::consts::FRAC_1_PI;
        assert!((flat / expected(45.0) - 1.0).abs() < 0.02, "{integrator:?}: flat {flat}");
        assert!((towards / expected(5.0) - 1.0).abs() < 0.02, "{integrator:?}: towards the light {towards}");
        assert!((away / expected(85.0) - 1.0).abs() < 0.05, "{integrator:?}: away from the light {away}");
        // Up the image is up the quad: a light from above.
        let from_above = Vec3::new(0.0, -1.0, -1.0);
        assert!(normal_mapped(Some(up), from_above, integrator, |_| {}).0.x > 1.3 * flat, "{integrator:?}: +Y is up");
    }
    // On the second texture coordinates, whose u runs up the quad: the map's +X is up.
    let second = [("normal_texcoord", ParamValue::Float(1.0))];
    let up_the_quad = |m: &mut Mesh| m.uvs1 = m.positions.iter().map(|p| Vec2::new(p.y, p.x)).collect();
    let from_above = Vec3::new(0.0, -1.0, -1.0);
    let flat = normal_mapped(None, from_above, Integrator::Whitted, |_| {}).0.x;
    let tilted = normal_mapped_with(&second, Some(right), from_above, Integrator::Whitted, up_the_quad).0.x;
    assert!(tilted > 1.3 * flat, "second coordinates: flat {flat}, tilted up {tilted}");
    // The eye light faces the quad: any tilt darkens it.
    let flat = normal_mapped(None, Vec3::Z, Integrator::EyeLight, |_| {}).0.x;
    let tilted = normal_mapped(Some(right), Vec3::Z, Integrator::EyeLight, |_| {}).0.x;
    assert!(tilted < 0.9 * flat, "eye light: flat {flat}, tilted {tilted}");
}

#[test]
fn bad_tangent_frames_shade_with_the_unmapped_normal_and_never_a_nan() {
    let right = Vec3::new(0.6, 0.0, 0.8);
    let light = Vec3::new(-1.0, 0.0, -1.0);
    type Spoil = fn(&mut Mesh);
    let spoilers: [(&str, Spoil); 4] = [
        ("zero tangents", |m| m.tangents = vec![glam::Vec4::ZERO; 4]),
        ("tangents along the normal", |m| m.tangents = vec![glam::Vec4::new(0.0, 0.0, 1.0, 1.0); 4]),
        ("degenerate texture coordinates", |m| m.uvs = vec![Vec2::splat(0.5); 4]),
        ("no texture coordinates", |m| m.uvs.clear()),
    ];
    for integrator in Integrator::ALL {
        let flat = normal_mapped(None, light, integrator, |_| {}).0;
        for (what, spoil) in spoilers {
            let (centre, finite) = normal_mapped(Some(right), light, integrator, spoil);
            assert!(finite, "{integrator:?}, {what}: a pixel is not finite");
            assert!((centre - flat).abs().max_element() < 1e-4, "{integrator:?}, {what}: {centre}, unmapped {flat}");
        }
        // Zero-length vertex normals shade with the triangle's normal.
        let (centre, finite) = normal_mapped(Some(right), light, integrator, |m| m.normals = vec![Vec3::ZERO; 4]);
        assert!(finite && centre.x > 0.0, "{integrator:?}, zero normals: {centre}");
    }
}

#[test]
fn normals_mapped_away_from_the_viewer_shade_with_the_unmapped_normal() {
    // The quad turned 70° about x, its top away from the camera, lit from the camera's side;
    // the map tilts the normal 40° up the quad: 110° from the direction to the camera, where
    // it would shade the point black.
    let (s, c) = 70f32.to_radians().sin_cos();
    let turned = |m: &mut Mesh| m.positions.iter_mut().for_each(|p| *p = Vec3::new(p.x, p.y * c, -p.y * s));
    let up = Vec3::new(0.0, 40f32.to_radians().sin(), 40f32.to_radians().cos());
    for integrator in Integrator::ALL {
        let flat = normal_mapped(None, -Vec3::Z, integrator, turned).0;
        let (centre, finite) = normal_mapped(Some(up), -Vec3::Z, integrator, turned);
        assert!(finite && flat.x > 0.0, "{integrator:?}: {flat}");
        assert!((centre - flat).abs().max_element() < 1e-4, "{integrator:?}: {centre}, unmapped {flat}");
    }
}

/// A 1 × 1 data texture of `value`.
fn texel(scene: &mut Scene, value: Vec3) -> ParamValue {
    ParamValue::Texture(Some(scene.add_texture(Texture::Image(Image::new(1, 1, vec![value]).unwrap().into())).unwrap()))
}

#[test]
fn an_emissive_texture_colours_the_emission_seen_and_the_light_cast() {
    // Seen directly: a black quad emitting white through a red | green texture.
    let mut scene = Scene::new();
    let texture = ParamValue::Texture(Some(scene.add_texture(Texture::Image(Image::new(2, 1, vec![Vec3::X, Vec3::Y]).unwrap().into())).unwrap()));
    let glow = shader(&mut scene, "PhysicallyBased", &[("base_color", ParamValue::Color(Vec3::ZERO)), ("emissive", ParamValue::Color(Vec3::splat(2.0))), ("emissive_texture", texture), ("emissive_filter", ParamValue::Float(9728.0))]);
    common::place(&mut scene, quad(), glow);
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, Integrator::Path, 16, 16, 1);
    assert_eq!((film.pixel(4, 8), film.pixel(12, 8)), (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)), "factor × texel");

    // Cast on a floor: an emitter of 4 through a texture of 0.25 lights as one of 1 untextured
    // (light sampling and hits both read the texture, and weigh each other by the factor).
    let floor_under = |emissive: f32, texture: Option<f32>| {
        let mut scene = Scene::new();
        let mut params = vec![("base_color", ParamValue::Color(Vec3::ZERO)), ("emissive", ParamValue::Color(Vec3::splat(emissive)))];
        if let Some(t) = texture {
            params.push(("emissive_texture", texel(&mut scene, Vec3::splat(t))));
        }
        let glow = shader(&mut scene, "PhysicallyBased", &params);
        // The emitter 1.5 above the floor, facing down.
        let mut light = quad();
        light.positions.iter_mut().for_each(|p| *p = Vec3::new(p.x * 0.5, 1.5, p.y * 0.5));
        common::place(&mut scene, light, glow);
        let matte = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::ONE))]);
        let mut floor = quad();
        floor.positions.iter_mut().for_each(|p| *p = Vec3::new(p.x * 4.0, 0.0, -p.y * 4.0));
        common::place(&mut scene, floor, matte);
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 30.0).unwrap()).unwrap();
        let (film, _) = render_with(&scene, Integrator::Path, 24, 24, 64);
        let lit: Vec<Vec3> = (16..24).flat_map(|y| (4..20).map(move |x| (x, y))).map(|(x, y)| film.pixel(x, y)).collect();
        lit.iter().sum::<Vec3>().x / lit.len() as f32
    };
    let (plain, textured) = (floor_under(1.0, None), floor_under(4.0, Some(0.25)));
    assert!(plain > 0.01 && (textured / plain - 1.0).abs() < 0.05, "untextured {plain}, textured {textured}");
}

#[test]
fn an_occlusion_texture_darkens_the_eye_light_only() {
    let render = |occlusion: Option<(f32, f32)>, integrator: Integrator| {
        let mut scene = Scene::new();
        let mut params = vec![("metallic", ParamValue::Float(0.0))];
        if let Some((red, strength)) = occlusion {
            params.push(("occlusion_texture", texel(&mut scene, Vec3::new(red, 1.0, 1.0))));
            params.push(("occlusion_strength", ParamValue::Float(strength)));
        }
        let pbr = shader(&mut scene, "PhysicallyBased", &params);
        common::place(&mut scene, quad(), pbr);
        scene.add_light(common::point_light()).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
        render_with(&scene, integrator, 8, 8, 1).0.pixel(4, 4).x
    };
    let open = render(None, Integrator::EyeLight);
    assert!((render(Some((0.25, 1.0)), Integrator::EyeLight) / open - 0.25).abs() < 1e-4);
    // glTF: 1 + strength × (occlusion − 1).
    assert!((render(Some((0.25, 0.5)), Integrator::EyeLight) / open - 0.625).abs() < 1e-4);
    for integrator in [Integrator::Whitted, Integrator::Path] {
        assert_eq!(render(Some((0.25, 1.0)), integrator), render(None, integrator), "{integrator:?} finds occlusion itself");
    }
}

/// [`quad`] moved by `offset`.
fn quad_at(offset: Vec3) -> Mesh {
    let mut mesh = quad();
    mesh.positions.iter_mut().for_each(|p| *p += offset);
    mesh
}

/// A physically based white matte shader whose base colour texture is cut out on its left half
/// (alpha 0 there, 1 on the right), with `params`.
fn cut_out(scene: &mut Scene, params: &[(&str, ParamValue)]) -> raystage_scene::ShaderId {
    let image = Image::new(2, 1, vec![Vec3::ONE; 2]).unwrap().with_alpha(vec![0.0, 1.0]).unwrap();
    let texture = ParamValue::Texture(Some(scene.add_texture(Texture::Image(image.into())).unwrap()));
    let mut all = vec![("metallic", ParamValue::Float(0.0)), ("base_color_texture", texture), ("base_color_filter", ParamValue::Float(9728.0))];
    all.extend_from_slice(params);
    shader(scene, "PhysicallyBased", &all)
}

/// A red matte quad at z = 0, seen from +z, and in front of it (at z = 1) the quad of
/// [`cut_out`] with `params`: the centre row of the image.
fn in_front_of_red(params: &[(&str, ParamValue)], integrator: Integrator, spp: u32) -> Vec<Vec3> {
    let mut scene = Scene::new();
    let red = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::X))]);
    common::place(&mut scene, quad(), red);
    let front = cut_out(&mut scene, params);
    common::place(&mut scene, quad_at(Vec3::Z), front);
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, integrator, 16, 16, spp);
    (0..16).map(|x| film.pixel(x, 8)).collect()
}

#[test]
fn alpha_masks_cut_out_what_camera_rays_see() {
    let mask = [("alpha_mode", ParamValue::Float(1.0))];
    for integrator in [Integrator::EyeLight, Integrator::Whitted, Integrator::Path] {
        let row = in_front_of_red(&mask, integrator, 1);
        // Left: through the cut-out, the red quad; right: the white front quad.
        // (The red quad reflects red alone, whatever lights it.)
        let (left, right) = (row[4], row[12]);
        assert!(left.x > 0.0 && left.y == 0.0 && left.z == 0.0, "{integrator:?}: the red quad behind the cut-out: {left}");
        assert!(right.y > 0.0 && right.z > 0.0, "{integrator:?}: the white quad in front: {right}");
        // Opaque (the default), the same texture's alpha is ignored.
        let opaque = in_front_of_red(&[], integrator, 1)[4];
        assert!(opaque.y > 0.0 && opaque.z > 0.0, "{integrator:?}: opaque: {opaque}");
    }
    // A cut-off of 0 keeps all; opacity scales the texture's alpha.
    let kept = in_front_of_red(&[mask[0], ("alpha_cutoff", ParamValue::Float(0.0))], Integrator::EyeLight, 1)[4];
    assert!(kept.y > 0.0, "{kept}");
    let faint = in_front_of_red(&[mask[0], ("opacity", ParamValue::Float(0.4))], Integrator::EyeLight, 1)[12];
    assert!(faint.y == 0.0 && faint.x > 0.0, "coverage 0.4 is cut at 0.5: {faint}");
}

#[test]
fn blended_surfaces_let_through_in_proportion_to_their_transparency() {
    let blend = [("alpha_mode", ParamValue::Float(2.0)), ("opacity", ParamValue::Float(0.5))];
    let row = in_front_of_red(&blend, Integrator::EyeLight, 256);
    let opaque = in_front_of_red(&[], Integrator::EyeLight, 1)[12];
    // The right half: half the white quad, half the red one behind (in red, both).
    let right = row[12];
    assert!((right.y / opaque.y - 0.5).abs() < 0.08, "half white: {right}, opaque {opaque}");
    // The left half is cut out (coverage 0): red alone.
    assert_eq!(row[4].y, 0.0);
}

#[test]
fn cut_out_and_single_sided_surfaces_cast_no_shadow_where_they_are_not() {
    // A red quad at z = 0 lit from (+x, +z) through the quad of `cut_out` at z = 2, x = 1…3
    // (facing +z, unless flipped), out of the camera's view: its cut-out half lets the light onto
    // the left half of the red quad, its opaque half shades the right half.
    let shadowed = |params: &[(&str, ParamValue)], flip: bool, integrator: Integrator| {
        let mut scene = Scene::new();
        let red = shader(&mut scene, "Diffuse", &[("diffuse", ParamValue::Color(Vec3::X))]);
        common::place(&mut scene, quad(), red);
        let blocker = cut_out(&mut scene, params);
        let mut mesh = quad_at(Vec3::new(2.0, 0.0, 2.0));
        if flip {
            // Wound the other way: its front faces the red quad.
            mesh.indices.iter_mut().for_each(|t| t.swap(1, 2));
        }
        common::place(&mut scene, mesh, blocker);
        scene.add_light(Light::Directional { direction: Vec3::new(-1.0, 0.0, -1.0), intensity: Vec3::ONE }).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
        let (film, _) = render_with(&scene, integrator, 16, 16, 4);
        (film.pixel(4, 8).x, film.pixel(12, 8).x)
    };
    let lit = std::f32::consts::FRAC_1_SQRT_2 * std::f32::consts::FRAC_1_PI;
    for integrator in [Integrator::Whitted, Integrator::Path] {
        let (left, right) = shadowed(&[("alpha_mode", ParamValue::Float(1.0))], false, integrator);
        assert!((left / lit - 1.0).abs() < 0.02 && right == 0.0, "{integrator:?}: masked: lit {left}, shadowed {right}");
        let (left, right) = shadowed(&[], false, integrator);
        assert!(left == 0.0 && right == 0.0, "{integrator:?}: opaque: {left} {right}");
        // Single-sided and met from behind by the shadow rays (which run from the red quad
        // towards the light): not there at all.
        let (left, right) = shadowed(&[("double_sided", ParamValue::Float(0.0))], false, integrator);
        assert!((left / lit - 1.0).abs() < 0.02 && (right / lit - 1.0).abs() < 0.02, "{integrator:?}: single-sided, from behind: {left} {right}");
        let (left, right) = shadowed(&[("double_sided", ParamValue::Float(0.0))], true, integrator);
        assert!(left == 0.0 && right == 0.0, "{integrator:?}: single-sided, from the front: {left} {right}");
    }
}

#[test]
fn single_sided_surfaces_are_invisible_from_behind() {
    let seen = |double_sided: f32, eye_z: f32| {
        let mut scene = Scene::new();
        let pbr = shader(&mut scene, "PhysicallyBased", &[("metallic", ParamValue::Float(0.0)), ("double_sided", ParamValue::Float(double_sided))]);
        common::place(&mut scene, quad(), pbr);
        scene.set_background(Some(raystage_scene::Background::Color(Vec3::new(0.0, 0.0, 1.0)))).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, eye_z), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
        render_with(&scene, Integrator::EyeLight, 8, 8, 1).0.pixel(4, 4)
    };
    assert!(seen(0.0, 4.0).x > 0.5, "single-sided, from the front");
    assert_eq!(seen(0.0, -4.0), Vec3::new(0.0, 0.0, 1.0), "single-sided, from behind: the background");
    assert!(seen(1.0, -4.0).x > 0.5, "double-sided, from behind");
}

/// A floor 400 units square, seen from 1 unit above it towards the horizon, whose physically
/// based matte shader's base colour is `texture` repeated 200 times across it (a 64-texel image
/// thus shows 32 texels per unit of floor), lit by a directional light from above: the rows
/// of a 48 × 32 image rendered by `integrator` at one sample per pixel that see the far floor
/// (the top of the image is the horizon).
fn far_floor(texture: Image, integrator: Integrator) -> Vec<Vec<Vec3>> {
    let mut scene = Scene::new();
    let texture = scene.add_texture(Texture::Image(texture.into())).unwrap();
    let matte = [("metallic", ParamValue::Float(0.0)), ("specular", ParamValue::Float(0.0)), ("base_color_texture", ParamValue::Texture(Some(texture)))];
    let pbr = shader(&mut scene, "PhysicallyBased", &matte);
    let corners = [(-200.0, -200.0), (200.0, -200.0), (200.0, 200.0), (-200.0, 200.0)];
    let mut floor = Mesh::new(corners.iter().map(|&(x, z)| Vec3::new(x, 0.0, z)).collect(), vec![[0, 3, 2], [0, 2, 1]]);
    floor.uvs = corners.iter().map(|&(x, z)| Vec2::new(x + 200.0, z + 200.0) * 0.5).collect();
    common::place(&mut scene, floor, pbr);
    scene.add_light(Light::Directional { direction: Vec3::new(0.3, -1.0, 0.2), intensity: Vec3::ONE }).unwrap();
    // Looking down 15° across the floor: the horizon at the top edge.
    scene.set_camera(Camera::look_at(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0 - (15f32).to_radians().tan(), -1.0), Vec3::Y, 30.0).unwrap()).unwrap();
    let (film, _) = render_with(&scene, integrator, 48, 32, 1);
    // Rows 2 to 10: floor 5 to 20 units away, where a pixel spans 3 to 30 texels.
    (2..10).map(|y| (0..48).map(|x| film.pixel(x, y)).collect()).collect()
}

/// A texture seen from afar averages its texels, as its mip pyramid has them, instead of
/// showing whichever texel each pixel's one ray happens to hit: a floor of alternating black
/// and white texels looks as a floor of flat 50 % grey does, in the preview and in the
/// integrators that resolve hits in full. (Unfiltered, each pixel is black or white: the far
/// floor's pixels differ from grey by up to 100 %.)
#[test]
fn a_fine_texture_far_away_averages_instead_of_aliasing() {
    let texels = (0..64 * 64).map(|i| if (i % 64 + i / 64) % 2 == 0 { Vec3::ZERO } else { Vec3::ONE }).collect();
    let checker = Image::new(64, 64, texels).unwrap();
    let grey = Image::new(1, 1, vec![Vec3::splat(0.5)]).unwrap();
    for integrator in [Integrator::EyeLight, Integrator::Whitted, Integrator::Path] {
        let (seen, expected) = (far_floor(checker.clone(), integrator), far_floor(grey.clone(), integrator));
        let mut worst: f32 = 0.0;
        for (row, grey_row) in seen.iter().zip(&expected) {
            for (pixel, grey) in row.iter().zip(grey_row) {
                worst = worst.max(((pixel.x - grey.x) / grey.x).abs());
            }
        }
        // Nothing but the floor and the sun: the path tracer's one sample is as exact.
        assert!(worst < 0.1, "{integrator:?}: the far floor differs from grey by up to {:.0} %", 100.0 * worst);
    }
}

/// A 2 × 1 texture, black on its left half and white on its right (alpha too), to be sampled
/// nearest on the quad of [`quad`].
fn black_then_white(scene: &mut Scene) -> ParamValue {
    ParamValue::Texture(Some(scene.add_texture(Texture::Image(Image::new(2, 1, vec![Vec3::ZERO, Vec3::ONE]).unwrap().with_alpha(vec![0.0, 1.0]).unwrap().into())).unwrap()))
}

/// glTF's and OpenGL's `NEAREST` magnification.
const NEAREST: ParamValue = ParamValue::Float(9728.0);

/// A black quad that reflects nothing itself, under a clear coat whose texture is black on the
/// left half and white on the right, lit by a point light at the camera: the coat's highlight,
/// colourless, on the right half only, in every integrator that lights through the BSDF.
#[test]
fn a_clearcoat_texture_lays_the_coat_only_where_it_is_white() {
    for integrator in [Integrator::Whitted, Integrator::Distribution, Integrator::Path] {
        let mut scene = Scene::new();
        let mask = black_then_white(&mut scene);
        let paint = shader(
            &mut scene,
            "PhysicallyBased",
            &[
                ("base_color", ParamValue::Color(Vec3::ZERO)),
                ("metallic", ParamValue::Float(0.0)),
                ("specular", ParamValue::Float(0.0)),
                ("clearcoat", ParamValue::Float(1.0)),
                ("clearcoat_roughness", ParamValue::Float(0.3)),
                ("clearcoat_texture", mask),
                ("clearcoat_filter", NEAREST),
            ],
        );
        common::place(&mut scene, quad(), paint);
        scene.add_light(Light::Point { position: Vec3::new(0.0, 0.0, 4.0), intensity: Vec3::splat(10.0) }).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
        let (film, stats) = render_with(&scene, integrator, 16, 16, 4);
        // Pixels 6 and 9 lie a little left and right of the centre, where the light is mirrored.
        let (left, right) = (film.pixel(6, 8), film.pixel(9, 8));
        assert!(left.max_element() < 1e-4, "{integrator:?}: no coat on the left: {left}");
        assert!(right.min_element() > 0.1 && (right.x - right.z).abs() < 1e-3 * right.x, "{integrator:?}: the coat's highlight on the right: {right}");
        assert!(film.pixels().iter().all(|p| p.is_finite()) && stats.non_finite == 0, "{integrator:?}");
    }
}

/// A transmission texture, black on the left and white on the right, on a white, smooth, thin
/// wall in front of a red backdrop: the red shows through on the right only, and the left is the
/// wall's lit white. With a transmission factor of 0 the texture cannot make it transmit: the
/// frame traces no refraction rays at all.
#[test]
fn a_transmission_texture_lets_light_through_only_where_it_is_white() {
    let render = |factor: f32| {
        let mut scene = Scene::new();
        let mask = black_then_white(&mut scene);
        let wall = shader(
            &mut scene,
            "PhysicallyBased",
            &[
                ("metallic", ParamValue::Float(0.0)),
                ("roughness", ParamValue::Float(0.0)),
                ("specular", ParamValue::Float(0.0)),
                ("transmission", ParamValue::Float(factor)),
                ("transmission_texture", mask),
                ("transmission_filter", NEAREST),
            ],
        );
        common::place(&mut scene, quad(), wall);
        let red = shader(&mut scene, "Constant", &[("color", ParamValue::Color(Vec3::X))]);
        common::place(&mut scene, quad_at(Vec3::new(0.0, 0.0, -1.0)), red);
        scene.add_light(Light::Directional { direction: -Vec3::Z, intensity: Vec3::ONE }).unwrap();
        scene.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 20.0).unwrap()).unwrap();
        let (film, stats) = render_with(&scene, Integrator::Whitted, 16, 16, 1);
        (film.pixel(4, 8), film.pixel(12, 8), stats)
    };
    let lit_white = std::f32::consts::FRAC_1_PI;
    let (left, right, stats) = render(1.0);
    assert!((left - Vec3::splat(lit_white)).abs().max_element() < 1e-3, "opaque white on the left: {left}");
    assert!((right - Vec3::X).abs().max_element() < 1e-3, "the red backdrop through the right: {right}");
    assert!(stats.effects.refraction && stats.rays.refraction > 0);
    let (left, right, stats) = render(0.0);
    assert!((left - Vec3::splat(lit_white)).abs().max_element() < 1e-3 && (right - left).abs().max_element() < 1e-6, "opaque everywhere: {left} {right}");
    assert!(!stats.effects.refraction && stats.rays.refraction == 0, "{:?}", stats.effects);
}
