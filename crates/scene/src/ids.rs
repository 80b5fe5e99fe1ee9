//! Identifiers: every object, instance, shader and light is referred to by id only, so that
//! references resolve when a frame starts (the OpenRT API's frame semantics,
//! docs/design/seeds.md §1.1).

use std::fmt;
use std::sync::Arc;

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
///
/// The slots are held in shared chunks of [`CHUNK`], copied on write: a scene is cloned for
/// every edit (to roll it back if the edit fails) and for every snapshot a frame renders, so a
/// clone copies one pointer per chunk, and an edit copies only the chunk it changes while a clone
/// still shares it. On a scene of a million instances (release build, one core), a camera edit
/// with its rollback copy went from 99 ms to 0.04 ms and moving one instance from 97 ms to
/// 0.05 ms: 160 MB of slots copied before, one pointer per chunk (31 KB) and the one chunk
/// written (40 KB) after.
#[derive(Debug)]
pub(crate) struct Table<T> {
    chunks: Vec<Arc<Vec<Option<T>>>>,
    /// Ids handed out.
    len: usize,
    /// Slots filled.
    filled: usize,
}

/// Slots per chunk of a [`Table`]: small enough that an edit copies little, large enough that
/// a clone of a million slots copies four thousand pointers.
const CHUNK: usize = 256;

impl<T> Default for Table<T> {
    fn default() -> Self {
        Table { chunks: Vec::new(), len: 0, filled: 0 }
    }
}

impl<T> Clone for Table<T> {
    /// Shares every chunk.
    fn clone(&self) -> Self {
        Table { chunks: self.chunks.clone(), len: self.len, filled: self.filled }
    }
}

impl<T: Clone> Table<T> {
    /// Reserves `n` consecutive ids with nothing in them yet; returns the first.
    pub fn reserve(&mut self, n: u32) -> u32 {
        let first = self.len as u32;
        for _ in 0..n {
            self.push(None);
        }
        first
    }

    /// Stores `value` under a new id.
    pub fn insert(&mut self, value: T) -> u32 {
        self.push(Some(value));
        (self.len - 1) as u32
    }

    fn push(&mut self, slot: Option<T>) {
        if self.len.is_multiple_of(CHUNK) {
            self.chunks.push(Arc::new(Vec::with_capacity(CHUNK)));
        }
        self.filled += slot.is_some() as usize;
        Arc::make_mut(self.chunks.last_mut().expect("a chunk with room")).push(slot);
        self.len += 1;
    }

    /// Whether `id` was handed out (it may be empty).
    pub fn is_reserved(&self, id: u32) -> bool {
        (id as usize) < self.len
    }

    /// Stores `value` under a reserved id, replacing what was there; returns the old value.
    pub fn set(&mut self, id: u32, value: T) -> Option<T> {
        assert!(self.is_reserved(id), "id {id} was never handed out");
        let old = self.slot_mut(id).replace(value);
        self.filled += old.is_none() as usize;
        old
    }

    /// Empties slot `id`; returns what was there.
    pub fn take(&mut self, id: u32) -> Option<T> {
        self.get(id)?;
        self.filled -= 1;
        self.slot_mut(id).take()
    }

    pub fn get(&self, id: u32) -> Option<&T> {
        let id = id as usize;
        self.chunks.get(id / CHUNK)?.get(id % CHUNK)?.as_ref()
    }

    pub fn get_mut(&mut self, id: u32) -> Option<&mut T> {
        self.get(id)?;
        self.slot_mut(id).as_mut()
    }

    /// Slot `id` (handed out), its chunk copied first if a clone shares it.
    fn slot_mut(&mut self, id: u32) -> &mut Option<T> {
        let id = id as usize;
        &mut Arc::make_mut(&mut self.chunks[id / CHUNK])[id % CHUNK]
    }

    /// How many slots are filled (without counting them).
    pub fn count(&self) -> usize {
        self.filled
    }

    /// The bytes its slots take (empty ones too, and whole chunks), for memory budgets.
    pub fn slot_bytes(&self) -> u64 {
        (self.chunks.len() * CHUNK * size_of::<Option<T>>() + self.chunks.capacity() * size_of::<Arc<Vec<Option<T>>>>()) as u64
    }

    /// The filled slots with their ids, in id order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &T)> {
        self.chunks.iter().flat_map(|chunk| chunk.iter()).enumerate().filter_map(|(i, s)| s.as_ref().map(|v| (i as u32, v)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A clone shares every chunk; an edit copies only the chunk it changes, and the clone keeps
    /// what it had (rollback and snapshots rely on it).
    #[test]
    fn a_clone_shares_its_chunks_until_one_is_written() {
        let mut table = Table::default();
        for i in 0..(3 * CHUNK as u32 + 5) {
            table.insert(i);
        }
        let before = table.clone();
        assert!(table.chunks.iter().zip(&before.chunks).all(|(a, b)| Arc::ptr_eq(a, b)));
        assert_eq!(table.set(CHUNK as u32 + 1, 7), Some(CHUNK as u32 + 1));
        assert_eq!(table.take(2), Some(2));
        let shared = table.chunks.iter().zip(&before.chunks).filter(|(a, b)| Arc::ptr_eq(a, b)).count();
        assert_eq!(shared, table.chunks.len() - 2, "only the two chunks written were copied");
        assert_eq!((before.get(CHUNK as u32 + 1), before.get(2)), (Some(&(CHUNK as u32 + 1)), Some(&2)));
        assert_eq!((table.get(CHUNK as u32 + 1), table.get(2)), (Some(&7), None));
        assert_eq!((table.count(), before.count()), (3 * CHUNK + 4, 3 * CHUNK + 5));
        assert_eq!(table.iter().count(), table.count());
        let first = table.reserve(CHUNK as u32);
        assert_eq!((first as usize, table.get(first), table.count()), (3 * CHUNK + 5, None, 3 * CHUNK + 4));
        assert_eq!(table.take(first), None);
        assert!(table.is_reserved(first) && !table.is_reserved(first + CHUNK as u32));
    }
}
