//! What `report` runs: the CLI's options, their defaults, and every technique it knows.

use soft_shadow_core::{Registry, Technique, Tier};
use std::path::PathBuf;

/// Map resolutions of the full run: 16 to 2048.
pub const FULL_RESOLUTIONS: [u32; 4] = [16, 128, 512, 2048];
/// Map resolution of `--quick`.
pub const QUICK_RESOLUTIONS: [u32; 1] = [256];
/// G-buffer side of the full run.
pub const FULL_SIZE: u32 = 256;
/// G-buffer side of `--quick`.
pub const QUICK_SIZE: u32 = 128;

/// Which backends to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    /// CPU only.
    Cpu,
    /// GPU only (an error without an adapter).
    Gpu,
    /// Both; without an adapter, CPU only with a warning.
    All,
}

/// The memory budgets of one generation, per backend (`None`: the contexts' defaults,
/// [`soft_shadow_core::memory::default_budget`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryBudgets {
    /// Bytes one CPU generation may allocate.
    pub cpu: Option<u64>,
    /// Bytes one GPU generation may allocate.
    pub gpu: Option<u64>,
}

/// Options of `report`, one field per CLI flag.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// `--quick`: [`QUICK_SIZE`]² G-buffer, [`QUICK_RESOLUTIONS`], fewer variants; under 2
    /// minutes on 2 cores.
    pub quick: bool,
    /// `--out`.
    pub out: PathBuf,
    /// `--scenes` (built-in names); `None` = all.
    pub scenes: Option<Vec<String>>,
    /// `--techniques` (technique names); `None` = all of [`ReportOptions::registry`].
    pub techniques: Option<Vec<String>>,
    /// The techniques the report knows: the variants of [`Tier::Report`] (quick:
    /// [`Tier::Quick`]) of every family. The binary runs `soft_shadow_techniques::registry()`.
    pub registry: Registry,
    /// `--resolutions`; `None` = [`FULL_RESOLUTIONS`] (quick: [`QUICK_RESOLUTIONS`]).
    pub resolutions: Option<Vec<u32>>,
    /// `--backend`.
    pub backend: BackendChoice,
    /// `--scene-file`, repeatable.
    pub scene_files: Vec<PathBuf>,
    /// `--as-seen`: the scenes drawn and measured as a person sees them (catalogue names or
    /// the names of [`ReportOptions::scene_files`]' scenes; empty: none); `None` = the default
    /// of [`crate::report::seen::scene_names`].
    pub as_seen: Option<Vec<String>>,
    /// `--size`: G-buffer side; `None` = [`FULL_SIZE`] (quick: [`QUICK_SIZE`]).
    pub size: Option<u32>,
    /// Memory budgets (the binary reads `SHADOW_CPU_MEMORY_BUDGET` and
    /// `SHADOW_GPU_MEMORY_BUDGET`, in bytes).
    pub memory: MemoryBudgets,
}

impl ReportOptions {
    /// The G-buffer side used.
    pub fn size(&self) -> u32 {
        self.size
            .unwrap_or(if self.quick { QUICK_SIZE } else { FULL_SIZE })
    }

    /// The map resolutions used.
    pub fn resolutions(&self) -> Vec<u32> {
        self.resolutions.clone().unwrap_or_else(|| {
            if self.quick {
                QUICK_RESOLUTIONS.to_vec()
            } else {
                FULL_RESOLUTIONS.to_vec()
            }
        })
    }

    /// The resolution flicker is measured at: the one used closest to 512.
    pub fn flicker_resolution(&self) -> Option<u32> {
        self.resolutions()
            .into_iter()
            .min_by_key(|r| (*r as i64 - 512).abs())
    }

    /// The tier of variants the report runs: [`Tier::Quick`] or [`Tier::Report`].
    pub fn tier(&self) -> Tier {
        tier(self.quick)
    }
}

/// The tier of variants a report runs: [`Tier::Quick`] for `--quick`, else [`Tier::Report`].
pub fn tier(quick: bool) -> Tier {
    if quick { Tier::Quick } else { Tier::Report }
}

/// Every technique of `soft_shadow_techniques::registry()` a report runs (`quick`: the quick
/// report's), each family's default first.
pub fn all_techniques(quick: bool) -> Vec<Technique> {
    soft_shadow_techniques::registry().techniques(tier(quick))
}
