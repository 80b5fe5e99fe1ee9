/*
 * motion_blur.c: Cook's distribution ray tracing from C. An orange cube slides across the ground
 * while the shutter is open, so it is smeared along its path; a thin lens focused on it blurs
 * the poles behind. The same frame is written twice: with the shutter open (motion_blur.png) and
 * taking an instant (motion_blur_still.png), where only the lens blurs.
 *
 * Usage: motion_blur [WIDTH HEIGHT [SAMPLES]]   (default 320 180, 32 samples per pixel)
 */
#include <raystage/rt.h>

#include <stdio.h>
#include <stdlib.h>

static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "motion_blur: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

/* A Diffuse shader of colour (r, g, b). */
static RTuint diffuse(RTuint cls, RTfloat r, RTfloat g, RTfloat b) {
    RTuint id = rtGenShaders(1);
    rtBindShaderClass(cls);
    rtNewShader(id);
    rtParameter3f(rtParameterHandle("diffuse"), r, g, b);
    return id;
}

/* An axis-aligned box from (x0, y0, z0) to (x1, y1, z1), as one flat quad per side. */
static void box(RTfloat x0, RTfloat y0, RTfloat z0, RTfloat x1, RTfloat y1, RTfloat z1) {
    const RTfloat c[8][3] = {{x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0},
                             {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}};
    /* Corners of each side, counter-clockwise seen from outside. */
    static const int sides[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    rtBegin(RT_QUADS);
    for (int s = 0; s < 6; s++) {
        for (int k = 0; k < 4; k++) {
            rtVertex3fv(c[sides[s][k]]);
        }
    }
    rtEnd();
}

int main(int argc, char *argv[]) {
    size_t width = argc > 2 ? (size_t)atoi(argv[1]) : 320;
    size_t height = argc > 2 ? (size_t)atoi(argv[2]) : 180;
    int samples = argc > 3 ? atoi(argv[3]) : 32;
    unsigned char *pixels = malloc(width * height * 4);
    if (pixels == NULL) {
        return 1;
    }
    rtFrameBuffer(pixels, width, height, RT_RGBA8);
    rtPerspective(35, (float)width / (float)height, 0.1f, 100);
    rtLookAt(0, 2.5f, 9, 0, 0.5f, 0, 0, 1, 0);
    /* Focused on the cube, 9 units away: the poles 6 units behind it are blurred. */
    rtLens(0.3f, 9.2f);
    rtRenderMode(RT_DISTRIBUTION);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, samples);
    check("setting up the camera");

    RTuint classes = rtGenShaderClasses(2);
    rtNewShaderClass(classes, "Diffuse", NULL);
    rtNewShaderClass(classes + 1, "DirectionalLight", NULL);
    RTuint grey = diffuse(classes, 0.6f, 0.6f, 0.6f);
    RTuint orange = diffuse(classes, 0.9f, 0.4f, 0.05f);
    RTuint white = diffuse(classes, 0.9f, 0.9f, 0.9f);
    rtBindShaderClass(classes + 1);
    rtNewShader(rtGenShaders(1));
    rtParameter3f(rtParameterHandle("direction"), -0.3f, -1.0f, -0.5f);
    rtParameter3f(rtParameterHandle("intensity"), 2.5f, 2.5f, 2.4f);
    check("making the shaders");

    RTuint scenery = rtGenObjects(2), cube = scenery + 1;
    rtNewObject(scenery, RT_COMPILE);
    rtBindShader(grey);
    box(-20, -0.1f, -20, 20, 0, 20);
    rtBindShader(white);
    for (int i = -3; i <= 3; i++) {
        box(1.5f * i - 0.1f, 0, -6.1f, 1.5f * i + 0.1f, 3, -5.9f);
    }
    rtEndObject();
    rtObjectKind(RT_ANIMATED); /* it moves only through its instance */
    rtNewObject(cube, RT_COMPILE);
    rtBindShader(orange);
    box(-0.5f, 0, -0.5f, 0.5f, 1, 0.5f);
    rtEndObject();
    check("defining the objects");

    rtInstantiateObject(scenery);
    rtTranslatef(-1.5f, 0, 0);
    RTuint sliding = rtInstantiateObject(cube); /* where it is as the shutter opens */
    rtLoadIdentity();
    rtTranslatef(1.5f, 0, 0);
    rtInstanceMotion(sliding); /* ... and as it closes */
    check("placing the instances");

    rtShutter(0, 1);
    rtSwapBuffers();
    rtWritePNG("motion_blur.png");
    rtShutter(0, 0);
    rtSwapBuffers();
    rtWritePNG("motion_blur_still.png");
    check("rendering");
    free(pixels);
    return 0;
}
