// wrapper.cpp: checks raystage/rt.hpp, the C++ wrapper. First the four faults of the example
// header it replaced: each FrameBuffer gets its own frames, destroying a buffer leaves
// the attached one attached, an exception thrown inside Object::define leaves no error behind,
// and a kept Instance stays in the scene (dropping one does not compile: discarded.cpp). Then
// ownership across moves, Objects dying before their Instances and handles outliving their
// Context, errors as raystage::Error, and the GL calls the wrapper checks.
//
// Prints each failed check and exits 1 if any failed (run by crates/capi/tests/examples.rs).
#include "check.hpp"

#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

const std::size_t W = 32, H = 16;

/// A square of half-size `half` around the origin in the plane z = 0, facing +z.
void square(float half) {
    raystage::Primitive quad(RT_QUADS);
    rtVertex3f(-half, -half, 0);
    rtVertex3f(half, -half, 0);
    rtVertex3f(half, half, 0);
    rtVertex3f(-half, half, 0);
}

/// An object of one square of `paint`.
raystage::Object square_object(const raystage::Shader &paint, float half) {
    raystage::Object object;
    object.define([&] {
        paint.bind();
        square(half);
    });
    return object;
}

/// The camera the checks use: at z = 6, looking at the origin.
void camera() { raystage::look_at(0, 0, 6, 0, 0, 0, 0, 1, 0); }

/// Fault 2: swap rendered into the FrameBuffer made last, whichever was swapped.
void each_buffer_gets_its_own_frames() {
    raystage::Context context;
    camera();
    raystage::Shader paint("Constant");
    paint.set("color", 1, 0, 0);
    raystage::Object wall = square_object(paint, 20);
    raystage::Instance instance = wall.instantiate();
    raystage::FrameBuffer a(W, H), b(W, H);
    a.swap();
    paint.set("color", 0, 0, 1);
    b.swap();
    CHECK(all_pixels(a, 255, 0, 0), "a's frame is not red: it went elsewhere");
    CHECK(all_pixels(b, 0, 0, 255), "b's frame is not blue");
    paint.set("color", 0, 1, 0);
    a.swap();
    CHECK(all_pixels(a, 0, 255, 0), "a's second frame is not green");
    CHECK(all_pixels(b, 0, 0, 255), "a's second frame changed b");
    // rtWritePNG writes the context's last frame, which is a's now, not b's.
    throws("b.write_png after a.swap", RT_INVALID_OPERATION, "not rendered into this frame buffer",
           [&] { b.write_png("b.png"); });
    a.write_png("a.png");
    no_error("a.write_png");
}

/// Fault 3: destroying any FrameBuffer detached the attached one.
void destroying_a_buffer_keeps_the_attached_one() {
    raystage::Context context;
    camera();
    raystage::clear_color(1, 1, 0);
    raystage::FrameBuffer a(W, H);
    a.swap();
    { raystage::FrameBuffer unused(8, 8); }
    CHECK(a.attached(), "a is no longer attached");
    std::vector<RTint> viewport = raystage::get_integers(RT_VIEWPORT);
    CHECK(viewport == (std::vector<RTint>{0, 0, RTint(W), RTint(H)}), "the viewport is %d x %d, not a's", viewport[2],
          viewport[3]);
    rtSwapBuffers(); // through the C ABI: a is still where frames go
    no_error("rtSwapBuffers after another buffer died");
    {
        raystage::FrameBuffer brief(8, 8);
        brief.swap();
        CHECK(brief.attached() && !a.attached(), "brief took the attachment");
    }
    // The attached one detached itself: raystage must not write its freed memory.
    CHECK(raystage::get_integers(RT_VIEWPORT)[2] == 0, "a destroyed attached buffer is still attached");
    rtSwapBuffers();
    error_is("rtSwapBuffers with the attached buffer destroyed", RT_INVALID_OPERATION, "no frame buffer");
    a.swap();
    CHECK(all_pixels(a, 255, 255, 0), "a attaches itself again");
}

/// Fault 4: an exception inside define left rtEndObject's error pending for the next call.
void an_exception_in_define_leaves_a_clean_context() {
    raystage::Context context;
    camera();
    raystage::clear_color(0, 0, 0);
    raystage::FrameBuffer frame(W, H);
    raystage::Shader paint("Constant");
    paint.set("color", 1, 1, 1);
    raystage::Object object;

    // Thrown inside a primitive, before it made a triangle.
    try {
        object.define([&] {
            raystage::Primitive triangles(RT_TRIANGLES);
            rtVertex3f(0, 0, 0);
            throw std::runtime_error("the model file ended");
        });
        CHECK(false, "define swallowed the exception");
    } catch (const std::runtime_error &e) {
        CHECK(std::string(e.what()) == "the model file ended", "define threw something else: %s", e.what());
    }
    no_error("after an exception inside a primitive");
    frame.swap(); // threw RT_INVALID_OPERATION (an object without triangles) with the old header
    no_error("a frame after the exception");

    // Thrown with a primitive left open by the C calls: define ends it.
    try {
        object.define([&] {
            rtBegin(RT_QUADS);
            rtVertex3f(0, 0, 0);
            throw 42;
        });
    } catch (int) {
    }
    no_error("after an exception with rtBegin open");
    raystage::Object other = square_object(paint, 1); // rtNewObject is refused inside a definition

    // A raystage::Error from inside define reaches the caller as it was thrown.
    throws("an invalid primitive inside define", RT_INVALID_ENUM, "rtBegin",
           [&] { object.define([&] { raystage::Primitive points(12345); }); });

    // The context is out of the definition: the object can be defined and placed again. Thrown
    // after a triangle, the object keeps the triangles issued before (rtEndObject's rule).
    try {
        object.define([&] {
            paint.bind();
            square(20);
            throw std::runtime_error("later");
        });
    } catch (const std::runtime_error &) {
    }
    no_error("after an exception that followed a square");
    raystage::Instance instance = object.instantiate();
    frame.swap();
    CHECK(all_pixels(frame, 255, 255, 255), "the square issued before the exception is not in the object");
}

/// Fault 1, at run time: a kept Instance stays in the scene until it dies.
void instances_live_as_long_as_their_handles() {
    raystage::Context context;
    camera();
    raystage::clear_color(0, 0, 0);
    raystage::FrameBuffer frame(W, H);
    raystage::Shader paint("Constant");
    paint.set("color", 0, 1, 0);
    raystage::Object wall = square_object(paint, 20);
    {
        raystage::Instance kept = wall.instantiate();
        std::optional<raystage::Hit> hit = frame.pick(W / 2, H / 2);
        CHECK(hit && hit->instance == kept.id() && hit->object == wall.id(), "the kept instance is not picked");
        raystage::Instance moved = std::move(kept);
        CHECK(kept.id() == 0 && moved.id() != 0, "a moved instance keeps its id in the source");
        frame.swap();
        CHECK(all_pixels(frame, 0, 255, 0), "the moved instance left the scene");
    }
    CHECK(!frame.pick(W / 2, H / 2), "a destroyed instance is still in the scene");
    no_error("instances destroyed");

    // An Object dying first removes its instances; theirs must not be removed again.
    {
        std::optional<raystage::Object> doomed = square_object(paint, 1);
        raystage::Instance orphan = doomed->instantiate();
        doomed.reset();
    }
    no_error("an instance whose object died first");
}

/// Moves transfer ownership; a move-assignment deletes what the target owned.
void moves_transfer_ownership() {
    raystage::Context context;
    camera();
    raystage::FrameBuffer frame(W, H);
    // The preview shows the default shader's grey as it is (RT_AUTO would light the unlit
    // scene by the sky, which tints it).
    raystage::render_mode(RT_EYELIGHT);
    raystage::Shader red("Constant"), blue("Constant");
    red.set("color", 1, 0, 0);
    blue.set("color", 0, 0, 1);
    raystage::Object wall = square_object(red, 20);
    raystage::Instance instance = wall.instantiate();

    raystage::Shader owner = std::move(red);
    CHECK(red.id() == 0 && owner.id() != 0, "a moved shader keeps its id in the source");
    frame.swap();
    CHECK(all_pixels(frame, 255, 0, 0), "the moved-from shader deleted the red one");

    owner = std::move(blue); // deletes the red shader: the wall takes the default one
    frame.swap();
    const std::uint8_t *p = frame.pixel(W / 2, H / 2);
    CHECK(p[0] > 20 && std::abs(p[0] - p[1]) < 10 && std::abs(p[1] - p[2]) < 10,
          "the wall is (%d, %d, %d), not the default grey: the red shader survived", p[0], p[1], p[2]);

    raystage::Object other = std::move(wall);
    CHECK(wall.id() == 0 && other.id() != 0, "a moved object keeps its id in the source");
    CHECK(frame.pick(W / 2, H / 2).has_value(), "the moved-from object deleted the wall");

    raystage::FrameBuffer moved_buffer = std::move(frame);
    CHECK(moved_buffer.attached() && !frame.attached(), "the attachment did not move with the buffer");
    moved_buffer.swap();
    throws("a moved-from buffer", RT_INVALID_OPERATION, "moved from", [&] { frame.swap(); });
    no_error("moves");
}

/// Handles that outlive their Context free nothing in the next one, whose ids they would name.
void handles_outlive_their_context() {
    std::optional<raystage::Object> survivor;
    std::optional<raystage::Shader> light;
    {
        raystage::Context first;
        survivor.emplace();
        light.emplace("PointLight");
    }
    raystage::Context second;
    camera();
    raystage::FrameBuffer frame(W, H);
    raystage::Shader paint("Constant");
    paint.set("color", 1, 0, 1);
    raystage::Object wall = square_object(paint, 20);
    CHECK(wall.id() == survivor->id() && paint.id() == light->id(), "the second context gave other ids");
    raystage::Instance instance = wall.instantiate();
    survivor.reset();
    light.reset();
    frame.swap();
    CHECK(all_pixels(frame, 255, 0, 255), "a handle of the first context deleted the second's object or shader");
}

/// Errors are raystage::Error with the C ABI's code and message, or the wrapper's own for what
/// only it can check (the sizes of vectors).
void errors_carry_code_and_message() {
    raystage::Context context;
    throws("perspective(200)", RT_INVALID_VALUE, "rtPerspective", [] { raystage::perspective(200, 1, 0.1f, 100); });
    throws("an unknown shader class", RT_INVALID_VALUE, "Diffuse", [] { raystage::Shader("NoSuchClass"); });
    throws("a zero-sized frame buffer", RT_INVALID_VALUE, "raystage::FrameBuffer", [] { raystage::FrameBuffer(0, 4); });
    throws("waiting for no frame", RT_INVALID_VALUE, "names no frame", [] { raystage::Frame().wait(); });
    throws("shutter(0.5, 0.2)", RT_INVALID_VALUE, "rtShutter", [] { raystage::shutter(0.5f, 0.2f); });
    throws("an unknown render parameter", RT_INVALID_ENUM, "rtGetRenderParameteri",
           [] { (void)raystage::render_parameter(RT_VIEWPORT); });
    raystage::Object object;
    throws("a mesh of half a triangle", RT_INVALID_VALUE, "raystage::triangle_mesh",
           [&] { object.define([] { raystage::triangle_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1}); }); });
    throws("a mesh with too few normals", RT_INVALID_VALUE, "3 normals",
           [&] { object.define([] { raystage::triangle_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, {0, 0, 1}); }); });
    throws("an index out of range", RT_INVALID_VALUE, "rtTriangleMesh",
           [&] { object.define([] { raystage::triangle_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 7}); }); });
    raystage::Shader paint("Constant");
    throws("two numbers for a colour", RT_INVALID_OPERATION, "rtParameter2f", [&] { paint.set("color", 0, 1); });
    throws("four numbers for a colour", RT_INVALID_OPERATION, "rtParameter4f", [&] { paint.set("color", 0, 1, 0, 1); });
    raystage::Texture texture;
    throws("a float image of the wrong size", RT_INVALID_VALUE, "raystage::Texture::image",
           [&] { texture.image(1, 1, RT_RGBA, std::vector<RTfloat>(3)); });
    throws("an image of the wrong size", RT_INVALID_VALUE, "raystage::Texture::image",
           [&] { texture.image(2, 2, RT_RGB, std::vector<std::uint8_t>(9)); });
    throws("a missing image file", RT_IO_ERROR, "rtTexImageFile", [&] { texture.file("no/such/file.png"); });
}

/// The projections, background and state calls, checked through the pixels and queries.
void gl_calls() {
    raystage::Context context;
    raystage::FrameBuffer frame(W, H);
    camera();
    raystage::clear_color(0, 0, 1);
    std::vector<RTfloat> clear = raystage::get_floats(RT_COLOR_CLEAR_VALUE);
    CHECK(clear == (std::vector<RTfloat>{0, 0, 1, 1}), "RT_COLOR_CLEAR_VALUE is %g %g %g %g", clear[0], clear[1],
          clear[2], clear[3]);
    raystage::Shader paint("Constant");
    paint.set("color", 1, 0, 0);
    raystage::Object small = square_object(paint, 0.5f);
    raystage::Instance instance = small.instantiate();

    // glOrtho's window [-1, 1] fills the 32 pixels: the square covers pixels 8 to 23.
    raystage::ortho(-1, 1, -1, 1, 0.1, 100);
    frame.swap();
    CHECK(pixel_is(frame, 16, 8, 255, 0, 0) && pixel_is(frame, 10, 8, 255, 0, 0), "ortho: the square is not in the middle half");
    CHECK(pixel_is(frame, 5, 8, 0, 0, 255) && pixel_is(frame, 26, 8, 0, 0, 255), "ortho: the clear colour is not around it");
    // An off-axis frustum looking right of the square: it shows at the left edge only.
    raystage::frustum(0, 0.2, -0.1, 0.1, 0.1, 100);
    frame.swap();
    CHECK(pixel_is(frame, 0, 8, 255, 0, 0) && pixel_is(frame, 16, 8, 0, 0, 255), "frustum: the square is not at the left edge");

    // Matrices: a scope pops the stack it pushed, even after the mode changed inside it.
    raystage::load_identity();
    {
        raystage::MatrixScope scope;
        raystage::translate(1, 2, 3);
        raystage::scale(2, 2, 2);
        raystage::rotate(90, 0, 0, 1);
        std::vector<RTfloat> m = raystage::get_floats(RT_MODELVIEW_MATRIX);
        CHECK(m[12] == 1 && m[13] == 2 && m[14] == 3 && std::abs(m[1] - 2) < 1e-5f, "the modelview matrix: %g %g %g, %g",
              m[12], m[13], m[14], m[1]);
        raystage::matrix_mode(RT_TEXTURE);
    }
    CHECK(raystage::get_integers(RT_MODELVIEW_STACK_DEPTH)[0] == 1, "the scope did not pop the modelview stack");
    CHECK(raystage::get_integers(RT_MATRIX_MODE)[0] == RT_TEXTURE, "the scope changed the matrix mode back");
    raystage::matrix_mode(RT_MODELVIEW);
    raystage::load_matrix({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 4, 0, 0, 1});
    raystage::mult_matrix({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1});
    std::vector<RTfloat> m = raystage::get_floats(RT_MODELVIEW_MATRIX);
    CHECK(m[12] == 4 && m[13] == 5, "load_matrix and mult_matrix give a translation of %g %g", m[12], m[13]);
    throws("a matrix whose last row is not 0 0 0 1", RT_INVALID_VALUE, "rtLoadMatrixf",
           [] { raystage::load_matrix({1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}); });
    raystage::load_identity();

    // Render settings read back.
    raystage::render_mode(RT_PATH);
    raystage::render_parameter(RT_SAMPLES_PER_PIXEL, 3);
    CHECK(raystage::render_parameter(RT_RENDER_MODE) == RT_PATH, "the render mode did not stick");
    CHECK(raystage::render_parameter(RT_SAMPLES_PER_PIXEL) == 3, "the samples per pixel did not stick");
    raystage::lens(0, 0);
    raystage::shutter(0, 0.5f);
    raystage::translate(0.1f, 0, 0);
    instance.move_by_shutter_close(); // from where instantiate put it to here, while the shutter is open
    raystage::load_identity();
    instance.move();
    raystage::shade_model(RT_FLAT);
    CHECK(raystage::get_integers(RT_SHADE_MODEL)[0] == RT_FLAT, "the shade model did not stick");
    no_error("the GL calls");
}

/// A float frame buffer holds linear light beyond 1, as rendered; the double-precision calls
/// move the matrix as the float ones do.
void float_buffers_and_double_calls() {
    raystage::Context context;
    camera();
    raystage::Shader paint("Constant");
    paint.set("color", 2.0f, 0.5f, 0.25f); // brighter than white: an sRGB byte would clip it
    raystage::Object wall = square_object(paint, 10.0f);
    raystage::Instance instance = wall.instantiate();
    raystage::FrameBuffer linear(W, H, RT_RGBA32F);
    CHECK(linear.format() == RT_RGBA32F, "the format");
    linear.swap();
    std::array<float, 4> p = linear.linear(W / 2, H / 2);
    CHECK(p[0] == 2.0f && p[1] == 0.5f && p[2] == 0.25f && p[3] == 1.0f, "a float pixel is %g %g %g %g", p[0], p[1], p[2], p[3]);
    throws("reading floats as bytes", RT_INVALID_OPERATION, "linear()", [&] { linear.pixel(0, 0); });
    raystage::FrameBuffer bytes(W, H);
    bytes.swap();
    CHECK(pixel_is(bytes, W / 2, H / 2, 255, 188, 137), "the same wall in sRGB bytes");
    throws("reading bytes as floats", RT_INVALID_OPERATION, "pixel()", [&] { bytes.linear(0, 0); });
    throws("a format that is not one", RT_INVALID_ENUM, "RT_RGBA32F", [] { raystage::FrameBuffer bad(W, H, RT_QUADS); });
    // A moved float buffer stays a float buffer, attached.
    raystage::FrameBuffer moved(std::move(linear));
    moved.swap();
    CHECK(moved.format() == RT_RGBA32F && moved.linear(0, 0)[0] == 2.0f, "the moved float buffer");

    raystage::load_identity();
    raystage::translated(1, 2, 3);
    raystage::scaled(2, 2, 2);
    raystage::rotated(90, 0, 0, 1);
    std::vector<RTfloat> m = raystage::get_floats(RT_MODELVIEW_MATRIX);
    CHECK(m[12] == 1 && m[13] == 2 && m[14] == 3 && std::abs(m[1] - 2) < 1e-5f, "the double calls' matrix: %g %g %g, %g", m[12],
          m[13], m[14], m[1]);
    raystage::load_matrixd({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 4, 0, 0, 1});
    raystage::mult_matrixd({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1});
    m = raystage::get_floats(RT_MODELVIEW_MATRIX);
    CHECK(m[12] == 4 && m[13] == 5, "load_matrixd and mult_matrixd give a translation of %g %g", m[12], m[13]);
    throws("a double matrix whose last row is not 0 0 0 1", RT_INVALID_VALUE, "rtLoadMatrixd",
           [] { raystage::load_matrixd({1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}); });
    throws("a translation past RT_MAX_COORDINATE", RT_INVALID_VALUE, "RT_MAX_COORDINATE", [] { raystage::translated(1e12, 0, 0); });
    raystage::load_identity();
}

/// Textures: an image on a Diffuse wall, seen in the eye-light preview.
void textures() {
    raystage::Context context;
    raystage::FrameBuffer frame(W, H);
    camera();
    raystage::perspective(30, 2, 0.1f, 100);
    raystage::render_mode(RT_EYELIGHT);
    raystage::Texture halves;
    halves.image(2, 1, RT_RGB, std::vector<std::uint8_t>{255, 0, 0, 0, 0, 255}).parameter(RT_TEXTURE_MAG_FILTER, RT_NEAREST);
    raystage::Shader wall_paint("Diffuse");
    wall_paint.set("diffuse", 1, 1, 1).set("diffuse_texture", halves);
    raystage::Object wall;
    wall.define([&] {
        wall_paint.bind();
        raystage::Primitive quad(RT_QUADS);
        const float corners[4][2] = {{-20, -20}, {20, -20}, {20, 20}, {-20, 20}};
        for (const auto &c : corners) {
            rtTexCoord2f(c[0] < 0 ? 0.0f : 1.0f, c[1] < 0 ? 0.0f : 1.0f);
            rtVertex3f(c[0], c[1], 0);
        }
    });
    raystage::Instance instance = wall.instantiate();
    frame.swap();
    const std::uint8_t *left = frame.pixel(2, H / 2), *right = frame.pixel(W - 3, H / 2);
    CHECK(left[0] > 100 && left[2] < 30, "the left half is (%d, %d, %d), not red", left[0], left[1], left[2]);
    CHECK(right[2] > 100 && right[0] < 30, "the right half is (%d, %d, %d), not blue", right[0], right[1], right[2]);
    raystage::Texture sky;
    sky.image(2, 1, RT_RGB, std::vector<RTfloat>{4, 4, 4, 0.5f, 0.5f, 1}).parameter(RT_TEXTURE_WRAP_S, RT_CLAMP_TO_EDGE);
    raystage::Shader spot("SpotLight");
    spot.set("cone", 30).set("position", 0, 0, 5);
    raystage::Texture board;
    board.checker({1, 1, 1}, {0, 0, 0}, 1);
    raystage::Texture clouds;
    clouds.noise({1, 1, 1}, {0, 0, 0}, 2);
    no_error("textures");
}

/// Texture::image reads bytes as rtTexImage2D does: linear (byte / 255) by default, sRGB-encoded
/// only when asked with RT_SRGB8. A grey wall textured by the wrapper and again by the C call
/// renders the same.
void texture_bytes_read_as_c_reads_them() {
    raystage::Context context;
    raystage::FrameBuffer frame(W, H, RT_RGBA32F);
    camera();
    raystage::render_mode(RT_EYELIGHT);
    const std::vector<std::uint8_t> grey{128, 128, 128};
    raystage::Texture texture;
    texture.image(1, 1, RT_RGB, grey);
    raystage::Shader paint("Diffuse");
    paint.set("diffuse", 1, 1, 1).set("diffuse_texture", texture);
    raystage::Object wall = square_object(paint, 20);
    raystage::Instance instance = wall.instantiate();
    frame.swap();
    const float wrapped = frame.linear(W / 2, H / 2)[0];
    texture.bind();
    rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB, 1, 1, 0, RT_RGB, RT_UNSIGNED_BYTE, grey.data());
    frame.swap();
    const float c = frame.linear(W / 2, H / 2)[0];
    CHECK(wrapped == c && c > 0.3f, "the wrapper's grey renders %g, the C call's %g", wrapped, c);
    texture.image(1, 1, RT_RGB, grey, RT_SRGB8);
    frame.swap();
    const float srgb = frame.linear(W / 2, H / 2)[0];
    CHECK(srgb < c * 0.6f, "sRGB-encoded 128 is darker (%g) than linear 128 (%g)", srgb, c);
    no_error("texture bytes");
}

/// Shader::set writes a shader's parameter without changing which shader is bound: inside
/// Object::define, triangles issued after it still get the shader bound before.
void set_keeps_the_bound_shader() {
    raystage::Context context;
    raystage::FrameBuffer frame(W, H);
    camera();
    raystage::Shader red("Constant"), green("Constant");
    red.set("color", 1, 0, 0);
    raystage::Object wall;
    wall.define([&] {
        red.bind();
        green.set("color", 0, 1, 0);
        square(20);
    });
    raystage::Instance instance = wall.instantiate();
    frame.swap();
    const std::uint8_t *p = frame.pixel(W / 2, H / 2);
    CHECK(p[0] > 200 && p[1] < 30, "the wall is (%d, %d, %d), not the red bound before green's set", p[0], p[1], p[2]);
    // Outside define too, and with nothing bound: set leaves nothing bound.
    rtBindShader(0);
    green.set("color", 0, 0.5f, 0);
    RTint bound = -1;
    rtGetIntegerv(RT_SHADER_BINDING, &bound);
    CHECK(bound == 0, "set left shader %d bound", bound);
    no_error("set keeps the bound shader");
}

/// Channels: each buffer's own, filled by its frames, taken back when another buffer attaches.
void channels() {
    raystage::Context context;
    camera();
    raystage::Shader paint("Diffuse");
    paint.set("diffuse", 0.5f, 0.25f, 0.125f);
    raystage::Object wall = square_object(paint, 2);
    raystage::Instance instance = wall.instantiate();
    raystage::FrameBuffer a(W, H), small(4, 4);
    a.enable(RT_DEPTH_CHANNEL);
    a.enable(RT_NORMAL_CHANNEL);
    a.enable(RT_ALBEDO_CHANNEL);
    a.enable(RT_INSTANCE_ID_CHANNEL);
    a.swap();
    CHECK(a.value(RT_DEPTH_CHANNEL, W / 2, H / 2) > 5.9f && a.value(RT_DEPTH_CHANNEL, W / 2, H / 2) < 6.1f, "depth %f",
          a.value(RT_DEPTH_CHANNEL, W / 2, H / 2));
    CHECK(a.value(RT_NORMAL_CHANNEL, W / 2, H / 2, 2) == 1.0f, "the wall faces the camera");
    CHECK(a.value(RT_ALBEDO_CHANNEL, W / 2, H / 2, 1) == 0.25f, "albedo");
    CHECK(a.id(RT_INSTANCE_ID_CHANNEL, W / 2, H / 2) == instance.id() && a.id(RT_INSTANCE_ID_CHANNEL, 0, 0) == 0, "ids");
    // Another buffer of another size renders without a's channels (they would not fit).
    small.swap();
    no_error("a smaller buffer after a's channels");
    a.swap();
    throws("a channel never enabled", RT_INVALID_OPERATION, "not enabled", [&] { small.value(RT_Z_CHANNEL, 0, 0); });
    no_error("channels");
}

/// Introspection: every class and parameter, with a known one checked in full.
void classes() {
    std::vector<raystage::ClassInfo> classes = raystage::shader_classes();
    CHECK(classes.size() > 10 && classes.front().kind == RT_SURFACE_CLASS && classes.back().kind == RT_LIGHT_CLASS, "%zu classes", classes.size());
    const raystage::ClassInfo *spot = nullptr;
    for (const auto &c : classes) {
        CHECK(!c.name.empty() && !c.doc.empty(), "class %s is named and documented", c.name.c_str());
        if (c.name == "SpotLight") {
            spot = &c;
        }
    }
    CHECK(spot != nullptr, "SpotLight is listed");
    bool cone = false;
    for (const auto &p : spot->parameters) {
        if (p.name == "cone") {
            cone = p.type == RT_FLOAT && p.defaults[0] == 30 && p.range[1] == 90;
        }
    }
    CHECK(cone, "SpotLight's cone is a number, 30 by default, at most 90");
    no_error("classes");
}

} // namespace

int main() {
    run("each_buffer_gets_its_own_frames", each_buffer_gets_its_own_frames);
    run("destroying_a_buffer_keeps_the_attached_one", destroying_a_buffer_keeps_the_attached_one);
    run("an_exception_in_define_leaves_a_clean_context", an_exception_in_define_leaves_a_clean_context);
    run("instances_live_as_long_as_their_handles", instances_live_as_long_as_their_handles);
    run("moves_transfer_ownership", moves_transfer_ownership);
    run("handles_outlive_their_context", handles_outlive_their_context);
    run("errors_carry_code_and_message", errors_carry_code_and_message);
    run("gl_calls", gl_calls);
    run("float_buffers_and_double_calls", float_buffers_and_double_calls);
    run("textures", textures);
    run("texture_bytes_read_as_c_reads_them", texture_bytes_read_as_c_reads_them);
    run("set_keeps_the_bound_shader", set_keeps_the_bound_shader);
    run("channels", channels);
    run("classes", classes);
    return verdict("wrapper.cpp");
}
