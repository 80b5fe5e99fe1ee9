//! Rendering one frame on every rank of an MPI job (`mpirun -n N raystage render … --mpi`), as
//! OpenRT rendered on its cluster: every rank holds the whole scene, renders its share of the
//! frame's tiles with all its threads, and rank 0 gathers the shares into the film and
//! writes the image. The application side cannot tell one process from N: the image is the one
//! a single process renders, to the bit.
//!
//! The scene is replicated by each rank building it from the same command line (a demo, or a
//! glTF file on a file system every node sees, as clusters share their home directories).
//! Shares are a static interleave of tiles (see [`Share`]): no messages while the frame renders,
//! and interleaving spreads expensive regions over every rank.
//!
//! Faults: every step a rank can fail alone (creating the output file, reading the scene) ends
//! in a vote, so that all ranks go on or all stop with an error — never one rank waiting for a
//! message that will not come. A rank that dies makes `mpirun` end the whole job with an error.

use std::cell::RefCell;
use std::time::Instant;

use anyhow::{Result, bail};
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use raystage_render::{Film, FrameStats, Share};

use raystage_cluster::{MpiJob, MpiTransport};

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
    job: MpiJob,
    world: SimpleCommunicator,
    /// What rank 0's last gather took, kept for its timing line: [`Ranks::gather`] is shared
    /// with one-process rendering, which has nothing of this to report.
    gathered: RefCell<Option<Gathered>>,
}

/// What putting one frame together took, seen from rank 0: where a cluster frame's time goes.
#[derive(Clone, Debug, PartialEq)]
pub struct Gathered {
    /// Each rank's seconds rendering its share, by rank (rank 0's first).
    pub render_seconds: Vec<f64>,
    /// Seconds from rank 0 finishing its own share to holding every share: the transfers, and
    /// the wait for ranks slower than rank 0.
    pub seconds: f64,
    /// Bytes rank 0 received: every other rank's pixels, ray counts and timings.
    pub bytes: usize,
}

impl std::fmt::Display for Gathered {
    /// `share render s per rank A B …: min A, max B, imbalance R (max/mean); gather S s on rank 0;
    /// N bytes gathered`, the end of rank 0's timing line.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let seconds = &self.render_seconds;
        let min = seconds.iter().copied().fold(f64::INFINITY, f64::min);
        let max = seconds.iter().copied().fold(0.0, f64::max);
        let mean = seconds.iter().sum::<f64>() / seconds.len().max(1) as f64;
        let each: Vec<String> = seconds.iter().map(|s| format!("{s:.3}")).collect();
        write!(
            f,
            "share render s per rank {}: min {min:.3}, max {max:.3}, imbalance {:.3} (max/mean); gather {:.3} s on rank 0; {} bytes gathered",
            each.join(" "),
            max / mean,
            self.seconds,
            self.bytes
        )
    }
}

impl Cluster {
    /// Joins the MPI job this process was started in (a process started without `mpirun` is a
    /// job of one; see [`MpiJob::join`]).
    pub fn join() -> Result<Cluster> {
        let job = MpiJob::join().map_err(anyhow::Error::msg)?;
        let world = job.world();
        Ok(Cluster { job, world, gathered: RefCell::new(None) })
    }

    /// Ends the whole job at once, with `code` (when ranks cannot be told to stop).
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }

    /// The job as the server's transport (see [`MpiTransport`]).
    pub fn transport(&self) -> MpiTransport {
        self.job.transport()
    }

    /// This rank: 0 is the application side, which writes the image and logs.
    pub fn rank(&self) -> u32 {
        self.world.rank() as u32
    }

    /// Ranks in the job.
    pub fn size(&self) -> u32 {
        self.world.size() as u32
    }

    /// What the last frame's gather took, on rank 0 once it has gathered one; `None` elsewhere.
    pub fn gathered(&self) -> Option<Gathered> {
        self.gathered.borrow().clone()
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

    /// Puts the shares together on rank 0: every other rank sends its share's pixels of `film`
    /// (its pixels' means, as floats: the very bits rank 0 would have computed), its ray counts,
    /// its mean samples per pixel and its render seconds (kept in [`Cluster::gathered`]).
    /// Returns, on rank 0, the whole film, the statistics with every rank's rays and the mean
    /// samples per pixel over the frame; `None` on the others.
    fn gather(&self, mut film: Film, mut stats: FrameStats, mean_samples: f64) -> Result<Option<(Film, FrameStats, f64)>> {
        let start = Instant::now();
        let (w, h) = (film.width(), film.height());
        let owned_pixels = |share: Share| share.pixel_count(w, h);
        if self.rank() != 0 {
            let floats = film.share_values(self.share());
            let counts = stats.share_counts();
            let root = self.world.process_at_rank(0);
            root.send(&floats[..]);
            root.send(&counts[..]);
            root.send(&[mean_samples, stats.seconds][..]);
            return Ok(None);
        }
        let mut samples = mean_samples * owned_pixels(self.share()) as f64;
        let mut gathered = Gathered { render_seconds: vec![stats.seconds], seconds: 0.0, bytes: 0 };
        for rank in 1..self.size() {
            let share = Share { index: rank, count: self.size() };
            let source = self.world.process_at_rank(rank as i32);
            let (floats, _) = source.receive_vec::<f32>();
            let (counts, _) = source.receive_vec::<u64>();
            let (means, _) = source.receive_vec::<f64>();
            if counts.len() != 6 || means.len() != 2 || !film.set_share_values(share, &floats) {
                bail!("rank {rank} sent {} values for its share of {} pixels", floats.len(), owned_pixels(share));
            }
            gathered.bytes += std::mem::size_of_val(&floats[..]) + std::mem::size_of_val(&counts[..]) + std::mem::size_of_val(&means[..]);
            stats.add_share_counts(counts.try_into().expect("six counts, checked above"));
            samples += means[0] * owned_pixels(share) as f64;
            gathered.render_seconds.push(means[1]);
        }
        gathered.seconds = start.elapsed().as_secs_f64();
        *self.gathered.borrow_mut() = Some(gathered);
        Ok(Some((film, stats, samples / (w as f64 * h as f64))))
    }
}

