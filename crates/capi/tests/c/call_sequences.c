/*
 * call_sequences.c: sequences of public calls that once broke rt.h's rules, each checked against
 * the rule it broke. Run by crates/capi/tests/examples.rs against the installed shared library,
 * and by scripts/test.sh under valgrind, which fails on any read or write of freed memory.
 *
 *   window_resize      RTUT's window memory reallocated by a resize (rtutInitWindowSize after
 *                      rtutCreateWindow, then rtutMainLoop) while the context still rendered
 *                      into it: the next rtSwapBuffers, or an asynchronous frame, wrote freed
 *                      memory. RTUT lends no memory now: its frames go to a frame buffer the
 *                      library keeps (rtSwapBuffersKept).
 *   stale_handles      Frame handles started again at 1 after rtResetContext, so releasing a
 *                      stale handle cancelled a newer frame. Handles are unique in the process.
 *   failed_rtut_swap   A refused rtutSwapBuffers (inside rtNewObject, or with channels lent at
 *                      another size) kept the window's pixels as the context's frame buffer. A
 *                      failed call changes nothing.
 *   far_orthographic   rtOrtho with znear far behind the eye measured depths beyond single
 *                      precision (infinite where the id channels saw a surface). The camera's
 *                      planes are bound by RT_MAX_COORDINATE, and within it depth, z, the id
 *                      channels and rtPick agree.
 *
 * RTUT runs headless (RTUT_HEADLESS=1) and writes its frames as call-sequences-NNNN.png in the
 * working directory. Prints each failed check and exits 1 if any failed.
 */
#define _POSIX_C_SOURCE 200809L
#include <raystage/rtut.h>

#include "check.h"

#include <math.h>
#include <stdlib.h>

/* A Constant quad of (r, g, b), 40 × 40 at z = 0 (or `side` wide), seen from z = 6; returns its
 * instance. */
static RTuint quad(float r, float g, float b, float side) {
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Constant", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    rtParameter3f(rtParameterHandle("color"), r, g, b);
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    rtVertex3f(-side, -side, 0.0f);
    rtVertex3f(side, -side, 0.0f);
    rtVertex3f(side, side, 0.0f);
    rtVertex3f(-side, side, 0.0f);
    rtEnd();
    rtEndObject();
    RTuint instance = rtInstantiateObject(object);
    rtLookAt(0.0f, 0.0f, 6.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f);
    no_error("the quad");
    return instance;
}

/* The frame buffer's size as RT_VIEWPORT reads it. */
static void viewport(RTint *width, RTint *height) {
    RTint v[4] = {0, 0, 0, 0};
    rtGetIntegerv(RT_VIEWPORT, v);
    *width = v[2];
    *height = v[3];
}

/* ----- window_resize ----- */

static void swap_and_leave(void) {
    rtutSwapBuffers();
    no_error("rtutSwapBuffers in the first loop");
    rtutLeaveMainLoop();
}

static void leave(void) { rtutLeaveMainLoop(); }

static void window_resize(void) {
    quad(1.0f, 0.0f, 0.0f, 20.0f);
    rtutInit(NULL, NULL);
    rtutInitWindowSize(64, 64);
    CHECK(rtutCreateWindow("resize") == 1, "the window");
    rtutDisplayFunc(swap_and_leave);
    rtutMainLoop();
    no_error("the first loop");
    RTint width, height;
    viewport(&width, &height);
    CHECK(width == 64 && height == 64, "the window's frame buffer is 64 x 64, not %d x %d", width, height);

    /* The window shrinks while the context still renders into its pixels. */
    rtutInitWindowSize(8, 8);
    rtutDisplayFunc(leave);
    rtutMainLoop();
    no_error("the second loop");

    /* Both frames go to the frame buffer the context was given: the library's (valgrind checks). */
    rtSwapBuffers();
    no_error("rtSwapBuffers after the resize");
    RTuint frame = rtRenderFrameAsync();
    CHECK(frame != 0, "an asynchronous frame after the resize");
    CHECK(rtFrameWait(frame) == RT_NO_ERROR, "the asynchronous frame completes");
    rtFrameRelease(frame);
    no_error("the asynchronous frame");

    /* Shown again, the window renders at its new size. */
    rtutDisplayFunc(swap_and_leave);
    rtutPostRedisplay();
    rtutMainLoop();
    viewport(&width, &height);
    CHECK(width == 8 && height == 8, "the resized window's frame buffer is 8 x 8, not %d x %d", width, height);
    rtResetContext();
}

/* ----- stale_handles ----- */

static void stale_handles(void) {
    static unsigned char pixels[16 * 16 * 4];
    quad(0.0f, 1.0f, 0.0f, 20.0f);
    rtFrameBuffer(pixels, 16, 16, RT_RGBA8);
    RTuint before = rtRenderFrameAsync();
    CHECK(before != 0, "the first frame");
    rtResetContext();

    quad(0.0f, 1.0f, 0.0f, 20.0f);
    rtFrameBuffer(pixels, 16, 16, RT_RGBA8);
    memset(pixels, 0, sizeof pixels);
    RTuint after = rtRenderFrameAsync();
    CHECK(after != 0 && after != before, "a frame after rtResetContext has a new handle (%u, then %u)", before, after);
    rtFrameRelease(before);
    error_is("releasing the stale handle", RT_INVALID_VALUE, "was released");
    CHECK(rtFrameWait(after) == RT_NO_ERROR, "the new frame completes: the stale handle did not cancel it");
    CHECK(pixels[(8 * 16 + 8) * 4 + 1] > 200, "the new frame's image arrived (green %d)", pixels[(8 * 16 + 8) * 4 + 1]);
    rtFrameRelease(after);
    no_error("the new frame");
    rtResetContext();
}

/* ----- failed_rtut_swap ----- */

static RTuint defined_object = 0;
static float channel[16 * 16];

static void refused_swaps(void) {
    /* Inside an object's definition: refused. */
    rtNewObject(defined_object, RT_COMPILE);
    rtutSwapBuffers();
    error_is("rtutSwapBuffers inside rtNewObject", RT_INVALID_OPERATION, "rtEndObject");
    rtEndObject();
    rtGetError();
    /* A channel lent at the program's size, not the window's: refused. */
    rtChannelBuffer(RT_DEPTH_CHANNEL, channel, 16, 16);
    rtutSwapBuffers();
    error_is("rtutSwapBuffers with a channel of another size", RT_INVALID_OPERATION, "same size");
    rtutLeaveMainLoop();
}

static void failed_rtut_swap(void) {
    static unsigned char pixels[16 * 16 * 4];
    quad(0.0f, 0.0f, 1.0f, 20.0f);
    defined_object = rtGenObjects(1);
    rtFrameBuffer(pixels, 16, 16, RT_RGBA8);
    rtutInitWindowSize(64, 64);
    rtutDisplayFunc(refused_swaps);
    rtutPostRedisplay();
    rtutMainLoop();
    no_error("the loop");

    /* The program's frame buffer is still the context's: its size, and the next frame. */
    RTint width, height;
    viewport(&width, &height);
    CHECK(width == 16 && height == 16, "the program's 16 x 16 frame buffer, not %d x %d", width, height);
    rtSwapBuffers();
    no_error("rtSwapBuffers after the refused swaps");
    CHECK(pixels[(8 * 16 + 8) * 4 + 2] > 200, "the frame went to the program's pixels (blue %d)", pixels[(8 * 16 + 8) * 4 + 2]);
    CHECK(channel[8 * 16 + 8] > 5.9f && channel[8 * 16 + 8] < 6.1f, "the depth channel reads %g, not 6", channel[8 * 16 + 8]);
    rtChannelBuffer(RT_DEPTH_CHANNEL, NULL, 0, 0);
    no_error("taking the channel back");
    rtResetContext();
}

/* ----- far_orthographic ----- */

static void far_orthographic(void) {
    enum { S = 8 };
    static unsigned char pixels[S * S * 4];
    static float depth[S * S], z[S * S];
    static RTuint instances[S * S];
    /* The largest scene and camera the limits allow: a quad to RT_MAX_COORDINATE, the eye there,
     * rays starting as far behind it. */
    RTuint instance = quad(1.0f, 1.0f, 1.0f, RT_MAX_COORDINATE);
    rtLookAt(RT_MAX_COORDINATE, RT_MAX_COORDINATE, RT_MAX_COORDINATE, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f);
    no_error("a camera at RT_MAX_COORDINATE");
    rtOrtho(-2.0, 2.0, -2.0, 2.0, -1e30, 10.0);
    error_is("znear far beyond RT_MAX_COORDINATE", RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE");
    rtLookAt(1e30f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f);
    error_is("an eye beyond RT_MAX_COORDINATE", RT_INVALID_VALUE, "beyond RT_MAX_COORDINATE");
    rtOrtho(-2.0, 2.0, -2.0, 2.0, -RT_MAX_COORDINATE, RT_MAX_COORDINATE);
    no_error("znear at -RT_MAX_COORDINATE");

    rtFrameBuffer(pixels, S, S, RT_RGBA8);
    rtChannelBuffer(RT_DEPTH_CHANNEL, depth, S, S);
    rtChannelBuffer(RT_Z_CHANNEL, z, S, S);
    rtChannelBuffer(RT_INSTANCE_ID_CHANNEL, instances, S, S);
    rtSwapBuffers();
    no_error("the far orthographic frame");
    int seen = 0;
    for (RTuint y = 0; y < S; ++y) {
        for (RTuint x = 0; x < S; ++x) {
            RTuint i = y * S + x, picked = 0;
            RTboolean hit = rtPick(x, y, &picked, NULL, NULL);
            int surface = instances[i] != 0 || hit || isfinite(depth[i]) || isfinite(z[i]);
            seen += surface;
            if (surface) {
                CHECK(instances[i] == instance && hit && picked == instance, "pixel (%u, %u): instance channel %u, pick %d (%u)", x, y,
                      instances[i], hit, picked);
                CHECK(isfinite(depth[i]) && depth[i] > 0.0f, "pixel (%u, %u): depth %g where the surface is seen", x, y, depth[i]);
                CHECK(isfinite(z[i]), "pixel (%u, %u): z %g where the surface is seen", x, y, z[i]);
            }
        }
    }
    CHECK(seen == S * S, "the quad fills the view (%d of %d pixels)", seen, S * S);
    rtResetContext();
}

int main(void) {
    setenv("RTUT_HEADLESS", "1", 1);
    setenv("RTUT_OUTPUT", "call-sequences", 1);
    window_resize();
    stale_handles();
    failed_rtut_swap();
    far_orthographic();
    return failures != 0;
}
