//! What a frame cost: rays by kind, samples, and time by phase.

use raystage_scene::FrameWork;

use crate::effects::EffectSet;

/// Rays traced, by what they were for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays.
    pub primary: u64,
    /// Rays towards lights (visibility only).
    pub shadow: u64,
    /// Specular and glossy reflection rays.
    pub reflection: u64,
    /// Rays refracted into or out of transmissive surfaces.
    pub refraction: u64,
    /// Diffuse rays: path-tracing bounces and ambient-occlusion probes.
    pub diffuse: u64,
}

impl RayCounts {
    /// All rays.
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection + self.refraction + self.diffuse
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: RayCounts) {
        self.primary += o.primary;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.diffuse += o.diffuse;
    }
}

/// Seconds spent in each phase of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Placing instances and building the top level.
    pub top_level: f64,
    /// Building and refitting object trees (lazily, while tracing): the wall time during which
    /// some build ran, part of `trace_and_shade`.
    pub object_builds: f64,
    /// Tracing and shading.
    pub trace_and_shade: f64,
}

/// How a frame's work was shared out: its tasks (tiles) and what they took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TaskTimes {
    /// Tasks run (tiles, once per pass).
    pub count: u32,
    /// Seconds of the longest task.
    pub largest_seconds: f64,
    /// Seconds of all tasks, summed over threads.
    pub total_seconds: f64,
}

impl TaskTimes {
    /// One task of `seconds`.
    pub fn one(seconds: f64) -> TaskTimes {
        TaskTimes { count: 1, largest_seconds: seconds, total_seconds: seconds }
    }

    /// The longest task's share of all the work: at most `1 / threads` lets every thread of a
    /// pool be busy to the end (a frame of 1/256 or less feeds 64 threads with room to balance).
    pub fn largest_share(&self) -> f64 {
        if self.total_seconds > 0.0 { self.largest_seconds / self.total_seconds } else { 0.0 }
    }
}

impl std::ops::AddAssign for TaskTimes {
    fn add_assign(&mut self, o: TaskTimes) {
        self.count += o.count;
        self.largest_seconds = self.largest_seconds.max(o.largest_seconds);
        self.total_seconds += o.total_seconds;
    }
}

/// What a frame (or a progressive pass) cost and what it computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// The effects the frame simulated.
    pub effects: EffectSet,
    /// Whether the scene had no light of its own and the default sky lit it.
    pub default_lights: bool,
    /// Samples that came out NaN or infinite (a bug: they go into the image as black).
    pub non_finite: u64,
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Samples per pixel added by this frame.
    pub samples_per_pixel: u32,
    /// Samples per pixel accumulated so far (progressive rendering).
    pub accumulated_samples: u32,
    /// Shutter times drawn for camera rays (motion blur only).
    pub time_samples: u64,
    /// Lens positions drawn for camera rays (depth of field only).
    pub lens_samples: u64,
    /// Time by phase.
    pub phases: PhaseTimes,
    /// The tasks the frame was cut into.
    pub tasks: TaskTimes,
    /// Wall-clock seconds of the whole frame.
    pub seconds: f64,
    /// Object trees built, refitted or skipped.
    pub work: FrameWork,
}

impl FrameStats {
    /// Adds a later pass of the same frame: its rays, samples and time; the state it left
    /// (effects, tree work, samples accumulated) replaces this one's.
    pub fn merge(&mut self, pass: &FrameStats) {
        self.rays += pass.rays;
        self.time_samples += pass.time_samples;
        self.lens_samples += pass.lens_samples;
        self.non_finite += pass.non_finite;
        self.samples_per_pixel += pass.samples_per_pixel;
        self.phases.trace_and_shade += pass.phases.trace_and_shade;
        self.phases.object_builds += pass.phases.object_builds;
        self.seconds += pass.seconds;
        self.tasks += pass.tasks;
        (self.effects, self.work, self.accumulated_samples, self.default_lights) = (pass.effects, pass.work, pass.accumulated_samples, pass.default_lights);
    }

    /// What a share of a frame rendered elsewhere counts, as it travels to the process that
    /// puts the frame together: rays by kind (primary, shadow, reflection, refraction,
    /// diffuse), then non-finite samples.
    pub fn share_counts(&self) -> [u64; 6] {
        let r = self.rays;
        [r.primary, r.shadow, r.reflection, r.refraction, r.diffuse, self.non_finite]
    }

    /// Adds another share's [`FrameStats::share_counts`] to this frame's.
    pub fn add_share_counts(&mut self, counts: [u64; 6]) {
        self.rays.primary += counts[0];
        self.rays.shadow += counts[1];
        self.rays.reflection += counts[2];
        self.rays.refraction += counts[3];
        self.rays.diffuse += counts[4];
        self.non_finite += counts[5];
    }

    /// Tracing throughput in millions of rays per second, not counting lazy object builds (the
    /// wall time during which one ran: other threads may have traced meanwhile, so this errs
    /// high by at most the share of the frame spent building).
    pub fn mrays_per_second(&self) -> f64 {
        let tracing = (self.phases.trace_and_shade - self.phases.object_builds).max(self.phases.trace_and_shade * 1e-3);
        self.rays.total() as f64 / tracing / 1e6
    }
}
