/*
 * textures.c: textures from C, named, bound and filled as in OpenGL. A checkerboard floor
 * (a procedural texture), a picture on a panel (an 8-bit sRGB image made in memory and given
 * with rtTexImage2D), and a sky that lights everything: an environment light whose map is a
 * high-dynamic-range image of floats, or the Radiance .hdr file named on the command line
 * (loaded with rtTexImageFile). Rendered by the path tracer.
 *
 * Usage: textures [SKY.hdr]   writes textures.png (240 × 160)
 */
#include <raystage/rt.h>

#include <stdio.h>
#include <stdlib.h>

static void check(const char *what) {
    RTenum error = rtGetError();
    if (error != RT_NO_ERROR) {
        fprintf(stderr, "textures: %s: %s (error 0x%x)\n", what, rtGetErrorString(), (unsigned)error);
        exit(1);
    }
}

/* A Diffuse shader of class `cls`, white, textured with `texture`. */
static RTuint textured(RTuint cls, RTuint texture) {
    RTuint id = rtGenShaders(1);
    rtBindShaderClass(cls);
    rtNewShader(id);
    rtParameter3f(rtParameterHandle("diffuse"), 1.f, 1.f, 1.f);
    rtParameterTexture(rtParameterHandle("diffuse_texture"), texture);
    return id;
}

/* A quad with texture coordinates from (0, 0) at its first corner to (1, 1) at its third. */
static void quad(const float c[4][3]) {
    static const float st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    rtBegin(RT_QUADS);
    for (int i = 0; i < 4; i++) {
        rtTexCoord2f(st[i][0], st[i][1]);
        rtVertex3f(c[i][0], c[i][1], c[i][2]);
    }
    rtEnd();
}

int main(int argc, char **argv) {
    enum { W = 240, H = 160 };
    static unsigned char pixels[W * H * 4];
    rtFrameBuffer(pixels, W, H, RT_RGBA8);

    RTuint floor_texture = rtGenTextures(3), picture = floor_texture + 1, sky = floor_texture + 2;
    /* The floor: a checkerboard of squares 0.1 wide in texture coordinates. */
    const float light[3] = {0.8f, 0.8f, 0.75f}, dark[3] = {0.1f, 0.1f, 0.12f};
    rtBindTexture(RT_TEXTURE_2D, floor_texture);
    rtTexChecker(RT_TEXTURE_2D, light, dark, 10.f);

    /* The picture: 64 × 64 sRGB bytes, rows from the top: red above, yellow below, and a blue
     * disc in the middle. */
    static unsigned char image[64][64][3];
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            int dx = x - 32, dy = y - 32, disc = dx * dx + dy * dy < 16 * 16;
            image[y][x][0] = disc ? 30 : 230;
            image[y][x][1] = disc ? 60 : (y < 32 ? 40 : 200);
            image[y][x][2] = disc ? 220 : 30;
        }
    rtBindTexture(RT_TEXTURE_2D, picture);
    rtTexImage2D(RT_TEXTURE_2D, 0, RT_SRGB8, 64, 64, 0, RT_RGB, RT_UNSIGNED_BYTE, image);

    /* The sky, a latitude-longitude map (top row straight up): a file, or linear floats from
     * deep blue overhead to a bright horizon. */
    rtBindTexture(RT_TEXTURE_2D, sky);
    if (argc > 1) {
        rtTexImageFile(RT_TEXTURE_2D, argv[1]);
    } else {
        static float map[32][64][3];
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 64; x++) {
                float up = 1.f - (float)y / 16.f; /* 1 overhead, 0 at the horizon, < 0 below */
                float a = up < 0.f ? 0.f : up;
                map[y][x][0] = 1.0f - 0.8f * a;
                map[y][x][1] = 1.0f - 0.6f * a;
                map[y][x][2] = 1.1f - 0.2f * a;
            }
        rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB32F, 64, 32, 0, RT_RGB, RT_FLOAT, map);
    }
    check("defining the textures");

    RTuint classes = rtGenShaderClasses(2);
    rtNewShaderClass(classes, "Diffuse", NULL);
    rtNewShaderClass(classes + 1, "EnvironmentLight", NULL);
    RTuint environment = rtGenShaders(1);
    rtNewShader(environment);
    rtParameterTexture(rtParameterHandle("map"), sky);
    RTuint floor_shader = textured(classes, floor_texture), picture_shader = textured(classes, picture);
    check("defining the shaders");

    RTuint object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(floor_shader);
    const float ground[4][3] = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
    quad(ground);
    rtBindShader(picture_shader);
    const float panel[4][3] = {{-1, 2.2f, 0}, {1, 2.2f, 0}, {1, 0.2f, 0}, {-1, 0.2f, 0}};
    quad(panel);
    rtEndObject();
    rtInstantiateObject(object);
    check("building the scene");

    rtLookAt(0, 1.4f, 5, 0, 0.9f, 0, 0, 1, 0);
    rtPerspective(45, (float)W / H, 0.1f, 100);
    rtRenderMode(RT_PATH);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 16);
    rtSwapBuffers();
    rtWritePNG("textures.png");
    check("rendering");
    return 0;
}
