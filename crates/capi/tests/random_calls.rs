//! Random sequences of every C call in rt.h and RTUT's rtut.h, valid and invalid, through the
//! `extern "C"` functions: no panic escapes, no call fails inside raystage (`RT_INTERNAL_ERROR`), every call
//! the model can judge records the error it predicts, a refused call changes none of the state
//! the context reports (`rtGet*v`, the render parameters), the render settings read back are the
//! last ones accepted, and whatever happened, the scene still renders. Asynchronous frames start,
//! are waited for, cancelled and released among the edits; frame buffers and channel buffers are
//! lent and taken back at other sizes; RTUT runs its main loop headless, whose display callback
//! makes calls of its own (the window resized, frames swapped into it), and `rtResetContext`
//! starts over in the middle. RTUT is the `rtut` crate's, written on rt.h alone: its calls of
//! rt.h link to the C ABI this test calls, as librtut.so's link to libraystage.so.
//!
//! Each sequence runs on a thread of its own, so that it starts with a fresh context and a fresh
//! RTUT. `random_calls_under_valgrind` runs 256 sequences again under valgrind
//! (`RAYSTAGE_RANDOM_CALLS_CASES`), which fails on any access to freed memory; there
//! `RAYSTAGE_PRINT_CALLS` prints each sequence before it runs, so that a report or a crash names
//! it.
//!
//! `every_call_in_rt_h_is_generated` fails when rt.h or rtut.h gains a call the generator does
//! not make.

use std::cell::RefCell;
use std::ffi::CString;
use std::path::PathBuf;
use std::sync::OnceLock;

use proptest::prelude::*;
use raystage_capi::abi::*;
use raystage_scene::SHADER_CLASSES;
use rtut::*;

/// One C call with its arguments.
#[derive(Clone, Debug)]
enum Call {
    GenObjects(usize),
    NewObject(RTuint, RTenum),
    EndObject,
    ObjectKind(RTenum),
    DeleteObjects(RTuint, usize),
    Instantiate(RTuint),
    MoveInstance(RTuint),
    InstanceMotion(RTuint),
    DeleteInstance(RTuint),
    DeleteAllInstances,
    Begin(RTenum),
    End,
    Vertex([f32; 3]),
    Vertex2([f32; 2]),
    Normal([f32; 3]),
    Color([f32; 3]),
    TexCoord([f32; 2]),
    ShadeModel(RTenum),
    TriangleMesh { positions: Vec<[f32; 3]>, indices: Vec<[u32; 3]>, normals: bool },
    MatrixMode(RTenum),
    LoadIdentity,
    PushMatrix,
    PopMatrix,
    Translate([f32; 3]),
    Rotate(f32, [f32; 3]),
    Scale([f32; 3]),
    Perspective(f32),
    /// `rtOrtho` (true) or `rtFrustum` (false) with left, right, bottom, top, znear, zfar.
    Window(bool, [f32; 6]),
    ClearColor([f32; 4]),
    TexParameter(RTenum, RTint),
    Get(RTenum),
    LookAt([f32; 3]),
    Lens(f32, f32),
    Shutter(f32, f32),
    RenderMode(RTenum),
    RenderParameter(RTenum, RTint),
    GetRenderParameter(RTenum),
    GenShaderClasses(usize),
    NewShaderClass(RTuint, String),
    BindShaderClass(RTuint),
    GenShaders(usize),
    NewShader(RTuint),
    BindShader(RTuint),
    DeleteShaders(RTuint, usize),
    ParameterHandle(String),
    Parameter(RTint, Vec<f32>),
    GenTextures(usize),
    BindTexture(RTenum, RTuint),
    TexImage { size: [usize; 2], format: RTenum, pixels: Vec<f32> },
    TexChecker([f32; 3], f32),
    DeleteTextures(RTuint, usize),
    ParameterTexture(RTint, RTuint),
    Swap,
    Pick(RTuint, RTuint),
    StartFrame,
    /// The `rtFrame*` calls name a frame by [`FrameRef`].
    WaitFrame(FrameRef),
    CancelFrame(FrameRef),
    FrameProgress(FrameRef),
    ReleaseFrame(FrameRef),
    FrameIsReady(FrameRef),
    /// `rtFrameBuffer` of `side × side` pixels of the test's memory (NULL if `null`).
    FrameBuffer { side: usize, format: RTenum, null: bool },
    /// `rtChannelBuffer` of `side × side` values of the test's memory (NULL if `null`).
    ChannelBuffer { channel: RTenum, side: usize, null: bool },
    /// `rtWritePNG` into the test's directory, or into one that does not exist.
    WritePng(bool),
    /// `rtSwapBuffersKept` of a frame of this size.
    SwapBuffersKept(usize, usize),
    /// `rtReadPixels` of one pixel of the last frame: its corner, or (`inside` false) beyond any
    /// frame; into NULL if `null`.
    ReadPixels { format: RTenum, inside: bool, null: bool },
    /// `rtRecordError` of `code` as the call "rtTestCall", or with NULL strings.
    RecordError { code: RTenum, null: bool },
    ResetContext,
    FinishMpi,
    /// `rtInitMPI`, only where the library is built without MPI (it refuses then): with MPI it
    /// would join the test process to a job, which a process can do once.
    InitMpi,
    Vertex3d([f64; 3]),
    /// The `v` forms, NULL for `None`.
    Vertex3fv(Option<[f32; 3]>),
    Normal3f([f32; 3]),
    Color4f([f32; 4]),
    Color3fv(Option<[f32; 3]>),
    TexCoord2fv(Option<[f32; 2]>),
    /// `rtMultMatrixf` (true) or `rtLoadMatrixf`.
    Matrixf(bool, [f32; 16]),
    /// `rtMultMatrixd` (true) or `rtLoadMatrixd`.
    Matrixd(bool, [f64; 16]),
    Translated([f64; 3]),
    Rotated(f64, [f64; 3]),
    Scaled([f64; 3]),
    ParameterScope(RTenum),
    Parameter3fv(RTint, Option<[f32; 3]>),
    /// `rtTexImageFile` of a PNG the test wrote (true) or of a file that does not exist.
    TexImageFile(bool),
    TexNoise([f32; 3], f32),
    /// `rtGetDoublev` (true) or `rtGetIntegerv`.
    GetWide(bool, RTenum),
    /// `rtGetShaderClass{Name, Doc, Kind}` and `rtGetShaderParameterCount` (0 to 3) of a class.
    ClassQuery(u8, RTsizei),
    /// `rtGetShaderParameter{Name, Doc, Type, Default, Range}` (0 to 4) of a class's parameter;
    /// `Default` and `Range` write through NULL if the flag says so.
    ParameterQuery(u8, RTsizei, RTsizei, bool),
    RtutInit,
    RtutInitWindowSize(RTint, RTint),
    /// `rtutCreateWindow` with a title, or NULL.
    RtutCreateWindow(bool),
    /// `rtutDisplayFunc` with the test's display callback (true) or NULL; likewise below.
    RtutDisplayFunc(bool),
    RtutReshapeFunc(bool),
    RtutKeyboardFunc(bool),
    RtutMouseFunc(bool),
    RtutIdleFunc(bool),
    RtutPostRedisplay,
    RtutSwapBuffers,
    RtutLeaveMainLoop,
    /// `rtutMainLoop`; the display callback makes these calls the first time it is called.
    RtutMainLoop(Vec<Call>),
}

/// A frame handle as a sequence names it: the `n`th handle `rtRenderFrameAsync` returned in it,
/// 0, or one never handed out.
#[derive(Clone, Copy, Debug)]
enum FrameRef {
    Issued(usize),
    Zero,
    Never,
}

/// Mostly ordinary numbers, sometimes NaN or infinite.
fn number() -> impl Strategy<Value = f32> {
    prop_oneof![20 => -4.0f32..4.0, 1 => Just(f32::NAN), 1 => Just(f32::INFINITY), 1 => Just(1e30f32)]
}

fn vec3() -> impl Strategy<Value = [f32; 3]> {
    [number(), number(), number()]
}

/// Small ids (0 names nothing), so that calls often hit what exists.
fn id() -> impl Strategy<Value = RTuint> {
    0u32..6
}

/// A valid value of the enum most of the time, else something else.
fn one_of(valid: &'static [RTenum]) -> impl Strategy<Value = RTenum> {
    prop_oneof![4 => proptest::sample::select(valid), 1 => 0u32..0x9100]
}

const PRIMITIVES: &[RTenum] = &[RT_TRIANGLES, RT_TRIANGLE_STRIP, RT_TRIANGLE_FAN, RT_QUADS, RT_QUAD_STRIP, RT_POLYGON];
const KINDS: &[RTenum] = &[RT_STATIC, RT_ANIMATED, RT_UNSTRUCTURED];
const MODES: &[RTenum] = &[RT_MODELVIEW, RT_TEXTURE];
const SHADE: &[RTenum] = &[RT_FLAT, RT_SMOOTH];
const LIGHTS: &[&str] = &["PointLight", "SpotLight", "DirectionalLight", "AmbientLight", "AreaLight", "EnvironmentLight"];
const RENDER_MODES: &[RTenum] = &[RT_AUTO, RT_EYELIGHT, RT_WHITTED, RT_DISTRIBUTION, RT_PATH];
const RENDER_PARAMETERS: &[RTenum] = &[RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_LIGHT_SAMPLES, RT_RUSSIAN_ROULETTE, RT_SEED];
const PARAMS: &[&str] = &["diffuse", "color", "position", "intensity", "cone", "specularColor", "diffuse_texture", "map"];
const PIXEL_LAYOUTS: &[RTenum] = &[RT_RGBA8, RT_RGBA32F];
const ERRORS: &[RTenum] = &[
    RT_INVALID_ENUM,
    RT_INVALID_VALUE,
    RT_INVALID_OPERATION,
    RT_STACK_OVERFLOW,
    RT_STACK_UNDERFLOW,
    RT_OUT_OF_MEMORY,
    RT_IO_ERROR,
    RT_INTERNAL_ERROR,
];
const CHANNELS: &[RTenum] = &[
    RT_DEPTH_CHANNEL,
    RT_Z_CHANNEL,
    RT_NORMAL_CHANNEL,
    RT_ALBEDO_CHANNEL,
    RT_INSTANCE_ID_CHANNEL,
    RT_OBJECT_ID_CHANNEL,
    RT_PRIMITIVE_ID_CHANNEL,
];
const SCOPES: &[RTenum] = &[RT_PER_SHADER, RT_PER_SCENE, RT_PER_OBJECT, RT_PER_TRIANGLE, RT_PER_VERTEX];
const PIXEL_FORMATS: &[RTenum] = &[RT_LUMINANCE, RT_RGB, RT_RGBA];
const TEXTURE_PARAMETERS: &[RTenum] = &[RT_TEXTURE_WRAP_S, RT_TEXTURE_WRAP_T, RT_TEXTURE_MAG_FILTER, RT_TEXTURE_MIN_FILTER];
const WRAPS: &[RTenum] = &[RT_REPEAT, RT_CLAMP_TO_EDGE, RT_MIRRORED_REPEAT];
const FILTERS: &[RTenum] = &[RT_NEAREST, RT_LINEAR];
const MIN_FILTERS: &[RTenum] =
    &[RT_NEAREST, RT_LINEAR, RT_NEAREST_MIPMAP_NEAREST, RT_LINEAR_MIPMAP_NEAREST, RT_NEAREST_MIPMAP_LINEAR, RT_LINEAR_MIPMAP_LINEAR];
const QUERIES: &[RTenum] = &[
    RT_MODELVIEW_MATRIX,
    RT_TEXTURE_MATRIX,
    RT_MODELVIEW_STACK_DEPTH,
    RT_TEXTURE_STACK_DEPTH,
    RT_MATRIX_MODE,
    RT_CURRENT_COLOR,
    RT_CURRENT_NORMAL,
    RT_CURRENT_TEXTURE_COORDS,
    RT_SHADE_MODEL,
    RT_COLOR_CLEAR_VALUE,
    RT_VIEWPORT,
    RT_TEXTURE_BINDING_2D,
    RT_SHADER_BINDING,
];

/// Shutter times: mostly in [0, 1], sometimes not, or not numbers.
fn time() -> impl Strategy<Value = f32> {
    prop_oneof![4 => 0.0f32..=1.0, 1 => number()]
}

/// Render parameter values: mostly small (so that frames stay cheap), sometimes out of range.
fn render_value() -> impl Strategy<Value = RTint> {
    prop_oneof![8 => -1..6, 1 => Just(RT_MAX_RAY_DEPTH + 1), 1 => Just(RT_MAX_SAMPLES + 1), 1 => Just(RTint::MAX)]
}

fn class_name() -> impl Strategy<Value = String> {
    let mut names: Vec<String> = SHADER_CLASSES.iter().map(|c| c.name.to_string()).collect();
    names.extend(LIGHTS.iter().chain(&["NoSuchClass", ""]).map(|n| n.to_string()));
    proptest::sample::select(names)
}

/// Doubles: mostly ordinary, sometimes beyond single precision or not numbers.
fn double() -> impl Strategy<Value = f64> {
    prop_oneof![20 => -4.0f64..4.0, 1 => Just(f64::NAN), 1 => Just(1e300), 1 => Just(1e30)]
}

/// An array, or NULL (rarely).
fn maybe<T: std::fmt::Debug + Clone>(s: impl Strategy<Value = T>) -> impl Strategy<Value = Option<T>> {
    prop_oneof![8 => s.prop_map(Some), 1 => Just(None)]
}

/// Mostly the handles this sequence was given, sometimes 0 or one never handed out.
fn frame_ref() -> impl Strategy<Value = FrameRef> {
    prop_oneof![8 => (0usize..3).prop_map(FrameRef::Issued), 1 => Just(FrameRef::Zero), 1 => Just(FrameRef::Never)]
}

/// Sides of lent memory: mostly the frame's usual ones, sometimes none or another.
fn side() -> impl Strategy<Value = usize> {
    prop_oneof![6 => Just(SIDE), 2 => 0usize..=MAX_SIDE]
}

/// Window sides: small mostly, sometimes refused.
fn window_side() -> impl Strategy<Value = RTint> {
    prop_oneof![6 => 1..=(MAX_SIDE as RTint), 1 => -1..=0, 1 => Just(RT_MAX_FRAMEBUFFER_SIZE as RTint + 1)]
}

/// The calls of a display callback: any but another loop (which it tries once in a while),
/// with more of what callbacks do.
fn callback_calls() -> impl Strategy<Value = Vec<Call>> {
    let one = prop_oneof![
        8 => plain_call(),
        3 => Just(Call::RtutSwapBuffers),
        1 => Just(Call::RtutPostRedisplay),
        1 => Just(Call::RtutLeaveMainLoop),
        1 => Just(Call::RtutMainLoop(Vec::new())),
    ];
    proptest::collection::vec(one, 0..8)
}

fn call() -> impl Strategy<Value = Call> {
    prop_oneof![
        12 => plain_call(),
        2 => callback_calls().prop_map(Call::RtutMainLoop),
        1 => (window_side(), window_side()).prop_map(|(w, h)| Call::RtutInitWindowSize(w, h)),
    ]
}

/// Every call but `rtutMainLoop`.
fn plain_call() -> impl Strategy<Value = Call> {
    prop_oneof![3 => legacy_call(), 2 => new_call()]
}

/// The calls added to rt.h after the first sixty: buffers, the `d` and `v` forms, introspection,
/// MPI, `rtResetContext` and RTUT.
fn new_call() -> impl Strategy<Value = Call> {
    prop_oneof![
        4 => (side(), one_of(PIXEL_LAYOUTS), proptest::bool::weighted(0.1)).prop_map(|(side, format, null)| Call::FrameBuffer { side, format, null }),
        2 => (one_of(CHANNELS), side(), proptest::bool::weighted(0.1)).prop_map(|(channel, side, null)| Call::ChannelBuffer { channel, side, null }),
        1 => proptest::bool::weighted(0.8).prop_map(Call::WritePng),
        2 => (side(), side()).prop_map(|(w, h)| Call::SwapBuffersKept(w, h)),
        1 => (one_of(PIXEL_LAYOUTS), proptest::bool::weighted(0.9), proptest::bool::weighted(0.1))
            .prop_map(|(format, inside, null)| Call::ReadPixels { format, inside, null }),
        1 => (one_of(ERRORS), proptest::bool::weighted(0.1)).prop_map(|(code, null)| Call::RecordError { code, null }),
        1 => Just(Call::ResetContext),
        1 => Just(Call::FinishMpi),
        // rtInitMPI only where it refuses (see `Call::InitMpi`).
        1 => Just(if cfg!(feature = "mpi") { Call::FinishMpi } else { Call::InitMpi }),
        2 => [double(), double(), double()].prop_map(Call::Vertex3d),
        2 => maybe(vec3()).prop_map(Call::Vertex3fv),
        1 => vec3().prop_map(Call::Normal3f),
        1 => [number(), number(), number(), number()].prop_map(Call::Color4f),
        1 => maybe(vec3()).prop_map(Call::Color3fv),
        1 => maybe([number(), number()]).prop_map(Call::TexCoord2fv),
        1 => (any::<bool>(), proptest::array::uniform16(prop_oneof![8 => -2.0f32..2.0, 1 => number()])).prop_map(|(m, v)| Call::Matrixf(m, v)),
        1 => (any::<bool>(), proptest::array::uniform16(prop_oneof![8 => -2.0f64..2.0, 1 => double()])).prop_map(|(m, v)| Call::Matrixd(m, v)),
        1 => [double(), double(), double()].prop_map(Call::Translated),
        1 => (double(), [double(), double(), double()]).prop_map(|(a, axis)| Call::Rotated(a, axis)),
        1 => [double(), double(), double()].prop_map(Call::Scaled),
        1 => one_of(SCOPES).prop_map(Call::ParameterScope),
        1 => (-1i32..8, maybe([0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0])).prop_map(|(h, v)| Call::Parameter3fv(h, v)),
        1 => any::<bool>().prop_map(Call::TexImageFile),
        1 => (vec3(), number()).prop_map(|(a, scale)| Call::TexNoise(a, scale)),
        1 => (any::<bool>(), one_of(QUERIES)).prop_map(|(d, p)| Call::GetWide(d, p)),
        1 => (0u8..5, 0usize..40).prop_map(|(q, i)| Call::ClassQuery(q, i)),
        1 => (0u8..5, 0usize..40, 0usize..12, proptest::bool::weighted(0.1)).prop_map(|(q, c, p, n)| Call::ParameterQuery(q, c, p, n)),
        1 => Just(Call::RtutInit),
        1 => (window_side(), window_side()).prop_map(|(w, h)| Call::RtutInitWindowSize(w, h)),
        1 => proptest::bool::weighted(0.9).prop_map(Call::RtutCreateWindow),
        2 => proptest::bool::weighted(0.9).prop_map(Call::RtutDisplayFunc),
        1 => any::<bool>().prop_map(Call::RtutReshapeFunc),
        1 => any::<bool>().prop_map(Call::RtutKeyboardFunc),
        1 => any::<bool>().prop_map(Call::RtutMouseFunc),
        1 => any::<bool>().prop_map(Call::RtutIdleFunc),
        1 => Just(Call::RtutPostRedisplay),
        1 => Just(Call::RtutSwapBuffers),
        1 => Just(Call::RtutLeaveMainLoop),
    ]
}

/// The first sixty calls of rt.h.
fn legacy_call() -> impl Strategy<Value = Call> {
    let mesh = (proptest::collection::vec(vec3(), 0..6), proptest::collection::vec([0u32..4, 0u32..4, 0u32..4], 0..4), any::<bool>())
        .prop_map(|(positions, indices, normals)| Call::TriangleMesh { positions, indices, normals });
    prop_oneof![
        1 => (0usize..3).prop_map(Call::GenObjects),
        1 => Just(Call::GenObjects(RT_MAX_IDS + 1)),
        4 => (id(), one_of(&[RT_COMPILE])).prop_map(|(i, m)| Call::NewObject(i, m)),
        3 => Just(Call::EndObject),
        1 => one_of(KINDS).prop_map(Call::ObjectKind),
        1 => (id(), 0usize..3).prop_map(|(i, n)| Call::DeleteObjects(i, n)),
        3 => id().prop_map(Call::Instantiate),
        1 => id().prop_map(Call::MoveInstance),
        1 => id().prop_map(Call::InstanceMotion),
        1 => id().prop_map(Call::DeleteInstance),
        1 => Just(Call::DeleteAllInstances),
        4 => one_of(PRIMITIVES).prop_map(Call::Begin),
        4 => Just(Call::End),
        10 => vec3().prop_map(Call::Vertex),
        2 => [number(), number()].prop_map(Call::Vertex2),
        1 => vec3().prop_map(Call::Normal),
        1 => vec3().prop_map(Call::Color),
        1 => [number(), number()].prop_map(Call::TexCoord),
        1 => one_of(SHADE).prop_map(Call::ShadeModel),
        2 => mesh,
        1 => one_of(MODES).prop_map(Call::MatrixMode),
        1 => Just(Call::LoadIdentity),
        1 => Just(Call::PushMatrix),
        1 => Just(Call::PopMatrix),
        1 => vec3().prop_map(Call::Translate),
        1 => (number(), vec3()).prop_map(|(a, axis)| Call::Rotate(a, axis)),
        1 => vec3().prop_map(Call::Scale),
        1 => prop_oneof![1.0f32..179.0, Just(0.0), Just(180.0), Just(f32::NAN)].prop_map(Call::Perspective),
        1 => vec3().prop_map(Call::LookAt),
        1 => (any::<bool>(), [number(), number(), number(), number(), number(), number()]).prop_map(|(o, w)| Call::Window(o, w)),
        1 => [number(), number(), number(), number()].prop_map(Call::ClearColor),
        1 => (one_of(TEXTURE_PARAMETERS), prop_oneof![proptest::sample::select(WRAPS), proptest::sample::select(FILTERS), (-1i32..0x9000).prop_map(|v| v as RTenum)])
            .prop_map(|(p, v)| Call::TexParameter(p, v as RTint)),
        1 => one_of(QUERIES).prop_map(Call::Get),
        1 => (number(), number()).prop_map(|(a, f)| Call::Lens(a, f)),
        1 => (time(), time()).prop_map(|(o, c)| Call::Shutter(o, c)),
        1 => one_of(RENDER_MODES).prop_map(Call::RenderMode),
        2 => (prop_oneof![6 => proptest::sample::select(RENDER_PARAMETERS), 1 => Just(RT_RENDER_MODE), 1 => 0u32..0x9100], render_value())
            .prop_map(|(p, v)| Call::RenderParameter(p, v)),
        1 => one_of(&[RT_RENDER_MODE, RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_SEED]).prop_map(Call::GetRenderParameter),
        1 => (0usize..3).prop_map(Call::GenShaderClasses),
        1 => (id(), class_name()).prop_map(|(i, n)| Call::NewShaderClass(i, n)),
        1 => id().prop_map(Call::BindShaderClass),
        1 => (0usize..3).prop_map(Call::GenShaders),
        3 => id().prop_map(Call::NewShader),
        3 => id().prop_map(Call::BindShader),
        1 => (id(), 0usize..3).prop_map(|(i, n)| Call::DeleteShaders(i, n)),
        1 => proptest::sample::select(PARAMS).prop_map(|n| Call::ParameterHandle(n.to_string())),
        3 => (-1i32..8, proptest::collection::vec(prop_oneof![6 => 0.0f32..1.0, 1 => number()], 1..5))
            .prop_map(|(h, v)| Call::Parameter(h, v)),
        1 => (0usize..3).prop_map(Call::GenTextures),
        2 => (one_of(&[RT_TEXTURE_2D]), id()).prop_map(|(t, i)| Call::BindTexture(t, i)),
        1 => ([0usize..3, 0usize..3], one_of(PIXEL_FORMATS), proptest::collection::vec(prop_oneof![6 => 0.0f32..4.0, 1 => number()], 0..40))
            .prop_map(|(size, format, pixels)| Call::TexImage { size, format, pixels }),
        1 => (vec3(), number()).prop_map(|(a, scale)| Call::TexChecker(a, scale)),
        1 => (id(), 0usize..3).prop_map(|(i, n)| Call::DeleteTextures(i, n)),
        2 => (-1i32..10, id()).prop_map(|(h, t)| Call::ParameterTexture(h, t)),
        3 => Just(Call::Swap),
        1 => (0u32..10, 0u32..10).prop_map(|(x, y)| Call::Pick(x, y)),
        3 => Just(Call::StartFrame),
        2 => frame_ref().prop_map(Call::WaitFrame),
        1 => frame_ref().prop_map(Call::CancelFrame),
        1 => frame_ref().prop_map(Call::FrameProgress),
        1 => frame_ref().prop_map(Call::ReleaseFrame),
        1 => frame_ref().prop_map(Call::FrameIsReady),
    ]
}

/// Vertices of a primitive: mostly ordinary, rarely not finite.
fn vertices() -> impl Strategy<Value = Vec<Call>> {
    proptest::collection::vec(vec3().prop_map(Call::Vertex), 0..7)
}

/// A primitive: `rtBegin`, vertices, `rtEnd`.
fn primitive() -> impl Strategy<Value = Vec<Call>> {
    (one_of(PRIMITIVES), vertices()).prop_map(|(mode, vertices)| {
        std::iter::once(Call::Begin(mode)).chain(vertices).chain([Call::End]).collect()
    })
}

/// A whole object: `rtNewObject`, a shader binding, primitives, `rtEndObject`, and an instance.
fn definition() -> impl Strategy<Value = Vec<Call>> {
    (id(), id(), proptest::collection::vec(primitive(), 1..3)).prop_map(|(object, shader, primitives)| {
        let mut calls = vec![Call::NewObject(object, RT_COMPILE), Call::BindShader(shader)];
        calls.extend(primitives.into_iter().flatten());
        calls.extend([Call::EndObject, Call::Instantiate(object)]);
        calls
    })
}

/// A step of a random session: mostly one call, sometimes a primitive or an object.
fn step_calls() -> impl Strategy<Value = Vec<Call>> {
    prop_oneof![6 => call().prop_map(|c| vec![c]), 2 => primitive(), 1 => definition()]
}

/// The side of the frame buffer the test renders into, and of RTUT's window, most of the time.
const SIDE: usize = 8;
/// The largest side of memory the test lends (frame buffer, channels, window).
const MAX_SIDE: usize = 12;
/// RTUT's window size at the start of a sequence.
const WINDOW: (usize, usize) = (SIDE + 2, SIDE - 2);

/// What the model expects a call to record.
#[derive(Debug)]
enum Expect {
    /// Exactly this code.
    Code(RTenum),
    /// One of these codes (the model does not track what decides between them).
    OneOf(&'static [RTenum]),
}

const OK_OR_VALUE: &[RTenum] = &[RT_NO_ERROR, RT_INVALID_VALUE];
const OK_OR_OPERATION: &[RTenum] = &[RT_NO_ERROR, RT_INVALID_OPERATION];
const OK_VALUE_OR_OPERATION: &[RTenum] = &[RT_NO_ERROR, RT_INVALID_VALUE, RT_INVALID_OPERATION];
const ENUM_OR_OPERATION: &[RTenum] = &[RT_INVALID_ENUM, RT_INVALID_OPERATION];
const OPERATION_OR_VALUE: &[RTenum] = &[RT_INVALID_VALUE, RT_INVALID_OPERATION];
const OK_OR_IO: &[RTenum] = &[RT_NO_ERROR, RT_INVALID_OPERATION, RT_IO_ERROR];
const FILE_TEXTURE: &[RTenum] = &[RT_NO_ERROR, RT_INVALID_VALUE, RT_INVALID_OPERATION, RT_IO_ERROR];

/// What the model knows of RTUT, which `rtResetContext` does not reset.
#[derive(Debug, Default)]
struct RtutModel {
    initialised: bool,
    window: bool,
    /// The window's size as `rtutInitWindowSize` last set it.
    size: (usize, usize),
    /// The size of the pixels the running loop lends (the size when it started).
    frame: (usize, usize),
    display: bool,
    /// The test's display callback is making its calls.
    running: bool,
}

/// The state of the C ABI that decides most errors.
#[derive(Debug, Default)]
struct Model {
    defining: bool,
    in_primitive: bool,
    texture_mode: bool,
    depth: [usize; 2],
    objects: usize,
    classes: usize,
    /// The render mode and parameters as `rtGetRenderParameteri` should return them.
    rendering: Vec<(RTenum, RTint)>,
    /// The handles `rtRenderFrameAsync` returned in this sequence, in order.
    issued: Vec<RTuint>,
    /// The handles not yet released.
    frames: Vec<RTuint>,
    /// The frame started and not yet waited for nor released.
    in_flight: Option<RTuint>,
    /// The frame buffer's size, if there is one.
    frame: Option<(usize, usize)>,
    /// The channels lent, with their side.
    channels: Vec<(RTenum, usize)>,
    /// Whether a frame was rendered (`rtWritePNG` writes it); `None` where an asynchronous frame
    /// may have delivered one.
    rendered: Option<bool>,
    /// How many parameters each built-in class has.
    parameter_counts: Vec<usize>,
    rtut: RtutModel,
}

/// A handle never handed out (handles count up from 1 in the process).
const NEVER: RTuint = RTuint::MAX - 7;

impl Model {
    /// A context as `rtResetContext` leaves it (RTUT and the classes' table are not the
    /// context's).
    fn reset(&mut self) {
        let rtut = std::mem::take(&mut self.rtut);
        let parameter_counts = std::mem::take(&mut self.parameter_counts);
        let issued = std::mem::take(&mut self.issued);
        let rendering = vec![
            (RT_RENDER_MODE, RT_AUTO as RTint),
            (RT_SAMPLES_PER_PIXEL, 1),
            (RT_RAY_DEPTH, 6),
            (RT_LIGHT_SAMPLES, 1),
            (RT_RUSSIAN_ROULETTE, 1),
            (RT_SEED, 0),
        ];
        *self = Model { depth: [1, 1], rendering, rendered: Some(false), rtut, parameter_counts, issued, ..Model::default() };
    }

    /// The handle `frame` names in this sequence.
    fn handle(&self, frame: FrameRef) -> RTuint {
        match frame {
            FrameRef::Issued(n) => self.issued.get(n).copied().unwrap_or(NEVER),
            FrameRef::Zero => 0,
            FrameRef::Never => NEVER,
        }
    }

    /// The values render parameter `pname` takes; `None` if `rtRenderParameteri` refuses it.
    fn render_range(pname: RTenum) -> Option<std::ops::RangeInclusive<RTint>> {
        match pname {
            RT_SAMPLES_PER_PIXEL => Some(1..=RT_MAX_SAMPLES),
            RT_RAY_DEPTH => Some(1..=RT_MAX_RAY_DEPTH),
            RT_LIGHT_SAMPLES => Some(1..=RT_MAX_LIGHT_SAMPLES),
            RT_RUSSIAN_ROULETTE => Some(0..=1),
            RT_SEED => Some(0..=RTint::MAX),
            _ => None,
        }
    }

    /// What `rtGetRenderParameteri(pname)` should return.
    fn render_value(&self, pname: RTenum) -> RTint {
        self.rendering.iter().find(|(p, _)| *p == pname).map_or(0, |&(_, v)| v)
    }

    fn finite(v: &[f32]) -> bool {
        v.iter().all(|x| x.is_finite())
    }

    /// Doubles that single precision holds (the `d` calls refuse the others).
    fn single(v: &[f64]) -> Option<Vec<f32>> {
        let narrowed: Vec<f32> = v.iter().map(|&x| x as f32).collect();
        Model::finite(&narrowed).then_some(narrowed)
    }

    fn valid(e: RTenum, valid: &[RTenum]) -> bool {
        valid.contains(&e)
    }

    /// Whether a frame of `size` can render now (`rtSwapBuffers`, `rtRenderFrameAsync`,
    /// `rtutSwapBuffers`): no definition open, no frame in flight, every channel of its size.
    fn renders(&self, size: Option<(usize, usize)>) -> bool {
        let Some((w, h)) = size else { return false };
        !self.defining && self.in_flight.is_none() && self.channels.iter().all(|&(_, side)| (side, side) == (w, h))
    }

    /// What lending `side × side` memory (NULL if `null`) records, the layout checked first.
    fn lend(&self, layout_ok: bool, side: usize, null: bool) -> RTenum {
        if !layout_ok {
            RT_INVALID_ENUM
        } else if null != (side == 0) {
            RT_INVALID_VALUE
        } else if self.in_flight.is_some() {
            RT_INVALID_OPERATION
        } else {
            RT_NO_ERROR
        }
    }

    /// What a vertex call with (single-precision) coordinates `v` records.
    fn vertex(&self, v: &[f32]) -> Expect {
        if !self.in_primitive {
            Expect::Code(RT_INVALID_OPERATION)
        } else if !Model::finite(v) {
            Expect::Code(RT_INVALID_VALUE)
        } else {
            Expect::OneOf(OK_OR_VALUE)
        }
    }

    /// What `call` should record in the current state.
    fn expect(&self, call: &Call) -> Expect {
        use Call::*;
        use Expect::*;
        // Calls that record nothing, anywhere: RTUT's callback setters and flags, the class count,
        // and rtResetContext.
        if matches!(
            call,
            RtutDisplayFunc(_)
                | RtutReshapeFunc(_)
                | RtutKeyboardFunc(_)
                | RtutMouseFunc(_)
                | RtutIdleFunc(_)
                | RtutPostRedisplay
                | RtutLeaveMainLoop
                | ResetContext
                | ClassQuery(4, _)
        ) {
            return Code(RT_NO_ERROR);
        }
        // The calls allowed between rtBegin and rtEnd (rtEndObject ends the primitive too), and
        // RTUT's that make no rt.h call but rtRecordError, which is allowed there too.
        let vertex_call = matches!(
            call,
            Vertex(_)
                | Vertex2(_)
                | Normal(_)
                | Color(_)
                | TexCoord(_)
                | End
                | EndObject
                | Get(_)
                | GetWide(..)
                | Vertex3d(_)
                | Vertex3fv(_)
                | Normal3f(_)
                | Color4f(_)
                | Color3fv(_)
                | TexCoord2fv(_)
                | RecordError { .. }
                | RtutInit
                | RtutInitWindowSize(..)
                | RtutCreateWindow(_)
                | RtutMainLoop(_)
        );
        if self.in_primitive && !vertex_call {
            return Code(RT_INVALID_OPERATION);
        }
        let value = |ok: bool| Code(if ok { RT_NO_ERROR } else { RT_INVALID_VALUE });
        let enumerated = |e, valid| Code(if Model::valid(e, valid) { RT_NO_ERROR } else { RT_INVALID_ENUM });
        let operation = |ok: bool| Code(if ok { RT_NO_ERROR } else { RT_INVALID_OPERATION });
        let depth = self.depth[self.texture_mode as usize];
        let classes = self.parameter_counts.len();
        match call {
            GenObjects(n) => Code(if self.objects + n > RT_MAX_IDS { RT_OUT_OF_MEMORY } else { RT_NO_ERROR }),
            NewObject(id, mode) => Code(if self.defining {
                RT_INVALID_OPERATION
            } else if *mode != RT_COMPILE {
                RT_INVALID_ENUM
            } else if *id == 0 || *id as usize > self.objects {
                RT_INVALID_VALUE
            } else {
                RT_NO_ERROR
            }),
            EndObject if !self.defining => Code(RT_INVALID_OPERATION),
            EndObject => OneOf(OK_OR_OPERATION),
            ObjectKind(k) => enumerated(*k, KINDS),
            Instantiate(_) if self.defining => Code(RT_INVALID_OPERATION),
            Instantiate(_) | MoveInstance(_) | InstanceMotion(_) | DeleteInstance(_) => OneOf(OK_OR_VALUE),
            DeleteObjects(..) | DeleteAllInstances | LoadIdentity | GenShaderClasses(_) | GenShaders(_) | DeleteShaders(..) => {
                Code(RT_NO_ERROR)
            }
            GenTextures(_) | DeleteTextures(..) => Code(RT_NO_ERROR),
            BindTexture(target, _) if *target != RT_TEXTURE_2D => Code(RT_INVALID_ENUM),
            BindTexture(_, 0) => Code(RT_NO_ERROR),
            BindTexture(..) => OneOf(OK_OR_VALUE),
            TexImage { format, .. } if !Model::valid(*format, PIXEL_FORMATS) => Code(RT_INVALID_ENUM),
            TexImage { .. } | TexChecker(..) | TexNoise(..) | ParameterTexture(..) | Parameter3fv(..) => OneOf(OK_VALUE_OR_OPERATION),
            TexImageFile(_) => OneOf(FILE_TEXTURE),
            ParameterHandle(_) => Code(RT_NO_ERROR),
            ParameterScope(scope) => Code(if *scope == RT_PER_SHADER { RT_NO_ERROR } else { RT_INVALID_ENUM }),
            Begin(_) if !self.defining => Code(RT_INVALID_OPERATION),
            Begin(mode) if !Model::valid(*mode, PRIMITIVES) => Code(RT_INVALID_ENUM),
            Begin(_) => OneOf(OK_OR_OPERATION),
            End => operation(self.in_primitive),
            Vertex(v) | Vertex3fv(Some(v)) => self.vertex(v),
            Vertex2(v) => self.vertex(v),
            Vertex3d(v) => match Model::single(v) {
                Some(v) => self.vertex(&v),
                None => Code(RT_INVALID_VALUE),
            },
            Vertex3fv(None) | Color3fv(None) | TexCoord2fv(None) => Code(RT_INVALID_VALUE),
            Normal(v) | Normal3f(v) | Color(v) | Color3fv(Some(v)) => value(Model::finite(v)),
            Color4f(c) => value(Model::finite(c)),
            TexCoord(v) | TexCoord2fv(Some(v)) => value(Model::finite(v)),
            ShadeModel(m) => enumerated(*m, SHADE),
            TriangleMesh { .. } if !self.defining => Code(RT_INVALID_OPERATION),
            TriangleMesh { .. } => OneOf(OK_VALUE_OR_OPERATION),
            MatrixMode(m) => enumerated(*m, MODES),
            PushMatrix => Code(if depth == RT_MAX_STACK_DEPTH { RT_STACK_OVERFLOW } else { RT_NO_ERROR }),
            PopMatrix => Code(if depth == 1 { RT_STACK_UNDERFLOW } else { RT_NO_ERROR }),
            Translate(v) | Scale(v) if !Model::finite(v) => Code(RT_INVALID_VALUE),
            Rotate(a, v) if !Model::finite(v) || !a.is_finite() || *v == [0.0; 3] => Code(RT_INVALID_VALUE),
            Translate(_) | Scale(_) | Rotate(..) | LookAt(_) => OneOf(OK_OR_VALUE),
            Translated(v) | Scaled(v) => match Model::single(v) {
                Some(_) => OneOf(OK_OR_VALUE),
                None => Code(RT_INVALID_VALUE),
            },
            Rotated(a, v) => match Model::single(&[*a, v[0], v[1], v[2]]) {
                Some(v) if v[1..] != [0.0; 3] => OneOf(OK_OR_VALUE),
                _ => Code(RT_INVALID_VALUE),
            },
            Matrixf(_, m) if !Model::finite(m) => Code(RT_INVALID_VALUE),
            Matrixd(_, m) if Model::single(m).is_none() => Code(RT_INVALID_VALUE),
            Matrixf(..) | Matrixd(..) => OneOf(OK_OR_VALUE),
            Perspective(fov) => value(*fov > 0.0 && *fov < 180.0),
            Window(orthographic, w) => {
                let [left, right, bottom, top, near, far] = *w;
                let empty = left == right || bottom == top || near == far;
                let depth_ok = *orthographic || (near > 0.0 && far > near);
                let bounded = w.iter().all(|v| v.abs() <= RT_MAX_COORDINATE);
                if !Model::finite(w) || empty || !depth_ok || !bounded {
                    Code(RT_INVALID_VALUE)
                } else {
                    // A frustum too wide for its znear is refused too.
                    OneOf(OK_OR_VALUE)
                }
            }
            ClearColor(c) => value(Model::finite(c) && c[..3].iter().all(|&x| x >= 0.0)),
            TexParameter(p, v) => {
                let values = match *p {
                    RT_TEXTURE_WRAP_S | RT_TEXTURE_WRAP_T => WRAPS,
                    RT_TEXTURE_MAG_FILTER => FILTERS,
                    RT_TEXTURE_MIN_FILTER => MIN_FILTERS,
                    _ => &[],
                };
                // No bound texture is an error before the enums are looked at.
                OneOf(if values.contains(&(*v as RTenum)) { OK_OR_OPERATION } else { ENUM_OR_OPERATION })
            }
            Get(p) | GetWide(_, p) => enumerated(*p, QUERIES),
            Lens(a, f) => value(Model::finite(&[*a, *f]) && *a >= 0.0 && *f >= 0.0),
            Shutter(open, close) => value(0.0 <= *open && open <= close && *close <= 1.0),
            RenderMode(m) => enumerated(*m, RENDER_MODES),
            RenderParameter(p, v) => match Model::render_range(*p) {
                None => Code(RT_INVALID_ENUM),
                Some(range) => value(range.contains(v)),
            },
            GetRenderParameter(p) => {
                let known = *p == RT_RENDER_MODE || Model::render_range(*p).is_some();
                Code(if known { RT_NO_ERROR } else { RT_INVALID_ENUM })
            }
            NewShaderClass(id, name) => {
                let known = SHADER_CLASSES.iter().any(|c| c.name == name) || LIGHTS.contains(&name.as_str());
                value(*id != 0 && *id as usize <= self.classes && known)
            }
            BindShaderClass(0) | BindShader(0) => Code(RT_NO_ERROR),
            BindShaderClass(_) | BindShader(_) => OneOf(OK_OR_VALUE),
            NewShader(_) | Parameter(..) => OneOf(OK_VALUE_OR_OPERATION),
            Swap | StartFrame => operation(self.renders(self.frame)),
            WaitFrame(h) | CancelFrame(h) | FrameProgress(h) | ReleaseFrame(h) | FrameIsReady(h) => {
                value(self.frames.contains(&self.handle(*h)))
            }
            Pick(x, y) => match self.frame {
                None => Code(RT_INVALID_OPERATION),
                Some((w, h)) => value((*x as usize) < w && (*y as usize) < h),
            },
            FrameBuffer { side, format, null } => Code(self.lend(Model::valid(*format, PIXEL_LAYOUTS), *side, *null)),
            ChannelBuffer { channel, side, null } => Code(self.lend(Model::valid(*channel, CHANNELS), *side, *null)),
            WritePng(good) => match self.rendered {
                Some(false) => Code(RT_INVALID_OPERATION),
                Some(true) => Code(if *good { RT_NO_ERROR } else { RT_IO_ERROR }),
                None => OneOf(OK_OR_IO),
            },
            SwapBuffersKept(w, h) if ![w, h].iter().all(|&&side| (1..=RT_MAX_FRAMEBUFFER_SIZE).contains(&side)) => Code(RT_INVALID_VALUE),
            SwapBuffersKept(w, h) => operation(self.renders(Some((*w, *h)))),
            ReadPixels { format, .. } if !Model::valid(*format, PIXEL_LAYOUTS) => Code(RT_INVALID_ENUM),
            ReadPixels { null: true, .. } => Code(RT_INVALID_VALUE),
            ReadPixels { inside, .. } => match self.rendered {
                Some(false) => Code(RT_INVALID_OPERATION),
                Some(true) => value(*inside),
                None if *inside => OneOf(OK_OR_OPERATION),
                None => OneOf(OPERATION_OR_VALUE),
            },
            RecordError { code, .. } if !Model::valid(*code, ERRORS) => Code(RT_INVALID_ENUM),
            RecordError { null, code } => Code(if *null { RT_INVALID_VALUE } else { *code }),
            // Without rtInitMPI (which refuses without MPI) there is nothing to finish.
            InitMpi | FinishMpi => Code(RT_INVALID_OPERATION),
            ClassQuery(_, index) => value(*index < classes),
            ParameterQuery(query, class, param, null) => {
                let exists = self.parameter_counts.get(*class).is_some_and(|&n| *param < n);
                value(exists && !(*null && *query >= 3))
            }
            RtutInit => Code(RT_NO_ERROR),
            RtutInitWindowSize(w, h) => value([w, h].iter().all(|&&v| (1..=RT_MAX_FRAMEBUFFER_SIZE as RTint).contains(&v))),
            RtutCreateWindow(false) => Code(RT_INVALID_VALUE),
            RtutCreateWindow(true) => operation(self.rtut.initialised && !self.rtut.window),
            RtutSwapBuffers => operation(self.rtut.window && self.rtut.running && self.renders(Some(self.rtut.frame))),
            RtutMainLoop(_) => operation(self.rtut.window && self.rtut.display && !self.rtut.running),
            RtutDisplayFunc(_) | RtutReshapeFunc(_) | RtutKeyboardFunc(_) | RtutMouseFunc(_) | RtutIdleFunc(_) => Code(RT_NO_ERROR),
            RtutPostRedisplay | RtutLeaveMainLoop | ResetContext => Code(RT_NO_ERROR),
        }
    }

    fn set_render_value(&mut self, pname: RTenum, value: RTint) {
        self.rendering.iter_mut().filter(|(p, _)| *p == pname).for_each(|(_, v)| *v = value);
    }

    /// Follows the state change of `call`, which recorded `code` and returned `returned`.
    fn update(&mut self, call: &Call, code: RTenum, returned: Option<i64>) {
        use Call::*;
        let ok = code == RT_NO_ERROR;
        match call {
            EndObject if self.defining => (self.defining, self.in_primitive) = (false, false),
            ResetContext => self.reset(),
            _ if !ok => {}
            GenObjects(n) => self.objects += n,
            GenShaderClasses(n) => self.classes += n,
            NewObject(..) => self.defining = true,
            Begin(_) => self.in_primitive = true,
            End => self.in_primitive = false,
            MatrixMode(m) => self.texture_mode = *m == RT_TEXTURE,
            PushMatrix => self.depth[self.texture_mode as usize] += 1,
            PopMatrix => self.depth[self.texture_mode as usize] -= 1,
            RenderMode(m) => self.set_render_value(RT_RENDER_MODE, *m as RTint),
            RenderParameter(p, v) => self.set_render_value(*p, *v),
            Swap => self.rendered = Some(true),
            StartFrame => {
                let handle = returned.expect("a handle") as RTuint;
                self.issued.push(handle);
                self.frames.push(handle);
                self.in_flight = Some(handle);
            }
            WaitFrame(h) => {
                let h = self.handle(*h);
                if self.in_flight == Some(h) {
                    self.in_flight = None;
                }
                if returned == Some(i64::from(RT_NO_ERROR)) {
                    self.rendered = Some(true);
                }
            }
            FrameIsReady(h) if returned == Some(1) && self.in_flight == Some(self.handle(*h)) => {
                self.in_flight = None;
                // Completed (delivered) or cancelled: the model does not know which.
                self.rendered = self.rendered.filter(|&r| r);
            }
            ReleaseFrame(h) => {
                let h = self.handle(*h);
                self.frames.retain(|&f| f != h);
                self.in_flight = self.in_flight.filter(|&f| f != h);
            }
            FrameBuffer { side, null, .. } => self.frame = (!null).then_some((*side, *side)),
            ChannelBuffer { channel, side, null } => {
                self.channels.retain(|(c, _)| c != channel);
                if !null {
                    self.channels.push((*channel, *side));
                }
            }
            RtutInit => self.rtut.initialised = true,
            RtutInitWindowSize(w, h) => self.rtut.size = (*w as usize, *h as usize),
            RtutCreateWindow(_) => self.rtut.window = true,
            RtutDisplayFunc(set) => self.rtut.display = *set,
            RtutSwapBuffers => {
                self.frame = Some(self.rtut.frame);
                self.rendered = Some(true);
            }
            SwapBuffersKept(w, h) => {
                self.frame = Some((*w, *h));
                self.rendered = Some(true);
            }
            _ => {}
        }
    }
}

/// Memory the test lends: a frame buffer and one buffer per channel, of the largest size.
struct Memory {
    frame: Vec<u8>,
    channels: Vec<Vec<f32>>,
    /// Where frames are written (`rtWritePNG`, RTUT headless) and the PNG `rtTexImageFile` reads.
    dir: PathBuf,
}

impl Memory {
    fn new() -> Memory {
        let dir = std::env::temp_dir().join(format!("raystage-random-calls-{}", std::process::id()));
        Memory { frame: vec![0; MAX_SIDE * MAX_SIDE * 16], channels: vec![vec![0.0; MAX_SIDE * MAX_SIDE * 3]; CHANNELS.len()], dir }
    }
}

/// One sequence's state, on its thread: the model, the calls the display callback makes, the
/// first failure found inside a callback (which cannot return it), and the lent memory.
struct Harness {
    model: Model,
    body: Option<Vec<Call>>,
    failure: Option<String>,
}

thread_local! {
    static HARNESS: RefCell<Harness> = RefCell::new(Harness { model: Model::default(), body: None, failure: None });
    static MEMORY: RefCell<Memory> = RefCell::new(Memory::new());
}

fn with_model<R>(f: impl FnOnce(&mut Model) -> R) -> R {
    HARNESS.with(|h| f(&mut h.borrow_mut().model))
}

/// RTUT's display callback: makes the loop's calls the first time, and leaves afterwards so that
/// every loop ends.
unsafe extern "C" fn display() {
    let Some(calls) = HARNESS.with(|h| h.borrow_mut().body.take()) else {
        rtutLeaveMainLoop();
        return;
    };
    with_model(|m| {
        m.rtut.running = true;
        m.rtut.frame = m.rtut.size;
    });
    for call in &calls {
        if let Err(failure) = step(call) {
            HARNESS.with(|h| h.borrow_mut().failure.get_or_insert(failure).clone());
            rtutLeaveMainLoop();
            break;
        }
    }
    with_model(|m| m.rtut.running = false);
}

unsafe extern "C" fn reshape(_: std::ffi::c_int, _: std::ffi::c_int) {}
unsafe extern "C" fn keyboard(_: std::ffi::c_uchar, _: std::ffi::c_int, _: std::ffi::c_int) {}
unsafe extern "C" fn mouse(_: std::ffi::c_int, _: std::ffi::c_int, _: std::ffi::c_int, _: std::ffi::c_int) {}
unsafe extern "C" fn idle() {
    rtutLeaveMainLoop();
}

/// The C functions `call` calls.
fn c_name(call: &Call) -> &'static str {
    use Call::*;
    match call {
        GenObjects(_) => "rtGenObjects",
        NewObject(..) => "rtNewObject",
        EndObject => "rtEndObject",
        ObjectKind(_) => "rtObjectKind",
        DeleteObjects(..) => "rtDeleteObjects",
        Instantiate(_) => "rtInstantiateObject",
        MoveInstance(_) => "rtMoveInstance",
        InstanceMotion(_) => "rtInstanceMotion",
        DeleteInstance(_) => "rtDeleteInstance",
        DeleteAllInstances => "rtDeleteAllInstances",
        Begin(_) => "rtBegin",
        End => "rtEnd",
        Vertex(_) => "rtVertex3f",
        Vertex2(_) => "rtVertex2f",
        Normal(_) => "rtNormal3fv",
        Color(_) => "rtColor3f",
        TexCoord(_) => "rtTexCoord2f",
        ShadeModel(_) => "rtShadeModel",
        TriangleMesh { .. } => "rtTriangleMesh",
        MatrixMode(_) => "rtMatrixMode",
        LoadIdentity => "rtLoadIdentity",
        PushMatrix => "rtPushMatrix",
        PopMatrix => "rtPopMatrix",
        Translate(_) => "rtTranslatef",
        Rotate(..) => "rtRotatef",
        Scale(_) => "rtScalef",
        Perspective(_) => "rtPerspective",
        Window(true, _) => "rtOrtho",
        Window(false, _) => "rtFrustum",
        ClearColor(_) => "rtClearColor",
        TexParameter(..) => "rtTexParameteri",
        Get(_) => "rtGetFloatv",
        LookAt(_) => "rtLookAt",
        Lens(..) => "rtLens",
        Shutter(..) => "rtShutter",
        RenderMode(_) => "rtRenderMode",
        RenderParameter(..) => "rtRenderParameteri",
        GetRenderParameter(_) => "rtGetRenderParameteri",
        GenShaderClasses(_) => "rtGenShaderClasses",
        NewShaderClass(..) => "rtNewShaderClass",
        BindShaderClass(_) => "rtBindShaderClass",
        GenShaders(_) => "rtGenShaders",
        NewShader(_) => "rtNewShader",
        BindShader(_) => "rtBindShader",
        DeleteShaders(..) => "rtDeleteShaders",
        ParameterHandle(_) => "rtParameterHandle",
        Parameter(_, v) => ["rtParameter1f", "rtParameter2f", "rtParameter3f", "rtParameter4f"][v.len() - 1],
        GenTextures(_) => "rtGenTextures",
        BindTexture(..) => "rtBindTexture",
        TexImage { .. } => "rtTexImage2D",
        TexChecker(..) => "rtTexChecker",
        DeleteTextures(..) => "rtDeleteTextures",
        ParameterTexture(..) => "rtParameterTexture",
        Swap => "rtSwapBuffers",
        Pick(..) => "rtPick",
        StartFrame => "rtRenderFrameAsync",
        WaitFrame(_) => "rtFrameWait",
        CancelFrame(_) => "rtFrameCancel",
        FrameProgress(_) => "rtFrameProgress",
        ReleaseFrame(_) => "rtFrameRelease",
        FrameIsReady(_) => "rtFrameIsReady",
        FrameBuffer { .. } => "rtFrameBuffer",
        ChannelBuffer { .. } => "rtChannelBuffer",
        WritePng(_) => "rtWritePNG",
        SwapBuffersKept(..) => "rtSwapBuffersKept",
        ReadPixels { .. } => "rtReadPixels",
        RecordError { .. } => "rtRecordError",
        ResetContext => "rtResetContext",
        FinishMpi => "rtFinishMPI",
        InitMpi => "rtInitMPI",
        Vertex3d(_) => "rtVertex3d",
        Vertex3fv(_) => "rtVertex3fv",
        Normal3f(_) => "rtNormal3f",
        Color4f(_) => "rtColor4f",
        Color3fv(_) => "rtColor3fv",
        TexCoord2fv(_) => "rtTexCoord2fv",
        Matrixf(true, _) => "rtMultMatrixf",
        Matrixf(false, _) => "rtLoadMatrixf",
        Matrixd(true, _) => "rtMultMatrixd",
        Matrixd(false, _) => "rtLoadMatrixd",
        Translated(_) => "rtTranslated",
        Rotated(..) => "rtRotated",
        Scaled(_) => "rtScaled",
        ParameterScope(_) => "rtParameterScope",
        Parameter3fv(..) => "rtParameter3fv",
        TexImageFile(_) => "rtTexImageFile",
        TexNoise(..) => "rtTexNoise",
        GetWide(true, _) => "rtGetDoublev",
        GetWide(false, _) => "rtGetIntegerv",
        ClassQuery(q, _) => ["rtGetShaderClassName", "rtGetShaderClassDoc", "rtGetShaderClassKind", "rtGetShaderParameterCount", "rtGetShaderClassCount"]
            [*q as usize],
        ParameterQuery(q, ..) => [
            "rtGetShaderParameterName",
            "rtGetShaderParameterDoc",
            "rtGetShaderParameterType",
            "rtGetShaderParameterDefault",
            "rtGetShaderParameterRange",
        ][*q as usize],
        RtutInit => "rtutInit",
        RtutInitWindowSize(..) => "rtutInitWindowSize",
        RtutCreateWindow(_) => "rtutCreateWindow",
        RtutDisplayFunc(_) => "rtutDisplayFunc",
        RtutReshapeFunc(_) => "rtutReshapeFunc",
        RtutKeyboardFunc(_) => "rtutKeyboardFunc",
        RtutMouseFunc(_) => "rtutMouseFunc",
        RtutIdleFunc(_) => "rtutIdleFunc",
        RtutPostRedisplay => "rtutPostRedisplay",
        RtutSwapBuffers => "rtutSwapBuffers",
        RtutLeaveMainLoop => "rtutLeaveMainLoop",
        RtutMainLoop(_) => "rtutMainLoop",
    }
}

/// Makes the call through the C ABI; returns what a query or a handle call returned.
fn perform(call: &Call) -> Option<i64> {
    use Call::*;
    let null = std::ptr::null();
    let handle = |frame: &FrameRef| with_model(|m| m.handle(*frame));
    let dir = MEMORY.with(|m| m.borrow().dir.clone());
    let path = |name: &str| CString::new(dir.join(name).into_os_string().into_encoded_bytes()).unwrap();
    match call {
        GenObjects(n) => return Some(i64::from(rtGenObjects(*n))),
        NewObject(id, mode) => rtNewObject(*id, *mode),
        EndObject => rtEndObject(),
        ObjectKind(k) => rtObjectKind(*k),
        DeleteObjects(first, n) => rtDeleteObjects(*first, *n),
        Instantiate(id) => drop(rtInstantiateObject(*id)),
        MoveInstance(id) => rtMoveInstance(*id),
        InstanceMotion(id) => rtInstanceMotion(*id),
        DeleteInstance(id) => rtDeleteInstance(*id),
        DeleteAllInstances => rtDeleteAllInstances(),
        Begin(mode) => rtBegin(*mode),
        End => rtEnd(),
        Vertex([x, y, z]) => rtVertex3f(*x, *y, *z),
        Vertex2([x, y]) => rtVertex2f(*x, *y),
        Normal(v) => unsafe { rtNormal3fv(v.as_ptr()) },
        Color([r, g, b]) => rtColor3f(*r, *g, *b),
        TexCoord([s, t]) => rtTexCoord2f(*s, *t),
        ShadeModel(m) => rtShadeModel(*m),
        TriangleMesh { positions, indices, normals } => {
            let normal_ptr = if *normals { positions.as_ptr().cast() } else { null };
            unsafe { rtTriangleMesh(positions.as_ptr().cast(), normal_ptr, null, null, positions.len(), indices.as_ptr().cast(), indices.len()) }
        }
        MatrixMode(m) => rtMatrixMode(*m),
        LoadIdentity => rtLoadIdentity(),
        PushMatrix => rtPushMatrix(),
        PopMatrix => rtPopMatrix(),
        Translate([x, y, z]) => rtTranslatef(*x, *y, *z),
        Rotate(a, [x, y, z]) => rtRotatef(*a, *x, *y, *z),
        Scale([x, y, z]) => rtScalef(*x, *y, *z),
        Perspective(fov) => rtPerspective(*fov, 1.0, 0.1, 100.0),
        Window(orthographic, w) => {
            let [l, r, b, t, n, f] = w.map(f64::from);
            if *orthographic { rtOrtho(l, r, b, t, n, f) } else { rtFrustum(l, r, b, t, n, f) }
        }
        ClearColor([r, g, b, a]) => rtClearColor(*r, *g, *b, *a),
        TexParameter(p, v) => rtTexParameteri(RT_TEXTURE_2D, *p, *v),
        Get(p) => {
            let mut values = [0.0f32; 16];
            unsafe { rtGetFloatv(*p, values.as_mut_ptr()) };
        }
        LookAt([x, y, z]) => rtLookAt(*x, *y, *z, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0),
        Lens(aperture, focus) => rtLens(*aperture, *focus),
        Shutter(open, close) => rtShutter(*open, *close),
        RenderMode(m) => rtRenderMode(*m),
        RenderParameter(p, v) => rtRenderParameteri(*p, *v),
        GetRenderParameter(p) => return Some(i64::from(rtGetRenderParameteri(*p))),
        GenShaderClasses(n) => drop(rtGenShaderClasses(*n)),
        NewShaderClass(id, name) => {
            let name = CString::new(name.as_str()).unwrap();
            unsafe { rtNewShaderClass(*id, name.as_ptr(), std::ptr::null()) }
        }
        BindShaderClass(id) => rtBindShaderClass(*id),
        GenShaders(n) => drop(rtGenShaders(*n)),
        NewShader(id) => rtNewShader(*id),
        BindShader(id) => rtBindShader(*id),
        DeleteShaders(first, n) => rtDeleteShaders(*first, *n),
        ParameterHandle(name) => {
            let name = CString::new(name.as_str()).unwrap();
            unsafe { rtParameterHandle(name.as_ptr()) };
        }
        Parameter(h, v) => match v.as_slice() {
            [x] => rtParameter1f(*h, *x),
            [x, y] => rtParameter2f(*h, *x, *y),
            [x, y, z] => rtParameter3f(*h, *x, *y, *z),
            [x, y, z, w] => rtParameter4f(*h, *x, *y, *z, *w),
            _ => unreachable!("one to four values"),
        },
        GenTextures(n) => drop(rtGenTextures(*n)),
        BindTexture(target, id) => rtBindTexture(*target, *id),
        // Floats of the texture's size, if there are enough of them (else NULL, an error).
        TexImage { size: [w, h], format, pixels } => {
            let channels = match *format {
                RT_LUMINANCE => 1,
                RT_RGBA => 4,
                _ => 3,
            };
            let data: *const f32 = if pixels.len() >= w * h * channels { pixels.as_ptr() } else { null };
            unsafe { rtTexImage2D(RT_TEXTURE_2D, 0, RT_RGB32F as RTint, *w, *h, 0, *format, RT_FLOAT, data.cast()) }
        }
        TexChecker(a, scale) => unsafe { rtTexChecker(RT_TEXTURE_2D, a.as_ptr(), [0.1f32; 3].as_ptr(), *scale) },
        DeleteTextures(first, n) => rtDeleteTextures(*first, *n),
        ParameterTexture(h, t) => rtParameterTexture(*h, *t),
        Swap => rtSwapBuffers(),
        StartFrame => return Some(i64::from(rtRenderFrameAsync())),
        WaitFrame(h) => return Some(i64::from(rtFrameWait(handle(h)))),
        CancelFrame(h) => rtFrameCancel(handle(h)),
        FrameProgress(h) => {
            let progress = rtFrameProgress(handle(h));
            assert!((0.0..=1.0).contains(&progress), "progress {progress}");
        }
        ReleaseFrame(h) => rtFrameRelease(handle(h)),
        FrameIsReady(h) => return Some(i64::from(rtFrameIsReady(handle(h)))),
        Pick(x, y) => drop(unsafe { rtPick(*x, *y, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) }),
        FrameBuffer { side, format, null } => {
            let pixels = if *null { std::ptr::null_mut() } else { MEMORY.with(|m| m.borrow_mut().frame.as_mut_ptr()) };
            unsafe { rtFrameBuffer(pixels.cast(), *side, *side, *format) }
        }
        ChannelBuffer { channel, side, null } => {
            let index = CHANNELS.iter().position(|c| c == channel).unwrap_or(0);
            let data = if *null { std::ptr::null_mut() } else { MEMORY.with(|m| m.borrow_mut().channels[index].as_mut_ptr()) };
            unsafe { rtChannelBuffer(*channel, data.cast(), *side, *side) }
        }
        WritePng(true) => unsafe { rtWritePNG(path("frame.png").as_ptr()) },
        WritePng(false) => unsafe { rtWritePNG(c"/nonexistent-raystage-directory/frame.png".as_ptr()) },
        SwapBuffersKept(w, h) => return Some(i64::from(rtSwapBuffersKept(*w, *h))),
        ReadPixels { format, inside, null } => {
            let mut pixel = [0u8; 16];
            let out = if *null { std::ptr::null_mut() } else { pixel.as_mut_ptr() };
            let x = if *inside { 0 } else { RT_MAX_FRAMEBUFFER_SIZE };
            unsafe { rtReadPixels(x, 0, 1, 1, *format, out.cast()) }
        }
        RecordError { code, null: false } => unsafe { rtRecordError(*code, c"rtTestCall".as_ptr(), c"a test's error".as_ptr()) },
        RecordError { code, null: true } => unsafe { rtRecordError(*code, null.cast(), null.cast()) },
        ResetContext => rtResetContext(),
        FinishMpi => rtFinishMPI(),
        InitMpi if cfg!(feature = "mpi") => unreachable!("rtInitMPI is not generated where the library has MPI"),
        InitMpi => return Some(i64::from(rtInitMPI())),
        Vertex3d([x, y, z]) => rtVertex3d(*x, *y, *z),
        Vertex3fv(v) => unsafe { rtVertex3fv(v.as_ref().map_or(null, |v| v.as_ptr())) },
        Normal3f([x, y, z]) => rtNormal3f(*x, *y, *z),
        Color4f([r, g, b, a]) => rtColor4f(*r, *g, *b, *a),
        Color3fv(v) => unsafe { rtColor3fv(v.as_ref().map_or(null, |v| v.as_ptr())) },
        TexCoord2fv(v) => unsafe { rtTexCoord2fv(v.as_ref().map_or(null, |v| v.as_ptr())) },
        Matrixf(true, m) => unsafe { rtMultMatrixf(m.as_ptr()) },
        Matrixf(false, m) => unsafe { rtLoadMatrixf(m.as_ptr()) },
        Matrixd(true, m) => unsafe { rtMultMatrixd(m.as_ptr()) },
        Matrixd(false, m) => unsafe { rtLoadMatrixd(m.as_ptr()) },
        Translated([x, y, z]) => rtTranslated(*x, *y, *z),
        Rotated(a, [x, y, z]) => rtRotated(*a, *x, *y, *z),
        Scaled([x, y, z]) => rtScaled(*x, *y, *z),
        ParameterScope(scope) => rtParameterScope(*scope),
        Parameter3fv(h, v) => unsafe { rtParameter3fv(*h, v.as_ref().map_or(null, |v| v.as_ptr())) },
        TexImageFile(true) => unsafe { rtTexImageFile(RT_TEXTURE_2D, path("texture.png").as_ptr()) },
        TexImageFile(false) => unsafe { rtTexImageFile(RT_TEXTURE_2D, path("no-such-texture.png").as_ptr()) },
        TexNoise(a, scale) => unsafe { rtTexNoise(RT_TEXTURE_2D, a.as_ptr(), [0.1f32; 3].as_ptr(), *scale) },
        GetWide(true, p) => unsafe { rtGetDoublev(*p, [0.0f64; 16].as_mut_ptr()) },
        GetWide(false, p) => unsafe { rtGetIntegerv(*p, [0 as RTint; 16].as_mut_ptr()) },
        ClassQuery(q, index) => {
            let index = *index;
            return Some(match q {
                0 => i64::from(!rtGetShaderClassName(index).is_null()),
                1 => i64::from(!rtGetShaderClassDoc(index).is_null()),
                2 => i64::from(rtGetShaderClassKind(index)),
                3 => rtGetShaderParameterCount(index) as i64,
                _ => rtGetShaderClassCount() as i64,
            });
        }
        ParameterQuery(q, class, param, null) => {
            let (class, param) = (*class, *param);
            let mut out = [0.0f32; 8];
            let out = if *null { std::ptr::null_mut() } else { out.as_mut_ptr() };
            match q {
                0 => drop(rtGetShaderParameterName(class, param)),
                1 => drop(rtGetShaderParameterDoc(class, param)),
                2 => drop(rtGetShaderParameterType(class, param)),
                3 => unsafe { rtGetShaderParameterDefault(class, param, out) },
                _ => unsafe { rtGetShaderParameterRange(class, param, out) },
            }
        }
        RtutInit => rtutInit(std::ptr::null_mut(), std::ptr::null_mut()),
        RtutInitWindowSize(w, h) => rtutInitWindowSize(*w, *h),
        RtutCreateWindow(title) => return Some(i64::from(unsafe { rtutCreateWindow(if *title { c"random calls".as_ptr() } else { null.cast() }) })),
        RtutDisplayFunc(set) => rtutDisplayFunc(set.then_some(display as unsafe extern "C" fn())),
        RtutReshapeFunc(set) => rtutReshapeFunc(set.then_some(reshape as unsafe extern "C" fn(_, _))),
        RtutKeyboardFunc(set) => rtutKeyboardFunc(set.then_some(keyboard as unsafe extern "C" fn(_, _, _))),
        RtutMouseFunc(set) => rtutMouseFunc(set.then_some(mouse as unsafe extern "C" fn(_, _, _, _))),
        RtutIdleFunc(set) => rtutIdleFunc(set.then_some(idle as unsafe extern "C" fn())),
        RtutPostRedisplay => rtutPostRedisplay(),
        RtutSwapBuffers => rtutSwapBuffers(),
        RtutLeaveMainLoop => rtutLeaveMainLoop(),
        RtutMainLoop(calls) => {
            HARNESS.with(|h| h.borrow_mut().body = Some(calls.clone()));
            rtutMainLoop();
            // A loop that was refused, or whose display callback never ran, leaves its calls.
            HARNESS.with(|h| h.borrow_mut().body = None);
        }
    }
    None
}

fn message() -> String {
    unsafe { std::ffi::CStr::from_ptr(rtGetErrorString()) }.to_string_lossy().into_owned()
}

/// The state the context reports: every `rtGetDoublev` value and, outside a primitive (where
/// the call is refused), every render parameter.
fn reported_state(in_primitive: bool) -> Vec<f64> {
    let mut state = Vec::new();
    for &pname in QUERIES {
        let mut values = [0.0f64; 16];
        unsafe { rtGetDoublev(pname, values.as_mut_ptr()) };
        state.extend(values);
    }
    if !in_primitive {
        for pname in [RT_RENDER_MODE, RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_LIGHT_SAMPLES, RT_RUSSIAN_ROULETTE, RT_SEED] {
            state.push(f64::from(rtGetRenderParameteri(pname)));
        }
    }
    state
}

/// Makes one call and checks it against the model; returns the rule it broke.
fn step(call: &Call) -> Result<(), String> {
    let (expected, in_primitive) = with_model(|m| (m.expect(call), m.in_primitive));
    let before = reported_state(in_primitive);
    let returned = perform(call);
    let code = rtGetError();
    let what = message();
    // `rtRecordError` records the internal error it is given, which is no failure of raystage's.
    if code == RT_INTERNAL_ERROR && !matches!(call, Call::RecordError { code: RT_INTERNAL_ERROR, null: false }) {
        return Err(format!("{call:?} failed inside raystage: {what}"));
    }
    if let (Call::GetRenderParameter(pname), Some(value), RT_NO_ERROR) = (call, returned, code) {
        let model = with_model(|m| m.render_value(*pname));
        if value != i64::from(model) {
            return Err(format!("{call:?} returned {value}, not {model}: a refused setting changed something"));
        }
    }
    if let (Call::WaitFrame(_), Some(status)) = (call, returned) {
        let expected: &[RTenum] = if code == RT_NO_ERROR { &[RT_NO_ERROR, RT_CANCELLED] } else { &[code] };
        if !expected.contains(&(status as RTenum)) {
            return Err(format!("{call:?} returned {status:#x}, recorded {code:#x}"));
        }
    }
    if let (Call::StartFrame, Some(handle)) = (call, returned) {
        let issued = with_model(|m| m.issued.clone());
        if (handle != 0) != (code == RT_NO_ERROR) || issued.contains(&(handle as RTuint)) {
            return Err(format!("rtRenderFrameAsync returned handle {handle} (recorded {code:#x}) after {issued:?}: handles are never reused"));
        }
    }
    if let (Call::ClassQuery(4, _), Some(count)) = (call, returned) {
        let model = with_model(|m| m.parameter_counts.len());
        if count as usize != model {
            return Err(format!("rtGetShaderClassCount returned {count}, not {model}"));
        }
    }
    let fits = match expected {
        Expect::Code(c) => code == c,
        Expect::OneOf(codes) => codes.contains(&code),
    };
    if !fits {
        return Err(format!("{call:?} recorded {code:#x}, expected {expected:?}: {what}"));
    }
    // rt.h: a failed call changes nothing (rtResetContext never fails).
    if code != RT_NO_ERROR {
        let after = reported_state(in_primitive);
        let extra = rtGetError();
        if extra != RT_NO_ERROR {
            return Err(format!("reading the state after {call:?} recorded {extra:#x}: {}", message()));
        }
        if before != after {
            let changed: Vec<usize> = (0..before.len()).filter(|&i| before[i] != after[i]).collect();
            return Err(format!("{call:?} was refused ({what}) yet changed the state the context reports (values {changed:?})"));
        }
    }
    with_model(|m| m.update(call, code, returned));
    match HARNESS.with(|h| h.borrow_mut().failure.take()) {
        Some(failure) => Err(failure),
        None => Ok(()),
    }
}

/// RTUT runs headless, writing its frames into the test's directory; set once, before any
/// thread of the test reads the environment.
fn headless_rtut() {
    static SET: OnceLock<()> = OnceLock::new();
    SET.get_or_init(|| {
        let dir = MEMORY.with(|m| m.borrow().dir.clone());
        std::fs::create_dir_all(&dir).expect("the test's directory");
        image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255])).save(dir.join("texture.png")).expect("a texture file");
        // SAFETY: the first thing the test does, before it starts threads that read the
        // environment (proptest's runner reads its own variables before, not while).
        unsafe {
            std::env::set_var("RTUT_HEADLESS", "1");
            std::env::set_var("RTUT_OUTPUT", dir.join("rtut"));
        }
    });
}

/// A fresh context where ids 1 to 3 of objects, shader classes, shaders and textures exist, the
/// classes are defined (a surface class, a light class, another surface class), handles 1 to 8
/// name parameters, texture 1 is a checkerboard and an 8 × 8 frame buffer is lent, so that
/// random calls reach deep states often; RTUT is initialised for 10 × 6 frames, and with
/// `window` its window exists with the test's display callback.
fn prologue(window: bool) -> Result<(), String> {
    rtResetContext();
    rtGenObjects(3);
    rtGenShaderClasses(3);
    rtGenShaders(3);
    for (cid, name) in [(1, c"Diffuse"), (2, c"PointLight"), (3, c"Constant")] {
        unsafe { rtNewShaderClass(cid, name.as_ptr(), std::ptr::null()) };
    }
    for name in PARAMS {
        let name = CString::new(*name).unwrap();
        unsafe { rtParameterHandle(name.as_ptr()) };
    }
    rtGenTextures(3);
    rtBindTexture(RT_TEXTURE_2D, 1);
    unsafe { rtTexChecker(RT_TEXTURE_2D, [1.0f32; 3].as_ptr(), [0.0f32; 3].as_ptr(), 4.0) };
    let pixels = MEMORY.with(|m| m.borrow_mut().frame.as_mut_ptr());
    unsafe { rtFrameBuffer(pixels.cast(), SIDE, SIDE, RT_RGBA8) };
    let parameter_counts: Vec<usize> = (0..rtGetShaderClassCount()).map(|class| rtGetShaderParameterCount(class)).collect();
    rtutInit(std::ptr::null_mut(), std::ptr::null_mut());
    // Not the frame buffer's size, so that a frame buffer RTUT lent shows in RT_VIEWPORT.
    rtutInitWindowSize(WINDOW.0 as RTint, WINDOW.1 as RTint);
    if window {
        unsafe { rtutCreateWindow(c"random calls".as_ptr()) };
        rtutDisplayFunc(Some(display));
    }
    if rtGetError() != RT_NO_ERROR {
        return Err(format!("the prologue failed: {}", message()));
    }
    with_model(|m| {
        m.reset();
        m.objects = 3;
        m.classes = 3;
        m.frame = Some((SIDE, SIDE));
        m.parameter_counts = parameter_counts;
        m.rtut = RtutModel { initialised: true, window, size: WINDOW, display: window, ..RtutModel::default() };
    });
    Ok(())
}

/// Runs one sequence on this (fresh) thread, then checks that the scene still renders.
fn run_sequence(window: bool, calls: &[Call]) -> Result<(), String> {
    prologue(window)?;
    for call in calls {
        step(call)?;
    }
    // Whatever happened, finishing the definition leaves a scene that renders.
    let model = HARNESS.with(|h| std::mem::take(&mut h.borrow_mut().model));
    if model.in_primitive {
        rtEnd();
    }
    if model.defining {
        rtEndObject();
    }
    if let Some(frame) = model.in_flight {
        rtFrameWait(frame);
    }
    for channel in CHANNELS {
        unsafe { rtChannelBuffer(*channel, std::ptr::null_mut(), 0, 0) };
    }
    rtGetError();
    let mut frame = vec![0u8; 16 * 16 * 4];
    unsafe { rtFrameBuffer(frame.as_mut_ptr().cast(), 16, 16, RT_RGBA8) };
    rtSwapBuffers();
    let code = rtGetError();
    let rendered = code == RT_NO_ERROR && frame.chunks_exact(4).all(|p| p[3] == 255);
    let what = message();
    rtResetContext();
    if rendered { Ok(()) } else { Err(format!("the scene no longer renders ({code:#x}: {what})")) }
}

/// How many sequences to run: `RAYSTAGE_RANDOM_CALLS_CASES`, else 192.
fn cases() -> u32 {
    std::env::var("RAYSTAGE_RANDOM_CALLS_CASES").ok().and_then(|n| n.parse().ok()).unwrap_or(192)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn random_calls_keep_the_context_sound(window in any::<bool>(), steps in proptest::collection::vec(step_calls(), 1..24)) {
        headless_rtut();
        let calls: Vec<Call> = steps.into_iter().flatten().collect();
        if std::env::var_os("RAYSTAGE_PRINT_CALLS").is_some() {
            eprintln!("sequence (window {window}): {calls:?}");
        }
        let thread = std::thread::spawn(move || run_sequence(window, &calls));
        match thread.join() {
            Ok(result) => prop_assert!(result.is_ok(), "{}", result.unwrap_err()),
            Err(_) => prop_assert!(false, "the sequence panicked"),
        }
    }
}

/// The C functions declared in `header` (rt.h or rtut.h): each line that declares one starts
/// with its return type and names it before its first parenthesis.
fn declared_calls(header: &str) -> Vec<String> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../api/include/raystage").join(header);
    let header = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    header
        .lines()
        .filter(|line| line.starts_with(|c: char| c.is_ascii_alphabetic()) && !line.starts_with("typedef"))
        .filter_map(|line| {
            let before = &line[..line.find('(')?];
            let name = before.rsplit(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).next()?;
            name.starts_with("rt").then(|| name.to_string())
        })
        .collect()
}

#[test]
fn every_call_in_rt_h_is_generated() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    // Called around every generated call, not as one.
    let harness = ["rtGetError", "rtGetErrorString"];
    // Not generated, and why.
    let excluded: &[(&str, &str)] = if cfg!(feature = "mpi") {
        &[("rtInitMPI", "joins the test process to an MPI job, which a process does once; tests/examples.rs runs it under mpirun")]
    } else {
        &[]
    };
    fn names(call: &Call, out: &mut std::collections::BTreeSet<&'static str>) {
        out.insert(c_name(call));
        if let Call::RtutMainLoop(calls) = call {
            calls.iter().for_each(|c| names(c, out));
        }
    }
    let mut generated = std::collections::BTreeSet::new();
    let mut runner = TestRunner::deterministic();
    let strategy = step_calls();
    for _ in 0..20_000 {
        for call in strategy.new_tree(&mut runner).unwrap().current() {
            names(&call, &mut generated);
        }
    }
    let (rt, rtut) = (declared_calls("rt.h"), declared_calls("rtut.h"));
    assert!(rt.len() > 100 && rt.iter().any(|n| n == "rtSwapBuffers"), "rt.h was not read: {rt:?}");
    assert!(rtut.len() > 10 && rtut.iter().all(|n| n.starts_with("rtut")), "rtut.h was not read: {rtut:?}");
    let declared: Vec<String> = rt.into_iter().chain(rtut).collect();
    let missing: Vec<&String> = declared
        .iter()
        .filter(|n| !generated.contains(n.as_str()) && !harness.contains(&n.as_str()) && !excluded.iter().any(|(e, _)| e == n))
        .collect();
    assert!(missing.is_empty(), "rt.h or rtut.h declares calls the random-call model never makes: {missing:?}; add them to `Call`");
}

/// The random sequences again under valgrind (where it is installed, and this process is not
/// already under it), 256 of them: a read or write of freed memory that happens to leave the
/// results right fails here. The sequence that ran when valgrind first complained is printed.
#[test]
fn random_calls_under_valgrind() {
    if std::env::var_os("RAYSTAGE_UNDER_VALGRIND").is_some() {
        return;
    }
    let Ok(version) = std::process::Command::new("valgrind").arg("--version").output() else {
        eprintln!("valgrind is not installed: skipping (scripts/test.sh installs it)");
        return;
    };
    assert!(version.status.success(), "valgrind --version failed");
    let exe = std::env::current_exe().expect("this test's executable");
    let output = std::process::Command::new("valgrind")
        .args(["--error-exitcode=99", "--errors-for-leak-kinds=none", "--quiet"])
        .arg(&exe)
        .args(["--exact", "random_calls_keep_the_context_sound", "--test-threads=1", "--nocapture"])
        .env("RAYSTAGE_UNDER_VALGRIND", "1")
        .env("RAYSTAGE_PRINT_CALLS", "1")
        .env("RAYSTAGE_RANDOM_CALLS_CASES", "256")
        .output()
        .expect("valgrind runs");
    if output.status.success() {
        return;
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    // Valgrind's reports start with ==PID==; the sequence printed last before the first is the one.
    let first_report = lines.iter().position(|l| l.starts_with("==")).unwrap_or(lines.len());
    let sequence = lines[..first_report].iter().rev().find(|l| l.starts_with("sequence")).copied().unwrap_or("(none printed)");
    let report: Vec<&str> = lines[first_report..].iter().take(60).copied().collect();
    panic!(
        "under valgrind ({}):\nthe {sequence}\n{}\n{}",
        output.status,
        report.join("\n"),
        String::from_utf8_lossy(&output.stdout).lines().rev().take(30).collect::<Vec<_>>().into_iter().rev().collect::<Vec<_>>().join("\n")
    );
}
