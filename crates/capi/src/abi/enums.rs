//! The constants of the C ABI. Values that OpenGL also has keep OpenGL's numbers, so a ported
//! program's constants mean the same; raystage's own values start at 0x9000.

use crate::abi::types::{RTenum, RTfloat, RTint, RTsizei, RTuint};

// ----- error codes (rtGetError) -----

/// No error has been recorded since the last `rtGetError`.
pub const RT_NO_ERROR: RTenum = 0;
/// An `RTenum` argument is not one of the values the call accepts.
pub const RT_INVALID_ENUM: RTenum = 0x0500;
/// A numeric or pointer argument is out of range: NaN or infinite, an id that names nothing, a
/// NULL pointer, a size beyond the limits.
pub const RT_INVALID_VALUE: RTenum = 0x0501;
/// The call is not allowed in the current state (for example `rtVertex3f` outside
/// `rtBegin`/`rtEnd`, or `rtEndObject` with no object being defined).
pub const RT_INVALID_OPERATION: RTenum = 0x0502;
/// `rtPushMatrix` on a full matrix stack (`RT_MAX_STACK_DEPTH` matrices).
pub const RT_STACK_OVERFLOW: RTenum = 0x0503;
/// `rtPopMatrix` on a stack holding one matrix.
pub const RT_STACK_UNDERFLOW: RTenum = 0x0504;
/// Memory could not be allocated, or a count exceeds raystage's limits.
pub const RT_OUT_OF_MEMORY: RTenum = 0x0505;
/// A file could not be written (`rtWritePNG`).
pub const RT_IO_ERROR: RTenum = 0x9000;
/// raystage itself failed (a bug): the call was stopped. Please report the message.
pub const RT_INTERNAL_ERROR: RTenum = 0x9001;
/// Not an error but a frame's status: `rtFrameWait` of a frame that `rtFrameCancel` stopped
/// before it completed. Never recorded for `rtGetError`.
pub const RT_CANCELLED: RTenum = 0x9002;

// ----- objects -----

/// `rtNewObject` mode: record the object (the only mode; OpenGL's `GL_COMPILE`).
pub const RT_COMPILE: RTenum = 0x1300;
/// Object kind (`rtObjectKind`): geometry that never changes; it gets the best tree, once.
pub const RT_STATIC: RTenum = 0x9010;
/// Object kind: moves only through its instances (`rtMoveInstance`); never rebuilt.
pub const RT_ANIMATED: RTenum = 0x9011;
/// Object kind: redefined often with `rtNewObject` on the same id; its tree is refitted while
/// that stays cheap, else rebuilt fast.
pub const RT_UNSTRUCTURED: RTenum = 0x9012;

// ----- primitives (rtBegin) -----

/// Independent triangles: vertices 3i, 3i+1, 3i+2.
pub const RT_TRIANGLES: RTenum = 0x0004;
/// A triangle strip: each vertex after the second makes a triangle with the two before it.
pub const RT_TRIANGLE_STRIP: RTenum = 0x0005;
/// A triangle fan around the first vertex.
pub const RT_TRIANGLE_FAN: RTenum = 0x0006;
/// Independent quadrilaterals, four vertices each, split into two triangles.
pub const RT_QUADS: RTenum = 0x0007;
/// A strip of quadrilaterals: each pair of vertices after the first pair adds one.
pub const RT_QUAD_STRIP: RTenum = 0x0008;
/// One convex polygon, fanned around its first vertex.
pub const RT_POLYGON: RTenum = 0x0009;

// ----- shade model (rtShadeModel) -----

/// Each triangle takes the normal and colour of one vertex (OpenGL's provoking vertex).
pub const RT_FLAT: RTenum = 0x1D00;
/// Normals and colours are interpolated across each triangle (the default).
pub const RT_SMOOTH: RTenum = 0x1D01;

// ----- matrices (rtMatrixMode) -----

/// The modelview stack: transforms vertices issued inside objects, and places instances.
pub const RT_MODELVIEW: RTenum = 0x1700;
/// The texture stack: transforms texture coordinates as they are issued.
pub const RT_TEXTURE: RTenum = 0x1702;
/// Matrices each stack holds at most; a push beyond records `RT_STACK_OVERFLOW`.
pub const RT_MAX_STACK_DEPTH: RTsizei = 32;

// ----- state queries (rtGetFloatv, rtGetDoublev, rtGetIntegerv), OpenGL's values -----

/// The current colour, 4 values: `rtColor3f`/`rtColor4f`'s red, green, blue and alpha
/// (initially 1, 1, 1, 1).
pub const RT_CURRENT_COLOR: RTenum = 0x0B00;
/// The current normal, 3 values (initially 0, 0, 1).
pub const RT_CURRENT_NORMAL: RTenum = 0x0B02;
/// The current texture coordinates, 4 values: s, t, 0, 1 (initially 0, 0, 0, 1).
pub const RT_CURRENT_TEXTURE_COORDS: RTenum = 0x0B03;
/// The shade model, 1 value: `RT_SMOOTH` or `RT_FLAT`.
pub const RT_SHADE_MODEL: RTenum = 0x0B54;
/// The matrix mode, 1 value: `RT_MODELVIEW` or `RT_TEXTURE`.
pub const RT_MATRIX_MODE: RTenum = 0x0BA0;
/// The frame buffer's extent, 4 values: 0, 0, width, height (all 0 without a frame buffer).
pub const RT_VIEWPORT: RTenum = 0x0BA2;
/// Matrices on the modelview stack, 1 value (1 to `RT_MAX_STACK_DEPTH`).
pub const RT_MODELVIEW_STACK_DEPTH: RTenum = 0x0BA3;
/// Matrices on the texture stack, 1 value.
pub const RT_TEXTURE_STACK_DEPTH: RTenum = 0x0BA5;
/// The modelview stack's top matrix, 16 values in column-major order (as `rtLoadMatrixf`
/// takes them).
pub const RT_MODELVIEW_MATRIX: RTenum = 0x0BA6;
/// The texture stack's top matrix, 16 values in column-major order.
pub const RT_TEXTURE_MATRIX: RTenum = 0x0BA8;
/// The colour `rtClearColor` set, 4 values; −1, −1, −1, −1 while the default background
/// applies (see `rtClearColor`).
pub const RT_COLOR_CLEAR_VALUE: RTenum = 0x0C22;
/// The texture bound with `rtBindTexture`, 1 value (0 for none).
pub const RT_TEXTURE_BINDING_2D: RTenum = 0x8069;
/// The shader bound with `rtBindShader` (or `rtNewShader`), 1 value (0 for none): what a library
/// that binds a shader for a moment binds back (OpenGL's `GL_CURRENT_PROGRAM`).
pub const RT_SHADER_BINDING: RTenum = 0x8B8D;

// ----- shader parameters (rtParameterScope) -----

/// Parameters are stored in the bound shader (the default, and what every built-in class uses).
pub const RT_PER_SHADER: RTenum = 0x9020;
/// Parameters stored per scene. No built-in class declares such parameters: selecting this scope
/// records `RT_INVALID_ENUM`.
pub const RT_PER_SCENE: RTenum = 0x9021;
/// Parameters stored per object. Not supported yet: records `RT_INVALID_ENUM`.
pub const RT_PER_OBJECT: RTenum = 0x9022;
/// Parameters stored per triangle. Not supported yet: records `RT_INVALID_ENUM`.
pub const RT_PER_TRIANGLE: RTenum = 0x9023;
/// Parameters stored per vertex. Not supported yet (per-vertex data are the colour, normal and
/// texture coordinates of `rtColor3f`, `rtNormal3f`, `rtTexCoord2f`): records `RT_INVALID_ENUM`.
pub const RT_PER_VERTEX: RTenum = 0x9024;

// ----- frame buffers (rtFrameBuffer) -----

/// Four bytes per pixel: sRGB-encoded red, green, blue, and alpha 255. (As a texture's internal
/// format in `rtTexImage2D`: 8-bit linear values, as in OpenGL.)
pub const RT_RGBA8: RTenum = 0x8058;
/// Four floats per pixel (native byte order): linear red, green, blue, and alpha 1. (As a
/// texture's internal format in `rtTexImage2D`: linear floats.)
pub const RT_RGBA32F: RTenum = 0x8814;
/// Largest frame buffer width or height.
pub const RT_MAX_FRAMEBUFFER_SIZE: RTsizei = 16384;

// ----- channels (rtChannelBuffer) -----

/// Channel: one float per pixel, the distance along the camera ray to the first surface
/// (`INFINITY` where the ray meets nothing).
pub const RT_DEPTH_CHANNEL: RTenum = 0x9050;
/// Channel: one float per pixel, the camera-space depth of the first surface (its distance
/// from the eye along the view axis; `INFINITY` where there is none).
pub const RT_Z_CHANNEL: RTenum = 0x9051;
/// Channel: three floats per pixel, the unit shading normal in the world (normal maps
/// applied), facing the camera; zero where nothing is hit.
pub const RT_NORMAL_CHANNEL: RTenum = 0x9052;
/// Channel: three floats per pixel, the surface's linear albedo (its base colour, textured and
/// vertex coloured); zero where nothing is hit.
pub const RT_ALBEDO_CHANNEL: RTenum = 0x9053;
/// Channel: one `RTuint` per pixel, the id of the instance seen (as `rtInstantiateObject`
/// returned it; 0 where there is none).
pub const RT_INSTANCE_ID_CHANNEL: RTenum = 0x9054;
/// Channel: one `RTuint` per pixel, the id of the object seen (0 where there is none).
pub const RT_OBJECT_ID_CHANNEL: RTenum = 0x9055;
/// Channel: one `RTuint` per pixel, the triangle seen, counted from 0 in its object as `rtPick`
/// counts it (`RT_NO_PRIMITIVE` where there is none).
pub const RT_PRIMITIVE_ID_CHANNEL: RTenum = 0x9056;
/// What `RT_PRIMITIVE_ID_CHANNEL` holds where a pixel sees nothing.
pub const RT_NO_PRIMITIVE: RTuint = 0xFFFF_FFFF;

// ----- introspection (rtGetShaderClass*, rtGetShaderParameter*) -----

/// `rtGetShaderClassKind`: a surface class (`rtBindShader` binds its shaders to geometry).
pub const RT_SURFACE_CLASS: RTenum = 0x9060;
/// `rtGetShaderClassKind`: a light class (its shaders light the scene while they exist).
pub const RT_LIGHT_CLASS: RTenum = 0x9061;
/// `rtGetShaderParameterType`: three numbers (a colour, a position or a direction), written
/// with `rtParameter3f`. (A number is `RT_FLOAT`, `rtParameter1f`; a texture `RT_TEXTURE_2D`,
/// `rtParameterTexture`.)
pub const RT_FLOAT_VEC3: RTenum = 0x8B51;

// ----- textures (rtBindTexture, rtTexImage2D) -----

/// The texture target of every texture call: raystage's textures are two-dimensional images or
/// procedural textures looked up in object space.
pub const RT_TEXTURE_2D: RTenum = 0x0DE1;
/// `rtTexImage2D` pixel format: one grey value per pixel.
pub const RT_LUMINANCE: RTenum = 0x1909;
/// `rtTexImage2D` pixel format (and internal format): red, green and blue per pixel.
pub const RT_RGB: RTenum = 0x1907;
/// `rtTexImage2D` pixel format (and internal format): red, green, blue and alpha per pixel;
/// alpha is ignored.
pub const RT_RGBA: RTenum = 0x1908;
/// `rtTexImage2D` internal format: 8-bit linear values (byte ÷ 255), as `RT_RGB`.
pub const RT_RGB8: RTenum = 0x8051;
/// `rtTexImage2D` internal format: 8-bit sRGB-encoded values, decoded to linear light (what
/// photographs and PNG files hold).
pub const RT_SRGB8: RTenum = 0x8C41;
/// `rtTexImage2D` internal format: as `RT_SRGB8`, with an alpha value per pixel (ignored).
pub const RT_SRGB8_ALPHA8: RTenum = 0x8C43;
/// `rtTexImage2D` internal format: linear floats (high dynamic range), as `RT_RGB`.
pub const RT_RGB32F: RTenum = 0x8815;
/// `rtTexImage2D` pixel type: one unsigned byte per value.
pub const RT_UNSIGNED_BYTE: RTenum = 0x1401;
/// `rtTexImage2D` pixel type: one float per value (native byte order), linear.
pub const RT_FLOAT: RTenum = 0x1406;
/// Largest texture width or height.
pub const RT_MAX_TEXTURE_SIZE: RTsizei = 16384;

// ----- texture parameters (rtTexParameteri), OpenGL's values -----

/// How the bound texture is magnified: `RT_NEAREST` or `RT_LINEAR` (the default, bilinear).
pub const RT_TEXTURE_MAG_FILTER: RTenum = 0x2800;
/// How the bound texture is minified: accepted (`RT_NEAREST`, `RT_LINEAR` or a mipmap mode) for
/// OpenGL programs that set it, but without effect: a ray has no footprint to minify over, so
/// every lookup uses `RT_TEXTURE_MAG_FILTER`.
pub const RT_TEXTURE_MIN_FILTER: RTenum = 0x2801;
/// How texture coordinate s wraps: `RT_REPEAT` (the default), `RT_CLAMP_TO_EDGE` or
/// `RT_MIRRORED_REPEAT`.
pub const RT_TEXTURE_WRAP_S: RTenum = 0x2802;
/// How texture coordinate t wraps, as `RT_TEXTURE_WRAP_S`.
pub const RT_TEXTURE_WRAP_T: RTenum = 0x2803;
/// The nearest texel.
pub const RT_NEAREST: RTenum = 0x2600;
/// Bilinear interpolation of the four nearest texels.
pub const RT_LINEAR: RTenum = 0x2601;
/// A minification filter of OpenGL's mipmaps (accepted, without effect).
pub const RT_NEAREST_MIPMAP_NEAREST: RTenum = 0x2700;
/// A minification filter of OpenGL's mipmaps (accepted, without effect).
pub const RT_LINEAR_MIPMAP_NEAREST: RTenum = 0x2701;
/// A minification filter of OpenGL's mipmaps (accepted, without effect; OpenGL's default).
pub const RT_NEAREST_MIPMAP_LINEAR: RTenum = 0x2702;
/// A minification filter of OpenGL's mipmaps (accepted, without effect).
pub const RT_LINEAR_MIPMAP_LINEAR: RTenum = 0x2703;
/// The image tiles the plane.
pub const RT_REPEAT: RTenum = 0x2901;
/// Coordinates beyond the image take its edge texels.
pub const RT_CLAMP_TO_EDGE: RTenum = 0x812F;
/// The image tiles the plane, every other copy mirrored.
pub const RT_MIRRORED_REPEAT: RTenum = 0x8370;

// ----- rendering (rtRenderMode, rtRenderParameteri) -----

/// `rtRenderMode` (the default): the integrator `raystage render` and the HTTP API choose for
/// the scene: `RT_PATH` where an image environment lights it, `RT_WHITTED` where anything else
/// does (a light, an emitting surface, or the default sky while `RT_DEFAULT_LIGHTS` is on), else
/// `RT_EYELIGHT`, so that an unlit scene is not black. (Before 2026-12-06 it ignored
/// `RT_DEFAULT_LIGHTS` and image environments: an unlit scene was previewed by `RT_EYELIGHT`.)
pub const RT_AUTO: RTenum = 0x9030;
/// `rtRenderMode`: a fast preview lit by a light at the eye; no shadows, no secondary rays.
pub const RT_EYELIGHT: RTenum = 0x9031;
/// `rtRenderMode`: Whitted's ray tracing: shadows, mirror reflection and refraction, recursively.
pub const RT_WHITTED: RTenum = 0x9032;
/// `rtRenderMode`: Cook's distribution ray tracing: Whitted's rays spread over the pixel, the
/// lens (depth of field), the shutter (motion blur), area lights and glossy reflections.
pub const RT_DISTRIBUTION: RTenum = 0x9033;
/// `rtRenderMode`: path tracing (global illumination), with depth of field and motion blur too.
pub const RT_PATH: RTenum = 0x9034;

/// `rtGetRenderParameteri`: the mode `rtRenderMode` set (`RT_AUTO`, `RT_EYELIGHT`, ...).
pub const RT_RENDER_MODE: RTenum = 0x9040;
/// Render parameter: samples per pixel each `rtSwapBuffers` renders, 1 to `RT_MAX_SAMPLES`
/// (default 1). Depth of field and motion blur need many to be smooth.
pub const RT_SAMPLES_PER_PIXEL: RTenum = 0x9041;
/// Render parameter: the deepest recursion (Whitted, distribution) or the longest path (path
/// tracer), 1 to `RT_MAX_RAY_DEPTH` (default 6).
pub const RT_RAY_DEPTH: RTenum = 0x9042;
/// Render parameter: shadow rays per area or environment light at each shading point of the
/// distribution ray tracer and the path tracer, 1 to `RT_MAX_LIGHT_SAMPLES` (default 1).
pub const RT_LIGHT_SAMPLES: RTenum = 0x9043;
/// Render parameter: 1 (the default) lets the path tracer end paths early by Russian roulette
/// (cheaper samples, more noise, no bias); 0 runs every path to `RT_RAY_DEPTH`.
pub const RT_RUSSIAN_ROULETTE: RTenum = 0x9044;
/// Render parameter: the seed of the sample sequences, 0 (the default) or more. Frames with the
/// same seed and scene are the same image; frames with different seeds have independent noise.
pub const RT_SEED: RTenum = 0x9045;
/// Render parameter: 1 (the default) lights a scene that nothing lights (no light, no emitting
/// surface) by the sky, as an environment light; 0 leaves it dark.
pub const RT_DEFAULT_LIGHTS: RTenum = 0x9046;
/// Largest `RT_SAMPLES_PER_PIXEL`.
pub const RT_MAX_SAMPLES: RTint = 65536;
/// Largest `RT_RAY_DEPTH`.
pub const RT_MAX_RAY_DEPTH: RTint = 64;
/// Largest `RT_LIGHT_SAMPLES`.
pub const RT_MAX_LIGHT_SAMPLES: RTint = 256;

// ----- limits -----

/// Largest magnitude of a vertex coordinate once transformed by the modelview matrix, of an
/// instance's reach (its object's bounds placed by the matrix), of a matrix's translation, and
/// of the camera's points and planes: `rtVertex*`, `rtTriangleMesh`, `rtInstantiateObject`,
/// `rtMoveInstance`, `rtInstanceMotion`, the matrix calls, `rtLookAt`, `rtOrtho` and `rtFrustum`
/// refuse more with `RT_INVALID_VALUE`. A matrix's other entries (its scale, its rotation) need
/// only be finite: the bound is on what the matrix places, so a large scale may place a small
/// object. Single-precision arithmetic renders scenes within it correctly; beyond it shading and
/// hit points lose their precision, and squared distances overflow.
pub const RT_MAX_COORDINATE: RTfloat = 1e8;

/// Most ids of each kind (objects, shaders, shader classes, textures) that one context can
/// generate.
pub const RT_MAX_IDS: RTsizei = 1 << 20;
