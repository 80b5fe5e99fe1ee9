//! Primitive assembly: how the vertices issued between `rtBegin` and `rtEnd` become triangles,
//! with OpenGL's rules (orientation of strips, leftover vertices ignored, provoking vertex for
//! flat shading, OpenGL 2.1 §2.6.1 and table 2.12).

use crate::abi::enums::{RT_POLYGON, RT_QUAD_STRIP, RT_QUADS, RT_TRIANGLE_FAN, RT_TRIANGLE_STRIP, RT_TRIANGLES};
use crate::abi::types::RTenum;
use crate::error::Error;

/// A primitive mode of `rtBegin`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PrimitiveMode {
    Triangles,
    TriangleStrip,
    TriangleFan,
    Quads,
    QuadStrip,
    /// Convex, fanned around its first vertex.
    Polygon,
}

impl PrimitiveMode {
    /// The mode named by an `RT_*` constant.
    pub fn from_enum(mode: RTenum) -> Result<PrimitiveMode, Error> {
        Ok(match mode {
            RT_TRIANGLES => PrimitiveMode::Triangles,
            RT_TRIANGLE_STRIP => PrimitiveMode::TriangleStrip,
            RT_TRIANGLE_FAN => PrimitiveMode::TriangleFan,
            RT_QUADS => PrimitiveMode::Quads,
            RT_QUAD_STRIP => PrimitiveMode::QuadStrip,
            RT_POLYGON => PrimitiveMode::Polygon,
            _ => {
                return Err(Error::invalid_enum(format!(
                    "{mode:#x} is not a primitive mode (points and lines are not supported by a ray tracer)"
                )));
            }
        })
    }
}

/// One assembled triangle: three vertex indices (counter-clockwise when the primitive was) and
/// the vertex whose normal and colour the whole triangle takes under flat shading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Assembled {
    pub corners: [usize; 3],
    pub provoking: usize,
}

/// The triangles that `n` vertices make in `mode`.
pub(crate) fn assemble(mode: PrimitiveMode, n: usize) -> Vec<Assembled> {
    let tri = |a, b, c, provoking| Assembled { corners: [a, b, c], provoking };
    match mode {
        PrimitiveMode::Triangles => (0..n / 3).map(|i| tri(3 * i, 3 * i + 1, 3 * i + 2, 3 * i + 2)).collect(),
        // Every other triangle of a strip swaps its first two vertices to keep the orientation.
        PrimitiveMode::TriangleStrip => (2..n)
            .map(|i| if i % 2 == 0 { tri(i - 2, i - 1, i, i) } else { tri(i - 1, i - 2, i, i) })
            .collect(),
        PrimitiveMode::TriangleFan => (2..n).map(|i| tri(0, i - 1, i, i)).collect(),
        PrimitiveMode::Polygon => (2..n).map(|i| tri(0, i - 1, i, 0)).collect(),
        PrimitiveMode::Quads => (0..n / 4)
            .flat_map(|q| {
                let [a, b, c, d] = [4 * q, 4 * q + 1, 4 * q + 2, 4 * q + 3];
                [tri(a, b, c, d), tri(a, c, d, d)]
            })
            .collect(),
        // Quad i of a strip has the vertices 2i, 2i+1, 2i+3, 2i+2 in order around it.
        PrimitiveMode::QuadStrip => (0..(n / 2).saturating_sub(1))
            .flat_map(|q| {
                let [a, b, c, d] = [2 * q, 2 * q + 1, 2 * q + 3, 2 * q + 2];
                [tri(a, b, c, c), tri(a, c, d, c)]
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corners(mode: PrimitiveMode, n: usize) -> Vec<[usize; 3]> {
        assemble(mode, n).iter().map(|t| t.corners).collect()
    }

    #[test]
    fn triangles_ignore_leftover_vertices() {
        assert_eq!(corners(PrimitiveMode::Triangles, 7), [[0, 1, 2], [3, 4, 5]]);
        assert!(corners(PrimitiveMode::Triangles, 2).is_empty());
    }

    #[test]
    fn strips_keep_their_orientation() {
        assert_eq!(corners(PrimitiveMode::TriangleStrip, 5), [[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
    }

    #[test]
    fn fans_and_polygons_share_the_first_vertex() {
        assert_eq!(corners(PrimitiveMode::TriangleFan, 5), [[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        assert_eq!(corners(PrimitiveMode::Polygon, 4), [[0, 1, 2], [0, 2, 3]]);
        assert!(assemble(PrimitiveMode::Polygon, 4).iter().all(|t| t.provoking == 0));
        assert!(corners(PrimitiveMode::Polygon, 2).is_empty());
    }

    #[test]
    fn quads_become_two_triangles() {
        assert_eq!(corners(PrimitiveMode::Quads, 9), [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]);
        assert_eq!(corners(PrimitiveMode::QuadStrip, 7), [[0, 1, 3], [0, 3, 2], [2, 3, 5], [2, 5, 4]]);
        assert!(corners(PrimitiveMode::QuadStrip, 3).is_empty());
    }

    #[test]
    fn the_provoking_vertex_is_the_last_of_each_primitive() {
        let strip: Vec<usize> = assemble(PrimitiveMode::TriangleStrip, 5).iter().map(|t| t.provoking).collect();
        assert_eq!(strip, [2, 3, 4]);
        let quads: Vec<usize> = assemble(PrimitiveMode::QuadStrip, 6).iter().map(|t| t.provoking).collect();
        assert_eq!(quads, [3, 3, 5, 5]);
    }

    #[test]
    fn every_mode_is_named_by_its_constant() {
        assert_eq!(PrimitiveMode::from_enum(RT_QUAD_STRIP), Ok(PrimitiveMode::QuadStrip));
        assert!(PrimitiveMode::from_enum(0x0000).unwrap_err().message.contains("not a primitive mode"));
    }
}
