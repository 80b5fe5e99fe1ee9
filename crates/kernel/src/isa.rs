//! Run-time choice of the instruction set the traversal kernels use.

use std::sync::OnceLock;

/// An instruction-set flavour of the traversal kernels. Chosen at run time, never at compile
/// time: the binary runs on any x86-64 (or other) CPU and uses AVX2 where the CPU has it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// 8-wide AVX2 + FMA kernels (x86-64 only).
    Avx2,
    /// Plain Rust, any CPU. Bit-identical results to the SIMD kernels.
    Portable,
}

impl Isa {
    /// The fastest kernel this CPU supports. The environment variable `RAYSTAGE_ISA=portable`
    /// (or `avx2`) overrides the choice, e.g. to measure the fallback; an unsupported request is
    /// ignored.
    pub fn best() -> Isa {
        static BEST: OnceLock<Isa> = OnceLock::new();
        *BEST.get_or_init(|| {
            let requested = std::env::var("RAYSTAGE_ISA").ok().and_then(|s| Isa::from_name(&s));
            match requested {
                Some(isa) if isa.is_supported() => isa,
                _ => Isa::all().find(|isa| isa.is_supported()).unwrap_or(Isa::Portable),
            }
        })
    }

    /// Every flavour, fastest first.
    pub fn all() -> impl Iterator<Item = Isa> {
        [Isa::Avx2, Isa::Portable].into_iter()
    }

    /// Whether this CPU can run the flavour.
    pub fn is_supported(self) -> bool {
        match self {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            Isa::Avx2 => false,
            Isa::Portable => true,
        }
    }

    /// Lower-case name, as accepted by `RAYSTAGE_ISA`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Avx2 => "avx2",
            Isa::Portable => "portable",
        }
    }

    /// Parses a name as printed by [`Isa::name`].
    pub fn from_name(name: &str) -> Option<Isa> {
        Isa::all().find(|isa| isa.name().eq_ignore_ascii_case(name.trim()))
    }
}
