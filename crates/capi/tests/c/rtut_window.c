/*
 * rtut_window.c: a GLUT program ported to RTUT by renaming. A red square on the clear colour
 * blue, in a 160 × 120 window; the callbacks print what they get (one line each, flushed), so
 * that the test driving the program (tests/rtut.rs) can follow it:
 *
 *   reshape W H                      when the window gets its size
 *   display N                        after the Nth frame is rendered and shown
 *   key C X Y                        for a key; 'r' posts a redisplay, 'q' leaves the main loop
 *   mouse BUTTON STATE X Y hit H     for a button; H is 1 if rtPick finds the square there
 *   done N                           after rtutMainLoop returned, N frames rendered
 *
 * Headless (no display), RTUT renders RTUT_FRAMES frames: the idle callback posts a redisplay
 * each time. Checks of the calls' errors use check.h; the program returns 1 if any failed.
 */
#include <raystage/rtut.h>

#include "check.h"

static int displays = 0;
static RTuint square_instance = 0;

static void display(void) {
    rtutSwapBuffers();
    no_error("rtutSwapBuffers");
    printf("display %d\n", ++displays);
    fflush(stdout);
}

static void reshape(int width, int height) {
    printf("reshape %d %d\n", width, height);
    fflush(stdout);
}

static void keyboard(unsigned char key, int x, int y) {
    printf("key %c %d %d\n", key, x, y);
    fflush(stdout);
    if (key == 'r') {
        rtutPostRedisplay();
    } else if (key == 'q') {
        rtutLeaveMainLoop();
    }
}

static void mouse(int button, int state, int x, int y) {
    RTuint instance = 0;
    RTboolean hit = rtPick((RTuint)x, (RTuint)y, &instance, NULL, NULL);
    no_error("rtPick in the mouse callback");
    printf("mouse %d %d %d %d hit %d\n", button, state, x, y, hit && instance == square_instance);
    fflush(stdout);
}

static void idle(void) { rtutPostRedisplay(); }

int main(int argc, char **argv) {
    /* Before rtutInit, there is no window to make; without one, no loop to run. */
    CHECK(rtutCreateWindow("too early") == 0, "a window before rtutInit");
    error_is("rtutCreateWindow before rtutInit", RT_INVALID_OPERATION, "rtutInit");
    rtutInit(&argc, argv);
    rtutInitWindowSize(0, 120);
    error_is("a window of no width", RT_INVALID_VALUE, "each side must be 1 to");
    rtutMainLoop();
    error_is("rtutMainLoop without a window", RT_INVALID_OPERATION, "rtutCreateWindow");
    rtutSwapBuffers();
    error_is("rtutSwapBuffers without a window", RT_INVALID_OPERATION, "rtutCreateWindow");

    rtutInitWindowSize(160, 120);
    CHECK(rtutCreateWindow("rtut window test") == 1, "the window's id");
    CHECK(rtutCreateWindow("a second") == 0, "one window");
    error_is("a second window", RT_INVALID_OPERATION, "one window");
    rtutMainLoop();
    error_is("rtutMainLoop without a display callback", RT_INVALID_OPERATION, "rtutDisplayFunc");
    rtutSwapBuffers();
    error_is("rtutSwapBuffers outside the loop", RT_INVALID_OPERATION, "rtutMainLoop");

    /* The scene: a red 2 × 2 square at the origin, seen from 3 units away, on blue. */
    RTuint cid = rtGenShaderClasses(1);
    rtNewShaderClass(cid, "Constant", NULL);
    RTuint sid = rtGenShaders(1);
    rtNewShader(sid);
    rtParameter3f(rtParameterHandle("color"), 1.0f, 0.0f, 0.0f);
    RTuint square = rtGenObjects(1);
    rtNewObject(square, RT_COMPILE);
    rtBindShader(sid);
    rtBegin(RT_QUADS);
    rtVertex3f(-1.0f, -1.0f, 0.0f);
    rtVertex3f(1.0f, -1.0f, 0.0f);
    rtVertex3f(1.0f, 1.0f, 0.0f);
    rtVertex3f(-1.0f, 1.0f, 0.0f);
    rtEnd();
    rtEndObject();
    square_instance = rtInstantiateObject(square);
    rtClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    rtPerspective(45.0f, 160.0f / 120.0f, 0.1f, 100.0f);
    rtLookAt(0, 0, 3, 0, 0, 0, 0, 1, 0);
    no_error("the scene");

    rtutDisplayFunc(display);
    rtutReshapeFunc(reshape);
    rtutKeyboardFunc(keyboard);
    rtutMouseFunc(mouse);
    if (argc > 1 && strcmp(argv[1], "--animate") == 0) {
        rtutIdleFunc(idle);
    }
    rtutMainLoop();
    no_error("rtutMainLoop");
    printf("done %d\n", displays);
    return failures != 0;
}
