//! Rendering one frame on every rank of an MPI job (`mpirun -n N raystage render … --mpi`), as
//! OpenRT rendered on its cluster: every rank holds the whole scene, renders its share of the
//! frame's bands of tiles with all its threads, and rank 0 gathers the shares into the film and
//! writes the image. The application side cannot tell one process from N: the image is the one
//! a single process renders, to the bit.
//!
//! The scene is replicated by each rank building it from the same command line (a demo, or a
//! glTF file on a file system every node sees, as clusters share their home directories).
//! Shares are a static interleave of bands of tiles (see [`Share`]): no messages while the frame
//! renders, and interleaving spreads expensive regions over every rank.
//!
//! Faults: every step a rank can fail alone (creating the output file, reading the scene) ends
//! in a vote, so that all ranks go on or all stop with an error — never one rank waiting for a
//! message that will not come. A rank that dies makes `mpirun` end the whole job with an error.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{Result, bail, ensure};
use mpi::Threading;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use raystage_render::{Film, FrameStats, Share};

use crate::render::Ranks;

/// An error this rank has printed already (see [`Ranks::agree`]): the command line prints
/// nothing more for it.
#[derive(Debug)]
pub struct Reported;

impl std::fmt::Display for Reported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("reported above")
    }
}

impl std::error::Error for Reported {}

/// This process's place in the MPI job.
pub struct Cluster {
    /// Keeps MPI initialised; finalised when dropped.
    _universe: mpi::environment::Universe,
    world: SimpleCommunicator,
}

impl Cluster {
    /// Joins the MPI job this process was started in (a process started without `mpirun` is a
    /// job of one). MPI is asked to let any thread call it, one at a time: the server's
    /// requests reach the cluster from whichever thread serves them ([`MpiTransport`] takes
    /// turns).
    pub fn join() -> Result<Cluster> {
        let Some((universe, threading)) = mpi::initialize_with_threading(Threading::Serialized) else { bail!("MPI was initialised already") };
        ensure!(threading >= Threading::Serialized, "this MPI library cannot be called from several threads (it offers {threading:?}, raystage needs Serialized)");
        let world = universe.world();
        Ok(Cluster { _universe: universe, world })
    }

    /// Ends the whole job at once, with `code` (when ranks cannot be told to stop).
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }

    /// The job as the server's transport (see [`MpiTransport`]).
    pub fn transport(&self) -> MpiTransport {
        MpiTransport { world: Mutex::new(self.world.duplicate()) }
    }

    /// This rank: 0 is the application side, which writes the image and logs.
    pub fn rank(&self) -> u32 {
        self.world.rank() as u32
    }

    /// Ranks in the job.
    pub fn size(&self) -> u32 {
        self.world.size() as u32
    }

}

impl Ranks for Cluster {
    fn is_root(&self) -> bool {
        self.rank() == 0
    }

    fn share(&self) -> Share {
        Share { index: self.rank(), count: self.size() }
    }

    /// Every rank's `result`, agreed: `Ok` on every rank if it is `Ok` on all, else [`Reported`]
    /// on every rank once each has printed why it stops: its own error, or how many other ranks
    /// failed (they print their own).
    fn agree(&self, result: Result<()>) -> Result<()> {
        let failed = u32::from(result.is_err());
        let mut failures = 0u32;
        self.world.all_reduce_into(&failed, &mut failures, SystemOperation::sum());
        if failures == 0 {
            return Ok(());
        }
        // Every rank says why it stops before any rank quits: mpirun kills the rest of the job
        // as soon as one rank exits with an error, and a message printed after the barrier
        // would be lost. The failing ranks give their error, the others the count.
        let why = match &result {
            Err(e) => format!("{e:#}"),
            Ok(()) => format!("{failures} of {} MPI ranks failed (see their errors)", self.size()),
        };
        // One write, so that the line reaches mpirun whole (eprintln! writes in pieces).
        let line = format!("error: rank {}: {why}\n", self.rank());
        let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
        let _ = std::io::Write::flush(&mut std::io::stderr());
        self.world.barrier();
        Err(Reported.into())
    }

    /// Puts the shares together on rank 0: every other rank sends its share's rows of `film`
    /// (its pixels' means, as floats: the very bits rank 0 would have computed), its ray counts
    /// and its mean samples per pixel. Returns, on rank 0, the whole film, the statistics with
    /// every rank's rays and the mean samples per pixel over the frame; `None` on the others.
    fn gather(&self, film: Film, mut stats: FrameStats, mean_samples: f64) -> Result<Option<(Film, FrameStats, f64)>> {
        let (w, h) = (film.width(), film.height());
        let owned_pixels = |share: Share| share.rows(w, h).iter().map(|r| (r.end - r.start) as usize * w as usize).sum::<usize>();
        if self.rank() != 0 {
            let mut rows = Vec::with_capacity(owned_pixels(self.share()) * 3);
            for y in self.share().rows(w, h).into_iter().flatten() {
                (0..w).for_each(|x| rows.extend(film.pixel(x, y).to_array()));
            }
            let counts = stats.share_counts();
            let root = self.world.process_at_rank(0);
            root.send(&rows[..]);
            root.send(&counts[..]);
            root.send(&mean_samples);
            return Ok(None);
        }
        let mut pixels = film.pixels().to_vec();
        let mut samples = mean_samples * owned_pixels(self.share()) as f64;
        for rank in 1..self.size() {
            let share = Share { index: rank, count: self.size() };
            let source = self.world.process_at_rank(rank as i32);
            let (rows, _) = source.receive_vec::<f32>();
            let (counts, _) = source.receive_vec::<u64>();
            let (their_mean, _) = source.receive::<f64>();
            if rows.len() != owned_pixels(share) * 3 || counts.len() != 6 {
                bail!("rank {rank} sent {} values for its share of {} pixels", rows.len(), owned_pixels(share));
            }
            let mut values = rows.chunks_exact(3);
            for y in share.rows(w, h).into_iter().flatten() {
                for x in 0..w {
                    let v = values.next().expect("counted above");
                    pixels[(y * w + x) as usize] = glam::Vec3::new(v[0], v[1], v[2]);
                }
            }
            stats.add_share_counts(counts.try_into().expect("six counts, checked above"));
            samples += their_mean * owned_pixels(share) as f64;
        }
        Ok(Some((Film::from_pixels(w, h, pixels), stats, samples / (w as f64 * h as f64))))
    }
}

/// The MPI job as the messages of `raystage serve --mpi` travel (see
/// [`raystage_server::cluster`]): point-to-point messages on a communicator of their own. A
/// rank waiting for a message probes for it and sleeps in between, rather than blocking in MPI
/// (Open MPI spins while it waits, which would take a core from the rank's render threads), and
/// rank 0 can give up a worker that does not answer in time.
pub struct MpiTransport {
    /// Every MPI call is made with this lock held: MPI was initialised for calls from any
    /// thread, one at a time.
    world: Mutex<SimpleCommunicator>,
}

// SAFETY: a communicator is a handle MPI lets any thread use once initialised with
// `Threading::Serialized` (checked in `Cluster::join`), provided the calls do not overlap;
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
}

impl raystage_server::cluster::Transport for MpiTransport {
    fn rank(&self) -> u32 {
        self.world().rank() as u32
    }

    fn ranks(&self) -> u32 {
        self.world().size() as u32
    }

    /// The length first, then the bytes in pieces of at most [`PIECE`].
    fn send(&self, rank: u32, message: &[u8]) -> Result<(), String> {
        let world = self.world();
        let to = world.process_at_rank(rank as i32);
        to.send(&(message.len() as u64));
        for piece in message.chunks(PIECE) {
            to.send(piece);
        }
        Ok(())
    }

    fn receive(&self, rank: u32, deadline: Option<Instant>) -> Result<Option<Vec<u8>>, String> {
        let mut pause = Duration::from_micros(20);
        loop {
            {
                let world = self.world();
                let from = world.process_at_rank(rank as i32);
                if from.immediate_probe().is_some() {
                    // The pieces follow the length at once: receiving them blocks only while they
                    // are on their way.
                    let (length, _) = from.receive::<u64>();
                    let mut message = Vec::with_capacity(length as usize);
                    while message.len() < length as usize {
                        let (piece, _) = from.receive_vec::<u8>();
                        message.extend_from_slice(&piece);
                    }
                    return Ok(Some(message));
                }
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return Ok(None);
            }
            std::thread::sleep(pause);
            // Quick answers are caught quickly; a long wait costs a wake-up a millisecond.
            pause = (pause * 2).min(Duration::from_millis(1));
        }
    }
}
