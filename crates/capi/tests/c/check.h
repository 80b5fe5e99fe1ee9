/*
 * check.h: the checks the C test programs share. CHECK prints a failed condition with a message
 * and counts it (atomically, so threads may check too); main returns 1 if `failures` is not 0.
 */
#ifndef RAYSTAGE_TESTS_CHECK_H
#define RAYSTAGE_TESTS_CHECK_H

#include <raystage/rt.h>

#include <stdio.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond, ...)                                                              \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: %s: ", __FILE__, __LINE__, #cond);                \
            fprintf(stderr, __VA_ARGS__);                                             \
            fprintf(stderr, "\n");                                                    \
            __atomic_add_fetch(&failures, 1, __ATOMIC_RELAXED);                       \
        }                                                                             \
    } while (0)

/* No error is pending. */
static inline void no_error(const char *what) {
    RTenum error = rtGetError();
    CHECK(error == RT_NO_ERROR, "%s: %s (0x%x)", what, rtGetErrorString(), (unsigned)error);
}

/* Error `code` is pending, with a message that contains `fragment`. */
static inline void error_is(const char *what, RTenum code, const char *fragment) {
    char copy[512];
    snprintf(copy, sizeof copy, "%s", rtGetErrorString());
    RTenum error = rtGetError();
    CHECK(error == code, "%s: error 0x%x (%s), not 0x%x", what, (unsigned)error, copy, (unsigned)code);
    CHECK(strstr(copy, fragment) != NULL, "%s: \"%s\" does not mention \"%s\"", what, copy, fragment);
}

#endif
