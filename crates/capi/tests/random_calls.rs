//! Random sequences of C calls, valid and invalid, through the `extern "C"` functions: no panic
//! escapes, no call fails inside raystage (`RT_INTERNAL_ERROR`), every call the model can judge
//! records the error it predicts, the render settings read back are the last ones accepted, and
//! whatever happened, the scene still renders. Asynchronous frames start, are waited for,
//! cancelled and released among the edits, with one in flight at a time.

use std::ffi::CString;

use proptest::prelude::*;
use raystage_capi::abi::*;
use raystage_scene::SHADER_CLASSES;

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
    WaitFrame(RTuint),
    CancelFrame(RTuint),
    FrameProgress(RTuint),
    ReleaseFrame(RTuint),
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

fn call() -> impl Strategy<Value = Call> {
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
        1 => Just(Call::Swap),
        1 => (0u32..10, 0u32..10).prop_map(|(x, y)| Call::Pick(x, y)),
        1 => Just(Call::StartFrame),
        1 => (0u32..4).prop_map(Call::WaitFrame),
        1 => (0u32..4).prop_map(Call::CancelFrame),
        1 => (0u32..4).prop_map(Call::FrameProgress),
        1 => (0u32..4).prop_map(Call::ReleaseFrame),
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
fn step() -> impl Strategy<Value = Vec<Call>> {
    prop_oneof![6 => call().prop_map(|c| vec![c]), 2 => primitive(), 1 => definition()]
}

/// The side of the frame buffer the test renders into.
const SIDE: usize = 8;

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
    /// Asynchronous frame handles handed out (they count from 1 in each context).
    frames_issued: RTuint,
    /// The handles not yet released.
    frames: Vec<RTuint>,
    /// The frame started and not yet waited for nor released.
    in_flight: Option<RTuint>,
}

impl Model {
    fn new() -> Model {
        let rendering = vec![
            (RT_RENDER_MODE, RT_AUTO as RTint),
            (RT_SAMPLES_PER_PIXEL, 1),
            (RT_RAY_DEPTH, 6),
            (RT_LIGHT_SAMPLES, 1),
            (RT_RUSSIAN_ROULETTE, 1),
            (RT_SEED, 0),
        ];
        Model { depth: [1, 1], rendering, ..Model::default() }
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

    fn valid(e: RTenum, valid: &[RTenum]) -> bool {
        valid.contains(&e)
    }

    /// What `call` should record in the current state.
    fn expect(&self, call: &Call) -> Expect {
        use Call::*;
        use Expect::*;
        // The calls allowed between rtBegin and rtEnd (rtEndObject ends the primitive too).
        let vertex_call = matches!(call, Vertex(_) | Vertex2(_) | Normal(_) | Color(_) | TexCoord(_) | End | EndObject | Get(_));
        if self.in_primitive && !vertex_call {
            return Code(RT_INVALID_OPERATION);
        }
        let value = |ok: bool| Code(if ok { RT_NO_ERROR } else { RT_INVALID_VALUE });
        let enumerated = |e, valid| Code(if Model::valid(e, valid) { RT_NO_ERROR } else { RT_INVALID_ENUM });
        let depth = self.depth[self.texture_mode as usize];
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
            TexImage { .. } | TexChecker(..) | ParameterTexture(..) => OneOf(OK_VALUE_OR_OPERATION),
            ParameterHandle(_) => Code(RT_NO_ERROR),
            Begin(_) if !self.defining => Code(RT_INVALID_OPERATION),
            Begin(mode) if !Model::valid(*mode, PRIMITIVES) => Code(RT_INVALID_ENUM),
            Begin(_) => OneOf(OK_OR_OPERATION),
            End => Code(if self.in_primitive { RT_NO_ERROR } else { RT_INVALID_OPERATION }),
            Vertex(_) if !self.in_primitive => Code(RT_INVALID_OPERATION),
            Vertex(v) if !Model::finite(v) => Code(RT_INVALID_VALUE),
            Vertex(_) => OneOf(OK_OR_VALUE),
            Vertex2(_) if !self.in_primitive => Code(RT_INVALID_OPERATION),
            Vertex2(v) if !Model::finite(v) => Code(RT_INVALID_VALUE),
            Vertex2(_) => OneOf(OK_OR_VALUE),
            Normal(v) | Color(v) => value(Model::finite(v)),
            TexCoord(v) => value(Model::finite(v)),
            ShadeModel(m) => enumerated(*m, SHADE),
            TriangleMesh { .. } if !self.defining => Code(RT_INVALID_OPERATION),
            TriangleMesh { .. } => OneOf(OK_VALUE_OR_OPERATION),
            MatrixMode(m) => enumerated(*m, MODES),
            PushMatrix => Code(if depth == RT_MAX_STACK_DEPTH { RT_STACK_OVERFLOW } else { RT_NO_ERROR }),
            PopMatrix => Code(if depth == 1 { RT_STACK_UNDERFLOW } else { RT_NO_ERROR }),
            Translate(v) | Scale(v) if !Model::finite(v) => Code(RT_INVALID_VALUE),
            Rotate(a, v) if !Model::finite(v) || !a.is_finite() || *v == [0.0; 3] => Code(RT_INVALID_VALUE),
            Translate(_) | Scale(_) | Rotate(..) | LookAt(_) => OneOf(OK_OR_VALUE),
            Perspective(fov) => value(*fov > 0.0 && *fov < 180.0),
            Window(orthographic, w) => {
                let [left, right, bottom, top, near, far] = *w;
                let empty = left == right || bottom == top || near == far;
                let depth_ok = *orthographic || (near > 0.0 && far > near);
                if !Model::finite(w) || empty || !depth_ok {
                    Code(RT_INVALID_VALUE)
                } else {
                    // A window wider than single precision's range is refused too.
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
            Get(p) => enumerated(*p, QUERIES),
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
            Swap | StartFrame if self.defining || self.in_flight.is_some() => Code(RT_INVALID_OPERATION),
            Swap | StartFrame => Code(RT_NO_ERROR),
            WaitFrame(h) | CancelFrame(h) | FrameProgress(h) | ReleaseFrame(h) => value(self.frames.contains(h)),
            Pick(x, y) => value((*x as usize) < SIDE && (*y as usize) < SIDE),
        }
    }

    fn set_render_value(&mut self, pname: RTenum, value: RTint) {
        self.rendering.iter_mut().filter(|(p, _)| *p == pname).for_each(|(_, v)| *v = value);
    }

    /// Follows the state change of `call`, which recorded `code`.
    fn update(&mut self, call: &Call, code: RTenum) {
        use Call::*;
        let ok = code == RT_NO_ERROR;
        match call {
            EndObject if self.defining => (self.defining, self.in_primitive) = (false, false),
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
            StartFrame => {
                self.frames_issued += 1;
                self.frames.push(self.frames_issued);
                self.in_flight = Some(self.frames_issued);
            }
            WaitFrame(h) if self.in_flight == Some(*h) => self.in_flight = None,
            ReleaseFrame(h) => {
                self.frames.retain(|f| f != h);
                self.in_flight = self.in_flight.filter(|f| f != h);
            }
            _ => {}
        }
    }
}

/// Makes the call through the C ABI; returns what a query returned.
fn perform(call: &Call) -> Option<RTint> {
    use Call::*;
    let null = std::ptr::null();
    match call {
        GenObjects(n) => drop(rtGenObjects(*n)),
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
        GetRenderParameter(p) => return Some(rtGetRenderParameteri(*p)),
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
        StartFrame => drop(rtRenderFrameAsync()),
        WaitFrame(h) => return Some(rtFrameWait(*h) as RTint),
        CancelFrame(h) => rtFrameCancel(*h),
        FrameProgress(h) => {
            let progress = rtFrameProgress(*h);
            assert!((0.0..=1.0).contains(&progress), "progress {progress}");
        }
        ReleaseFrame(h) => rtFrameRelease(*h),
        Pick(x, y) => drop(unsafe { rtPick(*x, *y, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) }),
    }
    None
}

/// A fresh context where ids 1 to 3 of objects, shader classes, shaders and textures exist, the
/// classes are defined (a surface class, a light class, another surface class), handles 1 to 8
/// name parameters and texture 1 is a checkerboard, so that random calls reach deep states
/// often.
fn prologue(model: &mut Model) {
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
    assert_eq!(rtGetError(), RT_NO_ERROR, "{}", message());
    model.objects = 3;
    model.classes = 3;
}

fn message() -> String {
    unsafe { std::ffi::CStr::from_ptr(rtGetErrorString()) }.to_string_lossy().into_owned()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]

    #[test]
    fn random_calls_keep_the_context_sound(steps in proptest::collection::vec(step(), 1..24)) {
        let calls: Vec<Call> = steps.into_iter().flatten().collect();
        let mut model = Model::new();
        prologue(&mut model);
        let mut pixels = vec![0u8; SIDE * SIDE * 4];
        unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), SIDE, SIDE, RT_RGBA8) };
        for call in &calls {
            let expected = model.expect(call);
            let returned = perform(call);
            let code = rtGetError();
            prop_assert_ne!(code, RT_INTERNAL_ERROR, "{:?}: {}", call, message());
            if let (Call::GetRenderParameter(pname), Some(value), RT_NO_ERROR) = (call, returned, code) {
                prop_assert_eq!(value, model.render_value(*pname), "{:?}: refused settings change nothing", call);
            }
            if let (Call::WaitFrame(_), Some(status)) = (call, returned) {
                let expected: &[RTenum] = if code == RT_NO_ERROR { &[RT_NO_ERROR, RT_CANCELLED] } else { &[code] };
                prop_assert!(expected.contains(&(status as RTenum)), "{:?} returned {:#x}, recorded {:#x}", call, status, code);
            }
            match expected {
                Expect::Code(c) => prop_assert_eq!(code, c, "{:?}: {}", call, message()),
                Expect::OneOf(codes) => prop_assert!(codes.contains(&code), "{:?} recorded {:#x}: {}", call, code, message()),
            }
            model.update(call, code);
        }

        // Whatever happened, finishing the definition leaves a scene that renders.
        if model.in_primitive {
            rtEnd();
        }
        if model.defining {
            rtEndObject();
        }
        if let Some(frame) = model.in_flight {
            rtFrameWait(frame);
        }
        rtGetError();
        let mut frame = vec![0u8; 16 * 16 * 4];
        unsafe { rtFrameBuffer(frame.as_mut_ptr().cast(), 16, 16, RT_RGBA8) };
        rtSwapBuffers();
        prop_assert_eq!(rtGetError(), RT_NO_ERROR, "{}", message());
        prop_assert!(frame.chunks_exact(4).all(|p| p[3] == 255), "every pixel written");
        rtResetContext();
    }
}
