//! bezier-subdiv: view-adaptive, crack-free recursive subdivision of bicubic
//! Bézier surfaces (Tabaei, Kuth et al. 2026) on Vulkan, with the CPU oracle
//! every GPU path is checked against.

pub mod anim;
pub mod app;
pub mod cage;
pub mod commands;
pub mod constants;
pub mod draw;
pub mod eval;
pub mod figures;
pub mod files;
pub mod frame;
pub mod gpu;
pub mod input;
pub mod lod;
pub mod methods;
pub mod palette;
pub mod patch;
pub mod renderer;
pub mod scene;
pub mod validate;
pub mod vk;
