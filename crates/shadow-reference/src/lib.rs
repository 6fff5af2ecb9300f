#![doc = include_str!("../README.md")]

pub mod ground_truth;
pub mod scenes;
