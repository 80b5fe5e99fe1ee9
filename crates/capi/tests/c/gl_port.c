/*
 * gl_port.c: the OpenGL 1.x calls a porter reaches for, checked from C as a ported program uses
 * them: rtOrtho and rtFrustum (pixels of known geometry), rtClearColor, rtColor4f, rtVertex2f,
 * the double-precision calls, GL 1.0's internal formats 3 and 4, the rtGet* queries,
 * rtEndObject closing an open primitive, and RT_MAX_COORDINATE; with bad input (NULL, NaN,
 * unknown enums, calls in the wrong state) refused with the right code and message.
 *
 * Prints each failed check and exits 1 if any failed (run by crates/capi/tests/examples.rs).
 */
#include "check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 32
#define H 16

static unsigned char pixels[W * H * 4];

static const unsigned char *pixel(int x, int y) { return &pixels[(y * W + x) * 4]; }

/* Pixel (x, y) is the colour r, g, b (sRGB bytes) within 2. */
static void pixel_is(const char *what, int x, int y, int r, int g, int b) {
    const unsigned char *p = pixel(x, y);
    CHECK(abs(p[0] - r) <= 2 && abs(p[1] - g) <= 2 && abs(p[2] - b) <= 2, "%s: pixel (%d, %d) is %d %d %d, not %d %d %d", what, x,
          y, p[0], p[1], p[2], r, g, b);
}

static RTuint constant_shader(float r, float g, float b) {
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Constant", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    rtParameter3f(rtParameterHandle("color"), r, g, b);
    return sid;
}

/* The corners of the square (2..4, 1..3) at z = 0, counter-clockwise, with rtVertex2f. */
static void square_vertices(void) {
    rtVertex2f(2.0f, 1.0f);
    rtVertex2f(4.0f, 1.0f);
    rtVertex2f(4.0f, 3.0f);
    rtVertex2f(2.0f, 3.0f);
}

/* The square's corners with texture coordinates s from 0 to `s`, t from 0 to 1. */
static void textured_square_vertices(float s) {
    rtTexCoord2f(0, 0);
    rtVertex2f(2.0f, 1.0f);
    rtTexCoord2f(s, 0);
    rtVertex2f(4.0f, 1.0f);
    rtTexCoord2f(s, 1);
    rtVertex2f(4.0f, 3.0f);
    rtTexCoord2f(0, 1);
    rtVertex2f(2.0f, 3.0f);
}

/* rtOrtho: a 2 × 2 square drawn with rtVertex2f at (2..4, 1..3) in the window [0, 8] × [0, 4]
 * of a 32 × 16 frame: 4 pixels a unit, so it covers columns 8..15 and rows 4..11; around it the
 * clear colour. */
static void orthographic(void) {
    RTfloat clear[4];
    rtGetFloatv(RT_COLOR_CLEAR_VALUE, clear);
    CHECK(clear[0] == -1.0f && clear[3] == -1.0f, "no clear colour yet: %g %g %g %g", clear[0], clear[1], clear[2], clear[3]);
    rtClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    rtGetFloatv(RT_COLOR_CLEAR_VALUE, clear);
    CHECK(clear[0] == 0.0f && clear[2] == 1.0f && clear[3] == 1.0f, "clear colour %g %g %g %g", clear[0], clear[1], clear[2], clear[3]);
    constant_shader(1.0f, 0.0f, 0.0f);
    RTuint square = rtGenObjects(1);
    rtNewObject(square, RT_COMPILE);
    rtBegin(RT_QUADS);
    square_vertices();
    rtEnd();
    rtEndObject();
    rtInstantiateObject(square);
    rtLookAt(0, 0, 0, 0, 0, -1, 0, 1, 0);
    rtOrtho(0.0, 8.0, 0.0, 4.0, -1.0, 1.0); /* the rays start at z = 1, behind the eye */
    no_error("the orthographic scene");
    rtSwapBuffers();
    no_error("rendering it");
    pixel_is("inside", 12, 8, 255, 0, 0);
    pixel_is("first column", 8, 8, 255, 0, 0);
    pixel_is("last column", 15, 8, 255, 0, 0);
    pixel_is("left of it", 7, 8, 0, 0, 255);
    pixel_is("right of it", 16, 8, 0, 0, 255);
    pixel_is("first row", 12, 4, 255, 0, 0);
    pixel_is("last row", 12, 11, 255, 0, 0);
    pixel_is("above it", 12, 3, 0, 0, 255);
    pixel_is("below it", 12, 12, 0, 0, 255);
    RTuint instance = 0, object = 0, triangle = 0;
    CHECK(rtPick(12, 8, &instance, &object, &triangle) == 1 && object == square, "picking the square through the window: object %u", object);
    CHECK(rtPick(4, 8, &instance, &object, &triangle) == 0, "picking beside it finds nothing");

    /* A mirrored window flips the image, as in OpenGL. */
    rtOrtho(8.0, 0.0, 0.0, 4.0, -1.0, 1.0);
    rtSwapBuffers();
    no_error("the mirrored window");
    pixel_is("mirrored: left of it", 15, 8, 0, 0, 255);
    pixel_is("mirrored: inside", 16, 8, 255, 0, 0);

    /* Bad windows, NaN, and the wrong state: refused, the projection unchanged. */
    rtOrtho(1.0, 1.0, 0.0, 4.0, -1.0, 1.0);
    error_is("an empty window", RT_INVALID_VALUE, "rtOrtho: left and right are both 1");
    rtOrtho(0.0, 8.0, 0.0, 4.0, 2.0, 2.0);
    error_is("znear = zfar", RT_INVALID_VALUE, "znear and zfar are both 2");
    rtOrtho(0.0, NAN, 0.0, 4.0, -1.0, 1.0);
    error_is("NaN", RT_INVALID_VALUE, "rtOrtho: (left, right, bottom, top, znear, zfar)[1] is NaN");
    rtOrtho(0.0, 1e300, 0.0, 4.0, -1.0, 1.0);
    error_is("beyond single precision", RT_INVALID_VALUE, "beyond single precision");
    rtClearColor(0.0f, -1.0f, 0.0f, 1.0f);
    error_is("a negative clear colour", RT_INVALID_VALUE, "rtClearColor");
    rtClearColor(0.0f, 0.0f, 0.0f, NAN);
    error_is("a NaN alpha", RT_INVALID_VALUE, "(red, green, blue, alpha)[3] is NaN");
    RTuint open = rtGenObjects(1);
    rtNewObject(open, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtOrtho(0.0, 8.0, 0.0, 4.0, -1.0, 1.0);
    error_is("rtOrtho inside a primitive", RT_INVALID_OPERATION, "rtOrtho: not allowed between rtBegin and rtEnd");
    rtClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    error_is("rtClearColor inside a primitive", RT_INVALID_OPERATION, "not allowed between rtBegin and rtEnd");
    rtEnd();
    rtEndObject();
    error_is("an object with no triangles", RT_INVALID_OPERATION, "has no triangles");
    rtSwapBuffers();
    no_error("rendering again");
    pixel_is("the projection stayed", 16, 8, 255, 0, 0);
    rtDeleteAllInstances();
}

/* rtFrustum: an off-axis window [0, 1] × [-0.5, 0.5] at distance 1: the view axis runs along
 * the image's left edge, so a square spanning x in [0, 1] at distance 2, drawn with rtVertex3d,
 * fills the left half. */
static void frustum(void) {
    RTuint square = rtGenObjects(1);
    rtNewObject(square, RT_COMPILE);
    rtBegin(RT_QUADS);
    rtVertex3d(0.0, -1.5, -2.0);
    rtVertex3d(1.0, -1.5, -2.0);
    rtVertex3d(1.0, 1.5, -2.0);
    rtVertex3d(0.0, 1.5, -2.0);
    rtEnd();
    rtEndObject();
    rtInstantiateObject(square);
    rtFrustum(0.0, 1.0, -0.5, 0.5, 1.0, 10.0);
    rtSwapBuffers();
    no_error("the off-axis frustum");
    pixel_is("left edge", 0, 8, 255, 0, 0);
    pixel_is("left half", 15, 8, 255, 0, 0);
    pixel_is("right half", 16, 8, 0, 0, 255);
    pixel_is("right edge", 31, 8, 0, 0, 255);
    /* The symmetric perspective sees the square right of the centre instead. */
    rtPerspective(45.0f, 2.0f, 1.0f, 10.0f);
    rtSwapBuffers();
    no_error("the symmetric perspective");
    pixel_is("symmetric: left", 4, 8, 0, 0, 255);
    pixel_is("symmetric: right of centre", 20, 8, 255, 0, 0);

    rtFrustum(0.0, 1.0, -0.5, 0.5, 0.0, 10.0);
    error_is("znear 0", RT_INVALID_VALUE, "rtFrustum: znear 0 and zfar 10 do not satisfy 0 < znear < zfar");
    rtFrustum(0.0, 1.0, 0.5, 0.5, 1.0, 10.0);
    error_is("an empty window", RT_INVALID_VALUE, "bottom and top are both 0.5");
    rtFrustum(0.0, 1.0, -0.5, 0.5, 1.0, INFINITY);
    error_is("an infinite zfar", RT_INVALID_VALUE, "[5] is inf");
    rtDeleteAllInstances();
}

/* rtColor4f, the current attributes, and GL 1.0's internal formats 3 and 4. */
static void colours_and_textures(void) {
    rtOrtho(0.0, 8.0, 0.0, 4.0, -1.0, 1.0);
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "VertexColor", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    rtColor4f(0.0f, 1.0f, 0.0f, 0.5f);
    square_vertices();
    RTfloat colour[4];
    rtGetFloatv(RT_CURRENT_COLOR, colour); /* allowed inside a primitive */
    CHECK(colour[1] == 1.0f && colour[3] == 0.5f, "current colour %g %g %g %g", colour[0], colour[1], colour[2], colour[3]);
    rtColor4f(0.0f, 0.0f, 0.0f, NAN);
    error_is("a NaN alpha", RT_INVALID_VALUE, "rtColor4f: alpha is NaN");
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtSwapBuffers();
    no_error("vertex colours");
    pixel_is("rtColor4f's colour (alpha blends nothing)", 12, 8, 0, 255, 0);
    rtColor3f(1.0f, 1.0f, 1.0f);
    rtGetFloatv(RT_CURRENT_COLOR, colour);
    CHECK(colour[3] == 1.0f, "rtColor3f sets alpha 1, not %g", colour[3]);
    rtDeleteAllInstances();

    /* A 2 × 1 texture, red then green, given with internal format 3 and then 4 (RGBA bytes). */
    RTuint texture = rtGenTextures(1);
    rtBindTexture(RT_TEXTURE_2D, texture);
    RTint bound = 0;
    rtGetIntegerv(RT_TEXTURE_BINDING_2D, &bound);
    CHECK(bound == (RTint)texture, "bound texture %d, not %u", bound, texture);
    cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Diffuse", NULL);
    sid = rtGenShaders(1);
    rtNewShader(sid);
    rtParameter3f(rtParameterHandle("diffuse"), 1.0f, 1.0f, 1.0f);
    object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    textured_square_vertices(1.0f);
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    static const unsigned char rgb[] = {255, 0, 0, 0, 255, 0};
    static const unsigned char rgba[] = {255, 0, 0, 255, 0, 255, 0, 255};
    for (int components = 3; components <= 4; components++) {
        rtTexImage2D(RT_TEXTURE_2D, 0, components, 2, 1, 0, components == 3 ? RT_RGB : RT_RGBA, RT_UNSIGNED_BYTE,
                     components == 3 ? (const void *)rgb : (const void *)rgba);
        no_error(components == 3 ? "internal format 3" : "internal format 4");
        /* A texture with an image: the shader may now name it. */
        rtParameterTexture(rtParameterHandle("diffuse_texture"), texture);
        rtSwapBuffers();
        no_error("the textured square");
        const unsigned char *left = pixel(10, 8), *right = pixel(13, 8);
        CHECK(left[0] > 200 && left[1] < 128 && left[2] < 10, "format %d: the left texel is %d %d %d", components, left[0], left[1], left[2]);
        CHECK(right[1] > 200 && right[0] < 128 && right[2] < 10, "format %d: the right texel is %d %d %d", components, right[0], right[1],
              right[2]);
    }
    rtTexImage2D(RT_TEXTURE_2D, 0, 5, 2, 1, 0, RT_RGB, RT_UNSIGNED_BYTE, rgb);
    error_is("internal format 5", RT_INVALID_ENUM, "rtTexImage2D: 0x5 is not a texture internal format");
    rtTexImage2D(RT_TEXTURE_2D, 0, 3, 2, 1, 0, RT_RGB, RT_UNSIGNED_BYTE, NULL);
    error_is("NULL pixels", RT_INVALID_VALUE, "pixels is NULL");
    rtDeleteAllInstances();
}

/* rtTexParameteri: a 2 × 1 texture, red then green, across the square twice (s from 0 to 2),
 * magnified to 2 pixels a texel with RT_NEAREST: columns 8..11 show one copy, 12..15 the second
 * as each wrap mode makes it. */
static int is_red(int x) { return pixel(x, 8)[0] > 250 && pixel(x, 8)[1] < 5; }
static int is_green(int x) { return pixel(x, 8)[1] > 250 && pixel(x, 8)[0] < 5; }

/* A new shader of the bound class "Diffuse", white, with `texture`, bound. */
static void white_textured_shader(RTuint texture) {
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    rtParameter3f(rtParameterHandle("diffuse"), 1.0f, 1.0f, 1.0f);
    rtParameterTexture(rtParameterHandle("diffuse_texture"), texture);
}

static void texture_parameters(void) {
    rtOrtho(0.0, 8.0, 0.0, 4.0, -1.0, 1.0);
    RTuint texture = rtGenTextures(1);
    rtBindTexture(RT_TEXTURE_2D, texture);
    static const unsigned char rgb[] = {255, 0, 0, 0, 255, 0};
    rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB, 2, 1, 0, RT_RGB, RT_UNSIGNED_BYTE, rgb);
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Diffuse", NULL);
    white_textured_shader(texture);
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    textured_square_vertices(2.0f);
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_MAG_FILTER, RT_NEAREST);
    error_is("inside a primitive", RT_INVALID_OPERATION, "rtTexParameteri: not allowed between rtBegin and rtEnd");
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtSwapBuffers();
    no_error("bilinear, repeating");
    CHECK(!is_red(9) && !is_green(9), "bilinear filtering blends the texels: %d %d %d", pixel(9, 8)[0], pixel(9, 8)[1], pixel(9, 8)[2]);

    /* The shader already names the texture: the new parameters reach it. */
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_MAG_FILTER, RT_NEAREST);
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_MIN_FILTER, RT_LINEAR_MIPMAP_LINEAR);
    no_error("nearest");
    rtSwapBuffers();
    CHECK(is_red(8) && is_red(9) && is_green(10) && is_green(11), "nearest: the first copy");
    CHECK(is_red(12) && is_red(13) && is_green(14) && is_green(15), "RT_REPEAT: the second copy repeats the first");
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_S, RT_CLAMP_TO_EDGE);
    rtSwapBuffers();
    CHECK(is_red(9) && is_green(10) && is_green(12) && is_green(14), "RT_CLAMP_TO_EDGE: the last texel beyond s = 1");
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_S, RT_MIRRORED_REPEAT);
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_T, RT_CLAMP_TO_EDGE);
    rtSwapBuffers();
    no_error("mirrored");
    CHECK(is_red(9) && is_green(12) && is_red(14), "RT_MIRRORED_REPEAT: the second copy mirrored");

    /* A shader given the texture later samples it with its parameters too. */
    white_textured_shader(texture);
    RTuint copy = rtGenObjects(1);
    rtNewObject(copy, RT_COMPILE);
    rtBegin(RT_QUADS);
    textured_square_vertices(2.0f);
    rtEnd();
    rtEndObject();
    rtDeleteAllInstances();
    rtInstantiateObject(copy);
    rtSwapBuffers();
    no_error("the later shader");
    CHECK(is_red(9) && is_green(12) && is_red(14), "the later shader mirrors too");

    rtTexParameteri(RT_TEXTURE_2D, 0x1234, RT_REPEAT);
    error_is("an unknown parameter", RT_INVALID_ENUM, "rtTexParameteri: 0x1234 is not a texture parameter");
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_S, RT_NEAREST);
    error_is("a filter as wrap mode", RT_INVALID_ENUM, "0x2600 is not a wrap mode");
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_MAG_FILTER, RT_LINEAR_MIPMAP_LINEAR);
    error_is("a mipmap magnification", RT_INVALID_ENUM, "not a magnification filter");
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_S, -1);
    error_is("a negative value", RT_INVALID_ENUM, "not a wrap mode");
    rtTexParameteri(RT_TEXTURE, RT_TEXTURE_WRAP_S, RT_REPEAT);
    error_is("a wrong target", RT_INVALID_ENUM, "not a texture target");
    rtBindTexture(RT_TEXTURE_2D, 0);
    rtTexParameteri(RT_TEXTURE_2D, RT_TEXTURE_WRAP_S, RT_REPEAT);
    error_is("no bound texture", RT_INVALID_OPERATION, "no texture is bound");
    rtSwapBuffers();
    CHECK(is_red(14), "refused calls change nothing");
    rtDeleteAllInstances();
}

/* The double-precision matrix calls, read back with rtGet*. */
static void matrices(void) {
    RTdouble m[16];
    RTfloat f[16];
    RTint depth = 0, mode = 0, viewport[4] = {-1, -1, -1, -1};
    rtGetIntegerv(RT_VIEWPORT, viewport);
    CHECK(viewport[0] == 0 && viewport[1] == 0 && viewport[2] == W && viewport[3] == H, "viewport %d %d %d %d", viewport[0], viewport[1],
          viewport[2], viewport[3]);
    rtGetIntegerv(RT_MATRIX_MODE, &mode);
    CHECK(mode == RT_MODELVIEW, "matrix mode 0x%x", (unsigned)mode);
    rtGetIntegerv(RT_SHADE_MODEL, &mode);
    CHECK(mode == RT_SMOOTH, "shade model 0x%x", (unsigned)mode);
    rtLoadIdentity();
    rtPushMatrix();
    rtTranslated(1.0, 2.0, 3.0);
    rtScaled(2.0, 2.0, 2.0);
    rtRotated(90.0, 0.0, 0.0, 1.0);
    rtGetIntegerv(RT_MODELVIEW_STACK_DEPTH, &depth);
    CHECK(depth == 2, "stack depth %d", depth);
    rtGetDoublev(RT_MODELVIEW_MATRIX, m);
    /* Column-major: x goes to 2y, y to -2x, the translation last. */
    CHECK(fabs(m[0]) < 1e-6 && fabs(m[1] - 2.0) < 1e-6 && fabs(m[4] + 2.0) < 1e-6 && fabs(m[10] - 2.0) < 1e-6,
          "rotated and scaled: %g %g %g %.9g", m[0], m[1], m[4], m[10]);
    CHECK(m[12] == 1.0 && m[13] == 2.0 && m[14] == 3.0 && m[15] == 1.0, "translated: %g %g %g %g", m[12], m[13], m[14], m[15]);
    static const RTdouble shear[16] = {1, 0, 0, 0, 0.5, 1, 0, 0, 0, 0, 1, 0, 4, 5, 6, 1};
    rtLoadMatrixd(shear);
    rtGetFloatv(RT_MODELVIEW_MATRIX, f);
    CHECK(f[4] == 0.5f && f[12] == 4.0f && f[14] == 6.0f, "loaded: %g %g %g", f[4], f[12], f[14]);
    rtMultMatrixd(shear);
    rtGetFloatv(RT_MODELVIEW_MATRIX, f);
    CHECK(f[4] == 1.0f && f[12] == 10.5f && f[13] == 10.0f, "multiplied: %g %g %g", f[4], f[12], f[13]);
    RTdouble projective[16];
    memcpy(projective, shear, sizeof projective);
    projective[3] = 0.5;
    rtMultMatrixd(projective);
    error_is("a projective matrix", RT_INVALID_VALUE, "rtMultMatrixd: the matrix's last row");
    rtLoadMatrixd(NULL);
    error_is("NULL", RT_INVALID_VALUE, "rtLoadMatrixd: m is NULL");
    rtTranslated(0.0, NAN, 0.0);
    error_is("NaN", RT_INVALID_VALUE, "rtTranslated: (x, y, z)[1] is NaN");
    rtScaled(1e39, 1.0, 1.0);
    error_is("beyond single precision", RT_INVALID_VALUE, "rtScaled: (x, y, z)[0] is 1e39, beyond single precision");
    rtRotated(30.0, 0.0, 0.0, 0.0);
    error_is("a zero axis", RT_INVALID_VALUE, "rotation axis is zero");
    rtGetFloatv(RT_MODELVIEW_MATRIX, f);
    CHECK(f[12] == 10.5f, "refused calls change nothing: %g", f[12]);
    rtPopMatrix();

    rtGetFloatv(0x1234, f);
    error_is("an unknown query", RT_INVALID_ENUM, "rtGetFloatv: 0x1234 is not a state to query");
    rtGetDoublev(RT_VIEWPORT, NULL);
    error_is("NULL params", RT_INVALID_VALUE, "rtGetDoublev: params is NULL");
}

/* rtEndObject ends a primitive left open, keeps its triangles, and leaves the context usable. */
static void end_object_closes_the_primitive(void) {
    constant_shader(1.0f, 1.0f, 1.0f);
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtVertex2f(2.0f, 1.0f);
    rtVertex2f(4.0f, 1.0f);
    rtVertex2f(3.0f, 3.0f);
    rtEndObject(); /* no rtEnd */
    no_error("rtEndObject without rtEnd");
    rtInstantiateObject(object);
    rtSwapBuffers();
    no_error("the next frame");
    pixel_is("the triangle", 12, 8, 255, 255, 255);
    pixel_is("beside it", 4, 8, 0, 0, 255);
    rtEnd();
    error_is("rtEnd after it", RT_INVALID_OPERATION, "rtEnd without rtBegin");
    rtDeleteAllInstances();
}

/* Vertices beyond RT_MAX_COORDINATE vanish or mis-shade in single precision: refused. */
static void huge_coordinates(void) {
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_TRIANGLES);
    rtVertex3f(1e20f, 0.0f, 0.0f);
    error_is("1e20", RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE (1e8)");
    rtVertex3d(0.0, 0.0, -2e8);
    error_is("-2e8 in double precision", RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE");
    rtVertex2f(RT_MAX_COORDINATE, 0.0f);
    no_error("a vertex at the limit");
    rtEnd();
    rtEndObject();
    error_is("no triangle", RT_INVALID_OPERATION, "has no triangles");
}

int main(void) {
    rtFrameBuffer(pixels, W, H, RT_RGBA8);
    /* Colours are checked as given: the preview shows them as they are, where RT_AUTO would
       light these unlit scenes by the sky. */
    rtRenderMode(RT_EYELIGHT);
    orthographic();
    frustum();
    colours_and_textures();
    texture_parameters();
    matrices();
    end_object_closes_the_primitive();
    huge_coordinates();
    if (failures > 0) {
        fprintf(stderr, "gl_port: %d checks failed\n", failures);
        return 1;
    }
    printf("gl_port: every check passed\n");
    return 0;
}
