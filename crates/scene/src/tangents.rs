//! Tangent frames for normal maps: the direction of increasing u on a surface, and which way the
//! bitangent turns, after glTF 2.0 (whose normal maps put +X along increasing u and +Y up the
//! image, towards decreasing v) and MikkTSpace (per-vertex tangents from the triangles around
//! each vertex, orthogonalised against its normal).

use glam::{Vec2, Vec3, Vec4};

use crate::mesh::Mesh;

/// The tangent (direction of increasing u) and the up-the-image direction (decreasing v) of a
/// triangle with `corners` and texture coordinates `uvs`, neither normalised; `None` where the
/// texture coordinates are degenerate (a triangle of no area in texture space) or the numbers
/// are not finite.
pub(crate) fn triangle_tangents(corners: [Vec3; 3], uvs: [Vec2; 3]) -> Option<(Vec3, Vec3)> {
    let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
    let (d1, d2) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
    let det = d1.x * d2.y - d2.x * d1.y;
    let tangent = (e1 * d2.y - e2 * d1.y) / det;
    let along_v = (e2 * d1.x - e1 * d2.x) / det;
    (det != 0.0 && tangent.is_finite() && along_v.is_finite()).then_some((tangent, -along_v))
}

/// The unit tangent of `tangent` orthogonal to unit `normal` (Gram-Schmidt), with the
/// handedness that makes `w · normal × tangent` point along `up`: a zero vector where no
/// tangent can be made (a zero normal, or a tangent along it).
pub(crate) fn orthogonal_tangent(normal: Vec3, tangent: Vec3, up: Vec3) -> Vec4 {
    let Some(t) = (tangent - normal * normal.dot(tangent)).try_normalize() else { return Vec4::ZERO };
    if normal.length_squared() == 0.0 {
        return Vec4::ZERO;
    }
    let w = if normal.cross(t).dot(up) < 0.0 { -1.0 } else { 1.0 };
    t.extend(w)
}

/// Per-vertex tangents of `mesh` from its texture coordinates `set` (0: the first, 1: the
/// second), MikkTSpace-style: each
/// triangle's tangent and up direction, normalised and weighted by the triangle's angle at the
/// vertex, summed around each vertex; then orthogonalised against the vertex normal (the summed
/// face normals where the mesh has none), with the handedness of the summed up direction.
/// Vertices with no usable triangle around them get a zero tangent (shading then keeps the
/// unmapped normal). Empty for a mesh without those texture coordinates.
pub(crate) fn vertex_tangents(mesh: &Mesh, set: usize) -> Vec<Vec4> {
    let uvs = if set == 0 { &mesh.uvs } else { &mesh.uvs1 };
    if uvs.len() != mesh.positions.len() {
        return Vec::new();
    }
    let n = mesh.positions.len();
    let (mut tangents, mut ups, mut face_normals) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
    for &[a, b, c] in &mesh.indices {
        let index = [a, b, c].map(|i| i as usize);
        let corners = index.map(|i| mesh.positions[i]);
        let face = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let Some((tangent, up)) = triangle_tangents(corners, index.map(|i| uvs[i])) else { continue };
        let (Some(tangent), Some(up)) = (tangent.try_normalize(), up.try_normalize()) else { continue };
        for k in 0..3 {
            let (to_next, to_prev) = (corners[(k + 1) % 3] - corners[k], corners[(k + 2) % 3] - corners[k]);
            let angle = to_next.angle_between(to_prev);
            if !angle.is_finite() {
                continue;
            }
            tangents[index[k]] += tangent * angle;
            ups[index[k]] += up * angle;
            face_normals[index[k]] += face;
        }
    }
    (0..n)
        .map(|v| {
            let normal = mesh.normals.get(v).copied().unwrap_or(face_normals[v]).normalize_or_zero();
            orthogonal_tangent(normal, tangents[v], ups[v])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad facing +z whose texture is upright: u to the right, v down.
    fn upright_quad() -> Mesh {
        let mut mesh = Mesh::new(vec![Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)], vec![[0, 1, 2], [0, 2, 3]]);
        mesh.uvs = vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X];
        mesh
    }

    #[test]
    fn an_upright_texture_has_tangent_along_x_and_right_handed_bitangent_up() {
        let tangents = vertex_tangents(&upright_quad(), 0);
        assert_eq!(tangents, vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);
        // The image mirrored left to right: u runs along −x, and the frame turns left-handed.
        let mut mirrored = upright_quad();
        mirrored.uvs.iter_mut().for_each(|uv| uv.x = 1.0 - uv.x);
        assert_eq!(vertex_tangents(&mirrored, 0), vec![Vec4::new(-1.0, 0.0, 0.0, -1.0); 4]);
    }

    #[test]
    fn the_second_texture_coordinates_give_their_own_tangents() {
        // The second set runs up the quad: u along +y.
        let mut mesh = upright_quad();
        mesh.uvs1 = mesh.positions.iter().map(|p| Vec2::new(p.y, p.x)).collect();
        assert!(vertex_tangents(&mesh, 1).iter().all(|t| t.truncate() == Vec3::Y), "{:?}", vertex_tangents(&mesh, 1));
    }

    #[test]
    fn vertex_normals_orthogonalise_the_tangents() {
        let mut mesh = upright_quad();
        mesh.normals = vec![Vec3::new(1.0, 0.0, 1.0).normalize(); 4];
        for t in vertex_tangents(&mesh, 0) {
            assert!(t.truncate().dot(mesh.normals[0]).abs() < 1e-6 && (t.truncate().length() - 1.0).abs() < 1e-6, "{t}");
        }
    }

    #[test]
    fn degenerate_texture_coordinates_and_normals_give_zero_tangents_not_nans() {
        let mut flat = upright_quad();
        flat.uvs = vec![Vec2::splat(0.5); 4];
        assert_eq!(vertex_tangents(&flat, 0), vec![Vec4::ZERO; 4]);
        let mut zero_normals = upright_quad();
        zero_normals.normals = vec![Vec3::ZERO; 4];
        assert_eq!(vertex_tangents(&zero_normals, 0), vec![Vec4::ZERO; 4]);
        let mut along_normal = upright_quad();
        along_normal.normals = vec![Vec3::X; 4];
        assert_eq!(vertex_tangents(&along_normal, 0), vec![Vec4::ZERO; 4]);
        assert!(vertex_tangents(&Mesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]), 0).is_empty(), "no texture coordinates");
        assert!(vertex_tangents(&upright_quad(), 1).is_empty(), "no second texture coordinates");
    }
}
