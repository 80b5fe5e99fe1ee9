//! Shader parameters by name (seed: *The OpenRT API* §2.3.1, after the Stanford shading API):
//! `rtParameterHandle("diffuse")` turns a name into a handle once, `rtParameter3f(handle, ...)`
//! writes the bound shader's parameter of that name. A parameter the shader's class does not
//! export is ignored silently, so a front end can write the same material fields to any shader.
//!
//! Scopes: OpenRT lets a class store a parameter per shader, scene, object, triangle or vertex.
//! Every built-in class stores its parameters per shader, and the scene has nowhere to keep the
//! others, so only `RT_PER_SHADER` is accepted; the other scopes are refused with a clear error.

use glam::Vec3;
use raystage_scene::{ParamType, ParamValue, ShaderId, TextureId};

use crate::abi::enums::{RT_PER_OBJECT, RT_PER_SCENE, RT_PER_SHADER, RT_PER_TRIANGLE, RT_PER_VERTEX};
use crate::abi::types::{RTenum, RTint, RTuint};
use crate::context::Context;
use crate::error::{Error, finite};
use crate::light_class::Setter;
use crate::shaders::Slot;

/// Longest parameter name, in bytes.
const MAX_NAME_LEN: usize = 255;
/// Most distinct parameter names one context can hold handles for.
const MAX_HANDLES: usize = 1 << 16;

impl Context {
    /// `rtParameterHandle`: the handle of parameter `name` (the same for the same name).
    pub fn parameter_handle(&mut self, name: &str) -> Result<RTint, Error> {
        if name.is_empty() || name.len() > MAX_NAME_LEN {
            return Err(Error::invalid_value(format!("a parameter name has 1 to {MAX_NAME_LEN} bytes, not {}", name.len())));
        }
        let handles = &mut self.shaders.handles;
        let index = match handles.iter().position(|h| h == name) {
            Some(i) => i,
            None if handles.len() < MAX_HANDLES => {
                handles.push(name.to_string());
                handles.len() - 1
            }
            None => return Err(Error::out_of_memory(format!("a context holds at most {MAX_HANDLES} parameter names"))),
        };
        Ok(index as RTint + 1)
    }

    /// `rtParameterScope`: where the following parameter writes are stored.
    pub fn parameter_scope(&mut self, scope: RTenum) -> Result<(), Error> {
        let (unsupported, hint) = match scope {
            RT_PER_SHADER => return Ok(()),
            RT_PER_SCENE => ("per-scene", ""),
            RT_PER_OBJECT => ("per-object", ""),
            RT_PER_TRIANGLE => ("per-triangle", ""),
            RT_PER_VERTEX => ("per-vertex", "; per-vertex data are given with rtColor3f, rtNormal3f and rtTexCoord2f"),
            _ => return Err(Error::invalid_enum(format!("{scope:#x} is not a parameter scope"))),
        };
        Err(Error::invalid_enum(format!(
            "{unsupported} parameters are not supported: every built-in class stores its parameters per shader (RT_PER_SHADER){hint}"
        )))
    }

    /// `rtParameter1f` … `rtParameter4f`: writes `values` to parameter `handle` of the bound
    /// shader. Ignored if the shader's class does not export the name.
    pub fn parameter(&mut self, handle: RTint, values: &[f32]) -> Result<(), Error> {
        self.write_parameter(handle, Written::Numbers(values))
    }

    /// `rtParameterTexture`: makes parameter `handle` of the bound shader name texture `texture`
    /// (0: none). Ignored if the shader's class does not export the name.
    pub fn parameter_texture(&mut self, handle: RTint, texture: RTuint) -> Result<(), Error> {
        self.write_parameter(handle, Written::Texture(texture))
    }

    /// Writes `written` to parameter `handle` of the bound shader, a surface shader's or a
    /// light's, if its class exports the name and the parameter takes what is written.
    fn write_parameter(&mut self, handle: RTint, written: Written<'_>) -> Result<(), Error> {
        let (name, shader, slot) = self.parameter_target(handle)?;
        let written = match written {
            Written::Numbers(values) => finite("the value", values).map(|()| Value::Numbers(values))?,
            Written::Texture(0) => Value::Texture(None),
            Written::Texture(id) => Value::Texture(Some(self.textures.texture_id(id)?)),
        };
        match slot {
            Slot::Surface => {
                let class = self.scene.shader(shader)?.class();
                let Some(decl) = class.params.iter().find(|p| p.name == name) else {
                    return Ok(());
                };
                let value = match (decl.default.ty(), written) {
                    (ParamType::Texture, Value::Texture(texture)) => ParamValue::Texture(texture),
                    (ParamType::Texture, Value::Numbers(_)) => return Err(takes_texture(&name, class.name)),
                    (ty, Value::Texture(_)) => return Err(takes_numbers(&name, class.name, ty.describe())),
                    (ty, Value::Numbers(values)) => {
                        param_value(ty, values).ok_or_else(|| wrong_count(&name, class.name, ty.describe(), values.len()))?
                    }
                };
                self.scene.set_param(shader, &name, value)?;
                // The texture brings the parameters `rtTexParameteri` gave it to the slot.
                if let (ParamValue::Texture(Some(texture)), Some(slot)) = (value, name.strip_suffix("_texture")) {
                    self.textures.sampling(texture).write_to(&mut self.scene, shader, slot)?;
                }
            }
            Slot::Light { light, class } => {
                let Some(param) = class.params.iter().find(|p| p.name == name) else {
                    return Ok(());
                };
                let (_, &current) = self.scene.lights().find(|(id, _)| *id == light).expect("a light shader's light exists");
                let mut changed = current;
                match (param.set, written) {
                    (Setter::Number(set), Value::Numbers(&[v])) => set(&mut changed, v),
                    (Setter::Triple(set), Value::Numbers(&[x, y, z])) => set(&mut changed, Vec3::new(x, y, z)),
                    (Setter::Texture(set), Value::Texture(texture)) => set(&mut changed, texture),
                    (Setter::Number(_), Value::Numbers(values)) => return Err(wrong_count(&name, class.name, "a number", values.len())),
                    (Setter::Triple(_), Value::Numbers(values)) => return Err(wrong_count(&name, class.name, "three numbers", values.len())),
                    (Setter::Texture(_), Value::Numbers(_)) => return Err(takes_texture(&name, class.name)),
                    (Setter::Number(_) | Setter::Triple(_), Value::Texture(_)) => return Err(takes_numbers(&name, class.name, "numbers")),
                }
                self.scene.set_light(light, changed)?;
            }
            Slot::Generated | Slot::Fallback => unreachable!("only defined shaders are bound"),
        }
        Ok(())
    }

    /// The parameter name of `handle`, and the bound shader and what it holds.
    fn parameter_target(&self, handle: RTint) -> Result<(String, ShaderId, Slot), Error> {
        let name = usize::try_from(handle)
            .ok()
            .and_then(|h| self.shaders.handles.get(h.wrapping_sub(1)))
            .ok_or_else(|| Error::invalid_value(format!("{handle} is not a parameter handle from rtParameterHandle")))?
            .clone();
        let (shader, slot) = self
            .shaders
            .bound()
            .ok_or_else(|| Error::invalid_operation("no shader is bound: call rtNewShader or rtBindShader first"))?;
        Ok((name, shader, slot))
    }
}

/// What a parameter call writes, as the C call gives it.
enum Written<'a> {
    /// `rtParameter1f` … `rtParameter4f`.
    Numbers(&'a [f32]),
    /// `rtParameterTexture`: a C texture id, 0 for none.
    Texture(RTuint),
}

/// What a parameter call writes, checked: finite numbers, or a generated texture (or none).
#[derive(Clone, Copy)]
enum Value<'a> {
    Numbers(&'a [f32]),
    Texture(Option<TextureId>),
}

/// The error of a texture written to parameter `name`, which takes `expected`.
fn takes_numbers(name: &str, class: &str, expected: &str) -> Error {
    Error::invalid_operation(format!("parameter `{name}` of shader class `{class}` takes {expected}, not a texture"))
}

/// The error of numbers written to texture parameter `name`.
fn takes_texture(name: &str, class: &str) -> Error {
    Error::invalid_operation(format!("parameter `{name}` of shader class `{class}` takes a texture: write it with rtParameterTexture"))
}

/// `values` as a value of type `ty`, if the count fits.
fn param_value(ty: ParamType, values: &[f32]) -> Option<ParamValue> {
    match (ty, values) {
        (ParamType::Float, &[v]) => Some(ParamValue::Float(v)),
        (ParamType::Color, &[r, g, b]) => Some(ParamValue::Color(Vec3::new(r, g, b))),
        _ => None,
    }
}

fn wrong_count(name: &str, class: &str, expected: &str, got: usize) -> Error {
    let numbers = if got == 1 { "1 number".to_string() } else { format!("{got} numbers") };
    Error::invalid_operation(format!("parameter `{name}` of shader class `{class}` takes {expected}, not {numbers}"))
}
