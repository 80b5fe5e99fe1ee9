//! References to resources: an id, or in a batch the label of a resource an earlier command of
//! the same batch created.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// An existing resource's id, or the `label` an earlier command of the same batch gave the
/// resource it created.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "an id (a number) or the label of a resource created earlier in the same batch (a string)")]
pub enum Ref {
    /// An id.
    Id(u32),
    /// A label.
    Label(String),
}

impl std::fmt::Display for Ref {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Ref::Id(id) => write!(f, "{id}"),
            Ref::Label(label) => write!(f, "`{label}`"),
        }
    }
}
