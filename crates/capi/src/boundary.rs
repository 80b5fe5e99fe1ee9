//! The boundary between C and Rust: where the thread's context lives, where every call's
//! errors are recorded and every panic is caught, and the helpers that read C pointers.
//!
//! **One context per thread**, like a current OpenGL context: each thread that calls `rt*`
//! functions gets its own scene and state on its first call, and only sees what it built. The
//! calls need no lock, and tests (or programs) that run independent scenes on several threads do
//! not disturb each other. Rendering inside `rtSwapBuffers` is parallel on all cores regardless.

use std::cell::RefCell;
use std::ffi::{CStr, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

use crate::context::Context;
use crate::error::Error;

thread_local! {
    static CONTEXT: RefCell<Context> = RefCell::new(Context::default());
}

/// Runs `f` on this thread's context; `None` if the context is gone (the thread is exiting) or
/// already in use (no `rt*` call runs inside another).
fn with_context<R>(f: impl FnOnce(&mut Context) -> R) -> Option<R> {
    CONTEXT.try_with(|cell| cell.try_borrow_mut().ok().map(|mut ctx| f(&mut ctx))).ok().flatten()
}

/// Runs the body of C call `name` on this thread's context. The call is refused with
/// `RT_INVALID_OPERATION`, before its arguments are looked at, if a primitive is in progress
/// (between `rtBegin` and `rtEnd` only the vertex calls of [`call_in_primitive`] are allowed).
/// An error or a panic is recorded and the call returns `T::default()` (0 for ids and handles).
pub(crate) fn call<T: Default>(name: &'static str, f: impl FnOnce(&mut Context) -> Result<T, Error>) -> T {
    call_or(name, |_| T::default(), f)
}

/// Like [`call`], but a refused call returns `fallback` of its error instead of
/// `T::default()`: for calls whose result is a status, which must not read as success.
pub(crate) fn call_or<T>(name: &'static str, fallback: impl FnOnce(&Error) -> T, f: impl FnOnce(&mut Context) -> Result<T, Error>) -> T {
    run(name, fallback, |ctx| {
        if ctx.in_primitive() {
            return Err(Error::invalid_operation("not allowed between rtBegin and rtEnd"));
        }
        f(ctx)
    })
}

/// Like [`call`], for the calls that are also allowed between `rtBegin` and `rtEnd`.
pub(crate) fn call_in_primitive<T: Default>(name: &'static str, f: impl FnOnce(&mut Context) -> Result<T, Error>) -> T {
    run(name, |_| T::default(), f)
}

/// Runs a call that cannot fail and records nothing (`rtGetError`, `rtResetContext`).
pub(crate) fn query<T>(fallback: T, f: impl FnOnce(&mut Context) -> T) -> T {
    catch_unwind(AssertUnwindSafe(|| with_context(f))).ok().flatten().unwrap_or(fallback)
}

fn run<T>(name: &'static str, fallback: impl FnOnce(&Error) -> T, f: impl FnOnce(&mut Context) -> Result<T, Error>) -> T {
    let error = match catch_unwind(AssertUnwindSafe(|| with_context(f))) {
        Ok(Some(Ok(value))) => return value,
        Ok(Some(Err(error))) => error,
        Ok(None) => return fallback(&Error::internal("the context is not available")),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Error::internal(format!("{what} (please report this bug)"))
        }
    };
    let value = fallback(&error);
    with_context(|ctx| ctx.errors.record(name, error));
    value
}

/// Borrows `len` values from a C array.
///
/// # Safety
/// `ptr` must be NULL or point to `len` initialised values of `T` that stay valid and unchanged
/// for the lifetime `'a` chosen by the caller (the duration of one C call).
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], Error> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Error::invalid_value(format!("{what} is NULL")));
    }
    if !ptr.is_aligned() {
        return Err(Error::invalid_value(format!("{what} is not aligned for its element type")));
    }
    if len.checked_mul(size_of::<T>()).is_none_or(|bytes| bytes > isize::MAX as usize) {
        return Err(Error::invalid_value(format!("{what} would hold {len} elements, more than memory can")));
    }
    // SAFETY: not null, aligned, the size fits in isize; validity is the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// Reads `N` values from a C array (the `fv` calls).
///
/// # Safety
/// `ptr` must be NULL or point to `N` readable values of `T`.
pub(crate) unsafe fn array<T: Copy, const N: usize>(ptr: *const T, what: &str) -> Result<[T; N], Error> {
    // SAFETY: forwarded to the caller.
    let values = unsafe { slice(ptr, N, what)? };
    Ok(values.try_into().expect("slice of length N"))
}

/// Borrows a NUL-terminated C string.
///
/// # Safety
/// `ptr` must be NULL or point to a NUL-terminated string that stays valid during the call.
pub(crate) unsafe fn c_str<'a>(ptr: *const c_char, what: &str) -> Result<&'a CStr, Error> {
    if ptr.is_null() {
        return Err(Error::invalid_value(format!("{what} is NULL")));
    }
    // SAFETY: not null; NUL termination and validity are the caller's promise.
    Ok(unsafe { CStr::from_ptr(ptr) })
}

/// Borrows a NUL-terminated C string as UTF-8 text.
///
/// # Safety
/// As [`c_str`].
pub(crate) unsafe fn text<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, Error> {
    // SAFETY: forwarded to the caller.
    let s = unsafe { c_str(ptr, what)? };
    s.to_str().map_err(|_| Error::invalid_value(format!("{what} is not valid UTF-8")))
}

/// Writes `value` through an optional C out-pointer.
///
/// # Safety
/// `ptr` must be NULL or point to writable memory for a `T`.
pub(crate) unsafe fn write_out<T>(ptr: *mut T, value: T) {
    if !ptr.is_null() {
        // SAFETY: not null; writability is the caller's promise. `write` leaves whatever was
        // there alone (the C types written here have no destructors).
        unsafe { ptr.write_unaligned(value) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::enums::{RT_INTERNAL_ERROR, RT_INVALID_OPERATION};

    #[test]
    fn a_panic_becomes_an_internal_error() {
        query((), |ctx| *ctx = Context::default());
        let value: u32 = call("rtTest", |_| panic!("boom"));
        assert_eq!(value, 0);
        assert_eq!(query(0, |ctx| ctx.errors.take()), RT_INTERNAL_ERROR);
        let message = query(String::new(), |ctx| ctx.errors.message().to_string_lossy().into_owned());
        assert_eq!(message, "rtTest: boom (please report this bug)");
        // The context is usable afterwards.
        assert_eq!(call("rtTest", |_| Ok(7u32)), 7);
    }

    #[test]
    fn calls_inside_a_primitive_are_refused_unless_allowed() {
        query((), |ctx| {
            *ctx = Context::default();
            let mut builder = crate::builder::ObjectBuilder::new(raystage_scene::ObjectId(0));
            builder.primitive = Some(crate::builder::Primitive {
                mode: crate::assembly::PrimitiveMode::Triangles,
                shader: None,
                flat: false,
                vertices: Vec::new(),
            });
            ctx.definition = Some(builder);
        });
        assert_eq!(call("rtPushMatrix", |_| Ok(1u32)), 0);
        assert_eq!(query(0, |ctx| ctx.errors.take()), RT_INVALID_OPERATION);
        assert_eq!(call_in_primitive("rtVertex3f", |_| Ok(1u32)), 1);
        query((), |ctx| *ctx = Context::default());
    }

    #[test]
    fn pointers_are_checked_before_use() {
        // SAFETY: NULL and zero lengths are never dereferenced.
        unsafe {
            assert!(slice::<f32>(std::ptr::null(), 0, "v").unwrap().is_empty());
            assert_eq!(slice::<f32>(std::ptr::null(), 3, "v").unwrap_err().message, "v is NULL");
            let big = slice::<f32>(std::ptr::NonNull::dangling().as_ptr(), usize::MAX / 2, "v");
            assert!(big.unwrap_err().message.contains("more than memory"));
            assert_eq!(text(c"Diffuse".as_ptr(), "name"), Ok("Diffuse"));
            assert!(text(c"\xff".as_ptr(), "name").is_err());
            write_out(std::ptr::null_mut::<u32>(), 5);
        }
        let v = [1.0f32, 2.0, 3.0];
        // SAFETY: `v` holds three floats.
        assert_eq!(unsafe { array::<f32, 3>(v.as_ptr(), "v") }, Ok(v));
    }
}
