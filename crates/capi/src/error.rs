//! Errors of the C ABI: a code and a message, recorded OpenGL-style. The first error since the
//! last `rtGetError` sticks; later ones are dropped until it is read (like `glGetError`), so an
//! application can check once after many calls and still learn what went wrong first.

use std::ffi::{CStr, CString};

use raystage_scene::SceneError;

use crate::abi::enums::{
    RT_INTERNAL_ERROR, RT_INVALID_ENUM, RT_INVALID_OPERATION, RT_INVALID_VALUE, RT_IO_ERROR, RT_NO_ERROR,
    RT_OUT_OF_MEMORY, RT_STACK_OVERFLOW, RT_STACK_UNDERFLOW,
};
use crate::abi::types::RTenum;
use crate::ids;

/// A refused call: an `RT_*` error code and a message naming the problem.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Error {
    pub code: RTenum,
    pub message: String,
}

impl Error {
    /// Every code an error carries: those the constructors below give.
    pub const CODES: [RTenum; 8] =
        [RT_INVALID_ENUM, RT_INVALID_VALUE, RT_INVALID_OPERATION, RT_STACK_OVERFLOW, RT_STACK_UNDERFLOW, RT_OUT_OF_MEMORY, RT_IO_ERROR, RT_INTERNAL_ERROR];

    fn new(code: RTenum, message: impl Into<String>) -> Error {
        Error { code, message: message.into() }
    }

    /// `RT_INVALID_ENUM`.
    pub fn invalid_enum(message: impl Into<String>) -> Error {
        Error::new(RT_INVALID_ENUM, message)
    }

    /// `RT_INVALID_VALUE`.
    pub fn invalid_value(message: impl Into<String>) -> Error {
        Error::new(RT_INVALID_VALUE, message)
    }

    /// `RT_INVALID_OPERATION`.
    pub fn invalid_operation(message: impl Into<String>) -> Error {
        Error::new(RT_INVALID_OPERATION, message)
    }

    /// `RT_STACK_OVERFLOW`.
    pub fn stack_overflow(message: impl Into<String>) -> Error {
        Error::new(RT_STACK_OVERFLOW, message)
    }

    /// `RT_STACK_UNDERFLOW`.
    pub fn stack_underflow(message: impl Into<String>) -> Error {
        Error::new(RT_STACK_UNDERFLOW, message)
    }

    /// `RT_OUT_OF_MEMORY`.
    pub fn out_of_memory(message: impl Into<String>) -> Error {
        Error::new(RT_OUT_OF_MEMORY, message)
    }

    /// `RT_IO_ERROR`.
    pub fn io(message: impl Into<String>) -> Error {
        Error::new(RT_IO_ERROR, message)
    }

    /// `RT_INTERNAL_ERROR`.
    pub fn internal(message: impl Into<String>) -> Error {
        Error::new(RT_INTERNAL_ERROR, message)
    }
}

/// Checks that every number is finite; `what` names the argument in the message.
pub(crate) fn finite(what: &str, values: &[f32]) -> Result<(), Error> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) if values.len() == 1 => Err(Error::invalid_value(format!("{what} is {}", values[i]))),
        Some(i) => Err(Error::invalid_value(format!("{what}[{i}] is {}", values[i]))),
        None => Ok(()),
    }
}

/// Checks that every value of `values` (named `what`, as [`finite`] names them) is a coordinate
/// within [`RT_MAX_COORDINATE`](crate::abi::enums::RT_MAX_COORDINATE): the camera's points and
/// planes are bound as vertices are, so that a ray's origin and distance stay within single
/// precision's range wherever it meets the scene.
pub(crate) fn coordinates(what: &str, values: &[f32]) -> Result<(), Error> {
    use crate::abi::enums::RT_MAX_COORDINATE;
    finite(what, values)?;
    match values.iter().position(|v| v.abs() > RT_MAX_COORDINATE) {
        Some(i) => {
            let at = if values.len() == 1 { String::new() } else { format!("[{i}]") };
            Err(Error::invalid_value(format!("{what}{at} is {:e}, beyond RT_MAX_COORDINATE ({RT_MAX_COORDINATE:e})", values[i])))
        }
        None => Ok(()),
    }
}

/// Converts the arguments of a double-precision call to the single precision raystage computes
/// in, checking each is finite and within single precision's range (so none becomes infinite);
/// `what` names them in the message as [`finite`] does.
pub(crate) fn single<const N: usize>(what: &str, values: [f64; N]) -> Result<[f32; N], Error> {
    let narrowed = values.map(|v| v as f32);
    match values.iter().zip(&narrowed).position(|(v, n)| v.is_finite() != n.is_finite()) {
        Some(i) if N == 1 => Err(Error::invalid_value(format!("{what} is {:e}, beyond single precision", values[i]))),
        Some(i) => Err(Error::invalid_value(format!("{what}[{i}] is {:e}, beyond single precision", values[i]))),
        None => {
            finite(what, &narrowed)?;
            Ok(narrowed)
        }
    }
}

/// The one place scene errors become C ABI errors. Ids in messages are the C ids.
impl From<SceneError> for Error {
    fn from(e: SceneError) -> Error {
        match e {
            SceneError::UnknownObject(id) => Error::invalid_value(format!("object {} is not defined", ids::to_c(id.0))),
            SceneError::UnknownInstance(id) => Error::invalid_value(format!("instance {} does not exist", ids::to_c(id.0))),
            SceneError::UnknownShader(id) => Error::invalid_value(format!("shader {} is not defined", ids::to_c(id.0))),
            SceneError::UnknownTexture(id) => Error::invalid_value(format!(
                "texture {} has no image: give it one with rtTexImage2D, rtTexImageFile, rtTexChecker or rtTexNoise",
                ids::to_c(id.0)
            )),
            SceneError::UnknownLight(_) => Error::internal(format!("{e}: a light shader lost its light")),
            SceneError::EmptyMesh | SceneError::WrongParameterType { .. } => Error::invalid_operation(e.to_string()),
            // Every other refusal names a value out of range: an unknown name, a bad index, a
            // length, a number.
            _ => Error::invalid_value(e.to_string()),
        }
    }
}

/// An error as recorded: its code and its message, ready for C.
#[derive(Debug)]
struct Recorded {
    code: RTenum,
    message: CString,
}

/// The error state of a context.
#[derive(Debug, Default)]
pub(crate) struct ErrorLog {
    /// The first error not yet read by `rtGetError`.
    pending: Option<Recorded>,
    /// The error the last `rtGetError` returned.
    last_read: Option<Recorded>,
}

impl ErrorLog {
    /// Records that call `call` failed with `error`, unless an earlier error is still unread.
    pub fn record(&mut self, call: &str, error: Error) {
        if self.pending.is_none() {
            let text = format!("{call}: {}", error.message).replace('\0', "\u{FFFD}");
            let message = CString::new(text).expect("NUL bytes were replaced");
            self.pending = Some(Recorded { code: error.code, message });
        }
    }

    /// Returns the pending error's code (`RT_NO_ERROR` if none) and clears it (`rtGetError`).
    pub fn take(&mut self) -> RTenum {
        self.last_read = self.pending.take();
        self.last_read.as_ref().map_or(RT_NO_ERROR, |r| r.code)
    }

    /// The message of the pending error, else of the error the last `rtGetError` returned.
    pub fn message(&self) -> &CStr {
        match self.pending.as_ref().or(self.last_read.as_ref()) {
            Some(r) => &r.message,
            None => c"no error",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_error_sticks_until_read() {
        let mut log = ErrorLog::default();
        assert_eq!(log.message(), c"no error");
        log.record("rtBegin", Error::invalid_enum("0x1234 is not a primitive mode"));
        log.record("rtEnd", Error::invalid_operation("rtEnd without rtBegin"));
        assert_eq!(log.message(), c"rtBegin: 0x1234 is not a primitive mode");
        assert_eq!(log.take(), RT_INVALID_ENUM);
        assert_eq!(log.message(), c"rtBegin: 0x1234 is not a primitive mode", "the message of the error just read");
        assert_eq!(log.take(), RT_NO_ERROR);
        assert_eq!(log.message(), c"no error");
    }

    #[test]
    fn nul_bytes_in_messages_are_replaced() {
        let mut log = ErrorLog::default();
        log.record("rtWritePNG", Error::io("bad\0path"));
        assert_eq!(log.message().to_str().unwrap(), "rtWritePNG: bad\u{FFFD}path");
    }

    #[test]
    fn finite_names_the_entry() {
        assert_eq!(finite("v", &[1.0, f32::NAN, 2.0]).unwrap_err().message, "v[1] is NaN");
        assert_eq!(finite("angle", &[f32::INFINITY]).unwrap_err().message, "angle is inf");
        assert!(finite("v", &[0.0, -1e30]).is_ok());
    }

    #[test]
    fn single_refuses_what_single_precision_cannot_hold() {
        assert_eq!(single("(x, y)", [1.5, -2.0]), Ok([1.5, -2.0]));
        assert_eq!(single("(x, y)", [1.0, 1e300]).unwrap_err().message, "(x, y)[1] is 1e300, beyond single precision");
        assert_eq!(single("angle", [f64::NAN]).unwrap_err().message, "angle is NaN");
        assert_eq!(single("angle", [1e-300]), Ok([0.0]), "tiny values round to zero, as OpenGL's do");
    }
}
