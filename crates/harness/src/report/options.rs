//! What `report` runs: the CLI's options, their defaults, and every technique it knows.

use linear_light::LinearLight;
use occlusion_slices::OcclusionSlices;
use penumbra_limit::PenumbraLimit;
use shadow_maps::{Filter, SamplePattern, ShadowMapBaseline};
use shadow_width::ShadowWidth;
use soft_shadow_core::DynTechnique;
use std::path::PathBuf;

/// Map resolutions of the full run: 16 to 2048.
pub const FULL_RESOLUTIONS: [u32; 4] = [16, 128, 512, 2048];
/// Map resolution of `--quick`.
pub const QUICK_RESOLUTIONS: [u32; 1] = [256];
/// G-buffer side of the full run.
pub const FULL_SIZE: u32 = 256;
/// G-buffer side of `--quick`.
pub const QUICK_SIZE: u32 = 128;
/// Accumulation sample counts of the full run.
pub const FULL_ACCUMULATION: [u32; 3] = [4, 16, 64];
/// Accumulation sample counts of `--quick`.
pub const QUICK_ACCUMULATION: [u32; 1] = [16];

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
    /// `--techniques` (technique names); `None` = all.
    pub techniques: Option<Vec<String>>,
    /// `--resolutions`; `None` = [`FULL_RESOLUTIONS`] (quick: [`QUICK_RESOLUTIONS`]).
    pub resolutions: Option<Vec<u32>>,
    /// `--backend`.
    pub backend: BackendChoice,
    /// `--scene-file`, repeatable.
    pub scene_files: Vec<PathBuf>,
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
}

/// Every technique the report knows, for `--techniques`.
pub fn all_techniques(quick: bool) -> Vec<Box<dyn DynTechnique>> {
    let accumulation: &[u32] = if quick {
        &QUICK_ACCUMULATION
    } else {
        &FULL_ACCUMULATION
    };
    // Accumulation in both sample patterns: the papers' grid and the rotated one engines use.
    let rotated = accumulation.iter().map(|&samples| {
        ShadowMapBaseline::new(Filter::Accumulate { samples }).with_pattern(SamplePattern::Rotated)
    });
    let baselines = ShadowMapBaseline::standard_set(accumulation)
        .into_iter()
        .chain(rotated)
        .map(|b| Box::new(b) as Box<dyn DynTechnique>);
    let shadow_width = ShadowWidth::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let penumbra_limit = PenumbraLimit::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let occlusion_slices = OcclusionSlices::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    let linear_light = LinearLight::standard_set()
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn DynTechnique>);
    baselines
        .chain(shadow_width)
        .chain(penumbra_limit)
        .chain(occlusion_slices)
        .chain(linear_light)
        .collect()
}
