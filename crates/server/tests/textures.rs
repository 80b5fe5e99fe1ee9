//! Textures end to end, in-process: images written in the test (PNG, WebP, Radiance HDR) and
//! procedural textures made with JSON are uploaded, bound to shaders and environment lights,
//! rendered, replaced and deleted; bad bodies and references are refused and change nothing.

mod common;

use axum::body::Body;
use axum::http::StatusCode;
use common::*;
use serde_json::{Value, json};

/// `image` encoded as a file of `format`.
fn file(image: image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).unwrap();
    bytes.into_inner()
}

/// An 8 × 8 PNG: left half red, right half blue.
fn red_blue_png() -> Vec<u8> {
    let image = image::RgbImage::from_fn(8, 8, |x, _| if x < 4 { image::Rgb([255, 0, 0]) } else { image::Rgb([0, 0, 255]) });
    file(image.into(), image::ImageFormat::Png)
}

/// A Radiance HDR file of one linear colour.
fn hdr(colour: [f32; 3]) -> Vec<u8> {
    file(image::Rgb32FImage::from_pixel(16, 8, image::Rgb(colour)).into(), image::ImageFormat::Hdr)
}

/// Sends `body` with `content_type`; returns the status and the JSON body.
async fn upload(app: &axum::Router, method: &str, uri: &str, body: impl Into<Body>, content_type: &str) -> (StatusCode, Value) {
    let (status, response_type, bytes) = send(app, method, uri, body.into(), &[("content-type", content_type)]).await;
    assert!(response_type.starts_with("application/json"), "{method} {uri}: {status} with content type `{response_type}`");
    (status, serde_json::from_slice(&bytes).unwrap())
}

/// A 2 × 2 quad facing +z at the origin, texture coordinates (0, 0) at its top left.
fn quad() -> Value {
    json!({
        "positions": [[-1, 1, 0], [1, 1, 0], [1, -1, 0], [-1, -1, 0]],
        "indices": [[0, 3, 2], [0, 2, 1]],
        "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]]
    })
}

/// The camera of the quad scenes: the quad spans columns 5 to 27 of a 32 × 32 frame.
fn camera() -> Value {
    json!({ "eye": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_degrees": 40 })
}

/// A `Diffuse` shader of colour `diffuse` times texture `t`, on the quad before the camera in
/// scene `s`; returns the shader as created.
async fn textured_quad(app: &axum::Router, s: u64, diffuse: Value, t: u64) -> Value {
    let params = json!({ "diffuse": diffuse, "diffuse_texture": { "texture": t } });
    let shader = ok(app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": "Diffuse", "params": params }), StatusCode::CREATED).await;
    let mut mesh = quad();
    mesh["shader"] = shader["id"].clone();
    let object = ok(app, "POST", &format!("/scenes/{s}/objects"), json!({ "mesh": mesh }), StatusCode::CREATED).await;
    ok(app, "POST", &format!("/scenes/{s}/instances"), json!({ "object": object["id"] }), StatusCode::CREATED).await;
    ok(app, "PUT", &format!("/scenes/{s}/camera"), camera(), StatusCode::OK).await;
    shader
}

const FRAME: &str = "frame.png?width=32&height=32&integrator=eyelight";

/// Whether an 8-bit pixel is `[r, g, b]` (each 0 or 1) at full strength: channels that should
/// be 1 above 245 (the eye light's cosine is just below 1 off-centre), the others 0.
fn is(pixel: image::Rgba<u8>, rgb: [u8; 3]) -> bool {
    pixel.0[..3].iter().zip(rgb).all(|(&c, on)| if on == 1 { c > 245 } else { c == 0 })
}

#[tokio::test]
async fn a_png_texture_colours_a_quad_until_it_is_deleted() {
    let app = app();
    let s = new_scene(&app).await;
    let (status, created) = upload(&app, "POST", &format!("/scenes/{s}/textures"), red_blue_png(), "image/png").await;
    assert_eq!(status, StatusCode::CREATED, "{created}");
    let t = created["id"].as_u64().unwrap();
    let info = ok(&app, "GET", &format!("/scenes/{s}/textures/{t}"), json!(null), StatusCode::OK).await;
    assert_eq!(info, json!({ "id": t, "kind": "image", "width": 8, "height": 8 }));

    let shader = textured_quad(&app, s, json!([1, 1, 1]), t).await;
    let shown = ok(&app, "GET", &format!("/scenes/{s}/shaders/{}", shader["id"]), json!(null), StatusCode::OK).await;
    assert_eq!(shown["params"]["diffuse_texture"], json!({ "texture": t }));

    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    let (left, right, outside) = (*image.get_pixel(10, 16), *image.get_pixel(22, 16), *image.get_pixel(1, 16));
    assert!(is(left, [1, 0, 0]), "the quad's left is red: {left:?}");
    assert!(is(right, [0, 0, 1]), "its right is blue: {right:?}");
    assert!(!is(outside, [1, 0, 0]) && !is(outside, [0, 0, 1]), "beside it the sky: {outside:?}");

    ok(&app, "DELETE", &format!("/scenes/{s}/textures/{t}"), json!(null), StatusCode::OK).await;
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}/textures"), json!(null), StatusCode::OK).await, json!([]));
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    let (left, right) = (*image.get_pixel(10, 16), *image.get_pixel(22, 16));
    assert!(is(left, [1, 1, 1]) && is(right, [1, 1, 1]), "without its texture the quad is white: {left:?} {right:?}");
}

#[tokio::test]
async fn a_webp_texture_is_read_as_its_png_is() {
    let app = app();
    let s = new_scene(&app).await;
    let png = image::load_from_memory(&red_blue_png()).unwrap();
    let (status, created) = upload(&app, "POST", &format!("/scenes/{s}/textures"), file(png, image::ImageFormat::WebP), "image/webp").await;
    assert_eq!(status, StatusCode::CREATED, "{created}");
    let t = created["id"].as_u64().unwrap();
    textured_quad(&app, s, json!([1, 1, 1]), t).await;
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    let (left, right) = (*image.get_pixel(10, 16), *image.get_pixel(22, 16));
    assert!(is(left, [1, 0, 0]) && is(right, [0, 0, 1]), "red, then blue: {left:?} {right:?}");
}

#[tokio::test]
async fn a_radiance_hdr_environment_map_is_seen_where_nothing_is_hit() {
    let app = app();
    let s = new_scene(&app).await;
    // Powers of two, which Radiance's shared exponent stores exactly.
    let (status, created) = upload(&app, "POST", &format!("/scenes/{s}/textures"), hdr([0.5, 0.25, 0.125]), "image/vnd.radiance").await;
    assert_eq!(status, StatusCode::CREATED, "{created}");
    let map = created["id"].as_u64().unwrap();
    let light = json!({ "class": "EnvironmentLight", "radiance": 1.6, "map": map });
    let l = ok(&app, "POST", &format!("/scenes/{s}/lights"), light, StatusCode::CREATED).await["id"].as_u64().unwrap();
    let shown = ok(&app, "GET", &format!("/scenes/{s}/lights/{l}"), json!(null), StatusCode::OK).await;
    assert_eq!(shown, json!({ "id": l, "class": "EnvironmentLight", "radiance": [1.6, 1.6, 1.6], "map": map, "rotate": 0.0 }));

    // The map scaled by the radiance: linear (0.8, 0.4, 0.2), sRGB (231, 170, 124).
    let near = |pixel: image::Rgba<u8>, srgb: [u8; 3]| pixel.0[..3].iter().zip(srgb).all(|(&c, e)| c.abs_diff(e) <= 2);
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=8&height=8&integrator=eyelight")).await;
    assert!(image.pixels().all(|p| near(*p, [231, 170, 124])), "{:?}", image.get_pixel(4, 4));

    // Replacing the texture changes the light that uses it.
    let (status, body) = upload(&app, "PUT", &format!("/scenes/{s}/textures/{map}"), hdr([0.125, 0.25, 0.5]), "application/octet-stream").await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=8&height=8&integrator=eyelight")).await;
    assert!(near(*image.get_pixel(4, 4), [124, 170, 231]), "{:?}", image.get_pixel(4, 4));

    // Without it, the light is the same radiance from everywhere (1.6: white in a PNG).
    ok(&app, "DELETE", &format!("/scenes/{s}/textures/{map}"), json!(null), StatusCode::OK).await;
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=8&height=8&integrator=eyelight")).await;
    assert_eq!(image.get_pixel(4, 4).0, [255, 255, 255, 255]);
}

#[tokio::test]
async fn a_checker_made_with_json_is_described_rendered_and_replaced() {
    let app = app();
    let s = new_scene(&app).await;
    let textures = format!("/scenes/{s}/textures");
    let created = ok(&app, "POST", &textures, json!({ "kind": "checker", "a": [1, 0, 0], "b": 0, "scale": 2 }), StatusCode::CREATED).await;
    let t = created["id"].as_u64().unwrap();
    let description = json!({ "id": t, "kind": "checker", "a": [1.0, 0.0, 0.0], "b": [0.0, 0.0, 0.0], "scale": 2.0 });
    assert_eq!(ok(&app, "GET", &format!("{textures}/{t}"), json!(null), StatusCode::OK).await, description);
    assert_eq!(ok(&app, "GET", &textures, json!(null), StatusCode::OK).await, json!([description]));
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["textures"], 1);

    textured_quad(&app, s, json!(1), t).await;
    let quad_pixels = |image: &image::RgbaImage| -> Vec<image::Rgba<u8>> { (8..25).flat_map(|y| (8..25).map(move |x| (x, y))).map(|(x, y)| *image.get_pixel(x, y)).collect() };
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    let pixels = quad_pixels(&image);
    assert!(pixels.iter().any(|&p| is(p, [1, 0, 0])) && pixels.iter().any(|&p| is(p, [0, 0, 0])), "red and black squares");
    assert!(pixels.iter().all(|&p| is(p, [1, 0, 0]) || p.0[..3] == [0, 0, 0]), "nothing else");

    // PUT replaces it (fields left out take their defaults); the shader follows.
    let updated = ok(&app, "PUT", &format!("{textures}/{t}"), json!({ "kind": "noise", "a": [0, 1, 0], "scale": 3 }), StatusCode::OK).await;
    assert!(updated["version"].as_u64() > created["version"].as_u64());
    let noise = json!({ "id": t, "kind": "noise", "a": [0.0, 1.0, 0.0], "b": [0.2, 0.2, 0.2], "scale": 3.0 });
    assert_eq!(ok(&app, "GET", &format!("{textures}/{t}"), json!(null), StatusCode::OK).await, noise);
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    assert!(quad_pixels(&image).iter().all(|p| p.0[0] < 240 && p.0[2] < 240), "no more red squares");
}

#[tokio::test]
async fn a_batch_makes_textures_and_uses_them_by_label_all_or_nothing() {
    let app = app();
    let s = new_scene(&app).await;
    let commands = format!("/scenes/{s}/commands");
    let mut mesh = quad();
    mesh["shader"] = json!("checked");
    let batch = json!({ "commands": [
        { "add_texture": { "label": "checks", "kind": "checker", "a": [0, 1, 0], "b": [0, 0, 1], "scale": 2 } },
        { "add_shader": { "label": "checked", "class": "Diffuse", "params": { "diffuse": 1, "diffuse_texture": { "texture": "checks" } } } },
        { "add_object": { "label": "quad", "mesh": mesh } },
        { "add_instance": { "object": "quad" } },
        { "add_texture": { "label": "sky", "kind": "noise" } },
        { "add_light": { "class": "EnvironmentLight", "radiance": 0.5, "map": "sky" } },
        { "set_camera": camera() }
    ] });
    let result = ok(&app, "POST", &commands, batch, StatusCode::OK).await;
    let ids: Vec<u64> = result["results"].as_array().unwrap().iter().filter_map(|r| r["id"].as_u64()).collect();
    let [checks, shader, _, _, sky, light] = ids[..] else { panic!("six resources made: {result}") };
    let shown = ok(&app, "GET", &format!("/scenes/{s}/shaders/{shader}"), json!(null), StatusCode::OK).await;
    assert_eq!(shown["params"]["diffuse_texture"], json!({ "texture": checks }));
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}/lights/{light}"), json!(null), StatusCode::OK).await["map"], sky);
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    assert!(is(*image.get_pixel(12, 12), [0, 1, 0]) || is(*image.get_pixel(12, 12), [0, 0, 1]), "{:?}", image.get_pixel(12, 12));

    let red = json!({ "commands": [{ "set_texture": { "id": checks, "texture": { "kind": "checker", "a": [1, 0, 0], "b": [1, 0, 0] } } }] });
    ok(&app, "POST", &commands, red, StatusCode::OK).await;
    let image = frame(&app, &format!("/scenes/{s}/{FRAME}")).await;
    assert!(is(*image.get_pixel(12, 12), [1, 0, 0]) && is(*image.get_pixel(20, 20), [1, 0, 0]), "set_texture recolours the quad");

    // A texture deleted earlier in the batch cannot be used later in it: nothing is applied.
    let before = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    let stale = json!({ "commands": [
        { "delete_texture": { "id": checks } },
        { "set_params": { "id": shader, "params": { "diffuse_texture": { "texture": checks } } } }
    ] });
    assert_eq!(fails(&app, "POST", &commands, stale, StatusCode::NOT_FOUND).await, "commands[1].set_params.params.diffuse_texture");
    let bad = json!({ "commands": [{ "add_texture": { "kind": "noise" } }, { "set_texture": { "id": sky, "texture": { "kind": "noise", "scale": -1 } } }] });
    assert_eq!(fails(&app, "POST", &commands, bad, StatusCode::UNPROCESSABLE_ENTITY).await, "commands[1].set_texture.texture.scale");
    let unlabelled = json!({ "commands": [{ "add_light": { "class": "EnvironmentLight", "map": "nowhere" } }] });
    assert_eq!(fails(&app, "POST", &commands, unlabelled, StatusCode::NOT_FOUND).await, "commands[0].add_light.map");
    let wrong_kind = json!({ "commands": [{ "add_shader": { "label": "s", "class": "Diffuse" } }, { "add_light": { "class": "EnvironmentLight", "map": "s" } }] });
    assert_eq!(fails(&app, "POST", &commands, wrong_kind, StatusCode::UNPROCESSABLE_ENTITY).await, "commands[1].add_light.map");
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await, before);
    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}/textures"), json!(null), StatusCode::OK).await.as_array().unwrap().len(), 2);
}

#[tokio::test]
async fn bad_textures_and_references_are_refused_naming_the_field_and_change_nothing() {
    let app = app();
    let s = new_scene(&app).await;
    let textures = format!("/scenes/{s}/textures");
    let t = ok(&app, "POST", &textures, json!({ "kind": "checker" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
    let shader = ok(&app, "POST", &format!("/scenes/{s}/shaders"), json!({ "class": "Diffuse" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
    let light = ok(&app, "POST", &format!("/scenes/{s}/lights"), json!({ "class": "EnvironmentLight" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
    let scene_before = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await;
    let textures_before = ok(&app, "GET", &textures, json!(null), StatusCode::OK).await;

    // Bad JSON descriptions, on POST and PUT alike.
    for uri in [textures.clone(), format!("{textures}/{t}")] {
        let method = if uri == textures { "POST" } else { "PUT" };
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "marble" }), StatusCode::BAD_REQUEST).await, "kind");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "image" }), StatusCode::BAD_REQUEST).await, "kind", "images come as files");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "checker", "scale": 0 }), StatusCode::UNPROCESSABLE_ENTITY).await, "scale");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "noise", "scale": -2 }), StatusCode::UNPROCESSABLE_ENTITY).await, "scale");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "noise", "scale": 1e39 }), StatusCode::UNPROCESSABLE_ENTITY).await, "scale");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "noise", "scale": "big" }), StatusCode::BAD_REQUEST).await, "scale");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "checker", "a": [1, "red", 0] }), StatusCode::BAD_REQUEST).await, "a");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "checker", "b": [0, -1, 0] }), StatusCode::UNPROCESSABLE_ENTITY).await, "b");
        assert_eq!(fails(&app, method, &uri, json!({ "kind": "checker", "colour": 1 }), StatusCode::BAD_REQUEST).await, "colour");
        let (status, error) = upload(&app, method, &uri, r#"{"kind": "checker", "a": [0, NaN, 0]}"#, "application/json").await;
        assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("a[1]")), "{error}");

        // Image bodies that are not images, and bodies of other types.
        for garbage in [b"definitely not a png".to_vec(), red_blue_png()[..40].to_vec()] {
            let (status, error) = upload(&app, method, &uri, garbage, "image/png").await;
            assert_eq!((status, error["error"]["code"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("unprocessable")), "{error}");
            assert!(error["error"]["message"].as_str().unwrap().starts_with("the image cannot be read"), "{error}");
        }
        for content_type in ["text/plain", "image/gif"] {
            let (status, error) = upload(&app, method, &uri, red_blue_png(), content_type).await;
            assert_eq!(status, StatusCode::UNSUPPORTED_MEDIA_TYPE, "{content_type}: {error}");
            assert_eq!((error["error"]["code"].as_str(), error["error"]["field"].as_str()), (Some("unsupported_media_type"), Some("content-type")));
        }
        // curl's `-d` sends its JSON as a form: taken as JSON, as every other route takes it.
        let (status, error) = upload(&app, method, &uri, r#"{"kind": "checker", "scale": 0}"#, "application/x-www-form-urlencoded").await;
        assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::UNPROCESSABLE_ENTITY, Some("scale")), "{error}");
    }

    // Unknown ids.
    for method in ["GET", "DELETE"] {
        assert_eq!(fails(&app, method, &format!("{textures}/99"), json!(null), StatusCode::NOT_FOUND).await, "id");
    }
    assert_eq!(fails(&app, "PUT", &format!("{textures}/99"), json!({ "kind": "noise" }), StatusCode::NOT_FOUND).await, "id");
    let (status, error) = upload(&app, "PUT", &format!("{textures}/99"), red_blue_png(), "image/png").await;
    assert_eq!((status, error["error"]["field"].as_str()), (StatusCode::NOT_FOUND, Some("id")), "{error}");
    assert_eq!(fails(&app, "GET", "/scenes/99/textures", json!(null), StatusCode::NOT_FOUND).await, "scene");
    let (status, _) = upload(&app, "POST", "/scenes/99/textures", red_blue_png(), "image/png").await;
    assert_eq!(status, StatusCode::NOT_FOUND);

    // Unknown textures in shader parameters and environment maps, and references of the wrong form.
    let missing = json!({ "class": "Diffuse", "params": { "diffuse_texture": { "texture": 99 } } });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/shaders"), missing, StatusCode::NOT_FOUND).await, "params.diffuse_texture");
    let missing = json!({ "params": { "diffuse_texture": { "texture": 99 } } });
    assert_eq!(fails(&app, "PATCH", &format!("/scenes/{s}/shaders/{shader}"), missing, StatusCode::NOT_FOUND).await, "params.diffuse_texture");
    let bare = json!({ "params": { "diffuse_texture": t } });
    assert_eq!(fails(&app, "PATCH", &format!("/scenes/{s}/shaders/{shader}"), bare, StatusCode::UNPROCESSABLE_ENTITY).await, "params.diffuse_texture");
    let on_colour = json!({ "params": { "diffuse": { "texture": t } } });
    assert_eq!(fails(&app, "PATCH", &format!("/scenes/{s}/shaders/{shader}"), on_colour, StatusCode::UNPROCESSABLE_ENTITY).await, "params.diffuse");
    let unknown_map = json!({ "class": "EnvironmentLight", "map": 99 });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/lights"), unknown_map.clone(), StatusCode::NOT_FOUND).await, "map");
    assert_eq!(fails(&app, "PUT", &format!("/scenes/{s}/lights/{light}"), unknown_map, StatusCode::NOT_FOUND).await, "map");
    let point = json!({ "class": "PointLight", "map": t });
    assert_eq!(fails(&app, "POST", &format!("/scenes/{s}/lights"), point, StatusCode::UNPROCESSABLE_ENTITY).await, "map");

    assert_eq!(ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await, scene_before);
    assert_eq!(ok(&app, "GET", &textures, json!(null), StatusCode::OK).await, textures_before);
    let shown = ok(&app, "GET", &format!("/scenes/{s}/shaders/{shader}"), json!(null), StatusCode::OK).await;
    assert_eq!(shown["params"]["diffuse_texture"], json!({ "texture": null }));
}

#[tokio::test]
async fn mangled_image_files_are_decoded_or_refused_never_a_server_error() {
    let app = app();
    let s = new_scene(&app).await;
    let t = ok(&app, "POST", &format!("/scenes/{s}/textures"), json!({ "kind": "noise" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
    let webp = file(image::load_from_memory(&red_blue_png()).unwrap(), image::ImageFormat::WebP);
    for (good, content_type) in [(red_blue_png(), "image/png"), (webp, "image/webp"), (hdr([0.5, 2.0, 8.0]), "image/vnd.radiance")] {
        for at in 0..good.len() {
            let mut bad = good.clone();
            bad[at] ^= 0xa5;
            let (status, body) = upload(&app, "PUT", &format!("/scenes/{s}/textures/{t}"), bad, content_type).await;
            // A header mangled into a larger size is refused before anything is decoded (413).
            let refused = [StatusCode::UNPROCESSABLE_ENTITY, StatusCode::PAYLOAD_TOO_LARGE];
            assert!(status == StatusCode::OK || refused.contains(&status), "{content_type} byte {at}: {status} {body}");
        }
    }
    let image = frame(&app, &format!("/scenes/{s}/frame.png?width=8&height=8&integrator=eyelight")).await;
    assert_eq!(image.dimensions(), (8, 8), "the scene still renders");
}
