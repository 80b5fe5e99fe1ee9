//! Surface shaders: built-in shader classes with named, typed, documented parameters, and shader
//! instances that hold values for them.
//!
//! As in the OpenRT API (DIGEST §1.1), geometry refers to shaders by id, and parameters are
//! written by name: writing a parameter a class does not export is silently ignored, so a scene
//! graph front end can write the same material fields to every shader. Every class declares its
//! parameters and their defaults in one table, next to their documentation (as pbrt-v4's
//! `ParameterDictionary` readers do).

use glam::Vec3;

use crate::error::SceneError;

/// The type of a shader parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// One number.
    Float,
    /// A linear RGB colour, three numbers.
    Color,
}

impl ParamType {
    /// How the type is named in error messages and documentation.
    pub fn describe(self) -> &'static str {
        match self {
            ParamType::Float => "a number",
            ParamType::Color => "a colour (three numbers)",
        }
    }
}

/// A shader parameter value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    /// One number.
    Float(f32),
    /// A linear RGB colour.
    Color(Vec3),
}

impl ParamValue {
    /// The value's type.
    pub fn ty(&self) -> ParamType {
        match self {
            ParamValue::Float(_) => ParamType::Float,
            ParamValue::Color(_) => ParamType::Color,
        }
    }

    fn is_finite(&self) -> bool {
        match self {
            ParamValue::Float(f) => f.is_finite(),
            ParamValue::Color(c) => c.is_finite(),
        }
    }
}

/// A parameter a shader class exports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDecl {
    /// Its name, as written by `rtParameterHandle` or the HTTP API.
    pub name: &'static str,
    /// Its value until written (which also fixes its type).
    pub default: ParamValue,
    /// What it does.
    pub doc: &'static str,
}

/// What a shader class computes; the renderer dispatches on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadingModel {
    /// Lambertian reflection of the lights, with shadows.
    Diffuse,
    /// Lambertian reflection with the albedo interpolated from the vertex colours.
    VertexColor,
    /// A fixed colour, unlit.
    Constant,
}

/// A built-in shader class.
#[derive(Debug, PartialEq)]
pub struct ShaderClass {
    /// Its name, as given to `rtNewShaderClass` or the HTTP API.
    pub name: &'static str,
    /// What it looks like.
    pub doc: &'static str,
    /// What it computes.
    pub model: ShadingModel,
    /// The parameters it exports.
    pub params: &'static [ParamDecl],
}

/// Every built-in shader class.
pub static SHADER_CLASSES: &[ShaderClass] = &[
    ShaderClass {
        name: "Diffuse",
        doc: "Matte surface: Lambertian reflection of every light, with shadows.",
        model: ShadingModel::Diffuse,
        params: &[ParamDecl {
            name: "diffuse",
            default: ParamValue::Color(Vec3::splat(0.8)),
            doc: "Reflectance (albedo), linear RGB in [0, 1].",
        }],
    },
    ShaderClass {
        name: "VertexColor",
        doc: "Matte surface coloured by the mesh's per-vertex colours, interpolated across each triangle.",
        model: ShadingModel::VertexColor,
        params: &[ParamDecl {
            name: "diffuse",
            default: ParamValue::Color(Vec3::ONE),
            doc: "Multiplies the vertex colours.",
        }],
    },
    ShaderClass {
        name: "Constant",
        doc: "A flat colour that ignores the lights.",
        model: ShadingModel::Constant,
        params: &[ParamDecl { name: "color", default: ParamValue::Color(Vec3::ONE), doc: "The colour, linear RGB." }],
    },
];

/// The built-in class called `name`.
pub fn shader_class(name: &str) -> Option<&'static ShaderClass> {
    SHADER_CLASSES.iter().find(|c| c.name == name)
}

/// A shader: a class and a value for each of its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Shader {
    class: &'static ShaderClass,
    values: Vec<ParamValue>,
}

impl Shader {
    /// A shader of the class called `class`, every parameter at its default.
    pub fn new(class: &str) -> Result<Shader, SceneError> {
        let class = shader_class(class).ok_or_else(|| SceneError::UnknownShaderClass(class.to_string()))?;
        Ok(Shader { class, values: class.params.iter().map(|p| p.default).collect() })
    }

    /// The shader's class.
    pub fn class(&self) -> &'static ShaderClass {
        self.class
    }

    /// Writes parameter `name`. Returns `Ok(false)` if the class does not export it (the write
    /// is ignored), an error if the value has the wrong type or is not finite.
    pub fn set(&mut self, name: &str, value: ParamValue) -> Result<bool, SceneError> {
        let Some(index) = self.class.params.iter().position(|p| p.name == name) else {
            return Ok(false);
        };
        let expected = self.class.params[index].default.ty();
        if value.ty() != expected {
            return Err(SceneError::WrongParameterType {
                class: self.class.name,
                name: name.to_string(),
                expected: expected.describe(),
            });
        }
        if !value.is_finite() {
            return Err(SceneError::NotFinite { field: "shader parameter", index });
        }
        self.values[index] = value;
        Ok(true)
    }

    /// The value of parameter `name`, if the class exports it.
    pub fn get(&self, name: &str) -> Option<ParamValue> {
        self.class.params.iter().position(|p| p.name == name).map(|i| self.values[i])
    }

    /// The colour parameter `name` (black if the class has no such colour).
    pub fn color(&self, name: &str) -> Vec3 {
        match self.get(name) {
            Some(ParamValue::Color(c)) => c,
            _ => Vec3::ZERO,
        }
    }
}
