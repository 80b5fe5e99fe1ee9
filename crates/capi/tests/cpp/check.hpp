// check.hpp: what the C++ test programs share, on top of the C tests' CHECK (../c/check.h):
// pixels compared with a colour, a check that a call throws the right raystage::Error, and the
// groups of checks run so that an exception one lets out counts as a failure.
#ifndef RAYSTAGE_TESTS_CHECK_HPP
#define RAYSTAGE_TESTS_CHECK_HPP

#include "../c/check.h"

#include <raystage/rt.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

/// Whether pixel (x, y) of `buffer` is (r, g, b) within 2.
inline bool pixel_is(const raystage::FrameBuffer &buffer, std::size_t x, std::size_t y, int r, int g, int b) {
    const std::uint8_t *p = buffer.pixel(x, y);
    return std::abs(p[0] - r) <= 2 && std::abs(p[1] - g) <= 2 && std::abs(p[2] - b) <= 2;
}

/// Whether every pixel of `buffer` is (r, g, b) within 2.
inline bool all_pixels(const raystage::FrameBuffer &buffer, int r, int g, int b) {
    for (std::size_t y = 0; y < buffer.height(); y++) {
        for (std::size_t x = 0; x < buffer.width(); x++) {
            if (!pixel_is(buffer, x, y, r, g, b)) {
                return false;
            }
        }
    }
    return true;
}

/// Runs `body`, which must throw a raystage::Error of `code` whose message contains `fragment`
/// and leave no error pending.
template <class Body> void throws(const char *what, RTenum code, const char *fragment, Body &&body) {
    try {
        body();
        CHECK(false, "%s: no exception", what);
    } catch (const raystage::Error &e) {
        CHECK(e.code() == code, "%s: error 0x%x (%s), not 0x%x", what, unsigned(e.code()), e.what(), unsigned(code));
        CHECK(std::string(e.what()).find(fragment) != std::string::npos, "%s: \"%s\" does not mention \"%s\"", what,
              e.what(), fragment);
    }
    no_error(what);
}

/// Runs one group of checks; an exception it lets out is a failure too.
inline void run(const char *name, void (*checks)()) {
    try {
        checks();
    } catch (const std::exception &e) {
        CHECK(false, "%s threw: %s", name, e.what());
    }
}

/// main's result: 1 if a check failed (saying how many), else 0 (saying that `program` passed).
inline int verdict(const char *program) {
    if (failures) {
        std::fprintf(stderr, "%s: %d checks failed\n", program, failures);
        return 1;
    }
    std::printf("%s: all checks passed\n", program);
    return 0;
}

#endif
