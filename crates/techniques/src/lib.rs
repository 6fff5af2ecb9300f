#![doc = include_str!("../README.md")]

use soft_shadow_core::Registry;

/// Every technique of the workspace: the baselines (hard, PCF, PCSS, accumulation), then
/// penumbra-limit, occlusion-slices, linear-light and shadow-width, each crate's families in
/// its own order. A technique crate joins with one line here.
pub fn registry() -> Registry {
    Registry::new()
        .with(shadow_maps::families())
        .with(penumbra_limit::families())
        .with(occlusion_slices::families())
        .with(linear_light::families())
        .with(shadow_width::families())
}
