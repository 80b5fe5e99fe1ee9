// discarded.cpp: dropping a result of raystage/rt.hpp that must be kept is a compile error under
// -Werror (crates/capi/tests/examples.rs compiles this file three times). An Instance dropped at
// once would be deleted at once, and a Frame released (cancelled) at once: the example header
// this one replaced let `object.instantiate();` compile and silently delete the instance.
// Built with -DDISCARD_INSTANCE or -DDISCARD_FRAME it drops one and must not compile;
// built with neither it keeps both and must compile, so that the failure is the drop's.
#include <raystage/rt.hpp>

int main() {
    raystage::Context context;
    raystage::FrameBuffer buffer(4, 4);
    raystage::Object object;
    object.define([] {
        raystage::Primitive triangle(RT_TRIANGLES);
        rtVertex3f(0, 0, 0);
        rtVertex3f(1, 0, 0);
        rtVertex3f(0, 1, 0);
    });
#if defined(DISCARD_INSTANCE)
    object.instantiate();
#else
    raystage::Instance instance = object.instantiate();
#endif
#if defined(DISCARD_FRAME)
    buffer.render_async();
#else
    raystage::Frame frame = buffer.render_async();
    frame.wait();
#endif
    return 0;
}
