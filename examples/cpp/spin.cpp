// spin.cpp: a torus spinning over a floor, through the C++ wrapper raystage.hpp. The torus is
// an animated object: defined once from arrays, then only its instance moves.
//
// Usage: spin [FRAMES [WIDTH HEIGHT]]   writes spin_000.png, spin_001.png, ...
#include "raystage.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

const float pi = 3.14159265358979f;

/// Issues a torus around the z axis (radii `major` and `minor`) as one indexed mesh.
void torus(float major, float minor, int rings, int sides) {
    std::vector<RTfloat> positions, normals;
    std::vector<RTuint> indices;
    for (int i = 0; i < rings; i++) {
        float u = 2 * pi * i / rings;
        for (int j = 0; j < sides; j++) {
            float v = 2 * pi * j / sides;
            float n[3] = {std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
            positions.insert(positions.end(), {major * std::cos(u) + minor * n[0], major * std::sin(u) + minor * n[1], minor * n[2]});
            normals.insert(normals.end(), n, n + 3);
            RTuint a = i * sides + j, b = ((i + 1) % rings) * sides + j;
            RTuint c = ((i + 1) % rings) * sides + (j + 1) % sides, d = i * sides + (j + 1) % sides;
            indices.insert(indices.end(), {a, b, c, a, c, d});
        }
    }
    rtTriangleMesh(positions.data(), normals.data(), nullptr, nullptr, positions.size() / 3, indices.data(), indices.size() / 3);
}

} // namespace

int main(int argc, char *argv[]) {
    int frames = argc > 1 ? std::atoi(argv[1]) : 12;
    std::size_t width = argc > 3 ? std::atoi(argv[2]) : 320;
    std::size_t height = argc > 3 ? std::atoi(argv[3]) : 240;
    try {
        rt::Context context;
        rt::FrameBuffer frame(width, height);
        frame.render_mode(RT_WHITTED); // shadows from the two suns, one sample per pixel
        rtPerspective(45, float(width) / height, 0.1f, 100);
        rtLookAt(0, 2.5f, 7, 0, 0.6f, 0, 0, 1, 0);

        rt::Shader sun("DirectionalLight");
        sun.set("direction", -0.3f, -1, -0.5f).set("intensity", 2.5f, 2.4f, 2.2f);
        rt::Shader fill("DirectionalLight");
        fill.set("direction", 0, -0.2f, -1).set("intensity", 0.6f, 0.6f, 0.7f);
        rt::Shader teal("Diffuse");
        teal.set("diffuse", 0.1f, 0.6f, 0.6f);
        rt::Shader floor_paint("Diffuse");
        floor_paint.set("diffuse", 0.75f, 0.72f, 0.68f);

        rt::Object floor;
        floor.define([&] {
            floor_paint.bind();
            rt::Primitive quad(RT_QUADS);
            rtVertex3f(-6, -0.6f, -6);
            rtVertex3f(-6, -0.6f, 6);
            rtVertex3f(6, -0.6f, 6);
            rtVertex3f(6, -0.6f, -6);
        });
        rt::Object ring;
        ring.define(
            [&] {
                teal.bind();
                torus(1.0f, 0.35f, 48, 24);
            },
            RT_ANIMATED);

        rtLoadIdentity();
        rt::Instance floor_instance = floor.instantiate();
        rt::Instance spinning = ring.instantiate();
        for (int f = 0; f < frames; f++) {
            {
                rt::MatrixScope scope;
                rtTranslatef(0, 0.8f, 0);
                rtRotatef(15.0f * f, 0, 1, 0);
                rtRotatef(60, 1, 0, 0);
                spinning.move();
            }
            frame.swap();
            char name[32];
            std::snprintf(name, sizeof name, "spin_%03d.png", f);
            frame.write_png(name);
        }
    } catch (const rt::Error &e) {
        std::fprintf(stderr, "spin: %s (error 0x%x)\n", e.what(), unsigned(e.code()));
        return 1;
    }
    return 0;
}
