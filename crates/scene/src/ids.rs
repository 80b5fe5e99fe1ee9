//! Identifiers: every object, instance, shader and light is referred to by id only, so that
//! references resolve when a frame starts (the OpenRT API's frame semantics,
//! docs/design/seeds.md §1.1).

use std::fmt;

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident, $what:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
        pub struct $name(pub u32);

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($what, " {}"), self.0)
            }
        }
    };
}

id_type!(
    /// An object: geometry with its own acceleration structure.
    ObjectId,
    "object"
);
id_type!(
    /// An instance: an object placed in the world by a transform.
    InstanceId,
    "instance"
);
id_type!(
    /// A surface shader: a shader class with parameter values.
    ShaderId,
    "shader"
);
id_type!(
    /// A light source.
    LightId,
    "light"
);
id_type!(
    /// A texture.
    TextureId,
    "texture"
);

/// A table of records indexed by id. Ids are handed out in increasing order and never reused, so
/// an id that outlived its record can never name another one by accident.
#[derive(Clone, Debug)]
pub(crate) struct Table<T> {
    slots: Vec<Option<T>>,
}

impl<T> Default for Table<T> {
    fn default() -> Self {
        Table { slots: Vec::new() }
    }
}

impl<T> Table<T> {
    /// Reserves `n` consecutive ids with nothing in them yet; returns the first.
    pub fn reserve(&mut self, n: u32) -> u32 {
        let first = self.slots.len() as u32;
        self.slots.resize_with(self.slots.len() + n as usize, || None);
        first
    }

    /// Stores `value` under a new id.
    pub fn insert(&mut self, value: T) -> u32 {
        self.slots.push(Some(value));
        (self.slots.len() - 1) as u32
    }

    /// Whether `id` was handed out (it may be empty).
    pub fn is_reserved(&self, id: u32) -> bool {
        (id as usize) < self.slots.len()
    }

    /// Stores `value` under a reserved id, replacing what was there; returns the old value.
    pub fn set(&mut self, id: u32, value: T) -> Option<T> {
        self.slots[id as usize].replace(value)
    }

    /// Empties slot `id`; returns what was there.
    pub fn take(&mut self, id: u32) -> Option<T> {
        self.slots.get_mut(id as usize).and_then(Option::take)
    }

    pub fn get(&self, id: u32) -> Option<&T> {
        self.slots.get(id as usize).and_then(Option::as_ref)
    }

    pub fn get_mut(&mut self, id: u32) -> Option<&mut T> {
        self.slots.get_mut(id as usize).and_then(Option::as_mut)
    }

    /// The bytes its slots take (empty ones too), for memory budgets.
    pub fn slot_bytes(&self) -> u64 {
        (self.slots.capacity() * size_of::<Option<T>>()) as u64
    }

    /// The filled slots with their ids, in id order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &T)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| s.as_ref().map(|v| (i as u32, v)))
    }
}
