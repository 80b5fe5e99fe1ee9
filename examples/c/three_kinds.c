/*
 * three_kinds.c: an animation with the three kinds of objects of the seed's dynamic scenes
 * (Wald, "Handling Dynamic Scenes"; docs/design/seeds.md §1.3):
 *  - static:       the ground and a flag pole, defined once, never changed;
 *  - animated:     a cube that spins and bobs, moved every frame with rtMoveInstance only;
 *  - unstructured: a flag waving in the wind, redefined every frame (rtNewObject on the same id)
 *                  from arrays with rtTriangleMesh; its tree is refitted, not rebuilt.
 * Lit by a sun (a "DirectionalLight" shader) and a lamp (a "PointLight" shader), with shadows.
 *
 * Usage: three_kinds [FRAMES [WIDTH HEIGHT]] [--mpi]   writes three_kinds_000.png, ...
 * With --mpi, under `mpirun -n N`, every frame is rendered by all N ranks (rtInitMPI): the
 * program runs on rank 0, the other ranks render with it, and the frames are the same bytes.
 */
#include <raystage/rt.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FLAG_COLUMNS 24
#define FLAG_ROWS 12
#define FLAG_VERTICES ((FLAG_COLUMNS + 1) * (FLAG_ROWS + 1))
#define FLAG_TRIANGLES (2 * FLAG_COLUMNS * FLAG_ROWS)

static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "three_kinds: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

/* A shader of class `cls` with its colour parameter `name` set to (r, g, b). */
static RTuint shader(RTuint cls, const char *name, RTfloat r, RTfloat g, RTfloat b) {
    RTuint id = rtGenShaders(1);
    rtBindShaderClass(cls);
    rtNewShader(id);
    rtParameter3f(rtParameterHandle(name), r, g, b);
    return id;
}

/* An axis-aligned box from (x0, y0, z0) to (x1, y1, z1), one flat quad per side. */
static void box(RTfloat x0, RTfloat y0, RTfloat z0, RTfloat x1, RTfloat y1, RTfloat z1) {
    const RTfloat x[2] = {x0, x1}, y[2] = {y0, y1}, z[2] = {z0, z1};
    /* For each side: the axis it faces along, the side (0 low, 1 high), and the corner order. */
    static const int sides[6][4][3] = {
        {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
    };
    rtBegin(RT_QUADS);
    for (int s = 0; s < 6; s++) {
        RTfloat sign = (s % 2) ? 1.0f : -1.0f;
        rtNormal3f(s / 2 == 2 ? sign : 0, s / 2 == 1 ? sign : 0, s / 2 == 0 ? sign : 0);
        for (int k = 0; k < 4; k++) {
            rtVertex3f(x[sides[s][k][0]], y[sides[s][k][1]], z[sides[s][k][2]]);
        }
    }
    rtEnd();
}

/* The flag at time t: a 3 × 1.5 cloth in the xy plane that waves along z. */
static void define_flag(RTuint flag, RTuint stripes, float t) {
    static RTfloat positions[FLAG_VERTICES][3], normals[FLAG_VERTICES][3], colors[FLAG_VERTICES][3];
    static RTuint indices[FLAG_TRIANGLES][3];
    for (int j = 0; j <= FLAG_ROWS; j++) {
        for (int i = 0; i <= FLAG_COLUMNS; i++) {
            int v = j * (FLAG_COLUMNS + 1) + i;
            float u = (float)i / FLAG_COLUMNS, w = (float)j / FLAG_ROWS;
            /* The wave grows away from the pole and travels along the flag. */
            float phase = 6.0f * u - 4.0f * t, amplitude = 0.35f * u;
            positions[v][0] = 3.0f * u;
            positions[v][1] = 1.5f * w - 0.3f * u * u;
            positions[v][2] = amplitude * sinf(phase);
            /* Normal of z = a(u) sin(phase(u)): (-dz/dx, 0, 1), with x = 3u. */
            float dzdx = (0.35f * sinf(phase) + amplitude * 6.0f * cosf(phase)) / 3.0f;
            normals[v][0] = -dzdx;
            normals[v][1] = 0.0f;
            normals[v][2] = 1.0f;
            int stripe = (int)(w * 3.0f) % 3;
            colors[v][0] = stripe == 1 ? 1.0f : 0.9f;
            colors[v][1] = stripe == 1 ? 1.0f : 0.15f;
            colors[v][2] = stripe == 1 ? 1.0f : 0.1f;
        }
    }
    for (int j = 0, t3 = 0; j < FLAG_ROWS; j++) {
        for (int i = 0; i < FLAG_COLUMNS; i++, t3 += 2) {
            RTuint a = j * (FLAG_COLUMNS + 1) + i, b = a + 1, c = a + FLAG_COLUMNS + 2, d = a + FLAG_COLUMNS + 1;
            indices[t3][0] = a, indices[t3][1] = b, indices[t3][2] = c;
            indices[t3 + 1][0] = a, indices[t3 + 1][1] = c, indices[t3 + 1][2] = d;
        }
    }
    rtNewObject(flag, RT_COMPILE); /* the same id again: every instance follows */
    rtBindShader(stripes);
    /* Vertices are transformed by the modelview matrix as they are issued: issue the flag in
     * its own coordinates, whatever the caller's matrix is. */
    rtPushMatrix();
    rtLoadIdentity();
    rtTriangleMesh(&positions[0][0], &normals[0][0], &colors[0][0], NULL, FLAG_VERTICES, &indices[0][0], FLAG_TRIANGLES);
    rtPopMatrix();
    rtEndObject();
}

int main(int argc, char *argv[]) {
    /* First of all: on every rank but 0, rtInitMPI renders until rank 0 is done, then exits. */
    int mpi = argc > 1 && strcmp(argv[argc - 1], "--mpi") == 0;
    if (mpi) {
        argc--;
        RTint ranks = rtInitMPI();
        check("joining the MPI job");
        printf("rendering on %d MPI ranks\n", ranks);
    }
    int frames = argc > 1 ? atoi(argv[1]) : 12;
    size_t width = argc > 3 ? (size_t)atoi(argv[2]) : 480;
    size_t height = argc > 3 ? (size_t)atoi(argv[3]) : 270;
    unsigned char *pixels = malloc(width * height * 4);
    if (pixels == NULL) {
        return 1;
    }
    rtFrameBuffer(pixels, width, height, RT_RGBA8);
    rtPerspective(40, (float)width / (float)height, 0.1f, 100);
    rtLookAt(1.5f, 3.0f, 10.0f, 0.5f, 1.4f, 0, 0, 1, 0);

    RTuint classes = rtGenShaderClasses(4);
    rtNewShaderClass(classes, "Diffuse", NULL);
    rtNewShaderClass(classes + 1, "VertexColor", NULL);
    rtNewShaderClass(classes + 2, "DirectionalLight", NULL);
    rtNewShaderClass(classes + 3, "PointLight", NULL);
    RTuint grey = shader(classes, "diffuse", 0.7f, 0.7f, 0.65f);
    RTuint orange = shader(classes, "diffuse", 0.9f, 0.45f, 0.1f);
    RTuint stripes = shader(classes + 1, "diffuse", 1, 1, 1);
    shader(classes + 2, "intensity", 2.2f, 2.1f, 1.9f);
    rtParameter3f(rtParameterHandle("direction"), -0.4f, -1.0f, -0.6f);
    shader(classes + 3, "intensity", 6, 6, 7);
    rtParameter3f(rtParameterHandle("position"), -3, 3, 3);
    shader(classes + 2, "intensity", 0.5f, 0.55f, 0.6f); /* fill light from the viewer's side */
    rtParameter3f(rtParameterHandle("direction"), 0.1f, -0.3f, -1.0f);
    check("making the shaders");

    RTuint ground = rtGenObjects(3), cube = ground + 1, flag = ground + 2;

    rtObjectKind(RT_STATIC);
    rtNewObject(ground, RT_COMPILE);
    rtBindShader(grey);
    rtNormal3f(0, 1, 0);
    rtBegin(RT_QUADS);
    rtVertex3f(-12, 0, -12);
    rtVertex3f(-12, 0, 12);
    rtVertex3f(12, 0, 12);
    rtVertex3f(12, 0, -12);
    rtEnd();
    box(-0.05f, 0, -0.05f, 0.05f, 3.2f, 0.05f); /* the pole */
    rtEndObject();

    rtObjectKind(RT_ANIMATED);
    rtNewObject(cube, RT_COMPILE);
    rtBindShader(orange);
    box(-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f);
    rtEndObject();

    rtObjectKind(RT_UNSTRUCTURED);
    define_flag(flag, stripes, 0);
    check("defining the objects");

    rtLoadIdentity();
    rtInstantiateObject(ground);
    rtTranslatef(0, 1.6f, 0);
    rtInstantiateObject(flag);
    RTuint spinning = rtInstantiateObject(cube);
    check("placing the instances");

    for (int frame = 0; frame < frames; frame++) {
        float t = frame / 8.0f;
        rtLoadIdentity();
        rtTranslatef(-2.5f, 0.9f + 0.3f * sinf(2 * t), 1.5f);
        rtRotatef(40.0f * frame, 0.3f, 1, 0.2f);
        rtMoveInstance(spinning);
        define_flag(flag, stripes, t);
        rtSwapBuffers();
        char name[64];
        snprintf(name, sizeof name, "three_kinds_%03d.png", frame);
        rtWritePNG(name);
        check("rendering a frame");
    }
    if (mpi) {
        rtFinishMPI(); /* the other ranks exit */
        check("leaving the MPI job");
    }
    free(pixels);
    return 0;
}
