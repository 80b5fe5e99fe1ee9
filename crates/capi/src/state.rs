//! State queries (`rtGetFloatv`, `rtGetDoublev`, `rtGetIntegerv`), as OpenGL's `glGet*`: what
//! the context keeps (matrices, the current vertex attributes, the clear colour, the frame
//! buffer's extent, bindings) read back by name, so that a ported program that saves and
//! restores state, or checks it, keeps working.

use glam::Mat4;

use crate::abi::enums::{
    RT_COLOR_CLEAR_VALUE, RT_CURRENT_COLOR, RT_CURRENT_NORMAL, RT_CURRENT_TEXTURE_COORDS, RT_FLAT, RT_MATRIX_MODE, RT_MODELVIEW,
    RT_MODELVIEW_MATRIX, RT_MODELVIEW_STACK_DEPTH, RT_SHADE_MODEL, RT_SMOOTH, RT_TEXTURE, RT_SHADER_BINDING, RT_TEXTURE_BINDING_2D, RT_TEXTURE_MATRIX,
    RT_TEXTURE_STACK_DEPTH, RT_VIEWPORT,
};
use crate::abi::types::RTenum;
use crate::context::Context;
use crate::error::Error;
use crate::ids;
use crate::matrix::MatrixMode;

/// Most values one query writes (a matrix).
pub(crate) const MAX_VALUES: usize = 16;

/// The values of one query: up to [`MAX_VALUES`], in double precision so that every query type
/// converts from one source (integers and single-precision numbers are exact in it).
#[derive(Debug)]
pub(crate) struct Values {
    values: [f64; MAX_VALUES],
    len: usize,
}

impl Values {
    fn of(values: &[f64]) -> Values {
        let mut out = Values { values: [0.0; MAX_VALUES], len: values.len() };
        out.values[..values.len()].copy_from_slice(values);
        out
    }

    /// The values, in order.
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

impl Context {
    /// The values of state `pname`, or `RT_INVALID_ENUM` naming the states there are.
    pub fn state(&self, pname: RTenum) -> Result<Values, Error> {
        let floats = |v: &[f32]| Values::of(&v.iter().map(|&x| f64::from(x)).collect::<Vec<f64>>());
        let matrix = |m: glam::Affine3A| floats(&Mat4::from(m).to_cols_array());
        let current = &self.current;
        Ok(match pname {
            RT_MODELVIEW_MATRIX => matrix(self.matrices.modelview.top()),
            RT_TEXTURE_MATRIX => matrix(self.matrices.texture.top()),
            RT_MODELVIEW_STACK_DEPTH => Values::of(&[self.matrices.modelview.depth() as f64]),
            RT_TEXTURE_STACK_DEPTH => Values::of(&[self.matrices.texture.depth() as f64]),
            RT_MATRIX_MODE => Values::of(&[f64::from(match self.matrices.mode {
                MatrixMode::ModelView => RT_MODELVIEW,
                MatrixMode::Texture => RT_TEXTURE,
            })]),
            RT_CURRENT_COLOR => floats(&current.color.extend(current.alpha).to_array()),
            RT_CURRENT_NORMAL => floats(&current.normal.to_array()),
            RT_CURRENT_TEXTURE_COORDS => floats(&[current.uv.x, current.uv.y, 0.0, 1.0]),
            RT_SHADE_MODEL => Values::of(&[f64::from(if self.flat { RT_FLAT } else { RT_SMOOTH })]),
            RT_COLOR_CLEAR_VALUE => floats(&self.rendering.clear_color.unwrap_or([-1.0; 4])),
            RT_VIEWPORT => {
                let (width, height) = self.frames.target.as_ref().map_or((0, 0), |t| (t.width, t.height));
                Values::of(&[0.0, 0.0, f64::from(width), f64::from(height)])
            }
            RT_TEXTURE_BINDING_2D => Values::of(&[f64::from(self.textures.bound().map_or(0, |t| ids::to_c(t.0)))]),
            RT_SHADER_BINDING => Values::of(&[f64::from(self.shaders.bound().map_or(0, |(s, _)| ids::to_c(s.0)))]),
            _ => {
                return Err(Error::invalid_enum(format!(
                    "{pname:#x} is not a state to query (RT_MODELVIEW_MATRIX, RT_TEXTURE_MATRIX, RT_MODELVIEW_STACK_DEPTH, \
                     RT_TEXTURE_STACK_DEPTH, RT_MATRIX_MODE, RT_CURRENT_COLOR, RT_CURRENT_NORMAL, RT_CURRENT_TEXTURE_COORDS, \
                     RT_SHADE_MODEL, RT_COLOR_CLEAR_VALUE, RT_VIEWPORT, RT_TEXTURE_BINDING_2D or RT_SHADER_BINDING; the camera is \
                     not a matrix)"
                )));
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_read_back_column_major() {
        let mut ctx = Context::default();
        ctx.matrices.current().multiply(crate::matrix::translation(1.0, 2.0, 3.0).unwrap()).unwrap();
        let m = ctx.state(RT_MODELVIEW_MATRIX).unwrap();
        assert_eq!(&m.as_slice()[12..], &[1.0, 2.0, 3.0, 1.0]);
        assert_eq!(ctx.state(RT_MODELVIEW_STACK_DEPTH).unwrap().as_slice(), &[1.0]);
        assert_eq!(ctx.state(RT_COLOR_CLEAR_VALUE).unwrap().as_slice(), &[-1.0; 4]);
        assert!(ctx.state(0x1234).unwrap_err().message.contains("not a state to query"));
    }
}
