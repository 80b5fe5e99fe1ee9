//! glTF animations and skins read into raystage-scene's animation types ([`raystage_scene::Rig`]
//! holds the arithmetic): each channel's keyframes checked and bound to its node of the default
//! scene, each skin's joints and inverse bind matrices.

use gltf::animation::{Interpolation as GltfInterpolation, Property};
use glam::Mat4;
use raystage_scene::{Channel, Clip, Interpolation, Keyframes, Skin, Target};

use crate::accessor::{Encoding, read_floats};
use crate::error::ImportError;
use crate::nodes::Placements;

/// The file's animations, each channel bound to its node (an index into
/// [`Placements::nodes`]). `morph_targets` gives each placed node's number of morph targets
/// (its mesh's), which a `weights` channel must match. What is left out is a note.
pub(crate) fn read_clips(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    placed: &Placements,
    morph_targets: &[usize],
    notes: &mut Vec<String>,
) -> Result<Vec<Clip>, ImportError> {
    let mut clips = Vec::new();
    for animation in document.animations() {
        let mut channels = Vec::new();
        for (c, channel) in animation.channels().enumerate() {
            let field = format!("animations[{}].channels[{c}]", animation.index());
            let target = channel.target();
            let Some(node) = placed.placed[target.node().index()] else {
                notes.push(format!("{field}: targets nodes[{}], which is not in the scene; left out", target.node().index()));
                continue;
            };
            let (target, width) = match target.property() {
                Property::Translation => (Target::Translation, 3),
                Property::Rotation => (Target::Rotation, 4),
                Property::Scale => (Target::Scale, 3),
                Property::MorphTargetWeights => (Target::Weights, morph_targets[node]),
            };
            if target == Target::Weights && width == 0 {
                return Err(ImportError::invalid(field, format!("moves the morph target weights of nodes[{}], whose mesh has no morph targets", placed.nodes[node].index)));
            }
            if target != Target::Weights && matches!(placed.nodes[node].local, raystage_scene::Local::Matrix(_)) {
                return Err(ImportError::invalid(field, format!("moves nodes[{}], which is given by a matrix: glTF animates only nodes given by translation, rotation and scale", placed.nodes[node].index)));
            }
            let sampler = channel.sampler();
            let sfield = format!("animations[{}].samplers[{}]", animation.index(), sampler.index());
            let times: Vec<f32> = read_floats::<1>(&sampler.input(), buffers, Encoding::FLOAT, &format!("{sfield}.input"))?.into_iter().map(|[t]| t).collect();
            let ofield = format!("{sfield}.output");
            let values: Vec<f32> = match target {
                Target::Translation | Target::Scale => read_floats::<3>(&sampler.output(), buffers, Encoding::FLOAT, &ofield)?.concat(),
                Target::Rotation => read_floats::<4>(&sampler.output(), buffers, Encoding::NORMALISED, &ofield)?.concat(),
                Target::Weights => read_floats::<1>(&sampler.output(), buffers, Encoding::NORMALISED, &ofield)?.concat(),
            };
            let interpolation = match sampler.interpolation() {
                GltfInterpolation::Step => Interpolation::Step,
                GltfInterpolation::Linear => Interpolation::Linear,
                GltfInterpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let keyframes = Keyframes::new(times, values, width, interpolation).map_err(|e| ImportError::invalid(sfield, e.to_string()))?;
            channels.push(Channel { node, target, keyframes });
        }
        clips.push(Clip { name: animation.name().unwrap_or_default().to_string(), channels });
    }
    moving_views_and_lights(placed, &clips, notes);
    Ok(clips)
}

/// Notes the camera and lights that animations move: the scene's camera and lights stay where
/// they are at rest.
fn moving_views_and_lights(placed: &Placements, clips: &[Clip], notes: &mut Vec<String>) {
    let mut moving = vec![false; placed.nodes.len()];
    for channel in clips.iter().flat_map(|c| &c.channels).filter(|c| c.target != Target::Weights) {
        moving[channel.node] = true;
    }
    for (k, node) in placed.nodes.iter().enumerate() {
        moving[k] |= node.parent.is_some_and(|p| moving[p]);
        if moving[k] && node.holds_view_or_light {
            notes.push(format!("nodes[{}]: animations move its camera or light, which stays where it is at time 0 (not supported yet)", node.index));
        }
    }
}

/// Skin `index` of the file: its joints (nodes of the default scene) and inverse bind matrices
/// (identity where the file gives none).
pub(crate) fn read_skin(document: &gltf::Document, index: usize, buffers: &[Vec<u8>], placed: &Placements) -> Result<Skin, ImportError> {
    let field = format!("skins[{index}]");
    let skin = document.skins().nth(index).ok_or_else(|| ImportError::invalid(&field, "is missing"))?;
    let joints = skin
        .joints()
        .enumerate()
        .map(|(k, j)| placed.placed[j.index()].ok_or_else(|| ImportError::invalid(format!("{field}.joints[{k}]"), format!("nodes[{}] is not in the scene", j.index()))))
        .collect::<Result<Vec<usize>, _>>()?;
    let inverse_bind = match skin.inverse_bind_matrices() {
        Some(accessor) => {
            let mfield = format!("{field}.inverseBindMatrices");
            let matrices: Vec<Mat4> = read_floats::<16>(&accessor, buffers, Encoding::FLOAT, &mfield)?.iter().map(Mat4::from_cols_array).collect();
            if matrices.len() < joints.len() {
                return Err(ImportError::invalid(mfield, format!("has {} matrices for {} joints", matrices.len(), joints.len())));
            }
            matrices[..joints.len()].to_vec()
        }
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    Ok(Skin { joints, inverse_bind })
}
