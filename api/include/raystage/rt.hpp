// raystage/rt.hpp: the C++ interface of raystage, a header-only wrapper of raystage/rt.h (C++17).
//
// What it adds to the C calls:
// - Errors are exceptions: every call of the wrapper checks rtGetError and throws
//   raystage::Error, which carries the RT_* code and rtGetErrorString's message.
// - Ownership: an object owns exactly the ids it generated and deletes them when it dies (Object,
//   Instance, Shader, Texture; move-only). What the C ABI cannot delete (shader classes) is a
//   plain value. An id dies with its context, so an object that outlives its Context frees
//   nothing; an Instance also dies with its Object, which deletes it.
// - Results whose loss is a bug are [[nodiscard]]: an Instance or Frame dropped at once would be
//   deleted or released at once.
// - Scopes for the C ABI's pairs: Object::define (rtNewObject/rtEndObject, closed on the
//   exception path too), Primitive (rtBegin/rtEnd), MatrixScope (rtPushMatrix/rtPopMatrix).
// - FrameBuffer attaches itself before it renders, so each buffer gets its own frames, and
//   detaches itself only if it is the attached one; Frame is an asynchronous frame
//   (rtRenderFrameAsync) as a move-only future that its destructor releases.
//
// Inside Object::define the per-vertex calls of rt.h (rtVertex3f, rtNormal3f, rtColor3f,
// rtTexCoord2f, ...) are used as they are: their errors stick until define checks them when the
// object ends, which costs nothing per vertex.
//
// The C ABI's rules hold: each thread has its own context, and everything is resolved when a
// frame is rendered. Use the objects of this header on the thread that made them, and let
// Context (not rtResetContext) reset the context and FrameBuffer (not rtFrameBuffer) attach
// frame buffers, since the wrapper keeps track of both.
#ifndef RAYSTAGE_RT_HPP
#define RAYSTAGE_RT_HPP

#if __cplusplus < 201703L
#error "raystage/rt.hpp needs C++17 (-std=c++17, or CMake's raystage::cpp target)"
#endif

#include <raystage/rt.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace raystage {

/// A failed call: its RT_* error code and raystage's message, which names the call.
class Error : public std::runtime_error {
  public:
    Error(RTenum code, const std::string &message) : std::runtime_error(message), code_(code) {}
    /// The RT_* error code (RT_INVALID_VALUE, RT_INVALID_OPERATION, ...).
    RTenum code() const noexcept { return code_; }

  private:
    RTenum code_;
};

/// Throws the pending error of this thread's context as an Error, if there is one (and clears it,
/// as rtGetError does). For programs that mix rt.h calls with the wrapper.
inline void check() {
    RTenum code = rtGetError();
    if (code != RT_NO_ERROR) {
        throw Error(code, rtGetErrorString());
    }
}

class FrameBuffer;
class Frame;

namespace detail {

/// What the wrapper knows of this thread's context.
struct Thread {
    /// Counts the resets by Context: ids generated before a reset name nothing after it.
    std::uint64_t generation = 0;
    /// The FrameBuffer attached with rtFrameBuffer, if any.
    const FrameBuffer *attached = nullptr;
    /// The FrameBuffer that received the last frame, which rtWritePNG writes.
    const FrameBuffer *last = nullptr;
};

/// Every channel rtChannelBuffer takes.
constexpr RTenum channels[] = {RT_DEPTH_CHANNEL, RT_Z_CHANNEL, RT_NORMAL_CHANNEL, RT_ALBEDO_CHANNEL,
                               RT_INSTANCE_ID_CHANNEL, RT_OBJECT_ID_CHANNEL, RT_PRIMITIVE_ID_CHANNEL};

inline Thread &thread() {
    static thread_local Thread state;
    return state;
}

/// The context an id was generated in: this thread's, until the next reset.
class Lifetime {
  public:
    Lifetime() : thread_(&thread()), generation_(thread().generation) {}
    /// Whether the context is still the one the id belongs to (and this is its thread).
    bool alive() const { return thread_ == &thread() && generation_ == thread_->generation; }

  private:
    const Thread *thread_;
    std::uint64_t generation_;
};

/// `id` from an rtGen* call, or the error that call recorded.
inline RTuint generated(RTuint id) {
    check();
    return id;
}

inline void delete_object(RTuint id) { rtDeleteObjects(id, 1); }
inline void delete_shader(RTuint id) { rtDeleteShaders(id, 1); }
inline void delete_texture(RTuint id) { rtDeleteTextures(id, 1); }

/// An id owned by a C++ object and freed by `Free` when the object dies, unless the context it
/// belongs to is gone; move-only.
template <void (*Free)(RTuint)> class Owned {
  public:
    /// The C id, for rt.h calls (0 once moved from).
    RTuint id() const noexcept { return id_; }

  protected:
    explicit Owned(RTuint id) noexcept : id_(id) {}
    Owned(Owned &&other) noexcept : id_(std::exchange(other.id_, 0)), lifetime_(other.lifetime_) {}
    Owned &operator=(Owned &&other) noexcept {
        if (this != &other) {
            free();
            id_ = std::exchange(other.id_, 0);
            lifetime_ = other.lifetime_;
        }
        return *this;
    }
    ~Owned() { free(); }
    Owned(const Owned &) = delete;
    Owned &operator=(const Owned &) = delete;

  private:
    void free() noexcept {
        if (id_ != 0 && lifetime_.alive()) {
            Free(id_);
        }
        id_ = 0;
    }

    RTuint id_;
    Lifetime lifetime_;
};

/// How many values `rtGetFloatv(pname)` writes (1 for a name it refuses: it then writes none).
inline std::size_t values_of(RTenum pname) {
    switch (pname) {
    case RT_MODELVIEW_MATRIX:
    case RT_TEXTURE_MATRIX:
        return 16;
    case RT_CURRENT_COLOR:
    case RT_CURRENT_TEXTURE_COORDS:
    case RT_COLOR_CLEAR_VALUE:
    case RT_VIEWPORT:
        return 4;
    case RT_CURRENT_NORMAL:
        return 3;
    default:
        return 1;
    }
}

} // namespace detail

/// This thread's context, reset when the Context is made and again (freed) when it dies. Wrapper
/// objects that outlive it free nothing: their ids died with it.
class Context {
  public:
    Context() { reset(); }
    ~Context() { reset(); }
    Context(const Context &) = delete;
    Context &operator=(const Context &) = delete;

  private:
    static void reset() noexcept {
        rtResetContext();
        detail::Thread &state = detail::thread();
        state.generation++;
        state.attached = nullptr;
        state.last = nullptr;
    }
};

// ---------------------------------------------------------------------------------------------
// Camera, background, render settings, matrices and state queries: the rt.h calls, checked.

/// rtPerspective: a symmetric projection of `fovy` degrees vertically.
inline void perspective(RTfloat fovy, RTfloat aspect, RTfloat znear, RTfloat zfar) {
    rtPerspective(fovy, aspect, znear, zfar);
    check();
}

/// rtFrustum: an off-axis perspective projection, as glFrustum.
inline void frustum(RTdouble left, RTdouble right, RTdouble bottom, RTdouble top, RTdouble znear, RTdouble zfar) {
    rtFrustum(left, right, bottom, top, znear, zfar);
    check();
}

/// rtOrtho: an orthographic projection (parallel rays), as glOrtho.
inline void ortho(RTdouble left, RTdouble right, RTdouble bottom, RTdouble top, RTdouble znear, RTdouble zfar) {
    rtOrtho(left, right, bottom, top, znear, zfar);
    check();
}

/// rtLookAt: places the camera at the eye, looking at the centre, `up` up in the image.
inline void look_at(RTfloat eye_x, RTfloat eye_y, RTfloat eye_z, RTfloat center_x, RTfloat center_y, RTfloat center_z,
                    RTfloat up_x, RTfloat up_y, RTfloat up_z) {
    rtLookAt(eye_x, eye_y, eye_z, center_x, center_y, center_z, up_x, up_y, up_z);
    check();
}

/// rtLens: a thin lens for depth of field (0 and 0: a pinhole).
inline void lens(RTfloat aperture_radius, RTfloat focus_distance) {
    rtLens(aperture_radius, focus_distance);
    check();
}

/// rtShutter: the shutter's open and close times, for motion blur.
inline void shutter(RTfloat open, RTfloat close) {
    rtShutter(open, close);
    check();
}

/// rtClearColor: the background colour (linear RGB; alpha is state only).
inline void clear_color(RTfloat red, RTfloat green, RTfloat blue, RTfloat alpha = 1) {
    rtClearColor(red, green, blue, alpha);
    check();
}

/// rtRenderMode: RT_AUTO, RT_EYELIGHT, RT_WHITTED, RT_DISTRIBUTION or RT_PATH.
inline void render_mode(RTenum mode) {
    rtRenderMode(mode);
    check();
}

/// rtRenderParameteri: RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_LIGHT_SAMPLES, RT_SEED, ...
inline void render_parameter(RTenum pname, RTint value) {
    rtRenderParameteri(pname, value);
    check();
}

/// rtGetRenderParameteri: a render parameter's value, or the mode with RT_RENDER_MODE.
inline RTint render_parameter(RTenum pname) {
    RTint value = rtGetRenderParameteri(pname);
    check();
    return value;
}

/// rtMatrixMode: RT_MODELVIEW or RT_TEXTURE, the stack the matrix calls act on.
inline void matrix_mode(RTenum mode) {
    rtMatrixMode(mode);
    check();
}

/// rtLoadIdentity.
inline void load_identity() {
    rtLoadIdentity();
    check();
}

/// rtTranslatef.
inline void translate(RTfloat x, RTfloat y, RTfloat z) {
    rtTranslatef(x, y, z);
    check();
}

/// rtRotatef: `angle` degrees counter-clockwise about (x, y, z).
inline void rotate(RTfloat angle, RTfloat x, RTfloat y, RTfloat z) {
    rtRotatef(angle, x, y, z);
    check();
}

/// rtScalef.
inline void scale(RTfloat x, RTfloat y, RTfloat z) {
    rtScalef(x, y, z);
    check();
}

/// rtMultMatrixf: 16 values in column-major order, last row 0 0 0 1.
inline void mult_matrix(const std::array<RTfloat, 16> &m) {
    rtMultMatrixf(m.data());
    check();
}

/// rtLoadMatrixf: 16 values in column-major order, last row 0 0 0 1.
inline void load_matrix(const std::array<RTfloat, 16> &m) {
    rtLoadMatrixf(m.data());
    check();
}

// The double-precision calls have names of their own, as in rt.h: overloads on float and
// double would make `translate(1, 0, 0)` ambiguous.

/// rtTranslated.
inline void translated(RTdouble x, RTdouble y, RTdouble z) {
    rtTranslated(x, y, z);
    check();
}

/// rtRotated: `angle` degrees counter-clockwise about (x, y, z).
inline void rotated(RTdouble angle, RTdouble x, RTdouble y, RTdouble z) {
    rtRotated(angle, x, y, z);
    check();
}

/// rtScaled.
inline void scaled(RTdouble x, RTdouble y, RTdouble z) {
    rtScaled(x, y, z);
    check();
}

/// rtMultMatrixd: 16 values in column-major order, last row 0 0 0 1.
inline void mult_matrixd(const std::array<RTdouble, 16> &m) {
    rtMultMatrixd(m.data());
    check();
}

/// rtLoadMatrixd: 16 values in column-major order, last row 0 0 0 1.
inline void load_matrixd(const std::array<RTdouble, 16> &m) {
    rtLoadMatrixd(m.data());
    check();
}

/// rtShadeModel: RT_SMOOTH or RT_FLAT, for primitives begun later.
inline void shade_model(RTenum mode) {
    rtShadeModel(mode);
    check();
}

/// rtGetFloatv: the values of state `pname` (16 for a matrix, 4 for a colour, ...).
inline std::vector<RTfloat> get_floats(RTenum pname) {
    std::vector<RTfloat> values(detail::values_of(pname));
    rtGetFloatv(pname, values.data());
    check();
    return values;
}

/// rtGetIntegerv: the values of state `pname`, each rounded to the nearest integer.
inline std::vector<RTint> get_integers(RTenum pname) {
    std::vector<RTint> values(detail::values_of(pname));
    rtGetIntegerv(pname, values.data());
    check();
    return values;
}

/// A parameter of a built-in shader class (rtGetShaderParameter*).
struct ParameterInfo {
    std::string name;
    /// What it does, its units and its default, in words.
    std::string doc;
    /// RT_FLOAT, RT_FLOAT_VEC3 or RT_TEXTURE_2D.
    RTenum type;
    /// Three numbers; a number in the first; zeros for a texture.
    std::array<RTfloat, 3> defaults;
    /// The least and most of each number (infinite where open).
    std::array<RTfloat, 2> range;
};

/// A built-in shader class (rtGetShaderClass*): surface classes come first, then light classes.
struct ClassInfo {
    std::string name;
    std::string doc;
    /// RT_SURFACE_CLASS or RT_LIGHT_CLASS.
    RTenum kind;
    std::vector<ParameterInfo> parameters;
};

/// Every built-in shader class with its parameters, as the library declares them.
inline std::vector<ClassInfo> shader_classes() {
    std::vector<ClassInfo> classes;
    for (RTsizei c = 0, n = rtGetShaderClassCount(); c < n; c++) {
        ClassInfo info{rtGetShaderClassName(c), rtGetShaderClassDoc(c), rtGetShaderClassKind(c), {}};
        for (RTsizei p = 0, m = rtGetShaderParameterCount(c); p < m; p++) {
            ParameterInfo param{rtGetShaderParameterName(c, p), rtGetShaderParameterDoc(c, p), rtGetShaderParameterType(c, p), {}, {}};
            rtGetShaderParameterDefault(c, p, param.defaults.data());
            rtGetShaderParameterRange(c, p, param.range.data());
            info.parameters.push_back(std::move(param));
        }
        check();
        classes.push_back(std::move(info));
    }
    return classes;
}

/// Pushes the current matrix stack for the scope of this object, and pops that same stack when
/// it ends, even if the matrix mode changed meanwhile.
class MatrixScope {
  public:
    MatrixScope() {
        rtGetIntegerv(RT_MATRIX_MODE, &mode_);
        rtPushMatrix();
        check();
    }
    ~MatrixScope() {
        RTint now = mode_;
        rtGetIntegerv(RT_MATRIX_MODE, &now);
        if (now != mode_) {
            rtMatrixMode(static_cast<RTenum>(mode_));
        }
        rtPopMatrix();
        if (now != mode_) {
            rtMatrixMode(static_cast<RTenum>(now));
        }
    }
    MatrixScope(const MatrixScope &) = delete;
    MatrixScope &operator=(const MatrixScope &) = delete;

  private:
    RTint mode_ = RT_MODELVIEW;
};

// ---------------------------------------------------------------------------------------------
// Textures and shaders.

/// A texture (rtGenTextures), deleted when destroyed; it is defined by one of image, file,
/// checker or noise, and handed to shaders with Shader::set.
class Texture : public detail::Owned<detail::delete_texture> {
  public:
    Texture() : Owned(detail::generated(rtGenTextures(1))) {}
    /// rtBindTexture: binds the texture for the rtTex* calls.
    void bind() const {
        rtBindTexture(RT_TEXTURE_2D, id());
        check();
    }
    /// rtTexImage2D with bytes: `format` RT_LUMINANCE, RT_RGB or RT_RGBA, `pixels` rows from the
    /// top; linear bytes (byte / 255) by default, as rtTexImage2D reads them, sRGB-encoded ones
    /// (a photograph's) with RT_SRGB8.
    Texture &image(RTsizei width, RTsizei height, RTenum format, const std::vector<std::uint8_t> &pixels,
                   RTint internal_format = RT_RGB8) {
        return define_image(width, height, format, RT_UNSIGNED_BYTE, pixels.data(), pixels.size(), internal_format);
    }
    /// rtTexImage2D with linear floats (high dynamic range).
    Texture &image(RTsizei width, RTsizei height, RTenum format, const std::vector<RTfloat> &pixels,
                   RTint internal_format = RT_RGB32F) {
        return define_image(width, height, format, RT_FLOAT, pixels.data(), pixels.size(), internal_format);
    }
    /// rtTexImageFile: a PNG, JPEG or Radiance HDR file.
    Texture &file(const std::string &path) {
        bind();
        rtTexImageFile(RT_TEXTURE_2D, path.c_str());
        check();
        return *this;
    }
    /// rtTexChecker: a 3D checkerboard of cubes of edge 1 / `scale`, colours `a` and `b`.
    Texture &checker(const std::array<RTfloat, 3> &a, const std::array<RTfloat, 3> &b, RTfloat scale) {
        bind();
        rtTexChecker(RT_TEXTURE_2D, a.data(), b.data(), scale);
        check();
        return *this;
    }
    /// rtTexNoise: solid noise blending `a` into `b`, `scale` features per unit length.
    Texture &noise(const std::array<RTfloat, 3> &a, const std::array<RTfloat, 3> &b, RTfloat scale) {
        bind();
        rtTexNoise(RT_TEXTURE_2D, a.data(), b.data(), scale);
        check();
        return *this;
    }
    /// rtTexParameteri: RT_TEXTURE_WRAP_S/T or RT_TEXTURE_MAG_FILTER/MIN_FILTER.
    Texture &parameter(RTenum pname, RTint value) {
        bind();
        rtTexParameteri(RT_TEXTURE_2D, pname, value);
        check();
        return *this;
    }

  private:
    // rtTexImage2D reads width × height pixels of `format` through a bare pointer, so the size
    // of the vector is checked here, where it is known.
    Texture &define_image(RTsizei width, RTsizei height, RTenum format, RTenum type, const void *pixels,
                          std::size_t values, RTint internal_format) {
        std::size_t channels = format == RT_LUMINANCE ? 1 : format == RT_RGB ? 3 : format == RT_RGBA ? 4 : 0;
        // An unknown format or a size beyond the limits is left to rtTexImage2D, which refuses
        // them before reading anything.
        if (channels != 0 && width <= RT_MAX_TEXTURE_SIZE && height <= RT_MAX_TEXTURE_SIZE &&
            values != width * height * channels) {
            throw Error(RT_INVALID_VALUE, "raystage::Texture::image: " + std::to_string(values) + " values are not " +
                                              std::to_string(width) + " x " + std::to_string(height) + " pixels of " +
                                              std::to_string(channels));
        }
        bind();
        rtTexImage2D(RT_TEXTURE_2D, 0, internal_format, width, height, 0, format, type, pixels);
        check();
        return *this;
    }
};

/// A shader class (rtGenShaderClasses + rtNewShaderClass): a built-in class by name, such as
/// "Diffuse", "VertexColor", "Constant", "PointLight", "DirectionalLight", "EnvironmentLight".
/// The C ABI cannot delete a class, so this is a plain value that owns nothing.
class ShaderClass {
  public:
    explicit ShaderClass(const std::string &name) : id_(detail::generated(rtGenShaderClasses(1))) {
        rtNewShaderClass(id_, name.c_str(), nullptr);
        check();
    }
    /// The C id.
    RTuint id() const noexcept { return id_; }

  private:
    RTuint id_;
};

/// A shader of a class (rtGenShaders + rtNewShader), deleted when destroyed: a light shader's
/// light goes out then, and triangles bound to a surface shader get the default one.
class Shader : public detail::Owned<detail::delete_shader> {
  public:
    explicit Shader(const ShaderClass &shader_class) : Owned(detail::generated(rtGenShaders(1))) {
        rtBindShaderClass(shader_class.id());
        rtNewShader(id());
        check();
    }
    /// A shader of a new class of built-in class `class_name`.
    explicit Shader(const std::string &class_name) : Shader(ShaderClass(class_name)) {}
    /// rtBindShader: triangles issued from now on get this shader.
    void bind() const {
        rtBindShader(id());
        check();
    }
    /// Writes a parameter of one number; a name the class does not export is ignored. The shader
    /// bound before stays bound, inside Object::define too: rtParameter* writes the bound
    /// shader's parameters, so this binds the shader for the write only.
    Shader &set(const std::string &name, RTfloat x) {
        return write(name, [&](RTint handle) { rtParameter1f(handle, x); });
    }
    /// Writes a parameter of two numbers.
    Shader &set(const std::string &name, RTfloat x, RTfloat y) {
        return write(name, [&](RTint handle) { rtParameter2f(handle, x, y); });
    }
    /// Writes a parameter of three numbers: a colour, a position, a direction.
    Shader &set(const std::string &name, RTfloat x, RTfloat y, RTfloat z) {
        return write(name, [&](RTint handle) { rtParameter3f(handle, x, y, z); });
    }
    /// Writes a parameter of four numbers.
    Shader &set(const std::string &name, RTfloat x, RTfloat y, RTfloat z, RTfloat w) {
        return write(name, [&](RTint handle) { rtParameter4f(handle, x, y, z, w); });
    }
    /// Makes a texture parameter ("diffuse_texture", "map") name `texture`.
    Shader &set(const std::string &name, const Texture &texture) {
        return write(name, [&](RTint handle) { rtParameterTexture(handle, texture.id()); });
    }

  private:
    /// Binds this shader, writes parameter `name` with `parameter(handle)`, and binds back the
    /// shader bound before (RT_SHADER_BINDING), even if the write fails.
    template <class Write> Shader &write(const std::string &name, Write &&parameter) {
        RTint bound = 0;
        rtGetIntegerv(RT_SHADER_BINDING, &bound);
        check();
        bind();
        // A failed call changes nothing, and the first error sticks: both calls are made, and
        // the error read once, before the binding is restored.
        parameter(rtParameterHandle(name.c_str()));
        RTenum code = rtGetError();
        std::string message = code == RT_NO_ERROR ? "" : rtGetErrorString();
        rtBindShader(static_cast<RTuint>(bound));
        check();
        if (code != RT_NO_ERROR) {
            throw Error(code, message);
        }
        return *this;
    }
};

// ---------------------------------------------------------------------------------------------
// Objects and instances.

/// A primitive (rtBegin/rtEnd) for the scope of this object, inside Object::define.
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

/// rtTriangleMesh, inside Object::define: `positions` and the optional `normals` and `colors`
/// hold 3 values per vertex, `texcoords` 2, `indices` 3 vertex indices per triangle. Empty
/// optional arrays leave the current normal, colour or texture coordinates to every vertex.
inline void triangle_mesh(const std::vector<RTfloat> &positions, const std::vector<RTuint> &indices,
                          const std::vector<RTfloat> &normals = {}, const std::vector<RTfloat> &colors = {},
                          const std::vector<RTfloat> &texcoords = {}) {
    // rtTriangleMesh reads its arrays through bare pointers and counts, so their sizes are
    // checked here, where they are known.
    std::size_t vertices = positions.size() / 3;
    auto per_vertex = [vertices](const std::vector<RTfloat> &values, std::size_t each) {
        return values.empty() || values.size() == vertices * each;
    };
    if (positions.size() % 3 != 0 || indices.size() % 3 != 0 || !per_vertex(normals, 3) || !per_vertex(colors, 3) ||
        !per_vertex(texcoords, 2)) {
        throw Error(RT_INVALID_VALUE, "raystage::triangle_mesh: " + std::to_string(positions.size()) + " positions, " +
                                          std::to_string(normals.size()) + " normals, " + std::to_string(colors.size()) +
                                          " colours, " + std::to_string(texcoords.size()) +
                                          " texture coordinates and " + std::to_string(indices.size()) +
                                          " indices do not make whole vertices and triangles");
    }
    auto optional = [](const std::vector<RTfloat> &values) { return values.empty() ? nullptr : values.data(); };
    rtTriangleMesh(positions.data(), optional(normals), optional(colors), optional(texcoords), vertices, indices.data(),
                   indices.size() / 3);
    check();
}

class Object;

/// An instance of an object (rtInstantiateObject), removed from the scene when destroyed, unless
/// its Object was destroyed first (which removed it).
class [[nodiscard]] Instance {
  public:
    Instance(Instance &&other) noexcept
        : id_(std::exchange(other.id_, 0)), object_(std::move(other.object_)), lifetime_(other.lifetime_) {}
    Instance &operator=(Instance &&other) noexcept {
        if (this != &other) {
            remove();
            id_ = std::exchange(other.id_, 0);
            object_ = std::move(other.object_);
            lifetime_ = other.lifetime_;
        }
        return *this;
    }
    ~Instance() { remove(); }
    Instance(const Instance &) = delete;
    Instance &operator=(const Instance &) = delete;

    /// The C id (0 once moved from).
    RTuint id() const noexcept { return id_; }
    /// rtMoveInstance: moves the instance to the current modelview matrix.
    void move() const {
        rtMoveInstance(id_);
        check();
    }
    /// rtInstanceMotion: the current modelview matrix becomes the instance's transform at the
    /// shutter's close (motion blur: call move first, then this, each frame).
    void move_by_shutter_close() const {
        rtInstanceMotion(id_);
        check();
    }

  private:
    friend class Object;
    Instance(RTuint id, std::weak_ptr<const void> object) : id_(id), object_(std::move(object)) {}
    void remove() noexcept {
        if (id_ != 0 && !object_.expired() && lifetime_.alive()) {
            rtDeleteInstance(id_);
        }
        id_ = 0;
    }

    RTuint id_;
    // Expires when the Object dies: rtDeleteObjects removed this instance then, and deleting it
    // again would be an error.
    std::weak_ptr<const void> object_;
    detail::Lifetime lifetime_;
};

/// An object (rtGenObjects): geometry with its own acceleration structure, deleted with all its
/// instances when destroyed.
class Object : public detail::Owned<detail::delete_object> {
  public:
    Object() : Owned(detail::generated(rtGenObjects(1))) {}

    /// (Re)defines the object as the geometry that `issue()` issues, of kind RT_STATIC,
    /// RT_ANIMATED or RT_UNSTRUCTURED; every instance follows a new definition. If `issue`
    /// throws, the definition (and a primitive left open) is ended before the exception goes on,
    /// and what it recorded is discarded, so the context is ready for the next call; the object
    /// then holds the triangles issued before the throw, or its previous geometry if there were
    /// none (rtEndObject's rule).
    template <class Issue> void define(Issue &&issue, RTenum kind = RT_STATIC) {
        rtObjectKind(kind);
        check();
        rtNewObject(id(), RT_COMPILE);
        check();
        try {
            std::forward<Issue>(issue)();
        } catch (...) {
            rtEndObject();
            // The exception reports what went wrong: an error the aborted definition left
            // pending (say, an object without triangles) would otherwise surface at the next
            // call as if that call had failed.
            rtGetError();
            throw;
        }
        rtEndObject();
        check();
    }

    /// rtInstantiateObject: places an instance with the current modelview matrix.
    [[nodiscard]] Instance instantiate() const {
        RTuint instance = rtInstantiateObject(id());
        check();
        return Instance(instance, alive_);
    }

  private:
    // Shared with this object's Instances, which must not delete themselves once it is gone.
    std::shared_ptr<const void> alive_ = std::make_shared<char>();
};

// ---------------------------------------------------------------------------------------------
// Frame buffers and frames.

/// What a pixel sees (rtPick): the instance, object and triangle ids.
struct Hit {
    RTuint instance = 0;
    RTuint object = 0;
    RTuint triangle = 0;
};

/// How an asynchronous frame ended.
enum class FrameStatus {
    /// Its image is in the frame buffer.
    completed,
    /// Frame::cancel stopped it first; the frame buffer was left as it was.
    cancelled,
};

/// An RGBA8 frame buffer (sRGB bytes) in this object's memory. It attaches itself with
/// rtFrameBuffer before each frame it renders, and detaches when destroyed only if it is the one
/// attached (after releasing its frame in flight, whose image must not reach freed memory).
class FrameBuffer {
  public:
    /// `width` × `height` pixels of `format`: RT_RGBA8 (sRGB bytes, read with `pixel`) or
    /// RT_RGBA32F (linear floats, unclamped, read with `linear`).
    FrameBuffer(std::size_t width, std::size_t height, RTenum format = RT_RGBA8)
        : width_(width), height_(height), format_(format) {
        if (width < 1 || height < 1 || width > RT_MAX_FRAMEBUFFER_SIZE || height > RT_MAX_FRAMEBUFFER_SIZE) {
            throw Error(RT_INVALID_VALUE, "raystage::FrameBuffer: " + std::to_string(width) + " x " +
                                              std::to_string(height) + " pixels: each side must be 1 to " +
                                              std::to_string(RT_MAX_FRAMEBUFFER_SIZE));
        }
        if (format != RT_RGBA8 && format != RT_RGBA32F) {
            throw Error(RT_INVALID_ENUM, "raystage::FrameBuffer: the format must be RT_RGBA8 or RT_RGBA32F");
        }
        pixels_.resize(width * height * bytes_per_pixel());
    }
    FrameBuffer(FrameBuffer &&other) noexcept;
    FrameBuffer &operator=(FrameBuffer &&other) noexcept;
    ~FrameBuffer();
    FrameBuffer(const FrameBuffer &) = delete;
    FrameBuffer &operator=(const FrameBuffer &) = delete;

    /// rtFrameBuffer: attaches this buffer (done by every call below that needs it).
    void attach() {
        if (pixels_.empty()) {
            // rtFrameBuffer(NULL, 0, 0) would detach rather than fail.
            throw Error(RT_INVALID_OPERATION, "raystage::FrameBuffer: this frame buffer was moved from");
        }
        rtFrameBuffer(pixels_.data(), width_, height_, format_);
        check();
        // This buffer's channels, and none of another buffer's (of another size, or freed).
        for (RTenum channel : detail::channels) {
            std::vector<std::uint32_t> *data = channel_data(channel);
            rtChannelBuffer(channel, data ? data->data() : nullptr, data ? width_ : 0, data ? height_ : 0);
        }
        check();
        detail::thread().attached = this;
    }
    /// rtChannelBuffer: every frame rendered into this buffer from now on also fills `channel`
    /// (RT_DEPTH_CHANNEL, RT_Z_CHANNEL, RT_NORMAL_CHANNEL, RT_ALBEDO_CHANNEL,
    /// RT_INSTANCE_ID_CHANNEL, RT_OBJECT_ID_CHANNEL or RT_PRIMITIVE_ID_CHANNEL).
    void enable(RTenum channel) {
        if (channel_data(channel) == nullptr) {
            std::size_t components = channel == RT_NORMAL_CHANNEL || channel == RT_ALBEDO_CHANNEL ? 3 : 1;
            channels_.emplace_back(channel, std::vector<std::uint32_t>(width_ * height_ * components));
        }
        if (attached()) {
            attach();
        }
    }
    /// Value `k` (0 to 2 for normals and albedo) of float channel `channel` at pixel (x, y), as
    /// the last frame left it.
    float value(RTenum channel, std::size_t x, std::size_t y, std::size_t k = 0) const {
        std::size_t components = channel == RT_NORMAL_CHANNEL || channel == RT_ALBEDO_CHANNEL ? 3 : 1;
        float v;
        std::memcpy(&v, &enabled(channel)[(y * width_ + x) * components + k], sizeof v);
        return v;
    }
    /// Id channel `channel` at pixel (x, y), as the last frame left it (0 or RT_NO_PRIMITIVE for
    /// none).
    RTuint id(RTenum channel, std::size_t x, std::size_t y) const { return enabled(channel)[y * width_ + x]; }
    /// Whether this buffer is the attached one.
    bool attached() const { return detail::thread().attached == this; }
    /// rtSwapBuffers: renders a frame into this buffer.
    void swap() {
        attach_if_detached();
        rtSwapBuffers();
        check();
        detail::thread().last = this;
    }
    /// rtRenderFrameAsync: starts rendering a frame into this buffer on a thread of its own.
    [[nodiscard]] Frame render_async();
    /// rtPick: what pixel (x, y) of this buffer sees in the scene as it is now.
    std::optional<Hit> pick(RTuint x, RTuint y) {
        attach_if_detached();
        Hit hit;
        RTboolean seen = rtPick(x, y, &hit.instance, &hit.object, &hit.triangle);
        check();
        return seen ? std::optional<Hit>(hit) : std::nullopt;
    }
    /// rtWritePNG: writes this buffer's last frame as a PNG file. rtWritePNG writes the context's
    /// last frame, so this refuses (RT_INVALID_OPERATION) once another buffer rendered one.
    void write_png(const std::string &path) const {
        if (detail::thread().last != this) {
            throw Error(RT_INVALID_OPERATION, "raystage::FrameBuffer::write_png: the last frame was not rendered "
                                              "into this frame buffer");
        }
        rtWritePNG(path.c_str());
        check();
    }
    /// The sRGB bytes (red, green, blue, alpha) of pixel (x, y) of an RT_RGBA8 buffer, row 0 at
    /// the top.
    const std::uint8_t *pixel(std::size_t x, std::size_t y) const {
        if (format_ != RT_RGBA8) {
            throw Error(RT_INVALID_OPERATION, "raystage::FrameBuffer::pixel: this buffer holds floats: read it with linear()");
        }
        return &pixels_[(y * width_ + x) * 4];
    }
    /// The linear red, green, blue and alpha of pixel (x, y) of an RT_RGBA32F buffer, row 0 at
    /// the top.
    std::array<float, 4> linear(std::size_t x, std::size_t y) const {
        if (format_ != RT_RGBA32F) {
            throw Error(RT_INVALID_OPERATION, "raystage::FrameBuffer::linear: this buffer holds sRGB bytes: read it with pixel()");
        }
        std::array<float, 4> rgba;
        std::memcpy(rgba.data(), &pixels_[(y * width_ + x) * 16], sizeof rgba);
        return rgba;
    }
    /// RT_RGBA8 or RT_RGBA32F.
    RTenum format() const noexcept { return format_; }
    /// Width in pixels.
    std::size_t width() const noexcept { return width_; }
    /// Height in pixels.
    std::size_t height() const noexcept { return height_; }

  private:
    friend class Frame;
    void attach_if_detached() {
        if (!attached()) {
            attach();
        }
    }
    void detach() noexcept;
    /// Takes over `other`'s pixels, the attachment and its frame in flight.
    void take(FrameBuffer &other) noexcept;
    std::size_t bytes_per_pixel() const noexcept { return format_ == RT_RGBA32F ? 16 : 4; }

    /// The memory of `channel`, if enabled.
    std::vector<std::uint32_t> *channel_data(RTenum channel) {
        for (auto &c : channels_) {
            if (c.first == channel) {
                return &c.second;
            }
        }
        return nullptr;
    }
    const std::vector<std::uint32_t> &enabled(RTenum channel) const {
        for (const auto &c : channels_) {
            if (c.first == channel) {
                return c.second;
            }
        }
        throw Error(RT_INVALID_OPERATION, "raystage::FrameBuffer: that channel is not enabled");
    }

    std::size_t width_, height_;
    RTenum format_;
    // Moving a vector keeps its memory where it is, so a moved buffer stays attached.
    std::vector<std::uint8_t> pixels_;
    // The channels enabled, each as 4-byte values (floats or ids).
    std::vector<std::pair<RTenum, std::vector<std::uint32_t>>> channels_;
    // The frame rendering into this buffer, if any: rtFrameIsReady or rtFrameWait write its
    // image here, so it is released before the pixels are freed.
    Frame *in_flight_ = nullptr;
};

/// An asynchronous frame (rtRenderFrameAsync), a move-only future: `ready` polls, `wait` blocks,
/// `cancel` stops it, `progress` says how much is rendered; the destructor releases it
/// (rtFrameRelease cancels a frame still in flight, and its image never arrives). Its image lands
/// in its FrameBuffer in the `ready` or `wait` call that first finds it completed.
class [[nodiscard]] Frame {
  public:
    /// No frame: every call but the destructor fails with RT_INVALID_VALUE.
    Frame() = default;
    Frame(Frame &&other) noexcept { take(other); }
    Frame &operator=(Frame &&other) noexcept {
        if (this != &other) {
            release();
            take(other);
        }
        return *this;
    }
    ~Frame() { release(); }
    Frame(const Frame &) = delete;
    Frame &operator=(const Frame &) = delete;

    /// The C handle (0 for no frame: moved from, released, or default-constructed).
    RTuint id() const noexcept { return id_; }
    /// rtFrameIsReady: whether the frame finished (completed, or stopped by cancel). Never
    /// blocks; a failed frame throws its Error.
    [[nodiscard]] bool ready() {
        RTboolean done = rtFrameIsReady(id_);
        check();
        if (done) {
            // The frame is over: rtFrameWait returns its status at once.
            finished(rtFrameWait(id_));
        }
        return done;
    }
    /// rtFrameWait: blocks until the frame finished and says how; a failed frame throws its Error.
    FrameStatus wait() { return finished(rtFrameWait(id_)); }
    /// rtFrameCancel: asks the frame to stop and returns at once.
    void cancel() const {
        rtFrameCancel(id_);
        check();
    }
    /// rtFrameProgress: the share of the image rendered, 0 to 1, never decreasing.
    [[nodiscard]] RTfloat progress() const {
        RTfloat share = rtFrameProgress(id_);
        check();
        return share;
    }

  private:
    friend class FrameBuffer;
    Frame(RTuint id, FrameBuffer *target) : id_(id), target_(target) { target_->in_flight_ = this; }
    FrameStatus finished(RTenum status) {
        check();
        if (target_ != nullptr) {
            if (status == RT_NO_ERROR) {
                detail::thread().last = target_;
            }
            target_->in_flight_ = nullptr;
            target_ = nullptr;
        }
        return status == RT_CANCELLED ? FrameStatus::cancelled : FrameStatus::completed;
    }
    void release() noexcept {
        if (id_ != 0 && lifetime_.alive()) {
            rtFrameRelease(id_);
        }
        if (target_ != nullptr) {
            target_->in_flight_ = nullptr;
        }
        id_ = 0;
        target_ = nullptr;
    }
    void take(Frame &other) noexcept {
        id_ = std::exchange(other.id_, 0);
        target_ = std::exchange(other.target_, nullptr);
        lifetime_ = other.lifetime_;
        if (target_ != nullptr) {
            target_->in_flight_ = this;
        }
    }

    RTuint id_ = 0;
    // The buffer the frame renders into while it is in flight, else null.
    FrameBuffer *target_ = nullptr;
    detail::Lifetime lifetime_;
};

inline FrameBuffer::FrameBuffer(FrameBuffer &&other) noexcept : width_(0), height_(0), format_(RT_RGBA8) { take(other); }

inline FrameBuffer &FrameBuffer::operator=(FrameBuffer &&other) noexcept {
    if (this != &other) {
        detach();
        take(other);
    }
    return *this;
}

inline FrameBuffer::~FrameBuffer() { detach(); }

inline Frame FrameBuffer::render_async() {
    attach_if_detached();
    RTuint id = rtRenderFrameAsync();
    check();
    return Frame(id, this);
}

inline void FrameBuffer::detach() noexcept {
    if (in_flight_ != nullptr) {
        in_flight_->release();
    }
    detail::Thread &state = detail::thread();
    if (state.last == this) {
        state.last = nullptr;
    }
    if (state.attached == this) {
        rtFrameBuffer(nullptr, 0, 0, RT_RGBA8);
        for (const auto &c : channels_) {
            rtChannelBuffer(c.first, nullptr, 0, 0);
        }
        state.attached = nullptr;
    }
}

inline void FrameBuffer::take(FrameBuffer &other) noexcept {
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
    format_ = other.format_;
    pixels_ = std::move(other.pixels_);
    channels_ = std::move(other.channels_);
    in_flight_ = std::exchange(other.in_flight_, nullptr);
    if (in_flight_ != nullptr) {
        in_flight_->target_ = this;
    }
    detail::Thread &state = detail::thread();
    if (state.attached == &other) {
        state.attached = this;
    }
    if (state.last == &other) {
        state.last = this;
    }
}

} // namespace raystage

#endif // RAYSTAGE_RT_HPP
