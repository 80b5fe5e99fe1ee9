/*
 * gears.c: glxgears (Brian Paul's OpenGL demo, in the public domain) ported to raystage.
 *
 * The port renames gl -> rt, and the display lists become objects, which is what OpenRT asks of
 * an OpenGL program (docs/design/seeds.md §1.1). Every other change is marked "raystage:";
 * in short:
 *  - No window: each frame is rendered into memory and written as gears_NNN.png.
 *  - Materials are shaders: glMaterialfv(GL_AMBIENT_AND_DIFFUSE) becomes a "Diffuse" shader
 *    whose "diffuse" parameter is written by name.
 *  - Lights are light shaders: GL_LIGHT0 at (5, 5, 10, 0) (w = 0: directional) becomes a
 *    "DirectionalLight" shader, and OpenGL's global ambient light (0.2) an "AmbientLight"
 *    shader. Shadows come with the ray tracer.
 *  - The camera is not a matrix: glFrustum + glTranslatef(0, 0, -40) become rtPerspective +
 *    rtLookAt. glEnable(GL_CULL_FACE / GL_DEPTH_TEST / GL_NORMALIZE) have no counterpart and
 *    are dropped (nothing is culled, visibility is exact, normals are normalised when shaded).
 *  - glCallList(gear) inside the view transform becomes rtInstantiateObject(gear): the
 *    modelview matrix at that moment places the gear; each frame re-instantiates the three.
 *
 * Usage: gears [FRAMES [WIDTH HEIGHT]]
 */
#include <raystage/rt.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* raystage: stops the program with raystage's message if a call failed. */
static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "gears: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

/*
 * Draw a gear wheel. You'll probably want to call this function when building a display list
 * (raystage: an object) since we do a lot of trig here.
 *
 * Input:  inner_radius - radius of hole at center
 *         outer_radius - radius at center of teeth
 *         width - width of gear teeth - number of teeth
 *         tooth_depth - depth of tooth
 */
static void gear(RTfloat inner_radius, RTfloat outer_radius, RTfloat width, int teeth, RTfloat tooth_depth) {
    int i;
    RTfloat r0, r1, r2;
    RTfloat angle, da;
    RTfloat u, v, len;

    r0 = inner_radius;
    r1 = outer_radius - tooth_depth / 2.0;
    r2 = outer_radius + tooth_depth / 2.0;

    da = 2.0 * M_PI / teeth / 4.0;

    rtShadeModel(RT_FLAT);

    rtNormal3f(0.0, 0.0, 1.0);

    /* draw front face */
    rtBegin(RT_QUAD_STRIP);
    for (i = 0; i <= teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;
        rtVertex3f(r0 * cos(angle), r0 * sin(angle), width * 0.5);
        rtVertex3f(r1 * cos(angle), r1 * sin(angle), width * 0.5);
        if (i < teeth) {
            rtVertex3f(r0 * cos(angle), r0 * sin(angle), width * 0.5);
            rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), width * 0.5);
        }
    }
    rtEnd();

    /* draw front sides of teeth */
    rtBegin(RT_QUADS);
    da = 2.0 * M_PI / teeth / 4.0;
    for (i = 0; i < teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;

        rtVertex3f(r1 * cos(angle), r1 * sin(angle), width * 0.5);
        rtVertex3f(r2 * cos(angle + da), r2 * sin(angle + da), width * 0.5);
        rtVertex3f(r2 * cos(angle + 2 * da), r2 * sin(angle + 2 * da), width * 0.5);
        rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), width * 0.5);
    }
    rtEnd();

    rtNormal3f(0.0, 0.0, -1.0);

    /* draw back face */
    rtBegin(RT_QUAD_STRIP);
    for (i = 0; i <= teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;
        rtVertex3f(r1 * cos(angle), r1 * sin(angle), -width * 0.5);
        rtVertex3f(r0 * cos(angle), r0 * sin(angle), -width * 0.5);
        if (i < teeth) {
            rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), -width * 0.5);
            rtVertex3f(r0 * cos(angle), r0 * sin(angle), -width * 0.5);
        }
    }
    rtEnd();

    /* draw back sides of teeth */
    rtBegin(RT_QUADS);
    da = 2.0 * M_PI / teeth / 4.0;
    for (i = 0; i < teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;

        rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), -width * 0.5);
        rtVertex3f(r2 * cos(angle + 2 * da), r2 * sin(angle + 2 * da), -width * 0.5);
        rtVertex3f(r2 * cos(angle + da), r2 * sin(angle + da), -width * 0.5);
        rtVertex3f(r1 * cos(angle), r1 * sin(angle), -width * 0.5);
    }
    rtEnd();

    /* draw outward faces of teeth */
    rtBegin(RT_QUAD_STRIP);
    for (i = 0; i < teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;

        rtVertex3f(r1 * cos(angle), r1 * sin(angle), width * 0.5);
        rtVertex3f(r1 * cos(angle), r1 * sin(angle), -width * 0.5);
        u = r2 * cos(angle + da) - r1 * cos(angle);
        v = r2 * sin(angle + da) - r1 * sin(angle);
        len = sqrt(u * u + v * v);
        u /= len;
        v /= len;
        rtNormal3f(v, -u, 0.0);
        rtVertex3f(r2 * cos(angle + da), r2 * sin(angle + da), width * 0.5);
        rtVertex3f(r2 * cos(angle + da), r2 * sin(angle + da), -width * 0.5);
        rtNormal3f(cos(angle), sin(angle), 0.0);
        rtVertex3f(r2 * cos(angle + 2 * da), r2 * sin(angle + 2 * da), width * 0.5);
        rtVertex3f(r2 * cos(angle + 2 * da), r2 * sin(angle + 2 * da), -width * 0.5);
        u = r1 * cos(angle + 3 * da) - r2 * cos(angle + 2 * da);
        v = r1 * sin(angle + 3 * da) - r2 * sin(angle + 2 * da);
        rtNormal3f(v, -u, 0.0);
        rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), width * 0.5);
        rtVertex3f(r1 * cos(angle + 3 * da), r1 * sin(angle + 3 * da), -width * 0.5);
        rtNormal3f(cos(angle), sin(angle), 0.0);
    }

    rtVertex3f(r1 * cos(0), r1 * sin(0), width * 0.5);
    rtVertex3f(r1 * cos(0), r1 * sin(0), -width * 0.5);

    rtEnd();

    rtShadeModel(RT_SMOOTH);

    /* draw inside radius cylinder */
    rtBegin(RT_QUAD_STRIP);
    for (i = 0; i <= teeth; i++) {
        angle = i * 2.0 * M_PI / teeth;
        rtNormal3f(-cos(angle), -sin(angle), 0.0);
        rtVertex3f(r0 * cos(angle), r0 * sin(angle), -width * 0.5);
        rtVertex3f(r0 * cos(angle), r0 * sin(angle), width * 0.5);
    }
    rtEnd();
}

static RTfloat view_rotx = 20.0, view_roty = 30.0, view_rotz = 0.0;
static RTuint gear1, gear2, gear3;
static RTfloat angle = 0.0;

static void draw(void) {
    /* raystage: instances replace the previous frame's. */
    rtDeleteAllInstances();

    rtPushMatrix();
    rtRotatef(view_rotx, 1.0, 0.0, 0.0);
    rtRotatef(view_roty, 0.0, 1.0, 0.0);
    rtRotatef(view_rotz, 0.0, 0.0, 1.0);

    rtPushMatrix();
    rtTranslatef(-3.0, -2.0, 0.0);
    rtRotatef(angle, 0.0, 0.0, 1.0);
    rtInstantiateObject(gear1);
    rtPopMatrix();

    rtPushMatrix();
    rtTranslatef(3.1, -2.0, 0.0);
    rtRotatef(-2.0 * angle - 9.0, 0.0, 0.0, 1.0);
    rtInstantiateObject(gear2);
    rtPopMatrix();

    rtPushMatrix();
    rtTranslatef(-3.1, 4.2, 0.0);
    rtRotatef(-2.0 * angle - 25.0, 0.0, 0.0, 1.0);
    rtInstantiateObject(gear3);
    rtPopMatrix();

    rtPopMatrix();
}

/* new window size or exposure */
static void reshape(int width, int height) {
    RTfloat h = (RTfloat)height / (RTfloat)width;
    /* raystage: glFrustum(-1, 1, -h, h, 5, 60) sees h / 5 up and down at distance 5, and
     * glTranslatef(0, 0, -40) puts the eye 40 units in front of the gears. */
    rtPerspective(2.0 * atan(h / 5.0) * 180.0 / M_PI, 1.0 / h, 5.0, 60.0);
    rtLookAt(0.0, 0.0, 40.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
}

/* raystage: a "Diffuse" shader with the colour of glMaterialfv(GL_AMBIENT_AND_DIFFUSE). */
static RTuint material(RTuint diffuse_class, const RTfloat color[4]) {
    RTuint shader = rtGenShaders(1);
    rtBindShaderClass(diffuse_class);
    rtNewShader(shader);
    rtParameter3fv(rtParameterHandle("diffuse"), color);
    return shader;
}

/* raystage: a light shader of class `light_class` with intensity `intensity` as OpenGL counts
 * it: irradiance pi makes a white surface facing the light exactly white. */
static void light(RTuint light_class, RTfloat intensity) {
    rtBindShaderClass(light_class);
    rtNewShader(rtGenShaders(1));
    rtParameter3f(rtParameterHandle("intensity"), intensity * M_PI, intensity * M_PI, intensity * M_PI);
}

static void init(void) {
    static RTfloat pos[4] = {5.0, 5.0, 10.0, 0.0};
    static RTfloat red[4] = {0.8, 0.1, 0.0, 1.0};
    static RTfloat green[4] = {0.0, 0.8, 0.2, 1.0};
    static RTfloat blue[4] = {0.2, 0.2, 1.0, 1.0};

    RTuint classes = rtGenShaderClasses(3);
    rtNewShaderClass(classes, "Diffuse", NULL);
    rtNewShaderClass(classes + 1, "DirectionalLight", NULL);
    rtNewShaderClass(classes + 2, "AmbientLight", NULL);
    /* raystage: GL_LIGHT0 at pos with w = 0 shines from pos towards the origin. */
    light(classes + 1, 1.0);
    rtParameter3f(rtParameterHandle("direction"), -pos[0], -pos[1], -pos[2]);
    light(classes + 2, 0.2);

    /* make the gears */
    gear1 = rtGenObjects(1);
    rtNewObject(gear1, RT_COMPILE);
    rtBindShader(material(classes, red));
    gear(1.0, 4.0, 1.0, 20, 0.7);
    rtEndObject();

    gear2 = rtGenObjects(1);
    rtNewObject(gear2, RT_COMPILE);
    rtBindShader(material(classes, green));
    gear(0.5, 2.0, 2.0, 10, 0.7);
    rtEndObject();

    gear3 = rtGenObjects(1);
    rtNewObject(gear3, RT_COMPILE);
    rtBindShader(material(classes, blue));
    gear(1.3, 2.0, 0.5, 10, 0.7);
    rtEndObject();
    check("making the gears");
}

int main(int argc, char *argv[]) {
    int frames = argc > 1 ? atoi(argv[1]) : 8;
    int width = argc > 3 ? atoi(argv[2]) : 300;
    int height = argc > 3 ? atoi(argv[3]) : 300;
    /* raystage: the frame buffer is the program's memory. */
    unsigned char *pixels = malloc((size_t)width * (size_t)height * 4);
    if (pixels == NULL) {
        return 1;
    }
    rtFrameBuffer(pixels, (size_t)width, (size_t)height, RT_RGBA8);

    init();
    reshape(width, height);
    for (int frame = 0; frame < frames; frame++) {
        draw();
        rtSwapBuffers();
        char name[64];
        snprintf(name, sizeof name, "gears_%03d.png", frame);
        rtWritePNG(name);
        check("rendering a frame");
        angle += 2.0;
    }
    free(pixels);
    return 0;
}
