//! Applying edits. Every edit, whether it came alone (`POST /objects`) or in a batch
//! (`POST /commands`), runs through [`execute`]: first each command is checked against the
//! scene as the earlier commands will have left it (ids, labels, deletions, meshes,
//! transforms, parameters, lights, textures, camera, animations), with no edit made; only when all pass
//! are they applied. So a failed batch changes nothing, without copying the scene.

use std::collections::{BTreeMap, HashMap, HashSet};

use glam::{Affine3A, Vec3};
use raystage_scene::{AnimationChoice, Camera, InstanceId, Light, LightId, Mesh, ObjectId, ObjectKind, ParamValue, Play, Scene, SceneError, Shader, ShaderId, Texture, TextureId};

use crate::config::Limits;
use crate::error::{Error, Result};
use crate::model::{AnimationRef, Binding, Command, CommandResult, Kind as JsonKind, LightSpec, MeshSpec, ParamJson, ParamWrite, Ref, decode_positions, param_value};

/// The kinds of resources commands refer to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Object,
    Instance,
    Shader,
    Light,
    Texture,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Object => "object",
            Kind::Instance => "instance",
            Kind::Shader => "shader",
            Kind::Light => "light",
            Kind::Texture => "texture",
        }
    }
}

/// A resource as a command sees it: one that exists, or the one command `n` of the batch
/// creates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Target {
    Existing(u32),
    New(usize),
}

/// A checked shader parameter write: a value, or a texture that may be one the batch creates.
enum Write {
    Value(ParamValue),
    Texture(Target),
}

/// A checked command, ready to apply. Lights carry their environment map apart, as it may be a
/// texture the batch creates.
enum Op {
    AddObject { kind: ObjectKind, mesh: Mesh, shaders: Binding<Target> },
    DefineObject { id: Target, kind: ObjectKind, mesh: Mesh, shaders: Binding<Target> },
    SetPositions { id: Target, positions: Vec<Vec3> },
    DeleteObject(Target),
    AddInstance { object: Target, start: Affine3A, end: Option<Affine3A> },
    SetInstance { id: Target, start: Affine3A, end: Option<Affine3A> },
    DeleteInstance(Target),
    AddShader { class: String, params: Vec<(String, Write)>, ignored: Vec<String> },
    DefineShader { id: Target, class: String, params: Vec<(String, Write)>, ignored: Vec<String> },
    SetParams { id: Target, params: Vec<(String, Write)>, ignored: Vec<String> },
    DeleteShader(Target),
    AddLight { light: Light, map: Option<Target> },
    SetLight { id: Target, light: Light, map: Option<Target> },
    DeleteLight(Target),
    AddTexture(Texture),
    SetTexture(Target, Texture),
    DeleteTexture(Target),
    SetCamera(Camera),
    SetTime { play: Play, seconds: f32 },
}

/// Checks every command, then applies them all. In a batch, error fields are prefixed with the
/// command's place (`commands[2].add_object.mesh.positions`).
pub(crate) fn execute(scene: &mut Scene, commands: Vec<Command>, limits: &Limits, in_batch: bool) -> Result<Vec<CommandResult>> {
    if commands.len() > limits.max_commands {
        return Err(Error::too_large(Some("commands".into()), format!("{} commands: the limit is {}", commands.len(), limits.max_commands)).limit("max_commands"));
    }
    let mut planner = Planner::new(scene, limits);
    let mut ops = Vec::with_capacity(commands.len());
    for (i, command) in commands.into_iter().enumerate() {
        let name = command.op();
        ops.push(planner.plan(i, command).map_err(|e| if in_batch { e.within(&format!("commands[{i}].{name}")) } else { e })?);
    }
    apply(scene, ops, in_batch)
}

/// The scene as the commands checked so far will leave it, as far as later commands can tell.
struct Planner<'s> {
    scene: &'s Scene,
    limits: &'s Limits,
    labels: HashMap<String, (Kind, usize)>,
    gone: HashSet<(Kind, Target)>,
    /// Vertex counts of objects created or redefined by the batch.
    vertices: HashMap<Target, usize>,
    /// Instances created by the batch, with their objects.
    new_instances: Vec<(Target, Target)>,
    /// The scene's instances and their objects, and its lights (looked up once, when needed).
    existing_instances: Option<HashMap<u32, u32>>,
    existing_lights: Option<HashSet<u32>>,
    /// Shaders as the batch leaves them.
    shaders: HashMap<Target, Shader>,
    camera: Camera,
}

impl<'s> Planner<'s> {
    fn new(scene: &'s Scene, limits: &'s Limits) -> Planner<'s> {
        Planner {
            scene,
            limits,
            labels: HashMap::new(),
            gone: HashSet::new(),
            vertices: HashMap::new(),
            new_instances: Vec::new(),
            existing_instances: None,
            existing_lights: None,
            shaders: HashMap::new(),
            camera: *scene.camera(),
        }
    }

    fn plan(&mut self, i: usize, command: Command) -> Result<Op> {
        Ok(match command {
            Command::AddObject(b) => {
                let (mesh, shaders) = self.mesh(b.mesh)?;
                self.label(b.label, Kind::Object, i)?;
                self.vertices.insert(Target::New(i), mesh.positions.len());
                Op::AddObject { kind: b.kind.unwrap_or_default().to_scene(), mesh, shaders }
            }
            Command::DefineObject(d) => {
                let id = self.resolve(&d.id, Kind::Object, "id")?;
                let (mesh, shaders) = self.mesh(d.mesh)?;
                self.vertices.insert(id, mesh.positions.len());
                Op::DefineObject { id, kind: d.kind.unwrap_or(JsonKind::Unstructured).to_scene(), mesh, shaders }
            }
            Command::SetPositions(s) => {
                let id = self.resolve(&s.id, Kind::Object, "id")?;
                let positions = decode_positions(s.positions, s.positions_base64, self.limits)?;
                let expected = match (self.vertices.get(&id), id) {
                    (Some(&n), _) => n,
                    (None, Target::Existing(object)) => self.scene.mesh(ObjectId(object))?.positions.len(),
                    (None, Target::New(_)) => unreachable!("objects made by the batch have their vertex count recorded"),
                };
                if positions.len() != expected {
                    return Err(SceneError::WrongLength { field: "positions", got: positions.len(), expected }.into());
                }
                if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
                    return Err(SceneError::NotFinite { field: "positions", index }.into());
                }
                Op::SetPositions { id, positions }
            }
            Command::DeleteObject(d) => {
                let id = self.resolve(&d.id, Kind::Object, "id")?;
                self.gone.insert((Kind::Object, id));
                // Its instances go with it.
                let mut doomed: Vec<Target> = self.new_instances.iter().filter(|(_, o)| *o == id).map(|(inst, _)| *inst).collect();
                if let Target::Existing(object) = id {
                    doomed.extend(self.instances().iter().filter(|(_, o)| **o == object).map(|(inst, _)| Target::Existing(*inst)));
                }
                self.gone.extend(doomed.into_iter().map(|t| (Kind::Instance, t)));
                Op::DeleteObject(id)
            }
            Command::AddInstance(b) => {
                let object = self.resolve(&b.object, Kind::Object, "object")?;
                let start = b.transform.to_affine().map_err(|e| e.within("transform"))?;
                let end = b.end_transform.map(|t| t.to_affine().map_err(|e| e.within("end_transform"))).transpose()?;
                self.label(b.label, Kind::Instance, i)?;
                self.new_instances.push((Target::New(i), object));
                Op::AddInstance { object, start, end }
            }
            Command::SetInstance(s) => {
                let id = self.resolve(&s.id, Kind::Instance, "id")?;
                let start = s.transform.to_affine().map_err(|e| e.within("transform"))?;
                let end = s.end_transform.map(|t| t.to_affine().map_err(|e| e.within("end_transform"))).transpose()?;
                Op::SetInstance { id, start, end }
            }
            Command::DeleteInstance(d) => {
                let id = self.resolve(&d.id, Kind::Instance, "id")?;
                self.gone.insert((Kind::Instance, id));
                Op::DeleteInstance(id)
            }
            Command::AddShader(b) => {
                let shader = Shader::new(&b.class).map_err(Error::from)?;
                let (shader, params, ignored) = self.write_params(shader, b.params)?;
                self.label(b.label, Kind::Shader, i)?;
                self.shaders.insert(Target::New(i), shader);
                Op::AddShader { class: b.class, params, ignored }
            }
            Command::DefineShader(d) => {
                let id = self.resolve(&d.id, Kind::Shader, "id")?;
                let shader = Shader::new(&d.class).map_err(Error::from)?;
                let (shader, params, ignored) = self.write_params(shader, d.params)?;
                self.shaders.insert(id, shader);
                Op::DefineShader { id, class: d.class, params, ignored }
            }
            Command::SetParams(s) => {
                let id = self.resolve(&s.id, Kind::Shader, "id")?;
                let shader = match (self.shaders.get(&id), id) {
                    (Some(shader), _) => shader.clone(),
                    (None, Target::Existing(shader)) => self.scene.shader(ShaderId(shader))?.clone(),
                    (None, Target::New(_)) => unreachable!("shaders made by the batch are recorded"),
                };
                let (shader, params, ignored) = self.write_params(shader, s.params)?;
                self.shaders.insert(id, shader);
                Op::SetParams { id, params, ignored }
            }
            Command::DeleteShader(d) => {
                let id = self.resolve(&d.id, Kind::Shader, "id")?;
                self.gone.insert((Kind::Shader, id));
                self.shaders.remove(&id);
                Op::DeleteShader(id)
            }
            Command::AddLight(spec) => {
                let (light, map) = self.light(&spec)?;
                self.label(spec.label, Kind::Light, i)?;
                Op::AddLight { light, map }
            }
            Command::SetLight(s) => {
                let id = self.resolve(&s.id, Kind::Light, "id")?;
                let (light, map) = self.light(&s.light).map_err(|e| e.within("light"))?;
                Op::SetLight { id, light, map }
            }
            Command::DeleteLight(d) => {
                let id = self.resolve(&d.id, Kind::Light, "id")?;
                self.gone.insert((Kind::Light, id));
                Op::DeleteLight(id)
            }
            Command::AddTexture(spec) => {
                let texture = spec.to_texture()?;
                self.label(spec.label, Kind::Texture, i)?;
                Op::AddTexture(texture)
            }
            Command::SetTexture(s) => {
                let id = self.resolve(&s.id, Kind::Texture, "id")?;
                Op::SetTexture(id, s.texture.to_texture().map_err(|e| e.within("texture"))?)
            }
            Command::DeleteTexture(d) => {
                let id = self.resolve(&d.id, Kind::Texture, "id")?;
                self.gone.insert((Kind::Texture, id));
                Op::DeleteTexture(id)
            }
            Command::SetCamera(patch) => {
                self.camera = patch.apply(self.camera)?;
                Op::SetCamera(self.camera)
            }
            Command::SetTime(t) => {
                // The bound is `f32`'s, the scene's time type: past it a time is infinite.
                let seconds = t.seconds as f32;
                if !(t.seconds >= 0.0 && seconds.is_finite()) {
                    return Err(Error::unprocessable(Some("seconds".into()), format!("{} is not a time: it must be a finite number of seconds, at least 0", t.seconds)));
                }
                Op::SetTime { play: self.play(t.animation)?, seconds }
            }
        })
    }

    /// The animations `animation` names (default the first), which must be the scene's.
    fn play(&self, animation: Option<AnimationRef>) -> Result<Play> {
        let field = Some("animation".to_string());
        let animations = self.scene.animations();
        if animations.is_empty() {
            return Err(Error::unprocessable(field, "the scene has no animations (a glTF file's come with it: POST /scenes/{scene}/gltf)"));
        }
        let choice = animation.as_ref().map(|a| match a {
            AnimationRef::Index(k) => AnimationChoice::Index(*k as usize),
            AnimationRef::Name(name) => AnimationChoice::Name(name),
        });
        Play::choose(&animations, choice).ok_or_else(|| {
            let message = match &animation {
                Some(AnimationRef::Index(k)) => format!("there is no animation {k}: the scene has {}", animations.len()),
                Some(AnimationRef::Name(name)) => format!("the scene has no animation named `{name}`"),
                None => "the scene has no animations".to_string(),
            };
            Error::unprocessable(field, message)
        })
    }

    /// A light checked, with its environment map resolved.
    fn light(&mut self, spec: &LightSpec) -> Result<(Light, Option<Target>)> {
        let light = spec.to_light()?;
        let map = spec.map.as_ref().map(|r| self.resolve(r, Kind::Texture, "map")).transpose()?;
        Ok((light, map))
    }

    /// Writes parameters into a copy of a shader (checking each as the scene will, and
    /// resolving textures); returns the shader, the writes to make, and the names the class
    /// does not export.
    #[allow(clippy::type_complexity)]
    fn write_params(&mut self, mut shader: Shader, params: BTreeMap<String, ParamJson>) -> Result<(Shader, Vec<(String, Write)>, Vec<String>)> {
        let mut writes = Vec::new();
        let mut ignored = Vec::new();
        for (name, value) in params {
            let field = format!("params.{name}");
            match param_value(shader.class(), &name, value) {
                None => ignored.push(name),
                Some(ParamWrite::Value(value)) => {
                    shader.set(&name, value).map_err(|e| {
                        let mut e = Error::from(e);
                        e.detail.field = Some(field);
                        e
                    })?;
                    writes.push((name, Write::Value(value)));
                }
                // Only texture parameters take texture references, so the write has the right
                // type; the copy, which checks later writes, need not know which texture it is.
                Some(ParamWrite::Texture(texture)) => {
                    let texture = self.resolve(&texture, Kind::Texture, &field)?;
                    writes.push((name, Write::Texture(texture)));
                }
            }
        }
        Ok((shader, writes, ignored))
    }

    /// A mesh decoded and checked, with its shaders resolved.
    fn mesh(&mut self, spec: MeshSpec) -> Result<(Mesh, Binding<Target>)> {
        let (mesh, binding) = spec.decode(self.limits).map_err(|e| e.within("mesh"))?;
        mesh.validate().map_err(|e| Error::from(e).within("mesh"))?;
        let shaders = match binding {
            Binding::Default => Binding::Default,
            Binding::All(r) => Binding::All(self.resolve(&r, Kind::Shader, "mesh.shader")?),
            Binding::Each(refs) => {
                if refs.len() != mesh.indices.len() {
                    return Err(Error::from(SceneError::WrongLength { field: "shaders", got: refs.len(), expected: mesh.indices.len() }).within("mesh"));
                }
                let mut resolved = HashMap::new();
                let mut out = Vec::with_capacity(refs.len());
                for (k, r) in refs.iter().enumerate() {
                    // Meshes bind few distinct shaders: resolve each once.
                    let t = match resolved.get(r) {
                        Some(&t) => t,
                        None => {
                            let t = self.resolve(r, Kind::Shader, &format!("mesh.shaders[{k}]"))?;
                            resolved.insert(r.clone(), t);
                            t
                        }
                    };
                    out.push(t);
                }
                Binding::Each(out)
            }
        };
        Ok((mesh, shaders))
    }

    /// Gives the resource command `i` creates a label.
    fn label(&mut self, label: Option<String>, kind: Kind, i: usize) -> Result<()> {
        let Some(label) = label else {
            return Ok(());
        };
        if self.labels.contains_key(&label) {
            return Err(Error::unprocessable(Some("label".into()), format!("label `{label}` is already used in this batch")));
        }
        self.labels.insert(label, (kind, i));
        Ok(())
    }

    /// The resource `r` names, which must exist when the command runs (404 otherwise).
    fn resolve(&mut self, r: &Ref, kind: Kind, field: &str) -> Result<Target> {
        let missing = |message: String| Error::not_found(Some(field.to_string()), message);
        let target = match r {
            Ref::Id(id) => {
                if !self.exists(kind, *id) {
                    return Err(missing(format!("unknown {} {id}", kind.name())));
                }
                Target::Existing(*id)
            }
            Ref::Label(label) => match self.labels.get(label) {
                Some(&(k, i)) if k == kind => Target::New(i),
                Some(&(k, _)) => {
                    return Err(Error::unprocessable(Some(field.to_string()), format!("`{label}` labels a {}, not a {}", k.name(), kind.name())));
                }
                None => return Err(missing(format!("no earlier command of this batch has the label `{label}`"))),
            },
        };
        if self.gone.contains(&(kind, target)) {
            return Err(missing(format!("{} {r} was deleted earlier in this batch", kind.name())));
        }
        Ok(target)
    }

    fn exists(&mut self, kind: Kind, id: u32) -> bool {
        match kind {
            Kind::Object => self.scene.mesh(ObjectId(id)).is_ok(),
            Kind::Shader => self.scene.shader(ShaderId(id)).is_ok(),
            Kind::Instance => self.instances().contains_key(&id),
            Kind::Light => {
                let scene = self.scene;
                self.existing_lights.get_or_insert_with(|| scene.lights().map(|(id, _)| id.0).collect()).contains(&id)
            }
            Kind::Texture => self.scene.texture(TextureId(id)).is_ok(),
        }
    }

    /// The scene's instances and their objects.
    fn instances(&mut self) -> &HashMap<u32, u32> {
        let scene = self.scene;
        self.existing_instances.get_or_insert_with(|| scene.instances().map(|(i, o, _)| (i.0, o.0)).collect())
    }
}

/// Applies checked commands in order. A pose is the one edit that can still fail here: whether
/// every node can be placed at a time (a node scaled to zero cannot) is known only by posing,
/// so that failure is the client's (422), and the caller restores the scene.
fn apply(scene: &mut Scene, ops: Vec<Op>, in_batch: bool) -> Result<Vec<CommandResult>> {
    let mut ids: Vec<Option<u32>> = Vec::with_capacity(ops.len());
    let mut results = Vec::with_capacity(ops.len());
    for (k, op) in ops.into_iter().enumerate() {
        let posing = matches!(op, Op::SetTime { .. });
        let result = apply_one(scene, op, &ids).map_err(|e| {
            if !posing {
                return Error::internal(format!("command {k} failed although it was checked ({e}); the commands before it were applied"));
            }
            let e = Error::unprocessable(Some("seconds".into()), format!("the scene cannot be posed at this time: {e}"));
            if in_batch { e.within(&format!("commands[{k}].set_time")) } else { e }
        })?;
        ids.push(result.id);
        results.push(result);
    }
    Ok(results)
}

fn apply_one(scene: &mut Scene, op: Op, ids: &[Option<u32>]) -> Result<CommandResult, SceneError> {
    let real = |t: Target| match t {
        Target::Existing(id) => id,
        Target::New(i) => ids[i].expect("a command's resources are created before later commands use them"),
    };
    let bind = |mut mesh: Mesh, shaders: Binding<Target>| {
        mesh.shaders = match shaders {
            Binding::Default => Vec::new(),
            Binding::All(t) => vec![ShaderId(real(t)); mesh.indices.len()],
            Binding::Each(ts) => ts.into_iter().map(|t| ShaderId(real(t))).collect(),
        };
        mesh
    };
    let created = |id: u32| CommandResult { id: Some(id), ignored: Vec::new() };
    let done = CommandResult::default();
    let write = |scene: &mut Scene, id: ShaderId, params: Vec<(String, Write)>| -> Result<(), SceneError> {
        for (name, write) in params {
            let value = match write {
                Write::Value(value) => value,
                Write::Texture(t) => ParamValue::Texture(Some(TextureId(real(t)))),
            };
            scene.set_param(id, &name, value)?;
        }
        Ok(())
    };
    let mapped = |mut light: Light, map: Option<Target>| {
        if let (Light::Environment { map: slot, .. }, Some(t)) = (&mut light, map) {
            *slot = Some(TextureId(real(t)));
        }
        light
    };
    Ok(match op {
        Op::AddObject { kind, mesh, shaders } => created(scene.add_object(kind, bind(mesh, shaders))?.0),
        Op::DefineObject { id, kind, mesh, shaders } => {
            scene.define_object(ObjectId(real(id)), kind, bind(mesh, shaders))?;
            done
        }
        Op::SetPositions { id, positions } => {
            scene.set_positions(ObjectId(real(id)), positions)?;
            done
        }
        Op::DeleteObject(id) => {
            scene.delete_object(ObjectId(real(id)))?;
            done
        }
        Op::AddInstance { object, start, end } => {
            let id = scene.add_instance(ObjectId(real(object)), start)?;
            if end.is_some() {
                scene.set_motion(id, start, end)?;
            }
            created(id.0)
        }
        Op::SetInstance { id, start, end } => {
            scene.set_motion(InstanceId(real(id)), start, end)?;
            done
        }
        Op::DeleteInstance(id) => {
            scene.remove_instance(InstanceId(real(id)))?;
            done
        }
        Op::AddShader { class, params, ignored } => {
            let id = scene.add_shader(&class)?;
            write(scene, id, params)?;
            CommandResult { id: Some(id.0), ignored }
        }
        Op::DefineShader { id, class, params, ignored } => {
            let id = ShaderId(real(id));
            scene.define_shader(id, &class)?;
            write(scene, id, params)?;
            CommandResult { id: None, ignored }
        }
        Op::SetParams { id, params, ignored } => {
            write(scene, ShaderId(real(id)), params)?;
            CommandResult { id: None, ignored }
        }
        Op::DeleteShader(id) => {
            scene.remove_shader(ShaderId(real(id)))?;
            done
        }
        Op::AddLight { light, map } => created(scene.add_light(mapped(light, map))?.0),
        Op::SetLight { id, light, map } => {
            scene.set_light(LightId(real(id)), mapped(light, map))?;
            done
        }
        Op::DeleteLight(id) => {
            scene.remove_light(LightId(real(id)))?;
            done
        }
        Op::AddTexture(texture) => created(scene.add_texture(texture)?.0),
        Op::SetTexture(id, texture) => {
            scene.set_texture(TextureId(real(id)), texture)?;
            done
        }
        Op::DeleteTexture(id) => {
            scene.remove_texture(TextureId(real(id)))?;
            done
        }
        Op::SetCamera(camera) => {
            scene.set_camera(camera)?;
            done
        }
        Op::SetTime { play, seconds } => {
            scene.pose(play, seconds)?;
            done
        }
    })
}
