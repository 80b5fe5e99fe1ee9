//! Rendering on every rank of an MPI job, as OpenRT rendered on its cluster (libraystage built
//! with the `mpi` feature).

use crate::abi::types::RTint;
use crate::boundary::call;

/// Joins the MPI job the program was started in (`mpirun -n N program`): from then on every
/// `rtSwapBuffers` renders with all N ranks, and the image is the one one process renders. Call
/// it first, before anything is built (else `RT_INVALID_OPERATION`). On rank 0 it returns N and
/// the program goes on; on every other rank it does not return: the rank renders its share of
/// rank 0's frames until rank 0 calls `rtFinishMPI`, then the process exits (status 0). Only the
/// calling thread's frames use the ranks, and `rtRenderFrameAsync` renders on rank 0 alone.
/// Returns 0 and records `RT_INVALID_OPERATION` if this libraystage was built without MPI, if
/// MPI was joined already, or if the job cannot be joined.
#[unsafe(no_mangle)]
pub extern "C" fn rtInitMPI() -> RTint {
    call("rtInitMPI", |ctx| ctx.init_mpi())
}

/// Ends the workers of `rtInitMPI` (their processes exit) and leaves MPI; frames render in this
/// process alone afterwards. Call it before the program exits, as MPI requires of every rank.
#[unsafe(no_mangle)]
pub extern "C" fn rtFinishMPI() {
    call("rtFinishMPI", |ctx| ctx.finish_mpi())
}
