//! What the built-in shader classes are, for programs to ask at run time, as ANARI has
//! `anariGetObjectSubtypes` and `anariGetParameterInfo`: every class (surfaces, then lights),
//! its documentation, and each parameter's name, type, default, range and documentation. A
//! porter then tells a real parameter from one the class ignores without guessing. Read from the
//! same registries that `rtNewShaderClass` and `rtParameterHandle` use, so they cannot differ.

use std::ffi::CString;
use std::sync::LazyLock;

use raystage_scene::{ParamValue, SHADER_CLASSES};

use crate::abi::enums::{RT_FLOAT, RT_FLOAT_VEC3, RT_LIGHT_CLASS, RT_SURFACE_CLASS, RT_TEXTURE_2D};
use crate::abi::types::RTenum;
use crate::error::Error;
use crate::light_class::{LIGHT_CLASSES, Setter};

/// A class, with its strings as C strings that live as long as the library.
pub(crate) struct ClassInfo {
    pub name: CString,
    pub doc: CString,
    /// `RT_SURFACE_CLASS` or `RT_LIGHT_CLASS`.
    pub kind: RTenum,
    pub params: Vec<ParamInfo>,
}

/// A parameter of a class.
pub(crate) struct ParamInfo {
    pub name: CString,
    pub doc: CString,
    /// `RT_FLOAT`, `RT_FLOAT_VEC3` or `RT_TEXTURE_2D`.
    pub ty: RTenum,
    /// Three numbers (a number in the first, zeros for a texture).
    pub default: [f32; 3],
    /// The values accepted, for each of its numbers.
    pub range: [f32; 2],
}

/// A C string of `text` (the registries' strings have no NUL).
fn c(text: &str) -> CString {
    CString::new(text).expect("no NUL in the class registries")
}

/// Every class, surfaces first.
static CLASSES: LazyLock<Vec<ClassInfo>> = LazyLock::new(|| {
    let surfaces = SHADER_CLASSES.iter().map(|class| ClassInfo {
        name: c(class.name),
        doc: c(class.doc),
        kind: RT_SURFACE_CLASS,
        params: class
            .params
            .iter()
            .map(|p| {
                let (ty, default) = match p.default {
                    ParamValue::Float(f) => (RT_FLOAT, [f, 0.0, 0.0]),
                    ParamValue::Color(v) => (RT_FLOAT_VEC3, v.to_array()),
                    ParamValue::Texture(_) => (RT_TEXTURE_2D, [0.0; 3]),
                };
                ParamInfo { name: c(p.name), doc: c(p.doc), ty, default, range: p.range }
            })
            .collect(),
    });
    let lights = LIGHT_CLASSES.iter().map(|class| ClassInfo {
        name: c(class.name),
        doc: c(class.doc),
        kind: RT_LIGHT_CLASS,
        params: class
            .params
            .iter()
            .map(|p| {
                let ty = match p.set {
                    Setter::Number(_) => RT_FLOAT,
                    Setter::Triple(_) => RT_FLOAT_VEC3,
                    Setter::Texture(_) => RT_TEXTURE_2D,
                };
                ParamInfo { name: c(p.name), doc: c(p.doc), ty, default: (p.get)(&class.default), range: p.range }
            })
            .collect(),
    });
    surfaces.chain(lights).collect()
});

/// How many classes there are.
pub(crate) fn class_count() -> usize {
    CLASSES.len()
}

/// Class `index` (an error naming the count if there is none).
pub(crate) fn class(index: usize) -> Result<&'static ClassInfo, Error> {
    CLASSES.get(index).ok_or_else(|| Error::invalid_value(format!("class {index} does not exist: there are {}", CLASSES.len())))
}

/// Parameter `param` of class `index`.
pub(crate) fn param(index: usize, param: usize) -> Result<&'static ParamInfo, Error> {
    let class = class(index)?;
    class.params.get(param).ok_or_else(|| {
        Error::invalid_value(format!("{} has no parameter {param}: it has {}", class.name.to_string_lossy(), class.params.len()))
    })
}
