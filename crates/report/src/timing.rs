//! Timings that can be trusted on a shared machine: every setting is timed several times,
//! interleaved with the others, in wall and CPU time, and shown as a median with its spread.

use std::time::Instant;

/// Repeated measurements of one quantity.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spread {
    /// Every measurement, in the order taken.
    pub samples: Vec<f64>,
}

impl Spread {
    /// The median (the mean of the middle two for an even count); 0 with no samples.
    pub fn median(&self) -> f64 {
        let mut s = self.samples.clone();
        s.sort_by(f64::total_cmp);
        match s.len() {
            0 => 0.0,
            n if n % 2 == 1 => s[n / 2],
            n => 0.5 * (s[n / 2 - 1] + s[n / 2]),
        }
    }

    /// The smallest measurement.
    pub fn min(&self) -> f64 {
        self.samples.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The largest measurement.
    pub fn max(&self) -> f64 {
        self.samples.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    /// Half the range: what the tables print after ±.
    pub fn half_range(&self) -> f64 {
        if self.samples.is_empty() { 0.0 } else { 0.5 * (self.max() - self.min()) }
    }

    /// Whether the two ranges overlap: the measurements cannot tell the two apart.
    pub fn overlaps(&self, other: &Spread) -> bool {
        self.min() <= other.max() && other.min() <= self.max()
    }

    /// Every measurement scaled by `factor`.
    pub fn scaled(&self, factor: f64) -> Spread {
        Spread { samples: self.samples.iter().map(|s| s * factor).collect() }
    }
}

/// CPU time this process has used (user plus system, all threads), in seconds.
fn process_cpu_seconds() -> f64 {
    // Safety: getrusage writes into the struct we pass and reads nothing else.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) } != 0 {
        return 0.0;
    }
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    seconds(usage.ru_utime) + seconds(usage.ru_stime)
}

/// Runs `work`, returning its result with its wall and CPU seconds.
pub fn timed<T>(work: impl FnOnce() -> T) -> (T, f64, f64) {
    let (cpu, wall) = (process_cpu_seconds(), Instant::now());
    let result = work();
    (result, wall.elapsed().as_secs_f64(), (process_cpu_seconds() - cpu).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_ranges_and_overlaps() {
        let a = Spread { samples: vec![3.0, 1.0, 2.0] };
        assert_eq!((a.median(), a.min(), a.max(), a.half_range()), (2.0, 1.0, 3.0, 1.0));
        assert_eq!(Spread { samples: vec![4.0, 1.0, 2.0, 3.0] }.median(), 2.5);
        assert!(a.overlaps(&Spread { samples: vec![2.9, 5.0] }));
        assert!(!a.overlaps(&Spread { samples: vec![3.1, 5.0] }));
        assert_eq!(a.scaled(2.0).max(), 6.0);
    }

    #[test]
    fn busy_work_uses_cpu_time() {
        let (sum, wall, cpu) = timed(|| (0..20_000_000u64).fold(0u64, |s, i| s.wrapping_add(std::hint::black_box(i) * i)));
        assert!(sum > 0 && wall > 0.0);
        assert!(cpu > 0.0, "a busy loop shows in CPU time");
    }
}
