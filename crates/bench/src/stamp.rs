//! What a benchmark run was measured on: the first line of every `--json` report, so that a
//! performance page made from the report (see [`crate::page`]) says which machine, build and
//! commit its figures belong to.

use serde::{Deserialize, Serialize};

/// The machine, build and commit of a benchmark run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stamp {
    /// The benchmark's arguments, as given (`kernel --scene sphere --reps 3`).
    pub command: String,
    /// When the run started, UTC (`2026-12-06T14:05:00Z`).
    pub date: String,
    /// The commit of the working tree the binary was run from (`git rev-parse --short HEAD`),
    /// with `-dirty` when it had uncommitted changes; `unknown` outside a git checkout.
    pub commit: String,
    /// The CPU's model name (`/proc/cpuinfo`).
    pub cpu: String,
    /// Logical cores the process may use.
    pub cores: usize,
    /// The SIMD extensions of the CPU that matter to the kernels and to Embree's.
    pub simd: Vec<String>,
    /// The instruction set raystage's kernels chose ([`raystage_kernel::Isa::best`]).
    pub kernel_isa: String,
    /// Embree's version, when the benchmark was built with the `embree` feature.
    pub embree: Option<String>,
    /// The 1-minute load average when the run started: a shared machine's figures drift with it.
    pub load_average: Option<f64>,
    /// Whether this is a release build (debug builds' figures mean little).
    pub release: bool,
}

impl Stamp {
    /// The stamp of a run started now with `args` (the arguments after the program's name).
    pub fn now(args: &[String]) -> Stamp {
        Stamp {
            command: args.join(" "),
            date: utc_date(std::time::SystemTime::now()),
            commit: commit(),
            cpu: cpu_model(),
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            simd: simd(),
            kernel_isa: raystage_kernel::Isa::best().name().to_string(),
            embree: embree_version(),
            load_average: std::fs::read_to_string("/proc/loadavg").ok().and_then(|s| s.split_whitespace().next()?.parse().ok()),
            release: !cfg!(debug_assertions),
        }
    }
}

/// The line a `--json` report starts with: `{"stamp": {...}}`.
#[derive(Serialize, Deserialize)]
pub struct StampLine {
    /// The stamp.
    pub stamp: Stamp,
}

/// `time` as an ISO 8601 UTC date and time to the second.
fn utc_date(time: std::time::SystemTime) -> String {
    let seconds = time.duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rest) = ((seconds / 86_400) as i64, seconds % 86_400);
    // Days since 1970-01-01 to a civil date (the proleptic Gregorian calendar), after
    // Howard Hinnant's `civil_from_days`: eras of 400 years, years starting in March.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z", rest / 3600, rest / 60 % 60, rest % 60)
}

/// The commit of the current directory's checkout, `-dirty` if it has changes.
fn commit() -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git").args(args).output().ok().filter(|o| o.status.success()).map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(hash) if !hash.is_empty() => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
            if dirty { format!("{hash}-dirty") } else { hash }
        }
        _ => "unknown".to_string(),
    }
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| info.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split_once(':')).map(|(_, v)| v.trim().to_string()))
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

fn simd() -> Vec<String> {
    #[cfg(target_arch = "x86_64")]
    {
        let mut found = Vec::new();
        macro_rules! check {
            ($($feature:tt),*) => {$(
                if std::arch::is_x86_feature_detected!($feature) {
                    found.push($feature.to_string());
                }
            )*};
        }
        check!("sse4.2", "avx", "avx2", "fma", "avx512f", "avx512vl", "avx512bw", "avx512dq");
        found
    }
    #[cfg(not(target_arch = "x86_64"))]
    Vec::new()
}

fn embree_version() -> Option<String> {
    #[cfg(feature = "embree")]
    return crate::embree::Device::new(1).ok().map(|d| d.version());
    #[cfg(not(feature = "embree"))]
    None
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, UNIX_EPOCH};

    use super::*;

    #[test]
    fn dates_are_civil_utc() {
        assert_eq!(utc_date(UNIX_EPOCH), "1970-01-01T00:00:00Z");
        // 951,782,400 s: 2000-02-29, a leap day of a year divisible by 400.
        assert_eq!(utc_date(UNIX_EPOCH + Duration::from_secs(951_782_400 + 3_723)), "2000-02-29T01:02:03Z");
        // 1,796,515,200 s: 2026-12-06 (after a leap year's February in 2024).
        assert_eq!(utc_date(UNIX_EPOCH + Duration::from_secs(1_796_515_200)), "2026-12-06T00:00:00Z");
        assert_eq!(utc_date(UNIX_EPOCH + Duration::from_secs(4_107_542_399)), "2100-02-28T23:59:59Z");
    }

    #[test]
    fn a_stamp_names_this_machine_and_round_trips() {
        let stamp = Stamp::now(&["kernel".to_string(), "--reps".to_string(), "1".to_string()]);
        assert_eq!(stamp.command, "kernel --reps 1");
        assert!(stamp.cores >= 1 && !stamp.cpu.is_empty() && !stamp.commit.is_empty());
        let line = serde_json::to_string(&StampLine { stamp: stamp.clone() }).unwrap();
        assert_eq!(serde_json::from_str::<StampLine>(&line).unwrap().stamp, stamp);
    }
}
