/*
 * late_binding.c: the seed's example of frame semantics (Wald, "The OpenRT API", §2.5.1):
 *
 *     diffuse = red;   <triangle A>
 *     diffuse = green; <triangle B>
 *     rtSwapBuffers();
 *
 * gives two green triangles, not a red and a green one as in OpenGL: both triangles refer to the
 * same shader, and its "diffuse" parameter is green when the frame is rendered.
 *
 * Usage: late_binding   writes late_binding.png (160 × 80)
 */
#include <raystage/rt.h>

#include <stdio.h>
#include <stdlib.h>

static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "late_binding: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

static void triangle(float x) {
    rtBegin(RT_TRIANGLES);
    rtVertex3f(x - 1.2f, -1.0f, 0.0f);
    rtVertex3f(x + 1.2f, -1.0f, 0.0f);
    rtVertex3f(x, 1.0f, 0.0f);
    rtEnd();
}

int main(void) {
    static unsigned char pixels[160 * 80 * 4];
    rtFrameBuffer(pixels, 160, 80, RT_RGBA8);
    rtLookAt(0, 0, 5, 0, 0, 0, 0, 1, 0);

    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Diffuse", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    RTint diffuse = rtParameterHandle("diffuse");

    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtParameter3f(diffuse, 1.f, 0.f, 0.f);
    triangle(-1.5f); /* triangle A */
    rtParameter3f(diffuse, 0.f, 1.f, 0.f);
    triangle(1.5f); /* triangle B */
    rtEndObject();
    rtInstantiateObject(object);
    check("building the scene");

    rtSwapBuffers(); /* render the frame: both triangles are green */
    rtWritePNG("late_binding.png");
    check("rendering");
    return 0;
}
