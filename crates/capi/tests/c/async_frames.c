/*
 * async_frames.c: asynchronous frames as an interactive C program uses them: start a frame,
 * keep working while it renders, poll its progress, read the image once it is ready; edit the
 * scene while a frame renders (frame semantics: the edit belongs to the next frame); cancel a
 * long frame and find that it stops at once; two threads rendering on their own contexts at the
 * same time; and bad handles and calls in the wrong state refused with the right code and
 * message.
 *
 * Prints each failed check and exits 1 if any failed (run by crates/capi/tests/examples.rs).
 */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define W 64
#define H 32
#define BIG 512

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* A quad filling the view of a camera at z = 6, of a Constant shader coloured (r, g, b), which
 * stays bound; returns the handle of its "color". */
static RTint constant_quad(float r, float g, float b) {
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Constant", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    RTint color = rtParameterHandle("color");
    rtParameter3f(color, r, g, b);
    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    rtVertex3f(-20.0f, -20.0f, 0.0f);
    rtVertex3f(20.0f, -20.0f, 0.0f);
    rtVertex3f(20.0f, 20.0f, 0.0f);
    rtVertex3f(-20.0f, 20.0f, 0.0f);
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0f, 0.0f, 6.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f);
    no_error("the quad");
    return color;
}

/* Every pixel of a w × h RGBA8 image is (r, g, b) within 2. */
static int all_pixels(const unsigned char *pixels, int w, int h, int r, int g, int b) {
    for (int i = 0; i < w * h; i++) {
        const unsigned char *p = &pixels[i * 4];
        if (abs(p[0] - r) > 2 || abs(p[1] - g) > 2 || abs(p[2] - b) > 2) return 0;
    }
    return 1;
}

/* Start a frame, keep working, poll progress; an edit made meanwhile is not in the frame. */
static void interactive_loop(void) {
    static unsigned char pixels[W * H * 4];
    RTint color = constant_quad(1.0f, 0.0f, 0.0f);
    rtFrameBuffer(pixels, W, H, RT_RGBA8);
    RTuint frame = rtRenderFrameAsync();
    CHECK(frame != 0, "rtRenderFrameAsync: %s", rtGetErrorString());
    rtParameter3f(color, 0.0f, 0.0f, 1.0f); /* the next frame's colour */
    no_error("editing while the frame renders");

    float last = 0.0f;
    while (!rtFrameIsReady(frame)) {
        /* The application handles its input here; it only watches the progress. */
        float progress = rtFrameProgress(frame);
        CHECK(progress >= last && progress <= 1.0f, "progress went from %g to %g", last, progress);
        last = progress;
    }
    CHECK(rtFrameProgress(frame) == 1.0f, "a completed frame's progress is %g", rtFrameProgress(frame));
    CHECK(rtFrameWait(frame) == RT_NO_ERROR, "rtFrameWait of a completed frame");
    CHECK(all_pixels(pixels, W, H, 255, 0, 0), "the frame is not all red: the edit after its start leaked in");
    rtFrameRelease(frame);
    no_error("the interactive loop");

    rtSwapBuffers();
    CHECK(all_pixels(pixels, W, H, 0, 0, 255), "the next frame is not all blue");
    no_error("rtSwapBuffers after the asynchronous frame");
    rtResetContext();
}

/* A long frame, cancelled once it has made progress, stops at once and leaves the buffer. */
static void cancel_stops_work(void) {
    static unsigned char pixels[BIG * BIG * 4];
    constant_quad(0.8f, 0.8f, 0.8f);
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "PointLight", NULL);
    RTuint light = rtGenShaders(1);
    rtNewShader(light);
    rtParameter3f(rtParameterHandle("position"), 0.0f, 3.0f, 3.0f);
    rtParameter3f(rtParameterHandle("intensity"), 20.0f, 20.0f, 20.0f);
    rtRenderMode(RT_PATH);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 1024);
    rtFrameBuffer(pixels, BIG, BIG, RT_RGBA8);
    no_error("the long frame's scene");

    RTuint frame = rtRenderFrameAsync();
    double start = now();
    while (rtFrameProgress(frame) == 0.0f && now() - start < 120.0) sleep_ms(5);
    float before = rtFrameProgress(frame);
    CHECK(before > 0.0f && before < 1.0f, "progress %g after %.1f s", before, now() - start);
    rtFrameCancel(frame);
    double cancelled = now();
    CHECK(rtFrameWait(frame) == RT_CANCELLED, "rtFrameWait after rtFrameCancel");
    CHECK(now() - cancelled < 3.0, "rtFrameWait took %.2f s after rtFrameCancel", now() - cancelled);
    float stopped = rtFrameProgress(frame);
    sleep_ms(300);
    CHECK(rtFrameProgress(frame) == stopped && stopped < 1.0f, "progress went on: %g then %g", stopped, rtFrameProgress(frame));
    CHECK(all_pixels(pixels, BIG, BIG, 0, 0, 0), "a cancelled frame wrote the frame buffer");
    CHECK(rtFrameIsReady(frame) == 1, "a cancelled frame is ready");
    rtFrameRelease(frame);
    no_error("cancelling");
    rtResetContext();
}

/* One frame in flight per context; handles that name no frame. */
static void wrong_state_and_bad_handles(void) {
    static unsigned char pixels[W * H * 4];
    CHECK(rtRenderFrameAsync() == 0, "a frame without a frame buffer");
    error_is("rtRenderFrameAsync without a frame buffer", RT_INVALID_OPERATION, "no frame buffer");
    constant_quad(0.0f, 1.0f, 0.0f);
    rtFrameBuffer(pixels, W, H, RT_RGBA8);
    RTuint frame = rtRenderFrameAsync();
    rtSwapBuffers();
    error_is("rtSwapBuffers in flight", RT_INVALID_OPERATION, "is in flight");
    CHECK(rtRenderFrameAsync() == 0, "a second frame in flight");
    error_is("rtRenderFrameAsync in flight", RT_INVALID_OPERATION, "is in flight");
    rtFrameBuffer(NULL, 0, 0, RT_RGBA8);
    error_is("rtFrameBuffer in flight", RT_INVALID_OPERATION, "rtFrameBuffer while frame");
    CHECK(rtFrameWait(frame) == RT_NO_ERROR, "the frame completes");
    CHECK(all_pixels(pixels, W, H, 0, 255, 0), "the frame is not all green");
    rtFrameRelease(frame);
    no_error("the frame");

    CHECK(rtFrameWait(frame) == RT_INVALID_VALUE, "rtFrameWait of a released frame");
    error_is("rtFrameWait of a released frame", RT_INVALID_VALUE, "was released");
    rtFrameRelease(frame);
    error_is("rtFrameRelease twice", RT_INVALID_VALUE, "was released");
    CHECK(rtFrameWait(0) == RT_INVALID_VALUE, "rtFrameWait(0)");
    error_is("rtFrameWait(0)", RT_INVALID_VALUE, "frame handle 0 names no frame");
    CHECK(rtFrameIsReady(12345) == 0, "rtFrameIsReady of an unknown frame");
    error_is("rtFrameIsReady of an unknown frame", RT_INVALID_VALUE, "frame 12345 does not exist");
    CHECK(rtFrameProgress(12345) == 0.0f, "rtFrameProgress of an unknown frame");
    error_is("rtFrameProgress of an unknown frame", RT_INVALID_VALUE, "does not exist");
    rtFrameCancel(12345);
    error_is("rtFrameCancel of an unknown frame", RT_INVALID_VALUE, "does not exist");
    rtResetContext();
}

/* Two threads, each with its own context, each with a frame in flight at the same time. */
static pthread_barrier_t both_started;

static void *render_on_own_context(void *arg) {
    int channel = *(int *)arg;
    static unsigned char pixels[2][W * H * 4];
    float rgb[3] = {0.0f, 0.0f, 0.0f};
    rgb[channel] = 1.0f;
    constant_quad(rgb[0], rgb[1], rgb[2]);
    rtFrameBuffer(pixels[channel], W, H, RT_RGBA8);
    RTuint frame = rtRenderFrameAsync();
    CHECK(frame != 0, "thread %d: %s", channel, rtGetErrorString());
    pthread_barrier_wait(&both_started);
    CHECK(rtFrameWait(frame) == RT_NO_ERROR, "thread %d's frame", channel);
    CHECK(all_pixels(pixels[channel], W, H, channel == 0 ? 255 : 0, channel == 1 ? 255 : 0, 0), "thread %d's frame is not its colour",
          channel);
    rtFrameRelease(frame);
    no_error("a thread's frame");
    return NULL;
}

static void two_contexts(void) {
    pthread_t threads[2];
    int channels[2] = {0, 1};
    pthread_barrier_init(&both_started, NULL, 2);
    for (int i = 0; i < 2; i++) pthread_create(&threads[i], NULL, render_on_own_context, &channels[i]);
    for (int i = 0; i < 2; i++) pthread_join(threads[i], NULL);
    pthread_barrier_destroy(&both_started);
}

int main(void) {
    interactive_loop();
    cancel_stops_work();
    wrong_state_and_bad_handles();
    two_contexts();
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("async_frames.c: all checks passed\n");
    return 0;
}
