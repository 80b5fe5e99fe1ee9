//! A model of one frame on a cluster: what `raystage render --mpi` would take on N
//! nodes, from a cost per pixel measured on this machine and a network's bandwidth and latency.
//!
//! Each node renders 1/N of the frame with all its cores, at the measured per-core rate (the
//! frame's core-seconds per pixel, as if threads scaled perfectly: the thread scaling is measured
//! apart, by `raystage-bench scaling`). Then every other node sends its share to node 0 over
//! node 0's one link: the transfers are serialised there, each paying the link's latency once, so
//! the gather takes `(N-1)/N × frame bytes / bandwidth + (N-1) × latency`. Overlapped, nodes send
//! finished tiles while later ones render, so the frame ends at the later of the render and the
//! gather, plus one latency (the last tiles' own transfer is left out: a few tiles of a frame).

use serde::Serialize;

/// A network link into node 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Link {
    pub name: &'static str,
    /// Bytes per second it carries.
    pub bytes_per_s: f64,
    /// Seconds one message takes beyond its bytes (MPI over TCP, switch included).
    pub latency_s: f64,
}

/// 10 Gigabit Ethernet: 1.25 GB/s; 50 µs per message, Open MPI's TCP transport's order of
/// magnitude (RDMA would be a few µs).
pub const TEN_GBE: Link = Link { name: "10 GbE", bytes_per_s: 1.25e9, latency_s: 50e-6 };

/// Gigabit Ethernet: 125 MB/s; 100 µs per message.
pub const ONE_GBE: Link = Link { name: "1 GbE", bytes_per_s: 0.125e9, latency_s: 100e-6 };

/// How a share's pixels travel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Encoding {
    pub name: String,
    pub bytes_per_pixel: f64,
}

/// The cost of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Frame {
    /// Pixels in the frame.
    pub pixels: f64,
    /// Samples per pixel (for reports: the cost below includes them).
    pub spp: u32,
    /// Core-seconds per pixel.
    pub core_seconds_per_pixel: f64,
    /// Cores of each node.
    pub cores_per_node: usize,
}

impl Frame {
    /// Seconds one node takes to render the whole frame.
    pub fn one_node_s(&self) -> f64 {
        self.core_seconds_per_pixel * self.pixels / self.cores_per_node.max(1) as f64
    }
}

/// The model's figures for one node count, link and encoding.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Prediction {
    pub nodes: u32,
    /// Each node's render of its 1/N.
    pub render_s: f64,
    /// The other nodes' shares into node 0, one after another.
    pub gather_s: f64,
    /// Render, then gather.
    pub frame_s: f64,
    pub frames_per_s: f64,
    /// `frame_s` on one node over `frame_s` here, over `nodes`.
    pub efficiency: f64,
    /// With the gather overlapping the render.
    pub overlapped_frame_s: f64,
    pub overlapped_efficiency: f64,
}

/// The frame on `nodes` nodes, each share sent to node 0 over `link` as `encoding`.
pub fn predict(frame: &Frame, nodes: u32, link: &Link, encoding: &Encoding) -> Prediction {
    let n = f64::from(nodes.max(1));
    let one_node = frame.one_node_s();
    let render_s = one_node / n;
    let (gather_s, latency) = if nodes > 1 {
        let bytes = encoding.bytes_per_pixel * frame.pixels * (n - 1.0) / n;
        (bytes / link.bytes_per_s + (n - 1.0) * link.latency_s, link.latency_s)
    } else {
        (0.0, 0.0)
    };
    let frame_s = render_s + gather_s;
    let overlapped_frame_s = render_s.max(gather_s) + latency;
    Prediction {
        nodes,
        render_s,
        gather_s,
        frame_s,
        frames_per_s: 1.0 / frame_s,
        efficiency: one_node / frame_s / n,
        overlapped_frame_s,
        overlapped_efficiency: one_node / overlapped_frame_s / n,
    }
}

/// Node counts the model is printed for.
pub const NODES: [u32; 6] = [1, 2, 4, 8, 16, 32];

/// The efficiency worth a node: at or above it, a table marks the figure.
pub const GOOD_EFFICIENCY: f64 = 0.8;

#[cfg(test)]
mod tests {
    use super::*;

    fn f32_rgb() -> Encoding {
        Encoding { name: "f32 RGB".into(), bytes_per_pixel: 12.0 }
    }

    #[test]
    fn one_node_renders_everything_and_sends_nothing() {
        let frame = Frame { pixels: 1000.0, spp: 1, core_seconds_per_pixel: 0.016, cores_per_node: 16 };
        let p = predict(&frame, 1, &TEN_GBE, &f32_rgb());
        assert_eq!((p.render_s, p.gather_s, p.frame_s, p.efficiency), (1.0, 0.0, 1.0, 1.0));
        assert_eq!(p.overlapped_frame_s, 1.0);
    }

    #[test]
    fn the_gather_is_the_other_shares_through_one_link() {
        // 1 MB per frame at 12 B/px; four nodes send 3/4 of it: 750 kB at 1.25 GB/s is 0.6 ms,
        // plus three latencies.
        let frame = Frame { pixels: 1e6 / 12.0, spp: 1, core_seconds_per_pixel: 16.0 * 12e-6, cores_per_node: 16 };
        let p = predict(&frame, 4, &TEN_GBE, &f32_rgb());
        assert!((p.render_s - 0.25).abs() < 1e-12);
        assert!((p.gather_s - (0.6e-3 + 3.0 * 50e-6)).abs() < 1e-12, "{p:?}");
        assert!((p.efficiency - 1.0 / (4.0 * (0.25 + p.gather_s))).abs() < 1e-12);
        assert!((p.overlapped_frame_s - (0.25 + 50e-6)).abs() < 1e-12);
        assert!(p.overlapped_efficiency > p.efficiency);
    }

    #[test]
    fn fewer_bytes_or_a_faster_link_scale_better_and_efficiency_falls_with_nodes() {
        let frame = Frame { pixels: 1920.0 * 1080.0, spp: 1, core_seconds_per_pixel: 1e-5, cores_per_node: 16 };
        let srgb8 = Encoding { name: "sRGB8".into(), bytes_per_pixel: 3.0 };
        let at = |nodes, link: &Link, e: &Encoding| predict(&frame, nodes, link, e).efficiency;
        assert!(at(16, &TEN_GBE, &srgb8) > at(16, &TEN_GBE, &f32_rgb()));
        assert!(at(16, &TEN_GBE, &f32_rgb()) > at(16, &ONE_GBE, &f32_rgb()));
        let efficiencies: Vec<f64> = NODES.iter().map(|&n| at(n, &ONE_GBE, &f32_rgb())).collect();
        assert!(efficiencies.windows(2).all(|w| w[1] < w[0]), "{efficiencies:?}");
        // A gather longer than the render bounds the overlapped frame.
        let p = predict(&frame, 32, &ONE_GBE, &f32_rgb());
        assert!(p.gather_s > p.render_s && p.overlapped_frame_s == p.gather_s + ONE_GBE.latency_s, "{p:?}");
    }
}
