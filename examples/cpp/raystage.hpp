// raystage.hpp: a header-only C++ wrapper of raystage/rt.h. Errors become exceptions
// (rt::Error), ids are owned by objects that free them, and the begin/end pairs of the C API
// (rtNewObject/rtEndObject, rtBegin/rtEnd, rtPushMatrix/rtPopMatrix) are scopes.
//
// The C API's rules hold: one context per thread, frame semantics (everything is resolved at
// rtSwapBuffers). Wrapper objects must be destroyed on the thread that made them, before the
// rt::Context they belong to.
#ifndef RAYSTAGE_HPP
#define RAYSTAGE_HPP

#include <raystage/rt.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rt {

/// A failed rt call: its error code and raystage's message.
class Error : public std::runtime_error {
  public:
    Error(RTenum code, const char *message) : std::runtime_error(message), code_(code) {}
    /// The RT_* error code.
    RTenum code() const { return code_; }

  private:
    RTenum code_;
};

/// Throws the pending error, if any.
inline void check() {
    RTenum code = rtGetError();
    if (code != RT_NO_ERROR) {
        throw Error(code, rtGetErrorString());
    }
}

/// This thread's context: reset (and freed) when the Context goes out of scope.
class Context {
  public:
    Context() { rtResetContext(); }
    ~Context() { rtResetContext(); }
    Context(const Context &) = delete;
    Context &operator=(const Context &) = delete;
};

/// An id owned by a C++ object, freed by `Free` when the object dies; move-only.
template <void (*Free)(RTuint)> class Owned {
  public:
    explicit Owned(RTuint id) : id_(id) {}
    Owned(Owned &&other) noexcept : id_(std::exchange(other.id_, 0)) {}
    Owned &operator=(Owned &&other) noexcept {
        std::swap(id_, other.id_);
        return *this;
    }
    ~Owned() {
        if (id_ != 0) {
            Free(id_);
        }
    }
    Owned(const Owned &) = delete;
    Owned &operator=(const Owned &) = delete;
    /// The C id.
    RTuint id() const { return id_; }

  private:
    RTuint id_;
};

namespace detail {
inline void delete_object(RTuint id) { rtDeleteObjects(id, 1); }
inline void delete_shader(RTuint id) { rtDeleteShaders(id, 1); }
inline void delete_instance(RTuint id) { rtDeleteInstance(id); }
inline RTuint generated(RTuint id) {
    check();
    return id;
}
} // namespace detail

/// A shader of a built-in class ("Diffuse", "VertexColor", "Constant", "PointLight",
/// "DirectionalLight", ...), bound when made.
class Shader : public Owned<detail::delete_shader> {
  public:
    explicit Shader(const std::string &class_name) : Owned(detail::generated(rtGenShaders(1))) {
        RTuint cls = detail::generated(rtGenShaderClasses(1));
        rtNewShaderClass(cls, class_name.c_str(), nullptr);
        rtNewShader(id());
        check();
    }
    /// Binds the shader for the triangles issued next and for set().
    void bind() const {
        rtBindShader(id());
        check();
    }
    /// Writes a parameter of three numbers (ignored if the class does not export it).
    Shader &set(const std::string &name, RTfloat x, RTfloat y, RTfloat z) {
        bind();
        rtParameter3f(rtParameterHandle(name.c_str()), x, y, z);
        check();
        return *this;
    }
    /// Writes a parameter of one number (ignored if the class does not export it).
    Shader &set(const std::string &name, RTfloat x) {
        bind();
        rtParameter1f(rtParameterHandle(name.c_str()), x);
        check();
        return *this;
    }
};

/// Pushes the current matrix stack for the scope of this object.
class MatrixScope {
  public:
    MatrixScope() {
        rtPushMatrix();
        check();
    }
    ~MatrixScope() { rtPopMatrix(); }
    MatrixScope(const MatrixScope &) = delete;
    MatrixScope &operator=(const MatrixScope &) = delete;
};

/// A primitive (rtBegin/rtEnd) for the scope of this object.
class Primitive {
  public:
    explicit Primitive(RTenum mode) {
        rtBegin(mode);
        check();
    }
    ~Primitive() { rtEnd(); }
    Primitive(const Primitive &) = delete;
    Primitive &operator=(const Primitive &) = delete;
};

/// An instance of an object; removed from the scene when destroyed.
class Instance : public Owned<detail::delete_instance> {
  public:
    using Owned::Owned;
    /// Moves the instance to the current modelview matrix.
    void move() const {
        rtMoveInstance(id());
        check();
    }
    /// Makes the current modelview matrix the instance's transform at the shutter's close (it
    /// moves from where `move` or `instantiate` put it: motion blur, with `rtShutter`).
    void move_by_shutter_close() const {
        rtInstanceMotion(id());
        check();
    }
};

/// An object: geometry with its own acceleration structure; deleted when destroyed.
class Object : public Owned<detail::delete_object> {
  public:
    Object() : Owned(detail::generated(rtGenObjects(1))) {}
    /// (Re)defines the object: `issue()` issues its geometry. A second definition replaces the
    /// first, and every instance follows.
    template <class Issue> void define(Issue &&issue, RTenum kind = RT_STATIC) {
        rtObjectKind(kind);
        rtNewObject(id(), RT_COMPILE);
        check();
        try {
            std::forward<Issue>(issue)();
        } catch (...) {
            rtEndObject();
            throw;
        }
        rtEndObject();
        check();
    }
    /// Places an instance with the current modelview matrix.
    Instance instantiate() const { return Instance(detail::generated(rtInstantiateObject(id()))); }
};

/// An RGBA8 frame buffer in this object's memory, attached while it lives.
class FrameBuffer {
  public:
    FrameBuffer(std::size_t width, std::size_t height) : width_(width), height_(height), pixels_(width * height * 4) {
        rtFrameBuffer(pixels_.data(), width, height, RT_RGBA8);
        check();
    }
    ~FrameBuffer() { rtFrameBuffer(nullptr, 0, 0, RT_RGBA8); }
    FrameBuffer(const FrameBuffer &) = delete;
    FrameBuffer &operator=(const FrameBuffer &) = delete;
    /// How the next frames are rendered: `RT_AUTO`, `RT_EYELIGHT`, `RT_WHITTED`,
    /// `RT_DISTRIBUTION` or `RT_PATH`, with `samples` samples per pixel.
    void render_mode(RTenum integrator, RTint samples = 1) {
        rtRenderMode(integrator);
        check();
        rtRenderParameteri(RT_SAMPLES_PER_PIXEL, samples);
        check();
    }
    /// Renders a frame into the buffer.
    void swap() {
        rtSwapBuffers();
        check();
    }
    /// Writes the last frame as a PNG file.
    void write_png(const std::string &path) const {
        rtWritePNG(path.c_str());
        check();
    }
    /// The sRGB bytes (red, green, blue, alpha) of pixel (x, y), row 0 at the top.
    const std::uint8_t *pixel(std::size_t x, std::size_t y) const { return &pixels_[(y * width_ + x) * 4]; }
    std::size_t width() const { return width_; }
    std::size_t height() const { return height_; }

  private:
    std::size_t width_, height_;
    std::vector<std::uint8_t> pixels_;
};

} // namespace rt

#endif // RAYSTAGE_HPP
