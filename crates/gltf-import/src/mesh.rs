//! glTF meshes as raystage meshes: every triangle primitive of a mesh in one object, each
//! triangle bound to its primitive's material, with what deforms the mesh (its skin's joints and
//! weights, its morph targets) lined up with the merged vertices.

use gltf::accessor::DataType;
use gltf::mesh::{Mode, Semantic};
use glam::{Vec2, Vec3, Vec4};
use raystage_scene::{Mesh, MorphTarget, ShaderId};

use crate::accessor::{Encoding, read_floats, read_indices, read_uints};
use crate::error::ImportError;
use crate::material::MaterialShaders;
use crate::Limits;

/// Running totals checked against the limits.
#[derive(Debug, Default)]
pub(crate) struct Budget {
    pub triangles: usize,
    pub vertices: usize,
}

impl Budget {
    pub(crate) fn take(&mut self, triangles: usize, vertices: usize, limits: &Limits) -> Result<(), ImportError> {
        self.triangles += triangles;
        self.vertices += vertices;
        if self.triangles > limits.max_triangles {
            return Err(ImportError::TooLarge { what: "triangles", count: self.triangles, limit: limits.max_triangles });
        }
        if self.vertices > limits.max_vertices {
            return Err(ImportError::TooLarge { what: "vertices", count: self.vertices, limit: limits.max_vertices });
        }
        Ok(())
    }
}

/// One primitive's vertices and triangles.
struct Primitive {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    uvs1: Option<Vec<Vec2>>,
    tangents: Option<Vec<Vec4>>,
    /// The texture coordinates its material's normal map reads, if it has one: it needs
    /// tangents for them.
    wants_tangents: Option<usize>,
    colors: Option<Vec<Vec3>>,
    triangles: Vec<[u32; 3]>,
    shader: u32,
    /// Each `JOINTS_n`/`WEIGHTS_n` set's joints and weights.
    influences: Vec<SkinSet>,
    /// Its morph targets' displacements (`None` for an attribute a target leaves alone).
    targets: Vec<[Option<Vec<Vec3>>; 3]>,
}

/// One `JOINTS_n`/`WEIGHTS_n` set of a primitive: four joints and four weights per vertex.
type SkinSet = (Vec<[u32; 4]>, Vec<[f32; 4]>);

/// What deforms a mesh, per merged vertex: the joints and weights of every skin set (four per
/// set), and the morph targets. Empty for a mesh with neither.
#[derive(Clone, Debug, Default)]
pub(crate) struct Deformation {
    /// Influences per vertex (four per set; 0 for none).
    pub per_vertex: usize,
    /// `per_vertex` joints (indices into the skin's joints) per vertex.
    pub joints: Vec<u32>,
    /// `per_vertex` weights per vertex.
    pub weights: Vec<f32>,
    /// The morph targets.
    pub targets: Vec<MorphTarget>,
}
/// How a file may store each vertex attribute: as the core specification says, or with the
/// wider choice of `KHR_mesh_quantization` where the file uses it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Encodings {
    /// Positions, and the translations and scales of `EXT_mesh_gpu_instancing`.
    pub positions: Encoding,
    directions: Encoding,
    coordinates: Encoding,
    /// Morph displacements of positions. (Those of normals and tangents are always
    /// [`Encoding::DIRECTION`]: floats or normalised signed integers, read so before the
    /// extension was, and what it allows.)
    displacements: Encoding,
}

impl Encodings {
    /// The encodings `document` may use.
    pub fn of(document: &gltf::Document) -> Encodings {
        if document.extensions_used().any(|e| e == "KHR_mesh_quantization") {
            Encodings { positions: Encoding::QUANTISED, directions: Encoding::DIRECTION, coordinates: Encoding::QUANTISED, displacements: Encoding::SIGNED }
        } else {
            Encodings { positions: Encoding::FLOAT, directions: Encoding::FLOAT, coordinates: Encoding::UNIT, displacements: Encoding::DIRECTION }
        }
    }
}

/// The mesh's triangle primitives as one mesh whose `shaders` hold local shader indices (see
/// [`MaterialShaders`]), and what deforms it; `None` if it has no triangles (only points or
/// lines).
pub(crate) fn read_mesh(
    mesh: &gltf::Mesh<'_>,
    buffers: &[Vec<u8>],
    encodings: Encodings,
    shaders: &mut MaterialShaders<'_>,
    budget: &mut Budget,
    limits: &Limits,
) -> Result<Option<(Mesh, Deformation)>, ImportError> {
    let mut parts = Vec::new();
    for primitive in mesh.primitives() {
        let field = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
        if let Some(part) = read_primitive(&primitive, buffers, encodings, shaders, budget, limits, &field)? {
            parts.push(part);
        }
    }
    let field = format!("meshes[{}].primitives", mesh.index());
    let skinned = parts.iter().filter(|p| !p.influences.is_empty()).count();
    if skinned != 0 && skinned != parts.len() {
        return Err(ImportError::invalid(field, "some primitives have JOINTS_0 and WEIGHTS_0 and some do not: a skin moves the whole mesh"));
    }
    if parts.iter().any(|p| p.targets.len() != parts[0].targets.len()) {
        return Err(ImportError::invalid(field, "the primitives have different numbers of morph targets"));
    }
    if let Some(weights) = mesh.weights().filter(|w| parts.first().is_some_and(|p| w.len() != p.targets.len())) {
        return Err(ImportError::invalid(format!("meshes[{}].weights", mesh.index()), format!("has {} weights for {} morph targets", weights.len(), parts[0].targets.len())));
    }
    Ok(merge(parts))
}

fn read_primitive(
    primitive: &gltf::Primitive<'_>,
    buffers: &[Vec<u8>],
    encodings: Encodings,
    shaders: &mut MaterialShaders<'_>,
    budget: &mut Budget,
    limits: &Limits,
    field: &str,
) -> Result<Option<Primitive>, ImportError> {
    if !matches!(primitive.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(None);
    }
    let attribute = |semantic: Semantic| primitive.get(&semantic).map(|a| (format!("{field}.attributes.{}", semantic.to_string()), a));
    let (pfield, positions) = attribute(Semantic::Positions).ok_or_else(|| ImportError::invalid(format!("{field}.attributes"), "has no POSITION"))?;
    let vertex_count = positions.count();
    let index_count = primitive.indices().map_or(vertex_count, |a| a.count());
    // Checked before reading, so a file cannot make the reader allocate past the limits.
    budget.take(index_count / 3, vertex_count, limits)?;
    let positions: Vec<Vec3> = read_floats::<3>(&positions, buffers, encodings.positions, &pfield)?.into_iter().map(Vec3::from).collect();
    let same_length = |name: &str, len: usize| {
        if len == positions.len() { Ok(()) } else { Err(ImportError::invalid(name, format!("has {len} elements, POSITION has {}", positions.len()))) }
    };
    // Every attribute has one element per vertex, of `N` numbers of the `allowed` types.
    fn vertex_attribute<const N: usize, T: From<[f32; N]>>(
        found: Option<(String, gltf::Accessor<'_>)>,
        buffers: &[Vec<u8>],
        encoding: Encoding,
        same_length: impl Fn(&str, usize) -> Result<(), ImportError>,
    ) -> Result<Option<Vec<T>>, ImportError> {
        let Some((f, a)) = found else { return Ok(None) };
        let values: Vec<T> = read_floats::<N>(&a, buffers, encoding, &f)?.into_iter().map(T::from).collect();
        same_length(&f, values.len())?;
        Ok(Some(values))
    }
    let normals = vertex_attribute::<3, Vec3>(attribute(Semantic::Normals), buffers, encodings.directions, same_length)?;
    let tangents = vertex_attribute::<4, Vec4>(attribute(Semantic::Tangents), buffers, encodings.directions, same_length)?;
    let uvs = vertex_attribute::<2, Vec2>(attribute(Semantic::TexCoords(0)), buffers, encodings.coordinates, same_length)?;
    let uvs1 = vertex_attribute::<2, Vec2>(attribute(Semantic::TexCoords(1)), buffers, encodings.coordinates, same_length)?;
    let colors = match attribute(Semantic::Colors(0)) {
        Some((f, a)) => {
            let c: Vec<Vec3> = if a.dimensions() == gltf::accessor::Dimensions::Vec4 {
                read_floats::<4>(&a, buffers, Encoding::UNIT, &f)?.into_iter().map(|[r, g, b, _]| Vec3::new(r, g, b)).collect()
            } else {
                read_floats::<3>(&a, buffers, Encoding::UNIT, &f)?.into_iter().map(Vec3::from).collect()
            };
            same_length(&f, c.len())?;
            Some(c)
        }
        None => None,
    };
    let indices = match primitive.indices() {
        Some(a) => {
            let ifield = format!("{field}.indices");
            let indices = read_indices(&a, buffers, &ifield)?;
            if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(ImportError::invalid(ifield, format!("index {bad} is past the {} vertices", positions.len())));
            }
            indices
        }
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = assemble(primitive.mode(), &indices);
    let shader = shaders.get(&primitive.material(), colors.is_some());
    // (A map on a third set or later is left out: it needs none.)
    let wants_tangents = primitive.material().normal_texture().map(|n| crate::material::normal_coordinate_set(&n)).filter(|&set| set <= 1);
    let mut influences = Vec::new();
    for set in 0.. {
        let (Some((jfield, joints)), Some((wfield, weights))) = (attribute(Semantic::Joints(set)), attribute(Semantic::Weights(set))) else {
            if attribute(Semantic::Joints(set)).is_some() != attribute(Semantic::Weights(set)).is_some() {
                return Err(ImportError::invalid(format!("{field}.attributes"), format!("has only one of JOINTS_{set} and WEIGHTS_{set}")));
            }
            break;
        };
        budget.take(0, vertex_count, limits)?;
        let joints = read_uints::<4>(&joints, buffers, &[DataType::U8, DataType::U16], &jfield)?;
        same_length(&jfield, joints.len())?;
        let weights = read_floats::<4>(&weights, buffers, Encoding::UNIT, &wfield)?;
        same_length(&wfield, weights.len())?;
        if weights.iter().flatten().any(|w| *w < 0.0) {
            return Err(ImportError::invalid(wfield, "has a negative weight"));
        }
        influences.push((joints, weights));
    }
    let mut targets = Vec::new();
    for (k, target) in primitive.morph_targets().enumerate() {
        let tfield = format!("{field}.targets[{k}]");
        let mut deltas = |accessor: Option<gltf::Accessor<'_>>, name: &str, encoding: Encoding| -> Result<Option<Vec<Vec3>>, ImportError> {
            let Some(a) = accessor else { return Ok(None) };
            let f = format!("{tfield}.{name}");
            budget.take(0, vertex_count, limits)?;
            let d: Vec<Vec3> = read_floats::<3>(&a, buffers, encoding, &f)?.into_iter().map(Vec3::from).collect();
            same_length(&f, d.len())?;
            Ok(Some(d))
        };
        targets.push([
            deltas(target.positions(), "POSITION", encodings.displacements)?,
            deltas(target.normals(), "NORMAL", Encoding::DIRECTION)?,
            deltas(target.tangents(), "TANGENT", Encoding::DIRECTION)?,
        ]);
    }
    Ok(Some(Primitive { positions, normals, uvs, uvs1, tangents, wants_tangents, colors, triangles, shader, influences, targets }))
}

/// Triangles from an index list in the primitive's mode.
fn assemble(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => indices
            .windows(3)
            .enumerate()
            // Every other triangle of a strip is flipped to keep the winding.
            .map(|(k, w)| if k % 2 == 0 { [w[0], w[1], w[2]] } else { [w[1], w[0], w[2]] })
            .collect(),
        Mode::TriangleFan if indices.len() >= 3 => indices[1..].windows(2).map(|w| [indices[0], w[0], w[1]]).collect(),
        Mode::TriangleFan => Vec::new(),
        _ => indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    }
}

/// One mesh of the primitives. Normals, each set of texture coordinates and tangents are kept
/// only if every primitive has them; vertex colours if any has them (white elsewhere). A mesh
/// with a normal-mapped primitive but without tangents for every vertex gets tangents generated
/// from its texture coordinates (MikkTSpace-style, as glTF asks). Skin sets missing from a
/// primitive that has fewer weigh nothing; a morph target's displacements of an attribute the
/// mesh keeps are zero where a primitive's target leaves it alone.
fn merge(parts: Vec<Primitive>) -> Option<(Mesh, Deformation)> {
    if parts.iter().all(|p| p.triangles.is_empty()) {
        return None;
    }
    let all_normals = parts.iter().all(|p| p.normals.is_some());
    let all_uvs = parts.iter().all(|p| p.uvs.is_some());
    let all_uvs1 = parts.iter().all(|p| p.uvs1.is_some());
    let all_tangents = parts.iter().all(|p| p.tangents.is_some());
    // One set of tangents serves the mesh: those of the first normal map's coordinates.
    let wants_tangents = parts.iter().find_map(|p| p.wants_tangents);
    let any_colors = parts.iter().any(|p| p.colors.is_some());
    let sets = parts.iter().map(|p| p.influences.len()).max().unwrap_or(0);
    let mut deformation = Deformation { per_vertex: 4 * sets, targets: vec![MorphTarget::default(); parts[0].targets.len()], ..Deformation::default() };
    let mut mesh = Mesh::default();
    for part in parts {
        let offset = mesh.positions.len() as u32;
        let n = part.positions.len();
        mesh.positions.extend(part.positions);
        mesh.indices.extend(part.triangles.iter().map(|t| t.map(|i| i + offset)));
        mesh.shaders.extend(std::iter::repeat_n(ShaderId(part.shader), part.triangles.len()));
        if all_normals {
            mesh.normals.extend(part.normals.into_iter().flatten());
        }
        if all_uvs {
            mesh.uvs.extend(part.uvs.into_iter().flatten());
        }
        if all_uvs1 {
            mesh.uvs1.extend(part.uvs1.into_iter().flatten());
        }
        if all_tangents {
            mesh.tangents.extend(part.tangents.into_iter().flatten());
        }
        if any_colors {
            mesh.colors.extend(part.colors.unwrap_or_else(|| vec![Vec3::ONE; n]));
        }
        for v in 0..n {
            for set in 0..sets {
                let (joints, weights) = part.influences.get(set).map_or(([0; 4], [0.0; 4]), |(j, w)| (j[v], w[v]));
                deformation.joints.extend(joints);
                deformation.weights.extend(weights);
            }
        }
        for (merged, deltas) in deformation.targets.iter_mut().zip(part.targets) {
            let [positions, normals, tangents] = deltas;
            for (kept, out, delta) in [(true, &mut merged.positions, positions), (all_normals, &mut merged.normals, normals), (all_tangents, &mut merged.tangents, tangents)] {
                if kept {
                    out.extend(delta.unwrap_or_else(|| vec![Vec3::ZERO; n]));
                }
            }
        }
    }
    // A target that moves nothing of an attribute keeps an empty list for it.
    for target in &mut deformation.targets {
        for list in [&mut target.positions, &mut target.normals, &mut target.tangents] {
            if list.iter().all(|d| *d == Vec3::ZERO) {
                list.clear();
            }
        }
    }
    if let Some(set) = wants_tangents.filter(|_| !all_tangents) {
        mesh.generate_tangents(set);
    }
    Some((mesh, deformation))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_their_winding() {
        assert_eq!(assemble(Mode::TriangleStrip, &[0, 1, 2, 3]), vec![[0, 1, 2], [2, 1, 3]]);
        assert_eq!(assemble(Mode::TriangleFan, &[0, 1, 2, 3]), vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(assemble(Mode::Triangles, &[0, 1, 2, 3, 4]), vec![[0, 1, 2]]);
        assert!(assemble(Mode::TriangleFan, &[0, 1]).is_empty());
    }

    fn part(vertices: usize, influences: Vec<SkinSet>, targets: Vec<[Option<Vec<Vec3>>; 3]>) -> Primitive {
        Primitive {
            positions: vec![Vec3::ZERO; vertices],
            normals: Some(vec![Vec3::Z; vertices]),
            uvs: None,
            uvs1: None,
            tangents: None,
            wants_tangents: None,
            colors: None,
            triangles: vec![[0, 1, 2]],
            shader: 0,
            influences,
            targets,
        }
    }

    #[test]
    fn every_skin_set_and_morph_target_lines_up_with_the_merged_vertices() {
        // The first primitive has two JOINTS/WEIGHTS sets, the second one: eight influences a
        // vertex, the second primitive's last four weighing nothing.
        let two_sets = vec![(vec![[1, 2, 3, 4]; 3], vec![[0.5, 0.5, 0.0, 0.0]; 3]), (vec![[5, 6, 7, 8]; 3], vec![[0.25, 0.0, 0.0, 0.0]; 3])];
        let one_set = vec![(vec![[9, 0, 0, 0]; 3], vec![[1.0, 0.0, 0.0, 0.0]; 3])];
        // A target that moves the first primitive's positions and the second's normals.
        let first = part(3, two_sets, vec![[Some(vec![Vec3::X; 3]), None, Some(vec![Vec3::Y; 3])]]);
        let second = part(3, one_set, vec![[None, Some(vec![Vec3::Y; 3]), None]]);
        let (mesh, d) = merge(vec![first, second]).unwrap();
        assert_eq!((mesh.positions.len(), d.per_vertex), (6, 8));
        assert_eq!(d.joints[..8], [1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(d.joints[24..32], [9, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(d.weights[24..32], [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let target = &d.targets[0];
        assert_eq!(target.positions, [[Vec3::X; 3], [Vec3::ZERO; 3]].concat());
        assert_eq!(target.normals, [[Vec3::ZERO; 3], [Vec3::Y; 3]].concat());
        assert!(target.tangents.is_empty(), "the merged mesh has no tangents to displace");
    }
}
