/*
 * eight_cubes.c: the OpenRT example of the seed (Wald, "The OpenRT API", §2.4): a cube with
 * vertex colours, defined once as an object, instantiated eight times and re-instantiated every
 * frame with a new rotation. The window of the original (RTUT, a GLUT replacement) is replaced by
 * a frame buffer in memory that each frame is rendered into and written out as a PNG file.
 *
 * Usage: eight_cubes [FRAMES [WIDTH HEIGHT]]   writes eight_cubes_000.png, eight_cubes_001.png, ...
 */
#include <raystage/rt.h>

#include <stdio.h>
#include <stdlib.h>

/* Stops the program with raystage's message if a call failed. */
static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "eight_cubes: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

/* The unit cube's six sides, four corners each, counter-clockwise seen from outside. */
static const float corners[6][4][3] = {
    {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, /* z = 0 */
    {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, /* z = 1 */
    {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, /* y = 0 */
    {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, /* y = 1 */
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, /* x = 0 */
    {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, /* x = 1 */
};

static RTuint create_color_cube_object(void) {
    /* Step 1: define the class of a vertex colour shader. */
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "VertexColor", NULL); /* built in: no shader library to load */
    /* Step 2: create one instance of that class. */
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid); /* a shader of the bound class */
    /* Step 3: define the object. */
    RTuint obj_id = rtGenObjects(1);
    rtNewObject(obj_id, RT_COMPILE);
    /* Step 3a: bind the shader. */
    rtBindShader(sid);
    /* Step 3b: transforms: scale the cube to [-1, 1]^3. */
    rtMatrixMode(RT_MODELVIEW);
    rtPushMatrix();
    rtLoadIdentity();
    rtTranslatef(-1, -1, -1);
    rtScalef(2, 2, 2);
    /* Step 3c: issue the geometry, each corner coloured by its position. */
    for (int side = 0; side < 6; side++) {
        rtBegin(RT_POLYGON);
        for (int k = 0; k < 4; k++) {
            rtColor3fv(corners[side][k]);
            rtVertex3fv(corners[side][k]);
        }
        rtEnd();
    }
    rtPopMatrix();
    rtEndObject();
    check("defining the cube");
    return obj_id;
}

int main(int argc, char *argv[]) {
    int frames = argc > 1 ? atoi(argv[1]) : 8;
    size_t width = argc > 3 ? (size_t)atoi(argv[2]) : 320;
    size_t height = argc > 3 ? (size_t)atoi(argv[3]) : 240;
    unsigned char *pixels = malloc(width * height * 4);
    if (pixels == NULL) {
        return 1;
    }
    rtFrameBuffer(pixels, width, height, RT_RGBA8);

    rtPerspective(65, 1, 1, 100000);
    rtLookAt(2, 4, 3, 0, 0, 0, 0, 0, 1);
    check("setting up the camera");

    /* Generate the object once. */
    RTuint obj_id = create_color_cube_object();

    for (int rot = 0; rot < frames; rot++) {
        /* Instantiate the object eight times, every frame with a new transformation. */
        rtDeleteAllInstances();
        for (int i = 0; i < 8; i++) {
            int dx = (i & 1) ? -1 : 1;
            int dy = (i & 2) ? -1 : 1;
            int dz = (i & 4) ? -1 : 1;
            rtLoadIdentity();
            rtTranslatef(dx, dy, dz);
            rtRotatef(4 * rot * dx, dz, dy, dx);
            rtScalef(.5, .5, .5);
            rtInstantiateObject(obj_id);
        }
        /* Render, and "display" the image. */
        rtSwapBuffers();
        char name[64];
        snprintf(name, sizeof name, "eight_cubes_%03d.png", rot);
        rtWritePNG(name);
        check("rendering a frame");
    }
    free(pixels);
    return 0;
}
