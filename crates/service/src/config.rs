//! What a server allows: the access token and the size limits of requests.

use std::net::SocketAddr;

/// A server's configuration.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Config {
    /// The bearer token every request must carry (`Authorization: Bearer <token>`); `None`
    /// serves anyone who can connect, which `raystage_server::serve` allows on loopback addresses only.
    pub token: Option<String>,
    /// Size limits.
    pub limits: Limits,
}

/// Size limits: a request over one is refused (413 for sizes of what was sent, 422 for what it
/// asks to be computed) before any work is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest request body in bytes (JSON, glTF uploads).
    pub max_body_bytes: usize,
    /// Most triangles in one mesh or upload.
    pub max_triangles: usize,
    /// Most vertices in one mesh or upload.
    pub max_vertices: usize,
    /// Largest image width or height.
    pub max_dimension: u32,
    /// Most samples per pixel in one frame.
    pub max_spp: u32,
    /// Most samples in one frame (width × height × samples per pixel).
    pub max_frame_samples: u64,
    /// Most commands in one batch.
    pub max_commands: usize,
    /// Most scenes held at once.
    pub max_scenes: usize,
    /// Most memory one scene's geometry, trees and images may take ([`Scene::memory_bytes`],
    /// trees counted as built): an edit, upload or demo past it is refused (413) and changes
    /// nothing.
    ///
    /// [`Scene::memory_bytes`]: raystage_scene::Scene::memory_bytes
    pub max_scene_bytes: u64,
    /// Most memory all scenes together may take, counted as `max_scene_bytes` is; default half
    /// the memory the server may use ([`usable_memory`]: the cgroup's limit where one is set,
    /// as in a container, else the machine's).
    pub max_total_scene_bytes: u64,
    /// Most bytes one image texture may take once decoded, counted from the image's header
    /// before it is decoded as width × height × 16 (three colour channels and coverage, as
    /// `f32`): a small PNG of a large, flat image would otherwise cost gigabytes.
    pub max_texture_bytes: usize,
    /// Most triangles of a demo scene built on request (`{"demo": "museum-<triangles>"}`): a
    /// 30-byte request should not build half a gigabyte of geometry.
    pub max_demo_triangles: usize,
    /// Most open streams.
    pub max_streams: usize,
    /// Most render jobs held at once, finished ones included until they are deleted or expire
    /// (each keeps its PNG). A new job past it makes room by dropping the oldest finished one;
    /// only when every job is still rendering is it refused (413).
    pub max_render_jobs: usize,
    /// Most bytes the finished render jobs' PNGs may hold together: a job whose image would pass
    /// it drops the oldest finished jobs first, and fails (413 naming the limit) if its image
    /// alone is larger.
    pub max_job_image_bytes: usize,
    /// How long a finished render job is kept for its client to fetch, in seconds from when it
    /// finished; then it is dropped with its image, as if deleted.
    pub job_expiry_seconds: u64,
    /// Renders running at once (more wait their turn); each uses every core.
    pub concurrent_renders: usize,
    /// Most memory the images being rendered may take together, frames and streams, counted
    /// from their sizes before anything is allocated (16 bytes a pixel for a frame, 34 for a
    /// stream's image): an image larger than all of it is refused (413), one that does not fit
    /// beside those in progress is 503 (a stream holds its share while it is open).
    pub max_render_bytes: usize,
    /// Longest a render may run, in seconds, once its turn has come: past it the render is
    /// stopped and the request answered 503 (a frame within the other limits can still take
    /// minutes with the path tracer, holding one of the few render turns all the while).
    pub max_render_seconds: u64,
    /// Longest a client may take to send a request's headers, in seconds; the connection is
    /// closed past it (a client that trickles its headers would otherwise hold it forever).
    pub header_read_seconds: u64,
    /// Longest a client may take to send a request's body, in seconds, from when the handler
    /// starts reading it; 408 past it, and the connection is closed.
    pub body_read_seconds: u64,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_body_bytes: 256 << 20,
            max_triangles: 4_000_000,
            max_vertices: 4_000_000,
            max_dimension: 8192,
            max_spp: 4096,
            // A 1920×1080 frame at 256 samples per pixel.
            max_frame_samples: 1920 * 1080 * 256,
            max_commands: 100_000,
            max_scenes: 64,
            max_scene_bytes: 4 << 30,
            max_total_scene_bytes: usable_memory().0 / 2,
            // 4096 × 4096 texels, or 8192 × 2048.
            max_texture_bytes: 256 << 20,
            // The standard scenes' million (the sphere grid has 1,000,002).
            max_demo_triangles: 1_000_002,
            max_streams: 32,
            max_render_jobs: 16,
            // Eight noisy 4K PNGs, or hundreds of clean full-HD ones.
            max_job_image_bytes: 512 << 20,
            job_expiry_seconds: 600,
            concurrent_renders: 4,
            // Two 8192 × 8192 frames, or one stream that size; 64 streams of 1080p.
            max_render_bytes: 2 << 30,
            max_render_seconds: 60,
            header_read_seconds: 10,
            body_read_seconds: 60,
        }
    }
}

/// Half the machine's physical memory (from `/proc/meminfo`), or 8 GiB where it cannot be read.
/// The memory this process may use, in bytes, and where the figure comes from: the cgroup's
/// limit (v2 `memory.max`, v1 `memory.limit_in_bytes`) where one is set below the machine's
/// memory, as in a container whose limit would kill the server before a budget of the machine's
/// memory refused anything; else the machine's (`MemTotal`); 16 GiB where neither can be read.
pub fn usable_memory() -> (u64, &'static str) {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    usable_memory_of(
        read("/proc/meminfo").as_deref(),
        read("/sys/fs/cgroup/memory.max").or_else(|| read("/sys/fs/cgroup/memory/memory.limit_in_bytes")).as_deref(),
    )
}

/// [`usable_memory`] from the texts of `/proc/meminfo` and of the cgroup's limit.
fn usable_memory_of(meminfo: Option<&str>, cgroup_limit: Option<&str>) -> (u64, &'static str) {
    let machine = meminfo.and_then(|info| {
        let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
        Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
    });
    // "max" (v2) or a huge number (v1, and v2 on some kernels) means no limit.
    let limit = cgroup_limit.and_then(|text| text.trim().parse::<u64>().ok());
    match (machine, limit) {
        (Some(machine), Some(limit)) if limit < machine => (limit, "the cgroup's memory limit"),
        (None, Some(limit)) if limit < 1 << 50 => (limit, "the cgroup's memory limit"),
        (Some(machine), _) => (machine, "the machine's memory"),
        (None, _) => (16 << 30, "a guess (neither the machine's memory nor a cgroup limit could be read)"),
    }
}

/// Why a server refuses to start with a configuration.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Refused {
    /// A non-loopback address without a token.
    #[error("refusing to serve on {0} without a token: anyone who can reach it could use the server (bind to 127.0.0.1, or set a token)")]
    ExposedWithoutToken(SocketAddr),
    /// A token that is empty or only whitespace: on loopback it would lock every request out
    /// (no `Authorization` header can carry it), elsewhere it would guard nothing.
    #[error("refusing an empty or blank token: set a token of visible characters, or none")]
    BlankToken,
}

impl Config {
    /// Checks that the server may listen on `addr`: loopback addresses always, any other only
    /// with a token; and that a token, if there is one, is not blank.
    pub fn check_address(&self, addr: SocketAddr) -> Result<(), Refused> {
        match self.token.as_deref() {
            Some(token) if token.trim().is_empty() => Err(Refused::BlankToken),
            None if !addr.ip().is_loopback() => Err(Refused::ExposedWithoutToken(addr)),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_memory_budget_follows_a_container_limit() {
        let meminfo = "MemTotal:       24576000 kB\nMemFree:         1000 kB\n";
        let machine = 24_576_000 * 1024;
        assert_eq!(usable_memory_of(Some(meminfo), None), (machine, "the machine's memory"));
        assert_eq!(usable_memory_of(Some(meminfo), Some("max\n")).0, machine, "no limit (v2)");
        assert_eq!(usable_memory_of(Some(meminfo), Some("9223372036854771712\n")).0, machine, "no limit (v1)");
        assert_eq!(usable_memory_of(Some(meminfo), Some("4294967296\n")), (4 << 30, "the cgroup's memory limit"));
        assert_eq!(usable_memory_of(None, Some("4294967296")).0, 4 << 30);
        assert_eq!(usable_memory_of(None, None).0, 16 << 30);
        assert_eq!(Limits::default().max_total_scene_bytes, usable_memory().0 / 2);
    }

    #[test]
    fn only_loopback_is_served_without_a_token() {
        let open = Config::default();
        assert!(open.check_address("127.0.0.1:8080".parse().unwrap()).is_ok());
        assert!(open.check_address("[::1]:8080".parse().unwrap()).is_ok());
        assert!(open.check_address("0.0.0.0:8080".parse().unwrap()).is_err());
        assert!(Config { token: Some("s3cret".into()), ..Config::default() }.check_address("0.0.0.0:80".parse().unwrap()).is_ok());
    }

    #[test]
    fn a_blank_token_is_refused_on_every_address() {
        for token in ["", " ", "\t \n"] {
            let config = Config { token: Some(token.into()), ..Config::default() };
            for addr in ["0.0.0.0:80", "127.0.0.1:8080"] {
                assert_eq!(config.check_address(addr.parse().unwrap()), Err(Refused::BlankToken), "{token:?} on {addr}");
            }
        }
    }
}
