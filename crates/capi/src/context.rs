//! The context: all the state of the C ABI for one thread, and the scene it records into.

use raystage_scene::{ObjectKind, Scene};

use crate::async_frames::AsyncFrames;
use crate::builder::ObjectBuilder;
use crate::error::{Error, ErrorLog};
use crate::frames::Frames;
use crate::geometry::CurrentVertex;
use crate::matrix::Matrices;
use crate::rendering::Rendering;
use crate::shaders::Shaders;
use crate::textures::Textures;

/// Everything the `rt*` calls of one thread act on (see [`crate::boundary`] for why per thread).
#[derive(Debug, Default)]
pub(crate) struct Context {
    /// The retained scene.
    pub scene: Scene,
    /// The first unread error.
    pub errors: ErrorLog,
    /// How many object ids `rtGenObjects` handed out.
    pub objects_generated: u32,
    /// The kind `rtEndObject` gives the object it commits (`rtObjectKind`).
    pub kind: ObjectKind,
    /// The object between `rtNewObject` and `rtEndObject`, with the primitive in progress.
    pub definition: Option<ObjectBuilder>,
    /// The modelview and texture stacks.
    pub matrices: Matrices,
    /// The normal, colour and texture coordinates the next vertex takes.
    pub current: CurrentVertex,
    /// Flat shading (`rtShadeModel(RT_FLAT)`) is in force.
    pub flat: bool,
    /// Shader classes, shaders, the bindings and parameter handles.
    pub shaders: Shaders,
    /// Texture ids and the bound texture.
    pub textures: Textures,
    /// The application's frame buffer and the last frame rendered.
    pub frames: Frames,
    /// How `rtSwapBuffers` renders: the render mode and parameters.
    pub rendering: Rendering,
    /// The asynchronous frames, by handle; dropping the context (`rtResetContext`, thread exit)
    /// stops and joins those in flight.
    pub async_frames: AsyncFrames,
    /// The MPI job whose ranks render this context's frames (`rtInitMPI`), if any.
    #[cfg(feature = "mpi")]
    pub cluster: Option<crate::cluster::Session>,
}

impl Context {
    /// Whether a primitive is in progress (between `rtBegin` and `rtEnd`).
    pub fn in_primitive(&self) -> bool {
        self.definition.as_ref().is_some_and(|d| d.primitive.is_some())
    }

    /// The object being defined, or an error saying `what` needs one.
    pub fn definition(&mut self, what: &str) -> Result<&mut ObjectBuilder, Error> {
        self.definition.as_mut().ok_or_else(|| {
            Error::invalid_operation(format!("{what} outside rtNewObject/rtEndObject: geometry belongs to an object"))
        })
    }

    /// Fails if an object is being defined; `what` says what cannot happen then, and why.
    pub fn outside_definition(&self, what: &str) -> Result<(), Error> {
        match &self.definition {
            Some(d) => Err(Error::invalid_operation(format!(
                "{what} while object {} is being defined (call rtEndObject first)",
                crate::ids::to_c(d.id.0)
            ))),
            None => Ok(()),
        }
    }
}
