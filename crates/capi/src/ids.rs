//! C ids and scene ids. As OpenGL names, C ids start at 1 and 0 names nothing (so
//! `rtBindShader(0)` unbinds, and a generating call returns 0 when it fails); scene ids start at 0.

use crate::abi::enums::RT_MAX_IDS;
use crate::abi::types::{RTsizei, RTuint};
use crate::error::Error;

/// The C id of scene id `id`.
pub(crate) fn to_c(id: u32) -> RTuint {
    id + 1
}

/// The scene id of C id `id`; `None` for 0.
pub(crate) fn from_c(id: RTuint) -> Option<u32> {
    id.checked_sub(1)
}

/// Checks that `n` more ids of a kind (`what`, plural) fit beside the `already` generated ones.
pub(crate) fn check_generate(already: usize, n: RTsizei, what: &str) -> Result<u32, Error> {
    if n > RT_MAX_IDS - already.min(RT_MAX_IDS) {
        return Err(Error::out_of_memory(format!(
            "cannot generate {n} more {what}: {already} exist and a context holds at most {RT_MAX_IDS}"
        )));
    }
    Ok(n as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_names_nothing() {
        assert_eq!(from_c(0), None);
        assert_eq!(from_c(to_c(0)), Some(0));
        assert_eq!(to_c(41), 42);
    }

    #[test]
    fn generation_is_capped() {
        assert_eq!(check_generate(0, RT_MAX_IDS, "objects"), Ok(RT_MAX_IDS as u32));
        assert!(check_generate(1, RT_MAX_IDS, "objects").unwrap_err().message.contains("at most 1048576"));
        assert!(check_generate(0, usize::MAX, "shaders").is_err());
    }
}
