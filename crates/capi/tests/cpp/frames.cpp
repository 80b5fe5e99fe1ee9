// frames.cpp: checks raystage::Frame, the asynchronous frame of raystage/rt.hpp as a move-only
// future: a polled frame whose progress climbs to 1, a waited one, a cancelled one that stops at
// once and leaves its buffer alone, handles that move and are released exactly once, a buffer
// destroyed or moved while its frame renders, and frames on two threads' contexts at once.
//
// Prints each failed check and exits 1 if any failed (run by crates/capi/tests/examples.rs).
#include "check.hpp"

#include <chrono>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace {

const std::size_t W = 64, H = 32, BIG = 384;

/// A scene for the frames: a wall of a Constant shader filling the view.
struct Wall {
    raystage::Shader paint{"Constant"};
    raystage::Object object;
    std::optional<raystage::Instance> instance;

    Wall(float r, float g, float b) {
        raystage::look_at(0, 0, 6, 0, 0, 0, 0, 1, 0);
        paint.set("color", r, g, b);
        object.define([&] {
            paint.bind();
            raystage::Primitive quad(RT_QUADS);
            rtVertex3f(-20, -20, 0);
            rtVertex3f(20, -20, 0);
            rtVertex3f(20, 20, 0);
            rtVertex3f(-20, 20, 0);
        });
        instance.emplace(object.instantiate());
    }
};

/// An interactive loop: start a frame, edit the scene meanwhile, poll until it is ready.
void a_polled_frame_completes() {
    raystage::Context context;
    Wall wall(1, 0, 0);
    raystage::FrameBuffer buffer(W, H);
    raystage::Frame frame = buffer.render_async();
    wall.paint.set("color", 0, 0, 1); // the next frame's colour
    float last = 0;
    while (!frame.ready()) {
        float progress = frame.progress();
        CHECK(progress >= last && progress <= 1, "progress went from %g to %g", last, progress);
        last = progress;
    }
    CHECK(frame.progress() == 1.0f, "a completed frame's progress is %g", frame.progress());
    CHECK(frame.wait() == raystage::FrameStatus::completed, "a ready frame did not complete");
    CHECK(all_pixels(buffer, 255, 0, 0), "the frame is not all red: the edit after its start leaked in");
    buffer.write_png("polled.png"); // the delivered frame is the buffer's last
    buffer.swap();
    CHECK(all_pixels(buffer, 0, 0, 255), "the next frame is not all blue");
}

/// A long frame, cancelled while it renders, stops at once and leaves its buffer as it was.
void a_cancelled_frame_stops() {
    raystage::Context context;
    Wall wall(0.8f, 0.8f, 0.8f);
    raystage::render_mode(RT_PATH);
    raystage::render_parameter(RT_SAMPLES_PER_PIXEL, 4096);
    raystage::FrameBuffer buffer(BIG, BIG);
    raystage::Frame frame = buffer.render_async();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(!frame.ready(), "4096 samples per pixel took less than 50 ms");
    auto asked = std::chrono::steady_clock::now();
    frame.cancel();
    CHECK(frame.wait() == raystage::FrameStatus::cancelled, "a cancelled frame completed");
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    CHECK(seconds < 3, "wait took %.2f s after cancel", seconds);
    CHECK(frame.ready(), "a cancelled frame is not ready");
    CHECK(frame.progress() < 1, "a cancelled frame's progress is 1");
    CHECK(all_pixels(buffer, 0, 0, 0), "a cancelled frame wrote its buffer");
    throws("write_png of a cancelled frame", RT_INVALID_OPERATION, "not rendered into this frame buffer",
           [&] { buffer.write_png("cancelled.png"); });
}

/// Handles move; each is released exactly once, by whichever Frame holds it last.
void frames_move_and_release_once() {
    raystage::Context context;
    Wall wall(0, 1, 0);
    raystage::FrameBuffer buffer(W, H);

    raystage::Frame first = buffer.render_async();
    RTuint id = first.id();
    raystage::Frame second = std::move(first);
    CHECK(first.id() == 0 && second.id() == id, "the move left ids %u and %u", first.id(), second.id());
    throws("waiting for a moved-from frame", RT_INVALID_VALUE, "names no frame", [&] { first.wait(); });
    CHECK(second.wait() == raystage::FrameStatus::completed, "the moved frame did not complete");
    CHECK(all_pixels(buffer, 0, 255, 0), "the moved frame's image did not arrive");
    raystage::Frame third;
    third = std::move(second);
    CHECK(third.id() == id && second.id() == 0, "move-assignment left ids %u and %u", third.id(), second.id());

    // Assigning over a frame in flight releases it: cancelled, its handle gone, the buffer free.
    raystage::Frame in_flight = buffer.render_async();
    RTuint released = in_flight.id();
    in_flight = std::move(third);
    CHECK(rtFrameWait(released) == RT_INVALID_VALUE, "the overwritten frame was not released");
    error_is("waiting for the overwritten frame", RT_INVALID_VALUE, "was released");

    // The destructor releases, once.
    {
        raystage::Frame dropped = buffer.render_async();
        released = dropped.id();
    }
    CHECK(rtFrameWait(released) == RT_INVALID_VALUE, "a destroyed frame was not released");
    error_is("waiting for a destroyed frame", RT_INVALID_VALUE, "was released");
    buffer.swap(); // nothing is in flight any more
    no_error("frames moved and released");
}

/// A buffer destroyed while its frame renders releases the frame first, so that the image never
/// reaches freed memory; a buffer moved meanwhile receives it.
void buffers_outlived_or_moved_by_their_frames() {
    raystage::Context context;
    Wall wall(1, 1, 0);
    raystage::render_parameter(RT_SAMPLES_PER_PIXEL, 256);
    raystage::Frame orphan;
    {
        raystage::FrameBuffer doomed(BIG, BIG);
        orphan = doomed.render_async();
    }
    CHECK(orphan.id() == 0, "the destroyed buffer's frame still has handle %u", orphan.id());
    CHECK(raystage::get_integers(RT_VIEWPORT)[2] == 0, "the destroyed buffer is still attached");
    no_error("a buffer destroyed while its frame rendered");

    raystage::render_parameter(RT_SAMPLES_PER_PIXEL, 1);
    raystage::FrameBuffer before(W, H);
    raystage::Frame frame = before.render_async();
    raystage::FrameBuffer after = std::move(before);
    CHECK(frame.wait() == raystage::FrameStatus::completed, "the frame of a moved buffer did not complete");
    CHECK(all_pixels(after, 255, 255, 0), "the moved buffer did not receive the frame");
    after.write_png("moved.png");
    no_error("a buffer moved while its frame rendered");
}

/// Two threads, each with its own Context, render frames at the same time.
void frames_on_two_threads() {
    auto render = [](int channel) {
        try {
            raystage::Context context;
            Wall wall(channel == 0, channel == 1, 0);
            raystage::FrameBuffer buffer(W, H);
            raystage::Frame frame = buffer.render_async();
            CHECK(frame.wait() == raystage::FrameStatus::completed, "thread %d's frame did not complete", channel);
            CHECK(all_pixels(buffer, channel == 0 ? 255 : 0, channel == 1 ? 255 : 0, 0), "thread %d's frame is not its colour",
                  channel);
        } catch (const std::exception &e) {
            CHECK(false, "thread %d threw: %s", channel, e.what());
        }
    };
    std::thread red(render, 0), green(render, 1);
    red.join();
    green.join();
}

} // namespace

int main() {
    run("a_polled_frame_completes", a_polled_frame_completes);
    run("a_cancelled_frame_stops", a_cancelled_frame_stops);
    run("frames_move_and_release_once", frames_move_and_release_once);
    run("buffers_outlived_or_moved_by_their_frames", buffers_outlived_or_moved_by_their_frames);
    run("frames_on_two_threads", frames_on_two_threads);
    return verdict("frames.cpp");
}
