// spin.cpp: a torus spinning over a floor, through raystage's C++ wrapper raystage/rt.hpp. The
// torus is an animated object: defined once from arrays, then only its instance moves.
//
// Usage: spin [FRAMES [WIDTH HEIGHT]]   writes spin_000.png, spin_001.png, ...
#include <raystage/rt.hpp>

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
    raystage::triangle_mesh(positions, indices, normals);
}

} // namespace

int main(int argc, char *argv[]) {
    int frames = argc > 1 ? std::atoi(argv[1]) : 12;
    std::size_t width = argc > 3 ? std::atoi(argv[2]) : 320;
    std::size_t height = argc > 3 ? std::atoi(argv[3]) : 240;
    try {
        raystage::Context context;
        raystage::FrameBuffer frame(width, height);
        raystage::render_mode(RT_WHITTED); // shadows from the two suns, one sample per pixel
        raystage::perspective(45, float(width) / height, 0.1f, 100);
        raystage::look_at(0, 2.5f, 7, 0, 0.6f, 0, 0, 1, 0);

        raystage::Shader sun("DirectionalLight");
        sun.set("direction", -0.3f, -1, -0.5f).set("intensity", 2.5f, 2.4f, 2.2f);
        raystage::Shader fill("DirectionalLight");
        fill.set("direction", 0, -0.2f, -1).set("intensity", 0.6f, 0.6f, 0.7f);
        raystage::Shader teal("Diffuse");
        teal.set("diffuse", 0.1f, 0.6f, 0.6f);
        raystage::Shader floor_paint("Diffuse");
        floor_paint.set("diffuse", 0.75f, 0.72f, 0.68f);

        raystage::Object floor;
        floor.define([&] {
            floor_paint.bind();
            raystage::Primitive quad(RT_QUADS);
            rtVertex3f(-6, -0.6f, -6);
            rtVertex3f(-6, -0.6f, 6);
            rtVertex3f(6, -0.6f, 6);
            rtVertex3f(6, -0.6f, -6);
        });
        raystage::Object ring;
        ring.define(
            [&] {
                teal.bind();
                torus(1.0f, 0.35f, 48, 24);
            },
            RT_ANIMATED);

        raystage::load_identity();
        raystage::Instance floor_instance = floor.instantiate();
        raystage::Instance spinning = ring.instantiate();
        for (int f = 0; f < frames; f++) {
            {
                raystage::MatrixScope scope;
                raystage::translate(0, 0.8f, 0);
                raystage::rotate(15.0f * f, 0, 1, 0);
                raystage::rotate(60, 1, 0, 0);
                spinning.move();
            }
            frame.swap();
            char name[32];
            std::snprintf(name, sizeof name, "spin_%03d.png", f);
            frame.write_png(name);
        }
    } catch (const raystage::Error &e) {
        std::fprintf(stderr, "spin: %s (error 0x%x)\n", e.what(), unsigned(e.code()));
        return 1;
    }
    return 0;
}
