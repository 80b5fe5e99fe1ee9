//! Edits as values: every change the API makes to a scene's contents is an [`Edit`], which a
//! route builds from its request and [`apply`]s under the scene's write lock. A value rather
//! than a closure so that, in a cluster, the very same edit can go to every rank (see
//! [`crate::Workers`]) and be applied there the same way: every rank then holds the same scene
//! at the same version. Files (images, glTF) travel as the client sent them, once.

use raystage_gltf_import::Import;
use raystage_scene::{Image, Scene, SceneEdit, Texture, TextureId};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::batch;
use crate::config::Limits;
use crate::error::{Error, Result};
use crate::model::{Command, CommandResult, decode_image};
use crate::gltf::{CameraChoice, GltfAdded, add_environment, import_limits, parse_environment};

/// A change to one scene's contents.
#[derive(Serialize, Deserialize)]
pub enum Edit {
    /// Commands, of a batch (all or nothing, labels allowed) or of one resource request.
    Commands {
        /// The commands, in order.
        commands: Vec<Command>,
        /// Whether they came as a batch.
        in_batch: bool,
    },
    /// An image file as a texture: a new one, or replacing texture `texture`.
    Image {
        /// The texture replaced, if any.
        texture: Option<u32>,
        /// The file (PNG, JPEG, WebP or Radiance HDR).
        file: Blob,
        /// The file decoded, where the request decoded it already (not sent: each rank
        /// decodes its own).
        #[serde(skip)]
        decoded: Option<Image>,
    },
    /// A glTF 2.0 file added to the scene.
    Gltf {
        /// The file (`.glb`, or `.gltf` with its buffers as `data:` URIs).
        file: Blob,
        /// Which camera to see it through.
        camera: CameraChoice,
        /// A uniform environment light to add with it (`R,G,B` or one number).
        environment: Option<String>,
        /// The file imported, where the request imported it already (not sent).
        #[serde(skip)]
        import: Option<Box<Import>>,
    },
    /// Edits an application made to its own scene (the C ABI's), replayed in order (see
    /// `raystage_cluster::Mirror`).
    Journal {
        /// The edits.
        edits: Vec<SceneEdit>,
    },
}

/// What an edit gave back.
pub enum Applied {
    /// Each command's result.
    Commands(Vec<CommandResult>),
    /// The texture's id.
    Texture(u32),
    /// What a glTF file added (its `version` is left 0 for the caller to fill).
    Gltf(GltfAdded),
    /// A journal was replayed.
    Replayed,
}

/// Applies `edit` to `scene`; returns what it gave back and whether it changed anything. On
/// an error the scene may be partly changed: the caller restores it (as
/// [`crate::state::SceneSlot`] does).
pub(crate) fn apply(scene: &mut Scene, edit: Edit, limits: &Limits) -> Result<(Applied, bool)> {
    match edit {
        Edit::Commands { commands, in_batch } => {
            let results = batch::execute(scene, commands, limits, in_batch)?;
            let changed = !results.is_empty();
            Ok((Applied::Commands(results), changed))
        }
        Edit::Image { texture, file, decoded } => {
            let image = match decoded {
                Some(image) => image,
                None => decode_image(&file.0, limits)?,
            };
            let image = Texture::Image(std::sync::Arc::new(image));
            let id = match texture {
                None => scene.add_texture(image)?.0,
                Some(id) => {
                    scene.texture(TextureId(id)).map_err(|_| unknown_texture(id))?;
                    scene.set_texture(TextureId(id), image)?;
                    id
                }
            };
            Ok((Applied::Texture(id), true))
        }
        Edit::Gltf { file, camera: choice, environment, import } => {
            let import = match import {
                Some(import) => *import,
                None => raystage_gltf_import::read(&file.0, None, &import_limits(limits))?,
            };
            let environment = environment.as_deref().map(parse_environment).transpose()?;
            let was_empty = scene.instances().next().is_none();
            let unlit = import.lights().is_empty() && scene.lights().next().is_none();
            let camera = match choice {
                CameraChoice::Auto => import.camera().or_else(|| was_empty.then(|| import.framing_camera())),
                CameraChoice::File => import.camera(),
                CameraChoice::Frame => Some(import.framing_camera()),
                CameraChoice::Keep => None,
            };
            let (triangles, notes) = (import.triangles(), import.notes().to_vec());
            let mut added = import.add_to(scene)?;
            added.lights.extend(add_environment(scene, environment, unlit)?);
            if let Some(camera) = camera {
                scene.set_camera(camera)?;
            }
            let result = GltfAdded {
                shaders: added.shaders.iter().map(|s| s.0).collect(),
                objects: added.objects.iter().map(|o| o.0).collect(),
                instances: added.instances.iter().map(|i| i.0).collect(),
                lights: added.lights.iter().map(|l| l.0).collect(),
                camera_changed: camera.is_some(),
                triangles,
                notes,
                version: 0,
            };
            Ok((Applied::Gltf(result), true))
        }
        Edit::Journal { edits } => {
            let changed = !edits.is_empty();
            scene.replay(edits)?;
            Ok((Applied::Replayed, changed))
        }
    }
}

/// The error for texture `id` that a request names and the scene lacks.
pub fn unknown_texture(id: u32) -> Error {
    Error::not_found(Some("id".into()), format!("unknown texture {id}"))
}

/// Bytes that serialise as one byte string (CBOR's own type), not as a list of numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Blob(pub Vec<u8>);

impl Serialize for Blob {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_bytes(&self.0)
    }
}

impl<'de> Deserialize<'de> for Blob {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Blob, D::Error> {
        struct Bytes;
        impl serde::de::Visitor<'_> for Bytes {
            type Value = Blob;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a byte string")
            }
            fn visit_bytes<E: serde::de::Error>(self, bytes: &[u8]) -> Result<Blob, E> {
                Ok(Blob(bytes.to_vec()))
            }
            fn visit_byte_buf<E: serde::de::Error>(self, bytes: Vec<u8>) -> Result<Blob, E> {
                Ok(Blob(bytes))
            }
        }
        deserializer.deserialize_byte_buf(Bytes)
    }
}
