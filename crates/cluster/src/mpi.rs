//! MPI as the cluster's transport (the `mpi` feature: rsmpi needs an MPI installation and
//! libclang to build): joining the job, and messages between its ranks.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use mpi::Threading;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::datatype::Buffer;
use mpi::request::StaticScope;
use mpi::traits::*;

use crate::Transport;

/// This process's place in the MPI job it was started in: MPI stays initialised while it
/// lives, and is finalised when it is dropped.
pub struct MpiJob {
    universe: Universe,
}

// SAFETY: MPI was initialised with `Threading::Serialized` (checked in `MpiJob::join`): any
// thread may use it, one at a time. The job is only finalised (dropped) or asked for its world
// communicator; callers serialise their calls (the C ABI holds its context's lock throughout).
unsafe impl Send for MpiJob {}

impl MpiJob {
    /// Joins the MPI job this process was started in (a process started without `mpirun` is a
    /// job of one). MPI is asked to let any thread call it, one at a time: a server's requests
    /// reach the cluster from whichever thread serves them ([`MpiTransport`] takes turns).
    pub fn join() -> Result<MpiJob, String> {
        let Some((universe, threading)) = mpi::initialize_with_threading(Threading::Serialized) else {
            return Err("MPI was initialised already".into());
        };
        if threading < Threading::Serialized {
            return Err(format!("this MPI library cannot be called from several threads (it offers {threading:?}, raystage needs Serialized)"));
        }
        Ok(MpiJob { universe })
    }

    /// The job's communicator of all ranks.
    pub fn world(&self) -> SimpleCommunicator {
        self.universe.world()
    }

    /// The job as the cluster's transport, on a communicator of its own.
    pub fn transport(&self) -> MpiTransport {
        MpiTransport { world: Mutex::new(self.world().duplicate()) }
    }
}

/// The MPI job as the messages of `raystage serve --mpi` travel (see
/// [`crate`]): point-to-point messages on a communicator of their own. A
/// rank waiting for a message probes for it and sleeps in between, rather than blocking in MPI
/// (Open MPI spins while it waits, which would take a core from the rank's render threads), and
/// rank 0 can give up a worker that does not answer in time.
pub struct MpiTransport {
    /// Every MPI call is made with this lock held: MPI was initialised for calls from any
    /// thread, one at a time ([`MpiJob::join`]).
    world: Mutex<SimpleCommunicator>,
}

// SAFETY: a communicator is a handle MPI lets any thread use once initialised with
// `Threading::Serialized` (checked in [`MpiJob::join`]), provided the calls do not overlap;
// every use goes through the mutex.
unsafe impl Send for MpiTransport {}
// SAFETY: as above: shared use is serialised by the mutex.
unsafe impl Sync for MpiTransport {}

/// Bytes in one MPI message at most: MPI counts elements in an `int`, so a larger message
/// (a big frame's share of floats) goes in pieces.
const PIECE: usize = 1 << 30;

impl MpiTransport {
    fn world(&self) -> std::sync::MutexGuard<'_, SimpleCommunicator> {
        self.world.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Sends `buffer` to `rank` without blocking, then waits for MPI to be done with it until
    /// `deadline`; whether it was. The buffer is the message's copy: a send still pending at the
    /// deadline is abandoned, and MPI may still read its buffer, which is then leaked rather
    /// than freed (once per worker given up: the message that found it stopped, a pass's few
    /// hundred bytes or an edit's).
    fn send_until<B: Buffer + ?Sized + 'static>(&self, rank: u32, buffer: Box<B>, deadline: Instant) -> bool {
        let buffer: &'static B = Box::leak(buffer);
        let mut pending = Some(self.world().process_at_rank(rank as i32).immediate_send(StaticScope, buffer));
        let sent = poll_until(Some(deadline), || {
            let _world = self.world();
            match pending.take().expect("a send is pending until it completes").test() {
                Ok(_) => Some(()),
                Err(request) => {
                    pending = Some(request);
                    None
                }
            }
        });
        match pending {
            None => {
                // SAFETY: the buffer came from `Box::leak` above, and MPI, done with the
                // send, holds no reference to it any more: nothing else does.
                drop(unsafe { Box::from_raw(std::ptr::from_ref(buffer).cast_mut()) });
            }
            Some(request) => {
                // SAFETY: the request is abandoned, never completed; its buffer is leaked
                // above, so it outlives anything MPI may still do with it.
                let _ = unsafe { request.into_raw() };
            }
        }
        sent.is_some()
    }
}

/// Calls `poll` until it gives a value or `deadline` passes (`None`: never), sleeping in
/// between (see [`MpiTransport`] for why not in MPI): 20 µs at first, doubling up to a
/// millisecond, so quick answers are caught quickly and a long wait costs a wake-up a
/// millisecond.
fn poll_until<T>(deadline: Option<Instant>, mut poll: impl FnMut() -> Option<T>) -> Option<T> {
    let mut pause = Duration::from_micros(20);
    loop {
        if let Some(value) = poll() {
            return Some(value);
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(1));
    }
}

impl Transport for MpiTransport {
    fn rank(&self) -> u32 {
        self.world().rank() as u32
    }

    fn ranks(&self) -> u32 {
        self.world().size() as u32
    }

    /// The length first, then the bytes in pieces of at most [`PIECE`]. With a deadline each
    /// part is sent without blocking and waited for ([`poll_until`]): a blocking send to a rank
    /// that stopped (alive, receiving nothing) may never return once MPI's buffers towards it
    /// are full. Without one, blocking sends (a worker's replies, which rank 0 always takes).
    fn send(&self, rank: u32, message: &[u8], deadline: Option<Instant>) -> Result<bool, String> {
        let Some(deadline) = deadline else {
            let world = self.world();
            let to = world.process_at_rank(rank as i32);
            to.send(&(message.len() as u64));
            for piece in message.chunks(PIECE) {
                to.send(piece);
            }
            return Ok(true);
        };
        Ok(self.send_until(rank, Box::new(message.len() as u64), deadline)
            && message.chunks(PIECE).all(|piece| self.send_until(rank, Box::<[u8]>::from(piece), deadline)))
    }

    fn receive(&self, rank: u32, deadline: Option<Instant>) -> Result<Option<Vec<u8>>, String> {
        Ok(poll_until(deadline, || {
            let world = self.world();
            let from = world.process_at_rank(rank as i32);
            from.immediate_probe()?;
            // The pieces follow the length at once: receiving them blocks only while they are
            // on their way.
            let (length, _) = from.receive::<u64>();
            let mut message = Vec::with_capacity(length as usize);
            while message.len() < length as usize {
                let (piece, _) = from.receive_vec::<u8>();
                message.extend_from_slice(&piece);
            }
            Some(message)
        }))
    }
}
